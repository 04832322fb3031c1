//! Explicit Runge–Kutta steppers for one scalar ODE dy/dx = f(x, y), for figures that
//! trace a numerical solution through a field (the article's Euler polyline).
//!
//! Each method is its Butcher tableau: with stages
//!
//! ```text
//! k_i = f(x + c_i·h, y + h·Σ_{j<i} a_ij·k_j),   i = 1..s
//! ```
//!
//! one step is y_{n+1} = y_n + h·Σ_i b_i·k_i and x_{n+1} = x_n + h. One generic loop
//! runs every tableau, so a method is its coefficients and nothing else. These steppers
//! are separate from the body integrators in `integrators/`, which advance coupled
//! positions and velocities of many bodies.

use std::fmt;
use std::str::FromStr;

/// A scalar explicit method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ScalarMethod {
    /// Explicit Euler: y_{n+1} = y_n + h·f(x_n, y_n).
    Euler,
    /// The explicit midpoint method:
    /// y_{n+1} = y_n + h·f(x_n + h/2, y_n + (h/2)·f(x_n, y_n)).
    Midpoint,
    /// Heun's method (the explicit trapezoid):
    /// y_{n+1} = y_n + (h/2)·(f(x_n, y_n) + f(x_n + h, y_n + h·f(x_n, y_n))).
    Heun,
    /// The classical fourth-order Runge–Kutta method:
    /// y_{n+1} = y_n + (h/6)·(k1 + 2·k2 + 2·k3 + k4).
    Rk4,
}

/// A Butcher tableau of at most four stages: nodes c, the strictly lower triangular
/// matrix a (row i holds a_i0 .. a_i(i-1)), and weights b.
struct Tableau {
    stages: usize,
    c: [f64; 4],
    a: [[f64; 3]; 4],
    b: [f64; 4],
}

/// Euler: c = [0], b = [1].
const EULER: Tableau = Tableau {
    stages: 1,
    c: [0.0, 0.0, 0.0, 0.0],
    a: [[0.0; 3]; 4],
    b: [1.0, 0.0, 0.0, 0.0],
};

/// Midpoint: c = [0, 1/2], a_21 = 1/2, b = [0, 1].
const MIDPOINT: Tableau = Tableau {
    stages: 2,
    c: [0.0, 0.5, 0.0, 0.0],
    a: [[0.0; 3], [0.5, 0.0, 0.0], [0.0; 3], [0.0; 3]],
    b: [0.0, 1.0, 0.0, 0.0],
};

/// Heun: c = [0, 1], a_21 = 1, b = [1/2, 1/2].
const HEUN: Tableau = Tableau {
    stages: 2,
    c: [0.0, 1.0, 0.0, 0.0],
    a: [[0.0; 3], [1.0, 0.0, 0.0], [0.0; 3], [0.0; 3]],
    b: [0.5, 0.5, 0.0, 0.0],
};

/// RK4: c = [0, 1/2, 1/2, 1], a_21 = a_32 = 1/2, a_43 = 1, b = [1/6, 1/3, 1/3, 1/6].
const RK4: Tableau = Tableau {
    stages: 4,
    c: [0.0, 0.5, 0.5, 1.0],
    a: [[0.0; 3], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 1.0]],
    b: [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
};

impl ScalarMethod {
    /// Every method, in order of accuracy.
    pub const ALL: &'static [ScalarMethod] = &[
        ScalarMethod::Euler,
        ScalarMethod::Midpoint,
        ScalarMethod::Heun,
        ScalarMethod::Rk4,
    ];

    /// The name a scene writes.
    pub fn name(self) -> &'static str {
        match self {
            ScalarMethod::Euler => "euler",
            ScalarMethod::Midpoint => "midpoint",
            ScalarMethod::Heun => "heun",
            ScalarMethod::Rk4 => "rk4",
        }
    }

    fn tableau(self) -> &'static Tableau {
        match self {
            ScalarMethod::Euler => &EULER,
            ScalarMethod::Midpoint => &MIDPOINT,
            ScalarMethod::Heun => &HEUN,
            ScalarMethod::Rk4 => &RK4,
        }
    }

    /// Advances (x, y) by one step h: y_{n+1} = y_n + h·Σ b_i·k_i, with the stages k_i
    /// of the module documentation.
    pub fn step(self, f: &mut impl FnMut(f64, f64) -> f64, x: f64, y: f64, h: f64) -> f64 {
        let t = self.tableau();
        let mut k = [0.0f64; 4];
        for i in 0..t.stages {
            // y_i = y + h·Σ_{j<i} a_ij·k_j; k_i = f(x + c_i·h, y_i).
            let yi = y + h * (0..i).map(|j| t.a[i][j] * k[j]).sum::<f64>();
            k[i] = f(x + t.c[i] * h, yi);
        }
        // y_{n+1} = y_n + h·Σ_i b_i·k_i; Euler's single stage makes this y + h·f(x, y).
        y + h * (0..t.stages).map(|i| t.b[i] * k[i]).sum::<f64>()
    }

    /// Returns the step points (x_n, y_n) from (x0, y0) while x_n ≤ `end` (to within a
    /// millionth of a step), at most `max_steps` steps, stopping early at the first
    /// non-finite value. x_n = x0 + n·h is computed from n, so it does not drift.
    pub fn solve(
        self,
        mut f: impl FnMut(f64, f64) -> f64,
        (x0, y0): (f64, f64),
        h: f64,
        end: f64,
        max_steps: usize,
    ) -> Vec<(f64, f64)> {
        let mut points = vec![(x0, y0)];
        let mut y = y0;
        for n in 0..max_steps {
            let x = x0 + n as f64 * h;
            let next_x = x0 + (n + 1) as f64 * h;
            if (next_x - end) * h.signum() > 1e-6 * h.abs() {
                break;
            }
            y = self.step(&mut f, x, y, h);
            if !y.is_finite() {
                break;
            }
            points.push((next_x, y));
        }
        points
    }
}

impl fmt::Display for ScalarMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ScalarMethod {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ScalarMethod::ALL
            .iter()
            .copied()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = ScalarMethod::ALL.iter().map(|m| m.name()).collect();
                format!("unknown method `{s}`; expected one of {}", names.join(", "))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_steps_are_exactly_y_plus_h_f() {
        // dv/dt = -v/m with m = 1 and h = 0.5: v_{n+1} = v_n + h·(-v_n) = v_n/2.
        let points = ScalarMethod::Euler.solve(|_, v| -v, (0.0, 3.0), 0.5, 5.0, 100);
        assert_eq!(points.len(), 11);
        for w in points.windows(2) {
            let (x, y) = w[0];
            assert_eq!(w[1].0, x + 0.5);
            assert_eq!(w[1].1, y + 0.5 * -y);
        }
        assert_eq!(points[10], (5.0, 3.0 / 1024.0));
    }

    #[test]
    fn every_method_converges_at_its_order() {
        // dy/dx = y from y(0) = 1: y(1) = e. Halving h divides the error by 2^order.
        for (method, order) in [
            (ScalarMethod::Euler, 1.0),
            (ScalarMethod::Midpoint, 2.0),
            (ScalarMethod::Heun, 2.0),
            (ScalarMethod::Rk4, 4.0),
        ] {
            let error = |h: f64| {
                let points = method.solve(|_, y| y, (0.0, 1.0), h, 1.0, 10_000);
                let (x, y) = points[points.len() - 1];
                assert!((x - 1.0).abs() < 1e-12, "{method}: ends at {x}");
                (y - std::f64::consts::E).abs()
            };
            let ratio = error(0.05) / error(0.025);
            let measured = ratio.log2();
            assert!(
                (measured - order).abs() < 0.15,
                "{method}: measured order {measured}, nominal {order}"
            );
        }
    }

    #[test]
    fn solving_stops_at_the_first_non_finite_value() {
        let points = ScalarMethod::Euler.solve(|_, y| y * y * 1e200, (0.0, 1e200), 1.0, 10.0, 100);
        assert!(points.iter().all(|p| p.1.is_finite()));
        assert!(points.len() < 11);
    }
}
