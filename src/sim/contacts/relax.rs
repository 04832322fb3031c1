//! Stage 5 of a step with resting contact: relaxing positions. A few passes over the
//! resting contacts push apart every point that overlaps by more than the slop, by
//! β = 0.2 of its excess, moving the bodies along the normal without turning them
//! ([`solver::relaxation`] says why). Positions change, velocities do not, so no energy
//! is added.
//!
//! Each pass finds every contact afresh with the narrow phase, since the passes before
//! moved the bodies. A contact neither of whose bodies has moved since it was last
//! found, and which then gave no push, would be found the same, bit for bit, and give
//! no push again: it is skipped. In a stack at rest almost nothing overlaps past the
//! slop, so the second and later passes skip nearly every contact.

use super::narrow_phase::{contact, Rotations};
use super::response::Inverse;
use super::solver::{self, Manifold};
use super::Collider;
use crate::sim::State;

/// The passes' bookkeeping, kept between steps so that it allocates nothing once grown.
#[derive(Default)]
pub(super) struct Relax {
    /// For each body, the visit (counted over all passes from 1) at which a push last
    /// moved it; 0 when none has this step.
    moved_at: Vec<u64>,
    /// For each manifold, the visit at which it was last found and gave no push; 0
    /// when it has not been, or gave one.
    quiet_at: Vec<u64>,
}

impl Relax {
    /// Runs the passes over `manifolds` (whose colliders' inverse masses are `inv`),
    /// moving the bodies of `end`. `slop(i, j)` is the slop of colliders i and j.
    pub(super) fn run(
        &mut self,
        manifolds: &[Manifold],
        colliders: &[Collider],
        inv: &[Inverse],
        end: &mut State,
        rotations: &mut Rotations,
        slop: impl Fn(usize, usize) -> f64,
    ) {
        self.moved_at.clear();
        self.moved_at.resize(end.pos.len(), 0);
        self.quiet_at.clear();
        self.quiet_at.resize(manifolds.len(), 0);
        let mut visit: u64 = 0;
        for _ in 0..solver::position_passes() {
            for (k, m) in manifolds.iter().enumerate() {
                visit += 1;
                let (bi, bj) = (m.bi, m.bj);
                let quiet = self.quiet_at[k];
                if quiet != 0 && self.moved_at[bi] < quiet && self.moved_at[bj] < quiet {
                    // Found at `quiet` with no push, and nothing has moved since.
                    self.quiet_at[k] = visit;
                    continue;
                }
                let sl = slop(m.i as usize, m.j as usize);
                let pushed = push_apart(m, colliders, inv, end, rotations, sl);
                self.quiet_at[k] = if pushed { 0 } else { visit };
                if pushed {
                    // A body of finite mass moved (a static one, 1/M = 0, did not).
                    for (b, c) in [(bi, m.i), (bj, m.j)] {
                        if inv[c as usize].mass != 0.0 {
                            self.moved_at[b] = visit;
                        }
                    }
                }
            }
        }
    }
}

/// Finds one manifold's contact at the bodies' present poses and pushes apart its
/// points deeper than the slop. Returns whether any point was pushed.
fn push_apart(
    m: &Manifold,
    colliders: &[Collider],
    inv: &[Inverse],
    end: &mut State,
    rotations: &mut Rotations,
    sl: f64,
) -> bool {
    let (iu, ju) = (m.i as usize, m.j as usize);
    let (bi, bj) = (m.bi, m.bj);
    let pi = rotations.pose(iu, end.pos[bi], end.angle[bi]);
    let pj = rotations.pose(ju, end.pos[bj], end.angle[bj]);
    let Some(ct) = contact(&colliders[iu], &pi, &colliders[ju], &pj, sl, sl) else {
        return false;
    };
    let pair = (inv[iu], inv[ju]);
    let max = 0.1 * colliders[iu].size.min(colliders[ju].size);
    // The push moves the bodies along the normal and does not turn them, so its
    // mass is the linear one, 1/K = 1/(1/M_A + 1/M_B).
    let mass = solver::linear_mass(pair);
    let mut pushed = false;
    for k in 0..ct.count {
        let push = solver::relaxation(ct.gaps[k], sl, max, mass);
        if push == 0.0 {
            continue;
        }
        pushed = true;
        let p = push * ct.normal;
        // r_A += p/M_A; r_B -= p/M_B.
        end.pos[bi] += pair.0.mass * p;
        end.pos[bj] -= pair.1.mass * p;
    }
    pushed
}
