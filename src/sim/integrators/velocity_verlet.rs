//! Velocity Verlet, the workhorse of molecular dynamics, with a documented extension to
//! forces that depend on velocity.

use glam::DVec2;

use crate::sim::System;

/// Scratch buffers for velocity Verlet, including the acceleration carried over from the
/// end of one step to the start of the next.
#[derive(Clone, Debug)]
pub struct VelocityVerlet {
    /// The acceleration at the start of the step.
    acc: Vec<DVec2>,
    /// The acceleration at the end of the step.
    acc_end: Vec<DVec2>,
    /// The predicted end-of-step velocity, v + h·a, used only for velocity-dependent forces.
    vel_pred: Vec<DVec2>,
    /// The positions at which `acc` was evaluated, to check that the carried-over
    /// acceleration belongs to the state the next step starts from.
    acc_pos: Vec<DVec2>,
    /// The time at which `acc` was evaluated.
    acc_t: f64,
    /// True when `acc`, `acc_pos` and `acc_t` describe a valid carried-over acceleration.
    acc_valid: bool,
}

impl VelocityVerlet {
    /// Allocates the buffers for `n` bodies, once per run.
    pub fn new(n: usize) -> Self {
        VelocityVerlet {
            acc: vec![DVec2::ZERO; n],
            acc_end: vec![DVec2::ZERO; n],
            vel_pred: vec![DVec2::ZERO; n],
            acc_pos: vec![DVec2::ZERO; n],
            acc_t: 0.0,
            acc_valid: false,
        }
    }

    /// Forgets the carried-over acceleration, so that the next step evaluates it afresh.
    pub fn reset(&mut self) {
        self.acc_valid = false;
    }

    /// Advances one step and returns the number of force evaluations it used.
    ///
    /// Velocity Verlet, for forces that depend on position and time only:
    ///
    ///   r(t + h) = r + h·v + (h²/2)·a(t, r)
    ///   v(t + h) = v + (h/2)·(a(t, r) + a(t + h, r(t + h)))
    ///
    /// It is second order, time-reversible and symplectic. The end-of-step acceleration
    /// is the next step's start-of-step acceleration, so it is carried over ("first same
    /// as last") and a step costs one force evaluation. The carried value is used only
    /// when the next step starts at the same positions and (to within rounding) the same
    /// time it was evaluated at; otherwise it is evaluated again.
    ///
    /// Velocity-dependent forces (drag, spring damping, see
    /// [`crate::sim::forces::ForceSet::depends_on_velocity`]) need a velocity at the end
    /// of the step, which is what the step is computing. This implementation evaluates
    /// the end-of-step acceleration with the Euler-predicted velocity ṽ = v + h·a(t, r, v):
    ///
    ///   r(t + h) = r + h·v + (h²/2)·a(t, r, v)
    ///   ṽ        = v + h·a(t, r, v)
    ///   v(t + h) = v + (h/2)·(a(t, r, v) + a(t + h, r(t + h), ṽ))
    ///
    /// The velocity update is then Heun's method, whose local error is O(h³), so the
    /// scheme stays second order on drag (the tests check it). The end-of-step
    /// acceleration was computed with ṽ rather than v(t + h), so it is not carried over,
    /// and such a step costs two force evaluations. The scheme is no longer symplectic,
    /// but a damped system has no energy to conserve.
    pub fn step(
        &mut self,
        system: &System,
        t: f64,
        h: f64,
        pos: &mut [DVec2],
        vel: &mut [DVec2],
    ) -> u32 {
        let mut evaluations = 0;
        if !(self.acc_valid && same_time(self.acc_t, t) && self.acc_pos == pos) {
            // a(t, r, v) at the start of the step.
            system.accelerations(t, pos, vel, &mut self.acc);
            evaluations += 1;
        }
        let half = 0.5 * h;
        let half_h2 = 0.5 * h * h;
        for ((r, v), a) in pos.iter_mut().zip(vel.iter()).zip(&self.acc) {
            // r(t + h) = r + h·v + (h²/2)·a(t, r, v).
            *r += h * *v + half_h2 * *a;
        }
        let velocity_dependent = system.force_set().depends_on_velocity();
        if velocity_dependent {
            for ((vp, v), a) in self.vel_pred.iter_mut().zip(vel.iter()).zip(&self.acc) {
                // ṽ = v + h·a(t, r, v).
                *vp = *v + h * *a;
            }
            // a(t + h, r(t + h), ṽ).
            system.accelerations(t + h, pos, &self.vel_pred, &mut self.acc_end);
        } else {
            // a(t + h, r(t + h)); the velocity passed is ignored by every force here.
            system.accelerations(t + h, pos, vel, &mut self.acc_end);
        }
        evaluations += 1;
        for ((v, a0), a1) in vel.iter_mut().zip(&self.acc).zip(&self.acc_end) {
            // v(t + h) = v + (h/2)·(a(t) + a(t + h)).
            *v += half * (*a0 + *a1);
        }
        if velocity_dependent {
            self.acc_valid = false;
        } else {
            // Carry a(t + h, r(t + h)) over to the next step.
            std::mem::swap(&mut self.acc, &mut self.acc_end);
            self.acc_pos.copy_from_slice(pos);
            self.acc_t = t + h;
            self.acc_valid = true;
        }
        evaluations
    }
}

/// Returns true when two times differ only by rounding, as t + h and t0 + (n + 1)·h may.
pub(crate) fn same_time(a: f64, b: f64) -> bool {
    (a - b).abs() <= 8.0 * f64::EPSILON * a.abs().max(b.abs())
}
