//! Uniform gravity.

use glam::DVec2;

use super::Selection;

/// Uniform gravity, F = m·g, so that every body falls with the same acceleration g.
#[derive(Clone, Debug, PartialEq)]
pub struct Gravity {
    /// The gravitational acceleration g.
    pub g: DVec2,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl Gravity {
    /// Adds F = m·g to every selected body.
    #[inline]
    pub fn accumulate(&self, mass: &[f64], force: &mut [DVec2]) {
        match &self.bodies {
            Selection::All => {
                for (f, m) in force.iter_mut().zip(mass) {
                    *f += *m * self.g;
                }
            }
            sel => sel.for_each(force.len(), |i| force[i] += mass[i] * self.g),
        }
    }

    /// Returns the potential energy U = -Σ m·(g·r).
    pub fn potential_energy(&self, pos: &[DVec2], mass: &[f64]) -> f64 {
        let mut u = 0.0;
        self.bodies
            .for_each(pos.len(), |i| u -= mass[i] * self.g.dot(pos[i]));
        u
    }
}
