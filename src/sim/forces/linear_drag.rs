//! Linear drag, the article's Equation 12.

use glam::DVec2;

use super::Selection;

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
    /// Adds F = -k·v to every selected body.
    #[inline]
    pub fn accumulate(&self, vel: &[DVec2], force: &mut [DVec2]) {
        match &self.bodies {
            Selection::All => {
                for (f, v) in force.iter_mut().zip(vel) {
                    *f -= self.k * *v;
                }
            }
            sel => sel.for_each(force.len(), |i| force[i] -= self.k * vel[i]),
        }
    }
}
