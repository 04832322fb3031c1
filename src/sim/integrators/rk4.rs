//! The classical fourth-order Runge–Kutta method.

use glam::DVec2;

use crate::sim::dof::Dof;
use crate::sim::state::Coords;
use crate::sim::{State, System};

/// Scratch buffers for RK4: one stage state, its acceleration, and the running weighted
/// sums of the four slopes, for the linear pair and (for a system that spins) the
/// angular pair.
#[derive(Clone, Debug)]
pub struct Rk4 {
    lin: Buffers<DVec2>,
    ang: Buffers<f64>,
}

/// RK4's buffers for one kind of coordinate.
#[derive(Clone, Debug)]
struct Buffers<T> {
    stage_pos: Vec<T>,
    stage_vel: Vec<T>,
    acc: Vec<T>,
    sum_pos: Vec<T>,
    sum_vel: Vec<T>,
}

impl<T: Dof> Buffers<T> {
    fn new(n: usize) -> Self {
        Buffers {
            stage_pos: vec![T::ZERO; n],
            stage_vel: vec![T::ZERO; n],
            acc: vec![T::ZERO; n],
            sum_pos: vec![T::ZERO; n],
            sum_vel: vec![T::ZERO; n],
        }
    }

    /// After stage 1: starts the sums with (V1, A1) and writes the stage 2 state.
    fn after_first(&mut self, half: f64, r0: &[T], v0: &[T]) {
        let n = r0.len();
        let (sp, sv, acc) = (
            &mut self.stage_pos[..n],
            &mut self.stage_vel[..n],
            &self.acc[..n],
        );
        let (sr, sa) = (&mut self.sum_pos[..n], &mut self.sum_vel[..n]);
        for i in 0..n {
            // Start the sums with the first slope (V1, A1) = (v, A1).
            sr[i] = v0[i];
            sa[i] = acc[i];
            // Stage 2 state: r + (h/2)·V1, V2 = v + (h/2)·A1.
            sp[i] = r0[i] + v0[i] * half;
            sv[i] = v0[i] + acc[i] * half;
        }
    }

    /// After stage 2 or 3: adds 2·(V_k, A_k) to the sums and writes the next stage's
    /// state, r + c·V_k and v + c·A_k (c = h/2 before stage 3, h before stage 4).
    fn after_middle(&mut self, c: f64, r0: &[T], v0: &[T]) {
        let n = r0.len();
        let (sp, sv, acc) = (
            &mut self.stage_pos[..n],
            &mut self.stage_vel[..n],
            &self.acc[..n],
        );
        let (sr, sa) = (&mut self.sum_pos[..n], &mut self.sum_vel[..n]);
        for i in 0..n {
            // Sums += 2·(V_k, A_k).
            sr[i] += sv[i] * 2.0;
            sa[i] += acc[i] * 2.0;
            // Next stage state: r + c·V_k, V_(k+1) = v + c·A_k.
            sp[i] = r0[i] + sv[i] * c;
            sv[i] = v0[i] + acc[i] * c;
        }
    }

    /// After stage 4: the weighted average of the four slopes.
    fn finish(&self, h: f64, pos: &mut [T], vel: &mut [T]) {
        let n = pos.len();
        let (sv, acc) = (&self.stage_vel[..n], &self.acc[..n]);
        let (sr, sa) = (&self.sum_pos[..n], &self.sum_vel[..n]);
        let sixth = h / 6.0;
        for i in 0..n {
            // r(t + h) = r + (h/6)·(V1 + 2V2 + 2V3 + V4).
            pos[i] += (sr[i] + sv[i]) * sixth;
            // v(t + h) = v + (h/6)·(A1 + 2A2 + 2A3 + A4).
            vel[i] += (sa[i] + acc[i]) * sixth;
        }
    }
}

impl Rk4 {
    /// Allocates the buffers for `n` bodies, once per run; angular ones when `spin`.
    pub fn new(n: usize, spin: bool) -> Self {
        Rk4 {
            lin: Buffers::new(n),
            ang: Buffers::new(if spin { n } else { 0 }),
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
    /// A spinning body's (θ, ω) take the same four stages, with the angular
    /// accelerations α = τ/I in the place of a. It is fourth order.
    pub fn step(&mut self, system: &System, h: f64, state: &mut State) -> u32 {
        let (t, half, spin) = (state.t, 0.5 * h, system.spins());
        let (lin, ang) = (&mut self.lin, &mut self.ang);

        // Stage 1: A1 = a(t, r, v).
        system.derivatives(t, Coords::of(state), &mut lin.acc, &mut ang.acc);
        lin.after_first(half, &state.pos, &state.vel);
        if spin {
            ang.after_first(half, &state.angle, &state.omega);
        }

        // Stages 2 and 3: A_k = a(t + h/2, r + (h/2)·V_(k-1), V_k), then the state of
        // the next stage, at h/2 after stage 2 and at h after stage 3.
        for c in [half, h] {
            evaluate(system, t + half, lin, ang);
            lin.after_middle(c, &state.pos, &state.vel);
            if spin {
                ang.after_middle(c, &state.angle, &state.omega);
            }
        }

        // Stage 4: A4 = a(t + h, r + h·V3, V4).
        evaluate(system, t + h, lin, ang);
        lin.finish(h, &mut state.pos, &mut state.vel);
        if spin {
            ang.finish(h, &mut state.angle, &mut state.omega);
        }
        4
    }
}

/// Evaluates the slopes at the stage state held in the buffers, into their `acc`.
fn evaluate(system: &System, t: f64, lin: &mut Buffers<DVec2>, ang: &mut Buffers<f64>) {
    let y = Coords {
        pos: &lin.stage_pos,
        vel: &lin.stage_vel,
        angle: &ang.stage_pos,
        omega: &ang.stage_vel,
    };
    system.derivatives(t, y, &mut lin.acc, &mut ang.acc);
}
