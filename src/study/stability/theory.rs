//! What linear stability theory says of each integrator: its stability polynomial,
//! its per-step growth on the drag and spring test problems, where its stability
//! boundary lies, and the stable step a blow-up message quotes for a scene.

use std::f64::consts::SQRT_2;

use super::{bisect, StabilityProblem};
use crate::sim::{Anchor, ForceSpec, IntegratorKind};

/// What linear stability theory says about one integrator on one test equation.
#[derive(Clone, Debug, PartialEq)]
pub struct Theory {
    /// The end of the stable interval of s that starts at 0 (0 when only s = 0 is
    /// stable).
    pub boundary: f64,
    /// Drag only: the s past which R(-s) < 0 and the velocity changes sign every step.
    pub sign_flip: Option<f64>,
    /// Where the number comes from, in one line.
    pub reason: &'static str,
}

/// Returns theory's answer for `kind` on `problem`.
pub fn theory(problem: StabilityProblem, kind: IntegratorKind) -> Theory {
    use IntegratorKind::*;
    match (problem, kind) {
        (StabilityProblem::Drag, Euler | SymplecticEuler) => Theory {
            boundary: 2.0,
            sign_flip: Some(1.0),
            reason: "R = 1 - s: |1 - s| ≤ 1 for s ≤ 2, negative past 1",
        },
        (StabilityProblem::Drag, Midpoint | Heun | Verlet) => Theory {
            boundary: 2.0,
            sign_flip: None,
            reason: "R = 1 - s + s²/2 ≤ 1 for s ≤ 2, never negative",
        },
        (StabilityProblem::Drag, Rk4 | Dopri5) => Theory {
            boundary: bisect(|s| drag_theory_growth(kind, s) <= 1.0, 1.0, 5.0, 1e-15),
            sign_flip: None,
            reason: if kind == Rk4 {
                "|R(-s)| = 1 with R the degree-4 Taylor polynomial of exp: s³ - 4s² + 12s - 24 = 0"
            } else {
                "|R(-s)| = 1 with R(z) = Σ_{k≤5} z^k/k! + z⁶/600 (fixed steps, no error control)"
            },
        },
        (StabilityProblem::Spring, Euler) => Theory {
            boundary: 0.0,
            sign_flip: None,
            reason: "ρ = |1 + is| = (1 + s²)^(1/2) > 1: energy grows by 1 + s² every step",
        },
        (StabilityProblem::Spring, Midpoint | Heun) => Theory {
            boundary: 0.0,
            sign_flip: None,
            reason: "ρ = |1 + is - s²/2| = (1 + s⁴/4)^(1/2) > 1 for every s > 0",
        },
        (StabilityProblem::Spring, SymplecticEuler | Verlet) => Theory {
            boundary: 2.0,
            sign_flip: None,
            reason: "one-step map with det = 1 and trace 2 - s²: |eigenvalues| = 1 while s < 2",
        },
        (StabilityProblem::Spring, Rk4) => Theory {
            boundary: 2.0 * SQRT_2,
            sign_flip: None,
            reason: "|R(is)|² = 1 - s⁶/72 + s⁸/576 ≤ 1 for s ≤ 2√2",
        },
        (StabilityProblem::Spring, Dopri5) => Theory {
            // |R(is)|² - 1 = s⁶·q(s²) with q(u) = -1/1800 + u/1600 - u²/14400 + u³/360000,
            // negative from u = 0 up to its first root.
            boundary: bisect(|s| dopri5_imaginary_q(s * s) <= 0.0, 0.5, 2.0, 1e-15),
            sign_flip: None,
            reason:
                "|R(is)|² - 1 = s⁶·(-1/1800 + s²/1600 - s⁴/14400 + s⁶/360000) ≤ 0 (fixed steps)",
        },
    }
}

/// Returns a sentence giving the step that theory says would be stable for this
/// scene's linear drag, angular drag and springs with this integrator, or `None` when
/// none applies or theory has no limit for the method. `inertia` gives the bodies'
/// moments of inertia (angular drag's rate is k/I), or is empty when unknown.
pub fn stable_step_hint(
    kind: IntegratorKind,
    masses: &[f64],
    inertia: &[f64],
    forces: &[ForceSpec],
) -> Option<String> {
    let n = masses.len();
    // The fastest drag rate k/m of any body: the sum of every drag on it over its mass.
    let mut drag_rate = vec![0.0f64; n];
    // The fastest angular drag rate k/I: ω' = -(k/I)·ω is the drag's test equation.
    let mut spin_rate = vec![0.0f64; n];
    // The fastest spring frequency ω = √(stiffness/μ), μ the reduced mass.
    let mut omega = 0.0f64;
    for f in forces {
        match f {
            ForceSpec::Drag { k, bodies } => {
                bodies.for_each(n, |i| drag_rate[i] += k / masses[i]);
            }
            ForceSpec::AngularDrag { k, bodies } if inertia.len() == n => {
                bodies.for_each(n, |i| {
                    if inertia[i] > 0.0 {
                        spin_rate[i] += k / inertia[i];
                    }
                });
            }
            ForceSpec::Spring {
                a, b, stiffness, ..
            } => {
                let ma = masses[*a as usize];
                let mu = match b {
                    Anchor::Body(b) => {
                        let mb = masses[*b as usize];
                        ma * mb / (ma + mb)
                    }
                    Anchor::Point(_) => ma,
                };
                omega = omega.max((stiffness / mu).sqrt());
            }
            _ => {}
        }
    }
    // An adaptive method chooses its own steps: no fixed step to quote.
    if kind.is_adaptive() {
        return None;
    }
    let drag_limit = theory(StabilityProblem::Drag, kind).boundary;
    let spring_limit = theory(StabilityProblem::Spring, kind).boundary;
    let rate = drag_rate.iter().copied().fold(0.0, f64::max);
    let mut limits = Vec::new();
    if rate > 0.0 {
        limits.push((
            drag_limit / rate,
            format!(
                "linear drag with k/m = {rate} needs dt ≤ {drag_limit}·m/k = {}",
                drag_limit / rate
            ),
        ));
    }
    let spin = spin_rate.iter().copied().fold(0.0, f64::max);
    if spin > 0.0 {
        limits.push((
            drag_limit / spin,
            format!(
                "angular drag with k/I = {spin} needs dt ≤ {drag_limit}·I/k = {}",
                drag_limit / spin
            ),
        ));
    }
    if omega > 0.0 {
        if spring_limit == 0.0 {
            return Some(format!(
                "{kind} is never stable on an undamped spring (here ω = {omega}): its energy grows every step; use symplectic-euler or verlet with dt < 2/ω = {}, or rk4 with dt ≤ 2√2/ω = {}",
                2.0 / omega,
                2.0 * SQRT_2 / omega
            ));
        }
        limits.push((
            spring_limit / omega,
            format!(
                "a spring with ω = {omega} needs dt < {spring_limit}/ω = {}",
                spring_limit / omega
            ),
        ));
    }
    limits
        .into_iter()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, text)| format!("linear stability theory for {kind}: {text}"))
}

/// Returns theory's per-step amplification of `kind` on `problem` at the dimensionless
/// step `s`, from the stability polynomial (or, for the symplectic methods on the
/// spring, from the trace and determinant of their one-step map).
pub fn theory_growth(problem: StabilityProblem, kind: IntegratorKind, s: f64) -> f64 {
    use IntegratorKind::*;
    match problem {
        StabilityProblem::Drag => drag_theory_growth(kind, s),
        StabilityProblem::Spring => match kind {
            SymplecticEuler | Verlet => {
                // Both maps have det = 1 and trace 2 - s²: eigenvalues on the unit circle
                // while |trace| ≤ 2, else real with the larger modulus
                // |tr|/2 + √(tr²/4 - 1).
                let half = 0.5 * (2.0 - s * s);
                if half.abs() <= 1.0 {
                    1.0
                } else {
                    half.abs() + (half * half - 1.0).sqrt()
                }
            }
            // ρ = |R(is)|, written in closed forms that keep the difference from 1 free
            // of cancellation for small s.
            Euler => (1.0 + s * s).sqrt(),
            Midpoint | Heun => (1.0 + s.powi(4) / 4.0).sqrt(),
            Rk4 => (1.0 - s.powi(6) / 72.0 + s.powi(8) / 576.0).sqrt(),
            Dopri5 => (1.0 + s.powi(6) * dopri5_imaginary_q(s * s)).sqrt(),
        },
    }
}

/// Returns |R(-s)| for `kind`'s stability polynomial on the negative real axis.
pub(super) fn drag_theory_growth(kind: IntegratorKind, s: f64) -> f64 {
    polynomial(stability_polynomial(kind), -s).abs()
}

/// Returns the coefficients of R(z), lowest power first, for the velocity update of
/// `kind` on drag: symplectic Euler updates v exactly as explicit Euler does, and
/// velocity Verlet, on a velocity-dependent force, updates v by Heun's method.
pub(super) fn stability_polynomial(kind: IntegratorKind) -> &'static [f64] {
    use IntegratorKind::*;
    match kind {
        Euler | SymplecticEuler => &[1.0, 1.0],
        Midpoint | Heun | Verlet => &[1.0, 1.0, 0.5],
        Rk4 => &[1.0, 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0],
        // The fifth-order solution of Dormand–Prince: the Taylor polynomial of exp to
        // degree 5, and z⁶/600 from its seven stages.
        Dopri5 => &[
            1.0,
            1.0,
            1.0 / 2.0,
            1.0 / 6.0,
            1.0 / 24.0,
            1.0 / 120.0,
            1.0 / 600.0,
        ],
    }
}

/// Evaluates Σ c_k·x^k by Horner's rule.
pub(super) fn polynomial(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ck| acc * x + ck)
}

/// q(u) in |R(iy)|² - 1 = y⁶·q(y²) for dopri5's fifth-order solution, from expanding
/// |Σ_{k≤5} (iy)^k/k! + (iy)⁶/600|².
pub(super) fn dopri5_imaginary_q(u: f64) -> f64 {
    -1.0 / 1800.0 + u / 1600.0 - u * u / 14400.0 + u * u * u / 360000.0
}
