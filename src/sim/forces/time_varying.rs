//! Forces that change with time.

use glam::DVec2;

use super::{Selection, Within};

/// A force that changes linearly with time, F(t) = f0 + f1·t. The article's example
/// F = 2t is f0 = (0, 0), f1 = (2, 0); with it v(t) = v0 + t²/m and
/// r(t) = r0 + v0·t + t³/(3m).
#[derive(Clone, Debug, PartialEq)]
pub struct TimeVarying {
    /// The force at t = 0.
    pub f0: DVec2,
    /// The rate of change of the force.
    pub f1: DVec2,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl TimeVarying {
    /// Adds F(t) = f0 + f1·t to every selected body among the chunk of bodies
    /// `start..start + force.len()`.
    #[inline(always)]
    pub fn accumulate(&self, t: f64, start: usize, force: &mut [DVec2]) {
        // F(t) = f0 + f1·t, the same for every body.
        let f_t = self.f0 + t * self.f1;
        match self.bodies.within(start, force.len()) {
            Within::Run(run) => {
                for f in &mut force[run] {
                    *f += f_t;
                }
            }
            Within::List(list) => {
                for &i in list {
                    force[i as usize - start] += f_t;
                }
            }
        }
    }
}
