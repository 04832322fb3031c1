//! Forces that change with time.

use glam::DVec2;

use super::{Selection, Within};
use crate::sim::rigid::{perp_dot, rotate};

/// A force that changes linearly with time, F(t) = f0 + f1·t. The article's example
/// F = 2t is f0 = (0, 0), f1 = (2, 0); with it v(t) = v0 + t²/m and
/// r(t) = r0 + v0·t + t³/(3m).
///
/// Applied at a body point `at` (body coordinates) rather than at the centre of mass,
/// the same force also turns the body: its torque is τ = r⊥·F, with r = R(θ)·(at - c)
/// the arm from the centre of mass to the point in world axes (see [`crate::sim::rigid`]).
/// The force on the centre of mass is F either way.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeVarying {
    /// The force at t = 0.
    pub f0: DVec2,
    /// The rate of change of the force.
    pub f1: DVec2,
    /// The bodies it acts on.
    pub bodies: Selection,
    /// The body point it acts at, in body coordinates; `None` for the centre of mass.
    pub at: Option<DVec2>,
}

impl TimeVarying {
    /// Adds F(t) = f0 + f1·t to every selected body among the chunk of bodies
    /// `start..start + force.len()`.
    #[inline(always)]
    pub fn accumulate(&self, t: f64, start: usize, force: &mut [DVec2]) {
        // F(t) = f0 + f1·t, the same for every body.
        let f_t = self.f0 + t * self.f1;
        match self.bodies.within(start, force.len()) {
            Within::Run(run) => {
                for f in &mut force[run] {
                    *f += f_t;
                }
            }
            Within::List(list) => {
                for &i in list {
                    force[i as usize - start] += f_t;
                }
            }
        }
    }
}

impl TimeVarying {
    /// Adds the torque τ = r⊥·F(t) of the force to every selected body, with
    /// r = R(θ)·(at - c) from the body's angle θ and centre of mass c in body
    /// coordinates. Does nothing for a force at the centre of mass.
    #[inline]
    pub fn accumulate_torque(&self, t: f64, angle: &[f64], centre: &[DVec2], torque: &mut [f64]) {
        let Some(at) = self.at else {
            return;
        };
        // F(t) = f0 + f1·t.
        let f_t = self.f0 + t * self.f1;
        self.bodies.for_each(torque.len(), |i| {
            // r = R(θ)·(at - c), then τ = r⊥·F.
            let arm = rotate(angle[i].sin_cos(), at - centre[i]);
            torque[i] += perp_dot(arm, f_t);
        });
    }

    /// Returns true when the force acts off the centre of mass of some body it acts on
    /// (`centre` gives each body's centre of mass in body coordinates), so that it
    /// turns that body.
    pub fn has_lever(&self, centre: &[DVec2]) -> bool {
        let Some(at) = self.at else {
            return false;
        };
        let mut any = false;
        self.bodies
            .for_each(centre.len(), |i| any |= at != centre[i]);
        any
    }
}
