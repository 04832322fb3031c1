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

/// What an impulse did: j along n, j_t along t = n⊥, and the normal relative
/// velocity before and after.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impulse {
    pub j: f64,
    pub jt: f64,
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

/// How slowly two points may close and still count as at rest relative to each other:
/// a closing speed below this fraction of the points' own speeds is round-off (a
/// velocity and the step's chord that agree to the last bits), not an approach.
pub const APPROACH_EPSILON: f64 = 1e-9;

/// Returns true when a closing rate `rate` (negative: closing) of two points moving at
/// `scale` (the sum of their speeds) is an approach faster than `rest` (the resting
/// speed, in the same units; 0 without resting contact).
#[inline]
pub fn closes(rate: f64, scale: f64, rest: f64) -> bool {
    rate < -(APPROACH_EPSILON * scale).max(rest)
}

/// Returns the normal relative velocity at P and the speed scale it is measured
/// against, |v_AP| + |v_BP|.
#[inline]
fn normal_velocity_and_scale(a: &Side, b: &Side, p: DVec2, n: DVec2) -> (f64, f64) {
    let vap = point_velocity(a.v, a.omega, p - a.centre);
    let vbp = point_velocity(b.v, b.omega, p - b.centre);
    ((vap - vbp).dot(n), vap.length() + vbp.length())
}

/// Returns the point where one impulse along n acts as the contact's points would act
/// together, or `None` when no point approaches.
///
/// A contact of two points (an edge on an edge) is struck at both at once: impulses
/// j_1, j_2 ≥ 0 such that each point whose impulse is not zero leaves at
/// v_n' = -e·v_n, the others at no less (the 2 × 2 complementarity problem
/// K·j = -(1 + e)·v_n with K_kl = 1/M_A + 1/M_B + (r_Ak⊥·n)(r_Al⊥·n)/I_A +
/// (r_Bk⊥·n)(r_Bl⊥·n)/I_B, solved by trying which impulses are zero, as Box2D's
/// block solver does). Impulses along one normal add: j_1 at P_1 and j_2 at P_2 are
/// one impulse J = j_1 + j_2 at P* = (j_1·P_1 + j_2·P_2)/J, and since v_n is linear in
/// the point, v_n'(P*) = -e·v_n(P*): the article's impulse at P* is this one. Struck
/// one point at a time instead, a box rocking on an edge would be struck at each end in
/// turn without end.
///
/// Only an approach faster than `rest`, the resting speed, is struck: slower ones rest.
pub fn strike_point(
    a: &Side,
    b: &Side,
    points: &[DVec2],
    n: DVec2,
    e: f64,
    rest: f64,
) -> Option<DVec2> {
    let vn: Vec<(f64, f64)> = points
        .iter()
        .map(|p| normal_velocity_and_scale(a, b, *p, n))
        .collect();
    if !vn.iter().any(|(v, scale)| closes(*v, *scale, rest)) {
        return None;
    }
    if points.len() == 1 || (points[0] - points[1]).length_squared() == 0.0 {
        return Some(points[0]);
    }
    let lever = |p: DVec2| (perp_dot(p - a.centre, n), perp_dot(p - b.centre, n));
    let (l1, l2) = (lever(points[0]), lever(points[1]));
    let k = |x: (f64, f64), y: (f64, f64)| {
        a.inv.mass + b.inv.mass + x.0 * y.0 * a.inv.inertia + x.1 * y.1 * b.inv.inertia
    };
    let (k11, k12, k22) = (k(l1, l1), k(l1, l2), k(l2, l2));
    // The change of normal velocity each point needs: -(1 + e)·v_n.
    let (b1, b2) = (-(1.0 + e) * vn[0].0, -(1.0 + e) * vn[1].0);
    let weighted = |j1: f64, j2: f64| (j1 * points[0] + j2 * points[1]) / (j1 + j2);
    // Both struck: j = K⁻¹·b, when both are positive.
    let det = k11 * k22 - k12 * k12;
    if det > 1e-12 * k11 * k22 {
        let j1 = (k22 * b1 - k12 * b2) / det;
        let j2 = (k11 * b2 - k12 * b1) / det;
        if j1 > 0.0 && j2 > 0.0 {
            return Some(weighted(j1, j2));
        }
    }
    // One struck, and the other leaves no slower than e times its approach: v_n2 +
    // K_21·j_1 ≥ -e·v_n2, that is K_21·j_1 ≥ b2.
    let j1 = b1 / k11;
    if j1 > 0.0 && k12 * j1 >= b2 {
        return Some(points[0]);
    }
    let j2 = b2 / k22;
    if j2 > 0.0 && k12 * j2 >= b1 {
        return Some(points[1]);
    }
    // The points are so close that K is singular and each alone undoes the other:
    // strike their middle.
    Some(0.5 * (points[0] + points[1]))
}

/// Applies the impulse of restitution e at P along n (from B to A) to both sides'
/// velocities and spins, with Coulomb friction of coefficient μ along the tangent
/// t = n⊥, and returns it with v_n before and after.
///
/// Without friction (μ = 0) it is the article's impulse j·n. With friction the impulse
/// is j·n + j_t·t, and the pair (j, j_t) solves K·(j, j_t) = (-(1 + e)·v_n, -v_t), with
/// K the 2 × 2 matrix of the velocity changes a unit impulse along n or t makes at P:
/// the normal velocity leaves at -e·v_n and the point stops sliding. When that needs
/// |j_t| > μ·j the points slide: j_t = ∓μ·j against the sliding, and the normal row
/// alone gives j = -(1 + e)·v_n / (K_nn ∓ μ·K_nt). Either way v_n' = -e·v_n exactly,
/// and |j_t| ≤ μ·j.
///
/// The caller applies it only when v_n < 0 (approaching).
#[inline]
pub fn collide(a: &mut Side, b: &mut Side, p: DVec2, n: DVec2, e: f64, mu: f64) -> Impulse {
    let vn_before = normal_velocity(a, b, p, n);
    let (ra, rb) = (p - a.centre, p - b.centre);
    // r⊥·n for each arm: the lever of the normal impulse about each centre of mass.
    let (ran, rbn) = (perp_dot(ra, n), perp_dot(rb, n));
    // K = 1/M_A + 1/M_B + (r_AP⊥·n)²/I_A + (r_BP⊥·n)²/I_B: the normal relative velocity
    // a unit impulse makes.
    let k = a.inv.mass + b.inv.mass + ran * ran * a.inv.inertia + rbn * rbn * b.inv.inertia;
    let (j, jt) = if mu > 0.0 {
        with_friction(a, b, p, n, vn_before, e, mu)
    } else {
        // j = -(1 + e)·v_n / K.
        (-(1.0 + e) * vn_before / k, 0.0)
    };
    // v_A' = v_A + (j/M_A)·n, ω_A' = ω_A + (r_AP⊥·j·n)/I_A, and the opposite on B.
    a.v += (j * a.inv.mass) * n;
    a.omega += ran * j * a.inv.inertia;
    b.v -= (j * b.inv.mass) * n;
    b.omega -= rbn * j * b.inv.inertia;
    if jt != 0.0 {
        // The same for the friction impulse j_t·t.
        let t = n.perp();
        let (rat, rbt) = (perp_dot(ra, t), perp_dot(rb, t));
        a.v += (jt * a.inv.mass) * t;
        a.omega += rat * jt * a.inv.inertia;
        b.v -= (jt * b.inv.mass) * t;
        b.omega -= rbt * jt * b.inv.inertia;
    }
    let vn_after = normal_velocity(a, b, p, n);
    Impulse {
        j,
        jt,
        vn_before,
        vn_after,
    }
}

/// Returns (j, j_t) for [`collide`] with friction μ > 0.
fn with_friction(a: &Side, b: &Side, p: DVec2, n: DVec2, vn: f64, e: f64, mu: f64) -> (f64, f64) {
    let t = n.perp();
    let (ra, rb) = (p - a.centre, p - b.centre);
    let vap = point_velocity(a.v, a.omega, ra);
    let vbp = point_velocity(b.v, b.omega, rb);
    let vt = (vap - vbp).dot(t);
    let k = |x: DVec2, y: DVec2| {
        (a.inv.mass + b.inv.mass) * x.dot(y)
            + perp_dot(ra, x) * perp_dot(ra, y) * a.inv.inertia
            + perp_dot(rb, x) * perp_dot(rb, y) * b.inv.inertia
    };
    let (knn, knt, ktt) = (k(n, n), k(n, t), k(t, t));
    let bn = -(1.0 + e) * vn;
    // Sticking: both rows, solved by Cramer's rule.
    let det = knn * ktt - knt * knt;
    if det > 0.0 {
        let j = (ktt * bn + knt * vt) / det;
        let jt = (-knt * bn - knn * vt) / det;
        if jt.abs() <= mu * j {
            return (j, jt);
        }
    }
    // Sliding: j_t = -μ·j·sign(v_t) opposes the slide (the sticking impulse's sign,
    // which is that of -v_t when K is diagonal).
    let s = if vt > 0.0 { -1.0 } else { 1.0 };
    let denom = knn + s * mu * knt;
    if denom > 0.0 {
        let j = bn / denom;
        return (j, s * mu * j);
    }
    (bn / knn, 0.0)
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
        let i = collide(&mut a, &mut b, DVec2::ZERO, DVec2::X, 1.0, 0.0);
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
        let imp = collide(&mut a, &mut wall, p, DVec2::X, e, 0.0);
        // ω = r_AP⊥·(j·n)/I.
        let expected = perp_dot(p, imp.j * DVec2::X) / i_box;
        assert!((a.omega - expected).abs() <= 1e-15 * expected.abs());
        assert!((imp.vn_after + e * imp.vn_before).abs() <= 1e-15 * imp.vn_before.abs());
        assert_eq!(wall.v, DVec2::ZERO);
        assert_eq!(wall.omega, 0.0);
    }
}
