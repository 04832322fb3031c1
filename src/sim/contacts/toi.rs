//! Time of impact: the first instant within a step at which two bodies moving along
//! their paths come into contact, searched over the whole step so that no body, however
//! fast, passes through another between the step's ends.
//!
//! Within a step every body moves along a *path*: its centre of mass in a straight line
//! and its angle at a constant rate, from its pose where the path starts (λ_s, the step
//! fraction at which the body was last struck, or 0) to its pose at the step's end
//! (λ = 1). For explicit Euler this is exact (r(t + λ·h) = r + λ·h·v); for the other
//! methods it is the chord of the step, which is as close to the true path as the
//! method's own step is to the solution.
//!
//! Two discs are a closed form: the root of a quadratic. Every other pair is found by
//! conservative advancement (Mirtich): at a gap d along the closest points' normal n,
//! no point of either body approaches the other faster than
//! u = max(0, -(Δr_a - Δr_b)·n) + |Δθ_a|·reach_a + |Δθ_b|·reach_b per unit λ, so the
//! bodies cannot touch before λ + (d - d*)/u; stepping there again and again reaches
//! contact from outside without ever passing it.
//!
//! A pair already in contact that turns (a box resting on a floor, a disc rolling on
//! it) cannot be advanced that way: it is either shown to rest through the step, when
//! no point of its contact, wherever the contact moves, can close faster than the
//! resting speed along the contact's normal (the bound of `rests`), or searched by
//! sampling the rest of the step.

use glam::DVec2;

mod rests;

use rests::rests;

use super::collider::{Collider, ColliderShape};
use super::narrow_phase::{contact, separation, Pose};
use super::response::closes;

/// A body's motion within a step: from λ_s on, r(λ) = r_s + (λ - λ_s)·Δr and
/// θ(λ) = θ_s + (λ - λ_s)·Δθ; its velocity and spin are interpolated the same way.
#[derive(Clone, Copy, Debug)]
pub struct Path {
    /// The step fraction λ_s where this path starts.
    pub lambda: f64,
    /// r_s, θ_s: the pose at λ_s.
    pub r: DVec2,
    pub angle: f64,
    /// Δr, Δθ: the change of pose per unit of λ.
    pub dr: DVec2,
    pub dangle: f64,
    /// v_s, ω_s: the velocity and spin at λ_s.
    pub v: DVec2,
    pub omega: f64,
    /// The change of velocity and spin per unit of λ.
    pub dv: DVec2,
    pub domega: f64,
}

impl Path {
    /// Returns the pose at step fraction λ ≥ λ_s.
    #[inline]
    pub fn pose(&self, lambda: f64) -> Pose {
        let s = lambda - self.lambda;
        Pose::new(self.r + s * self.dr, self.angle + s * self.dangle)
    }

    /// Returns the velocity and spin at step fraction λ ≥ λ_s.
    #[inline]
    pub fn velocity(&self, lambda: f64) -> (DVec2, f64) {
        let s = lambda - self.lambda;
        (self.v + s * self.dv, self.omega + s * self.domega)
    }

    /// Returns the rate, per unit λ, at which the body point at world position `p`
    /// moves along the path when the body's centre of mass is at `centre`:
    /// Δr + Δθ·(p - r)⊥.
    #[inline]
    pub fn point_rate(&self, centre: DVec2, p: DVec2) -> DVec2 {
        let arm = p - centre;
        self.dr + self.dangle * arm.perp()
    }
}

/// Returns the first step fraction λ in [from, 1] at which a and b, on their paths, come
/// within `tol` of touching while approaching faster than `rest` (the resting speed as
/// a closing rate per unit of λ: slower arrivals are the resting-contact solver's);
/// `None` when they do not within the step.
pub fn time_of_impact(
    a: &Collider,
    pa: &Path,
    b: &Collider,
    pb: &Path,
    from: f64,
    tol: f64,
    rest: f64,
) -> Option<f64> {
    #[cfg(test)]
    tests::SEARCHES.with(|c| c.set(c.get() + 1));
    if let (ColliderShape::Disc { radius: ra }, ColliderShape::Disc { radius: rb }) =
        (&a.shape, &b.shape)
    {
        return discs(pa, pb, ra + rb, from, rest);
    }
    // No point of the pair closes faster than |Δr_a - Δr_b| + |Δθ_a|·reach_a +
    // |Δθ_b|·reach_b per unit λ: when that is no faster than the resting speed, no
    // impact can happen (a stack at rest, whose contacts are the solver's).
    let bound = motion_bound(a, pa, b, pb);
    if rest > 0.0 && bound <= rest {
        return None;
    }
    advance(a, pa, b, pb, from, Limits { tol, rest })
}

/// Returns the fastest any point of a or b can move relative to the other along their
/// paths, per unit λ: |Δr_a - Δr_b| + |Δθ_a|·reach_a + |Δθ_b|·reach_b.
#[inline]
fn motion_bound(a: &Collider, pa: &Path, b: &Collider, pb: &Path) -> f64 {
    (pa.dr - pb.dr).length() + pa.dangle.abs() * a.reach + pb.dangle.abs() * b.reach
}

/// What counts as an impact: within `tol` of touching, closing faster than `rest`.
#[derive(Clone, Copy)]
struct Limits {
    tol: f64,
    rest: f64,
}

/// Two discs: with d(s) = d0 + s·Δd the vector between their centres s after `from`,
/// they touch where |d(s)|² = R², R the sum of the radii:
/// |Δd|²·s² + 2·(d0·Δd)·s + (|d0|² - R²) = 0, entering at the smaller root while
/// d0·Δd < 0 (approaching). Already touching or overlapping (|d0| ≤ R) and approaching
/// gives s = 0. An arrival whose closing rate d·Δd/|d| is not faster than `rest` is no
/// impact.
fn discs(pa: &Path, pb: &Path, sum: f64, from: f64, rest: f64) -> Option<f64> {
    let ra = pa.r + (from - pa.lambda) * pa.dr;
    let rb = pb.r + (from - pb.lambda) * pb.dr;
    let d0 = ra - rb;
    let dd = pa.dr - pb.dr;
    let b_half = d0.dot(dd);
    if b_half >= 0.0 {
        // Not approaching now; the distance between two points moving in straight
        // lines only grows once it grows.
        return None;
    }
    let a = dd.length_squared();
    let c = d0.length_squared() - sum * sum;
    // The closing rate at the distance |d|: d·Δd/|d|.
    let fast = |d: DVec2| rest == 0.0 || d.dot(dd) < -rest * d.length();
    if c <= 0.0 {
        return fast(d0).then_some(from);
    }
    // Roots s = (-b_half ∓ √(b_half² - a·c))/a; the smaller one, written as
    // c/(-b_half + √(b_half² - a·c)) so that no two close numbers are subtracted.
    let disc = b_half * b_half - a * c;
    if disc < 0.0 {
        return None;
    }
    let s = c / (-b_half + disc.sqrt());
    let lambda = from + s;
    (lambda <= 1.0 && fast(d0 + s * dd)).then_some(lambda)
}

/// Conservative advancement for every pair with a polygon (see the module's notes).
/// Contact is reached when the gap is at most tol/2, aiming at tol/4 so that each
/// advance makes progress; a pair that is in contact but not approaching there (sliding,
/// or parting) has no impact unless a body turns, since the gap between two convex
/// shapes moving without turning is a convex function of λ: once it stops falling it
/// never falls again.
///
/// Advancement is slow where the bodies close far more slowly than their spins could
/// make them: two turning bodies rocking against each other, or parting at one corner
/// while turning. After [`ADVANCES_BEFORE_SAMPLING`] advances, or at once when they
/// touch and part while turning (unless [`rests`] shows that no impact can come), the
/// search samples the rest of the step instead ([`sample`]).
fn advance(
    a: &Collider,
    pa: &Path,
    b: &Collider,
    pb: &Path,
    from: f64,
    lim: Limits,
) -> Option<f64> {
    let tol = lim.tol;
    let spin = pa.dangle.abs() * a.reach + pb.dangle.abs() * b.reach;
    let (aim, accept) = (0.25 * tol, 0.5 * tol);
    let mut lambda = from;
    for _ in 0..ADVANCES_BEFORE_SAMPLING {
        let (posa, posb) = (pa.pose(lambda), pb.pose(lambda));
        // GJK can fail to tell two polygons a hair apart from touching (parry's GJK
        // stalls and reports an intersection that its EPA then cannot measure). No
        // answer is not "no impact": the search samples on from here instead, where
        // the manifold and deeper overlaps answer.
        let Some(s) = separation(a, &posa, b, &posb) else {
            return sample(a, pa, b, pb, lambda, lim);
        };
        if s.gap <= accept {
            if approaching(a, pa, b, pb, lambda, lim) {
                return Some(lambda);
            }
            if spin == 0.0 || rests(a, pa, b, pb, lambda, s.normal, s.gap, lim) {
                return None;
            }
            return sample(a, pa, b, pb, lambda, lim);
        }
        // No point approaches faster than this along n, per unit λ.
        let closing = (-(pa.dr - pb.dr).dot(s.normal)).max(0.0) + spin;
        if closing <= 0.0 {
            return None;
        }
        lambda += (s.gap - aim) / closing;
        if lambda > 1.0 {
            return None;
        }
    }
    sample(a, pa, b, pb, lambda, lim)
}

/// Conservative advances before a search samples instead.
const ADVANCES_BEFORE_SAMPLING: usize = 64;

/// The most a body turns between two samples of [`sample`], in radians.
const SAMPLE_TURN: f64 = 0.02;

/// The fewest samples [`sample`] takes over what is left of a step.
const MIN_SAMPLES: f64 = 16.0;

/// The most samples [`sample`] takes over what is left of a step: 0.02 rad apart, a body
/// turning up to 82 rad in one step (20,000 rad/s at dt = 1/240 s) is sampled as finely
/// as any other. A body spun faster than that by a hostile or mistaken scene (10¹² rad/s
/// would mean 10¹³ samples, a search that never ends) is sampled this many times, more
/// coarsely, and a contact missed between samples is left to the end-of-step overlap
/// check, which stops the run with exit code 3.
const MAX_SAMPLES: f64 = 4096.0;

/// Returns true when a and b, in contact at λ, approach along their paths at any of
/// their contact points: where the gap's rate of change, (u_a - u_b)·n per unit λ,
/// is negative. An edge against an edge touches at two points, and a body rocking on
/// it approaches at one while it parts at the other; the closest points alone would
/// tell only one of them.
fn approaching(a: &Collider, pa: &Path, b: &Collider, pb: &Path, lambda: f64, lim: Limits) -> bool {
    let tol = lim.tol;
    let (posa, posb) = (pa.pose(lambda), pb.pose(lambda));
    let closing = |p: DVec2, n: DVec2| closing_at(pa, &posa, pb, &posb, p, n, lim.rest);
    match contact(a, &posa, b, &posb, 2.0 * tol, tol) {
        Some(c) => c.points().iter().any(|p| closing(*p, c.normal)),
        // Deeper than the manifold reaches: the closest points answer.
        None => separation(a, &posa, b, &posb).is_some_and(|s| closing(s.point, s.normal)),
    }
}

/// Returns true when the bodies' points at p, a at `posa` and b at `posb` on their
/// paths, close along n faster than `rest`: (u_a - u_b)·n < -rest, with u the
/// point's rate per unit λ, Δr + Δθ·(p - r)⊥ (see [`closes`] for round-off).
#[inline]
fn closing_at(
    pa: &Path,
    posa: &Pose,
    pb: &Path,
    posb: &Pose,
    p: DVec2,
    n: DVec2,
    rest: f64,
) -> bool {
    let (ua, ub) = (pa.point_rate(posa.r, p), pb.point_rate(posb.r, p));
    closes((ua - ub).dot(n), ua.length() + ub.length(), rest)
}

/// Finds the first impact after `from` by sampling the gap at steps over which neither
/// body turns more than [`SAMPLE_TURN`] (at least [`MIN_SAMPLES`] of them and at most
/// [`MAX_SAMPLES`]), then halving the first interval whose end is in contact until
/// the bodies' points cannot move more than a quarter of the tolerance across it: the
/// article's halving of the step, "until they are within a small tolerance of
/// touching". Its start is no impact and its end is one, so where the start was not
/// yet in contact (the gap above tol/2) the end's gap is between tol/4 and tol/2, as
/// conservative advancement's is; halving on to round-off (about 49 halvings where
/// `mixed-contacts-300` now takes about 14) found the contact at most a quarter of the
/// tolerance's motion earlier.
///
/// What this cannot see is a contact that opens and closes again between two samples
/// by less than the tolerance's worth of motion: two turning bodies that touch and part
/// again within 0.02 rad of turning. The end-of-step overlap check stands behind it.
fn sample(a: &Collider, pa: &Path, b: &Collider, pb: &Path, from: f64, lim: Limits) -> Option<f64> {
    #[cfg(test)]
    tests::SAMPLED.with(|c| c.set(c.get() + 1));
    let accept = 0.5 * lim.tol;
    let turn = pa.dangle.abs().max(pb.dangle.abs());
    let rest = 1.0 - from;
    let stride = if turn > 0.0 {
        (SAMPLE_TURN / turn)
            .min(rest / MIN_SAMPLES)
            .max(rest / MAX_SAMPLES)
    } else {
        rest / MIN_SAMPLES
    };
    // In contact (the gap at most tol/2), and approaching at one of the contact's
    // points. The manifold answers first: a pair at rest, whose points do not
    // approach, is then answered without the separation's GJK and EPA.
    let hit = |lambda: f64| {
        #[cfg(test)]
        tests::HITS.with(|c| c.set(c.get() + 1));
        let (posa, posb) = (pa.pose(lambda), pb.pose(lambda));
        let in_contact = || separation(a, &posa, b, &posb).is_some_and(|s| s.gap <= accept);
        match contact(a, &posa, b, &posb, 2.0 * lim.tol, lim.tol) {
            Some(c) => {
                c.points()
                    .iter()
                    .any(|p| closing_at(pa, &posa, pb, &posb, *p, c.normal, lim.rest))
                    && in_contact()
            }
            // Deeper than the manifold reaches, or apart: the closest points answer.
            None => separation(a, &posa, b, &posb).is_some_and(|s| {
                s.gap <= accept && closing_at(pa, &posa, pb, &posb, s.point, s.normal, lim.rest)
            }),
        }
    };
    // Across a bracket narrower than (tol/4)/motion_bound the gap changes by at most
    // tol/4.
    let fine = 0.25 * lim.tol / motion_bound(a, pa, b, pb);
    let mut prev = from;
    while prev < 1.0 {
        let next = (prev + stride).min(1.0);
        if hit(next) {
            // An instant after `prev` (which is not one) that is, within `fine` of
            // the first, by halving.
            let (mut lo, mut hi) = (prev, next);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if hi - lo <= fine || mid <= lo || mid >= hi {
                    break;
                }
                if hit(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        prev = next;
    }
    None
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::sim::contacts::narrow_phase::Contact;
    use std::cell::Cell;

    thread_local! {
        /// How many times this thread's searches fell through to [`sample`].
        pub(super) static SAMPLED: Cell<usize> = const { Cell::new(0) };
        /// How many instants this thread's samplings tested.
        pub(super) static HITS: Cell<usize> = const { Cell::new(0) };
        /// How many searches this thread began (`time_of_impact` calls).
        pub(in crate::sim::contacts) static SEARCHES: Cell<usize> = const { Cell::new(0) };
    }

    /// Returns how many times `f` made this thread's searches sample, and its result.
    fn sampling<T>(f: impl FnOnce() -> T) -> (usize, T) {
        SAMPLED.with(|c| c.set(0));
        let out = f();
        (SAMPLED.with(|c| c.get()), out)
    }

    /// The resting speed of dt = 1/240 s under 9.81 m/s² (3·|g|·dt), as a closing rate
    /// per unit of λ (times dt), and the tolerance of a body 0.1 across.
    const REST: f64 = 3.0 * 9.81 / 240.0 / 240.0;
    const TOL: f64 = 1e-7;

    fn turning(r: DVec2, angle: f64, dr: DVec2, dangle: f64) -> Path {
        Path {
            angle,
            dangle,
            omega: dangle,
            ..moving(r, dr)
        }
    }

    /// Moves a's path along the normal until a and b, at λ = 0, are `gap` apart
    /// (negative: overlapping), and returns the separation there.
    fn place(a: &Collider, pa: &mut Path, b: &Collider, pb: &Path, gap: f64) -> Contact {
        for _ in 0..4 {
            let s = separation(a, &pa.pose(0.0), b, &pb.pose(0.0)).expect("answers");
            pa.r += (gap - s.gap) * s.normal;
        }
        separation(a, &pa.pose(0.0), b, &pb.pose(0.0)).expect("answers")
    }

    /// Returns the first of `count` evenly spaced λ in (0, 1] at which a and b are in
    /// contact and approach faster than the resting speed: the impact, looked for far
    /// more finely than [`sample`] does.
    fn dense_impact(a: &Collider, pa: &Path, b: &Collider, pb: &Path, count: usize) -> Option<f64> {
        let lim = Limits {
            tol: TOL,
            rest: REST,
        };
        (1..=count)
            .map(|k| k as f64 / count as f64)
            .find(|&lambda| {
                separation(a, &pa.pose(lambda), b, &pb.pose(lambda))
                    .is_some_and(|s| s.gap <= 0.5 * TOL && approaching(a, pa, b, pb, lambda, lim))
            })
    }

    fn moving(r: DVec2, dr: DVec2) -> Path {
        Path {
            lambda: 0.0,
            r,
            angle: 0.0,
            dr,
            dangle: 0.0,
            v: dr,
            omega: 0.0,
            dv: DVec2::ZERO,
            domega: 0.0,
        }
    }

    #[test]
    fn discs_meet_where_the_distance_between_centres_is_the_sum_of_radii() {
        let a = Collider::disc(0, 1.0, 1.0);
        let b = Collider::disc(1, 1.0, 1.0);
        // Centres 10 apart closing at 16 per step: they touch when 8 apart, at λ = 0.5.
        let pa = moving(DVec2::new(10.0, 0.0), DVec2::new(-8.0, 0.0));
        let pb = moving(DVec2::ZERO, DVec2::new(8.0, 0.0));
        assert_eq!(time_of_impact(&a, &pa, &b, &pb, 0.0, 1e-6, 0.0), Some(0.5));
        // Parting discs never meet; nor do discs that pass at a distance.
        let away = moving(DVec2::new(10.0, 0.0), DVec2::new(8.0, 0.0));
        assert_eq!(time_of_impact(&a, &away, &b, &pb, 0.0, 1e-6, 0.0), None);
        let above = moving(DVec2::new(10.0, 3.0), DVec2::new(-8.0, 0.0));
        assert_eq!(time_of_impact(&a, &above, &b, &pb, 0.0, 1e-6, 0.0), None);
    }

    #[test]
    fn a_fast_disc_is_caught_before_it_crosses_a_thin_wall() {
        // A disc of radius 0.1 at 1000 m/s, dt = 0.01: 10 m a step, against a wall 1 cm
        // thick whose near face is 2 m ahead: it touches at λ = (2 - 0.1)/10 = 0.19.
        let disc = Collider::disc(0, 0.1, 1.0);
        let wall = Collider::rectangle(1, 0.01, 2.0, 1.0).expect("a box");
        let pd = moving(DVec2::ZERO, DVec2::new(10.0, 0.0));
        let pw = moving(DVec2::new(2.005, 0.0), DVec2::ZERO);
        let tol = 1e-6 * 0.01;
        let lambda = time_of_impact(&disc, &pd, &wall, &pw, 0.0, tol, 0.0).expect("caught");
        let gap = (2.0 - 0.1) - 10.0 * lambda;
        assert!(gap >= 0.0 && gap <= 0.5 * tol, "gap {gap} at λ = {lambda}");
    }

    #[test]
    fn a_turning_box_is_caught_when_its_corner_swings_down_onto_a_floor() {
        // A 2 × 0.2 bar above a floor, its centre fixed, turning from flat by a quarter
        // turn in one step: its end reaches down 1 and the floor is 0.5 below.
        let bar = Collider::rectangle(0, 2.0, 0.2, 1.0).expect("a box");
        let floor = Collider::rectangle(1, 10.0, 1.0, 1.0).expect("a box");
        let mut pb = moving(DVec2::ZERO, DVec2::ZERO);
        pb.dangle = std::f64::consts::FRAC_PI_2;
        let pf = moving(DVec2::new(0.0, -1.0), DVec2::ZERO);
        let tol = 1e-7;
        let lambda = time_of_impact(&bar, &pb, &floor, &pf, 0.0, tol, 0.0).expect("caught");
        let pose = pb.pose(lambda);
        let c = separation(&bar, &pose, &floor, &pf.pose(lambda)).expect("answers");
        assert!(
            c.gap >= 0.0 && c.gap <= 0.5 * tol,
            "gap {} at λ = {lambda}",
            c.gap
        );
    }

    #[test]
    fn a_body_spun_absurdly_fast_is_sampled_at_most_max_samples_times_a_search() {
        // The bar above turning 10¹² rad in one step, its centre 2 above a floor it can
        // never reach (its ends are 1 from its centre): conservative advancement creeps
        // by 0.5/10¹² a time, and then the search samples the rest of the step, 0.02
        // rad apart, which would be 5·10¹³ samples. It tests at most MAX_SAMPLES
        // instants, and finds nothing.
        let bar = Collider::rectangle(0, 2.0, 0.2, 1.0).expect("a box");
        let floor = Collider::rectangle(1, 10.0, 1.0, 1.0).expect("a box");
        let mut pb = moving(DVec2::ZERO, DVec2::ZERO);
        pb.dangle = 1e12;
        let pf = moving(DVec2::new(0.0, -2.0), DVec2::ZERO);
        HITS.with(|c| c.set(0));
        let found = time_of_impact(&bar, &pb, &floor, &pf, 0.0, 1e-7, 0.0);
        let hits = HITS.with(|c| c.get());
        assert_eq!(found, None);
        assert!(
            // (One more where the strides' round-off falls short of the step's end.)
            hits > 1000 && hits as f64 <= MAX_SAMPLES + 1.0,
            "{hits} instants tested in one search"
        );
    }

    #[test]
    fn a_box_sliding_and_slowly_rocking_on_a_floor_is_answered_without_sampling() {
        // A 0.24 × 0.16 box lying on a static floor, 1e-5 into it, sliding at eight
        // times the resting speed and turning so slowly that its corners move at a
        // third of it: the pair's whole bound |Δr| + |Δθ|·reach is above the resting
        // speed, so the search reaches the contact, and the rest of the step is
        // answered by `rests` alone.
        let boxed = Collider::rectangle(0, 0.24, 0.16, 1.0).expect("a box");
        let floor = Collider::rectangle(1, 6.0, 0.4, 1.0).expect("a box");
        let pf = moving(DVec2::new(0.0, -0.2), DVec2::ZERO);
        let spin = REST / (3.0 * boxed.reach);
        let mut pb = turning(DVec2::new(0.0, 0.1), 0.0, DVec2::new(8.0 * REST, 0.0), spin);
        place(&boxed, &mut pb, &floor, &pf, -1e-5);
        assert!(pb.dr.length() + spin * boxed.reach > REST);
        let (sampled, hit) = sampling(|| time_of_impact(&boxed, &pb, &floor, &pf, 0.0, TOL, REST));
        assert_eq!((sampled, hit), (0, None));
        // Sampling, which the search did before, answers the same.
        let lim = Limits {
            tol: TOL,
            rest: REST,
        };
        assert_eq!(sample(&boxed, &pb, &floor, &pf, 0.0, lim), None);
    }

    #[test]
    fn a_disc_rolling_on_a_floor_is_answered_without_sampling() {
        // A disc of radius 0.1 rolling without slipping at three times the resting
        // speed, 1e-5 into a static floor: its point on the floor barely moves.
        let disc = Collider::disc(0, 0.1, 1.0);
        let floor = Collider::rectangle(1, 6.0, 0.4, 1.0).expect("a box");
        let pf = moving(DVec2::new(0.0, -0.2), DVec2::ZERO);
        let v = 3.0 * REST;
        let mut pd = turning(DVec2::new(0.0, 0.1), 0.0, DVec2::new(v, 0.0), -v / 0.1);
        place(&disc, &mut pd, &floor, &pf, -1e-5);
        let (sampled, hit) = sampling(|| time_of_impact(&disc, &pd, &floor, &pf, 0.0, TOL, REST));
        assert_eq!((sampled, hit), (0, None));
    }

    #[test]
    fn a_resting_bar_that_swings_its_far_end_down_is_still_caught() {
        // A 2 × 0.2 bar resting on a floor on its left corner, tilted by 0.05 rad, and
        // turning clockwise about its centre by 0.2 rad in the step: the left corner
        // lifts, so the pair touches and parts at λ = 0, and the right corner (about
        // 0.1 above the floor) comes down at some 0.2 per unit λ, far above the
        // resting speed, and strikes within the step.
        let bar = Collider::rectangle(0, 2.0, 0.2, 1.0).expect("a box");
        let floor = Collider::rectangle(1, 6.0, 0.4, 1.0).expect("a box");
        let pf = moving(DVec2::new(0.0, -0.2), DVec2::ZERO);
        let mut pb = turning(DVec2::new(0.0, 0.2), 0.05, DVec2::ZERO, -0.2);
        place(&bar, &mut pb, &floor, &pf, -1e-5);
        let lim = Limits {
            tol: TOL,
            rest: REST,
        };
        let s = separation(&bar, &pb.pose(0.0), &floor, &pf.pose(0.0)).expect("answers");
        assert!(!rests(&bar, &pb, &floor, &pf, 0.0, s.normal, s.gap, lim));
        HITS.with(|c| c.set(0));
        let (sampled, hit) = sampling(|| time_of_impact(&bar, &pb, &floor, &pf, 0.0, TOL, REST));
        let lambda = hit.expect("caught");
        assert!(sampled > 0);
        // Sixteen samples 1/16 apart (the bar turns 0.2 rad, under SAMPLE_TURN a
        // stride), then halvings until the bar's points, at most 0.2·reach per unit λ,
        // cannot move TOL/4 across the bracket: log2((1/16)·0.2·reach/(TOL/4)), 19
        // halvings, where halving to round-off took 42 here.
        let halvings = ((1.0 / 16.0) * 0.2 * bar.reach / (0.25 * TOL))
            .log2()
            .ceil();
        let hits = HITS.with(|c| c.get());
        assert!(
            hits as f64 <= MIN_SAMPLES + halvings,
            "{hits} instants tested, {halvings} halvings"
        );
        // The right corner is down there, at the floor within the tolerance: no more
        // than TOL/2 from it, and no closer than TOL/4, as the halving stops.
        let c = separation(&bar, &pb.pose(lambda), &floor, &pf.pose(lambda)).expect("answers");
        assert!(
            c.gap <= 0.5 * TOL && c.gap >= 0.25 * TOL && c.point.x > 0.9,
            "gap {} at {:?}",
            c.gap,
            c.point
        );
        let first = dense_impact(&bar, &pb, &floor, &pf, 4000).expect("an impact");
        assert!(
            (lambda - first).abs() <= 1.0 / 4000.0,
            "λ {lambda} against {first}"
        );
    }

    #[test]
    fn a_fast_polygon_is_never_let_through_a_thin_wall() {
        // Octagons, pentagons and triangles of a user's scene, thrown at 0.6 to 1.3
        // m a step (150 to 300 m/s at dt = 1/240 s) and spinning, at a static wall
        // 0.05 wide: every one whose centre would cross the wall's middle within the
        // step touches it first, and the search must find that impact. GJK can take
        // two polygons a hair apart for touching and then measure nothing (parry's
        // GJK stalls, its EPA fails); before the search sampled on from there, it
        // took that for no impact and let 24 of these 2912 through.
        let regular = |sides: usize, radius: f64| {
            let points = (0..sides)
                .map(|k| {
                    radius * DVec2::from_angle(std::f64::consts::TAU * k as f64 / sides as f64)
                })
                .collect();
            Collider::polygon(0, points, 0.5).expect("a regular polygon")
        };
        let shapes = [regular(8, 0.1191), regular(5, 0.09), regular(3, 0.12)];
        let wall = Collider::rectangle(1, 0.05, 10.0, 0.5).expect("a box");
        let pw = moving(DVec2::new(6.0, 5.0), DVec2::ZERO);
        let mut x: u64 = 0x5DEE_CE66_D1CE_4E5B;
        let (mut missed, mut tried) = (Vec::new(), 0);
        for case in 0..3000 {
            let a = &shapes[case % 3];
            let u = |x: &mut u64, lo: f64, hi: f64| {
                lo + (hi - lo) * super::super::narrow_phase::workspace_tests::next(x)
            };
            let dr = DVec2::new(u(&mut x, 0.6, 1.3), u(&mut x, -0.05, 0.05));
            let start = DVec2::new(
                5.975 - a.reach - u(&mut x, 0.0, dr.x - a.reach),
                u(&mut x, 1.0, 9.0),
            );
            let pa = turning(start, u(&mut x, 0.0, 6.3), dr, u(&mut x, -0.2, 0.2));
            if start.x + dr.x <= 6.0 {
                continue;
            }
            tried += 1;
            let found = if case % 2 == 0 {
                time_of_impact(a, &pa, &wall, &pw, 0.0, TOL, REST)
            } else {
                time_of_impact(&wall, &pw, a, &pa, 0.0, TOL, REST)
            };
            match found {
                // Found before the centre reaches the wall's face.
                Some(lambda) => assert!(
                    pa.pose(lambda).r.x < 5.975,
                    "case {case}: struck at λ {lambda}, centre {:?}",
                    pa.pose(lambda).r
                ),
                None => missed.push(case),
            }
        }
        assert_eq!(tried, 2912, "the throws that cross the wall");
        assert!(missed.is_empty(), "let through: {missed:?}");
    }

    #[test]
    fn no_pair_that_rests_meets_an_impact_anywhere_in_the_step() {
        // Thousands of pairs in contact (1e-4 into each other to 1e-8 apart) with
        // shapes, angles, velocities and spins drawn around the resting speed: where
        // `rests` answers that no impact can happen, none is found at 2000 instants
        // of the step, however it turns. Some rest, and some meet impacts, so that
        // both answers are exercised.
        let shapes = [
            Collider::disc(0, 0.1, 1.0),
            Collider::rectangle(0, 0.24, 0.16, 1.0).expect("a box"),
            Collider::polygon(
                0,
                vec![
                    DVec2::new(-0.12, -0.08),
                    DVec2::new(0.12, -0.08),
                    DVec2::new(0.0, 0.13),
                ],
                1.0,
            )
            .expect("a triangle"),
            Collider::rectangle(0, 3.0, 0.2, 1.0).expect("a ramp"),
        ];
        let mut x: u64 = 0x2545_F491_4F6C_DD1D;
        let mut uniform = |lo: f64, hi: f64| {
            // SplitMix64.
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
        };
        let lim = Limits {
            tol: TOL,
            rest: REST,
        };
        let (mut rested, mut struck) = (0, 0);
        for case in 0..6000 {
            let a = &shapes[case % 3];
            let b = &shapes[(case / 3) % 4];
            let scale = |u: f64| u * REST * [0.3, 1.0, 3.0, 10.0][(case / 12) % 4];
            let spin = |u: f64| u * REST * [1.0, 3.0, 10.0, 30.0, 100.0][(case / 48) % 5];
            let static_b = case % 5 == 0;
            let pb = if static_b {
                turning(DVec2::ZERO, uniform(-0.5, 0.5), DVec2::ZERO, 0.0)
            } else {
                let (vx, vy, w) = (uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0));
                turning(
                    DVec2::ZERO,
                    uniform(-3.2, 3.2),
                    DVec2::new(scale(vx), scale(vy)),
                    spin(w) / b.reach,
                )
            };
            let dir = uniform(0.0, std::f64::consts::TAU);
            let (vx, vy, w) = (uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0));
            let mut pa = turning(
                (a.reach + b.reach) * DVec2::from_angle(dir),
                uniform(-3.2, 3.2),
                DVec2::new(scale(vx), scale(vy)),
                spin(w) / a.reach,
            );
            let s = place(a, &mut pa, b, &pb, uniform(-1e-4, 1e-8));
            if s.gap > 0.5 * TOL || approaching(a, &pa, b, &pb, 0.0, lim) {
                continue;
            }
            let impact = dense_impact(a, &pa, b, &pb, 2000);
            if rests(a, &pa, b, &pb, 0.0, s.normal, s.gap, lim) {
                rested += 1;
                assert_eq!(impact, None, "case {case}: {pa:?} against {pb:?}");
            } else if impact.is_some() {
                struck += 1;
            }
        }
        assert!(
            rested > 1000 && struck > 40,
            "{rested} rested, {struck} struck"
        );
    }
}
