//! Times drawing the velocity arrows of a scene's first frame, alone, on one thread, and
//! says how far the fast arrows are from tiny-skia's paths.
//!
//! ```sh
//! cargo run --release --example arrow_probe -- scenes/bench/arrows-1000.toml
//! ```
//!
//! It lays out every arrow the renderer would draw at the start of the run, draws them
//! all into a pixmap of the scene's size 200 times with [`draw_arrow`] (ramps,
//! `raster/ramps/`) and with [`draw_arrow_path`] (tiny-skia's paths), and prints the best
//! milliseconds of each, how many pixels the arrows cover, and how many differ between
//! the two drawings and by how much. With `ONE_SPOT=1` every arrow starts at the same
//! pixel, so that the pixels stay in the cache and only the arithmetic is timed; with
//! `SCALE=K` every arrow is K times as long (what an arrow costs whatever its length,
//! against what its length costs); with `SKIP_PATHS=1` the paths are not drawn (to
//! profile the ramps alone); with `SAVE_TO=DIR` both drawings are written to
//! DIR as raw RGBA (`scan.rgba`, `paths.rgba`).

use std::path::Path;
use std::time::Instant;

use glam::DVec2;
use physframes::render::arrows::{draw_arrow, draw_arrow_path};
use physframes::render::clip::ClipRect;
use physframes::render::{ArrowScales, Camera};
use tiny_skia::{Color, Pixmap};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("give a scene file")?;
    let text = std::fs::read_to_string(&path)?;
    let scene = physframes::scene::parse(Path::new(&path), &text)?;
    let (w, h) = (scene.render.width, scene.render.height);
    let camera = Camera::fit(scene.render.view, w, h);
    let clip = ClipRect::guard(w, h);
    let vel: Vec<DVec2> = scene.bodies.iter().map(|b| b.velocity).collect();
    let scales = ArrowScales::fit(&scene, &vel, &vec![DVec2::ZERO; vel.len()]);
    // Every arrow's length times SCALE (1 unless set), to part what an arrow costs
    // whatever its length from what it costs a pixel of length.
    let scale: f64 = match std::env::var("SCALE") {
        Ok(s) => s
            .parse()
            .map_err(|_| format!("SCALE={s} is not a number"))?,
        Err(_) => 1.0,
    };
    let arrows: Vec<((f64, f64), (f64, f64))> = scene
        .bodies
        .iter()
        .filter(|b| b.show_velocity)
        .map(|b| {
            let mut at = camera.to_pixel_f64(b.position);
            if std::env::var_os("ONE_SPOT").is_some() {
                // Every arrow from the same few pixels, which stay in the cache: the
                // arithmetic alone.
                at = (400.0 + at.0.fract(), 300.0 + at.1.fract());
            }
            let d = camera.to_pixel_vector_f64(scales.velocity * b.velocity);
            (at, (scale * d.0, scale * d.1))
        })
        .collect();
    let colour = Color::from_rgba8(230, 90, 40, 255);
    let time = |draw: &dyn Fn(&mut Pixmap)| -> Result<(f64, Pixmap), String> {
        let mut pixmap = Pixmap::new(w, h).ok_or("no pixmap")?;
        let mut best = f64::MAX;
        for _ in 0..200 {
            let started = Instant::now();
            draw(&mut pixmap);
            best = best.min(started.elapsed().as_secs_f64() * 1e3);
        }
        let mut once = Pixmap::new(w, h).ok_or("no pixmap")?;
        once.fill(Color::WHITE);
        draw(&mut once);
        Ok((best, once))
    };
    let (fast, a) = time(&|p| {
        for &(at, d) in &arrows {
            draw_arrow(p, &clip, at, d, colour, 2.0);
        }
    })?;
    // With SKIP_PATHS, tiny-skia's paths draw nothing: a profile of the ramps
    // alone (the comparison below is then meaningless).
    let skip = std::env::var_os("SKIP_PATHS").is_some();
    let (paths, b) = time(&|p| {
        for &(at, d) in arrows.iter().filter(|_| !skip) {
            draw_arrow_path(p, &clip, at, d, colour, 2.0);
        }
    })?;
    let compare = |a: &Pixmap, b: &Pixmap| {
        let (mut covered, mut differ, mut sum, mut max) = (0usize, 0usize, 0u64, 0u8);
        for (pa, pb) in a.data().chunks_exact(4).zip(b.data().chunks_exact(4)) {
            if pa != [255; 4] || pb != [255; 4] {
                covered += 1;
            }
            let d = pa
                .iter()
                .zip(pb)
                .map(|(x, y)| x.abs_diff(*y))
                .max()
                .unwrap_or(0);
            if d > 0 {
                differ += 1;
                sum += u64::from(d);
                max = max.max(d);
            }
        }
        format!(
            "{covered} pixels covered, {differ} differ ({:.1}%), by {:.2}/255 on average over the covered, {max}/255 at most",
            100.0 * differ as f64 / covered.max(1) as f64,
            sum as f64 / covered.max(1) as f64,
        )
    };
    println!(
        "{} arrows, best of 200: ramps {fast:.3} ms, tiny-skia's paths {paths:.3} ms",
        arrows.len()
    );
    println!("against the paths: {}", compare(&a, &b));
    if let Some(dir) = std::env::var_os("SAVE_TO") {
        let dir = Path::new(&dir);
        std::fs::write(dir.join("scan.rgba"), a.data())?;
        std::fs::write(dir.join("paths.rgba"), b.data())?;
    }
    Ok(())
}
