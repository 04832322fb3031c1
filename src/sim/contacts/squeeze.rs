//! What an overlap left by a step is put down to when a light body lies beside a far
//! heavier one: the diagnosis behind the blow-up that asks for closer masses (see
//! `docs/collisions.md`, "A light body under a far heavier one"). Its own file because
//! it is no stage of the step, only a reading of the step's pairs when the overlap
//! check stops the run.

use super::response::Inverse;
use super::{Collider, Squeezed};

/// For bodies a and b left overlapping (scene indices): the lighter of them that
/// moves, if a moving body it could meet in the step (one of its candidate `pairs` of
/// colliders: a crowded step's last impacts may have thrown the heavy body off it by
/// the step's end) is at least [`SQUEEZE_RATIO`] times its mass, with the heaviest
/// such body. Impulses one pair at a time (the impacts in time order, the solver's
/// sweeps) hold a light body pressed by a far heavier one against a third (a pebble
/// under a boulder, on the ground) only by passing the push back and forth about as
/// many times as the ratio of their masses, which neither a step's budget of impacts
/// nor the solver's sweeps answer.
pub(super) fn squeezed(
    a: usize,
    b: usize,
    colliders: &[Collider],
    inv: &[Inverse],
    pairs: &[(u32, u32)],
) -> Option<Squeezed> {
    let index = |body: usize| colliders.iter().position(|c| c.body == body);
    // The lighter moving body of the two: the larger inverse mass.
    let light = [index(a)?, index(b)?]
        .into_iter()
        .filter(|&k| inv[k].mass > 0.0)
        .max_by(|&k, &l| inv[k].mass.total_cmp(&inv[l].mass).then(l.cmp(&k)))?;
    // The heaviest moving body it could meet: the smallest inverse mass above zero
    // (the first in order among equals).
    let by = pairs
        .iter()
        .filter_map(|&(i, j)| {
            let (i, j) = (i as usize, j as usize);
            (i == light).then_some(j).or((j == light).then_some(i))
        })
        .filter(|&k| inv[k].mass > 0.0)
        .min_by(|&k, &l| inv[k].mass.total_cmp(&inv[l].mass).then(k.cmp(&l)))?;
    // m_by / m_light = (1/m_light) / (1/m_by).
    let ratio = inv[light].mass / inv[by].mass;
    (ratio >= SQUEEZE_RATIO).then_some(Squeezed {
        body: colliders[light].body as u32,
        by: colliders[by].body as u32,
        ratio: ratio as f32,
    })
}

/// The ratio of masses from which a body left overlapping is reported as squeezed by a
/// heavier one: 150 discs, pentagons and boxes of 0.01 kg each on the ground under a
/// heptagon settled with the heptagon at 1 kg, and at 5 kg (a ratio of 500) one was
/// left pressed into the ground.
const SQUEEZE_RATIO: f64 = 100.0;
