//! The state of every body at one instant, and the borrowed view of it that a force
//! evaluation reads.

use glam::DVec2;
use rayon::prelude::*;

use super::chunks::{all_finite, BLOCK, PARALLEL_MIN};

/// The state of every body at one instant: the article's r and v (Equations 1 and 2)
/// for each body's centre of mass, and its orientation θ and angular velocity ω, in flat
/// arrays indexed by body.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Simulated time t.
    pub t: f64,
    /// Centre-of-mass positions r, one per body.
    pub pos: Vec<DVec2>,
    /// Centre-of-mass velocities v = dr/dt, one per body.
    pub vel: Vec<DVec2>,
    /// Orientations θ in radians, counter-clockwise positive, one per body.
    pub angle: Vec<f64>,
    /// Angular velocities ω = dθ/dt, one per body.
    pub omega: Vec<f64>,
}

/// The coordinates of every body at one instant, borrowed: what a force evaluation
/// reads. Stages of an integrator are states that live in its own buffers, so they are
/// passed as views rather than as [`State`]s.
#[derive(Clone, Copy, Debug)]
pub struct Coords<'a> {
    /// Centre-of-mass positions r.
    pub pos: &'a [DVec2],
    /// Centre-of-mass velocities v.
    pub vel: &'a [DVec2],
    /// Orientations θ; read only when the system spins (see
    /// [`System::spins`](super::system::System::spins)).
    pub angle: &'a [f64],
    /// Angular velocities ω; read only when the system spins.
    pub omega: &'a [f64],
}

impl<'a> Coords<'a> {
    /// Returns the coordinates of a state.
    pub fn of(state: &'a State) -> Self {
        Coords {
            pos: &state.pos,
            vel: &state.vel,
            angle: &state.angle,
            omega: &state.omega,
        }
    }

    /// Returns positions and velocities without angles, for a system that does not
    /// spin (which reads none).
    pub fn linear(pos: &'a [DVec2], vel: &'a [DVec2]) -> Self {
        Coords {
            pos,
            vel,
            angle: &[],
            omega: &[],
        }
    }
}

impl State {
    /// Returns a state of bodies at the given positions and velocities, none turned
    /// (θ = 0) or spinning (ω = 0).
    pub fn new(t: f64, pos: Vec<DVec2>, vel: Vec<DVec2>) -> Self {
        debug_assert_eq!(pos.len(), vel.len());
        let n = pos.len();
        State {
            t,
            pos,
            vel,
            angle: vec![0.0; n],
            omega: vec![0.0; n],
        }
    }

    /// Returns true when every angle and angular velocity is finite.
    pub fn angles_are_finite(&self) -> bool {
        self.angle
            .iter()
            .zip(&self.omega)
            .all(|(a, w)| a.is_finite() && w.is_finite())
    }

    /// Returns true when every position and velocity is finite. One pass over the flat
    /// arrays, split across threads for many bodies.
    pub fn is_finite(&self) -> bool {
        if self.len() < PARALLEL_MIN {
            return all_finite(&self.pos, &self.vel);
        }
        self.pos
            .par_chunks(BLOCK)
            .zip(self.vel.par_chunks(BLOCK))
            .all(|(p, v)| all_finite(p, v))
    }

    /// Returns the number of bodies.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Returns true when the state holds no body.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }
}
