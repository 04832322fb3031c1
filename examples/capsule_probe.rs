//! Times the trails' segments alone: 1000 capsules 1.5 pixels wide, each from a random
//! point a short random step, covered as `render/trails.rs` covers them
//! (`raster::cover_capsule`, by the distance to the segment) into a coverage kept as
//! the strongest (best of 2000 frames). With `POLYGONS=1`, each is the capsule's
//! polygon scan-converted with `raster::cover_convex` instead, as trails were drawn
//! until the eighteenth session of issue #16.
//!
//! ```sh
//! cargo run --release --example capsule_probe
//! POLYGONS=1 cargo run --release --example capsule_probe
//! ```
use std::time::Instant;

use physframes::render::raster;

fn main() {
    let (w, h) = (1280u32, 720u32);
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let segments: Vec<((f64, f64), (f64, f64))> = (0..1000)
        .map(|_| {
            let (x, y) = (10.0 + 1260.0 * rnd(), 10.0 + 700.0 * rnd());
            let (dx, dy) = (1.6 * rnd() - 0.8, 1.6 * rnd() - 0.8);
            ((x, y), (x + dx, y + dy))
        })
        .collect();
    let mut coverage = vec![0u8; (w * h) as usize];
    let mut outline = Vec::new();
    let mut best = f64::MAX;
    let polygons = std::env::var_os("POLYGONS").is_some();
    for _ in 0..2000 {
        coverage.fill(0);
        let t = Instant::now();
        for &(a, b) in &segments {
            let keep = |p: usize, c: u8| {
                if c > coverage[p] {
                    coverage[p] = c;
                }
            };
            if polygons {
                raster::capsule(a, b, 0.75, &mut outline);
                raster::cover_convex(w, h, &outline, keep);
            } else {
                raster::cover_capsule((w, h), a, b, 0.75, keep);
            }
        }
        best = best.min(t.elapsed().as_secs_f64());
    }
    let touched = coverage.iter().filter(|&&c| c != 0).count();
    let sum: u64 = coverage.iter().map(|&c| u64::from(c)).sum();
    println!(
        "1000 capsules: best {:.3} ms, {touched} pixels covered, coverage sum {sum}",
        best * 1e3
    );
}
