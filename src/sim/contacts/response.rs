//! The collision response of the series' part 3: the impulse along the contact normal
//! that sends the approach speed back times the coefficient of restitution.
//!
//! Bodies A and B touch at P with unit normal n from B to A; r_AP and r_BP run from the
//! centres of mass to P. The relative velocity of the two coincident points is
//! v_AB = v_AP - v_BP with v_XP = v_X + ω_X·r_XP⊥, and its normal part is
//! v_n = v_AB·n (negative while they approach). An impulse j·n at P changes
//!
//! ```text
//! v_A' = v_A + (j/M_A)·n            v_B' = v_B - (j/M_B)·n
//! ω_A' = ω_A + (r_AP⊥·j·n)/I_A      ω_B' = ω_B - (r_BP⊥·j·n)/I_B
//! ```
//!
//! and v_n' = -e·v_n requires
//!
//! ```text
//! j = -(1 + e)·v_n / (1/M_A + 1/M_B + (r_AP⊥·n)²/I_A + (r_BP⊥·n)²/I_B).
//! ```
//!
//! A static body has 1/M = 1/I = 0. The two impulses are equal, opposite and act at one
//! point, so total momentum and angular momentum about any point are unchanged; with
//! e = 1 so is the kinetic energy.

use glam::DVec2;

use crate::sim::rigid::{perp_dot, point_velocity};

/// The inverse mass and inverse moment of inertia of a body (both 0 for a static one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inverse {
    pub mass: f64,
    pub inertia: f64,
}

/// One body's side of a contact: its inverse mass properties, its centre of mass, and
/// its velocity and spin at the instant of the impulse.
#[derive(Clone, Copy, Debug)]
pub struct Side {
    pub inv: Inverse,
    pub centre: DVec2,
    pub v: DVec2,
    pub omega: f64,
}

/// What an impulse did: j, and the normal relative velocity before and after.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impulse {
    pub j: f64,
    pub vn_before: f64,
    pub vn_after: f64,
}

/// Returns v_n = (v_AP - v_BP)·n, the normal part of the relative velocity of the two
/// bodies' points at P.
#[inline]
pub fn normal_velocity(a: &Side, b: &Side, p: DVec2, n: DVec2) -> f64 {
    let vap = point_velocity(a.v, a.omega, p - a.centre);
    let vbp = point_velocity(b.v, b.omega, p - b.centre);
    (vap - vbp).dot(n)
}

/// Applies the impulse of restitution e at P along n (from B to A) to both sides'
/// velocities and spins, and returns it with v_n before and after.
///
/// The caller applies it only when v_n < 0 (approaching).
#[inline]
pub fn collide(a: &mut Side, b: &mut Side, p: DVec2, n: DVec2, e: f64) -> Impulse {
    let vn_before = normal_velocity(a, b, p, n);
    let (ra, rb) = (p - a.centre, p - b.centre);
    // r⊥·n for each arm: the lever of the normal impulse about each centre of mass.
    let (ran, rbn) = (perp_dot(ra, n), perp_dot(rb, n));
    // K = 1/M_A + 1/M_B + (r_AP⊥·n)²/I_A + (r_BP⊥·n)²/I_B: the normal relative velocity
    // a unit impulse makes.
    let k = a.inv.mass + b.inv.mass + ran * ran * a.inv.inertia + rbn * rbn * b.inv.inertia;
    // j = -(1 + e)·v_n / K.
    let j = -(1.0 + e) * vn_before / k;
    // v_A' = v_A + (j/M_A)·n, ω_A' = ω_A + (r_AP⊥·j·n)/I_A, and the opposite on B.
    a.v += (j * a.inv.mass) * n;
    a.omega += ran * j * a.inv.inertia;
    b.v -= (j * b.inv.mass) * n;
    b.omega -= rbn * j * b.inv.inertia;
    let vn_after = normal_velocity(a, b, p, n);
    Impulse {
        j,
        vn_before,
        vn_after,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn side(m: f64, i: f64, centre: DVec2, v: DVec2, omega: f64) -> Side {
        Side {
            inv: Inverse {
                mass: if m.is_finite() { 1.0 / m } else { 0.0 },
                inertia: if i.is_finite() { 1.0 / i } else { 0.0 },
            },
            centre,
            v,
            omega,
        }
    }

    #[test]
    fn equal_discs_head_on_with_e_1_swap_velocities() {
        let mut a = side(1.0, 0.5, DVec2::new(1.0, 0.0), DVec2::new(-3.0, 0.0), 0.0);
        let mut b = side(1.0, 0.5, DVec2::new(-1.0, 0.0), DVec2::new(2.0, 0.0), 0.0);
        let i = collide(&mut a, &mut b, DVec2::ZERO, DVec2::X, 1.0);
        assert_eq!(a.v, DVec2::new(2.0, 0.0));
        assert_eq!(b.v, DVec2::new(-3.0, 0.0));
        assert_eq!((i.vn_before, i.vn_after), (-5.0, 5.0));
    }

    #[test]
    fn a_box_struck_off_centre_spins_by_the_lever_of_the_impulse() {
        // A 2 × 1 box of mass 3 at rest, I = 3·(4 + 1)/12; a static wall's impulse
        // along n = x at P = (-1, 0.4) from its centre, approaching at 2 m/s.
        let i_box = 3.0 * 5.0 / 12.0;
        let mut a = side(3.0, i_box, DVec2::ZERO, DVec2::new(-2.0, 0.0), 0.0);
        let mut wall = side(
            f64::INFINITY,
            f64::INFINITY,
            DVec2::new(-5.0, 0.0),
            DVec2::ZERO,
            0.0,
        );
        let p = DVec2::new(-1.0, 0.4);
        let e = 0.5;
        let imp = collide(&mut a, &mut wall, p, DVec2::X, e);
        // ω = r_AP⊥·(j·n)/I.
        let expected = perp_dot(p, imp.j * DVec2::X) / i_box;
        assert!((a.omega - expected).abs() <= 1e-15 * expected.abs());
        assert!((imp.vn_after + e * imp.vn_before).abs() <= 1e-15 * imp.vn_before.abs());
        assert_eq!(wall.v, DVec2::ZERO);
        assert_eq!(wall.omega, 0.0);
    }
}
