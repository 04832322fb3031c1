//! The overlap check of a whole state at once (a scene's start, a resumed
//! checkpoint): every pair of bodies that overlap deeper than their tolerance.

use glam::DVec2;
use parry2d_f64::bounding_volume::Aabb;

use super::narrow_phase::{contact, Pose};
use super::{Contacts, Overlap};

/// See [`Contacts::overlaps`].
pub(super) fn overlaps(
    c: &mut Contacts,
    pos: &[DVec2],
    angle: &[f64],
    movable: impl Fn(usize) -> bool,
    limit: usize,
) -> Vec<Overlap> {
    let n = c.colliders.len();
    let mut boxes = Vec::with_capacity(n);
    for (k, col) in c.colliders.iter().enumerate() {
        let b = col.body;
        let (lo, hi) = col.aabb(pos[b], angle[b].sin_cos());
        let m = DVec2::splat(c.margin(k));
        boxes.push(Aabb::new(
            super::collider::to_parry(lo - m),
            super::collider::to_parry(hi + m),
        ));
    }
    // Each movable collider, in order, against the colliders whose boxes meet its own
    // (the later movable ones, and every immovable one, which asks nothing itself:
    // two immovable bodies may overlap). The search stops once `limit` overlaps are
    // found, so a hostile scene of 10^5 bodies piled on one spot costs one query, not
    // a list of 5·10^9 pairs, and 10^5 static bodies piled up cost nothing.
    c.scratch.broad.rebuild(boxes.into_iter());
    let mut found = Vec::new();
    let mut others = Vec::new();
    for i in 0..n {
        if found.len() >= limit {
            break;
        }
        if !movable(c.colliders[i].body) {
            continue;
        }
        let bx = c.scratch.broad.box_of(i);
        c.scratch.broad.query(&bx, &mut others);
        others.retain(|&j| {
            let j = j as usize;
            j > i || (j < i && !movable(c.colliders[j].body))
        });
        others.sort_unstable();
        for &j in &others {
            let (i, j) = (i.min(j as usize), i.max(j as usize));
            let (ci, cj) = (&c.colliders[i], &c.colliders[j]);
            let t = c.tolerance(i, j);
            let pi = Pose::new(pos[ci.body], angle[ci.body]);
            let pj = Pose::new(pos[cj.body], angle[cj.body]);
            if let Some(ct) = contact(ci, &pi, cj, &pj, t, t) {
                if ct.gap < -t {
                    found.push(Overlap {
                        a: ci.body,
                        b: cj.body,
                        depth: -ct.gap,
                        crowded: false,
                        squeezed: None,
                    });
                }
            }
        }
    }
    // In body order, as the pairs (a, b) sort.
    found.sort_by_key(|o| (o.a, o.b));
    found
}
