//! Closed-form solutions for scenes whose bodies each obey a linear equation of motion,
//! so that a run can be compared with the exact path.
//!
//! When every force on a body is uniform gravity, linear drag, a time-varying force
//! f0 + f1·t, or an undamped zero-length spring to a fixed point, and no force couples
//! two bodies, each body's centre of mass obeys
//!
//!   r'' = A + B·t - λ·r' - ω²·(r - c),
//!
//! with A = g + f0/m, B = f1/m, λ = k/m (the sum of the drag coefficients), ω² = s/m
//! (s the sum of the stiffnesses) and c the stiffness-weighted mean of the anchors. This
//! linear equation with constant coefficients has a closed form in every case; the
//! article's Equations 5 and 12 are two of them.

use glam::DVec2;

use super::{Anchor, ForceSpec, Selection, State};

/// The exact motion of every body of a scene, when the scene admits one.
#[derive(Clone, Debug)]
pub struct ExactSolution {
    laws: Vec<Law>,
    initial: State,
}

/// The coefficients of one body's equation of motion.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Law {
    a: DVec2,
    b: DVec2,
    lambda: f64,
    omega_sq: f64,
    centre: DVec2,
}

impl ExactSolution {
    /// Returns the exact solution for these bodies and forces from `initial`, or `None`
    /// when some force is not linear (quadratic drag, central, springs between bodies,
    /// damped or stretched springs).
    pub fn new(masses: &[f64], forces: &[ForceSpec], initial: &State) -> Option<Self> {
        let n = masses.len();
        let mut laws = vec![Law::default(); n];
        // Σ s_j·p_j per body, to find the weighted centre of its springs.
        let mut anchored = vec![DVec2::ZERO; n];
        let each = |bodies: &Selection, f: &mut dyn FnMut(usize)| bodies.for_each(n, f);
        for force in forces {
            match force {
                ForceSpec::Gravity { g, bodies } => each(bodies, &mut |i| laws[i].a += *g),
                ForceSpec::Drag { k, bodies } => {
                    each(bodies, &mut |i| laws[i].lambda += k / masses[i])
                }
                ForceSpec::TimeVarying { f0, f1, bodies, .. } => each(bodies, &mut |i| {
                    laws[i].a += *f0 / masses[i];
                    laws[i].b += *f1 / masses[i];
                }),
                ForceSpec::Spring {
                    a,
                    b: Anchor::Point(p),
                    stiffness,
                    rest_length,
                    damping,
                    a_at: None,
                    b_at: None,
                } if *rest_length == 0.0 && *damping == 0.0 => {
                    let i = *a as usize;
                    laws[i].omega_sq += stiffness / masses[i];
                    anchored[i] += *stiffness / masses[i] * *p;
                }
                // Torques turn bodies but do not move their centres of mass.
                ForceSpec::Torque { .. } | ForceSpec::AngularDrag { .. } => {}
                _ => return None,
            }
        }
        for (law, sum) in laws.iter_mut().zip(&anchored) {
            if law.omega_sq > 0.0 {
                law.centre = *sum / law.omega_sq;
            }
        }
        Some(ExactSolution {
            laws,
            initial: initial.clone(),
        })
    }

    /// Returns the exact state at time `t`.
    pub fn state_at(&self, t: f64) -> State {
        let s0 = &self.initial;
        let dt = t - s0.t;
        let (pos, vel) = self
            .laws
            .iter()
            .zip(s0.pos.iter().zip(&s0.vel))
            .map(|(law, (r0, v0))| law.at(dt, *r0, *v0))
            .unzip();
        State::new(t, pos, vel)
    }
}

impl Law {
    /// Returns (r, v) a time t after (r0, v0).
    fn at(&self, t: f64, r0: DVec2, v0: DVec2) -> (DVec2, DVec2) {
        let (a, b, lambda, w2) = (self.a, self.b, self.lambda, self.omega_sq);
        if w2 == 0.0 {
            if lambda == 0.0 {
                // r = r0 + v0·t + A·t²/2 + B·t³/6 (Equation 5 when B = 0).
                return (
                    r0 + v0 * t + a * (t * t / 2.0) + b * (t * t * t / 6.0),
                    v0 + a * t + b * (t * t / 2.0),
                );
            }
            // v' + λ·v = A + B·t has the particular solution v_p = (A + B·t)/λ - B/λ²;
            // v = v_p + (v0 - v_p(0))·e^(-λt) (Equation 12's v0·e^(-kt/m) when A = B = 0),
            // and r integrates it: r0 + (A/λ - B/λ²)·t + B·t²/(2λ) + (v0 - v_p(0))·(1 - e^(-λt))/λ.
            let vp0 = a / lambda - b / (lambda * lambda);
            let decay = (-lambda * t).exp();
            // 1 - e^(-λt) without cancellation for small λt.
            let gone = -(-lambda * t).exp_m1();
            let v = vp0 + b * (t / lambda) + (v0 - vp0) * decay;
            let r = r0 + vp0 * t + b * (t * t / (2.0 * lambda)) + (v0 - vp0) * (gone / lambda);
            return (r, v);
        }
        // With x = r - c: x'' + λ·x' + ω²·x = A + B·t, whose particular solution is
        // x_p = α + β·t with β = B/ω² and α = (A - λ·β)/ω². The rest, y = x - x_p, obeys
        // y'' + 2γ·y' + ω²·y = 0 with γ = λ/2.
        let beta = b / w2;
        let alpha = (a - lambda * beta) / w2;
        let y0 = r0 - self.centre - alpha;
        let dy0 = v0 - beta;
        let gamma = lambda / 2.0;
        let e = (-gamma * t).exp();
        let disc = w2 - gamma * gamma;
        let (y, dy) = if disc > 0.0 {
            // Under-damped: y = e^(-γt)·(y0·cos ωd·t + (y0' + γ·y0)/ωd·sin ωd·t).
            let wd = disc.sqrt();
            let (s, c) = (wd * t).sin_cos();
            let k = (dy0 + gamma * y0) / wd;
            (
                e * (y0 * c + k * s),
                e * (dy0 * c - (w2 * y0 + gamma * dy0) * (s / wd)),
            )
        } else if disc < 0.0 {
            // Over-damped: the same with cosh and sinh, ωd = √(γ² - ω²).
            let wd = (-disc).sqrt();
            let (s, c) = ((wd * t).sinh(), (wd * t).cosh());
            let k = (dy0 + gamma * y0) / wd;
            (
                e * (y0 * c + k * s),
                e * (dy0 * c + (gamma * dy0 + w2 * y0) * (-s / wd)),
            )
        } else {
            // Critically damped: y = e^(-γt)·(y0 + (y0' + γ·y0)·t).
            let k = dy0 + gamma * y0;
            (e * (y0 + k * t), e * (dy0 - gamma * k * t))
        };
        (self.centre + alpha + beta * t + y, beta + dy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks a law against its equation of motion by finite differences: the residual
    /// r'' + λ·r' + ω²·(r - c) - A - B·t is zero up to the differencing error.
    fn check_equation(law: Law, r0: DVec2, v0: DVec2) {
        let h = 1e-4;
        for t in [0.1, 0.7, 1.9, 3.3] {
            let (r, v) = law.at(t, r0, v0);
            let (rp, vp) = law.at(t + h, r0, v0);
            let (rm, vm) = law.at(t - h, r0, v0);
            // The reported velocity is the derivative of the position.
            let dr = (rp - rm) / (2.0 * h);
            assert!(
                (dr - v).length() < 1e-6 * (1.0 + v.length()),
                "{law:?}: r' {dr} vs v {v}"
            );
            let acc = (vp - vm) / (2.0 * h);
            let residual =
                acc + law.lambda * v + law.omega_sq * (r - law.centre) - law.a - law.b * t;
            assert!(
                residual.length() < 1e-5 * (1.0 + acc.length()),
                "{law:?} at t = {t}: residual {residual}"
            );
        }
        let (r, v) = law.at(0.0, r0, v0);
        assert!((r - r0).length() < 1e-12 && (v - v0).length() < 1e-12);
    }

    #[test]
    fn every_case_solves_its_equation_of_motion() {
        let (r0, v0) = (DVec2::new(1.0, -2.0), DVec2::new(0.5, 3.0));
        let (a, b) = (DVec2::new(0.3, -9.81), DVec2::new(2.0, 0.5));
        let c = DVec2::new(-1.0, 0.25);
        for (lambda, omega_sq) in [
            (0.0, 0.0),
            (0.8, 0.0),
            (0.0, 4.0),
            (0.6, 4.0),
            (4.0, 4.0),
            (5.0, 1.0),
        ] {
            check_equation(
                Law {
                    a,
                    b,
                    lambda,
                    omega_sq,
                    centre: c,
                },
                r0,
                v0,
            );
        }
    }

    #[test]
    fn scenes_with_coupling_or_nonlinear_forces_have_none() {
        let s = State::new(0.0, vec![DVec2::ZERO; 2], vec![DVec2::ZERO; 2]);
        let coupled = [ForceSpec::Spring {
            a: 0,
            b: Anchor::Body(1),
            stiffness: 1.0,
            rest_length: 0.0,
            damping: 0.0,
            a_at: None,
            b_at: None,
        }];
        assert!(ExactSolution::new(&[1.0, 1.0], &coupled, &s).is_none());
        let quadratic = [ForceSpec::QuadraticDrag {
            c: 1.0,
            bodies: Selection::All,
        }];
        assert!(ExactSolution::new(&[1.0, 1.0], &quadratic, &s).is_none());
        assert!(ExactSolution::new(&[1.0, 1.0], &[], &s).is_some());
    }
}
