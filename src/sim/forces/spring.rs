//! Damped springs between two bodies, or from a body to a fixed point.

use glam::DVec2;

use super::Anchor;

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

    /// Returns the elastic energy ½·stiffness·(ℓ - rest_length)², or `None` when the
    /// spring is damped (its energy is not conserved).
    pub fn potential_energy(&self, pos: &[DVec2]) -> Option<f64> {
        if self.damping != 0.0 {
            return None;
        }
        Some(self.elastic_energy(pos))
    }

    /// Returns the elastic energy ½·stiffness·(ℓ - rest_length)², damped or not.
    pub fn elastic_energy(&self, pos: &[DVec2]) -> f64 {
        let other = match self.b {
            Anchor::Body(b) => pos[b as usize],
            Anchor::Point(p) => p,
        };
        let stretch = (pos[self.a as usize] - other).length() - self.rest_length;
        0.5 * self.stiffness * stretch * stretch
    }
}
