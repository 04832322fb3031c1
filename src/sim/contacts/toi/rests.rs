//! Whether a pair in contact that turns can meet no impact in the rest of a step: the
//! bound that lets a resting pair (a box rocking slowly on a floor, a disc rolling on
//! it) skip the time-of-impact search's sampling. Its own file because the bound's
//! geometry (where the contact can be, how fast its points can close, which normals it
//! can have) is one idea apart from the search that uses it (`toi.rs`).

use glam::DVec2;

use super::super::collider::{Collider, ColliderShape};
use super::super::narrow_phase::Pose;
use super::{Limits, Path};

/// Returns true when a and b, in contact at λ0 = `from` (their gap `gap` along the unit
/// normal n from b to a) and not approaching there, can meet no impact in the rest of
/// the step: wherever their contact moves, none of its points can close faster than
/// the resting speed along its normal. The pair then rests through the step, for the
/// solver, and needs no sampling.
///
/// *Where the contact can be.* A contact point p at λ is the middle of a point of A's
/// outline and one of B's no farther apart than the manifold's reach (2·tol) or the
/// overlap d(λ), so it lies within m = 2·tol + D of both bodies, D bounding d over the
/// rest of the step. Within m of A, p = r_a(λ) + q with |q| ≤ R = reach_a + m; within
/// m of B, n·p ≤ H_b(λ) + m, with H_b(λ) B's support along n (the largest n·x over B
/// at λ). So ζ = -n·q is at least n·r_a(λ) - H_b(λ) - m, which falls no faster than
/// -n·(Δr_a - Δr_b) + s_b per unit λ (s_b = |Δθ_b|·reach_b, or 0 for a disc, whose
/// turning leaves its outline where it is), and over the rest of the step
///
///   ζ ≥ z = n·r_a(λ0) - H_b(λ0) - m + (1 - λ0)·min(0, n·(Δr_a - Δr_b) - s_b).
///
/// The points of the disc |q| ≤ R with ζ ≥ z lie in the rectangle
/// max(z, -R) ≤ ζ ≤ R, |τ| ≤ c, where τ = t·q, t = n⊥, and c = √(R² - z²) for z > 0
/// (the half chord), or R.
///
/// *How fast it can close.* A body point's rate at p is u = Δr + Δθ·(p - r)⊥, so with
/// Ω = Δθ_a - Δθ_b and q⊥ = -ζ·t - τ·n the two bodies' points at p part at
///
///   w = u_a - u_b = W(λ) - Ω·ζ·t - Ω·τ·n,   W(λ) = Δr_a - Δr_b - Δθ_b·(r_a(λ) - r_b(λ))⊥,
///
/// where W(λ) - W(λ0) = -(λ - λ0)·Δθ_b·(Δr_a - Δr_b)⊥, at most e_W = (1 - λ0)·|Δθ_b|·
/// |Δr_a - Δr_b| long. Along n and t (|W·t - Ω·ζ| is convex in ζ: largest at an end):
///
///   |w·n| ≤ w_n = |W(λ0)·n| + |Ω|·c + e_W,
///   |w·t| ≤ w_t = max(|W(λ0)·t - Ω·z|, |W(λ0)·t - Ω·R|) + e_W,
///   |w|   ≤ max(|W(λ0) - Ω·z·t|, |W(λ0) - Ω·R·t|) + |Ω|·c + e_W.
///
/// The contact's normal n' closes it at -w·n' ≤ |w·n|·|n'·n| + |w·t|·|n'·t|, so at no
/// more than K = min(|w|'s bound, w_n + S·w_t), with S the largest |n'·t| a contact
/// normal can have (see [`normal_slant`]: a body sliding on a long floor keeps the
/// floor's normal, and its sliding does not count). When no normal can face away from
/// n (n'·n ≥ 0), only closing along n counts: -w·n' ≤ max(0, -w·n) + |w·t|·S, and
/// w_n = max(0, -W(λ0)·n + |Ω|·c + e_W) (a pair parting along n passes). The same
/// with a and b in each other's places (n → -n) gives another bound; when the smaller
/// of the two is at most the resting speed, no impact can happen. A disc rolling on a floor passes (its point
/// on the floor barely moves: Ω·ζ·t cancels W), and so does a body sliding or slowly
/// rocking on another; a box rocking fast enough to strike with a corner does not (c
/// reaches the corner).
///
/// *How deep the overlap can get.* The overlap deepens no faster than its two witness
/// points close along its normal, and those are contact points as above, d apart (so
/// their rates differ by at most μ·d, μ = min(|Δθ_a|, |Δθ_b|)): at most rest + μ·d per
/// unit λ while K ≤ rest. So
///
///   d(λ) ≤ D = (d(λ0) + (1 - λ0)·rest) / (1 - (1 - λ0)·μ),
///
/// which holds for as long as the region it assumes does, hence (by continuity) over
/// the whole step. As conservative advancement does, this takes a contact's points to
/// lie on or between the bodies' outlines, no farther apart than the overlap, and its
/// normal to be one along which they overlap no deeper than that.
#[allow(clippy::too_many_arguments)]
pub(super) fn rests(
    a: &Collider,
    pa: &Path,
    b: &Collider,
    pb: &Path,
    from: f64,
    n: DVec2,
    gap: f64,
    lim: Limits,
) -> bool {
    let rest = lim.rest;
    if rest <= 0.0 {
        return false;
    }
    let left = 1.0 - from;
    // 1 - (1 - λ0)·μ, kept well away from 0 (a pair turning a radian or more within
    // the step is sampled).
    let keep = 1.0 - left * pa.dangle.abs().min(pb.dangle.abs());
    if keep < 0.5 {
        return false;
    }
    // D = (d(λ0) + (1 - λ0)·rest)/(1 - (1 - λ0)·μ), and m = 2·tol + D.
    let deepest = ((-gap).max(0.0) + left * rest) / keep;
    let m = 2.0 * lim.tol + deepest;
    let (posa, posb) = (pa.pose(from), pb.pose(from));
    let slant = normal_slant(a, pa, &posa, b, pb, &posb, n, left, m);
    let k = rest_bound(a, pa, b, pb, from, n, m, slant)
        .min(rest_bound(b, pb, a, pa, from, -n, m, slant));
    // A margin far above round-off in K and in the rates it bounds.
    k * (1.0 + REST_MARGIN) <= rest
}

/// The relative margin by which [`rests`]'s bound must be below the resting speed.
const REST_MARGIN: f64 = 1e-6;

/// Returns K of [`rests`] with a's ball (radius reach_a + m) and b's support along n
/// (the unit normal from b to a): the fastest any contact point of the pair can close
/// along its normal in the rest of the step after `from`, given the normals' `slant`.
#[allow(clippy::too_many_arguments)]
fn rest_bound(
    a: &Collider,
    pa: &Path,
    b: &Collider,
    pb: &Path,
    from: f64,
    n: DVec2,
    m: f64,
    slant: Slant,
) -> f64 {
    let left = 1.0 - from;
    let (posa, posb) = (pa.pose(from), pb.pose(from));
    // R = reach_a + m.
    let radius = a.reach + m;
    // H_b(λ0) = max over B of n·x, and s_b = |Δθ_b|·reach_b (0 for a disc).
    let (support, s_b) = match &b.shape {
        ColliderShape::Disc { radius: rb } => (n.dot(posb.r) + rb, 0.0),
        ColliderShape::Convex { points, .. } => (
            points
                .iter()
                .map(|q| n.dot(posb.apply(*q)))
                .fold(f64::NEG_INFINITY, f64::max),
            pb.dangle.abs() * b.reach,
        ),
    };
    let dr = pa.dr - pb.dr;
    // z = n·r_a(λ0) - H_b(λ0) - m + (1 - λ0)·min(0, n·(Δr_a - Δr_b) - s_b), held to -R.
    let z = (n.dot(posa.r) - support - m + left * (n.dot(dr) - s_b).min(0.0)).max(-radius);
    // c = √(R² - z²) for z > 0, else R.
    let c = if z > 0.0 {
        (radius * radius - z * z).max(0.0).sqrt()
    } else {
        radius
    };
    let omega = pa.dangle - pb.dangle;
    // W(λ0) = Δr_a - Δr_b - Δθ_b·(r_a(λ0) - r_b(λ0))⊥, t = n⊥, and
    // e_W = (1 - λ0)·|Δθ_b|·|Δr_a - Δr_b|.
    let w = dr - pb.dangle * (posa.r - posb.r).perp();
    let t = n.perp();
    let e_w = left * pb.dangle.abs() * dr.length();
    // |w| ≤ max(|W - Ω·z·t|, |W - Ω·R·t|) + |Ω|·c + e_W.
    let whole = (w - omega * z * t)
        .length()
        .max((w - omega * radius * t).length())
        + omega.abs() * c
        + e_w;
    // w_n = |W·n| + |Ω|·c + e_W, or with every normal in front of the contact
    // (n'·n ≥ 0) only its closing part, max(0, -W·n + |Ω|·c + e_W); and
    // w_t = max(|W·t - Ω·z|, |W·t - Ω·R|) + e_W.
    let w_n = if slant.front {
        (-w.dot(n) + omega.abs() * c + e_w).max(0.0)
    } else {
        w.dot(n).abs() + omega.abs() * c + e_w
    };
    let wt = w.dot(t);
    let w_t = (wt - omega * z).abs().max((wt - omega * radius).abs()) + e_w;
    // K = min(|w|'s bound, w_n + S·w_t).
    whole.min(w_n + slant.across * w_t)
}

/// How far a contact's normal n' can turn from n in the rest of the step: |n'·t| ≤
/// `across` (S of [`rests`]), and n'·n ≥ 0 when `front`.
#[derive(Clone, Copy, Debug)]
struct Slant {
    across: f64,
    front: bool,
}

/// Returns the [`Slant`] of the normals the contact of a and b can have in the rest of
/// the step after λ0, as a and b overlap along them no deeper than `m` (2·tol + D).
///
/// Along a contact's normal n' the bodies overlap no deeper than m:
/// σ_λ(n') = min over A of n'·x - max over B of n'·y ≥ -m. For any point x of A and y
/// of B, σ_λ(n') ≤ n'·(x - y); with x and y the bodies' supports at λ0 along -g and g,
/// which move apart by no more than e = |Δr_a - Δr_b| + s_a + s_b per unit λ
/// (s = |Δθ|·|x - r|, 0 for a disc), every contact normal satisfies
/// n'·(x - y) ≥ -(m + (1 - λ0)·e): it lies on the arc of the unit circle around
/// ĝ = (x - y)/|x - y| where n'·ĝ ≥ κ = -(m + (1 - λ0)·e)/|x - y|, whose ends are
/// κ·ĝ ± √(1 - κ²)·ĝ⊥.
///
/// With g = (n ± t)/√2 (the corners of B's face beside the contact, and A's farthest
/// point from them), the largest ±n'·t on the arc is 1 when ±t lies on it and the
/// larger of its ends' otherwise; S is the larger of the two. With g = -n (A's far
/// side and B's), the arc leaves out a cap around -n: when it leaves out all of the
/// cap |n'·t| ≤ S, n'·(-n) < 0, the normals are in front. Where -n and ĝ are α apart,
/// the cap's nearest point to ĝ is max(0, α - β) from it, β = asin S.
#[allow(clippy::too_many_arguments)]
fn normal_slant(
    a: &Collider,
    pa: &Path,
    posa: &Pose,
    b: &Collider,
    pb: &Path,
    posb: &Pose,
    n: DVec2,
    left: f64,
    m: f64,
) -> Slant {
    let t = n.perp();
    let dr = (pa.dr - pb.dr).length();
    // ĝ and κ for the supports along -g (of A) and g (of B), or None for the whole
    // circle.
    let arc = |g: DVec2| {
        let (x, s_a) = support(a, pa, posa, -g);
        let (y, s_b) = support(b, pb, posb, g);
        let apart = x - y;
        let len = apart.length();
        // e = |Δr_a - Δr_b| + s_a + s_b, and κ = -(m + (1 - λ0)·e)/|x - y|.
        let kappa = -(m + left * (dr + s_a + s_b)) / len;
        (kappa > -1.0).then(|| (apart / len, kappa))
    };
    let side = |dir: DVec2| match arc(std::f64::consts::FRAC_1_SQRT_2 * (n + dir)) {
        Some((g, kappa)) if dir.dot(g) < kappa => {
            // The arc's ends κ·ĝ ± √(1 - κ²)·ĝ⊥.
            let across = (1.0 - kappa * kappa).sqrt() * g.perp();
            let ends = [kappa * g + across, kappa * g - across];
            ends[0].dot(dir).max(ends[1].dot(dir)).clamp(0.0, 1.0)
        }
        _ => 1.0,
    };
    let across = side(t).max(side(-t));
    let front = across < 1.0
        && arc(-n).is_some_and(|(g, kappa)| {
            // cos α = -n·ĝ, sin α = |n × ĝ|, cos β = √(1 - S²), sin β = S; the cap's
            // nearest point to ĝ is at cos(α - β) when α > β (cos α < cos β), and
            // it must be off the arc: cos(α - β) < κ.
            let (cos_a, sin_a) = (-n.dot(g), n.perp_dot(g).abs());
            let (cos_b, sin_b) = ((1.0 - across * across).sqrt(), across);
            cos_a < cos_b && cos_a * cos_b + sin_a * sin_b < kappa
        });
    Slant { across, front }
}

/// Returns a body's support point along `dir` at its pose (a point of its outline
/// farthest along dir) and how fast that point can move from where it is, per unit λ,
/// through the body's turning: |Δθ|·|x - r|, or 0 for a disc (any point on its circle
/// serves, and none moves through its turning).
fn support(c: &Collider, path: &Path, pose: &Pose, dir: DVec2) -> (DVec2, f64) {
    match &c.shape {
        ColliderShape::Disc { radius } => (pose.r + *radius * dir.normalize_or_zero(), 0.0),
        ColliderShape::Convex { points, .. } => {
            let mut best = pose.apply(points[0]);
            for q in &points[1..] {
                let x = pose.apply(*q);
                if x.dot(dir) > best.dot(dir) {
                    best = x;
                }
            }
            (best, path.dangle.abs() * (best - pose.r).length())
        }
    }
}
