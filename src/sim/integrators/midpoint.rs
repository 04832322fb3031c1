//! The explicit midpoint method (second-order Runge–Kutta, RK2).

use glam::DVec2;

use crate::sim::System;

/// Scratch buffers for the midpoint method: the state at the middle of the step and the
/// accelerations.
#[derive(Clone, Debug)]
pub struct Midpoint {
    acc: Vec<DVec2>,
    mid_pos: Vec<DVec2>,
    mid_vel: Vec<DVec2>,
}

impl Midpoint {
    /// Allocates the buffers for `n` bodies, once per run.
    pub fn new(n: usize) -> Self {
        Midpoint {
            acc: vec![DVec2::ZERO; n],
            mid_pos: vec![DVec2::ZERO; n],
            mid_vel: vec![DVec2::ZERO; n],
        }
    }

    /// Advances one step and returns the number of force evaluations (2).
    ///
    /// For y' = f(t, y), the midpoint method takes a half Euler step to estimate the state
    /// at the middle of the step, and then a full step with the slope found there:
    ///
    ///   y_mid   = y + (h/2)·f(t, y)
    ///   y(t + h) = y + h·f(t + h/2, y_mid)
    ///
    /// With y = (r, v) and f = (v, a(t, r, v)):
    ///
    ///   r_mid = r + (h/2)·v,             v_mid = v + (h/2)·a(t, r, v)
    ///   r(t + h) = r + h·v_mid,          v(t + h) = v + h·a(t + h/2, r_mid, v_mid)
    ///
    /// The error of the half step is symmetric about the midpoint and cancels to first
    /// order, which makes the method second order.
    pub fn step(
        &mut self,
        system: &System,
        t: f64,
        h: f64,
        pos: &mut [DVec2],
        vel: &mut [DVec2],
    ) -> u32 {
        let half = 0.5 * h;
        system.accelerations(t, pos, vel, &mut self.acc);
        // The state an Euler sub-step of h/2 reaches: r_mid, v_mid.
        super::euler_substep(
            half,
            (pos, vel, &self.acc),
            &mut self.mid_pos,
            &mut self.mid_vel,
        );
        system.accelerations(t + half, &self.mid_pos, &self.mid_vel, &mut self.acc);
        for (((r, v), vm), a) in pos
            .iter_mut()
            .zip(vel.iter_mut())
            .zip(&self.mid_vel)
            .zip(&self.acc)
        {
            // r(t + h) = r + h·v_mid.
            *r += h * *vm;
            // v(t + h) = v + h·a(t + h/2, r_mid, v_mid).
            *v += h * *a;
        }
        2
    }
}
