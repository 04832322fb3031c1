//! What an adaptive method's error control needs: the tolerances a step's error is
//! measured against, and the PI controller of Hairer's DOPRI5 that chooses the next step
//! from that error.

/// The error tolerances of an adaptive method.
///
/// A step is accepted when the weighted root-mean-square of its error estimate is at most
/// one, each component being weighted by sc = atol + rtol·max(|y0|, |y1|) (Hairer's
/// norm, over the x and y components of every position and velocity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// The relative tolerance rtol > 0.
    pub rtol: f64,
    /// The absolute tolerance atol > 0, in the units of position and of velocity.
    pub atol: f64,
}

impl Tolerances {
    /// Returns tolerances with the same relative and absolute values, as in the
    /// work-precision studies.
    pub fn both(tol: f64) -> Self {
        Tolerances {
            rtol: tol,
            atol: tol,
        }
    }
}

impl Default for Tolerances {
    /// rtol = 1e-6 and atol = 1e-9: a millionth of the size of a quantity, and a
    /// billionth of a unit where it passes through zero; far below what a frame can show.
    fn default() -> Self {
        Tolerances {
            rtol: 1e-6,
            atol: 1e-9,
        }
    }
}

/// The PI step-size controller of Hairer's DOPRI5.
///
/// From the error norm err of a step of size h it proposes
///
///   h_new = h · clamp(safety · err^(-α) · err_prev^β, 1/5, 10),
///
/// with α = 1/5 - 0.75·β, β = 0.04 and safety = 0.9, where err_prev is the error of the
/// last accepted step (at least 10⁻⁴). The integral part err^(-α) aims the next error at
/// the tolerance; the proportional part err_prev^β damps oscillations of the step size.
/// A rejected step (err > 1) is retried with h·max(1/5, safety·err^(-α)), and the step
/// after a rejection may not grow.
#[derive(Clone, Debug)]
pub struct StepController {
    /// ln(err_prev), the logarithm of the last accepted error (at least 10⁻⁴).
    ln_err_prev: f64,
    rejected: bool,
}

impl Default for StepController {
    fn default() -> Self {
        StepController {
            ln_err_prev: 1e-4f64.ln(),
            rejected: false,
        }
    }
}

impl StepController {
    /// The safety factor that keeps the next error below the tolerance.
    pub const SAFETY: f64 = 0.9;
    /// The smallest factor by which a step may shrink.
    pub const MIN_FACTOR: f64 = 0.2;
    /// The largest factor by which a step may grow.
    pub const MAX_FACTOR: f64 = 10.0;
    /// The weight β of the previous error (the proportional part).
    pub const BETA: f64 = 0.04;
    /// The exponent α of the current error (the integral part).
    pub const ALPHA: f64 = 0.2 - 0.75 * Self::BETA;

    /// Decides whether a step of size `h` with error norm `err` is accepted, and returns
    /// that decision with the size of the next step. A non-finite error is a rejection
    /// with the largest reduction.
    ///
    /// The powers are computed from logarithms, err^α·err_prev^(-β) =
    /// exp(α·ln err - β·ln err_prev): one logarithm and one exponential per step instead
    /// of two general powers, which cost as much as the rest of the step control.
    pub fn decide(&mut self, err: f64, h: f64) -> (bool, f64) {
        let ln_err = err.ln();
        if err <= 1.0 {
            // 1/factor = clamp(err^α · err_prev^(-β) / safety, 1/10, 5).
            let inv = ((Self::ALPHA * ln_err - Self::BETA * self.ln_err_prev).exp() / Self::SAFETY)
                .clamp(1.0 / Self::MAX_FACTOR, 1.0 / Self::MIN_FACTOR);
            let mut h_new = h / inv;
            if self.rejected {
                h_new = h_new.min(h);
            }
            // err_prev = max(err, 10⁻⁴), kept as its logarithm.
            self.ln_err_prev = ln_err.max(1e-4f64.ln());
            self.rejected = false;
            (true, h_new)
        } else {
            // h_new = h / min(5, err^α / safety); f64::min ignores a NaN error.
            let fac11 = (Self::ALPHA * ln_err).exp();
            self.rejected = true;
            (
                false,
                h / (1.0 / Self::MIN_FACTOR).min(fac11 / Self::SAFETY),
            )
        }
    }
}
