//! An attractive inverse-square force towards a fixed centre, as of a heavy sun.

use glam::DVec2;

use super::{Masses, Selection, Within};

/// F = -μ·m·(r - c)/|r - c|³: an attraction towards the centre c whose magnitude falls
/// with the square of the distance, μ·m/|r - c|². Like gravity, the acceleration it
/// gives does not depend on the body's mass. A body at distance R moving at speed
/// √(μ/R) perpendicular to r - c stays on a circle of radius R with period 2π·√(R³/μ).
/// At the centre itself the force is undefined; it is taken as zero there.
#[derive(Clone, Debug, PartialEq)]
pub struct Central {
    /// The fixed centre c.
    pub centre: DVec2,
    /// The strength μ > 0 (G times the central mass).
    pub strength: f64,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl Central {
    /// Adds F = -μ·m·(r - c)/|r - c|³ to every selected body among the chunk of
    /// bodies `start..start + force.len()`, whose positions are `pos` and masses `mass`.
    #[inline(always)]
    pub fn accumulate(&self, start: usize, pos: &[DVec2], mass: Masses<'_>, force: &mut [DVec2]) {
        let one = |i: usize, force: &mut [DVec2]| {
            let d = pos[i] - self.centre;
            let r2 = d.length_squared();
            if r2 > 0.0 {
                // F = -μ·m·(r - c)/|r - c|³, with 1/|r - c|³ = 1/(r²·√r²).
                let inv_r3 = 1.0 / (r2 * r2.sqrt());
                force[i] -= self.strength * mass.m(i) * inv_r3 * d;
            }
        };
        match self.bodies.within(start, force.len()) {
            Within::Run(run) => run.for_each(|i| one(i, force)),
            Within::List(list) => list.iter().for_each(|&i| one(i as usize - start, force)),
        }
    }

    /// Returns the potential energy U = -Σ μ·m/|r - c|.
    pub fn potential_energy(&self, pos: &[DVec2], mass: &[f64]) -> f64 {
        let mut u = 0.0;
        self.bodies.for_each(pos.len(), |i| {
            let r = (pos[i] - self.centre).length();
            if r > 0.0 {
                u -= self.strength * mass[i] / r;
            }
        });
        u
    }
}
