//! Rigid-body kinematics in 2-D: where a point of a turned body is, how fast it moves,
//! and the torque of a force applied there.
//!
//! A body's points are written in *body coordinates*: the coordinates in which a scene
//! gives its polygon's vertices and point masses' offsets (a circle's and a box's
//! centre is their origin). With c the centre of mass in body coordinates, the body
//! point p is at r + R(θ)·(p - c) in the world, where r is the centre of mass and
//! R(θ) = [[cos θ, -sin θ], [sin θ, cos θ]] turns counter-clockwise by θ.

use glam::DVec2;

/// Returns R(θ)·p: the vector p turned counter-clockwise by θ, given (sin θ, cos θ).
///
/// R(θ)·p = (cos θ·p_x - sin θ·p_y, sin θ·p_x + cos θ·p_y).
#[inline(always)]
pub fn rotate(sin_cos: (f64, f64), p: DVec2) -> DVec2 {
    let (s, c) = sin_cos;
    DVec2::new(c * p.x - s * p.y, s * p.x + c * p.y)
}

/// Returns the perp-dot product a⊥·b = a_x·b_y - a_y·b_x, the 2-D cross product: the
/// torque τ = r⊥·F of a force F applied at r from the centre of mass.
#[inline(always)]
pub fn perp_dot(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Returns the velocity of a body point at arm r (world axes, from the centre of mass)
/// of a body moving at v and spinning at ω: v_P = v + ω·r⊥, with r⊥ = (-r_y, r_x).
#[inline(always)]
pub fn point_velocity(v: DVec2, omega: f64, r: DVec2) -> DVec2 {
    DVec2::new(v.x - omega * r.y, v.y + omega * r.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quarter_turn_takes_x_to_y() {
        let q = std::f64::consts::FRAC_PI_2.sin_cos();
        let p = rotate(q, DVec2::X);
        assert!((p - DVec2::Y).length() < 1e-16);
        // Turning keeps lengths and composes: R(a)·R(b) = R(a + b).
        let (a, b): (f64, f64) = (0.3, -1.1);
        let v = DVec2::new(2.0, -0.5);
        let twice = rotate(a.sin_cos(), rotate(b.sin_cos(), v));
        let once = rotate((a + b).sin_cos(), v);
        // A few roundings of numbers of the size of |v|: 4 units in the last place.
        let ulps = 4.0 * f64::EPSILON * v.length();
        assert!((twice - once).length() < ulps);
        assert!((rotate(a.sin_cos(), v).length() - v.length()).abs() < ulps);
    }

    #[test]
    fn the_torque_of_a_force_is_its_lever_arm_times_its_perpendicular_part() {
        // τ = |r|·|F|·sin(angle from r to F): a force along the arm has no torque; one
        // at right angles, counter-clockwise, has |r|·|F|.
        let r = DVec2::new(2.0, 0.0);
        assert_eq!(perp_dot(r, DVec2::new(5.0, 0.0)), 0.0);
        assert_eq!(perp_dot(r, DVec2::new(0.0, 3.0)), 6.0);
        assert_eq!(perp_dot(r, DVec2::new(0.0, -3.0)), -6.0);
        // v_P = v + ω·r⊥ is perpendicular to r for a pure spin.
        let vp = point_velocity(DVec2::ZERO, 1.5, DVec2::new(0.6, 0.8));
        assert!((vp - DVec2::new(-1.2, 0.9)).length() < 4.0 * f64::EPSILON);
        assert!(vp.dot(DVec2::new(0.6, 0.8)).abs() < 4.0 * f64::EPSILON);
        // A moving body adds its velocity to every point's.
        let moving = point_velocity(DVec2::new(3.0, -1.0), 1.5, DVec2::new(0.6, 0.8));
        assert_eq!(moving - vp, DVec2::new(3.0, -1.0));
    }
}
