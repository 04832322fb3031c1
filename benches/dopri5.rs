//! Our Dormand–Prince 5(4) against the `ode_solvers` crate's, on the same harmonic
//! oscillators at the same tolerances.
//!
//! One oscillator is the `spring` reference problem (a unit mass on a spring of rest
//! length 0 and stiffness 4π² to a fixed point, period 1, in the plane); the other
//! problem is 64 such oscillators with different anchors and phases, which measures the
//! per-body cost rather than the per-call cost. Both run for 10¼ periods. Both solvers use
//! Hairer's error norm over the same components (x, y, vx, vy of every body), the same PI
//! controller constants, the same starting-step heuristic, and the whole interval as the
//! largest step, so they take the same steps; what differs is the implementation.
//! `ode_solvers` runs with `OutputType::Sparse`: its default dense output would report
//! the final time by extrapolating from a step that ends before it. Each run builds its
//! solver and integrates, for both.
//!
//! Run with `cargo bench --bench dopri5`. It first prints each solver's error and step
//! counts, and the medians of runs of the two solvers taken in alternation (so that the
//! load of a shared machine falls on both alike); criterion's own timings follow, and its
//! medians are in `target/criterion/<group>/<solver>/new/estimates.json`.

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use glam::DVec2;
use ode_solvers::{OutputType, SVector};
use physframes::sim::integrators::Tolerances;
use physframes::sim::{Anchor, ForceSpec, IntegratorKind, Simulation, State, System};

/// The final time: 10¼ periods.
const T_END: f64 = 10.25;
/// The tolerances compared, with rtol = atol.
const TOLERANCES: [f64; 2] = [1e-6, 1e-10];
/// ω² = 4π², for a period of 1.
const OMEGA2: f64 = 4.0 * PI * PI;

/// N unit masses, body i on a spring of rest length 0 to its own anchor c_i.
struct Oscillators<const N: usize> {
    anchors: Vec<DVec2>,
    initial: State,
}

impl<const N: usize> Oscillators<N> {
    /// Body 0 is the `spring` reference problem: anchor (0.5, -0.25), offset (1, 0),
    /// velocity (0, π). The others are spread out with other offsets and phases.
    fn new() -> Self {
        let anchors: Vec<DVec2> = (0..N)
            .map(|i| DVec2::new(0.5 + 3.0 * i as f64, -0.25))
            .collect();
        let (pos, vel) = (0..N)
            .map(|i| {
                let phase = i as f64 * 0.37;
                let offset = DVec2::new(phase.cos(), 0.5 * phase.sin());
                let velocity = DVec2::new(-phase.sin(), 0.5 * phase.cos()) * (2.0 * PI);
                (anchors[i] + offset, velocity)
            })
            .unzip();
        Oscillators {
            anchors,
            initial: State::new(0.0, pos, vel),
        }
    }

    fn system(&self) -> System {
        let springs: Vec<ForceSpec> = (0..N)
            .map(|i| ForceSpec::Spring {
                a: i as u32,
                b: Anchor::Point(self.anchors[i]),
                stiffness: OMEGA2,
                rest_length: 0.0,
                damping: 0.0,
                a_at: None,
                b_at: None,
            })
            .collect();
        System::new(vec![1.0; N], &springs)
    }

    /// Returns max_i |r_i - r_exact,i| at T_END, with x(t) = x0·cos ωt + (v0/ω)·sin ωt.
    fn error(&self, pos: impl Iterator<Item = DVec2>) -> f64 {
        let omega = OMEGA2.sqrt();
        let (s, c) = (omega * T_END).sin_cos();
        pos.enumerate()
            .map(|(i, r)| {
                let x0 = self.initial.pos[i] - self.anchors[i];
                let exact = self.anchors[i] + x0 * c + self.initial.vel[i] * (s / omega);
                (r - exact).length()
            })
            .fold(0.0, f64::max)
    }
}

/// The same oscillators for `ode_solvers`: y = (x0, y0, x1, y1, …, vx0, vy0, …), with
/// M = 4N components.
struct TheirSystem<const N: usize> {
    anchors: Vec<DVec2>,
}

impl<const N: usize, const M: usize> ode_solvers::System<f64, SVector<f64, M>> for TheirSystem<N> {
    fn system(&self, _t: f64, y: &SVector<f64, M>, dy: &mut SVector<f64, M>) {
        let half = 2 * N;
        for (i, c) in self.anchors.iter().enumerate() {
            dy[2 * i] = y[half + 2 * i];
            dy[2 * i + 1] = y[half + 2 * i + 1];
            dy[half + 2 * i] = -OMEGA2 * (y[2 * i] - c.x);
            dy[half + 2 * i + 1] = -OMEGA2 * (y[2 * i + 1] - c.y);
        }
    }
}

/// Integrates with ours; returns the final positions, steps and evaluations.
fn ours<const N: usize>(problem: &Oscillators<N>, tol: f64) -> (Vec<DVec2>, u64, u64) {
    let mut sim = Simulation::new(
        problem.system(),
        problem.initial.clone(),
        IntegratorKind::Dopri5,
        T_END,
    )
    .with_tolerances(Tolerances::both(tol));
    // An oscillator cannot blow up at these tolerances; a failure would show as a
    // non-finite error in the report.
    let _ = sim.advance_to(T_END);
    (sim.state().pos.clone(), sim.steps(), sim.evaluations())
}

/// Integrates with `ode_solvers`; returns the final positions, steps and evaluations.
fn theirs<const N: usize, const M: usize>(
    problem: &Oscillators<N>,
    tol: f64,
) -> (Vec<DVec2>, u64, u64) {
    let s0 = &problem.initial;
    let mut y0 = SVector::<f64, M>::zeros();
    for i in 0..N {
        y0[2 * i] = s0.pos[i].x;
        y0[2 * i + 1] = s0.pos[i].y;
        y0[2 * N + 2 * i] = s0.vel[i].x;
        y0[2 * N + 2 * i + 1] = s0.vel[i].y;
    }
    let system = TheirSystem::<N> {
        anchors: problem.anchors.clone(),
    };
    let mut solver = ode_solvers::Dopri5::new(system, 0.0, T_END, T_END, y0, tol, tol);
    solver.set_output(OutputType::Sparse);
    let Ok(stats) = solver.integrate() else {
        return (vec![DVec2::NAN; N], 0, 0);
    };
    let last = solver.y_out().last().copied().unwrap_or(y0);
    let pos = (0..N)
        .map(|i| DVec2::new(last[2 * i], last[2 * i + 1]))
        .collect();
    (
        pos,
        u64::from(stats.accepted_steps),
        u64::from(stats.num_eval),
    )
}

/// Times `a` and `b` in alternation, each sample a batch lasting at least 5 ms, and
/// returns the median time of one run of each.
fn interleaved(mut a: impl FnMut(), mut b: impl FnMut()) -> (f64, f64) {
    let mut batch = 1u32;
    loop {
        let start = Instant::now();
        for _ in 0..batch {
            a();
        }
        if start.elapsed() >= Duration::from_millis(5) {
            break;
        }
        batch *= 2;
    }
    let sample = |f: &mut dyn FnMut()| {
        let start = Instant::now();
        for _ in 0..batch {
            f();
        }
        start.elapsed().as_secs_f64() / f64::from(batch)
    };
    let (mut ta, mut tb) = (Vec::new(), Vec::new());
    for _ in 0..41 {
        ta.push(sample(&mut a));
        tb.push(sample(&mut b));
    }
    ta.sort_by(f64::total_cmp);
    tb.sort_by(f64::total_cmp);
    (ta[ta.len() / 2], tb[tb.len() / 2])
}

fn report<const N: usize, const M: usize>(label: &str) {
    let problem = Oscillators::<N>::new();
    println!("{label}, t = 0 … {T_END}; error = max over bodies of |r - r_exact| at t_end");
    for tol in TOLERANCES {
        let (pos, steps, evaluations) = ours(&problem, tol);
        let (their_pos, their_steps, their_evaluations) = theirs::<N, M>(&problem, tol);
        let (t_ours, t_theirs) = interleaved(
            || {
                black_box(ours(black_box(&problem), tol));
            },
            || {
                black_box(theirs::<N, M>(black_box(&problem), tol));
            },
        );
        println!(
            "  tol {tol:.0e}: physframes error {:.3e}, {steps} steps, {evaluations} evaluations, \
             median {:.1} µs | ode_solvers error {:.3e}, {their_steps} steps, \
             {their_evaluations} evaluations, median {:.1} µs | ratio {:.2}",
            problem.error(pos.into_iter()),
            t_ours * 1e6,
            problem.error(their_pos.into_iter()),
            t_theirs * 1e6,
            t_ours / t_theirs,
        );
    }
}

fn bench(c: &mut Criterion) {
    report::<1, 4>("1 harmonic oscillator");
    report::<64, 256>("64 harmonic oscillators");
    let one = Oscillators::<1>::new();
    let many = Oscillators::<64>::new();
    for tol in TOLERANCES {
        let mut group = c.benchmark_group(format!("dopri5 1 oscillator tol {tol:.0e}"));
        group.bench_function("physframes", |b| b.iter(|| ours(black_box(&one), tol)));
        group.bench_function("ode_solvers", |b| {
            b.iter(|| theirs::<1, 4>(black_box(&one), tol))
        });
        group.finish();
        let mut group = c.benchmark_group(format!("dopri5 64 oscillators tol {tol:.0e}"));
        group.bench_function("physframes", |b| b.iter(|| ours(black_box(&many), tol)));
        group.bench_function("ode_solvers", |b| {
            b.iter(|| theirs::<64, 256>(black_box(&many), tol))
        });
        group.finish();
    }
}

criterion_group! {
    name = benches;
    // Short runs: two cores are shared with other builds.
    config = Criterion::default()
        .sample_size(30)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
