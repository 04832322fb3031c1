//! Collisions: bodies that touch exchange an impulse that sends their approach speed
//! back times the coefficient of restitution, at the instant they first touch, and no
//! body ever passes through another (the series' part 3).
//!
//! # The model
//!
//! The integrator first takes its step as if nothing collided. Within that step every
//! colliding body then moves along a *path* from its pose at the step's start to its pose
//! at the end: the centre of mass in a straight line, the angle at a constant rate, the
//! velocity and spin interpolated between their values at the two ends (`toi.rs`). For
//! explicit Euler the positions on the path are exactly Euler's: r(t + λ·h) = r + λ·h·v.
//!
//! The stages of a step, in `sweep.rs`, are:
//! 1. *broad phase* (`broad_phase.rs`): the pairs whose swept boxes overlap;
//! 2. *time of impact* (`toi.rs`): for each pair, the first step fraction λ at which
//!    the two touch while approaching, over the whole step, so that a disc at 1000 m/s
//!    is caught before a 1 cm wall;
//! 3. *events in time order*: the earliest impact is taken first. At its instant the
//!    *narrow phase* (`narrow_phase.rs`) gives the contact point and normal, and when
//!    the bodies approach (v_n < 0) the *response* (`response.rs`) applies the
//!    article's impulse. A struck body's path restarts there with its new velocity and
//!    spin, which also carry to the step's end: r(1) gains (1 - λ)·h·Δv and v(1) gains
//!    Δv. Its later impacts are searched again from λ;
//! 4. *resting contacts at the step's end*: pairs that touch (gap ≤ tolerance) and
//!    approach at the end of the step (a ball lying on the floor while gravity pulls
//!    it down) take their impulses at λ = 1, pair by pair in order, sweep after sweep,
//!    until no touching pair approaches;
//! 5. *the overlap check*: a pair left overlapping deeper than the tolerance stops the
//!    run (exit code 3) with both bodies, the time and the depth.
//!
//! Impacts at the same λ are taken in the order of the colliders' indices (body order),
//! and nothing depends on threads, so the outcome is the same on every run.
//!
//! Nothing persists from one step to the next: a step's contacts are found from its
//! start and end states alone, so checkpoints, `--resume` and shards need nothing
//! beyond the state.

mod broad_phase;
pub mod collider;
pub mod narrow_phase;
pub mod response;
pub mod solver;
mod sweep;
pub mod toi;

use glam::DVec2;

pub use collider::{convexity_problem, Collider, ColliderShape, PolygonProblem};
pub use narrow_phase::{Contact, Pose};

use response::Inverse;

/// Impacts in one step, per colliding body, past which the step stops searching for
/// more and leaves what is left to the resting contacts at its end and the overlap
/// check. Two bodies that stay in contact while they turn against each other (a box
/// rocking on another with e < 1) need a contact force for as long as they touch, which
/// impulses can only approach by ever more, ever smaller bounces: that is resting
/// contact, which a contact solver answers, not impacts. A violent scene meets about
/// one impact per body per step.
pub const IMPACTS_PER_BODY: usize = 8;

/// The default contact tolerance as a fraction of the smaller body's size (its least
/// width): two bodies closer than this count as touching.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// How contacts that touch without colliding rest (the resting-contact solver's
/// settings; see `solver.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resting {
    /// Bodies that approach at no more than this speed at a contact rest there: they
    /// take the solver's impulses, without bounce, and the collision log does not
    /// record them. Faster approaches are collisions, with the restitution law.
    pub speed: f64,
    /// How deep resting bodies may overlap before they are pushed apart, in world
    /// units; `None` for [`DEFAULT_SLOP`] times the smaller body's size.
    pub slop: Option<f64>,
    /// Sweeps of the resting-contact solver over every contact, each step.
    pub iterations: usize,
}

impl Default for Resting {
    fn default() -> Self {
        Resting {
            speed: 0.0,
            slop: None,
            iterations: DEFAULT_ITERATIONS,
        }
    }
}

/// The default slop as a fraction of the smaller body's size: resting bodies may
/// overlap by this much, as Box2D's linear slop lets them (0.5 cm for its metre-sized
/// bodies), so that a stack rests on contacts that stay touching from step to step.
pub const DEFAULT_SLOP: f64 = 1e-3;

/// The default sweeps of the resting-contact solver per step.
pub const DEFAULT_ITERATIONS: usize = 50;

/// One resting contact point's warm start: (collider i, collider j, the point's
/// features, P_n, P_t).
pub type WarmPoint = (u32, u32, u64, f64, f64);

/// One impulse, as the collision log records it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactEvent {
    /// When the impulse was applied.
    pub t: f64,
    /// Body a's index; the normal points from b to a, and `impulse` acts on a along it.
    pub a: usize,
    /// Body b's index.
    pub b: usize,
    /// The contact point.
    pub point: DVec2,
    /// The unit normal from b to a.
    pub normal: DVec2,
    /// v_n = (v_AP - v_BP)·n just before the impulse (negative: approaching).
    pub vn_before: f64,
    /// v_n just after; -e·vn_before to round-off.
    pub vn_after: f64,
    /// The impulse j applied to a along n (and -j to b).
    pub impulse: f64,
    /// The tangential (friction) impulse applied to a along t = n⊥ (and its opposite
    /// to b); |jt| ≤ μ·impulse.
    pub jt: f64,
}

/// Two bodies left overlapping deeper than the tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    pub a: usize,
    pub b: usize,
    /// How deep they overlap (positive).
    pub depth: f64,
    /// Whether the step met its budget of impacts (`IMPACTS_PER_BODY` per body) and
    /// stopped answering them: a crowd struck faster than impulses one pair at a time
    /// can settle, rather than a step too long for the contacts.
    pub crowded: bool,
}

/// The colliding bodies of a scene and the stages' reusable buffers.
pub struct Contacts {
    colliders: Vec<Collider>,
    /// An absolute tolerance for every pair, or `None` for DEFAULT_TOLERANCE times the
    /// smaller body's size.
    tolerance: Option<f64>,
    /// How contacts rest.
    resting: Resting,
    /// Whether impulses are recorded for the collision log.
    logging: bool,
    log: Vec<ContactEvent>,
    /// The impulses the resting contacts needed last step, which start this step's:
    /// part of the simulation's state (checkpoints carry it).
    warm: solver::WarmStart,
    scratch: sweep::Scratch,
}

impl Clone for Contacts {
    fn clone(&self) -> Self {
        Contacts {
            colliders: self.colliders.clone(),
            tolerance: self.tolerance,
            resting: self.resting,
            logging: self.logging,
            log: self.log.clone(),
            warm: self.warm.clone(),
            scratch: sweep::Scratch::default(),
        }
    }
}

impl std::fmt::Debug for Contacts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Contacts")
            .field("colliders", &self.colliders.len())
            .field("tolerance", &self.tolerance)
            .finish()
    }
}

impl Contacts {
    /// Returns the contacts of these colliders (at most one per body, in body order),
    /// with an absolute tolerance or the default relative one.
    pub fn new(colliders: Vec<Collider>, tolerance: Option<f64>) -> Self {
        debug_assert!(colliders.windows(2).all(|w| w[0].body < w[1].body));
        Contacts {
            colliders,
            tolerance,
            resting: Resting::default(),
            logging: false,
            log: Vec::new(),
            warm: solver::WarmStart::new(),
            scratch: sweep::Scratch::default(),
        }
    }

    /// Returns the contacts with these resting settings.
    pub fn with_resting(mut self, resting: Resting) -> Self {
        self.resting = resting;
        self
    }

    /// Returns the resting contacts' impulses of the last step (the warm start of the
    /// next), in a fixed order: (collider i, collider j, point's features, P_n, P_t).
    pub fn warm_start(&self) -> Vec<WarmPoint> {
        self.warm
            .iter()
            .map(|(&(i, j, id), &(pn, pt))| (i, j, id, pn, pt))
            .collect()
    }

    /// Restores the warm start that [`Contacts::warm_start`] returned.
    pub fn set_warm_start(&mut self, entries: &[WarmPoint]) {
        self.warm = entries
            .iter()
            .map(|&(i, j, id, pn, pt)| ((i, j, id), (pn, pt)))
            .collect();
    }

    /// Returns the resting settings.
    pub fn resting(&self) -> Resting {
        self.resting
    }

    /// Returns the colliders.
    pub fn colliders(&self) -> &[Collider] {
        &self.colliders
    }

    /// Makes every impulse from now on go to the log that [`Contacts::take_log`] empties.
    pub fn record(&mut self, on: bool) {
        self.logging = on;
    }

    /// Returns the impulses recorded since the last call, in the order they were
    /// applied, and empties the log.
    pub fn take_log(&mut self) -> Vec<ContactEvent> {
        std::mem::take(&mut self.log)
    }

    /// Returns the tolerance of the pair of colliders i and j: the scene's, or
    /// DEFAULT_TOLERANCE times the smaller one's size.
    pub fn tolerance(&self, i: usize, j: usize) -> f64 {
        self.tolerance.unwrap_or_else(|| {
            DEFAULT_TOLERANCE * self.colliders[i].size.min(self.colliders[j].size)
        })
    }

    /// Returns every pair of bodies that overlap by more than their tolerance at these
    /// positions and angles, in body order; pairs are found through the broad phase.
    /// `movable(i)` tells whether body i can move (two immovable bodies may overlap: a
    /// floor built of several boxes). The search stops at the first body by which
    /// `limit` overlaps are found (all of that body's are kept).
    pub fn overlaps(
        &mut self,
        pos: &[DVec2],
        angle: &[f64],
        movable: impl Fn(usize) -> bool,
        limit: usize,
    ) -> Vec<Overlap> {
        sweep::overlaps(self, pos, angle, movable, limit)
    }

    /// The margin every swept box is widened by: the body's own tolerance, so that two
    /// boxes meet whenever their bodies are within the pair's tolerance.
    fn margin(&self, i: usize) -> f64 {
        self.tolerance
            .unwrap_or(DEFAULT_TOLERANCE * self.colliders[i].size)
    }
}

/// Returns the inverse mass and inverse moment of inertia of a body whose mass and
/// inertia are given as inverses (0 for static bodies).
fn inverse(inv_mass: f64, inv_inertia: f64) -> Inverse {
    Inverse {
        mass: inv_mass,
        inertia: inv_inertia,
    }
}

#[cfg(test)]
mod tests;
