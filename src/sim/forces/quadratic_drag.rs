//! Quadratic drag, the law of fast bodies in air.

use glam::DVec2;

use super::Selection;

/// Quadratic drag, F = -c·|v|·v: opposing the velocity, with a magnitude c·|v|².
#[derive(Clone, Debug, PartialEq)]
pub struct QuadraticDrag {
    /// The coefficient c ≥ 0.
    pub c: f64,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl QuadraticDrag {
    /// Adds F = -c·|v|·v to every selected body.
    #[inline]
    pub fn accumulate(&self, vel: &[DVec2], force: &mut [DVec2]) {
        self.bodies.for_each(force.len(), |i| {
            let v = vel[i];
            force[i] -= self.c * v.length() * v;
        });
    }
}
