//! Forces and torques, one file per family, gathered into a [`ForceSet`] that sums them.
//!
//! Each family keeps its own list, so a scene pays per step only for the kinds of force
//! it declares: an empty list is one branch on its length. Every force adds into a
//! net-force buffer (Equation 11: the net force accelerates the centre of mass,
//! wherever on the body each force acts); the system then divides by mass. A force
//! applied off the centre of mass (a force `at` a body point, a spring anchored off
//! it) also adds its torque τ = r⊥·F into a net-torque buffer, beside the pure torques
//! (constant torque, angular drag), and the system divides that by the moment of
//! inertia: α = Στ/I.

mod angular_drag;
mod central;
mod constant_gravity;
mod linear_drag;
mod quadratic_drag;
mod spring;
mod time_varying;
mod torque;

use glam::DVec2;

pub use angular_drag::AngularDrag;
pub use central::Central;
pub use constant_gravity::Gravity;
pub use linear_drag::LinearDrag;
pub use quadratic_drag::QuadraticDrag;
pub use spring::Spring;
pub use time_varying::TimeVarying;
pub use torque::ConstantTorque;

/// Bodies whose forces are summed at once in the per-body loops (see
/// [`ForceSet::forces_on`]).
pub const LANES: usize = 8;

/// Which bodies a force acts on.
#[derive(Clone, Debug, PartialEq)]
pub enum Selection {
    /// Every body in the scene.
    All,
    /// The bodies with indices start..end (a swarm, say): a contiguous run, which the
    /// force loops walk without an index list, so that they vectorise.
    Range { start: u32, end: u32 },
    /// The bodies with these indices, each at most once, in increasing order.
    Bodies(Vec<u32>),
}

impl Selection {
    /// Builds the selection of the bodies listed, each at most once, in increasing
    /// order, among `n` bodies: `All` when every body is listed, `Range` when they are
    /// contiguous, and the list otherwise. All three act on the same bodies in the same
    /// order, so the choice changes speed, not results.
    pub fn from_sorted(list: Vec<u32>, n: usize) -> Self {
        debug_assert!(list.windows(2).all(|w| w[0] < w[1]));
        match (list.first(), list.last()) {
            (Some(&start), Some(&last)) if (last - start) as usize + 1 == list.len() => {
                if start == 0 && list.len() == n {
                    Selection::All
                } else {
                    Selection::Range {
                        start,
                        end: last + 1,
                    }
                }
            }
            _ => Selection::Bodies(list),
        }
    }

    /// Returns the contiguous run of bodies selected among `n`, if the selection is one.
    #[inline]
    pub fn as_range(&self, n: usize) -> Option<std::ops::Range<usize>> {
        match self {
            Selection::All => Some(0..n),
            Selection::Range { start, end } => Some(*start as usize..*end as usize),
            Selection::Bodies(_) => None,
        }
    }

    /// Calls `f` with the index of every selected body, in increasing order.
    #[inline]
    pub fn for_each(&self, n: usize, mut f: impl FnMut(usize)) {
        match self {
            Selection::All => (0..n).for_each(f),
            Selection::Range { start, end } => (*start as usize..*end as usize).for_each(f),
            Selection::Bodies(list) => list.iter().for_each(|&i| f(i as usize)),
        }
    }

    /// Returns true when body `i` is selected.
    pub fn contains(&self, i: usize) -> bool {
        match self {
            Selection::All => true,
            Selection::Range { start, end } => (*start as usize..*end as usize).contains(&i),
            Selection::Bodies(list) => list.binary_search(&(i as u32)).is_ok(),
        }
    }
}

/// The selected bodies within a chunk of bodies `start..start + len`.
#[derive(Clone, Debug, PartialEq)]
pub enum Within<'a> {
    /// A contiguous run, as indices relative to the chunk's start: the loop over it
    /// walks flat slices and vectorises.
    Run(std::ops::Range<usize>),
    /// The selected bodies' indices in the chunk, in increasing order; indices are
    /// the scene's, not relative to the chunk.
    List(&'a [u32]),
}

impl Selection {
    /// Returns the selected bodies within the chunk `start..start + len`.
    #[inline(always)]
    pub fn within(&self, start: usize, len: usize) -> Within<'_> {
        let end = start + len;
        match self {
            Selection::All => Within::Run(0..len),
            Selection::Range { start: a, end: b } => {
                let a = (*a as usize).clamp(start, end);
                let b = (*b as usize).clamp(a, end);
                Within::Run(a - start..b - start)
            }
            Selection::Bodies(list) => {
                let lo = list.partition_point(|&i| (i as usize) < start);
                let hi = list.partition_point(|&i| (i as usize) < end);
                Within::List(&list[lo..hi])
            }
        }
    }
}

/// The masses of a chunk of bodies, and their inverses: one value for every body when
/// all masses are equal (as in a swarm), so that the per-body loops read no mass array.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Masses<'a> {
    /// Every body has mass `m`; `inv` = 1/m.
    Uniform { m: f64, inv: f64 },
    /// Body i has mass `m[i]`; `inv[i]` = 1/`m[i]`.
    PerBody { m: &'a [f64], inv: &'a [f64] },
}

impl<'a> Masses<'a> {
    /// Returns the mass of body `i` of the chunk.
    #[inline(always)]
    pub fn m(&self, i: usize) -> f64 {
        match self {
            Masses::Uniform { m, .. } => *m,
            Masses::PerBody { m, .. } => m[i],
        }
    }

    /// Returns 1/m of body `i` of the chunk.
    #[inline(always)]
    pub fn inv(&self, i: usize) -> f64 {
        match self {
            Masses::Uniform { inv, .. } => *inv,
            Masses::PerBody { inv, .. } => inv[i],
        }
    }

    /// Returns the masses of the bodies `start..start + len` of this chunk.
    #[inline(always)]
    pub fn chunk(&self, start: usize, len: usize) -> Masses<'a> {
        match *self {
            Masses::PerBody { m, inv } => Masses::PerBody {
                m: &m[start..start + len],
                inv: &inv[start..start + len],
            },
            uniform => uniform,
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
    /// A force that changes linearly in time: F = f0 + f1·t (the article's F = 2t),
    /// at the centre of mass or, with `at`, at that body point (body coordinates),
    /// where it also exerts a torque.
    TimeVarying {
        f0: DVec2,
        f1: DVec2,
        bodies: Selection,
        at: Option<DVec2>,
    },
    /// A spring (Hooke's law with damping along its axis) from body `a` to `b`, with
    /// its ends at the centres of mass or, with `a_at` and `b_at`, at those body points
    /// (body coordinates); `b_at` only when `b` is a body.
    Spring {
        a: u32,
        b: Anchor,
        stiffness: f64,
        rest_length: f64,
        damping: f64,
        a_at: Option<DVec2>,
        b_at: Option<DVec2>,
    },
    /// A constant torque τ (counter-clockwise positive).
    Torque { tau: f64, bodies: Selection },
    /// Angular drag: τ = -k·ω.
    AngularDrag { k: f64, bodies: Selection },
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
            ForceSpec::Torque { .. } => "torque",
            ForceSpec::AngularDrag { .. } => "angular-drag",
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
    torque: Vec<ConstantTorque>,
    angular_drag: Vec<AngularDrag>,
}

impl ForceSet {
    /// Groups validated force specifications by family for a scene of `n` bodies.
    ///
    /// `centre` gives each body's centre of mass in its body coordinates, to turn the
    /// body points at which springs are anchored into arms from the centre of mass;
    /// `None` means every centre of mass is the origin of its body coordinates.
    pub fn new(specs: &[ForceSpec], n: usize, centre: Option<&[DVec2]>) -> Self {
        debug_assert!(centre.is_none_or(|c| c.len() == n));
        let centre_of = |i: usize| centre.map_or(DVec2::ZERO, |c| c[i]);
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
                ForceSpec::TimeVarying { f0, f1, bodies, at } => {
                    set.time_varying.push(TimeVarying { f0, f1, bodies, at })
                }
                ForceSpec::Spring {
                    a,
                    b,
                    stiffness,
                    rest_length,
                    damping,
                    a_at,
                    b_at,
                } => {
                    // The arm from each centre of mass to its end, in body axes: at - c.
                    let arm_a = a_at.map_or(DVec2::ZERO, |p| p - centre_of(a as usize));
                    let arm_b = match (b, b_at) {
                        (Anchor::Body(b), Some(p)) => p - centre_of(b as usize),
                        _ => DVec2::ZERO,
                    };
                    let arms =
                        (arm_a != DVec2::ZERO || arm_b != DVec2::ZERO).then_some((arm_a, arm_b));
                    set.springs.push(Spring {
                        a,
                        b,
                        stiffness,
                        rest_length,
                        damping,
                        arms,
                    })
                }
                ForceSpec::Torque { tau, bodies } => {
                    set.torque.push(ConstantTorque { tau, bodies })
                }
                ForceSpec::AngularDrag { k, bodies } => {
                    set.angular_drag.push(AngularDrag { k, bodies })
                }
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
            && self.torque.is_empty()
            && self.angular_drag.is_empty()
    }

    /// Returns true when some force depends on velocity or angular velocity (drag,
    /// spring damping, angular drag), which matters to integrators such as velocity
    /// Verlet that assume it does not.
    pub fn depends_on_velocity(&self) -> bool {
        !self.drag.is_empty()
            || !self.quadratic_drag.is_empty()
            || !self.angular_drag.is_empty()
            || self.springs.iter().any(|s| s.damping != 0.0)
    }

    /// Returns true when something here can set a body turning: a constant torque, a
    /// force applied off some body's centre of mass (`centre` gives each body's centre
    /// of mass in body coordinates), or a spring anchored off one. Angular drag alone
    /// cannot: it only slows a spin that is already there.
    pub fn has_torque_sources(&self, centre: &[DVec2]) -> bool {
        !self.torque.is_empty()
            || self.springs.iter().any(|s| s.arms.is_some())
            || self.time_varying.iter().any(|f| f.has_lever(centre))
    }

    /// Sets `turned[i]` for every body that something here can set turning: a
    /// constant torque on it, a force applied off its centre of mass (`centre` gives
    /// each body's centre of mass in body coordinates), or a spring anchored off it.
    pub fn mark_torque_targets(&self, centre: &[DVec2], turned: &mut [bool]) {
        let n = turned.len();
        for f in &self.torque {
            f.bodies.for_each(n, |i| turned[i] = true);
        }
        for f in &self.time_varying {
            if let Some(at) = f.at {
                f.bodies.for_each(n, |i| turned[i] |= at != centre[i]);
            }
        }
        for s in &self.springs {
            if let Some((arm_a, arm_b)) = s.arms {
                turned[s.a as usize] |= arm_a != DVec2::ZERO;
                if let Anchor::Body(b) = s.b {
                    turned[b as usize] |= arm_b != DVec2::ZERO;
                }
            }
        }
    }

    /// Returns true when some torque acts: a torque source, or angular drag.
    pub fn has_torques(&self, centre: &[DVec2]) -> bool {
        !self.angular_drag.is_empty() || self.has_torque_sources(centre)
    }

    /// Returns true when some force that acts on each body alone (all but the springs)
    /// is present.
    #[inline]
    pub fn has_per_body(&self) -> bool {
        !(self.gravity.is_empty()
            && self.drag.is_empty()
            && self.quadratic_drag.is_empty()
            && self.time_varying.is_empty()
            && self.central.is_empty())
    }

    /// Returns the summed gravitational acceleration g = Σ g_i and drag coefficient
    /// k = Σ k_i when every force is uniform gravity or linear drag acting on every one
    /// of the `n` bodies, and `None` when some other force acts or a force acts on only
    /// some bodies. Each sum starts from zero, as the net force does.
    pub fn gravity_and_linear_drag(&self) -> Option<(DVec2, f64)> {
        let everyone = |s: &Selection| s.as_range(self.n) == Some(0..self.n);
        let only_these = self.quadratic_drag.is_empty()
            && self.time_varying.is_empty()
            && self.springs.is_empty()
            && self.central.is_empty()
            && self.torque.is_empty()
            && self.angular_drag.is_empty();
        if !only_these
            || !self.gravity.iter().all(|f| everyone(&f.bodies))
            || !self.drag.iter().all(|f| everyone(&f.bodies))
        {
            return None;
        }
        // g = Σ g_i, in file order.
        let g = self.gravity.iter().fold(DVec2::ZERO, |sum, f| sum + f.g);
        // k = Σ k_i, in file order.
        let k = self.drag.iter().fold(0.0, |sum, f| sum + f.k);
        Some((g, k))
    }

    /// Returns true when some spring couples bodies (or a body to a point). Every other
    /// force acts on each body alone, so without springs each body's acceleration
    /// depends only on its own state and the time.
    pub fn has_springs(&self) -> bool {
        !self.springs.is_empty()
    }

    /// Adds every force at time `t` into `force` (which the caller has zeroed).
    ///
    /// Forces are summed family by family in a fixed order: gravity, linear drag,
    /// quadratic drag, time-varying forces, central forces, springs; within a family,
    /// in file order. Every way of computing the forces (whole arrays, chunks, threads,
    /// a few bodies in registers) adds in this order, so they agree to the bit. The
    /// springs come last because they alone couple bodies: everything before them can
    /// be summed body by body.
    pub fn accumulate(
        &self,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        mass: Masses<'_>,
        force: &mut [DVec2],
    ) {
        debug_assert_eq!(pos.len(), self.n);
        self.accumulate_per_body(t, 0, pos, vel, mass, force);
        self.accumulate_springs(pos, vel, force);
    }

    /// Adds the forces that act on each body alone (gravity, drag, quadratic drag,
    /// time-varying and central forces: all but the springs) on the chunk of bodies
    /// `start..start + force.len()`, whose positions are `pos`, velocities `vel` and
    /// masses `mass`.
    #[inline(always)]
    pub fn accumulate_per_body(
        &self,
        t: f64,
        start: usize,
        pos: &[DVec2],
        vel: &[DVec2],
        mass: Masses<'_>,
        force: &mut [DVec2],
    ) {
        for f in &self.gravity {
            f.accumulate(start, mass, force);
        }
        for f in &self.drag {
            f.accumulate(start, vel, force);
        }
        for f in &self.quadratic_drag {
            f.accumulate(start, vel, force);
        }
        for f in &self.time_varying {
            f.accumulate(t, start, force);
        }
        for f in &self.central {
            f.accumulate(start, pos, mass, force);
        }
    }

    /// Returns true when every force but the springs acts on every body of the chunk
    /// `start..start + len`, so that [`ForceSet::forces_on`] can sum them body by body.
    #[inline(always)]
    pub fn acts_on_whole_chunk(&self, start: usize, len: usize) -> bool {
        let whole = |s: &Selection| match s.within(start, len) {
            Within::Run(run) => run.start == 0 && run.end == len,
            Within::List(_) => false,
        };
        self.gravity.iter().all(|f| whole(&f.bodies))
            && self.drag.iter().all(|f| whole(&f.bodies))
            && self.quadratic_drag.iter().all(|f| whole(&f.bodies))
            && self.time_varying.iter().all(|f| whole(&f.bodies))
            && self.central.iter().all(|f| whole(&f.bodies))
    }

    /// Returns the forces on a chunk of bodies `start..start + len` of one mass `m` as
    /// F = G - k·v, when they are uniform gravity and at most one linear drag, each
    /// acting on the whole chunk (and nothing else but springs): then G, the gravity
    /// sum 0 + m·g₁ + m·g₂ + … that [`ForceSet::forces_on`] starts every body with, is
    /// one vector for the chunk, and a step's loop computes (G - k·v)·(1/m) with the
    /// very operations, and so the bits, of the general sum.
    #[inline(always)]
    pub fn uniform_linear(&self, m: f64, start: usize, len: usize) -> Option<(DVec2, Option<f64>)> {
        if !(self.quadratic_drag.is_empty()
            && self.time_varying.is_empty()
            && self.central.is_empty()
            && self.drag.len() <= 1
            && self.acts_on_whole_chunk(start, len))
        {
            return None;
        }
        let g = self
            .gravity
            .iter()
            .fold(DVec2::ZERO, |f, gravity| f + m * gravity.g);
        Some((g, self.drag.first().map(|d| d.k)))
    }

    /// Returns the net force of every force but the springs on `N` bodies with
    /// positions `r`, velocities `v` and masses `m`, each of which every force acts
    /// on, at time `t`.
    ///
    /// Each body's terms are added in the order of [`ForceSet::accumulate`] and with
    /// the same arithmetic, so the result is the same to the bit; working on a few
    /// bodies at once lets each family's loop run on vector registers.
    #[inline(always)]
    pub fn forces_on<const N: usize>(
        &self,
        t: f64,
        r: &[DVec2; N],
        v: &[DVec2; N],
        m: &[f64; N],
    ) -> [DVec2; N] {
        let mut f = [DVec2::ZERO; N];
        for g in &self.gravity {
            for j in 0..N {
                // F = m·g.
                f[j] += m[j] * g.g;
            }
        }
        for d in &self.drag {
            for j in 0..N {
                // F = -k·v.
                f[j] -= d.k * v[j];
            }
        }
        for q in &self.quadratic_drag {
            for j in 0..N {
                // F = -c·|v|·v.
                f[j] -= q.c * v[j].length() * v[j];
            }
        }
        for tv in &self.time_varying {
            // F(t) = f0 + f1·t.
            let f_t = tv.f0 + t * tv.f1;
            for fj in &mut f {
                *fj += f_t;
            }
        }
        for c in &self.central {
            for j in 0..N {
                let d = r[j] - c.centre;
                let r2 = d.length_squared();
                if r2 > 0.0 {
                    // F = -μ·m·(r - c)/|r - c|³, with 1/|r - c|³ = 1/(r²·√r²).
                    let inv_r3 = 1.0 / (r2 * r2.sqrt());
                    f[j] -= c.strength * m[j] * inv_r3 * d;
                }
            }
        }
        f
    }

    /// Adds every spring's force, in file order, to both its ends (whole arrays).
    #[inline(always)]
    pub fn accumulate_springs(&self, pos: &[DVec2], vel: &[DVec2], force: &mut [DVec2]) {
        for f in &self.springs {
            f.accumulate(pos, vel, force);
        }
    }

    /// Adds every spring's force, in file order, to both its ends, and the torque of
    /// each end that is off its body's centre of mass to that body (whole arrays;
    /// `spin` holds the angles and angular velocities). A spring between centres of
    /// mass adds what [`ForceSet::accumulate_springs`] adds.
    #[inline]
    pub fn accumulate_springs_rigid(
        &self,
        pos: &[DVec2],
        vel: &[DVec2],
        spin: (&[f64], &[f64]),
        force: &mut [DVec2],
        torque: &mut [f64],
    ) {
        for f in &self.springs {
            f.accumulate_rigid(pos, vel, spin, force, torque);
        }
    }

    /// Adds the torques that act on each body alone to `torque` (whole arrays), family
    /// by family in a fixed order, each in file order: constant torques, angular drag,
    /// then the torques of forces applied off the centre of mass. `centre` gives each
    /// body's centre of mass in body coordinates.
    #[inline]
    pub fn accumulate_torques(
        &self,
        t: f64,
        (angle, omega): (&[f64], &[f64]),
        centre: &[DVec2],
        torque: &mut [f64],
    ) {
        for f in &self.torque {
            f.accumulate(torque);
        }
        for f in &self.angular_drag {
            f.accumulate(omega, torque);
        }
        for f in &self.time_varying {
            f.accumulate_torque(t, angle, centre, torque);
        }
    }

    /// Returns the total potential energy of the forces at time `t`, or `None` when a
    /// force without a potential (drag, angular drag, time-varying force, constant
    /// torque, damped spring) is present. `angle` places springs' ends that are off the
    /// centres of mass.
    pub fn potential_energy(
        &self,
        _t: f64,
        pos: &[DVec2],
        angle: &[f64],
        mass: &[f64],
    ) -> Option<f64> {
        if !self.drag.is_empty()
            || !self.quadratic_drag.is_empty()
            || !self.time_varying.is_empty()
            || !self.torque.is_empty()
            || !self.angular_drag.is_empty()
        {
            return None;
        }
        let mut energy = 0.0;
        for f in &self.gravity {
            energy += f.potential_energy(pos, mass);
        }
        for f in &self.springs {
            energy += f.potential_energy(pos, angle)?;
        }
        for f in &self.central {
            energy += f.potential_energy(pos, mass);
        }
        Some(energy)
    }

    /// Returns the potential energy of the conservative parts of the forces (gravity,
    /// the elastic part of springs, central forces), or `None` when an energy source
    /// (a time-varying force or a constant torque) is present. Drag, angular drag and
    /// damping only ever remove energy, so without a source the kinetic plus this
    /// potential energy cannot grow in the exact dynamics: growth is the integrator's
    /// doing. `angle` places springs' ends that are off the centres of mass.
    pub fn conservative_potential(
        &self,
        pos: &[DVec2],
        angle: &[f64],
        mass: &[f64],
    ) -> Option<f64> {
        if !self.time_varying.is_empty() || !self.torque.is_empty() {
            return None;
        }
        let mut energy = 0.0;
        for f in &self.gravity {
            energy += f.potential_energy(pos, mass);
        }
        for f in &self.springs {
            energy += f.elastic_energy(pos, angle);
        }
        for f in &self.central {
            energy += f.potential_energy(pos, mass);
        }
        Some(energy)
    }
}
