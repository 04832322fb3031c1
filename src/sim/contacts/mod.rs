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
//! With resting contact, two more stages follow (`solver.rs`, `sleep.rs`): the
//! resting contacts are solved together, and islands of bodies that have rested long
//! enough fall asleep. A sleeping body keeps its pose and stands still, as a static
//! body does, until something awake comes near it.
//!
//! Contacts are found afresh each step from its start and end states; what persists
//! besides the state is the resting contacts' warm start and each body's time at rest
//! (asleep or not), and checkpoints carry both, so `--resume` and shards give the
//! bytes of a single run.

mod box_features;
mod broad_phase;
pub mod collider;
mod gjk_epa;
pub mod narrow_phase;
mod overlaps;
mod relax;
pub mod response;
mod sleep;
pub mod solver;
mod squeeze;
mod sweep;
pub mod toi;
mod warm;

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

/// Candidate pairs in one step (pairs of bodies whose swept boxes overlap, found by
/// the broad phase and again for every struck body), per colliding body, past which
/// the step stops and the run with it ([`Unanswerable`]). A pile meets about 3 per
/// body, and a pour whose impacts ran out of their budget 90: each impact asks again
/// for the neighbours of two bodies, about ten. A body that crosses the whole scene in
/// one step meets every other body at each of its impacts, and without this budget a
/// hostile speed asks for gigabytes of pairs.
pub const PAIRS_PER_BODY: usize = 256;

/// Candidate pairs every step may meet whatever its number of bodies, so that a small
/// scene's impact cascade (`IMPACTS_PER_BODY` per body plus 1,000) is never cut short
/// by the budget of pairs.
pub const PAIRS_PER_STEP: usize = 65_536;

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
    /// When bodies at rest fall asleep (`sleep.rs`), or `None` for never.
    pub sleep: Option<Sleep>,
}

impl Default for Resting {
    fn default() -> Self {
        Resting {
            speed: 0.0,
            slop: None,
            iterations: DEFAULT_ITERATIONS,
            sleep: None,
        }
    }
}

/// When a body at rest falls asleep: once it and every body it rests on or under
/// (its island) have moved no faster than `speed` for `time`, and the island rests on
/// something that does not move (see `sleep.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sleep {
    /// The fastest any point of a body may move and still count as at rest:
    /// |v| + |ω|·reach ≤ speed.
    pub speed: f64,
    /// How long a whole island must stay at rest before it sleeps, in seconds.
    pub time: f64,
}

/// The default time an island must stay at rest before it sleeps (Box2D's).
pub const DEFAULT_SLEEP_TIME: f64 = 0.5;

/// The default sleep speed as a fraction of the resting speed: a tenth, which is
/// 0.3·|g|·dt with the default resting speed (1.2 cm/s at dt = 1/240 s under Earth's
/// gravity, near Box2D's 1 cm/s).
pub const DEFAULT_SLEEP_FRACTION: f64 = 0.1;

/// The default slop as a fraction of the smaller body's size: resting bodies may
/// overlap by this much, as Box2D's linear slop lets them (0.5 cm for its metre-sized
/// bodies), so that a stack rests on contacts that stay touching from step to step.
pub const DEFAULT_SLOP: f64 = 1e-3;

/// The default (and most) sweeps of the resting-contact solver per step; the sweeps
/// stop early once they converge, which a settled stack does in one. The 20-row
/// pyramid, awake for a minute, moves at most 2.3, 1.4, 1.0, 0.62 and 0.26 mm with 8,
/// 12, 16, 25 and 50 sweeps, all of it while it first settles; 1,000 poured discs
/// settle within the 4 s of `scenes/pour.toml` with 25 but not 16, which sets the
/// default.
pub const DEFAULT_ITERATIONS: usize = 25;

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
    /// The lighter of the two, when a far heavier moving body pressed on it.
    pub squeezed: Option<Squeezed>,
}

/// A light body pressed by a far heavier one against another: what an overlap it is
/// left in is put down to (see `squeeze.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Squeezed {
    /// The scene's index of the light body.
    pub body: u32,
    /// The heaviest moving body it could meet in the step, and how many times its
    /// mass that is (for a message: in 32 bits, so that a blow-up stays small).
    pub by: u32,
    pub ratio: f32,
}

/// A body whose contacts a step cannot answer, and why: the run stops there rather
/// than give a wrong answer or spend without bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unanswerable {
    /// The scene's index of the body.
    pub body: usize,
    pub why: Beyond,
}

/// Why a body's contacts cannot be answered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Beyond {
    /// Its position (or angle) is so large that neighbouring f64 values there lie
    /// further apart than its resting slop (`DEFAULT_SLOP` of its size, or
    /// `DEFAULT_SLOP` radians), the finest distance contacts are asked to keep:
    /// `coordinate` is the largest of |x|, |y| (or |angle| in radians, when `angle`)
    /// at the step's start or end.
    Precision {
        coordinate: f64,
        spacing: f64,
        angle: bool,
    },
    /// The step met more candidate pairs than its budget (`PAIRS_PER_BODY` per body
    /// plus `PAIRS_PER_STEP`): the body's path is the longest in the step,
    /// `distance` long, and the paths cross too many others.
    Pairs { distance: f64, budget: usize },
}

/// What stops a step's contacts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stop {
    /// Two bodies left overlapping deeper than allowed.
    Overlap(Overlap),
    /// A body whose contacts cannot be answered.
    Unanswerable(Unanswerable),
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
    /// Each collider's time at rest so far, or `ASLEEP`: part of the simulation's
    /// state (checkpoints carry it).
    still: Vec<f64>,
    /// The colliders that never sleep: those under a force that changes with time or
    /// tied by a spring to another body.
    restless: Vec<bool>,
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
            still: self.still.clone(),
            restless: self.restless.clone(),
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
        let n = colliders.len();
        Contacts {
            colliders,
            tolerance,
            resting: Resting::default(),
            logging: false,
            log: Vec::new(),
            warm: solver::WarmStart::new(),
            still: vec![0.0; n],
            restless: vec![false; n],
            scratch: sweep::Scratch::default(),
        }
    }

    /// Returns the contacts in which the bodies for which `restless(body)` is true never
    /// sleep.
    pub fn with_restless(mut self, restless: impl Fn(usize) -> bool) -> Self {
        self.restless = self.colliders.iter().map(|c| restless(c.body)).collect();
        self
    }

    /// Returns each collider's time at rest, in collider order, with
    /// `f64::INFINITY` for a collider asleep: the sleep state a checkpoint records.
    pub fn sleep_state(&self) -> &[f64] {
        &self.still
    }

    /// Restores the sleep state that [`Contacts::sleep_state`] returned; an empty or
    /// mismatched list wakes everything.
    pub fn set_sleep_state(&mut self, still: &[f64]) {
        if still.len() == self.still.len() {
            self.still.copy_from_slice(still);
        } else {
            self.still.fill(0.0);
        }
    }

    /// Returns whether a step can only hold every body where it is, without a look at
    /// the bodies' motion: sleeping is on, every one of the system's `bodies` collides,
    /// and each is asleep or immovable (`Contacts::all_held`). Then
    /// [`Contacts::resolve`] would hold the sleeping bodies after the integrator moved
    /// them and find nothing else to do, so the simulation may skip the integrator as
    /// well and call [`Contacts::hold_still`] instead, with the same bits.
    pub fn holds_everything(
        &self,
        bodies: usize,
        inv_mass: &[f64],
        inv_inertia: Option<&[f64]>,
    ) -> bool {
        self.colliders.len() >= 2
            && self.colliders.len() == bodies
            && self.all_held(inv_mass, inv_inertia)
    }

    /// Returns whether sleeping is on and every collider is asleep or immovable
    /// (`inv_mass` and `inv_inertia` zero; the latter is `None` when the system does
    /// not spin): a scene at rest, in which nothing can touch or wake anything.
    pub(crate) fn all_held(&self, inv_mass: &[f64], inv_inertia: Option<&[f64]>) -> bool {
        self.resting.sleep.is_some()
            && self.colliders.iter().zip(&self.still).all(|(c, &t)| {
                t == sleep::ASLEEP
                    || (inv_mass[c.body] == 0.0 && inv_inertia.is_none_or(|ii| ii[c.body] == 0.0))
            })
    }

    /// A step in which every body is held ([`Contacts::holds_everything`]): what
    /// [`Contacts::resolve`] does then besides holding the bodies, which is to forget
    /// the warm start (no contact is solved).
    pub fn hold_still(&mut self) {
        self.warm.clear();
    }

    /// Returns whether the body of collider k is asleep.
    pub fn is_asleep(&self, k: usize) -> bool {
        self.still[k] == sleep::ASLEEP
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
        overlaps::overlaps(self, pos, angle, movable, limit)
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
