//! The two kinds of coordinate a rigid body has in 2-D, under one trait, so that every
//! integrator advances the linear pair (r, v) and the angular pair (θ, ω) with the same
//! code, in the same stages.
//!
//! The position r and velocity v of a centre of mass are [`DVec2`]s; the angle θ and
//! the angular velocity ω are `f64`s. An explicit integrator only ever forms linear
//! combinations y + h·Σ b_i·k_i of them, component by component, which both types
//! support. Writing each stage once, generic over [`Dof`], rules out the bug of a
//! Runge–Kutta method whose angle takes an Euler step while its position takes the
//! method's stages: there is only one stage to write.
//!
//! Every product is written coordinate first (`v * h`), which is the same IEEE
//! multiplication, to the bit, as `h * v`: so the linear pair computes exactly what it
//! did before the angular pair shared its code.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Sub};

use glam::DVec2;

/// A coordinate an integrator advances: a vector of a few `f64` components on which
/// sums, differences and products with a scalar act component by component.
pub trait Dof:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f64, Output = Self>
    + Mul<Self, Output = Self>
    + Div<Self, Output = Self>
    + AddAssign
    + MulAssign<f64>
{
    /// The zero coordinate.
    const ZERO: Self;
    /// The number of `f64` components (2 for a `DVec2`, 1 for an `f64`).
    const COMPONENTS: usize;

    /// Returns the coordinate whose every component is `s`.
    fn splat(s: f64) -> Self;
    /// Returns the absolute value of every component.
    fn abs(self) -> Self;
    /// Returns the larger of each pair of components.
    fn max(self, other: Self) -> Self;
    /// Returns the sum of the components.
    fn component_sum(self) -> f64;
    /// Returns true when every component is finite.
    fn is_finite(self) -> bool;
}

impl Dof for DVec2 {
    const ZERO: Self = DVec2::ZERO;
    const COMPONENTS: usize = 2;

    #[inline(always)]
    fn splat(s: f64) -> Self {
        DVec2::splat(s)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        DVec2::abs(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        DVec2::max(self, other)
    }
    #[inline(always)]
    fn component_sum(self) -> f64 {
        self.x + self.y
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        DVec2::is_finite(self)
    }
}

impl Dof for f64 {
    const ZERO: Self = 0.0;
    const COMPONENTS: usize = 1;

    #[inline(always)]
    fn splat(s: f64) -> Self {
        s
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline(always)]
    fn component_sum(self) -> f64 {
        self
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stage written coordinate first gives, to the bit, what the scalar-first form
    /// the integrators used to write gives.
    #[test]
    fn coordinate_first_products_are_the_scalar_first_ones() {
        let (r, v, a) = (
            DVec2::new(0.1, -3.7),
            DVec2::new(1.0 / 3.0, 2e-9),
            DVec2::new(-9.81, 7.25),
        );
        for h in [0.001, 1.0 / 7.0, 0.3] {
            let generic = |r: DVec2, v: DVec2, a: DVec2| (r + v * h, v + a * (h * 0.5));
            let (r1, v1) = generic(r, v, a);
            assert_eq!(r1, r + h * v);
            assert_eq!(v1, v + (h * 0.5) * a);
            assert_eq!(<f64 as Dof>::component_sum(2.5), 2.5);
            assert_eq!(Dof::component_sum(DVec2::new(1.0, 2.0)), 3.0);
        }
    }
}
