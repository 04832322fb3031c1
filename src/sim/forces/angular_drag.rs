//! Angular drag: a torque opposing the spin, proportional to it.

use super::Selection;

/// τ = -k·ω, the rotational counterpart of linear drag F = -k·v. Alone it gives
/// dω/dt = -k·ω/I, whose exact solution is ω(t) = ω0·exp(-k·t/I); explicit Euler gives
/// exactly ω_n = ω0·(1 - h·k/I)^n, stable while h·k/I ≤ 2.
#[derive(Clone, Debug, PartialEq)]
pub struct AngularDrag {
    /// The coefficient k ≥ 0, in N·m·s.
    pub k: f64,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl AngularDrag {
    /// Adds τ = -k·ω to the net torque of every selected body, whose angular
    /// velocities are `omega`.
    #[inline]
    pub fn accumulate(&self, omega: &[f64], torque: &mut [f64]) {
        let n = torque.len();
        self.bodies.for_each(n, |i| {
            // τ = -k·ω.
            torque[i] -= self.k * omega[i];
        });
    }
}
