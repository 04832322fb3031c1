//! The driver that steps a system through time and stops when the state blows up.

use std::fmt;

use glam::DVec2;

use super::contacts::{ContactEvent, Contacts, Overlap, Stop, Unanswerable};
use super::integrators::{StepController, Tolerances};
use super::state::Coords;
use super::{IntegratorKind, State, Stepper, System};

/// The most steps an adaptive method may take in one call of `advance_to` (one frame),
/// before the run is stopped as too stiff for it.
pub const MAX_ADAPTIVE_STEPS_PER_ADVANCE: u64 = 1_000_000;

/// The `quantity` of a [`BlowUp`] that is not a non-finite value but an adaptive step
/// size driven towards zero by a stiff scene.
pub const STIFF: &str = "adaptive step size";

/// The `quantity` of a [`BlowUp`] that is two bodies left overlapping deeper than the
/// contact tolerance after a step (see [`BlowUp::overlap`]).
pub const OVERLAP: &str = "overlap";

/// The `quantity` of a [`BlowUp`] that is a body whose contacts a step cannot answer
/// (see [`BlowUp::unanswerable`]).
pub const UNANSWERABLE: &str = "contacts";

/// A simulation whose state stopped being finite.
#[derive(Clone, Debug, PartialEq)]
pub struct BlowUp {
    /// The index of the first body whose position or velocity is not finite.
    pub body: usize,
    /// The step (counted from 1) after which it was found.
    pub step: u64,
    /// The simulated time at the end of that step.
    pub t: f64,
    /// The quantity that stopped being finite: "position", "velocity", "angle" or
    /// "angular velocity"; or [`STIFF`], [`OVERLAP`] or [`UNANSWERABLE`].
    pub quantity: &'static str,
    /// For [`OVERLAP`]: the two bodies and how deep they overlap.
    pub overlap: Option<Overlap>,
    /// For [`UNANSWERABLE`]: the body and why.
    pub unanswerable: Option<Unanswerable>,
}

impl fmt::Display for BlowUp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(o) = self.overlap {
            return write!(
                f,
                "bodies #{} and #{} overlap by {:e} after step {} (t = {})",
                o.a, o.b, o.depth, self.step, self.t
            );
        }
        if let Some(u) = self.unanswerable {
            return write!(
                f,
                "the contacts of body #{} cannot be answered at step {} (t = {}): {:?}",
                u.body, self.step, self.t, u.why
            );
        }
        if self.quantity == STIFF {
            return write!(
                f,
                "the adaptive step size fell so far that {} steps did not reach the next output time (step {}, t = {})",
                MAX_ADAPTIVE_STEPS_PER_ADVANCE, self.step, self.t
            );
        }
        write!(
            f,
            "the {} of body #{} became non-finite at step {} (t = {})",
            self.quantity, self.body, self.step, self.t
        )
    }
}

/// A system, its state and an integrator, advanced with a fixed step h, or, for an
/// adaptive method, with steps of at most h chosen by error control.
///
/// For a fixed step, time is kept as a step count n, and t = n·h is computed from it, so
/// that a long run does not accumulate rounding in t and the state at a frame is the
/// state at exactly the step that frame names.
///
/// For an adaptive method (dopri5), h is the largest step allowed, the first step is
/// chosen by the starting-step heuristic of Hairer, Nørsett and Wanner (and is at most
/// h), and every later step by the PI controller of [`StepController`] from the
/// [`Tolerances`]. [`Simulation::advance_to`] lands exactly on the requested time by
/// shortening the last step (see there), so every state a frame shows is the result of
/// an accepted, error-controlled step.
#[derive(Clone, Debug)]
pub struct Simulation {
    system: System,
    stepper: Stepper,
    state: State,
    h: f64,
    t0: f64,
    steps: u64,
    adaptive: Option<Adaptive>,
    /// Collisions, for a scene with `[contacts]`.
    contacts: Option<Box<Colliding>>,
}

/// What a simulation with collisions keeps: the contacts, and the state at the start of
/// the step being taken (the start of every body's path through it).
#[derive(Clone, Debug)]
struct Colliding {
    contacts: Contacts,
    start: State,
    /// The steps taken at once because every body was held (see
    /// [`Simulation::held_steps`]).
    held: u64,
}

/// The step-size control of an adaptive run.
#[derive(Clone, Debug)]
struct Adaptive {
    tol: Tolerances,
    controller: StepController,
    /// The size of the next step, or `None` before the first.
    h_next: Option<f64>,
    /// Steps rejected so far.
    rejected: u64,
}

impl Adaptive {
    fn new(tol: Tolerances) -> Self {
        Adaptive {
            tol,
            controller: StepController::default(),
            h_next: None,
            rejected: 0,
        }
    }
}

impl Simulation {
    /// Creates a simulation that starts from `initial` and steps by `h` (for an adaptive
    /// method: by at most `h`, with the default [`Tolerances`]).
    ///
    /// When some body of `initial` spins already, the system is made to spin (see
    /// [`System::spins`]), so that its angle advances even when nothing acts on it.
    pub fn new(mut system: System, initial: State, kind: IntegratorKind, h: f64) -> Self {
        debug_assert_eq!(system.len(), initial.len());
        debug_assert_eq!(initial.angle.len(), initial.len());
        debug_assert_eq!(initial.omega.len(), initial.len());
        debug_assert!(h > 0.0 && h.is_finite());
        if !system.spins() && initial.omega.iter().any(|w| *w != 0.0) {
            system.start_spinning();
        }
        let stepper = Stepper::new(kind, &system);
        let t0 = initial.t;
        let adaptive = kind
            .is_adaptive()
            .then(|| Adaptive::new(Tolerances::default()));
        Simulation {
            system,
            stepper,
            state: initial,
            h,
            t0,
            steps: 0,
            adaptive,
            contacts: None,
        }
    }

    /// Makes the bodies of `contacts` collide, and returns the simulation. When an
    /// impulse can turn a body (any collider that is not a disc and can move), the
    /// system is made to spin.
    pub fn with_contacts(mut self, contacts: Contacts) -> Self {
        let inv = self.system.inverse_masses();
        // An impulse turns a collider that can move, unless it is a disc without
        // friction (whose normal always passes through its centre).
        let turnable = contacts.colliders().iter().any(|c| {
            inv[c.body] > 0.0
                && (c.friction > 0.0
                    || !matches!(c.shape, super::contacts::ColliderShape::Disc { .. }))
        });
        if turnable && !self.system.spins() && self.system.inertia().is_some() {
            self.system.start_spinning();
            self.stepper = Stepper::new(self.stepper.kind(), &self.system);
        }
        let start = self.state.clone();
        self.contacts = Some(Box::new(Colliding {
            contacts,
            start,
            held: 0,
        }));
        self
    }

    /// Returns the contacts of a simulation with collisions.
    pub fn contacts(&self) -> Option<&Contacts> {
        self.contacts.as_deref().map(|c| &c.contacts)
    }

    /// Restores the resting contacts' warm start (see [`Contacts::set_warm_start`]), as
    /// a checkpoint records it; without collisions, nothing.
    pub fn set_contact_warm_start(&mut self, entries: &[super::contacts::WarmPoint]) {
        if let Some(c) = &mut self.contacts {
            c.contacts.set_warm_start(entries);
        }
    }

    /// Restores each collider's time at rest and whether it sleeps (see
    /// [`Contacts::sleep_state`]), as a checkpoint records it; without collisions,
    /// nothing.
    pub fn set_contact_sleep_state(&mut self, still: &[f64]) {
        if let Some(c) = &mut self.contacts {
            c.contacts.set_sleep_state(still);
        }
    }

    /// Starts or stops recording every impulse for [`Simulation::take_contact_events`].
    pub fn record_contacts(&mut self, on: bool) {
        if let Some(c) = &mut self.contacts {
            c.contacts.record(on);
        }
    }

    /// Returns the impulses applied since the last call, in the order they were
    /// applied (empty without collisions or recording).
    pub fn take_contact_events(&mut self) -> Vec<ContactEvent> {
        self.contacts
            .as_mut()
            .map_or_else(Vec::new, |c| c.contacts.take_log())
    }

    /// Sets the tolerances of an adaptive method (ignored by a fixed-step one), and
    /// returns the simulation.
    pub fn with_tolerances(mut self, tol: Tolerances) -> Self {
        self.set_tolerances(tol);
        self
    }

    /// Sets the tolerances of an adaptive method; a fixed-step method ignores them.
    pub fn set_tolerances(&mut self, tol: Tolerances) {
        debug_assert!(tol.rtol >= 0.0 && tol.atol >= 0.0 && tol.rtol + tol.atol > 0.0);
        if let Some(a) = &mut self.adaptive {
            a.tol = tol;
        }
    }

    /// Returns the tolerances of an adaptive method, or `None` for a fixed step.
    pub fn tolerances(&self) -> Option<Tolerances> {
        self.adaptive.as_ref().map(|a| a.tol)
    }

    /// Starts again from `initial`, reusing every buffer: the counters return to zero and
    /// an adaptive method chooses its first step afresh.
    pub fn reset(&mut self, initial: &State) {
        debug_assert_eq!(initial.len(), self.system.len());
        self.state.t = initial.t;
        self.state.pos.copy_from_slice(&initial.pos);
        self.state.vel.copy_from_slice(&initial.vel);
        self.state.angle.copy_from_slice(&initial.angle);
        self.state.omega.copy_from_slice(&initial.omega);
        self.t0 = initial.t;
        self.steps = 0;
        self.stepper.reset();
        if let Some(a) = &mut self.adaptive {
            *a = Adaptive::new(a.tol);
        }
        self.set_contact_warm_start(&[]);
        self.set_contact_sleep_state(&[]);
    }

    /// Recreates a simulation that started at `t0` and has taken `steps` steps of size
    /// `h` to reach `state`, as a checkpoint records it; it then goes on bit for bit as
    /// the original run would, for a method that keeps no state between steps.
    pub fn restore(
        system: System,
        state: State,
        kind: IntegratorKind,
        h: f64,
        t0: f64,
        steps: u64,
    ) -> Self {
        Simulation::new(system, state, kind, h).continuing(t0, steps)
    }

    /// Returns the simulation, whose state is that of a run that started at `t0` and
    /// has taken `steps` steps, counting its time from there (see
    /// [`Simulation::restore`]).
    pub fn continuing(mut self, t0: f64, steps: u64) -> Self {
        self.t0 = t0;
        self.steps = steps;
        self
    }

    /// Returns how many of this simulation's steps were taken at once, every body
    /// asleep or static, without the integrator (0 without contacts).
    pub fn held_steps(&self) -> u64 {
        self.contacts.as_ref().map_or(0, |c| c.held)
    }

    /// Returns the current state.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// Returns the system being integrated.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Returns the step size h (for an adaptive method, the largest step allowed).
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Returns the number of steps taken (for an adaptive method, accepted) so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Returns the number of steps an adaptive method rejected so far (0 for a fixed step).
    pub fn rejected_steps(&self) -> u64 {
        self.adaptive.as_ref().map_or(0, |a| a.rejected)
    }

    /// Returns the number of force evaluations so far, including those of rejected steps
    /// and of the starting-step heuristic.
    pub fn evaluations(&self) -> u64 {
        self.stepper.evaluations()
    }

    /// Returns the integration method.
    pub fn integrator(&self) -> IntegratorKind {
        self.stepper.kind()
    }

    /// Writes the net force on every body at the current state into `force`, wherever
    /// on the body each force acts.
    pub fn net_forces(&self, force: &mut [DVec2]) {
        let s = &self.state;
        if self.system.spins() {
            let mut torque = vec![0.0; s.len()];
            self.system
                .net_forces_and_torques(s.t, Coords::of(s), force, &mut torque);
        } else {
            self.system.net_forces(s.t, &s.pos, &s.vel, force);
        }
    }

    /// Takes one step (for an adaptive method: one accepted step of the size the
    /// controller chooses), then checks that the state is still finite.
    pub fn step(&mut self) -> Result<(), BlowUp> {
        if self.adaptive.is_some() {
            return self.adaptive_step(f64::INFINITY);
        }
        if self.holds_everything() {
            return Ok(());
        }
        self.remember_start();
        let t_start = self.state.t;
        self.stepper.step(&self.system, self.h, &mut self.state);
        self.steps += 1;
        // t_n = t0 + n·h, computed rather than summed.
        self.state.t = self.t0 + self.steps as f64 * self.h;
        self.check_finite()?;
        self.collide(t_start)
    }

    /// Takes the step at once when every body is asleep or static and nothing can move
    /// (see [`Contacts::holds_everything`]): the time advances and the state keeps its
    /// bits, as the integrator followed by the contacts' hold would leave it. Returns
    /// whether it did. A scene at rest then costs a pass over its sleep states a step,
    /// not an integration and a pass over every collider.
    fn holds_everything(&mut self) -> bool {
        let Some(c) = &mut self.contacts else {
            return false;
        };
        let spins = self.system.spins();
        let inertia = if spins {
            self.system.inverse_inertia()
        } else {
            None
        };
        if !c
            .contacts
            .holds_everything(self.system.len(), self.system.inverse_masses(), inertia)
        {
            return false;
        }
        c.contacts.hold_still();
        c.held += 1;
        // What the full step does after a hold: the stepper forgets what it carried
        // over, and t_n = t0 + n·h.
        self.stepper.reset();
        self.steps += 1;
        self.state.t = self.t0 + self.steps as f64 * self.h;
        true
    }

    /// Keeps the state at the start of the step about to be taken, for collisions.
    fn remember_start(&mut self) {
        if let Some(c) = &mut self.contacts {
            let (from, to) = (&self.state, &mut c.start);
            to.t = from.t;
            to.pos.copy_from_slice(&from.pos);
            to.vel.copy_from_slice(&from.vel);
            to.angle.copy_from_slice(&from.angle);
            to.omega.copy_from_slice(&from.omega);
        }
    }

    /// Resolves the collisions of the step just taken from `t_start`; a step that
    /// changed any velocity makes the stepper forget what it carries over (velocity
    /// Verlet's last acceleration, dopri5's last stage), which belonged to the state
    /// before the impulses.
    fn collide(&mut self, t_start: f64) -> Result<(), BlowUp> {
        let Some(c) = &mut self.contacts else {
            return Ok(());
        };
        let t_end = self.state.t;
        match c
            .contacts
            .resolve(&self.system, &c.start, &mut self.state, t_start, t_end)
        {
            Ok(false) => Ok(()),
            Ok(true) => {
                self.stepper.reset();
                // Impulses on a state near overflow can themselves overflow.
                self.system.record_finite_step(&self.state.pos, false);
                self.check_finite()
            }
            Err(Stop::Overlap(o)) => Err(BlowUp {
                body: o.a,
                step: self.steps,
                t: t_end,
                quantity: OVERLAP,
                overlap: Some(o),
                unanswerable: None,
            }),
            Err(Stop::Unanswerable(u)) => Err(BlowUp {
                body: u.body,
                step: self.steps,
                t: t_end,
                quantity: UNANSWERABLE,
                overlap: None,
                unanswerable: Some(u),
            }),
        }
    }

    /// Takes one step that ends at or before `t_limit`: an adaptive method shortens its
    /// step to land on `t_limit`; a fixed-step method takes its usual step.
    pub fn step_towards(&mut self, t_limit: f64) -> Result<(), BlowUp> {
        if self.adaptive.is_some() {
            return self.adaptive_step(t_limit);
        }
        self.step()
    }

    /// Takes `n` steps, stopping at the first that blows up.
    pub fn run_steps(&mut self, n: u64) -> Result<(), BlowUp> {
        for _ in 0..n {
            self.step()?;
        }
        Ok(())
    }

    /// Advances to time `t_end`.
    ///
    /// ```
    /// use glam::DVec2;
    /// use physframes::sim::{ForceSpec, IntegratorKind, Selection, Simulation, State, System};
    ///
    /// // The article's Equation 12: drag F = -v on a body of mass 1, from v0 = 2.
    /// let drag = [ForceSpec::Drag { k: 1.0, bodies: Selection::All }];
    /// let system = System::new(vec![1.0], &drag);
    /// let start = State::new(0.0, vec![DVec2::ZERO], vec![DVec2::new(2.0, 0.0)]);
    /// let h = 0.001;
    /// let mut sim = Simulation::new(system, start, IntegratorKind::Euler, h);
    /// sim.advance_to(1.0).expect("drag stays finite");
    /// // Explicit Euler gives exactly v_n = v0·(1 - h·k/m)^n, after n = 1000 steps.
    /// let v = sim.state().vel[0].x;
    /// assert!((v - 2.0 * (1.0 - h).powi(1000)).abs() < 1e-12);
    /// assert_eq!(sim.steps(), 1000);
    /// ```
    /// With a fixed step, it advances to the step nearest `t_end` (which should be a
    /// whole number of steps from the start; frame times are, by validation).
    ///
    /// With an adaptive method, it lands exactly on `t_end`: when the step the controller
    /// proposes would reach past `t_end`, or stop short of it by less than 1% of a step,
    /// the step is set to end exactly there (the rule of Hairer's DOPRI5). The shortened
    /// step is error-controlled like any other, so the state at `t_end` meets the
    /// tolerances; the alternative, dense output, would evaluate a fourth-order
    /// interpolant whose error the controller never checks. The price is at most one
    /// extra step per output time. After a shortened step the next step resumes at the
    /// size proposed before shortening (or larger, if the controller asks), so frequent
    /// frames do not ratchet the step size down.
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), BlowUp> {
        if self.adaptive.is_some() {
            // A stiff scene drives the adaptive step towards zero, and the run would never
            // end; past a budget of steps for one advance it stops and says so instead.
            let budget = self.steps + MAX_ADAPTIVE_STEPS_PER_ADVANCE;
            while self.state.t < t_end {
                self.adaptive_step(t_end)?;
                if self.steps >= budget && self.state.t < t_end {
                    return Err(BlowUp {
                        body: 0,
                        step: self.steps,
                        t: self.state.t,
                        quantity: STIFF,
                        overlap: None,
                        unanswerable: None,
                    });
                }
            }
            return Ok(());
        }
        let target = ((t_end - self.t0) / self.h).round();
        let target = if target > 0.0 { target as u64 } else { 0 };
        while self.steps < target {
            self.step()?;
        }
        Ok(())
    }

    /// Takes one accepted adaptive step that ends at or before `t_limit`, retrying with
    /// smaller steps until the error estimate is within the tolerances.
    ///
    /// A step of at most h_min = 16·ε·max(|t|, h_max), too short to change t reliably, is
    /// accepted whatever its error: when the error is only round-off, the run goes on;
    /// when the state has stopped being finite, the check that follows reports it.
    fn adaptive_step(&mut self, t_limit: f64) -> Result<(), BlowUp> {
        self.remember_start();
        let Some(adaptive) = self.adaptive.as_mut() else {
            return Ok(());
        };
        let state = &mut self.state;
        let t = state.t;
        let mut h = match adaptive.h_next {
            Some(h) => h,
            None => self
                .stepper
                .initial_step(&self.system, state, adaptive.tol, self.h),
        };
        // Never above h_max, so that the clamp below has its bounds in order.
        let h_min = (16.0 * f64::EPSILON * t.abs().max(self.h)).min(self.h);
        loop {
            h = h.clamp(h_min, self.h);
            let proposed = h;
            // The last step before t_limit ends exactly on it: h = t_limit - t whenever
            // t + 1.01·h ≥ t_limit.
            let lands = t + 1.01 * h >= t_limit;
            if lands {
                h = t_limit - t;
            }
            let err = self
                .stepper
                .attempt(&self.system, h, state, adaptive.tol)
                .unwrap_or(0.0);
            let (accepted, h_new) = adaptive.controller.decide(err, h);
            if accepted || h <= h_min {
                let t_new = if lands { t_limit } else { t + h };
                let finite = self.stepper.accept(t_new, state);
                self.steps += 1;
                adaptive.h_next = Some(if lands { h_new.max(proposed) } else { h_new });
                // A candidate known to be finite needs no check, and no record for the
                // check to take (an atomic exchange, which waits for every store of the
                // step). Otherwise no stale record may vouch for it: the check reads
                // the state.
                if !finite {
                    self.system.record_finite_step(&self.state.pos, false);
                    self.check_finite()?;
                }
                return self.collide(t);
            }
            adaptive.rejected += 1;
            h = h_new;
        }
    }

    /// Returns an error naming the first body whose state is not finite.
    fn check_finite(&self) -> Result<(), BlowUp> {
        let s = &self.state;
        // A step that checked what it wrote leaves a record; otherwise one fast pass
        // over the flat arrays answers the common case. The slow search runs only after
        // a blow-up. Angles change only in a system that spins.
        let spins = self.system.spins();
        if (self.system.take_finite_step(&s.pos) || s.is_finite())
            && (!spins || s.angles_are_finite())
        {
            return Ok(());
        }
        for (i, (p, v)) in s.pos.iter().zip(&s.vel).enumerate() {
            let quantity = if !p.is_finite() {
                "position"
            } else if !v.is_finite() {
                "velocity"
            } else if spins && !s.angle[i].is_finite() {
                "angle"
            } else if spins && !s.omega[i].is_finite() {
                "angular velocity"
            } else {
                continue;
            };
            return Err(BlowUp {
                body: i,
                step: self.steps,
                t: s.t,
                quantity,
                overlap: None,
                unanswerable: None,
            });
        }
        // Finite terms can overflow when summed; that is not a blow-up of any body.
        Ok(())
    }
}
