//! The reference problems whose bodies turn: a spin-up under a constant torque, angular
//! drag with and without a driving torque, and a box hanging by a spring at its corner,
//! which has no closed form and is measured against a fine rk4 run.

use std::sync::OnceLock;

use glam::DVec2;

use super::{only, ReferenceKind, ReferenceProblem, Solution};
use crate::sim::{Anchor, ForceSpec, IntegratorKind, Selection, Simulation, State, System};

/// The step of the reference runs of problems without a closed form: rk4's error per
/// unit time is about (h·ω_max)^4 times the solution's size, with ω_max the fastest
/// rate of the motion; at h = 10⁻⁵ and ω_max ~ 10 that is 10⁻¹⁶, below the round-off
/// of the 10⁵ steps of a unit of time (about √(10⁵)·ε·|y| ~ 10⁻¹⁴).
pub const REFERENCE_STEP: f64 = 1e-5;

/// Integrates `system` from `initial` to `t` with rk4 at [`REFERENCE_STEP`] (the last
/// step shortened to land on `t`), for problems without a closed form.
pub(super) fn reference_run(system: &System, initial: &State, t: f64) -> State {
    let span = t - initial.t;
    let steps = (span / REFERENCE_STEP).ceil().max(1.0);
    let mut sim = Simulation::new(
        system.clone(),
        initial.clone(),
        IntegratorKind::Rk4,
        span / steps,
    );
    // A smooth problem of bounded energy stays finite; if it did not, the non-finite
    // state itself makes every error against it infinite, which the studies report.
    let _ = sim.run_steps(steps as u64);
    let mut out = sim.state().clone();
    out.t = t;
    out
}

/// Returns a system of bodies of the given masses and moments of inertia, with their
/// centres of mass at the origins of their body coordinates.
pub(super) fn rigid(mass: Vec<f64>, inertia: Vec<f64>, forces: &[ForceSpec]) -> System {
    let centre = vec![DVec2::ZERO; mass.len()];
    System::rigid(mass, inertia, centre, forces)
}

/// A motor's constant torque τ = 0.6 on two bodies at rest: body 0 (I = 0.2) spins up
/// from rest, α = 3; body 1 (I = 0.4) starts spinning backwards at ω0 = -2 and is
/// turned round, α = 1.5. Every method of order two or more integrates a constant
/// angular acceleration exactly, as it does the constant acceleration.
pub(super) fn spin_up() -> ReferenceProblem {
    let tau = 0.6;
    let inertia = vec![0.2, 0.4];
    let system = rigid(
        vec![1.0, 2.0],
        inertia.clone(),
        &[ForceSpec::Torque {
            tau,
            bodies: Selection::All,
        }],
    );
    let mut initial = State::new(0.0, vec![DVec2::ZERO, DVec2::X], vec![DVec2::ZERO; 2]);
    initial.angle = vec![0.0, 0.5];
    initial.omega = vec![0.0, -2.0];
    ReferenceProblem {
        kind: ReferenceKind::SpinUp,
        system,
        initial,
        t_end: 2.0,
        solution: Solution::Spin {
            rates: inertia.iter().map(|i| (tau / i, 0.0)).collect(),
        },
    }
}

/// Angular drag k = 0.5 on two bodies: body 0 (I = 0.25) spins down from ω0 = 8 with
/// rate λ = k/I = 2, ω = ω0·e^(-λt); body 1 (I = 0.5, λ = 1) is driven from rest by a
/// torque τ = 2 towards its terminal spin τ/k = 4.
pub(super) fn angular_drag() -> ReferenceProblem {
    let k = 0.5;
    let (inertia, tau) = (vec![0.25, 0.5], 2.0);
    let system = rigid(
        vec![1.0, 1.0],
        inertia.clone(),
        &[
            ForceSpec::AngularDrag {
                k,
                bodies: Selection::All,
            },
            ForceSpec::Torque {
                tau,
                bodies: only(1),
            },
        ],
    );
    let mut initial = State::new(0.0, vec![DVec2::ZERO, DVec2::X], vec![DVec2::ZERO; 2]);
    initial.angle = vec![0.25, 0.0];
    initial.omega = vec![8.0, 0.0];
    ReferenceProblem {
        kind: ReferenceKind::AngularDrag,
        system,
        initial,
        t_end: 2.0,
        solution: Solution::Spin {
            rates: vec![(0.0, k / inertia[0]), (tau / inertia[1], k / inertia[1])],
        },
    }
}

/// A 0.6 × 0.3 box of mass 1 (I = M·(w² + h²)/12 = 0.0375) hanging by an undamped
/// spring (k = 20, rest length 0.2) from its corner (0.3, 0.15) to the origin, under
/// gravity. Let go tilted by 0.4 rad and off to the side, it swings and turns, the
/// spring's torque about the centre of mass coupling the two: a problem with every
/// part of the rigid-body equations and no closed form.
pub(super) fn hanging_box() -> ReferenceProblem {
    let (m, w, h) = (1.0, 0.6, 0.3);
    let inertia = m * (w * w + h * h) / 12.0;
    let system = rigid(
        vec![m],
        vec![inertia],
        &[
            ForceSpec::Spring {
                a: 0,
                b: Anchor::Point(DVec2::ZERO),
                stiffness: 20.0,
                rest_length: 0.2,
                damping: 0.0,
                a_at: Some(DVec2::new(0.5 * w, 0.5 * h)),
                b_at: None,
            },
            ForceSpec::Gravity {
                g: DVec2::new(0.0, -9.81),
                bodies: Selection::All,
            },
        ],
    );
    let mut initial = State::new(0.0, vec![DVec2::new(0.2, -0.6)], vec![DVec2::ZERO]);
    initial.angle = vec![0.4];
    ReferenceProblem {
        kind: ReferenceKind::HangingBox,
        system,
        initial,
        t_end: 1.0,
        solution: Solution::Numerical {
            at_end: OnceLock::new(),
        },
    }
}
