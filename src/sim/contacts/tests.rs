//! The contact stages on states built by hand: what a step does to two bodies, and
//! what it refuses to leave behind.

use glam::DVec2;

use super::*;
use crate::sim::{IntegratorKind, Simulation, State, System};

/// Two discs of radius 0.5 and mass 1, at `ra` and `rb`, moving at `va` and `vb`.
fn two_discs(ra: DVec2, va: DVec2, rb: DVec2, vb: DVec2) -> (System, State, Contacts) {
    let system = System::rigid(
        vec![1.0, 1.0],
        vec![0.125, 0.125],
        vec![DVec2::ZERO; 2],
        &[],
    );
    let state = State::new(0.0, vec![ra, rb], vec![va, vb]);
    let contacts = Contacts::new(
        vec![Collider::disc(0, 0.5, 1.0), Collider::disc(1, 0.5, 1.0)],
        None,
    );
    (system, state, contacts)
}

/// Two discs closing at 4 m/s from 0.2 m apart, recording their impacts, and where a
/// step of 0.1 s of explicit Euler leaves them: 0.2 m into each other.
fn head_on() -> (System, State, Contacts, State) {
    let (system, start, mut contacts) = two_discs(
        DVec2::new(-0.6, 0.0),
        DVec2::new(2.0, 0.0),
        DVec2::new(0.6, 0.0),
        DVec2::new(-2.0, 0.0),
    );
    contacts.record(true);
    let mut end = start.clone();
    for i in 0..2 {
        end.pos[i] += 0.1 * start.vel[i];
    }
    (system, start, contacts, end)
}

#[test]
fn a_step_that_would_end_overlapping_is_turned_back_at_the_instant_of_touch() {
    // They would end 0.2 m into each other; they touch at λ = 0.5 and part again.
    let (system, start, mut contacts, mut end) = head_on();
    let changed = contacts
        .resolve(&system, &start, &mut end, 0.0, 0.1)
        .expect("no overlap is left");
    assert!(changed);
    let log = contacts.take_log();
    assert_eq!(log.len(), 1);
    assert_eq!(log[0].t, 0.05);
    // Equal masses, e = 1: they swap velocities, and spend the rest of the step parting.
    assert_eq!(end.vel[0], DVec2::new(-2.0, 0.0));
    assert_eq!(end.vel[1], DVec2::new(2.0, 0.0));
    assert!((end.pos[0].x - -0.6).abs() < 1e-15 && (end.pos[1].x - 0.6).abs() < 1e-15);
}

/// Returns how many times-of-impact searches `f` began on this thread, and its result.
fn searches<T>(f: impl FnOnce() -> T) -> (usize, T) {
    use super::toi::tests::SEARCHES;
    SEARCHES.with(|c| c.set(0));
    let out = f();
    (SEARCHES.with(|c| c.get()), out)
}

#[test]
fn a_struck_pair_is_searched_again_once_by_the_requery_of_its_second_body() {
    // The head-on pair: one search when the step begins, then after their impact
    // each body is requeried, and the pair is searched by the second body's requery
    // only (the first's would carry the second's old version).
    let (system, start, mut contacts, mut end) = head_on();
    let (count, changed) = searches(|| contacts.resolve(&system, &start, &mut end, 0.0, 0.1));
    assert!(changed.expect("no overlap is left"));
    assert_eq!(contacts.take_log().len(), 1);
    assert_eq!(count, 2);
}

#[test]
fn a_body_struck_against_a_static_one_searches_the_pair_again() {
    // A 1 × 0.5 box (collider 0) falling flat at 3 m/s onto a static floor (collider
    // 1, the later one) strikes it within the step. The floor is never requeried, so
    // the box's requery must search the pair itself: two searches, and after the
    // impact (e = 0.5, both bottom corners at once) the box rises at 1.5 m/s.
    let system = System::rigid(
        vec![2.0, 0.0],
        vec![2.0 * 1.25 / 12.0, 0.0],
        vec![DVec2::ZERO; 2],
        &[],
    );
    let mut start = State::new(
        0.0,
        vec![DVec2::new(0.3, 0.26), DVec2::new(0.0, -0.5)],
        vec![DVec2::new(0.0, -3.0), DVec2::ZERO],
    );
    start.angle = vec![0.0, 0.0];
    start.omega = vec![0.0, 0.0];
    let mut contacts = Contacts::new(
        vec![
            Collider::rectangle(0, 1.0, 0.5, 0.5).expect("a box"),
            Collider::rectangle(1, 4.0, 1.0, 0.5).expect("a box"),
        ],
        None,
    );
    contacts.record(true);
    let mut end = start.clone();
    end.pos[0] += 0.01 * start.vel[0];
    let (count, changed) = searches(|| contacts.resolve(&system, &start, &mut end, 0.0, 0.01));
    assert!(changed.expect("no overlap is left"));
    assert_eq!(contacts.take_log().len(), 1);
    assert_eq!(count, 2);
    assert!(
        (end.vel[0].y - 1.5).abs() < 1e-12,
        "rebound {}",
        end.vel[0].y
    );
}

#[test]
fn bodies_left_overlapping_deeper_than_the_tolerance_are_an_overlap() {
    // Already 0.1 m into each other and parting too slowly to leave it: nothing an
    // impulse should do, and the step must not pass it on.
    let (system, start, mut contacts) = two_discs(
        DVec2::new(-0.45, 0.0),
        DVec2::new(-0.01, 0.0),
        DVec2::new(0.45, 0.0),
        DVec2::new(0.01, 0.0),
    );
    let mut end = start.clone();
    for i in 0..2 {
        end.pos[i] += 0.1 * start.vel[i];
    }
    let Err(super::Stop::Overlap(o)) = contacts.resolve(&system, &start, &mut end, 0.0, 0.1) else {
        panic!("they overlap");
    };
    assert_eq!((o.a, o.b), (0, 1));
    assert!((o.depth - 0.098).abs() < 1e-12, "{}", o.depth);
    // Through a simulation, the overlap is a blow-up that names both bodies.
    let mut sim =
        Simulation::new(system, start, IntegratorKind::Euler, 0.1).with_contacts(Contacts::new(
            vec![Collider::disc(0, 0.5, 1.0), Collider::disc(1, 0.5, 1.0)],
            None,
        ));
    let b = sim.step().expect_err("an overlap");
    assert_eq!(b.quantity, crate::sim::OVERLAP);
    assert_eq!(b.overlap.map(|o| (o.a, o.b)), Some((0, 1)));
    assert!(b.to_string().contains("bodies #0 and #1 overlap"), "{b}");
}

#[test]
fn a_static_body_takes_no_impulse_and_a_flat_landing_no_spin() {
    // A 1 × 0.5 box falling flat at 3 m/s onto a static floor: both bottom corners
    // touch at once, so the impulse acts at the middle of its edge and it does not
    // turn; the floor does not move.
    let system = System::rigid(
        vec![0.0, 2.0],
        vec![0.0, 2.0 * 1.25 / 12.0],
        vec![DVec2::ZERO; 2],
        &[],
    );
    let mut start = State::new(
        0.0,
        vec![DVec2::new(0.0, -0.5), DVec2::new(0.3, 0.26)],
        vec![DVec2::ZERO, DVec2::new(0.0, -3.0)],
    );
    start.angle = vec![0.0, 0.0];
    let mut sim =
        Simulation::new(system, start, IntegratorKind::Euler, 0.01).with_contacts(Contacts::new(
            vec![
                Collider::rectangle(0, 4.0, 1.0, 0.5).expect("a box"),
                Collider::rectangle(1, 1.0, 0.5, 0.5).expect("a box"),
            ],
            None,
        ));
    sim.record_contacts(true);
    sim.run_steps(10).expect("no overlap");
    let log = sim.take_contact_events();
    assert_eq!(log.len(), 1, "{log:?}");
    let s = sim.state();
    assert_eq!(
        (s.pos[0], s.vel[0], s.omega[0]),
        (DVec2::new(0.0, -0.5), DVec2::ZERO, 0.0)
    );
    assert!(s.omega[1].abs() < 1e-12, "spin {}", s.omega[1]);
    assert!((s.vel[1].y - 1.5).abs() < 1e-12, "rebound {}", s.vel[1].y);
    assert!(
        (log[0].point.x - 0.3).abs() < 1e-12,
        "struck at {}",
        log[0].point
    );
}

#[test]
fn a_light_body_left_overlapping_beside_a_far_heavier_one_is_reported_squeezed() {
    // Colliders: a static floor (body 0), a 10 g pebble (1), a heavy block (2) and
    // another pebble (3); the pebble met the floor, the block and the other pebble.
    let colliders = vec![
        Collider::rectangle(0, 4.0, 1.0, 0.5).expect("a box"),
        Collider::disc(1, 0.05, 0.5),
        Collider::rectangle(2, 1.0, 0.5, 0.5).expect("a box"),
        Collider::disc(3, 0.05, 0.5),
    ];
    let pairs = [(0, 1), (1, 2), (1, 3)];
    let with_block = |mass: f64| {
        [0.0, 1.0 / 0.01, 1.0 / mass, 1.0 / 0.01].map(|m| response::Inverse {
            mass: m,
            inertia: 0.0,
        })
    };
    // 5 kg on 10 g: 500 times its mass, past SQUEEZE_RATIO (100), whichever order the
    // overlapping pair is named in.
    let q = squeeze::squeezed(0, 1, &colliders, &with_block(5.0), &pairs).expect("squeezed");
    assert_eq!((q.body, q.by), (1, 2));
    assert!((q.ratio - 500.0).abs() < 1e-4, "{}", q.ratio);
    assert_eq!(
        squeeze::squeezed(1, 0, &colliders, &with_block(5.0), &pairs),
        Some(q)
    );
    // 0.5 kg is 50 times the pebble's mass: an overlap then is not put down to it.
    assert_eq!(
        squeeze::squeezed(0, 1, &colliders, &with_block(0.5), &pairs),
        None
    );
    // Two pebbles: the first is the light one (equal masses), and the block it met
    // is the heaviest moving body; a static floor never counts as the heavier one.
    let q = squeeze::squeezed(1, 3, &colliders, &with_block(5.0), &pairs).expect("squeezed");
    assert_eq!((q.body, q.by), (1, 2));
    assert_eq!(
        squeeze::squeezed(0, 3, &colliders, &with_block(5.0), &[(0, 3)]),
        None
    );
}
