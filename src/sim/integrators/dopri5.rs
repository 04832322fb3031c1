//! The Dormand–Prince 5(4) embedded Runge–Kutta pair, with error control.
//!
//! One step computes seven stages; a fifth-order combination of them advances the state
//! and a fourth-order combination, subtracted from it, estimates the local error. The
//! seventh stage is evaluated at the new state, so it is the first stage of the next
//! step ("first same as last", FSAL): an accepted step costs six force evaluations, and
//! so does a rejected one (its first stage is still valid for the retry).
//!
//! The coefficients are those of Dormand and Prince (1980), as tabulated by Hairer,
//! Nørsett and Wanner, *Solving Ordinary Differential Equations I*, §II.5, Table 5.2.
//! The step-size controller, the PI controller of their code DOPRI5 (§IV.2), is in
//! `step_control.rs`.
//!
//! Why this file is long (about 700 lines): the stages, the error norm, the starting
//! step and the first-same-as-last bookkeeping share one set of buffers and one
//! tableau, and each is written once for any number of bodies and for the unrolled
//! versions of one to four; splitting them would separate code that must change
//! together.

use glam::DVec2;

use super::step_control::Tolerances;
use super::velocity_verlet::same_time;
use crate::sim::dof::Dof;
use crate::sim::state::Coords;
use crate::sim::{State, System};

/// The nodes c_i, the coefficients a_ij and the weights b_i of the fifth-order solution.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
/// E_i = b_i - b̂_i, the difference between the fifth- and fourth-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// The scratch buffers of Dormand–Prince for one kind of coordinate: the stage
/// velocities V_i and accelerations A_i (for the angular pair, the stage angular
/// velocities and angular accelerations).
///
/// With y = (r, v) and f(t, y) = (v, a(t, r, v)), stage i is the state
/// (R_i, V_i) = (r + h·Σ_j a_ij·V_j, v + h·Σ_j a_ij·A_j) and its slope is (V_i, A_i)
/// with A_i = a(t + c_i·h, R_i, V_i). V_1 is the starting velocity itself; R_7 and V_7
/// are the fifth-order result.
#[derive(Clone, Debug)]
struct Buffers<T> {
    a1: Vec<T>,
    a2: Vec<T>,
    a3: Vec<T>,
    a4: Vec<T>,
    a5: Vec<T>,
    a6: Vec<T>,
    a7: Vec<T>,
    v2: Vec<T>,
    v3: Vec<T>,
    v4: Vec<T>,
    v5: Vec<T>,
    v6: Vec<T>,
    /// V_7: the candidate velocity.
    v7: Vec<T>,
    /// The position of the stage being evaluated (R_2 … R_6).
    stage_pos: Vec<T>,
    /// R_7: the candidate position.
    new_pos: Vec<T>,
    /// The positions and velocities at which A_1 was evaluated.
    a1_pos: Vec<T>,
    a1_vel: Vec<T>,
}

/// Dormand–Prince's buffers for the linear pair and, for a system that spins, the
/// angular pair, and what it carries from one step to the next.
#[derive(Clone, Debug)]
pub struct Dopri5 {
    lin: Buffers<DVec2>,
    ang: Buffers<f64>,
    /// The time at which A_1 was evaluated.
    a1_t: f64,
    a1_valid: bool,
    /// The time at the end of the last attempted step.
    candidate_t: f64,
    /// True when the last attempt found every coordinate of its candidate finite
    /// (false: not known).
    candidate_finite: bool,
}

impl<T: Dof> Buffers<T> {
    fn new(n: usize) -> Self {
        let z = || vec![T::ZERO; n];
        Buffers {
            a1: z(),
            a2: z(),
            a3: z(),
            a4: z(),
            a5: z(),
            a6: z(),
            a7: z(),
            v2: z(),
            v3: z(),
            v4: z(),
            v5: z(),
            v6: z(),
            v7: z(),
            stage_pos: z(),
            new_pos: z(),
            a1_pos: z(),
            a1_vel: z(),
        }
    }

    /// Returns true when A_1 was evaluated at these positions and velocities.
    #[inline(always)]
    fn first_stage_is_at(&self, n: usize, pos: &[T], vel: &[T]) -> bool {
        self.a1_pos[..n] == pos[..n] && self.a1_vel[..n] == vel[..n]
    }

    /// Records the positions and velocities at which A_1 was just evaluated.
    #[inline(always)]
    fn first_stage_was_at(&mut self, n: usize, pos: &[T], vel: &[T]) {
        self.a1_pos[..n].copy_from_slice(&pos[..n]);
        self.a1_vel[..n].copy_from_slice(&vel[..n]);
    }

    /// Writes the state of stage `k` (2 to 6) into (`stage_pos`, V_k), or the
    /// fifth-order result into (R7, V7) for k = 7, from the start (r0, v0) and the
    /// slopes of the stages before it. `N` is the number of bodies when it is known at
    /// compile time, or 0 (see [`Dopri5::attempt`]).
    #[inline(always)]
    fn stage<const N: usize>(&mut self, k: usize, h: f64, r0: &[T], v0: &[T]) {
        let n = if N == 0 { r0.len() } else { N };
        // Every buffer as a slice of exactly n bodies, borrowed apart: the loops below
        // then need no bounds checks and the compiler knows the buffers do not overlap.
        let Buffers {
            a1,
            a2,
            a3,
            a4,
            a5,
            a6,
            v2,
            v3,
            v4,
            v5,
            v6,
            v7,
            stage_pos,
            new_pos,
            ..
        } = self;
        let (r0, v0, a1) = (&r0[..n], &v0[..n], &a1[..n]);
        let sp = &mut stage_pos[..n];
        match k {
            2 => {
                // Stage 2: R2 = r + h·a21·V1, V2 = v + h·a21·A1.
                let v2 = &mut v2[..n];
                let b = h * A21;
                for i in 0..n {
                    sp[i] = r0[i] + v0[i] * b;
                    v2[i] = v0[i] + a1[i] * b;
                }
            }
            3 => {
                // Stage 3: R3 = r + h·(a31·V1 + a32·V2), V3 = v + h·(a31·A1 + a32·A2).
                let (v2, a2, v3) = (&v2[..n], &a2[..n], &mut v3[..n]);
                let (b1, b2) = (h * A31, h * A32);
                for i in 0..n {
                    sp[i] = r0[i] + (v0[i] * b1 + v2[i] * b2);
                    v3[i] = v0[i] + (a1[i] * b1 + a2[i] * b2);
                }
            }
            4 => {
                // Stage 4: R4 = r + h·(a41·V1 + a42·V2 + a43·V3), and V4 likewise from
                // A1 … A3.
                let (v2, a2, v3, a3) = (&v2[..n], &a2[..n], &v3[..n], &a3[..n]);
                let v4 = &mut v4[..n];
                let (b1, b2, b3) = (h * A41, h * A42, h * A43);
                for i in 0..n {
                    sp[i] = r0[i] + (v0[i] * b1 + v2[i] * b2 + v3[i] * b3);
                    v4[i] = v0[i] + (a1[i] * b1 + a2[i] * b2 + a3[i] * b3);
                }
            }
            5 => {
                // Stage 5: R5 = r + h·(a51·V1 + a52·V2 + a53·V3 + a54·V4), and V5
                // likewise.
                let (v2, a2, v3, a3) = (&v2[..n], &a2[..n], &v3[..n], &a3[..n]);
                let (v4, a4, v5) = (&v4[..n], &a4[..n], &mut v5[..n]);
                let (b1, b2, b3, b4) = (h * A51, h * A52, h * A53, h * A54);
                for i in 0..n {
                    sp[i] = r0[i] + (v0[i] * b1 + v2[i] * b2 + v3[i] * b3 + v4[i] * b4);
                    v5[i] = v0[i] + (a1[i] * b1 + a2[i] * b2 + a3[i] * b3 + a4[i] * b4);
                }
            }
            6 => {
                // Stage 6: R6 = r + h·(a61·V1 + … + a65·V5), and V6 likewise; c6 = 1.
                let (v2, a2, v3, a3) = (&v2[..n], &a2[..n], &v3[..n], &a3[..n]);
                let (v4, a4, v5, a5) = (&v4[..n], &a4[..n], &v5[..n], &a5[..n]);
                let v6 = &mut v6[..n];
                let (b1, b2, b3, b4, b5) = (h * A61, h * A62, h * A63, h * A64, h * A65);
                for i in 0..n {
                    sp[i] =
                        r0[i] + (v0[i] * b1 + v2[i] * b2 + v3[i] * b3 + v4[i] * b4 + v5[i] * b5);
                    v6[i] =
                        v0[i] + (a1[i] * b1 + a2[i] * b2 + a3[i] * b3 + a4[i] * b4 + a5[i] * b5);
                }
            }
            _ => {
                // The fifth-order result, with b_i = a7i (b2 = b7 = 0):
                // R7 = r + h·(b1·V1 + b3·V3 + b4·V4 + b5·V5 + b6·V6), and V7 likewise.
                let (v3, a3, v4, a4) = (&v3[..n], &a3[..n], &v4[..n], &a4[..n]);
                let (v5, a5, v6, a6) = (&v5[..n], &a5[..n], &v6[..n], &a6[..n]);
                let (r1, v7) = (&mut new_pos[..n], &mut v7[..n]);
                let (b1, b3, b4, b5, b6) = (h * A71, h * A73, h * A74, h * A75, h * A76);
                for i in 0..n {
                    r1[i] =
                        r0[i] + (v0[i] * b1 + v3[i] * b3 + v4[i] * b4 + v5[i] * b5 + v6[i] * b6);
                    v7[i] =
                        v0[i] + (a1[i] * b1 + a3[i] * b3 + a4[i] * b4 + a5[i] * b5 + a6[i] * b6);
                }
            }
        }
    }

    /// Returns the sum over every component of ((y1 - ŷ1)/sc)², and the sum of every
    /// component of the candidate (R7 + V7), which is finite only if every component
    /// is.
    ///
    /// y1 - ŷ1 = h·Σ E_i·k_i, position part from the V_i, velocity part from the A_i,
    /// each component divided by sc = atol + rtol·max(|y0|, |y1|).
    #[inline(always)]
    fn error<const N: usize>(&self, h: f64, r0: &[T], v0: &[T], tol: Tolerances) -> (T, T) {
        let n = if N == 0 { r0.len() } else { N };
        let Buffers {
            a1,
            a3,
            a4,
            a5,
            a6,
            a7,
            v3,
            v4,
            v5,
            v6,
            v7,
            new_pos,
            ..
        } = self;
        let (r0, v0, r1) = (&r0[..n], &v0[..n], &new_pos[..n]);
        let (a1, a3, a4, a5, a6, a7) = (&a1[..n], &a3[..n], &a4[..n], &a5[..n], &a6[..n], &a7[..n]);
        let (v3, v4, v5, v6, v7) = (&v3[..n], &v4[..n], &v5[..n], &v6[..n], &v7[..n]);
        let (e1, e3, e4, e5, e6, e7) = (h * E1, h * E3, h * E4, h * E5, h * E6, h * E7);
        let (atol, rtol) = (T::splat(tol.atol), T::splat(tol.rtol));
        let mut sum = T::ZERO;
        let mut all = T::ZERO;
        for i in 0..n {
            all += r1[i] + v7[i];
            let er = v0[i] * e1 + v3[i] * e3 + v4[i] * e4 + v5[i] * e5 + v6[i] * e6 + v7[i] * e7;
            let ev = a1[i] * e1 + a3[i] * e3 + a4[i] * e4 + a5[i] * e5 + a6[i] * e6 + a7[i] * e7;
            let sr = atol + rtol * r0[i].abs().max(r1[i].abs());
            let sv = atol + rtol * v0[i].abs().max(v7[i].abs());
            let (qr, qv) = (er / sr, ev / sv);
            sum += qr * qr + qv * qv;
        }
        (sum, all)
    }

    /// The weighted squares of the starting-step heuristic's d0 = ‖y0‖ and
    /// d1 = ‖f(t0, y0)‖, summed over every component (see [`Dopri5::initial_step`]).
    fn start_norms(&self, pos: &[T], vel: &[T], tol: Tolerances) -> (f64, f64) {
        let (mut d0, mut d1) = (0.0, 0.0);
        for ((r, v), a) in pos.iter().zip(vel).zip(&self.a1) {
            let sr = T::splat(tol.atol) + T::splat(tol.rtol) * r.abs();
            let sv = T::splat(tol.atol) + T::splat(tol.rtol) * v.abs();
            // y0 = (r, v) and f0 = (v, a), both weighted by sc = atol + rtol·|y0|.
            let (qr, qv) = (*r / sr, *v / sv);
            d0 += (qr * qr).component_sum() + (qv * qv).component_sum();
            let (pr, pv) = (*v / sr, *a / sv);
            d1 += (pr * pr).component_sum() + (pv * pv).component_sum();
        }
        (d0, d1)
    }

    /// Writes y1 = y0 + h0·f0 into (`stage_pos`, V2), the state at which the heuristic
    /// samples the slope again.
    fn start_probe(&mut self, h0: f64, pos: &[T], vel: &[T]) {
        for i in 0..pos.len() {
            // y1 = y0 + h0·f0.
            self.stage_pos[i] = pos[i] + vel[i] * h0;
            self.v2[i] = vel[i] + self.a1[i] * h0;
        }
    }

    /// The weighted square of the heuristic's ‖f(t0 + h0, y1) - f(t0, y0)‖, summed
    /// over every component.
    fn probe_norm(&self, pos: &[T], vel: &[T], tol: Tolerances) -> f64 {
        let mut d2 = 0.0;
        for i in 0..pos.len() {
            let sr = T::splat(tol.atol) + T::splat(tol.rtol) * pos[i].abs();
            let sv = T::splat(tol.atol) + T::splat(tol.rtol) * vel[i].abs();
            // f1 - f0 = (v1 - v0, a1 - a0), with v1 - v0 = h0·a0.
            let (qr, qv) = ((self.v2[i] - vel[i]) / sr, (self.a2[i] - self.a1[i]) / sv);
            d2 += (qr * qr).component_sum() + (qv * qv).component_sum();
        }
        d2
    }

    /// Writes the candidate into (`pos`, `vel`) and keeps its last stage as the next
    /// step's first, with the state it belongs to.
    fn accept(&mut self, pos: &mut [T], vel: &mut [T]) {
        copy_bodies(pos, &self.new_pos);
        copy_bodies(vel, &self.v7);
        // FSAL: A7 = a(t + h, R7, V7) is A1 of the next step. Swapping buffers moves it,
        // and the state it belongs to, without copying.
        std::mem::swap(&mut self.a1, &mut self.a7);
        std::mem::swap(&mut self.a1_pos, &mut self.new_pos);
        std::mem::swap(&mut self.a1_vel, &mut self.v7);
    }
}

/// Evaluates the slopes at the state a stage wrote, for the first `n` bodies: the
/// buffers `pos` and `vel` of the linear and angular buffers hold the state, and the
/// slopes (A_k, α_k) go into their buffers `out`. The angular buffers are empty for a
/// system that does not spin, which then reads and writes none.
macro_rules! evaluate {
    ($system:expr, $t:expr, $lin:expr, $ang:expr, $n:expr, $pos:ident, $vel:ident, $out:ident) => {{
        let n = $n;
        let y = Coords {
            pos: &$lin.$pos[..n],
            vel: &$lin.$vel[..n],
            angle: &$ang.$pos[..$ang.$pos.len().min(n)],
            omega: &$ang.$vel[..$ang.$vel.len().min(n)],
        };
        let alpha_len = $ang.$out.len().min(n);
        $system.derivatives($t, y, &mut $lin.$out[..n], &mut $ang.$out[..alpha_len]);
    }};
}

impl Dopri5 {
    /// Allocates the buffers for `n` bodies, once per run; angular ones when `spin`.
    pub fn new(n: usize, spin: bool) -> Self {
        Dopri5 {
            lin: Buffers::new(n),
            ang: Buffers::new(if spin { n } else { 0 }),
            a1_t: 0.0,
            a1_valid: false,
            candidate_t: 0.0,
            candidate_finite: false,
        }
    }

    /// Forgets the carried-over first stage, so that the next step evaluates it afresh.
    pub fn reset(&mut self) {
        self.a1_valid = false;
    }

    /// Returns the number of components the error norm counts: 4 per body (the x and
    /// y of position and velocity), and 2 more (θ and ω) when the system spins.
    fn components(n: usize, spin: bool) -> usize {
        if spin {
            6 * n
        } else {
            4 * n
        }
    }

    /// Makes A_1 = a(t, r, v) (and α_1) valid for the given start, evaluating it unless
    /// the carried-over last stage of the previous step already is; returns the number
    /// of evaluations used (0 or 1). `N` is the number of bodies when it is known at
    /// compile time, or 0 when it is not (see [`Dopri5::attempt`]).
    #[inline(always)]
    fn ensure_first_stage<const N: usize>(&mut self, system: &System, state: &State) -> u32 {
        let n = if N == 0 { state.len() } else { N };
        let spin = system.spins();
        if self.a1_valid
            && same_time(self.a1_t, state.t)
            && self.lin.first_stage_is_at(n, &state.pos, &state.vel)
            && (!spin || self.ang.first_stage_is_at(n, &state.angle, &state.omega))
        {
            return 0;
        }
        let y = Coords {
            pos: &state.pos[..n],
            vel: &state.vel[..n],
            angle: &state.angle,
            omega: &state.omega,
        };
        system.derivatives(state.t, y, &mut self.lin.a1[..n], &mut self.ang.a1);
        self.lin.first_stage_was_at(n, &state.pos, &state.vel);
        if spin {
            self.ang.first_stage_was_at(n, &state.angle, &state.omega);
        }
        self.a1_t = state.t;
        self.a1_valid = true;
        1
    }

    /// Chooses a first step size with the starting-step heuristic of Hairer, Nørsett and
    /// Wanner (§II.4, "Starting Step Size"), capped at `h_max`; returns the step and the
    /// number of force evaluations used.
    ///
    /// With ‖·‖ the weighted RMS norm of [`Tolerances`] (weights from y0 alone):
    ///
    ///   d0 = ‖y0‖, d1 = ‖f(t0, y0)‖
    ///   h0 = 0.01·d0/d1 (or 10⁻⁶ when either is below 10⁻⁵)
    ///   d2 = ‖f(t0 + h0, y0 + h0·f(t0, y0)) - f(t0, y0)‖ / h0
    ///   h1 = (0.01 / max(d1, d2))^(1/5) (or max(10⁻⁶, 10⁻³·h0) when both are ≤ 10⁻¹⁵)
    ///   h  = min(100·h0, h1, h_max)
    ///
    /// so that the first explicit Euler step changes y by about 1% and the fifth-order
    /// local error, estimated from the second derivative, is about the tolerance. The
    /// slope f(t0, y0) is the first stage of the first step, so it is kept (FSAL). For a
    /// system that spins, y holds the angles and angular velocities too.
    pub fn initial_step(
        &mut self,
        system: &System,
        state: &State,
        tol: Tolerances,
        h_max: f64,
    ) -> (f64, u32) {
        let n = state.len();
        if n == 0 {
            return (h_max, 0);
        }
        let spin = system.spins();
        let t = state.t;
        let mut evaluations = self.ensure_first_stage::<0>(system, state);
        let count = Self::components(n, spin) as f64;
        let (mut d0, mut d1) = self.lin.start_norms(&state.pos, &state.vel, tol);
        if spin {
            let (a0, a1) = self.ang.start_norms(&state.angle, &state.omega, tol);
            (d0, d1) = (d0 + a0, d1 + a1);
        }
        let (d0, d1) = ((d0 / count).sqrt(), (d1 / count).sqrt());
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        let h0 = h0.min(h_max);
        self.lin.start_probe(h0, &state.pos, &state.vel);
        if spin {
            self.ang.start_probe(h0, &state.angle, &state.omega);
        }
        let (lin, ang) = (&mut self.lin, &mut self.ang);
        evaluate!(system, t + h0, lin, ang, n, stage_pos, v2, a2);
        evaluations += 1;
        let mut d2 = self.lin.probe_norm(&state.pos, &state.vel, tol);
        if spin {
            d2 += self.ang.probe_norm(&state.angle, &state.omega, tol);
        }
        let d2 = (d2 / count).sqrt() / h0;
        let d = d1.max(d2);
        let h1 = if d <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d).powf(1.0 / 5.0)
        };
        ((100.0 * h0).min(h1).min(h_max), evaluations)
    }

    /// Computes a candidate step from `state` (at its time t) to t + h without changing
    /// it, and returns its weighted RMS error estimate and the number of force
    /// evaluations used (6, or 7 when the first stage was not carried over).
    ///
    /// The error estimate is y1 - ŷ1 = h·Σ_i (b_i - b̂_i)·k_i, and its norm is
    /// err = sqrt((1/N)·Σ_j ((y1 - ŷ1)_j / sc_j)²), sc_j = atol + rtol·max(|y0_j|, |y1_j|),
    /// over the N = 4n position and velocity components, and for a system that spins
    /// the 2n angle and angular velocity components too (N = 6n).
    pub fn attempt(
        &mut self,
        system: &System,
        h: f64,
        state: &State,
        tol: Tolerances,
    ) -> (f64, u32) {
        // A few bodies are where an adaptive method spends its time on the cost of a
        // call rather than of a body: for them the number of bodies is made a constant,
        // so that every loop below, and the force evaluations inlined into them, are
        // unrolled into straight-line code. The arithmetic, and so every bit of the
        // result, is the same for every version.
        match state.len() {
            1 => self.attempt_n::<1>(system, h, state, tol),
            2 => self.attempt_n::<2>(system, h, state, tol),
            3 => self.attempt_n::<3>(system, h, state, tol),
            4 => self.attempt_n::<4>(system, h, state, tol),
            _ => self.attempt_n::<0>(system, h, state, tol),
        }
    }

    /// [`Dopri5::attempt`] for `N` bodies, or for any number of bodies when `N` is 0.
    #[inline(never)]
    fn attempt_n<const N: usize>(
        &mut self,
        system: &System,
        h: f64,
        state: &State,
        tol: Tolerances,
    ) -> (f64, u32) {
        let mut evaluations = self.ensure_first_stage::<N>(system, state);
        let n = if N == 0 { state.len() } else { N };
        let (t, spin) = (state.t, system.spins());
        let (lin, ang) = (&mut self.lin, &mut self.ang);
        let (r0, v0) = (&state.pos[..], &state.vel[..]);
        let (q0, w0) = (&state.angle[..], &state.omega[..]);
        // Each stage's state, for both kinds of coordinate, then its slopes.
        lin.stage::<N>(2, h, r0, v0);
        if spin {
            ang.stage::<N>(2, h, q0, w0);
        }
        evaluate!(system, t + C2 * h, lin, ang, n, stage_pos, v2, a2);
        lin.stage::<N>(3, h, r0, v0);
        if spin {
            ang.stage::<N>(3, h, q0, w0);
        }
        evaluate!(system, t + C3 * h, lin, ang, n, stage_pos, v3, a3);
        lin.stage::<N>(4, h, r0, v0);
        if spin {
            ang.stage::<N>(4, h, q0, w0);
        }
        evaluate!(system, t + C4 * h, lin, ang, n, stage_pos, v4, a4);
        lin.stage::<N>(5, h, r0, v0);
        if spin {
            ang.stage::<N>(5, h, q0, w0);
        }
        evaluate!(system, t + C5 * h, lin, ang, n, stage_pos, v5, a5);
        lin.stage::<N>(6, h, r0, v0);
        if spin {
            ang.stage::<N>(6, h, q0, w0);
        }
        evaluate!(system, t + h, lin, ang, n, stage_pos, v6, a6);
        lin.stage::<N>(7, h, r0, v0);
        if spin {
            ang.stage::<N>(7, h, q0, w0);
        }
        // A7 = a(t + h, R7, V7): the error estimate needs it, and it is the next A1.
        evaluate!(system, t + h, lin, ang, n, new_pos, v7, a7);
        evaluations += 6;

        // Σ ((y1 - ŷ1)/sc)² and Σ (R7 + V7): the sum is finite only if every
        // component of the candidate is, so that the check after the step need not
        // read the state again.
        let (sum, all) = lin.error::<N>(h, r0, v0, tol);
        let (mut sum, mut all) = (sum.component_sum(), all.component_sum());
        if spin {
            let (s, a) = ang.error::<N>(h, q0, w0, tol);
            sum += s;
            all += a;
        }
        self.candidate_t = t + h;
        self.candidate_finite = all.is_finite();
        let error = if n == 0 {
            0.0
        } else {
            (sum / Self::components(n, spin) as f64).sqrt()
        };
        (error, evaluations)
    }

    /// Writes the last candidate into `state`, taking `t_new` as its time (the caller
    /// may name the exact output time that t + h rounds to), and keeps its last stage
    /// as the next step's first. Returns true when every value written is known to be
    /// finite (false: not known).
    pub fn accept(&mut self, t_new: f64, state: &mut State) -> bool {
        debug_assert!(same_time(t_new, self.candidate_t));
        self.lin.accept(&mut state.pos, &mut state.vel);
        if !self.ang.a1.is_empty() {
            self.ang.accept(&mut state.angle, &mut state.omega);
        }
        self.a1_t = t_new;
        self.a1_valid = true;
        self.candidate_finite
    }
}

/// Copies `src` into `dst`, of equal lengths. For the few bodies of the systems where
/// an adaptive method spends its time per step rather than per body, the length is made
/// a constant, so that the copy is a few moves instead of a call to the C library.
#[inline(always)]
fn copy_bodies<T: Dof>(dst: &mut [T], src: &[T]) {
    match dst.len() {
        1 => dst[..1].copy_from_slice(&src[..1]),
        2 => dst[..2].copy_from_slice(&src[..2]),
        3 => dst[..3].copy_from_slice(&src[..3]),
        4 => dst[..4].copy_from_slice(&src[..4]),
        _ => dst.copy_from_slice(src),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Anchor, ForceSpec, Selection};

    /// Systems of `n` bodies with every force kind: springs between bodies and to
    /// points (damped or not, with and without rest length), and, when `per_body`,
    /// forces that act on each body alone, some on part of the bodies only.
    fn system(n: usize, per_body: bool) -> System {
        let mut forces = Vec::new();
        for i in 0..n as u32 {
            forces.push(ForceSpec::Spring {
                a: i,
                b: Anchor::Point(DVec2::new(0.5 * f64::from(i), -0.25)),
                stiffness: 3.0 + f64::from(i),
                rest_length: if i % 2 == 0 { 0.0 } else { 0.3 },
                damping: if i % 3 == 1 { 0.2 } else { 0.0 },
                a_at: None,
                b_at: None,
            });
            if i > 0 {
                forces.push(ForceSpec::Spring {
                    a: i - 1,
                    b: Anchor::Body(i),
                    stiffness: 2.0,
                    rest_length: 0.5 * f64::from(i % 2),
                    damping: 0.1,
                    a_at: None,
                    b_at: None,
                });
            }
        }
        if per_body {
            forces.push(ForceSpec::Gravity {
                g: DVec2::new(0.0, -9.81),
                bodies: Selection::All,
            });
            forces.push(ForceSpec::Drag {
                k: 0.3,
                bodies: Selection::Bodies(vec![0]),
            });
            forces.push(ForceSpec::QuadraticDrag {
                c: 0.05,
                bodies: Selection::All,
            });
            forces.push(ForceSpec::TimeVarying {
                f0: DVec2::new(0.1, 0.0),
                f1: DVec2::new(0.0, 0.2),
                bodies: Selection::All,
                at: None,
            });
            forces.push(ForceSpec::Central {
                centre: DVec2::new(-3.0, 2.0),
                strength: 1.5,
                bodies: Selection::All,
            });
        }
        let mass = (0..n).map(|i| 1.0 + 0.5 * i as f64).collect();
        System::new(mass, &forces)
    }

    /// Each version for a fixed number of bodies gives, to the bit, the error, the
    /// candidate and the carried-over stage of the version for any number of bodies,
    /// over steps whose first stages are carried over.
    #[test]
    fn fixed_body_counts_give_the_bits_of_the_general_step() {
        let tol = Tolerances::both(1e-8);
        for n in 1..=4 {
            for per_body in [false, true] {
                let system = system(n, per_body);
                let pos: Vec<DVec2> = (0..n)
                    .map(|i| DVec2::new(0.7 * i as f64 + 0.2, 0.1 * i as f64))
                    .collect();
                let vel: Vec<DVec2> = (0..n).map(|i| DVec2::new(0.3, -0.2 * i as f64)).collect();
                let mut s_fixed = State::new(0.0, pos, vel);
                let mut s_any = s_fixed.clone();
                let spin = system.spins();
                let (mut fixed, mut any) = (Dopri5::new(n, spin), Dopri5::new(n, spin));
                let (mut t, h) = (0.0, 0.01);
                for _ in 0..5 {
                    let a = fixed.attempt(&system, h, &s_fixed, tol);
                    let b = any.attempt_n::<0>(&system, h, &s_any, tol);
                    assert_eq!(a.0.to_bits(), b.0.to_bits(), "n = {n}");
                    assert_eq!(a.1, b.1);
                    fixed.accept(t + h, &mut s_fixed);
                    any.accept(t + h, &mut s_any);
                    s_fixed.t = t + h;
                    s_any.t = t + h;
                    let bits = |x: &[DVec2]| -> Vec<[u64; 2]> {
                        x.iter().map(|d| [d.x.to_bits(), d.y.to_bits()]).collect()
                    };
                    assert_eq!(bits(&s_fixed.pos), bits(&s_any.pos), "n = {n}");
                    assert_eq!(bits(&s_fixed.vel), bits(&s_any.vel), "n = {n}");
                    assert_eq!(bits(&fixed.lin.a1), bits(&any.lin.a1), "n = {n}");
                    t += h;
                }
            }
        }
    }
}
