//! Numerical integrators, one file per method, behind one enum and one `match`.
//!
//! Every integrator advances the flat arrays of positions and velocities from time t to
//! t + h using only the accelerations that the [`System`] reports. When the system
//! spins ([`System::spins`]), it advances the angles and angular velocities in the same
//! stages, from the angular accelerations the system reports with the accelerations:
//! each method's stages are written once, generic over the coordinate type ([`Dof`]),
//! and run on the linear pair (r, v) and the angular pair (θ, ω) alike. Scratch buffers
//! live in the [`Stepper`] and are allocated once per run, never per step; the angular
//! ones only for a system that spins.
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
mod step_control;
mod symplectic_euler;
mod velocity_verlet;

use std::fmt;
use std::str::FromStr;

use glam::DVec2;

use super::dof::Dof;
use super::{State, System};

pub use step_control::{StepController, Tolerances};

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

/// One evaluation's derivatives of the velocities: the accelerations a of the centres of
/// mass and, for a system that spins, the angular accelerations α (empty otherwise).
#[derive(Clone, Debug)]
pub(crate) struct Slopes {
    pub acc: Vec<DVec2>,
    pub alpha: Vec<f64>,
}

impl Slopes {
    /// Allocates the slopes of `n` bodies, with angular ones when `spin`.
    pub fn new(n: usize, spin: bool) -> Self {
        Slopes {
            acc: vec![DVec2::ZERO; n],
            alpha: vec![0.0; if spin { n } else { 0 }],
        }
    }
}

/// The scratch buffers of each method.
#[derive(Clone, Debug)]
enum Workspace {
    /// Explicit Euler's accelerations.
    Euler(Slopes),
    /// Symplectic Euler's accelerations.
    SymplecticEuler(Slopes),
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
    /// Creates a stepper for the bodies of `system`, allocating every buffer it will
    /// use: angular ones only when the system spins.
    pub fn new(kind: IntegratorKind, system: &System) -> Self {
        let (n, spin) = (system.len(), system.spins());
        let work = match kind {
            IntegratorKind::Euler => Workspace::Euler(Slopes::new(n, spin)),
            IntegratorKind::SymplecticEuler => Workspace::SymplecticEuler(Slopes::new(n, spin)),
            IntegratorKind::Midpoint => Workspace::Midpoint(midpoint::Midpoint::new(n, spin)),
            IntegratorKind::Heun => Workspace::Heun(heun::Heun::new(n, spin)),
            IntegratorKind::Rk4 => Workspace::Rk4(rk4::Rk4::new(n, spin)),
            IntegratorKind::Verlet => {
                Workspace::Verlet(velocity_verlet::VelocityVerlet::new(n, spin))
            }
            IntegratorKind::Dopri5 => Workspace::Dopri5(Box::new(dopri5::Dopri5::new(n, spin))),
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

    /// Advances `state` from its time t to t + h with a fixed step, and sets its time
    /// to t + h. (The simulation then writes t = t0 + n·h, which does not accumulate
    /// rounding.) The angles and angular velocities advance only when the system spins.
    ///
    /// For dopri5 this is one step of its fifth-order solution, without error control.
    pub fn step(&mut self, system: &System, h: f64, state: &mut State) {
        debug_assert!(h > 0.0 && h.is_finite());
        debug_assert!(!system.spins() || state.angle.len() == state.len());
        let t = state.t;
        let used = match &mut self.work {
            Workspace::Euler(slopes) => {
                explicit_euler::step(system, h, state, slopes);
                1
            }
            Workspace::SymplecticEuler(slopes) => symplectic_euler::step(system, h, state, slopes),
            Workspace::Midpoint(w) => w.step(system, h, state),
            Workspace::Heun(w) => w.step(system, h, state),
            Workspace::Rk4(w) => w.step(system, h, state),
            Workspace::Verlet(w) => w.step(system, h, state),
            Workspace::Dopri5(w) => {
                let tol = Tolerances::default();
                let (_, used) = w.attempt(system, h, state, tol);
                w.accept(t + h, state);
                used
            }
        };
        state.t = t + h;
        self.evaluations += u64::from(used);
    }

    /// Chooses the first step of an adaptive method from `state` (see
    /// `Dopri5::initial_step`), at most `h_max`; a fixed-step method simply returns
    /// `h_max`.
    pub fn initial_step(
        &mut self,
        system: &System,
        state: &State,
        tol: Tolerances,
        h_max: f64,
    ) -> f64 {
        match &mut self.work {
            Workspace::Dopri5(w) => {
                let (h, used) = w.initial_step(system, state, tol, h_max);
                self.evaluations += u64::from(used);
                h
            }
            _ => h_max,
        }
    }

    /// Computes a candidate step from `state` (at its time t) to t + h without changing
    /// the state, and returns its weighted RMS error estimate (at most 1 means within
    /// `tol`), or `None` for a method without an error estimate, which computes nothing.
    /// Every force evaluation is counted, whether the step is then accepted or not.
    pub fn attempt(
        &mut self,
        system: &System,
        h: f64,
        state: &State,
        tol: Tolerances,
    ) -> Option<f64> {
        debug_assert!(h > 0.0 && h.is_finite());
        match &mut self.work {
            Workspace::Dopri5(w) => {
                let (error, used) = w.attempt(system, h, state, tol);
                self.evaluations += u64::from(used);
                Some(error)
            }
            _ => None,
        }
    }

    /// Writes the candidate of the last [`Stepper::attempt`] into `state`, with the time
    /// `t_new`, and returns true when every value written is known to be finite. Does
    /// nothing (and returns false) for a method without an error estimate.
    pub fn accept(&mut self, t_new: f64, state: &mut State) -> bool {
        match &mut self.work {
            Workspace::Dopri5(w) => {
                let finite = w.accept(t_new, state);
                state.t = t_new;
                finite
            }
            _ => false,
        }
    }
}

/// Writes the state a sub-step of explicit Euler of length `c` reaches from a
/// coordinate y and its rate y' with derivative a, the first stage of the midpoint
/// and Heun methods; for (r, v) and for (θ, ω) alike:
///
///   r_out = r + c·v,  v_out = v + c·a
pub(crate) fn euler_substep<T: Dof>(
    c: f64,
    (pos, vel, acc): (&[T], &[T], &[T]),
    out_pos: &mut [T],
    out_vel: &mut [T],
) {
    for (((ro, vo), (r, v)), a) in out_pos
        .iter_mut()
        .zip(out_vel.iter_mut())
        .zip(pos.iter().zip(vel))
        .zip(acc)
    {
        // r_out = r + c·v.
        *ro = *r + *v * c;
        // v_out = v + c·a.
        *vo = *v + *a * c;
    }
}

/// Advances a coordinate and its rate by one step of explicit Euler with derivative a,
/// for (r, v) and for (θ, ω) alike:
///
///   r(t + h) = r(t) + h·v(t)
///   v(t + h) = v(t) + h·a(t)
#[inline]
pub(crate) fn euler_advance<T: Dof>(h: f64, pos: &mut [T], vel: &mut [T], acc: &[T]) {
    for ((r, v), a) in pos.iter_mut().zip(vel.iter_mut()).zip(acc.iter()) {
        // r(t + h) = r(t) + h·v(t), with the rate from the start of the step.
        *r += *v * h;
        // v(t + h) = v(t) + h·a(t).
        *v += *a * h;
    }
}
