//! Quadratic drag, the law of fast bodies in air.

use glam::DVec2;

use super::{Selection, Within};

/// Quadratic drag, F = -c·|v|·v: opposing the velocity, with a magnitude c·|v|².
#[derive(Clone, Debug, PartialEq)]
pub struct QuadraticDrag {
    /// The coefficient c ≥ 0.
    pub c: f64,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl QuadraticDrag {
    /// Adds F = -c·|v|·v to every selected body among the chunk of bodies `start..start +
    /// force.len()`, whose velocities are `vel`.
    #[inline(always)]
    pub fn accumulate(&self, start: usize, vel: &[DVec2], force: &mut [DVec2]) {
        let run = match self.bodies.within(start, force.len()) {
            Within::Run(run) => {
                for (f, v) in force[run.clone()].iter_mut().zip(&vel[run]) {
                    // F = -c·|v|·v.
                    *f -= self.c * v.length() * *v;
                }
                return;
            }
            Within::List(list) => list,
        };
        for &i in run {
            let i = i as usize - start;
            let v = vel[i];
            // F = -c·|v|·v.
            force[i] -= self.c * v.length() * v;
        }
    }
}
