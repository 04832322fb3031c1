//! A constant torque: the rotational counterpart of a constant force.

use super::Selection;

/// A torque τ (N·m, counter-clockwise positive) on every selected body, the same at
/// every instant. It changes only the spin: α = τ/I. From θ0 and ω0 it gives
/// ω(t) = ω0 + (τ/I)·t and θ(t) = θ0 + ω0·t + (τ/I)·t²/2, and explicit Euler gives
/// exactly ω_n = ω0 + n·h·τ/I and θ_n = θ0 + n·h·ω0 + h²·(τ/I)·n(n-1)/2.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstantTorque {
    /// The torque τ.
    pub tau: f64,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl ConstantTorque {
    /// Adds τ to the net torque of every selected body among `n`.
    #[inline]
    pub fn accumulate(&self, torque: &mut [f64]) {
        let n = torque.len();
        // τ_i += τ.
        self.bodies.for_each(n, |i| torque[i] += self.tau);
    }
}
