//! The driver that steps a system through time and stops when the state blows up.

use std::fmt;

use glam::DVec2;

use super::{IntegratorKind, State, Stepper, System};

/// A simulation whose state stopped being finite.
#[derive(Clone, Debug, PartialEq)]
pub struct BlowUp {
    /// The index of the first body whose position or velocity is not finite.
    pub body: usize,
    /// The step (counted from 1) after which it was found.
    pub step: u64,
    /// The simulated time at the end of that step.
    pub t: f64,
    /// The quantity that stopped being finite: "position" or "velocity".
    pub quantity: &'static str,
}

impl fmt::Display for BlowUp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the {} of body #{} became non-finite at step {} (t = {})",
            self.quantity, self.body, self.step, self.t
        )
    }
}

/// A system, its state and an integrator, advanced with a fixed step h.
///
/// Time is kept as a step count n, and t = n·h is computed from it, so that a long run
/// does not accumulate rounding in t and the state at a frame is the state at exactly
/// the step that frame names.
#[derive(Clone, Debug)]
pub struct Simulation {
    system: System,
    stepper: Stepper,
    state: State,
    h: f64,
    t0: f64,
    steps: u64,
}

impl Simulation {
    /// Creates a simulation that starts from `initial` and steps by `h`.
    pub fn new(system: System, initial: State, kind: IntegratorKind, h: f64) -> Self {
        debug_assert_eq!(system.len(), initial.len());
        debug_assert!(h > 0.0 && h.is_finite());
        let stepper = Stepper::new(kind, system.len());
        let t0 = initial.t;
        Simulation {
            system,
            stepper,
            state: initial,
            h,
            t0,
            steps: 0,
        }
    }

    /// Returns the current state.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// Returns the system being integrated.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Returns the step size h.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Returns the number of steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Returns the number of force evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.stepper.evaluations()
    }

    /// Returns the integration method.
    pub fn integrator(&self) -> IntegratorKind {
        self.stepper.kind()
    }

    /// Writes the net force on every body at the current state into `force`.
    pub fn net_forces(&self, force: &mut [DVec2]) {
        let s = &self.state;
        self.system.net_forces(s.t, &s.pos, &s.vel, force);
    }

    /// Takes one step of size h, then checks that the state is still finite.
    pub fn step(&mut self) -> Result<(), BlowUp> {
        let t = self.state.t;
        self.stepper.step(
            &self.system,
            t,
            self.h,
            &mut self.state.pos,
            &mut self.state.vel,
        );
        self.steps += 1;
        // t_n = t0 + n·h, computed rather than summed.
        self.state.t = self.t0 + self.steps as f64 * self.h;
        self.check_finite()
    }

    /// Takes `n` steps, stopping at the first that blows up.
    pub fn run_steps(&mut self, n: u64) -> Result<(), BlowUp> {
        for _ in 0..n {
            self.step()?;
        }
        Ok(())
    }

    /// Advances to the step nearest time `t_end` (for a fixed step, `t_end` should be a
    /// whole number of steps from the start; frame times are, by validation).
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), BlowUp> {
        let target = ((t_end - self.t0) / self.h).round();
        let target = if target > 0.0 { target as u64 } else { 0 };
        while self.steps < target {
            self.step()?;
        }
        Ok(())
    }

    /// Returns an error naming the first body whose state is not finite.
    fn check_finite(&self) -> Result<(), BlowUp> {
        let s = &self.state;
        // A step that checked what it wrote leaves a record; otherwise one fast pass
        // over the flat arrays answers the common case. The slow search runs only after
        // a blow-up.
        if self.system.take_finite_step(&s.pos) || s.is_finite() {
            return Ok(());
        }
        for (i, (p, v)) in s.pos.iter().zip(&s.vel).enumerate() {
            let quantity = if !p.is_finite() {
                "position"
            } else if !v.is_finite() {
                "velocity"
            } else {
                continue;
            };
            return Err(BlowUp {
                body: i,
                step: self.steps,
                t: s.t,
                quantity,
            });
        }
        // Finite terms can overflow when summed; that is not a blow-up of any body.
        Ok(())
    }
}
