//! Velocity Verlet, the workhorse of molecular dynamics, with a documented extension to
//! forces that depend on velocity.

use glam::DVec2;

use crate::sim::dof::Dof;
use crate::sim::state::Coords;
use crate::sim::{State, System};

/// Scratch buffers for velocity Verlet, including the acceleration carried over from the
/// end of one step to the start of the next, for the linear pair and (for a system that
/// spins) the angular pair.
#[derive(Clone, Debug)]
pub struct VelocityVerlet {
    lin: Buffers<DVec2>,
    ang: Buffers<f64>,
    /// The time at which `acc` was evaluated.
    acc_t: f64,
    /// True when `acc`, `acc_pos` and `acc_t` describe a valid carried-over acceleration.
    acc_valid: bool,
}

/// Velocity Verlet's buffers for one kind of coordinate.
#[derive(Clone, Debug)]
struct Buffers<T> {
    /// The acceleration at the start of the step.
    acc: Vec<T>,
    /// The acceleration at the end of the step.
    acc_end: Vec<T>,
    /// The predicted end-of-step velocity, v + h·a, used only for velocity-dependent forces.
    vel_pred: Vec<T>,
    /// The positions at which `acc` was evaluated, to check that the carried-over
    /// acceleration belongs to the state the next step starts from.
    acc_pos: Vec<T>,
}

impl<T: Dof> Buffers<T> {
    fn new(n: usize) -> Self {
        Buffers {
            acc: vec![T::ZERO; n],
            acc_end: vec![T::ZERO; n],
            vel_pred: vec![T::ZERO; n],
            acc_pos: vec![T::ZERO; n],
        }
    }

    /// r(t + h) = r + h·v + (h²/2)·a(t, r, v).
    fn drift(&self, h: f64, pos: &mut [T], vel: &[T]) {
        let half_h2 = 0.5 * h * h;
        for ((r, v), a) in pos.iter_mut().zip(vel.iter()).zip(&self.acc) {
            // r(t + h) = r + h·v + (h²/2)·a(t, r, v).
            *r += *v * h + *a * half_h2;
        }
    }

    /// ṽ = v + h·a(t, r, v).
    fn predict(&mut self, h: f64, vel: &[T]) {
        for ((vp, v), a) in self.vel_pred.iter_mut().zip(vel.iter()).zip(&self.acc) {
            // ṽ = v + h·a(t, r, v).
            *vp = *v + *a * h;
        }
    }

    /// v(t + h) = v + (h/2)·(a(t) + a(t + h)).
    fn kick(&self, h: f64, vel: &mut [T]) {
        let half = 0.5 * h;
        for ((v, a0), a1) in vel.iter_mut().zip(&self.acc).zip(&self.acc_end) {
            // v(t + h) = v + (h/2)·(a(t) + a(t + h)).
            *v += (*a0 + *a1) * half;
        }
    }

    /// Keeps a(t + h, r(t + h)) as the next step's start, with the positions it
    /// belongs to.
    fn carry(&mut self, pos: &[T]) {
        std::mem::swap(&mut self.acc, &mut self.acc_end);
        self.acc_pos.copy_from_slice(pos);
    }
}

impl VelocityVerlet {
    /// Allocates the buffers for `n` bodies, once per run; angular ones when `spin`.
    pub fn new(n: usize, spin: bool) -> Self {
        VelocityVerlet {
            lin: Buffers::new(n),
            ang: Buffers::new(if spin { n } else { 0 }),
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
    /// when the next step starts at the same positions (and angles) and (to within
    /// rounding) the same time it was evaluated at; otherwise it is evaluated again.
    ///
    /// Velocity-dependent forces (drag, spring damping, angular drag, see
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
    ///
    /// A spinning body's (θ, ω) take the same updates with α = τ/I in the place of a.
    pub fn step(&mut self, system: &System, h: f64, state: &mut State) -> u32 {
        let (t, spin) = (state.t, system.spins());
        let (lin, ang) = (&mut self.lin, &mut self.ang);
        let mut evaluations = 0;
        let carried = self.acc_valid
            && same_time(self.acc_t, t)
            && lin.acc_pos == state.pos
            && (!spin || ang.acc_pos == state.angle);
        if !carried {
            // a(t, r, v) at the start of the step.
            system.derivatives(t, Coords::of(state), &mut lin.acc, &mut ang.acc);
            evaluations += 1;
        }
        lin.drift(h, &mut state.pos, &state.vel);
        if spin {
            ang.drift(h, &mut state.angle, &state.omega);
        }
        let velocity_dependent = system.force_set().depends_on_velocity();
        if velocity_dependent {
            lin.predict(h, &state.vel);
            if spin {
                ang.predict(h, &state.omega);
            }
            // a(t + h, r(t + h), ṽ).
            let end = Coords {
                pos: &state.pos,
                vel: &lin.vel_pred,
                angle: &state.angle,
                omega: &ang.vel_pred,
            };
            system.derivatives(t + h, end, &mut lin.acc_end, &mut ang.acc_end);
        } else {
            // a(t + h, r(t + h)); the velocity passed is ignored by every force here.
            system.derivatives(t + h, Coords::of(state), &mut lin.acc_end, &mut ang.acc_end);
        }
        evaluations += 1;
        lin.kick(h, &mut state.vel);
        if spin {
            ang.kick(h, &mut state.omega);
        }
        if velocity_dependent {
            self.acc_valid = false;
        } else {
            // Carry a(t + h, r(t + h)) over to the next step.
            lin.carry(&state.pos);
            if spin {
                ang.carry(&state.angle);
            }
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
