//! Times the encoding of one frame of the benchmark scenes, both ways the default
//! compression can take: the static layer's tiles (`StaticPng::encode_damaged_tiles`)
//! and `fdeflate` over the whole frame (`--compression fastest`), and what the encoder
//! chooses (`StaticPng::encode_damaged`). The figures behind `StaticPng::tiles_pay`
//! come from this.
//!
//! ```sh
//! cargo run --release --example encode_probe                  # 1000 circles
//! cargo run --release --example encode_probe -- 2000 500      # 2000 circles, 500 runs
//! ```
//!
//! For each of `scenes/bench/circles-1000.toml` and `circles-1000-field.toml`, with the
//! swarm's count replaced, it prints the fraction of 8-pixel tiles the bodies damage,
//! the best and median time of each way over the runs, and the PNG sizes. One frame is
//! encoded over and over, so its data stays in cache: a render's workers see somewhat
//! longer times, alike for both ways.

use std::path::Path;
use std::time::Instant;

use glam::DVec2;
use physframes::render::fastpng::StaticPng;
use physframes::render::{
    encode_png_into, ArrowScales, Compression, Damage, FrameView, Provenance, Renderer,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let count: usize = args.next().map_or(Ok(1000), |a| a.parse())?;
    let runs: usize = args.next().map_or(Ok(300), |a| a.parse())?.max(1);
    println!("{count} circles, {runs} runs; times in ms (best / median), sizes in bytes");
    for name in ["circles-1000", "circles-1000-field"] {
        let path = format!("scenes/bench/{name}.toml");
        let text =
            std::fs::read_to_string(&path)?.replace("count = 1000", &format!("count = {count}"));
        let scene = physframes::scene::parse(Path::new(&path), &text)?;
        let sim = scene.simulation_with(scene.simulation.integrator);
        let mut force = vec![DVec2::ZERO; scene.bodies.len()];
        sim.net_forces(&mut force);
        let renderer = Renderer::new(&scene, ArrowScales::fit(&scene, &sim.state().vel, &force));
        let state = scene.initial_state();
        let view = FrameView {
            index: 0,
            t: 0.0,
            pos: &state.pos,
            vel: &[],
            angle: None,
            force: None,
            trail: None,
            traces: None,
            compare: None,
        };
        // Drawn twice, as a worker does, so that the damage is the bodies'.
        let mut pixmap = renderer.new_frame();
        let mut damage = Damage::default();
        renderer.draw_damaged(&view, &mut pixmap, &mut damage);
        renderer.draw_damaged(&view, &mut pixmap, &mut damage);
        let encoder = StaticPng::new(renderer.static_layer()).ok_or("no fdeflate code")?;
        let mut png = Vec::new();
        let mut time = |encode: &mut dyn FnMut(&mut Vec<u8>)| {
            let mut seconds: Vec<f64> = (0..runs)
                .map(|_| {
                    let started = Instant::now();
                    encode(&mut png);
                    started.elapsed().as_secs_f64() * 1e3
                })
                .collect();
            seconds.sort_by(f64::total_cmp);
            format!(
                "{:.3} / {:.3} ({} B)",
                seconds[0],
                seconds[runs / 2],
                png.len()
            )
        };
        let none = Provenance::default();
        let tiles = time(&mut |png| {
            encoder.encode_damaged_tiles(&pixmap, &damage, &none, png);
        });
        let whole = time(&mut |png| {
            encoder.encode_damaged_tiles(&pixmap, &Damage::whole(), &none, png);
        });
        let fdeflate = time(&mut |png| {
            let _ = encode_png_into(png, &pixmap, &none, Compression::Fastest, true);
        });
        let chosen = time(&mut |png| {
            encoder.encode_damaged(&pixmap, &damage, &none, png);
        });
        println!(
            "{name:20} damaged tiles {:5.1}% | tiles {tiles} | whole rows {whole} | fdeflate {fdeflate} | chosen {chosen}",
            100.0 * dirty_fraction(&damage, pixmap.width(), pixmap.height())
        );
    }
    Ok(())
}

/// The fraction of 8-pixel tiles, row by row, that the damage touches (or whose row
/// above it touches, as the Up filter reads that row): what the encoder compresses.
fn dirty_fraction(damage: &Damage, width: u32, height: u32) -> f64 {
    if damage.is_whole() {
        return 1.0;
    }
    let (tiles, h) = ((width as usize).div_ceil(8), height as usize);
    let mut dirty = vec![false; tiles * h];
    for r in damage.rects() {
        for y in r.y0 as usize..(r.y1 as usize + 1).min(h) {
            for t in r.x0 as usize / 8..(r.x1 as usize).div_ceil(8) {
                dirty[y * tiles + t] = true;
            }
        }
    }
    dirty.iter().filter(|d| **d).count() as f64 / dirty.len() as f64
}
