//! Times drawing and encoding one frame of any scene on one thread, to see where a
//! scene's frame time goes without the pipeline around it.
//!
//! ```sh
//! cargo run --release --example frame_probe -- scenes/bench/arrows-1000.toml        # frame 150, 200 runs
//! cargo run --release --example frame_probe -- scenes/bench/trails-1000.toml 1200 50
//! ```
//!
//! It simulates the scene to the frame (keeping the trail history when the scene has
//! trails), then draws the frame over and over as a worker does (into a reused pixmap,
//! from the last frame's damage, and with trails from a layer that holds the frame
//! before), and encodes it with the default compression and with `fdeflate` whole. It
//! prints the best and median milliseconds of each, the PNG's size, and the frame's
//! damage (whole, or how much of the frame its rectangles cover).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use glam::DVec2;
use physframes::history::HistoryWriter;
use physframes::render::damage::TileMask;
use physframes::render::fastpng::StaticPng;
use physframes::render::{
    encode_png_into, ArrowScales, Compression, Damage, FrameView, Provenance, Renderer,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("give a scene file")?;
    let text = std::fs::read_to_string(&path)?;
    let scene = physframes::scene::parse(Path::new(&path), &text)?;
    let frame: u64 = args
        .next()
        .map_or(Ok(scene.render.frame_count / 2), |a| a.parse())?
        .min(scene.render.frame_count - 1);
    let runs: usize = args.next().map_or(Ok(200), |a| a.parse())?.max(1);
    let mut sim = scene.simulation_with(scene.simulation.integrator);
    let mut force = vec![DVec2::ZERO; scene.bodies.len()];
    sim.net_forces(&mut force);
    let renderer = Renderer::new(&scene, ArrowScales::fit(&scene, &sim.state().vel, &force));
    let mut history: HistoryWriter<Arc<[DVec2]>> = HistoryWriter::new();
    let mut before = history.history().clone();
    for k in 0..=frame {
        before = history.history().clone();
        sim.advance_to(scene.frame_time(k))
            .map_err(|e| format!("blow-up: {e:?}"))?;
        if scene.render.trails {
            history.push(Arc::from(sim.state().pos.as_slice()));
        }
    }
    let state = sim.state();
    sim.net_forces(&mut force);
    let trail = history.history().clone();
    let view = FrameView {
        index: frame,
        t: state.t,
        pos: &state.pos,
        vel: &state.vel,
        angle: Some(&state.angle),
        force: Some(&force),
        trail: scene.render.trails.then_some(&trail),
        traces: None,
        compare: None,
    };
    let mut pixmap = renderer.new_frame();
    let mut damage = Damage::default();
    // A worker's trail layer as it stands after the frame before.
    let mut ready = None;
    if scene.render.trails {
        let previous = FrameView {
            index: frame.saturating_sub(1),
            trail: Some(&before),
            ..view
        };
        renderer.draw_with_trails(&previous, &mut pixmap, &mut damage, &mut ready);
    }
    let time = |f: &mut dyn FnMut()| {
        let mut ms: Vec<f64> = (0..runs)
            .map(|_| {
                let started = Instant::now();
                f();
                started.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        ms.sort_by(f64::total_cmp);
        format!("{:.3} / {:.3}", ms[0], ms[runs / 2])
    };
    let mut layer = None;
    let draw = time(&mut || {
        if let Some(ready) = &ready {
            layer = Some(ready.clone());
        }
        renderer.draw_with_trails(&view, &mut pixmap, &mut damage, &mut layer)
    });
    let encoder = StaticPng::new(renderer.static_layer()).ok_or("no fdeflate code")?;
    let none = Provenance::default();
    let mut png = Vec::new();
    let fast = time(&mut || {
        encoder.encode_damaged(&pixmap, &damage, &none, &mut png);
    });
    let fast_bytes = png.len();
    let whole = time(&mut || {
        let _ = encode_png_into(&mut png, &pixmap, &none, Compression::Fastest, true);
    });
    // What the frame's damage is: whole, or rectangles covering some of the frame
    // (their areas summed, overlaps counted twice).
    let covered = if damage.is_whole() {
        "whole".to_string()
    } else {
        let area = damage.area();
        let frame_area = u64::from(scene.render.width) * u64::from(scene.render.height);
        let mut tiles = TileMask::new(scene.render.width, scene.render.height);
        tiles.clear();
        tiles.add_damage(&damage);
        format!(
            "{} rectangles, {:.1}% of the frame, {:.1}% of its tiles",
            damage.rects().len(),
            100.0 * area as f64 / frame_area as f64,
            100.0 * tiles.count() as f64 / tiles.tiles() as f64
        )
    };
    println!(
        "{} frame {frame}, {runs} runs, ms best / median: draw {draw}, encode {fast} ({fast_bytes} B), fdeflate whole {whole} ({} B); damage {covered}",
        scene.name,
        png.len()
    );
    Ok(())
}
