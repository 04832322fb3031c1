//! Damped springs between two bodies, or from a body to a fixed point.

use glam::DVec2;

use super::Anchor;
use crate::sim::rigid::{perp_dot, point_velocity, rotate};

/// A spring obeying Hooke's law, with damping along its axis.
///
/// With d = r_a - r_b, ℓ = |d| and u = d/ℓ, the force on body a is
///
/// F_a = -stiffness·(ℓ - rest_length)·u - damping·((v_a - v_b)·u)·u,
///
/// and the force on body b is F_b = -F_a (Newton's third law), so a spring between two
/// bodies leaves the total momentum unchanged. When the anchor is a fixed point,
/// v_b = 0 and only body a feels the force. With a rest length of zero the elastic part
/// is simply -stiffness·d, defined even when the ends meet; when the ends meet with a
/// positive rest length the direction is undefined and the spring exerts no force.
///
/// Its ends may be body points other than the centres of mass (`a_at`, `b_at`, in body
/// coordinates). Then r_a and r_b above are those points, r + R(θ)·(at - c), and v_a,
/// v_b their velocities v + ω·(R(θ)·(at - c))⊥; the force acts at each point, so it
/// also exerts the torques τ_a = r_aP⊥·F_a and τ_b = r_bP⊥·F_b about the centres of mass,
/// with r_aP, r_bP the arms from each centre of mass to its end. Equal, opposite forces
/// along the line through both ends: the spring changes neither the total momentum nor
/// the total angular momentum about any point.
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    /// The first body.
    pub a: u32,
    /// The other end.
    pub b: Anchor,
    /// The stiffness (spring constant) ≥ 0.
    pub stiffness: f64,
    /// The length at which the spring exerts no elastic force, ≥ 0.
    pub rest_length: f64,
    /// The damping coefficient along the spring, ≥ 0.
    pub damping: f64,
    /// The arms from the centres of mass of a and b to the spring's ends, in body axes
    /// (at - c), when some end is not at its centre of mass; the second is zero for a
    /// fixed point. `None` when both ends are at the centres of mass.
    pub arms: Option<(DVec2, DVec2)>,
}

impl Spring {
    /// Returns the force on body a.
    #[inline(always)]
    fn force_on_a(&self, d: DVec2, relative_velocity: DVec2) -> DVec2 {
        if self.rest_length == 0.0 {
            // F_a = -stiffness·d - damping·((v_rel·d)/|d|²)·d, the zero-rest-length form.
            let elastic = -self.stiffness * d;
            if self.damping != 0.0 {
                // |d|² is needed only here: an undamped spring does not compute it.
                let len_sq = d.length_squared();
                if len_sq > 0.0 {
                    return elastic - self.damping * relative_velocity.dot(d) / len_sq * d;
                }
            }
            // Without damping the force is the elastic part alone: x - 0 = x to the bit,
            // so the subtraction of a zero damping term, a step in the chain of every
            // force evaluation, is left out.
            return elastic;
        }
        let len_sq = d.length_squared();
        if len_sq == 0.0 {
            return DVec2::ZERO;
        }
        let len = len_sq.sqrt();
        let u = d / len;
        // F_a = -stiffness·(ℓ - rest_length)·u - damping·(v_rel·u)·u.
        -(self.stiffness * (len - self.rest_length) + self.damping * relative_velocity.dot(u)) * u
    }

    /// Adds the spring's force to both ends.
    #[inline(always)]
    pub fn accumulate(&self, pos: &[DVec2], vel: &[DVec2], force: &mut [DVec2]) {
        let a = self.a as usize;
        match self.b {
            Anchor::Body(b) => {
                let b = b as usize;
                let f = self.force_on_a(pos[a] - pos[b], vel[a] - vel[b]);
                force[a] += f;
                force[b] -= f;
            }
            Anchor::Point(p) => {
                force[a] += self.force_on_a(pos[a] - p, vel[a]);
            }
        }
    }

    /// Adds the spring's force to both ends and, when an end is off its body's centre
    /// of mass, the force's torque to that body; `angle` and `omega` are the bodies'
    /// angles and angular velocities. A spring between centres of mass adds exactly
    /// what [`Spring::accumulate`] adds, and no torque.
    #[inline]
    pub fn accumulate_rigid(
        &self,
        pos: &[DVec2],
        vel: &[DVec2],
        (angle, omega): (&[f64], &[f64]),
        force: &mut [DVec2],
        torque: &mut [f64],
    ) {
        let Some((arm_a, arm_b)) = self.arms else {
            self.accumulate(pos, vel, force);
            return;
        };
        let a = self.a as usize;
        // r_aP = R(θ_a)·(at_a - c_a); the end is at r_a + r_aP and moves at
        // v_a + ω_a·r_aP⊥.
        let r_ap = rotate(angle[a].sin_cos(), arm_a);
        let (end_a, v_end_a) = (pos[a] + r_ap, point_velocity(vel[a], omega[a], r_ap));
        match self.b {
            Anchor::Body(b) => {
                let b = b as usize;
                let r_bp = rotate(angle[b].sin_cos(), arm_b);
                let end_b = pos[b] + r_bp;
                let v_end_b = point_velocity(vel[b], omega[b], r_bp);
                let f = self.force_on_a(end_a - end_b, v_end_a - v_end_b);
                force[a] += f;
                force[b] -= f;
                // τ_a = r_aP⊥·F_a, τ_b = r_bP⊥·(-F_a).
                torque[a] += perp_dot(r_ap, f);
                torque[b] -= perp_dot(r_bp, f);
            }
            Anchor::Point(p) => {
                let f = self.force_on_a(end_a - p, v_end_a);
                force[a] += f;
                // τ_a = r_aP⊥·F_a.
                torque[a] += perp_dot(r_ap, f);
            }
        }
    }

    /// Returns the elastic energy ½·stiffness·(ℓ - rest_length)², or `None` when the
    /// spring is damped (its energy is not conserved); `angle` places ends that are
    /// off the centres of mass.
    pub fn potential_energy(&self, pos: &[DVec2], angle: &[f64]) -> Option<f64> {
        if self.damping != 0.0 {
            return None;
        }
        Some(self.elastic_energy(pos, angle))
    }

    /// Returns the elastic energy ½·stiffness·(ℓ - rest_length)², damped or not, with ℓ
    /// the distance between the spring's ends; `angle` places ends that are off the
    /// centres of mass (it is read only for such a spring).
    pub fn elastic_energy(&self, pos: &[DVec2], angle: &[f64]) -> f64 {
        let (arm_a, arm_b) = self.arms.unwrap_or((DVec2::ZERO, DVec2::ZERO));
        let end = |i: usize, arm: DVec2| {
            if arm == DVec2::ZERO {
                pos[i]
            } else {
                pos[i] + rotate(angle[i].sin_cos(), arm)
            }
        };
        let other = match self.b {
            Anchor::Body(b) => end(b as usize, arm_b),
            Anchor::Point(p) => p,
        };
        let stretch = (end(self.a as usize, arm_a) - other).length() - self.rest_length;
        0.5 * self.stiffness * stretch * stretch
    }
}
