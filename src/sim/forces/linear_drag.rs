//! Linear drag, the article's Equation 12.

use glam::DVec2;

use super::{Selection, Within};

/// Linear drag, F = -k·v: a force opposing the velocity and proportional to it. The
/// article's example F = -v is k = 1; with it dv/dt = -k·v/m (Equation 12), whose exact
/// solution is v(t) = v0·exp(-k·t/m).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearDrag {
    /// The drag coefficient k ≥ 0.
    pub k: f64,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl LinearDrag {
    /// Adds F = -k·v to every selected body among the chunk of bodies `start..start +
    /// force.len()`, whose velocities are `vel`.
    #[inline(always)]
    pub fn accumulate(&self, start: usize, vel: &[DVec2], force: &mut [DVec2]) {
        match self.bodies.within(start, force.len()) {
            Within::Run(run) => {
                for (f, v) in force[run.clone()].iter_mut().zip(&vel[run]) {
                    // F = -k·v.
                    *f -= self.k * *v;
                }
            }
            Within::List(list) => {
                for &i in list {
                    let i = i as usize - start;
                    // F = -k·v.
                    force[i] -= self.k * vel[i];
                }
            }
        }
    }
}
