//! Linear stability theory: the largest step each integrator can take on the two model
//! problems the article's forces reduce to, used to tell a user what step would have
//! been stable when a run blows up.
//!
//! Linear drag dv/dt = -(k/m)·v is the test equation y' = λ·y with λ = -k/m on the
//! negative real axis; an undamped spring x'' = -ω²·x has eigenvalues ±iω on the
//! imaginary axis. A one-step method multiplies y by R(z), z = h·λ, every step, and is
//! stable while |R(z)| ≤ 1. For explicit Euler R(z) = 1 + z, so drag needs h·k/m ≤ 2
//! and the spring, |1 + i·h·ω| > 1, is never stable.

use super::{Anchor, ForceSpec, IntegratorKind};

/// Returns the largest h·k/m for which the method is stable on linear drag (the
/// stability interval on the negative real axis), when theory gives one.
pub fn drag_limit(kind: IntegratorKind) -> Option<f64> {
    match kind {
        // R(z) = 1 + z (Euler; symplectic Euler updates v exactly so on pure drag),
        // 1 + z + z²/2 (midpoint, Heun): both reach |R| = 1 at z = -2.
        IntegratorKind::Euler
        | IntegratorKind::SymplecticEuler
        | IntegratorKind::Midpoint
        | IntegratorKind::Heun => Some(2.0),
        // |R(z)| = |1 + z + z²/2 + z³/6 + z⁴/24| reaches 1 at z ≈ -2.785293563.
        IntegratorKind::Rk4 => Some(2.785_293_563_405_282),
        // Velocity Verlet with a predicted velocity, and the adaptive dopri5, have no
        // single fixed-step limit worth quoting here.
        IntegratorKind::Verlet | IntegratorKind::Dopri5 => None,
    }
}

/// Returns the largest h·ω for which the method is stable on an undamped spring (the
/// stability interval on the imaginary axis): 0 means never stable.
pub fn spring_limit(kind: IntegratorKind) -> Option<f64> {
    match kind {
        // |1 + iy| > 1 and |1 + iy - y²/2| = √(1 + y⁴/4) > 1 for every y ≠ 0.
        IntegratorKind::Euler | IntegratorKind::Midpoint | IntegratorKind::Heun => Some(0.0),
        // Symplectic Euler and velocity Verlet: the one-step map has trace 2 - (hω)²,
        // so its eigenvalues stay on the unit circle while hω < 2.
        IntegratorKind::SymplecticEuler | IntegratorKind::Verlet => Some(2.0),
        // |R(iy)| ≤ 1 for RK4 while y ≤ 2√2.
        IntegratorKind::Rk4 => Some(2.0 * std::f64::consts::SQRT_2),
        IntegratorKind::Dopri5 => None,
    }
}

/// Returns a sentence giving the step that theory says would be stable for this
/// scene's linear drag and springs with this integrator, or `None` when neither
/// applies or theory has no limit for the method.
pub fn stable_step_hint(
    kind: IntegratorKind,
    masses: &[f64],
    forces: &[ForceSpec],
) -> Option<String> {
    let n = masses.len();
    // The fastest drag rate k/m of any body: the sum of every drag on it over its mass.
    let mut drag_rate = vec![0.0f64; n];
    // The fastest spring frequency ω = √(stiffness/μ), μ the reduced mass.
    let mut omega = 0.0f64;
    for f in forces {
        match f {
            ForceSpec::Drag { k, bodies } => {
                bodies.for_each(n, |i| drag_rate[i] += k / masses[i]);
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
    let rate = drag_rate.iter().copied().fold(0.0, f64::max);
    let mut limits = Vec::new();
    if rate > 0.0 {
        if let Some(limit) = drag_limit(kind) {
            limits.push((
                limit / rate,
                format!(
                    "linear drag with k/m = {rate} needs dt ≤ {limit}·m/k = {}",
                    limit / rate
                ),
            ));
        }
    }
    if omega > 0.0 {
        match spring_limit(kind) {
            Some(0.0) => {
                return Some(format!(
                    "{kind} is never stable on an undamped spring (here ω = {omega}): its energy grows every step; use symplectic-euler or verlet with dt < 2/ω = {}, or rk4 with dt ≤ 2√2/ω = {}",
                    2.0 / omega,
                    2.0 * std::f64::consts::SQRT_2 / omega
                ));
            }
            Some(limit) => limits.push((
                limit / omega,
                format!(
                    "a spring with ω = {omega} needs dt < {limit}/ω = {}",
                    limit / omega
                ),
            )),
            None => {}
        }
    }
    limits
        .into_iter()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, text)| format!("linear stability theory for {kind}: {text}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Selection;

    #[test]
    fn rk4_real_axis_limit_is_where_the_amplification_reaches_one() {
        let z = -drag_limit(IntegratorKind::Rk4).expect("a limit");
        let r = 1.0 + z + z * z / 2.0 + z.powi(3) / 6.0 + z.powi(4) / 24.0;
        assert!((r.abs() - 1.0).abs() < 1e-12, "R(z) = {r}");
        // Just inside, |R| < 1; just outside, |R| > 1.
        let r_at = |z: f64| 1.0 + z + z * z / 2.0 + z.powi(3) / 6.0 + z.powi(4) / 24.0;
        assert!(r_at(z * 0.999).abs() < 1.0 && r_at(z * 1.001).abs() > 1.0);
    }

    #[test]
    fn the_hint_names_the_tightest_limit() {
        let forces = [ForceSpec::Drag {
            k: 1000.0,
            bodies: Selection::All,
        }];
        let hint = stable_step_hint(IntegratorKind::Euler, &[1.0, 2.0], &forces).expect("a hint");
        assert!(hint.contains("dt ≤ 2·m/k = 0.002"), "{hint}");
        let spring = [ForceSpec::Spring {
            a: 0,
            b: Anchor::Point(glam::DVec2::ZERO),
            stiffness: 4.0,
            rest_length: 0.0,
            damping: 0.0,
        }];
        let hint = stable_step_hint(IntegratorKind::Euler, &[1.0], &spring).expect("a hint");
        assert!(hint.contains("never stable"), "{hint}");
        let hint =
            stable_step_hint(IntegratorKind::SymplecticEuler, &[1.0], &spring).expect("a hint");
        assert!(hint.contains("dt < 2/ω = 1"), "{hint}");
        assert_eq!(
            stable_step_hint(IntegratorKind::Dopri5, &[1.0], &spring),
            None
        );
    }
}
