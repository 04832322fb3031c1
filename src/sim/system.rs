//! The system of equations the integrators solve: masses, moments of inertia and
//! forces, and what they give for a state (forces, accelerations and torques; energy and
//! momentum are in `energy.rs`).
//!
//! Why this file is long (about 700 lines): its several ways of summing the forces (in
//! registers for a few bodies, chunk by chunk on threads, family by family) must give
//! the same bits, and they are kept side by side, with the test that checks it, so that
//! a change to one is seen beside the others.

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::DVec2;

use super::chunks::{for_each_chunk, CHUNK, PARALLEL_MIN};
use super::forces::{ForceSet, ForceSpec, Masses, LANES};
use super::state::Coords;

/// The masses of the bodies and the forces on them: everything needed to compute
/// accelerations from a state. Fixed for the length of a run.
#[derive(Debug)]
pub struct System {
    pub(super) mass: Vec<f64>,
    inv_mass: Vec<f64>,
    /// The mass every body has, when all are equal (and its inverse): then the hot
    /// loops read no mass array.
    uniform_mass: Option<(f64, f64)>,
    pub(super) forces: ForceSet,
    /// True when every force but the springs acts on every body, so that the forces
    /// can be summed a few bodies at a time in registers.
    whole: bool,
    /// True when some force other than a spring acts.
    per_body: bool,
    /// Left by a step that checked, as it wrote them, that the positions and
    /// velocities it wrote are finite: the address of those positions, or 0. The check
    /// after the step takes it instead of reading the whole state again
    /// ([`System::take_finite_step`]).
    finite_step: AtomicUsize,
    /// The bodies' moments of inertia and centres of mass in body coordinates, for a
    /// system built with [`System::rigid`].
    pub(super) rigid: Option<Rigid>,
    /// True when the angles and angular velocities are advanced: something can turn a
    /// body, or some body spins already. Otherwise every ω is zero and stays zero, every
    /// θ keeps its value, and the steps do no angular work at all.
    pub(super) spins: bool,
}

/// What the rotation of rigid bodies needs beyond their masses.
#[derive(Clone, Debug)]
pub(super) struct Rigid {
    /// Moments of inertia I about the centres of mass.
    pub(super) inertia: Vec<f64>,
    /// 1/I.
    inv_inertia: Vec<f64>,
    /// Each body's centre of mass c in its body coordinates.
    centre: Vec<DVec2>,
}

impl Clone for System {
    fn clone(&self) -> Self {
        System {
            mass: self.mass.clone(),
            inv_mass: self.inv_mass.clone(),
            uniform_mass: self.uniform_mass,
            forces: self.forces.clone(),
            whole: self.whole,
            per_body: self.per_body,
            // A record belongs to the state its step wrote, not to a copy.
            finite_step: AtomicUsize::new(0),
            rigid: self.rigid.clone(),
            spins: self.spins,
        }
    }
}

impl System {
    /// Builds a system of bodies that never turn from their masses and the validated
    /// force specifications, none of which may exert a torque (use [`System::rigid`]).
    ///
    /// Every mass must be finite and positive (the scene validator guarantees it), and
    /// every body index named by a force must be below `mass.len()`.
    pub fn new(mass: Vec<f64>, forces: &[ForceSpec]) -> Self {
        let system = Self::build(mass, forces, None);
        debug_assert!(!system.forces.has_torques(&vec![DVec2::ZERO; system.len()]));
        system
    }

    /// Builds a system of rigid bodies from their masses, their moments of inertia
    /// about their centres of mass, their centres of mass in body coordinates (the
    /// coordinates in which forces' `at` points and springs' anchors are given), and
    /// the validated force specifications.
    ///
    /// Every mass must be finite and positive, or zero for a static body (which no
    /// force moves: 1/M = 0 and 1/I = 0), and every moment of inertia finite and
    /// positive or zero; a body whose moment of inertia is zero (point masses all at
    /// one point) has 1/I taken as 0, and never turns: the scene validator refuses
    /// any torque on it.
    pub fn rigid(
        mass: Vec<f64>,
        inertia: Vec<f64>,
        centre: Vec<DVec2>,
        forces: &[ForceSpec],
    ) -> Self {
        debug_assert!(inertia.iter().all(|i| i.is_finite() && *i >= 0.0));
        debug_assert!(inertia.len() == mass.len() && centre.len() == mass.len());
        let inv_inertia = inertia
            .iter()
            .map(|&i| if i > 0.0 { 1.0 / i } else { 0.0 })
            .collect();
        let rigid = Rigid {
            inertia,
            inv_inertia,
            centre,
        };
        Self::build(mass, forces, Some(rigid))
    }

    fn build(mass: Vec<f64>, forces: &[ForceSpec], rigid: Option<Rigid>) -> Self {
        debug_assert!(mass.iter().all(|m| m.is_finite() && *m >= 0.0));
        // A mass of zero marks a static body: 1/M = 0, so no force moves it.
        let inv_mass: Vec<f64> = mass
            .iter()
            .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
            .collect();
        let uniform_mass = match mass.first() {
            Some(&m) if m > 0.0 && mass.iter().all(|x| x.to_bits() == m.to_bits()) => {
                Some((m, inv_mass[0]))
            }
            _ => None,
        };
        let forces = ForceSet::new(forces, mass.len(), rigid.as_ref().map(|r| &r.centre[..]));
        let whole = forces.acts_on_whole_chunk(0, mass.len());
        let per_body = forces.has_per_body();
        let spins = rigid
            .as_ref()
            .is_some_and(|r| forces.has_torque_sources(&r.centre));
        System {
            mass,
            inv_mass,
            uniform_mass,
            forces,
            whole,
            per_body,
            finite_step: AtomicUsize::new(0),
            rigid,
            spins,
        }
    }

    /// Returns true when a step advances the angles and angular velocities: when
    /// something can turn a body (a torque, a force or spring off a centre of mass), or
    /// after [`System::start_spinning`]. When false, every ω is zero and stays so.
    #[inline]
    pub fn spins(&self) -> bool {
        self.spins
    }

    /// Makes the steps advance the angles and angular velocities, as they must when
    /// some body spins already, or when collisions may set bodies spinning. A system
    /// built with [`System::new`] has no moments of inertia, and cannot spin.
    pub fn start_spinning(&mut self) {
        debug_assert!(self.rigid.is_some(), "a system without inertia cannot spin");
        self.spins = self.rigid.is_some();
    }

    /// Returns the moments of inertia, or `None` for a system built with [`System::new`].
    pub fn inertia(&self) -> Option<&[f64]> {
        self.rigid.as_ref().map(|r| &r.inertia[..])
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

    /// Returns 1/M of every body: 0 for a static body (mass 0), which nothing moves.
    pub fn inverse_masses(&self) -> &[f64] {
        &self.inv_mass
    }

    /// Returns 1/I of every body (0 for one that cannot turn, static bodies among
    /// them), or `None` for a system built with [`System::new`].
    pub fn inverse_inertia(&self) -> Option<&[f64]> {
        self.rigid.as_ref().map(|r| &r.inv_inertia[..])
    }

    /// Returns the mass every body has when all masses are equal (to the bit), and
    /// `None` when they differ or there is no body.
    pub fn uniform_mass(&self) -> Option<f64> {
        self.uniform_mass.map(|(m, _)| m)
    }

    /// Returns, for the chunk of bodies `start..start + len`, (G, k, 1/m) when every
    /// body has the mass m and the forces on the chunk are F = G - k·v (gravity and at
    /// most one linear drag on every body: [`ForceSet::uniform_linear`]); `k` is `None`
    /// without drag.
    #[inline(always)]
    pub fn uniform_linear(&self, start: usize, len: usize) -> Option<(DVec2, Option<f64>, f64)> {
        let (m, inv) = self.uniform_mass?;
        let (g, k) = self.forces.uniform_linear(m, start, len)?;
        Some((g, k, inv))
    }

    /// Returns the forces acting in this system.
    pub fn force_set(&self) -> &ForceSet {
        &self.forces
    }

    /// Returns true when each body's acceleration depends only on its own position and
    /// velocity and the time (no spring couples two bodies), so that a step can compute
    /// and apply accelerations chunk by chunk with [`System::accelerations_of`].
    pub fn is_per_body(&self) -> bool {
        !self.forces.has_springs()
    }

    /// Records whether the step that just wrote `pos` (and its velocities) found every
    /// value it wrote finite, as it wrote them.
    pub fn record_finite_step(&self, pos: &[DVec2], finite: bool) {
        let mark = if finite { pos.as_ptr() as usize } else { 0 };
        self.finite_step.store(mark, Ordering::Relaxed);
    }

    /// Returns true when the last step recorded that the positions `pos` and their
    /// velocities, which it wrote, are all finite; forgets the record either way, so it
    /// vouches for one check only. False means "not known", not "not finite".
    pub fn take_finite_step(&self, pos: &[DVec2]) -> bool {
        let mark = self.finite_step.swap(0, Ordering::Relaxed);
        mark != 0 && mark == pos.as_ptr() as usize
    }

    /// Returns the masses of every body, in the form the force loops read.
    fn masses_view(&self) -> Masses<'_> {
        match self.uniform_mass {
            Some((m, inv)) => Masses::Uniform { m, inv },
            None => Masses::PerBody {
                m: &self.mass,
                inv: &self.inv_mass,
            },
        }
    }

    /// Writes the net force on every body at time `t` into `force`.
    ///
    /// This is the sum F_T of Equation 11: every force on a body acts at its centre of
    /// mass, whatever point of the body it is applied to.
    pub fn net_forces(&self, t: f64, pos: &[DVec2], vel: &[DVec2], force: &mut [DVec2]) {
        self.forces_or_accelerations(t, pos, vel, force, false);
    }

    /// Writes the acceleration of every body's centre of mass at time `t` into `acc`.
    ///
    /// Equation 11, solved for the acceleration: a_CM = F_T / M.
    #[inline]
    pub fn accelerations(&self, t: f64, pos: &[DVec2], vel: &[DVec2], acc: &mut [DVec2]) {
        self.forces_or_accelerations(t, pos, vel, acc, true);
    }

    /// Writes the acceleration of every centre of mass into `acc` and, when the system
    /// spins, the angular acceleration of every body into `alpha`: the derivatives of
    /// the velocities and angular velocities at time `t` and coordinates `y`.
    ///
    /// a = F_T/M (Equation 11) and α = τ_T/I, with τ_T the net torque about the centre
    /// of mass. When the system does not spin this is [`System::accelerations`], and
    /// `alpha` and the angles are not touched. When it spins, the forces that act on
    /// each body alone are summed as there, then the springs add their forces and their
    /// ends' torques, then the pure torques and the torques of forces applied off the
    /// centre of mass are added; every force's sum on a body is the one
    /// [`System::accelerations`] computes, to the bit, wherever it acts.
    #[inline]
    pub fn derivatives(&self, t: f64, y: Coords<'_>, acc: &mut [DVec2], alpha: &mut [f64]) {
        if !self.spins {
            self.accelerations(t, y.pos, y.vel, acc);
            return;
        }
        self.forces_and_torques(t, y, acc, alpha);
        let masses = self.masses_view();
        for_each_chunk(acc, |start, out| {
            divide_by_mass(masses.chunk(start, out.len()), out)
        });
        if let Some(rigid) = &self.rigid {
            for (a, inv) in alpha.iter_mut().zip(&rigid.inv_inertia) {
                // α = τ·(1/I).
                *a *= *inv;
            }
        }
    }

    /// Writes the net force on every body into `force` and, when the system spins,
    /// the net torque about every centre of mass into `torque`, at time `t` and
    /// coordinates `y`.
    pub fn net_forces_and_torques(
        &self,
        t: f64,
        y: Coords<'_>,
        force: &mut [DVec2],
        torque: &mut [f64],
    ) {
        if !self.spins {
            self.net_forces(t, y.pos, y.vel, force);
            return;
        }
        self.forces_and_torques(t, y, force, torque);
    }

    /// The sums of [`System::net_forces_and_torques`] for a spinning system.
    fn forces_and_torques(&self, t: f64, y: Coords<'_>, force: &mut [DVec2], torque: &mut [f64]) {
        debug_assert_eq!(torque.len(), self.len());
        let Some(rigid) = &self.rigid else {
            return;
        };
        let masses = self.masses_view();
        let forces = &self.forces;
        for_each_chunk(force, |start, out| {
            let mass = masses.chunk(start, out.len());
            let range = start..start + out.len();
            out.fill(DVec2::ZERO);
            forces.accumulate_per_body(t, start, &y.pos[range.clone()], &y.vel[range], mass, out);
        });
        torque.fill(0.0);
        let spin = (y.angle, y.omega);
        forces.accumulate_springs_rigid(y.pos, y.vel, spin, force, torque);
        forces.accumulate_torques(t, spin, &rigid.centre, torque);
    }

    /// Writes the accelerations a = F_T/M (Equation 11) at time `t` of the chunk of
    /// bodies `start..start + acc.len()`, whose positions and velocities are `pos` and
    /// `vel`. Valid only when [`System::is_per_body`]; the result is the same, to the
    /// bit, as the chunk's part of [`System::accelerations`].
    #[inline(always)]
    pub fn accelerations_of(
        &self,
        t: f64,
        start: usize,
        pos: &[DVec2],
        vel: &[DVec2],
        acc: &mut [DVec2],
    ) {
        debug_assert!(self.is_per_body());
        debug_assert!(pos.len() == acc.len() && vel.len() == acc.len());
        let mass = self.masses_view().chunk(start, acc.len());
        acc.fill(DVec2::ZERO);
        self.forces
            .accumulate_per_body(t, start, pos, vel, mass, acc);
        divide_by_mass(mass, acc);
    }

    /// Calls `update(r, v, a)` for every body of the chunk `start..start + pos.len()`,
    /// in order, with its position, velocity and acceleration a = F/m (Equation 11)
    /// at time `t`: what an integrator that moves each body on its own needs, computed
    /// while the chunk is in cache. Every acceleration of a group of bodies is computed
    /// before `update` changes them, and each `update` may change only its own body.
    /// Valid only when [`System::is_per_body`]; the accelerations are, to the bit,
    /// those of [`System::accelerations`].
    #[inline(always)]
    pub fn for_each_acceleration(
        &self,
        t: f64,
        start: usize,
        pos: &mut [DVec2],
        vel: &mut [DVec2],
        update: impl FnMut(&mut DVec2, &mut DVec2, DVec2),
    ) {
        debug_assert!(self.is_per_body());
        debug_assert!(pos.len() == vel.len() && pos.len() <= CHUNK);
        let len = pos.len();
        if !self.forces.acts_on_whole_chunk(start, len) {
            self.for_each_acceleration_by_family(t, start, pos, vel, update);
            return;
        }
        // Every force acts on every body here: sum a few bodies at a time, in
        // registers, with the mass lookup chosen once for the chunk.
        match self.masses_view().chunk(start, len) {
            Masses::Uniform { m, inv } => {
                self.for_each_acceleration_in_lanes(t, pos, vel, |_| m, |_| inv, update)
            }
            Masses::PerBody { m, inv } => {
                self.for_each_acceleration_in_lanes(t, pos, vel, |i| m[i], |i| inv[i], update)
            }
        }
    }

    /// The body-by-body part of [`System::for_each_acceleration`], for a chunk where
    /// every force acts on every body; `m(i)` and `inv(i)` give body i's mass and 1/m.
    #[inline(always)]
    fn for_each_acceleration_in_lanes(
        &self,
        t: f64,
        pos: &mut [DVec2],
        vel: &mut [DVec2],
        m: impl Fn(usize) -> f64,
        inv: impl Fn(usize) -> f64,
        mut update: impl FnMut(&mut DVec2, &mut DVec2, DVec2),
    ) {
        let len = pos.len();
        let mut r_lanes = pos.chunks_exact_mut(LANES);
        let mut v_lanes = vel.chunks_exact_mut(LANES);
        for (k, (r, v)) in (&mut r_lanes).zip(&mut v_lanes).enumerate() {
            let i = k * LANES;
            let rr: [DVec2; LANES] = std::array::from_fn(|j| r[j]);
            let vv: [DVec2; LANES] = std::array::from_fn(|j| v[j]);
            let mm: [f64; LANES] = std::array::from_fn(|j| m(i + j));
            let f = self.forces.forces_on(t, &rr, &vv, &mm);
            for j in 0..LANES {
                // a = F·(1/m).
                update(&mut r[j], &mut v[j], f[j] * inv(i + j));
            }
        }
        let done = len - len % LANES;
        for (j, (r, v)) in r_lanes
            .into_remainder()
            .iter_mut()
            .zip(v_lanes.into_remainder())
            .enumerate()
        {
            let i = done + j;
            let f = self.forces.forces_on(t, &[*r], &[*v], &[m(i)]);
            // a = F·(1/m).
            update(r, v, f[0] * inv(i));
        }
    }

    /// The family-by-family part of [`System::for_each_acceleration`], for a chunk
    /// where some force acts on only part of it.
    #[inline(never)]
    fn for_each_acceleration_by_family(
        &self,
        t: f64,
        start: usize,
        pos: &mut [DVec2],
        vel: &mut [DVec2],
        mut update: impl FnMut(&mut DVec2, &mut DVec2, DVec2),
    ) {
        let mut buffer = [DVec2::ZERO; CHUNK];
        let acc = &mut buffer[..pos.len()];
        self.accelerations_of(t, start, pos, vel, acc);
        for ((r, v), a) in pos.iter_mut().zip(vel.iter_mut()).zip(acc.iter()) {
            update(r, v, *a);
        }
    }

    /// Computes forces, or accelerations when `divide`, chunk by chunk; chunks are
    /// split across threads for many bodies. Springs couple bodies, so they are added
    /// on one thread, in file order, after the forces that act on each body alone.
    #[inline]
    fn forces_or_accelerations(
        &self,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        out: &mut [DVec2],
        divide: bool,
    ) {
        debug_assert_eq!(pos.len(), self.len());
        debug_assert_eq!(vel.len(), self.len());
        debug_assert_eq!(out.len(), self.len());
        if self.whole && out.len() < PARALLEL_MIN {
            self.forces_in_lanes(t, pos, vel, out, divide);
        } else {
            self.forces_by_chunk(t, pos, vel, out, divide);
        }
    }

    /// The general form of [`System::forces_or_accelerations`]: family by family over
    /// chunks of bodies, on several threads for many bodies.
    #[inline(never)]
    fn forces_by_chunk(
        &self,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        out: &mut [DVec2],
        divide: bool,
    ) {
        let masses = self.masses_view();
        let per_body = |start: usize, out: &mut [DVec2]| {
            let mass = masses.chunk(start, out.len());
            let range = start..start + out.len();
            out.fill(DVec2::ZERO);
            self.forces
                .accumulate_per_body(t, start, &pos[range.clone()], &vel[range], mass, out);
        };
        if self.forces.has_springs() {
            for_each_chunk(out, per_body);
            self.forces.accumulate_springs(pos, vel, out);
            if divide {
                for_each_chunk(out, |start, out| {
                    divide_by_mass(masses.chunk(start, out.len()), out)
                });
            }
        } else {
            for_each_chunk(out, |start, out| {
                per_body(start, out);
                if divide {
                    divide_by_mass(masses.chunk(start, out.len()), out);
                }
            });
        }
    }

    /// The serial form of [`System::forces_or_accelerations`] for a system in which
    /// every force but the springs acts on every body: the per-body forces of a few
    /// bodies at a time are summed in registers ([`ForceSet::forces_on`]) and written
    /// once, with no pass to zero the buffer first, and without springs the division
    /// by mass happens in the same pass. This is what keeps the cost of a call low for
    /// a system of a few bodies, where an adaptive method spends its time; the sums
    /// and products are those of the chunked path, so the bits are too.
    #[inline(always)]
    fn forces_in_lanes(
        &self,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        out: &mut [DVec2],
        divide: bool,
    ) {
        let springs = self.forces.has_springs();
        if !self.per_body {
            // Only springs act (or nothing does): they add into zeros, and nothing else
            // needs a pass.
            for f in out.iter_mut() {
                *f = DVec2::ZERO;
            }
        } else {
            // Without springs the per-body sum is the whole force, and a = F·(1/m) can
            // be taken at once; with them, the division waits until they are added.
            self.per_body_forces(t, pos, vel, out, divide && !springs);
        }
        if springs {
            self.forces.accumulate_springs(pos, vel, out);
        }
        // Without springs any division was done in the pass above (or there is
        // nothing but zeros to divide).
        if divide && springs {
            divide_by_mass(self.masses_view(), out);
        }
    }

    /// Writes into `out` the per-body forces (all but the springs) on every body, or
    /// the accelerations F·(1/m) when `scale`. Kept out of line so that a system of
    /// springs alone, which skips it, calls no more code than it runs.
    #[inline(never)]
    fn per_body_forces(
        &self,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        out: &mut [DVec2],
        scale: bool,
    ) {
        match self.masses_view() {
            Masses::Uniform { m, inv } => {
                self.per_body_in_lanes(t, pos, vel, out, |_| m, |_| inv, scale)
            }
            Masses::PerBody { m, inv } => {
                self.per_body_in_lanes(t, pos, vel, out, |i| m[i], |i| inv[i], scale)
            }
        }
    }

    /// Writes into `out` the per-body forces (all but the springs) on every body, or
    /// the accelerations F·(1/m) when `scale`; `m(i)` and `inv(i)` give body i's mass
    /// and 1/m.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn per_body_in_lanes(
        &self,
        t: f64,
        pos: &[DVec2],
        vel: &[DVec2],
        out: &mut [DVec2],
        m: impl Fn(usize) -> f64,
        inv: impl Fn(usize) -> f64,
        scale: bool,
    ) {
        let n = out.len();
        let (pos, vel) = (&pos[..n], &vel[..n]);
        let mut o_lanes = out.chunks_exact_mut(LANES);
        for (k, o) in (&mut o_lanes).enumerate() {
            let i = k * LANES;
            let rr: [DVec2; LANES] = std::array::from_fn(|j| pos[i + j]);
            let vv: [DVec2; LANES] = std::array::from_fn(|j| vel[i + j]);
            let mm: [f64; LANES] = std::array::from_fn(|j| m(i + j));
            let f = self.forces.forces_on(t, &rr, &vv, &mm);
            for j in 0..LANES {
                // a = F·(1/m), or the force F itself.
                o[j] = if scale { f[j] * inv(i + j) } else { f[j] };
            }
        }
        let done = n - n % LANES;
        for (j, o) in o_lanes.into_remainder().iter_mut().enumerate() {
            let i = done + j;
            let f = self.forces.forces_on(t, &[pos[i]], &[vel[i]], &[m(i)]);
            // a = F·(1/m), or the force F itself.
            *o = if scale { f[0] * inv(i) } else { f[0] };
        }
    }
}

/// Divides each force of a chunk by its body's mass: a = F/m, as F·(1/m).
#[inline(always)]
fn divide_by_mass(mass: Masses<'_>, acc: &mut [DVec2]) {
    match mass {
        Masses::Uniform { inv, .. } => {
            for a in acc {
                // a = F·(1/m).
                *a *= inv;
            }
        }
        Masses::PerBody { inv, .. } => {
            for (a, inv_m) in acc.iter_mut().zip(inv) {
                // a = F·(1/m).
                *a *= *inv_m;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::forces::{Anchor, Selection};

    /// Every family, each acting on every body, plus springs between bodies and to a
    /// point: the case the register path ([`System::forces_in_lanes`]) serves.
    fn all_families(n: usize) -> Vec<ForceSpec> {
        vec![
            ForceSpec::Gravity {
                g: DVec2::new(0.0, -9.81),
                bodies: Selection::All,
            },
            ForceSpec::Drag {
                k: 0.3,
                bodies: Selection::All,
            },
            ForceSpec::QuadraticDrag {
                c: 0.07,
                bodies: Selection::All,
            },
            ForceSpec::TimeVarying {
                f0: DVec2::new(0.1, 0.2),
                f1: DVec2::new(2.0, -1.0),
                bodies: Selection::All,
                at: None,
            },
            ForceSpec::Spring {
                a: 0,
                b: Anchor::Body(n as u32 - 1),
                stiffness: 5.0,
                rest_length: 0.5,
                damping: 0.2,
                a_at: None,
                b_at: None,
            },
            ForceSpec::Central {
                centre: DVec2::new(0.3, -0.4),
                strength: 2.0,
                bodies: Selection::All,
            },
            ForceSpec::Spring {
                a: 1,
                b: Anchor::Point(DVec2::new(1.0, 1.0)),
                stiffness: 3.0,
                rest_length: 0.0,
                damping: 0.1,
                a_at: None,
                b_at: None,
            },
        ]
    }

    fn bodies(n: usize) -> (Vec<DVec2>, Vec<DVec2>) {
        (0..n)
            .map(|i| {
                let x = i as f64;
                (
                    DVec2::new(0.37 * x - 1.0, (0.91 * x).sin()),
                    DVec2::new((1.3 * x).cos(), 0.1 * x - 0.4),
                )
            })
            .unzip()
    }

    #[test]
    fn the_register_path_gives_the_bits_of_the_family_by_family_sum() {
        // 11 bodies: one group of LANES and a remainder; masses equal and unequal;
        // with every family, with springs only, and with per-body forces only.
        let n = 11;
        let (pos, vel) = bodies(n);
        let t = 0.7;
        let specs = all_families(n);
        let springs_only: Vec<ForceSpec> = specs
            .iter()
            .filter(|s| matches!(s, ForceSpec::Spring { .. }))
            .cloned()
            .collect();
        let no_springs: Vec<ForceSpec> = specs
            .iter()
            .filter(|s| !matches!(s, ForceSpec::Spring { .. }))
            .cloned()
            .collect();
        let unequal: Vec<f64> = (0..n).map(|i| 0.5 + 0.25 * i as f64).collect();
        for forces in [&specs, &springs_only, &no_springs] {
            for mass in [vec![2.0; n], unequal.clone()] {
                let system = System::new(mass.clone(), forces);
                assert!(system.whole);
                // The reference: every family added in the documented order into
                // zeros, then a = F·(1/m).
                let mut expected = vec![DVec2::ZERO; n];
                let masses = Masses::PerBody {
                    m: &mass,
                    inv: &system.inv_mass,
                };
                system
                    .forces
                    .accumulate(t, &pos, &vel, masses, &mut expected);
                let mut force = vec![DVec2::NAN; n];
                system.net_forces(t, &pos, &vel, &mut force);
                let mut acc = vec![DVec2::NAN; n];
                system.accelerations(t, &pos, &vel, &mut acc);
                for i in 0..n {
                    let bits = |v: DVec2| (v.x.to_bits(), v.y.to_bits());
                    assert_eq!(bits(force[i]), bits(expected[i]), "force on body {i}");
                    let a = expected[i] * (1.0 / mass[i]);
                    assert_eq!(bits(acc[i]), bits(a), "acceleration of body {i}");
                }
                assert!(acc.iter().filter(|a| **a != DVec2::ZERO).count() >= 3);
            }
        }
    }
}
