//! The system of equations the integrators solve, and the state they advance.

use glam::DVec2;

use super::forces::{ForceSet, ForceSpec};

/// The state of every body at one instant: the article's r and v (Equations 1 and 2),
/// for each body's centre of mass, in flat arrays indexed by body.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Simulated time t.
    pub t: f64,
    /// Centre-of-mass positions r, one per body.
    pub pos: Vec<DVec2>,
    /// Centre-of-mass velocities v = dr/dt, one per body.
    pub vel: Vec<DVec2>,
}

impl State {
    /// Returns the number of bodies.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Returns true when the state holds no body.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }
}

/// The masses of the bodies and the forces on them: everything needed to compute
/// accelerations from a state. Fixed for the length of a run.
#[derive(Clone, Debug)]
pub struct System {
    mass: Vec<f64>,
    inv_mass: Vec<f64>,
    forces: ForceSet,
}

impl System {
    /// Builds a system from the bodies' masses and the validated force specifications.
    ///
    /// Every mass must be finite and positive (the scene validator guarantees it), and
    /// every body index named by a force must be below `mass.len()`.
    pub fn new(mass: Vec<f64>, forces: &[ForceSpec]) -> Self {
        debug_assert!(mass.iter().all(|m| m.is_finite() && *m > 0.0));
        let inv_mass = mass.iter().map(|m| 1.0 / m).collect();
        let forces = ForceSet::new(forces, mass.len());
        System {
            mass,
            inv_mass,
            forces,
        }
    }

    /// Returns the number of bodies.
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Returns true when the system has no body.
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// Returns the mass of every body.
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Returns the forces acting in this system.
    pub fn force_set(&self) -> &ForceSet {
        &self.forces
    }

    /// Writes the net force on every body at time `t` into `force`.
    ///
    /// This is the sum F_T of Equation 11: every force on a body acts at its centre of
    /// mass, whatever point of the body it is applied to.
    pub fn net_forces(&self, t: f64, pos: &[DVec2], vel: &[DVec2], force: &mut [DVec2]) {
        debug_assert_eq!(pos.len(), self.len());
        debug_assert_eq!(vel.len(), self.len());
        debug_assert_eq!(force.len(), self.len());
        force.fill(DVec2::ZERO);
        self.forces.accumulate(t, pos, vel, &self.mass, force);
    }

    /// Writes the acceleration of every body's centre of mass at time `t` into `acc`.
    ///
    /// Equation 11, solved for the acceleration: a_CM = F_T / M.
    pub fn accelerations(&self, t: f64, pos: &[DVec2], vel: &[DVec2], acc: &mut [DVec2]) {
        self.net_forces(t, pos, vel, acc);
        for (a, inv_m) in acc.iter_mut().zip(&self.inv_mass) {
            *a *= *inv_m;
        }
    }

    /// Returns the total momentum p_T = Σ m_i v_i (Equations 7 and 10).
    pub fn momentum(&self, vel: &[DVec2]) -> DVec2 {
        vel.iter()
            .zip(&self.mass)
            .fold(DVec2::ZERO, |p, (v, m)| p + *m * *v)
    }

    /// Returns the total kinetic energy Σ ½ m_i |v_i|².
    pub fn kinetic_energy(&self, vel: &[DVec2]) -> f64 {
        vel.iter()
            .zip(&self.mass)
            .map(|(v, m)| 0.5 * m * v.length_squared())
            .sum()
    }

    /// Returns the potential energy of the conservative forces (gravity, springs,
    /// central forces) at time `t`, or `None` when some force has no potential
    /// (drag, time-varying forces), so that energy is not a conserved quantity.
    pub fn potential_energy(&self, t: f64, pos: &[DVec2]) -> Option<f64> {
        self.forces.potential_energy(t, pos, &self.mass)
    }
}
