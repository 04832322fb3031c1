//! Uniform gravity.

use glam::DVec2;

use super::{Masses, Selection, Within};

/// Uniform gravity, F = m·g, so that every body falls with the same acceleration g.
#[derive(Clone, Debug, PartialEq)]
pub struct Gravity {
    /// The gravitational acceleration g.
    pub g: DVec2,
    /// The bodies it acts on.
    pub bodies: Selection,
}

impl Gravity {
    /// Adds F = m·g to every selected body among the chunk of bodies `start..start +
    /// force.len()`, whose masses are `mass`.
    #[inline(always)]
    pub fn accumulate(&self, start: usize, mass: Masses<'_>, force: &mut [DVec2]) {
        match (self.bodies.within(start, force.len()), mass) {
            (Within::Run(run), Masses::Uniform { m, .. }) => {
                // F = m·g, the same for every body of equal mass.
                let f_g = m * self.g;
                for f in &mut force[run] {
                    *f += f_g;
                }
            }
            (Within::Run(run), Masses::PerBody { m, .. }) => {
                for (f, m) in force[run.clone()].iter_mut().zip(&m[run]) {
                    // F = m·g.
                    *f += *m * self.g;
                }
            }
            (Within::List(list), _) => {
                for &i in list {
                    let i = i as usize - start;
                    // F = m·g.
                    force[i] += mass.m(i) * self.g;
                }
            }
        }
    }

    /// Returns the potential energy U = -Σ m·(g·r).
    pub fn potential_energy(&self, pos: &[DVec2], mass: &[f64]) -> f64 {
        let mut u = 0.0;
        self.bodies
            .for_each(pos.len(), |i| u -= mass[i] * self.g.dot(pos[i]));
        u
    }
}
