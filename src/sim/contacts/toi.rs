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
        // A search that starts a hair before the step's end has a stride below the
        // spacing of f64 there, and prev + stride would stay prev for ever: the step's
        // end is then the next instant.
        let next = if prev + stride > prev {
            (prev + stride).min(1.0)
        } else {
            1.0
        };
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
pub(super) mod tests;
