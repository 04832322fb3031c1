//! physframes against Rapier (`rapier2d-f64`), the Rust 2-D engine people use, on the
//! same scenes: the 20-row pyramid of `scenes/pyramid.toml` (210 boxes 1 m square on a
//! static floor, μ = 0.6, e = 0) and a pile of 2,000 discs in a bucket
//! (`benches/rapier/pile-2000.toml`: like `scenes/pour.toml` with twice the discs,
//! μ = 0.4, e = 0.2). Both scenes step at dt = 1/240 s under g = 9.81 m/s² down.
//!
//! Both engines are built from one `Scene` that physframes' own parser read from the
//! TOML text, so they start from the same bodies, positions, velocities, masses, moments
//! of inertia, friction and restitution (see `engines.rs` for what stays Rapier's own).
//! Both step on one thread: Rapier is built without its `parallel` feature, and our
//! per-body loops split across threads only from 65,536 bodies.
//!
//! # The solver's budget
//!
//! The two solvers are not the same algorithm, so "the same budget" can only mean the
//! same number of sweeps over every contact in a step:
//!
//! - physframes solves resting contacts with sequential impulses (Box2D v2.4's solver):
//!   once per step, up to 25 sweeps of friction and normal impulses, warm started,
//!   stopping early once a sweep changes no impulse by more than 1e-9 of the largest,
//!   then 3 passes that push apart (without turning) what overlaps by more than the
//!   slop;
//! - Rapier solves soft constraints by substepping (TGS-soft, as Box2D v3): each of its
//!   `num_solver_iterations` substeps makes one biased sweep
//!   (`num_internal_pgs_iterations` = 1), moves the bodies, and makes one unbiased sweep
//!   (`num_internal_stabilization_iterations` = 1). Its default is 4 substeps, 8
//!   sweeps a step.
//!
//! The bench runs Rapier twice: with its default (4 substeps, 8 sweeps), and with 13
//! substeps, 26 sweeps a step, at least as many as our solver's most (25). Rapier makes all of its
//! sweeps; ours stops when converged.
//!
//! # What it prints
//!
//! For each scene, each engine's time per step, measured in the same run in lockstep
//! (one step of each engine in turn, the engine that goes first changing every round,
//! so that the load of a shared machine falls on all alike), as the median and the mean
//! of many single steps; the ratio of our median to each of Rapier's; and
//!
//! - for the pyramid: whether it still stands after 10 s (2,400 steps), by the test of
//!   `tests/integration/resting.rs` (every box within 1% of its size of where it
//!   started, turned less than 0.01 rad), with the largest displacement and turn; and
//!   the largest displacement and turn from 1 s to 10 s, which tell a pyramid that
//!   settles into its contacts in the first second and then holds still from one that
//!   keeps moving. The times are of all 2,400 steps;
//! - for the pile: 2 s (480 steps) of settling, untimed, then 480 timed steps of the
//!   resting pile; the most discs seen outside the bucket after any step of the 4 s;
//!   the deepest overlap of two discs or of a disc and a wall after any step, and at
//!   4 s; and the highest disc's height at 4 s, which tells how far the pile has sunk
//!   into itself;
//! - for `scenes/bench/pile-10000.toml` (10,000 discs dropped into a bucket, issue 15's
//!   frame-rate target): all of its 480 steps from the start, in physframes and in
//!   Rapier's default, both sleeping, and the frame rate each one's mean step allows
//!   the render (8 steps a frame) before anything is drawn. No criterion timing
//!   follows this one.
//!
//! Criterion then times each engine's step again, going on from where the lockstep
//! runs left each world (a standing or fallen pyramid, a resting pile), under the names
//! `pyramid/physframes`, `pyramid/rapier-4-substeps`, `pyramid/rapier-13-substeps` and
//! the same for `pile`; its estimates are in
//! `target/criterion/<scene>/<engine>/new/estimates.json`.
//!
//! Run with `cargo bench --bench rapier`; the summary of each scene follows its
//! criterion timings.

mod checks;
mod engines;

use std::path::Path;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use physframes::scene::{parse, Scene};

use checks::{drift, Bucket, PileWorst};
use engines::{Engine, Physframes, Pose, Rapier};

/// Rapier's default substeps, and the substeps that make its sweeps our most.
const RAPIER_DEFAULT: usize = 4;
const RAPIER_EQUAL: usize = 13;

/// Steps at dt = 1/240 s: 10 s of the pyramid, of which the first second is its
/// settling; 2 s of the pile settling and 2 s timed.
const PYRAMID_STEPS: usize = 2400;
const PYRAMID_SETTLE: usize = 240;
const PILE_SETTLE: usize = 480;
const PILE_STEPS: usize = 480;

/// The pile's discs' radius, as `pile-2000.toml` gives it.
const RADIUS: f64 = 0.06;

/// One engine of the comparison.
struct Entry {
    /// Its name in criterion's output and in the summary.
    id: String,
    /// What its solver does each step.
    budget: &'static str,
    engine: Box<dyn Engine>,
    /// The index of the physframes entry its time is compared with.
    ours: usize,
    /// Its step times in seconds, from the lockstep run.
    times: Vec<f64>,
}

/// Returns physframes and Rapier at both budgets with bodies that never sleep, then
/// physframes and Rapier's default with sleeping on, each built from `scene`.
fn entries(scene: &Scene) -> Vec<Entry> {
    let entry = |id: String, budget, engine: Box<dyn Engine>, ours| Entry {
        id,
        budget,
        engine,
        ours,
        times: Vec::new(),
    };
    vec![
        entry(
            "physframes".into(),
            "up to 25 sweeps, early exit",
            Box::new(Physframes::new(scene, false)),
            0,
        ),
        entry(
            format!("rapier-{RAPIER_DEFAULT}-substeps"),
            "8 sweeps (Rapier's default)",
            Box::new(Rapier::new(scene, RAPIER_DEFAULT, false)),
            0,
        ),
        entry(
            format!("rapier-{RAPIER_EQUAL}-substeps"),
            "26 sweeps (equal budget)",
            Box::new(Rapier::new(scene, RAPIER_EQUAL, false)),
            0,
        ),
        entry(
            "physframes-sleeping".into(),
            "as above, bodies sleep",
            Box::new(Physframes::new(scene, true)),
            3,
        ),
        entry(
            format!("rapier-{RAPIER_DEFAULT}-substeps-sleeping"),
            "8 sweeps, bodies sleep",
            Box::new(Rapier::new(scene, RAPIER_DEFAULT, true)),
            3,
        ),
    ]
}

/// Parses a scene's text with physframes' own parser, as if read from `path`.
fn scene(path: &str, text: &str) -> Scene {
    parse(Path::new(path), text).unwrap_or_else(|e| panic!("{path} is a valid scene:\n{e}"))
}

/// What looks at an engine's bodies after a step: the engine's index and its poses.
type Look<'a> = &'a mut dyn FnMut(usize, &[Pose]);

/// Steps every engine `steps` times in lockstep: one step of each in turn, each round
/// starting one engine further on. When `timed`, each step's wall time is added to its
/// engine's `times`. `look` sees each engine's index and poses after each of its steps,
/// outside the times.
fn lockstep(entries: &mut [Entry], steps: usize, timed: bool, mut look: Option<Look<'_>>) {
    let n = entries.len();
    for round in 0..steps {
        for k in 0..n {
            let i = (round + k) % n;
            let e = &mut entries[i];
            let start = Instant::now();
            e.engine.step();
            let took = start.elapsed().as_secs_f64();
            if timed {
                e.times.push(took);
            }
            if let Some(look) = look.as_mut() {
                look(i, &e.engine.poses());
            }
        }
    }
}

/// Returns the median and the mean of `times`.
fn median_mean(times: &[f64]) -> (f64, f64) {
    let mut sorted = times.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let n = sorted.len();
    let median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    };
    (median, times.iter().sum::<f64>() / n as f64)
}

/// Prints each engine's median and mean step time, and the ratio of our median (asleep
/// or never) to each of Rapier's, then `verdict` of each engine.
fn print_times(entries: &[Entry], verdict: impl Fn(usize) -> String) {
    for (i, e) in entries.iter().enumerate() {
        let (median, mean) = median_mean(&e.times);
        let ratio = if e.ours == i {
            String::new()
        } else {
            let ours = median_mean(&entries[e.ours].times).0;
            format!(", {}/this {:.2}", entries[e.ours].id, ours / median)
        };
        println!(
            "  {:<34} {:<28} median {:>8.1} µs/step, mean {:>8.1}{ratio}; {}",
            e.id,
            e.budget,
            median * 1e6,
            mean * 1e6,
            verdict(i),
        );
    }
}

/// Times each engine's step under criterion, going on from where each one is.
fn criterion_steps(c: &mut Criterion, group: &str, entries: &mut [Entry]) {
    let mut g = c.benchmark_group(group);
    for e in entries.iter_mut() {
        let engine = &mut e.engine;
        g.bench_function(e.id.as_str(), |b| b.iter(|| engine.step()));
    }
    g.finish();
}

fn pyramid(c: &mut Criterion) {
    let scene = scene(
        "scenes/pyramid.toml",
        include_str!("../../scenes/pyramid.toml"),
    );
    let mut entries = entries(&scene);
    let start: Vec<_> = entries.iter().map(|e| e.engine.poses()).collect();
    eprintln!("pyramid: stepping each engine 10 s in lockstep…");
    lockstep(&mut entries, PYRAMID_SETTLE, true, None);
    let settled: Vec<_> = entries.iter().map(|e| e.engine.poses()).collect();
    lockstep(&mut entries, PYRAMID_STEPS - PYRAMID_SETTLE, true, None);
    let drifts: Vec<_> = entries
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let end = e.engine.poses();
            (
                drift(&scene, &start[i], &end),
                drift(&scene, &settled[i], &end),
            )
        })
        .collect();
    criterion_steps(c, "pyramid", &mut entries);
    println!(
        "pyramid: 210 boxes, dt = 1/240 s; {PYRAMID_STEPS} steps (10 s) of each engine in lockstep"
    );
    print_times(&entries, |i| {
        let (whole, late) = drifts[i];
        format!(
            "stands after 10 s: {} (largest displacement {:.2e} m = {:.2}% of a box, largest \
             turn {:.2e} rad; from 1 s to 10 s: {:.2e} m, {:.2e} rad)",
            if whole.stands() { "yes" } else { "NO" },
            whole.moved,
            100.0 * whole.moved_of_size,
            whole.turned,
            late.moved,
            late.turned,
        )
    });
}

fn pile(c: &mut Criterion) {
    let scene = scene(
        "benches/rapier/pile-2000.toml",
        include_str!("pile-2000.toml"),
    );
    let bucket = Bucket::new(&scene);
    let mut entries = entries(&scene);
    let mut worst = vec![PileWorst::default(); entries.len()];
    let mut look = |i: usize, poses: &[Pose]| bucket.look(poses, &mut worst[i]);
    eprintln!("pile: settling 2 s, then timing 2 s of each engine in lockstep…");
    lockstep(&mut entries, PILE_SETTLE, false, Some(&mut look));
    lockstep(&mut entries, PILE_STEPS, true, Some(&mut look));
    criterion_steps(c, "pile", &mut entries);
    println!(
        "pile: 2,000 discs in a bucket, dt = 1/240 s; {PILE_STEPS} steps (2 s) of each engine in \
         lockstep after {PILE_SETTLE} (2 s) of settling"
    );
    print_times(&entries, |i| {
        let w = worst[i];
        format!(
            "discs out of the bucket: {}; deepest overlap {:.2e} m ({:.0}% of a radius) over the \
             4 s, {:.2e} m ({:.0}%) at 4 s; top disc at y = {:.2} m",
            w.escaped,
            w.overlap,
            100.0 * w.overlap / RADIUS,
            w.last_overlap,
            100.0 * w.last_overlap / RADIUS,
            w.top,
        )
    });
}

/// The 10,000-disc pile of issue 15's frame-rate target (`scenes/bench/pile-10000.toml`,
/// which drops the discs from a loose grid), stepped from its start for its whole 2 s
/// in lockstep in physframes and in Rapier at its default budget, both sleeping as
/// each does by default: what `physframes bench` renders. The render's frames need 8
/// steps each (30 frames/s at dt = 1/240 s), so the mean step bounds the frame rate the
/// simulation alone allows, whatever the drawing costs; printed for both engines.
fn pile_10000(_: &mut Criterion) {
    let scene = scene(
        "scenes/bench/pile-10000.toml",
        include_str!("../../scenes/bench/pile-10000.toml"),
    );
    let mut entries = vec![
        Entry {
            id: "physframes-sleeping".into(),
            budget: "up to 25 sweeps, bodies sleep",
            engine: Box::new(Physframes::new(&scene, true)),
            ours: 0,
            times: Vec::new(),
        },
        Entry {
            id: format!("rapier-{RAPIER_DEFAULT}-substeps-sleeping"),
            budget: "8 sweeps, bodies sleep",
            engine: Box::new(Rapier::new(&scene, RAPIER_DEFAULT, true)),
            ours: 0,
            times: Vec::new(),
        },
    ];
    let steps = (scene.simulation.duration / scene.simulation.dt).round() as usize;
    let per_frame = (1.0 / (scene.render.fps * scene.simulation.dt)).round();
    eprintln!("pile-10000: stepping each engine {steps} steps in lockstep…");
    lockstep(&mut entries, steps, true, None);
    println!(
        "pile-10000: 10,000 discs dropped into a bucket, dt = 1/240 s; all {steps} steps (2 s) \
         of each engine in lockstep from the start, {per_frame} steps a frame"
    );
    print_times(&entries, |i| {
        let mean = median_mean(&entries[i].times).1;
        format!(
            "the simulation alone allows at most {:.1} frames/s",
            1.0 / (per_frame * mean)
        )
    });
}

criterion_group! {
    name = benches;
    // Short runs: the machine has two cores, shared with other work.
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = pyramid, pile, pile_10000
}
criterion_main!(benches);
