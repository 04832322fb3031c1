//! The simulation alone: explicit Euler through the general force pipeline (a scene's
//! gravity and drag, summed by `ForceSet`) on the 10^6-body swarm of
//! `scenes/bench/euler-1e6.toml`, with nothing drawn or written.
//!
//! Beside it, in the same group, the same physics from the same initial state through
//! `HandWrittenEuler`, a hand-written loop over flat `f64` arrays: the floor against
//! which the pipeline is judged, measured on the same machine at the same time.
//!
//! `cargo bench --bench simulate` reports the time for 10 steps and, as throughput,
//! body-steps per second (10^9 divided by it is nanoseconds per body-step). Target: at
//! most 1.0 ns per body-step on 2 threads. `physframes bench scenes/bench/euler-1e6.toml
//! --simulate-only` measures the same through the command line, and the ratio of the
//! two.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use physframes::scene::Scene;
use physframes::sim::{HandWrittenEuler, Simulation};

const STEPS: u64 = 10;

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/bench")
        .join(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn euler_million(c: &mut Criterion) {
    let scene = scene("euler-1e6.toml");
    let bodies = scene.bodies.len() as u64;
    let mut group = c.benchmark_group("explicit-euler-gravity-drag-1e6");
    group.sample_size(20);
    group.throughput(Throughput::Elements(STEPS * bodies));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        let mut sim = Simulation::new(
            scene.system(),
            scene.initial_state(),
            scene.simulation.integrator,
            scene.simulation.dt,
        );
        group.bench_function(format!("pipeline/{threads}-threads"), |b| {
            b.iter(|| pool.install(|| sim.run_steps(STEPS).expect("finite")))
        });
        let mut hand = HandWrittenEuler::new(
            &scene.system(),
            scene.simulation.integrator,
            scene.simulation.dt,
            &scene.initial_state(),
        )
        .expect("the scene is explicit Euler under gravity and drag on equal masses");
        group.bench_function(format!("hand-written/{threads}-threads"), |b| {
            b.iter(|| pool.install(|| hand.run_steps(STEPS)))
        });
    }
    group.finish();
}

criterion_group!(benches, euler_million);
criterion_main!(benches);
