//! The time-of-impact search's tests: closed forms for discs, conservative
//! advancement, sampling and its halving, the resting bound, and polygons thrown at a
//! thin wall.

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

/// A 2 × 0.2 bar resting on a floor on its left corner, tilted by 0.05 rad, and
/// turning clockwise about its centre by 0.2 rad in the step: the left corner lifts,
/// so the pair touches and parts at λ = 0, and the right corner (about 0.1 above the
/// floor) comes down at some 0.2 per unit λ, far above the resting speed, and strikes
/// within the step. Returns the bar, the floor, their paths and the limits.
fn swinging_bar() -> (Collider, Collider, Path, Path, Limits) {
    let bar = Collider::rectangle(0, 2.0, 0.2, 1.0).expect("a box");
    let floor = Collider::rectangle(1, 6.0, 0.4, 1.0).expect("a box");
    let pf = moving(DVec2::new(0.0, -0.2), DVec2::ZERO);
    let mut pb = turning(DVec2::new(0.0, 0.2), 0.05, DVec2::ZERO, -0.2);
    place(&bar, &mut pb, &floor, &pf, -1e-5);
    let lim = Limits {
        tol: TOL,
        rest: REST,
    };
    (bar, floor, pb, pf, lim)
}

#[test]
fn a_resting_bar_that_swings_its_far_end_down_is_still_caught() {
    let (bar, floor, pb, pf, lim) = swinging_bar();
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
fn a_sampling_that_starts_a_hair_before_the_step_ends_finishes() {
    // The swinging bar, sampled from the largest f64 below 1: the
    // stride, (1 - λ)/16, is below the spacing of f64 there, so stepping by it never
    // left λ and the search never ended (a user's scene of spinning needles hung in
    // one step). The step's end is the only instant left, and it is tested once.
    let (bar, floor, pb, pf, lim) = swinging_bar();
    let from = 1.0 - f64::EPSILON / 2.0;
    assert!(from < 1.0 && from + (1.0 - from) / MIN_SAMPLES == from);
    HITS.with(|c| c.set(0));
    let found = sample(&bar, &pb, &floor, &pf, from, lim);
    assert_eq!(HITS.with(|c| c.get()), 1);
    // By the step's end the right corner has struck: that instant is the impact.
    assert_eq!(found, Some(1.0));
    // The same bar a metre above the floor: no instant is a hit, so only the step's
    // end ends the search.
    let high = turning(DVec2::new(0.0, 1.2), 0.05, DVec2::ZERO, -0.2);
    HITS.with(|c| c.set(0));
    assert_eq!(sample(&bar, &high, &floor, &pf, from, lim), None);
    assert_eq!(HITS.with(|c| c.get()), 1);
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
            .map(|k| radius * DVec2::from_angle(std::f64::consts::TAU * k as f64 / sides as f64))
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
