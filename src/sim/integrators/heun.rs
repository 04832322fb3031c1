//! Heun's method: the explicit trapezoidal rule, a second-order Runge–Kutta method.

use glam::DVec2;

use crate::sim::System;

/// Scratch buffers for Heun's method: the Euler predictor and the accelerations at both
/// ends of the step.
#[derive(Clone, Debug)]
pub struct Heun {
    acc_start: Vec<DVec2>,
    acc_end: Vec<DVec2>,
    pred_pos: Vec<DVec2>,
    pred_vel: Vec<DVec2>,
}

impl Heun {
    /// Allocates the buffers for `n` bodies, once per run.
    pub fn new(n: usize) -> Self {
        Heun {
            acc_start: vec![DVec2::ZERO; n],
            acc_end: vec![DVec2::ZERO; n],
            pred_pos: vec![DVec2::ZERO; n],
            pred_vel: vec![DVec2::ZERO; n],
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
    /// It is second order.
    pub fn step(
        &mut self,
        system: &System,
        t: f64,
        h: f64,
        pos: &mut [DVec2],
        vel: &mut [DVec2],
    ) -> u32 {
        let half = 0.5 * h;
        system.accelerations(t, pos, vel, &mut self.acc_start);
        // The state an Euler sub-step of h reaches: r̃, ṽ.
        super::euler_substep(
            h,
            (pos, vel, &self.acc_start),
            &mut self.pred_pos,
            &mut self.pred_vel,
        );
        system.accelerations(t + h, &self.pred_pos, &self.pred_vel, &mut self.acc_end);
        for (((r, v), vp), (a0, a1)) in pos
            .iter_mut()
            .zip(vel.iter_mut())
            .zip(&self.pred_vel)
            .zip(self.acc_start.iter().zip(&self.acc_end))
        {
            // r(t + h) = r + (h/2)·(v + ṽ).
            *r += half * (*v + *vp);
            // v(t + h) = v + (h/2)·(a(t, r, v) + a(t + h, r̃, ṽ)).
            *v += half * (*a0 + *a1);
        }
        2
    }
}
