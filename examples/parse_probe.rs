//! Times parsing and validating a scene file in the process, without starting one or
//! printing anything: what `physframes check` spends on the scene itself.
//!
//! ```sh
//! cargo run --release --example parse_probe -- scenes/bench/bodies-10000.toml
//! ```
//!
//! It parses the file 20 times and prints the best time in milliseconds, and the
//! first parse's, which alone touches the memory fresh from the system: what a
//! process that parses once (`check`, `render`) waits.

use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("give a scene file")?;
    let text = std::fs::read_to_string(&path)?;
    let (mut best, mut first) = (f64::MAX, None);
    for _ in 0..20 {
        let started = Instant::now();
        let scene = physframes::scene::parse(std::path::Path::new(&path), &text)?;
        let ms = started.elapsed().as_secs_f64() * 1e3;
        best = best.min(ms);
        first.get_or_insert(ms);
        std::hint::black_box(scene);
    }
    let first = first.unwrap_or(best);
    println!(
        "{path}: parsed and validated in {best:.2} ms (best of 20); the first parse, as `check` and `render` make it: {first:.2} ms"
    );
    Ok(())
}
