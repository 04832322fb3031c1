//! Numerical integrators, one file per method, behind one enum and one `match`.
//!
//! Every integrator advances the flat arrays of positions and velocities from time t to
//! t + h using only the accelerations that the [`System`] reports. Scratch buffers live
//! in the [`Stepper`] and are allocated once per run, never per step.
//!
//! The fixed-step methods are explicit Euler, symplectic Euler, midpoint, Heun, RK4 and
//! velocity Verlet. Dormand–Prince 5(4) is adaptive: [`Stepper::attempt`] and
//! [`Stepper::accept`] let [`crate::sim::Simulation`] control its step size, and
//! [`Stepper::step`] takes one step of its fifth-order solution without error control
//! (which is how the convergence study measures its order).

mod dopri5;
mod explicit_euler;
mod heun;
mod midpoint;
mod rk4;
mod symplectic_euler;
mod velocity_verlet;

use std::fmt;
use std::str::FromStr;

use glam::DVec2;

use super::System;

pub use dopri5::{StepController, Tolerances};

/// The integration methods a scene or the command line can choose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum IntegratorKind {
    /// Explicit (forward) Euler, exactly as the article writes it; the default.
    Euler,
    /// Symplectic (semi-implicit) Euler: velocity first, then position with the new velocity.
    SymplecticEuler,
    /// The explicit midpoint method (RK2).
    Midpoint,
    /// Heun's method (the explicit trapezoidal rule).
    Heun,
    /// The classical fourth-order Runge–Kutta method.
    Rk4,
    /// Velocity Verlet.
    Verlet,
    /// Adaptive Dormand–Prince 5(4).
    Dopri5,
}

/// An alias kept for brevity at call sites.
pub type Integrator = IntegratorKind;

impl IntegratorKind {
    /// Every method, in the order tables and legends list them.
    pub const ALL: &'static [IntegratorKind] = &[
        IntegratorKind::Euler,
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Midpoint,
        IntegratorKind::Heun,
        IntegratorKind::Rk4,
        IntegratorKind::Verlet,
        IntegratorKind::Dopri5,
    ];

    /// Returns the name a scene file uses for this method.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Euler => "euler",
            IntegratorKind::SymplecticEuler => "symplectic-euler",
            IntegratorKind::Midpoint => "midpoint",
            IntegratorKind::Heun => "heun",
            IntegratorKind::Rk4 => "rk4",
            IntegratorKind::Verlet => "verlet",
            IntegratorKind::Dopri5 => "dopri5",
        }
    }

    /// Returns the method's global order of accuracy for a fixed step (for dopri5, the
    /// order of the solution it advances with).
    pub fn order(self) -> u32 {
        match self {
            IntegratorKind::Euler | IntegratorKind::SymplecticEuler => 1,
            IntegratorKind::Midpoint | IntegratorKind::Heun | IntegratorKind::Verlet => 2,
            IntegratorKind::Rk4 => 4,
            IntegratorKind::Dopri5 => 5,
        }
    }

    /// Returns how many times one step evaluates the forces in the steady state.
    ///
    /// Two methods carry their last evaluation over to the next step: velocity Verlet
    /// (1 per step, but 2 when some force depends on velocity) and dopri5 (6 per
    /// attempted step, accepted or rejected). Both pay one more evaluation on their
    /// first step, and dopri5 one more for its starting-step heuristic. The counter
    /// [`Stepper::evaluations`] counts what was actually done.
    pub fn evaluations_per_step(self) -> u32 {
        match self {
            IntegratorKind::Euler | IntegratorKind::SymplecticEuler | IntegratorKind::Verlet => 1,
            IntegratorKind::Midpoint | IntegratorKind::Heun => 2,
            IntegratorKind::Rk4 => 4,
            IntegratorKind::Dopri5 => 6,
        }
    }

    /// Returns true when the method controls its own step size from an error estimate.
    pub fn is_adaptive(self) -> bool {
        matches!(self, IntegratorKind::Dopri5)
    }

    /// Returns the names of every method, for error messages.
    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|k| k.name()).collect()
    }
}

impl fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for IntegratorKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                format!(
                    "unknown integrator `{s}`; expected one of: {}",
                    Self::names().join(", ")
                )
            })
    }
}

/// The scratch buffers of each method.
#[derive(Clone, Debug)]
enum Workspace {
    /// Explicit Euler's accelerations.
    Euler(Vec<DVec2>),
    /// Symplectic Euler's accelerations.
    SymplecticEuler(Vec<DVec2>),
    Midpoint(midpoint::Midpoint),
    Heun(heun::Heun),
    Rk4(rk4::Rk4),
    Verlet(velocity_verlet::VelocityVerlet),
    Dopri5(Box<dopri5::Dopri5>),
}

/// Advances a state one step at a time with a chosen method, owning the scratch
/// buffers that method needs and counting force evaluations.
#[derive(Clone, Debug)]
pub struct Stepper {
    kind: IntegratorKind,
    work: Workspace,
    /// Force evaluations performed so far.
    evaluations: u64,
}

impl Stepper {
    /// Creates a stepper for `n` bodies, allocating every buffer it will use.
    pub fn new(kind: IntegratorKind, n: usize) -> Self {
        let work = match kind {
            IntegratorKind::Euler => Workspace::Euler(vec![DVec2::ZERO; n]),
            IntegratorKind::SymplecticEuler => Workspace::SymplecticEuler(vec![DVec2::ZERO; n]),
            IntegratorKind::Midpoint => Workspace::Midpoint(midpoint::Midpoint::new(n)),
            IntegratorKind::Heun => Workspace::Heun(heun::Heun::new(n)),
            IntegratorKind::Rk4 => Workspace::Rk4(rk4::Rk4::new(n)),
            IntegratorKind::Verlet => Workspace::Verlet(velocity_verlet::VelocityVerlet::new(n)),
            IntegratorKind::Dopri5 => Workspace::Dopri5(Box::new(dopri5::Dopri5::new(n))),
        };
        Stepper {
            kind,
            work,
            evaluations: 0,
        }
    }

    /// Returns the method this stepper uses.
    pub fn kind(&self) -> IntegratorKind {
        self.kind
    }

    /// Returns the number of force evaluations performed so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Zeroes the evaluation counter and forgets any evaluation carried over from the
    /// last step, as before a new run.
    pub fn reset(&mut self) {
        self.evaluations = 0;
        match &mut self.work {
            Workspace::Verlet(w) => w.reset(),
            Workspace::Dopri5(w) => w.reset(),
            _ => {}
        }
    }

    /// Advances `pos` and `vel` from time `t` to `t + h` with a fixed step.
    ///
    /// For dopri5 this is one step of its fifth-order solution, without error control.
    pub fn step(&mut self, system: &System, t: f64, h: f64, pos: &mut [DVec2], vel: &mut [DVec2]) {
        debug_assert!(h > 0.0 && h.is_finite());
        let used = match &mut self.work {
            Workspace::Euler(acc) => {
                explicit_euler::step(system, t, h, pos, vel, acc);
                1
            }
            Workspace::SymplecticEuler(acc) => symplectic_euler::step(system, t, h, pos, vel, acc),
            Workspace::Midpoint(w) => w.step(system, t, h, pos, vel),
            Workspace::Heun(w) => w.step(system, t, h, pos, vel),
            Workspace::Rk4(w) => w.step(system, t, h, pos, vel),
            Workspace::Verlet(w) => w.step(system, t, h, pos, vel),
            Workspace::Dopri5(w) => {
                let tol = Tolerances::default();
                let (_, used) = w.attempt(system, t, h, pos, vel, tol);
                w.accept(t + h, pos, vel);
                used
            }
        };
        self.evaluations += u64::from(used);
    }

    /// Chooses the first step of an adaptive method (see `Dopri5::initial_step`),
    /// at most `h_max`; a fixed-step method simply returns `h_max`.
    pub fn initial_step(
        &mut self,
        system: &System,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        tol: Tolerances,
        h_max: f64,
    ) -> f64 {
        match &mut self.work {
            Workspace::Dopri5(w) => {
                let (h, used) = w.initial_step(system, t, pos, vel, tol, h_max);
                self.evaluations += u64::from(used);
                h
            }
            _ => h_max,
        }
    }

    /// Computes a candidate step from `(t, pos, vel)` to `t + h` without changing the
    /// state, and returns its weighted RMS error estimate (at most 1 means within
    /// `tol`), or `None` for a method without an error estimate, which computes nothing.
    /// Every force evaluation is counted, whether the step is then accepted or not.
    pub fn attempt(
        &mut self,
        system: &System,
        t: f64,
        h: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        tol: Tolerances,
    ) -> Option<f64> {
        debug_assert!(h > 0.0 && h.is_finite());
        match &mut self.work {
            Workspace::Dopri5(w) => {
                let (error, used) = w.attempt(system, t, h, pos, vel, tol);
                self.evaluations += u64::from(used);
                Some(error)
            }
            _ => None,
        }
    }

    /// Writes the candidate of the last [`Stepper::attempt`] into `pos` and `vel`, whose
    /// time is `t_new`, and returns true when every value written is known to be
    /// finite. Does nothing (and returns false) for a method without an error estimate.
    pub fn accept(&mut self, t_new: f64, pos: &mut [DVec2], vel: &mut [DVec2]) -> bool {
        match &mut self.work {
            Workspace::Dopri5(w) => w.accept(t_new, pos, vel),
            _ => false,
        }
    }
}

/// Writes the state a sub-step of explicit Euler of length `c` reaches from (r, v) with
/// acceleration a, the first stage of the midpoint and Heun methods:
///
///   r_out = r + c·v,  v_out = v + c·a
pub(crate) fn euler_substep(
    c: f64,
    (pos, vel, acc): (&[DVec2], &[DVec2], &[DVec2]),
    out_pos: &mut [DVec2],
    out_vel: &mut [DVec2],
) {
    for (((ro, vo), (r, v)), a) in out_pos
        .iter_mut()
        .zip(out_vel.iter_mut())
        .zip(pos.iter().zip(vel))
        .zip(acc)
    {
        // r_out = r + c·v.
        *ro = *r + c * *v;
        // v_out = v + c·a.
        *vo = *v + c * *a;
    }
}
