//! The conserved quantities of a system at a state: momentum, angular momentum about a
//! point, kinetic, potential and mechanical energy, each with the spins' share when the
//! system spins. The studies, the energy-growth check and the tests read them.

use glam::DVec2;

use super::rigid::perp_dot;
use super::state::State;
use super::system::System;

impl System {
    /// Returns the total momentum p_T = Σ m_i v_i (Equations 7 and 10).
    pub fn momentum(&self, vel: &[DVec2]) -> DVec2 {
        vel.iter()
            .zip(&self.mass)
            .fold(DVec2::ZERO, |p, (v, m)| p + *m * *v)
    }

    /// Returns the total angular momentum about the point `origin`:
    /// L_O = Σ ((r_i - O)⊥·(m_i·v_i) + I_i·ω_i), the orbital part of every centre of
    /// mass plus every body's spin (which is zero for a system that does not spin).
    pub fn angular_momentum(&self, state: &State, origin: DVec2) -> f64 {
        let orbital: f64 = state
            .pos
            .iter()
            .zip(&state.vel)
            .zip(&self.mass)
            .map(|((r, v), m)| perp_dot(*r - origin, *m * *v))
            .sum();
        orbital + self.spin_momentum(state)
    }

    /// Returns Σ I_i·ω_i, the bodies' spin angular momentum.
    fn spin_momentum(&self, state: &State) -> f64 {
        match &self.rigid {
            Some(rigid) if self.spins => rigid
                .inertia
                .iter()
                .zip(&state.omega)
                .map(|(i, w)| i * w)
                .sum(),
            _ => 0.0,
        }
    }

    /// Returns the total kinetic energy Σ (½·m_i·|v_i|² + ½·I_i·ω_i²): of the motion of
    /// the centres of mass, plus of the spins when the system spins.
    pub fn kinetic_energy(&self, state: &State) -> f64 {
        let linear: f64 = state
            .vel
            .iter()
            .zip(&self.mass)
            .map(|(v, m)| 0.5 * m * v.length_squared())
            .sum();
        match &self.rigid {
            Some(rigid) if self.spins => {
                // E = ½·M·|v|² + ½·I·ω².
                let spin: f64 = rigid
                    .inertia
                    .iter()
                    .zip(&state.omega)
                    .map(|(i, w)| 0.5 * i * w * w)
                    .sum();
                linear + spin
            }
            _ => linear,
        }
    }

    /// Returns the kinetic energy ½·m·|v|² + ½·I·ω² of body `i`.
    pub fn kinetic_energy_of(&self, state: &State, i: usize) -> f64 {
        let linear = 0.5 * self.mass[i] * state.vel[i].length_squared();
        match &self.rigid {
            Some(rigid) if self.spins => {
                linear + 0.5 * rigid.inertia[i] * state.omega[i] * state.omega[i]
            }
            _ => linear,
        }
    }

    /// Returns the potential energy of the conservative forces (gravity, springs,
    /// central forces) at the state, or `None` when some force has no potential
    /// (drag, angular drag, time-varying forces, torques), so that energy is not a
    /// conserved quantity.
    pub fn potential_energy(&self, state: &State) -> Option<f64> {
        self.forces
            .potential_energy(state.t, &state.pos, &state.angle, &self.mass)
    }

    /// Returns the mechanical energy, kinetic plus the potential of the conservative
    /// forces, or `None` when the scene has an energy source (a time-varying force or
    /// a constant torque).
    pub fn mechanical_energy(&self, state: &State) -> Option<f64> {
        let u = self
            .forces
            .conservative_potential(&state.pos, &state.angle, &self.mass)?;
        Some(self.kinetic_energy(state) + u)
    }
}
