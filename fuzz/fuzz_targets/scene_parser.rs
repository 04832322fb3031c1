//! Fuzzes the scene parser and validator with arbitrary text, and every scene that
//! validates with a short simulation: neither may panic, whatever the input.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use physframes::scene::parse;
use physframes::sim::Simulation;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse(Path::new("fuzz.toml"), text) {
        Ok(scene) => {
            let mut sim = Simulation::new(
                scene.system(),
                scene.initial_state(),
                scene.simulation.integrator,
                scene.simulation.dt,
            );
            // A blow-up is a correct outcome; only a panic is a finding.
            let _ = sim.run_steps(scene.total_steps().min(64));
        }
        Err(e) => {
            // Rendering the diagnostics must not panic either (spans, UTF-8 columns).
            let _ = e.render();
        }
    }
});
