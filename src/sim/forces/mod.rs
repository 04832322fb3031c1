//! Forces, one file per family, gathered into a [`ForceSet`] that sums them.
//!
//! Each family keeps its own list, so a scene pays per step only for the kinds of force
//! it declares: an empty list is one branch on its length. Every force adds into a
//! net-force buffer (Equation 11: all forces act at the centre of mass); the system then
//! divides by mass.

mod central;
mod constant_gravity;
mod linear_drag;
mod quadratic_drag;
mod spring;
mod time_varying;

use glam::DVec2;

pub use central::Central;
pub use constant_gravity::Gravity;
pub use linear_drag::LinearDrag;
pub use quadratic_drag::QuadraticDrag;
pub use spring::Spring;
pub use time_varying::TimeVarying;

/// Which bodies a force acts on.
#[derive(Clone, Debug, PartialEq)]
pub enum Selection {
    /// Every body in the scene.
    All,
    /// The bodies with these indices, each at most once, in increasing order.
    Bodies(Vec<u32>),
}

impl Selection {
    /// Calls `f` with the index of every selected body, in increasing order.
    #[inline]
    pub fn for_each(&self, n: usize, mut f: impl FnMut(usize)) {
        match self {
            Selection::All => (0..n).for_each(f),
            Selection::Bodies(list) => list.iter().for_each(|&i| f(i as usize)),
        }
    }

    /// Returns true when body `i` is selected.
    pub fn contains(&self, i: usize) -> bool {
        match self {
            Selection::All => true,
            Selection::Bodies(list) => list.binary_search(&(i as u32)).is_ok(),
        }
    }
}

/// The other end of a spring: a body or a point fixed in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Anchor {
    /// A body, by index.
    Body(u32),
    /// A fixed point in world coordinates.
    Point(DVec2),
}

/// A validated force, as the scene declares it. Body indices are in range and every
/// number is finite (the scene validator guarantees both).
#[derive(Clone, Debug, PartialEq)]
pub enum ForceSpec {
    /// Uniform gravity: F = m·g.
    Gravity { g: DVec2, bodies: Selection },
    /// Linear drag: F = -k·v (the article's Equation 12 is k = 1).
    Drag { k: f64, bodies: Selection },
    /// Quadratic drag: F = -c·|v|·v.
    QuadraticDrag { c: f64, bodies: Selection },
    /// A force that changes linearly in time: F = f0 + f1·t (the article's F = 2t).
    TimeVarying {
        f0: DVec2,
        f1: DVec2,
        bodies: Selection,
    },
    /// A spring (Hooke's law with damping along its axis) from body `a` to `b`.
    Spring {
        a: u32,
        b: Anchor,
        stiffness: f64,
        rest_length: f64,
        damping: f64,
    },
    /// An attractive inverse-square force towards a fixed centre:
    /// F = -μ·m·(r - c)/|r - c|³, with μ the strength.
    Central {
        centre: DVec2,
        strength: f64,
        bodies: Selection,
    },
}

impl ForceSpec {
    /// Returns the name of this force's kind as a scene writes it.
    pub fn kind_name(&self) -> &'static str {
        match self {
            ForceSpec::Gravity { .. } => "gravity",
            ForceSpec::Drag { .. } => "drag",
            ForceSpec::QuadraticDrag { .. } => "quadratic-drag",
            ForceSpec::TimeVarying { .. } => "force",
            ForceSpec::Spring { .. } => "spring",
            ForceSpec::Central { .. } => "central",
        }
    }
}

/// Every force of a scene, grouped by family.
#[derive(Clone, Debug, Default)]
pub struct ForceSet {
    n: usize,
    gravity: Vec<Gravity>,
    drag: Vec<LinearDrag>,
    quadratic_drag: Vec<QuadraticDrag>,
    time_varying: Vec<TimeVarying>,
    springs: Vec<Spring>,
    central: Vec<Central>,
}

impl ForceSet {
    /// Groups validated force specifications by family for a scene of `n` bodies.
    pub fn new(specs: &[ForceSpec], n: usize) -> Self {
        let mut set = ForceSet {
            n,
            ..ForceSet::default()
        };
        for spec in specs {
            match spec.clone() {
                ForceSpec::Gravity { g, bodies } => set.gravity.push(Gravity { g, bodies }),
                ForceSpec::Drag { k, bodies } => set.drag.push(LinearDrag { k, bodies }),
                ForceSpec::QuadraticDrag { c, bodies } => {
                    set.quadratic_drag.push(QuadraticDrag { c, bodies })
                }
                ForceSpec::TimeVarying { f0, f1, bodies } => {
                    set.time_varying.push(TimeVarying { f0, f1, bodies })
                }
                ForceSpec::Spring {
                    a,
                    b,
                    stiffness,
                    rest_length,
                    damping,
                } => set.springs.push(Spring {
                    a,
                    b,
                    stiffness,
                    rest_length,
                    damping,
                }),
                ForceSpec::Central {
                    centre,
                    strength,
                    bodies,
                } => set.central.push(Central {
                    centre,
                    strength,
                    bodies,
                }),
            }
        }
        set
    }

    /// Returns true when no force acts at all.
    pub fn is_empty(&self) -> bool {
        self.gravity.is_empty()
            && self.drag.is_empty()
            && self.quadratic_drag.is_empty()
            && self.time_varying.is_empty()
            && self.springs.is_empty()
            && self.central.is_empty()
    }

    /// Returns true when some force depends on velocity (drag, spring damping), which
    /// matters to integrators such as velocity Verlet that assume it does not.
    pub fn depends_on_velocity(&self) -> bool {
        !self.drag.is_empty()
            || !self.quadratic_drag.is_empty()
            || self.springs.iter().any(|s| s.damping != 0.0)
    }

    /// Adds every force at time `t` into `force` (which the caller has zeroed).
    pub fn accumulate(
        &self,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        mass: &[f64],
        force: &mut [DVec2],
    ) {
        debug_assert_eq!(pos.len(), self.n);
        for f in &self.gravity {
            f.accumulate(mass, force);
        }
        for f in &self.drag {
            f.accumulate(vel, force);
        }
        for f in &self.quadratic_drag {
            f.accumulate(vel, force);
        }
        for f in &self.time_varying {
            f.accumulate(t, force);
        }
        for f in &self.springs {
            f.accumulate(pos, vel, force);
        }
        for f in &self.central {
            f.accumulate(pos, mass, force);
        }
    }

    /// Returns the total potential energy of the forces at time `t`, or `None` when a
    /// force without a potential (drag, time-varying force, damped spring) is present.
    pub fn potential_energy(&self, _t: f64, pos: &[DVec2], mass: &[f64]) -> Option<f64> {
        if !self.drag.is_empty() || !self.quadratic_drag.is_empty() || !self.time_varying.is_empty()
        {
            return None;
        }
        let mut energy = 0.0;
        for f in &self.gravity {
            energy += f.potential_energy(pos, mass);
        }
        for f in &self.springs {
            energy += f.potential_energy(pos)?;
        }
        for f in &self.central {
            energy += f.potential_energy(pos, mass);
        }
        Some(energy)
    }
}
