//! Numerical integrators, one file per method, behind one enum and one `match`.
//!
//! Every integrator advances the flat arrays of positions and velocities from time t to
//! t + h using only the accelerations that the [`System`] reports. Scratch buffers live
//! in the [`Stepper`] and are allocated once per run, never per step.

mod explicit_euler;

use std::fmt;
use std::str::FromStr;

use glam::DVec2;

use super::System;

/// The integration methods a scene or the command line can choose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum IntegratorKind {
    /// Explicit (forward) Euler, exactly as the article writes it; the default.
    Euler,
}

/// An alias kept for brevity at call sites.
pub type Integrator = IntegratorKind;

impl IntegratorKind {
    /// Every method, in the order tables and legends list them.
    pub const ALL: &'static [IntegratorKind] = &[IntegratorKind::Euler];

    /// Returns the name a scene file uses for this method.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Euler => "euler",
        }
    }

    /// Returns the method's global order of accuracy for a fixed step.
    pub fn order(self) -> u32 {
        match self {
            IntegratorKind::Euler => 1,
        }
    }

    /// Returns how many times one step evaluates the forces.
    pub fn evaluations_per_step(self) -> u32 {
        match self {
            IntegratorKind::Euler => 1,
        }
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

/// Advances a state one step at a time with a chosen method, owning the scratch
/// buffers that method needs.
#[derive(Clone, Debug)]
pub struct Stepper {
    kind: IntegratorKind,
    /// Accelerations at the start of the step.
    acc: Vec<DVec2>,
    /// Force evaluations performed so far.
    evaluations: u64,
}

impl Stepper {
    /// Creates a stepper for `n` bodies.
    pub fn new(kind: IntegratorKind, n: usize) -> Self {
        Stepper {
            kind,
            acc: vec![DVec2::ZERO; n],
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

    /// Advances `pos` and `vel` from time `t` to `t + h`.
    pub fn step(&mut self, system: &System, t: f64, h: f64, pos: &mut [DVec2], vel: &mut [DVec2]) {
        debug_assert!(h > 0.0 && h.is_finite());
        self.evaluations += u64::from(self.kind.evaluations_per_step());
        match self.kind {
            IntegratorKind::Euler => {
                explicit_euler::step(system, t, h, pos, vel, &mut self.acc);
            }
        }
    }
}
