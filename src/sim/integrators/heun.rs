//! Heun's method: the explicit trapezoidal rule, a second-order Runge–Kutta method.

use glam::DVec2;

use super::euler_substep;
use crate::sim::dof::Dof;
use crate::sim::state::Coords;
use crate::sim::{State, System};

/// Scratch buffers for Heun's method: the Euler predictor and the accelerations at both
/// ends of the step, for the linear pair and (for a system that spins) the angular pair.
#[derive(Clone, Debug)]
pub struct Heun {
    lin: Buffers<DVec2>,
    ang: Buffers<f64>,
}

/// Heun's buffers for one kind of coordinate.
#[derive(Clone, Debug)]
struct Buffers<T> {
    acc_start: Vec<T>,
    acc_end: Vec<T>,
    pred_pos: Vec<T>,
    pred_vel: Vec<T>,
}

impl<T: Dof> Buffers<T> {
    fn new(n: usize) -> Self {
        Buffers {
            acc_start: vec![T::ZERO; n],
            acc_end: vec![T::ZERO; n],
            pred_pos: vec![T::ZERO; n],
            pred_vel: vec![T::ZERO; n],
        }
    }

    /// The predictor: r̃ = r + h·v, ṽ = v + h·a(t, r, v).
    fn predict(&mut self, h: f64, pos: &[T], vel: &[T]) {
        euler_substep(
            h,
            (pos, vel, &self.acc_start),
            &mut self.pred_pos,
            &mut self.pred_vel,
        );
    }

    /// The corrector: the trapezoidal average of the slopes at both ends.
    fn finish(&self, h: f64, pos: &mut [T], vel: &mut [T]) {
        let half = 0.5 * h;
        for (((r, v), vp), (a0, a1)) in pos
            .iter_mut()
            .zip(vel.iter_mut())
            .zip(&self.pred_vel)
            .zip(self.acc_start.iter().zip(&self.acc_end))
        {
            // r(t + h) = r + (h/2)·(v + ṽ).
            *r += (*v + *vp) * half;
            // v(t + h) = v + (h/2)·(a(t, r, v) + a(t + h, r̃, ṽ)).
            *v += (*a0 + *a1) * half;
        }
    }
}

impl Heun {
    /// Allocates the buffers for `n` bodies, once per run; angular ones when `spin`.
    pub fn new(n: usize, spin: bool) -> Self {
        Heun {
            lin: Buffers::new(n),
            ang: Buffers::new(if spin { n } else { 0 }),
        }
    }

    /// Advances one step and returns the number of force evaluations (2).
    ///
    /// For y' = f(t, y), Heun's method predicts the end of the step with Euler and then
    /// averages the slopes at both ends (the trapezoidal rule with an explicit predictor):
    ///
    ///   ỹ       = y + h·f(t, y)
    ///   y(t + h) = y + (h/2)·(f(t, y) + f(t + h, ỹ))
    ///
    /// With y = (r, v) and f = (v, a(t, r, v)):
    ///
    ///   r̃ = r + h·v,                     ṽ = v + h·a(t, r, v)
    ///   r(t + h) = r + (h/2)·(v + ṽ),     v(t + h) = v + (h/2)·(a(t, r, v) + a(t + h, r̃, ṽ))
    ///
    /// and (θ, ω) with α = τ/I take the same stages. It is second order.
    pub fn step(&mut self, system: &System, h: f64, state: &mut State) -> u32 {
        let (t, spin) = (state.t, system.spins());
        let (lin, ang) = (&mut self.lin, &mut self.ang);
        system.derivatives(t, Coords::of(state), &mut lin.acc_start, &mut ang.acc_start);
        // The state an Euler sub-step of h reaches: r̃, ṽ (and θ̃, ω̃).
        lin.predict(h, &state.pos, &state.vel);
        if spin {
            ang.predict(h, &state.angle, &state.omega);
        }
        let predicted = Coords {
            pos: &lin.pred_pos,
            vel: &lin.pred_vel,
            angle: &ang.pred_pos,
            omega: &ang.pred_vel,
        };
        system.derivatives(t + h, predicted, &mut lin.acc_end, &mut ang.acc_end);
        lin.finish(h, &mut state.pos, &mut state.vel);
        if spin {
            ang.finish(h, &mut state.angle, &mut state.omega);
        }
        2
    }
}
