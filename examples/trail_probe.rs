//! Times a scene with trails frame by frame as one worker of a render draws and encodes
//! it (`Renderer::draw_trail_frame` and `FrameCoder`, every `step`-th frame, as one of
//! `step` threads sees them), to show how a frame's cost moves as the trails grow.
//!
//! ```sh
//! cargo run --release --example trail_probe -- scenes/bench/trails-1000.toml      # step 2
//! cargo run --release --example trail_probe -- scenes/bench/trails-1000.toml 1
//! ```
//!
//! For each hundred frames drawn it prints the mean milliseconds of drawing and of
//! encoding, the mean PNG size and the fraction of the frame's 8-pixel tiles that were
//! compressed afresh (the rest copied from the worker's frame before); then, for the
//! last frame, what encoding it costs with no tile marked, with its own marks again, and
//! with every tile marked (best of 20, or of the `RUNS` environment variable); with
//! `ONLY_OWN=1`, only with its own marks (what a worker does), for profiling that alone.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use glam::DVec2;
use physframes::history::HistoryWriter;
use physframes::render::damage::TileMask;
use physframes::render::fastpng::FrameCoder;
use physframes::render::trails::TrailFrame;
use physframes::render::{ArrowScales, FrameView, Provenance, Renderer};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("give a scene file with trails")?;
    let step: u64 = args.next().map_or(Ok(2), |a| a.parse())?.max(1);
    let text = std::fs::read_to_string(&path)?;
    let scene = physframes::scene::parse(Path::new(&path), &text)?;
    let mut sim = scene.simulation_with(scene.simulation.integrator);
    let mut force = vec![DVec2::ZERO; scene.bodies.len()];
    sim.net_forces(&mut force);
    let renderer = Renderer::new(&scene, ArrowScales::fit(&scene, &sim.state().vel, &force));
    let (width, height) = (scene.render.width, scene.render.height);
    let mut history: HistoryWriter<Arc<[DVec2]>> = HistoryWriter::new();
    let mut state = TrailFrame::new(width, height);
    let mut coder = FrameCoder::new(width, height).ok_or("no fdeflate code")?;
    let mut pixmap = renderer.new_frame();
    let none = Provenance::default();
    let tiles = f64::from(width.div_ceil(8)) * f64::from(height);
    // Sums over the frames drawn since the last line printed.
    let (mut draw, mut encode, mut bytes, mut dirty, mut n) = (0.0, 0.0, 0usize, 0.0, 0);
    let mut from = 0;
    for k in 0..scene.render.frame_count {
        sim.advance_to(scene.frame_time(k))
            .map_err(|e| format!("blow-up: {e:?}"))?;
        history.push(Arc::from(sim.state().pos.as_slice()));
        if k % step != 0 {
            continue;
        }
        let s = sim.state();
        let trail = history.history().clone();
        let view = FrameView {
            index: k,
            t: s.t,
            pos: &s.pos,
            vel: &s.vel,
            angle: Some(&s.angle),
            force: None,
            trail: Some(&trail),
            traces: None,
            compare: None,
        };
        let started = Instant::now();
        renderer.draw_trail_frame(&view, &mut pixmap, &mut state);
        let drawn = Instant::now();
        bytes += coder.encode(&pixmap, state.changed(), &none).len();
        encode += drawn.elapsed().as_secs_f64() * 1e3;
        draw += (drawn - started).as_secs_f64() * 1e3;
        dirty += marked(state.changed()) / tiles;
        n += 1;
        let last = k + step >= scene.render.frame_count;
        if n == 100 || last {
            let m = f64::from(n);
            println!(
                "frames {from}..={k}: draw {:.3} ms, encode {:.3} ms, {} B, {:.1}% of tiles afresh",
                draw / m,
                encode / m,
                bytes / n as usize,
                100.0 * dirty / m
            );
            (draw, encode, bytes, dirty, n, from) = (0.0, 0.0, 0, 0.0, 0, k + step);
        }
        if last {
            let runs: usize = std::env::var("RUNS").map_or(Ok(20), |r| r.parse())?;
            let best = |coder: &mut FrameCoder, mask: &TileMask| {
                (0..runs.max(1))
                    .map(|_| {
                        let started = Instant::now();
                        coder.encode(&pixmap, mask, &none);
                        started.elapsed().as_secs_f64() * 1e3
                    })
                    .fold(f64::INFINITY, f64::min)
            };
            let mut clean = TileMask::new(width, height);
            clean.clear();
            let own = state.changed().clone();
            if std::env::var("ONLY_OWN").is_ok() {
                println!("own marks: {:.3} ms", best(&mut coder, &own));
                return Ok(());
            }
            println!(
                "frame {k} again: {:.3} ms with no tile marked, {:.3} with its marks, {:.3} with every tile",
                best(&mut coder, &clean),
                best(&mut coder, &own),
                best(&mut coder, &TileMask::new(width, height)),
            );
        }
    }
    Ok(())
}

/// The number of filtered tiles a mask makes the coder compress afresh: those marked
/// in their row or the row above.
fn marked(mask: &TileMask) -> f64 {
    let (width, height) = mask.size();
    if mask.is_whole() {
        return f64::from(width.div_ceil(8)) * f64::from(height);
    }
    let mut count = 0u32;
    for y in 0..height as usize {
        let above = mask.row(y.saturating_sub(1));
        for (a, b) in mask.row(y).iter().zip(above) {
            count += (a | b).count_ones();
        }
    }
    f64::from(count)
}
