//! The classical fourth-order Runge–Kutta method.

use glam::DVec2;

use crate::sim::System;

/// Scratch buffers for RK4: one stage state, its acceleration, and the running weighted
/// sums of the four slopes.
#[derive(Clone, Debug)]
pub struct Rk4 {
    stage_pos: Vec<DVec2>,
    stage_vel: Vec<DVec2>,
    acc: Vec<DVec2>,
    sum_pos: Vec<DVec2>,
    sum_vel: Vec<DVec2>,
}

impl Rk4 {
    /// Allocates the buffers for `n` bodies, once per run.
    pub fn new(n: usize) -> Self {
        Rk4 {
            stage_pos: vec![DVec2::ZERO; n],
            stage_vel: vec![DVec2::ZERO; n],
            acc: vec![DVec2::ZERO; n],
            sum_pos: vec![DVec2::ZERO; n],
            sum_vel: vec![DVec2::ZERO; n],
        }
    }

    /// Advances one step and returns the number of force evaluations (4).
    ///
    /// For y' = f(t, y), the classical Runge–Kutta method samples four slopes
    ///
    ///   k1 = f(t, y)
    ///   k2 = f(t + h/2, y + (h/2)·k1)
    ///   k3 = f(t + h/2, y + (h/2)·k2)
    ///   k4 = f(t + h, y + h·k3)
    ///
    /// and advances with their Simpson-like average y(t + h) = y + (h/6)·(k1 + 2k2 + 2k3 + k4).
    /// With y = (r, v) and f = (v, a(t, r, v)), the position part of each slope k_i is the
    /// stage velocity V_i and the velocity part is the stage acceleration A_i:
    ///
    ///   V1 = v,                A1 = a(t, r, v)
    ///   V2 = v + (h/2)·A1,     A2 = a(t + h/2, r + (h/2)·V1, V2)
    ///   V3 = v + (h/2)·A2,     A3 = a(t + h/2, r + (h/2)·V2, V3)
    ///   V4 = v + h·A3,         A4 = a(t + h, r + h·V3, V4)
    ///   r(t + h) = r + (h/6)·(V1 + 2V2 + 2V3 + V4)
    ///   v(t + h) = v + (h/6)·(A1 + 2A2 + 2A3 + A4)
    ///
    /// It is fourth order.
    pub fn step(
        &mut self,
        system: &System,
        t: f64,
        h: f64,
        pos: &mut [DVec2],
        vel: &mut [DVec2],
    ) -> u32 {
        let half = 0.5 * h;
        let n = pos.len();
        let (r0, v0) = (&pos[..n], &vel[..n]);
        let sp = &mut self.stage_pos[..n];
        let sv = &mut self.stage_vel[..n];
        let acc = &mut self.acc[..n];
        let sr = &mut self.sum_pos[..n];
        let sa = &mut self.sum_vel[..n];

        // Stage 1: A1 = a(t, r, v).
        system.accelerations(t, r0, v0, acc);
        for i in 0..n {
            // Start the sums with the first slope (V1, A1) = (v, A1).
            sr[i] = v0[i];
            sa[i] = acc[i];
            // Stage 2 state: r + (h/2)·V1, V2 = v + (h/2)·A1.
            sp[i] = r0[i] + half * v0[i];
            sv[i] = v0[i] + half * acc[i];
        }

        // Stage 2: A2 = a(t + h/2, r + (h/2)·V1, V2).
        system.accelerations(t + half, sp, sv, acc);
        for i in 0..n {
            // Sums += 2·(V2, A2).
            sr[i] += 2.0 * sv[i];
            sa[i] += 2.0 * acc[i];
            // Stage 3 state: r + (h/2)·V2, V3 = v + (h/2)·A2.
            sp[i] = r0[i] + half * sv[i];
            sv[i] = v0[i] + half * acc[i];
        }

        // Stage 3: A3 = a(t + h/2, r + (h/2)·V2, V3).
        system.accelerations(t + half, sp, sv, acc);
        for i in 0..n {
            // Sums += 2·(V3, A3).
            sr[i] += 2.0 * sv[i];
            sa[i] += 2.0 * acc[i];
            // Stage 4 state: r + h·V3, V4 = v + h·A3.
            sp[i] = r0[i] + h * sv[i];
            sv[i] = v0[i] + h * acc[i];
        }

        // Stage 4: A4 = a(t + h, r + h·V3, V4).
        system.accelerations(t + h, sp, sv, acc);
        let sixth = h / 6.0;
        for i in 0..n {
            // r(t + h) = r + (h/6)·(V1 + 2V2 + 2V3 + V4).
            pos[i] += sixth * (sr[i] + sv[i]);
            // v(t + h) = v + (h/6)·(A1 + 2A2 + 2A3 + A4).
            vel[i] += sixth * (sa[i] + acc[i]);
        }
        4
    }
}
