//! Frames: end to end (simulate, draw, encode, write) and stage by stage, on the
//! benchmark scenes of `scenes/bench/`.
//!
//! - `end-to-end/*`: a whole render with the default pipeline (one drawing thread per
//!   core) into a temporary folder; the throughput is frames per second. Targets at
//!   1280×720: ≥ 300 frames/s for 1000 circles, ≥ 100 for 10,000.
//! - `static-layer/*`: the 1000-circle render again, with and without a static layer
//!   of 500 arrows and axes drawn once into the renderer; the target is at most 10%
//!   more time per frame.
//! - `stage/*`: one frame's drawing and encoding on one thread, for 3, 1000 and 10,000
//!   circles, with and without the static layer (`encode-fast` is the
//!   default compression, which reuses the static layer's compressed tiles;
//!   `encode-fastest` the `png` crate's fastest mode).
//! - `compression/*`: encoding one frame at each `--compression` level (the sizes are
//!   printed once).

use std::path::Path;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode, Throughput};
use glam::DVec2;
use physframes::pipeline::{render_prepared, RenderOptions};
use physframes::render::bodies::draw_arrow;
use physframes::render::fastpng::StaticPng;
use physframes::render::{
    encode_png_into, ArrowScales, Compression, Damage, FrameView, Provenance, Renderer,
};
use physframes::scene::Scene;
use tiny_skia::Color;

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/bench")
        .join(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Draws a static layer like a plot's: a 25 × 20 field of 500 arrows and two axes
/// with ticks.
pub fn draw_static_layer(renderer: &mut Renderer) {
    let camera = *renderer.camera();
    let clip = *renderer.clip();
    let view = camera.visible();
    let layer = renderer.static_layer_mut();
    let grey = Color::from_rgba8(0x88, 0x88, 0x88, 0xff);
    let size = view.max - view.min;
    for i in 0..25 {
        for j in 0..20 {
            let p = view.min + DVec2::new((i as f64 + 0.5) / 25.0, (j as f64 + 0.5) / 20.0) * size;
            // A rotational field around the view's centre, as a vector field plot shows.
            let d = p - 0.5 * (view.min + view.max);
            let v = DVec2::new(-d.y, d.x) * 0.08;
            draw_arrow(
                layer,
                &clip,
                camera.to_pixel_f64(p),
                camera.to_pixel_vector_f64(v),
                grey,
                1.0,
            );
        }
    }
    let black = Color::BLACK;
    let (x0, y0) = camera.to_pixel_f64(view.min + DVec2::splat(0.5));
    let (x1, y1) = camera.to_pixel_f64(view.max - DVec2::splat(0.5));
    draw_arrow(layer, &clip, (x0, y0), (x1 - x0, 0.0), black, 1.5);
    draw_arrow(layer, &clip, (x0, y0), (0.0, y1 - y0), black, 1.5);
    for k in 0..16 {
        let x = x0 + (x1 - x0) * k as f64 / 16.0;
        draw_arrow(layer, &clip, (x, y0 + 6.0), (0.0, -6.0), black, 1.0);
    }
}

fn end_to_end(c: &mut Criterion) {
    let mut group = c.benchmark_group("end-to-end");
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    group.measurement_time(Duration::from_secs(20));
    for (name, static_layer) in [
        ("circles-1000", false),
        ("circles-10000", false),
        ("circles-1000", true),
    ] {
        let scene = scene(&format!("{name}.toml"));
        group.throughput(Throughput::Elements(scene.render.frame_count));
        let id = if static_layer {
            format!("{name}+static-layer")
        } else {
            name.to_string()
        };
        group.bench_function(id, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let dir = tempfile::tempdir().expect("a temporary folder");
                    let options = RenderOptions {
                        out_dir: dir.path().to_path_buf(),
                        frames: None,
                        threads: 0,
                        compression: Compression::Fast,
                        progress: false,
                    };
                    let started = Instant::now();
                    render_prepared(&scene, &options, |r| {
                        if static_layer {
                            draw_static_layer(r)
                        }
                    })
                    .expect("the render succeeds");
                    total += started.elapsed();
                }
                total
            })
        });
    }
    group.finish();
}

/// Returns a renderer of a scene and its initial state, for one-frame benchmarks.
fn frame_of(scene: &Scene, static_layer: bool) -> (Renderer, physframes::sim::State) {
    let mut renderer = Renderer::new(
        scene,
        ArrowScales {
            velocity: 1.0,
            force: 1.0,
        },
    );
    if static_layer {
        draw_static_layer(&mut renderer);
    }
    (renderer, scene.initial_state())
}

fn stages(c: &mut Criterion) {
    let mut group = c.benchmark_group("stage");
    for name in ["circles-3", "circles-1000", "circles-10000"] {
        let scene = if name == "circles-3" {
            // A few bodies over the field: most rows show the static layer unchanged.
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bench/circles-1000.toml");
            let text = std::fs::read_to_string(&path).expect("the benchmark scene");
            physframes::scene::parse(&path, &text.replace("count = 1000", "count = 3"))
                .expect("a valid scene")
        } else {
            scene(&format!("{name}.toml"))
        };
        for static_layer in [false, true] {
            let (renderer, state) = frame_of(&scene, static_layer);
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
            let suffix = if static_layer { "+static-layer" } else { "" };
            let mut pixmap = renderer.new_frame();
            // As a render's workers do: each frame restores only what the last one
            // drew over the static layer.
            let mut damage = Damage::default();
            group.bench_function(format!("{name}{suffix}/draw"), |b| {
                b.iter(|| renderer.draw_damaged(&view, &mut pixmap, &mut damage))
            });
            renderer.draw_damaged(&view, &mut pixmap, &mut damage);
            let mut png = Vec::new();
            // The default compression, as a render uses it: the static layer's tiles
            // compressed once.
            let encoder =
                StaticPng::new(renderer.static_layer()).expect("the fdeflate code is readable");
            group.bench_function(format!("{name}{suffix}/encode-fast"), |b| {
                b.iter(|| {
                    encoder.encode_damaged(&pixmap, &damage, &Provenance::default(), &mut png)
                })
            });
            group.bench_function(format!("{name}{suffix}/encode-fastest"), |b| {
                b.iter(|| {
                    encode_png_into(
                        &mut png,
                        &pixmap,
                        &Provenance::default(),
                        Compression::Fastest,
                        true,
                    )
                    .expect("encodes")
                })
            });
        }
    }
    group.finish();
}

fn compression(c: &mut Criterion) {
    let scene = scene("circles-1000.toml");
    let (renderer, state) = frame_of(&scene, false);
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
    let pixmap = renderer.draw(&view);
    let mut group = c.benchmark_group("compression");
    for (name, level) in [
        ("fastest", Compression::Fastest),
        ("fast", Compression::Fast),
        ("best", Compression::Best),
    ] {
        let mut png = Vec::new();
        encode_png_into(&mut png, &pixmap, &Provenance::default(), level, true).expect("encodes");
        eprintln!(
            "compression {name}: {} bytes for a 1000-circle frame",
            png.len()
        );
        if matches!(level, Compression::Best) {
            group.sample_size(10);
        }
        group.bench_function(name, |b| {
            b.iter(|| {
                encode_png_into(&mut png, &pixmap, &Provenance::default(), level, true)
                    .expect("encodes")
            })
        });
    }
    let encoder = StaticPng::new(renderer.static_layer()).expect("the fdeflate code is readable");
    let mut png = Vec::new();
    encoder.encode(&pixmap, &Provenance::default(), &mut png);
    eprintln!(
        "compression fast (static tiles): {} bytes for a 1000-circle frame",
        png.len()
    );
    group.bench_function("fast-static-tiles", |b| {
        b.iter(|| encoder.encode(&pixmap, &Provenance::default(), &mut png))
    });
    // The same frame over a static layer of 500 arrows and axes, with each encoder.
    let (renderer, _) = frame_of(&scene, true);
    let pixmap = renderer.draw(&view);
    let encoder = StaticPng::new(renderer.static_layer()).expect("the fdeflate code is readable");
    for (name, level) in [
        ("fastest", Compression::Fastest),
        ("fast", Compression::Fast),
    ] {
        group.bench_function(format!("{name}+static-layer"), |b| {
            b.iter(|| {
                encode_png_into(&mut png, &pixmap, &Provenance::default(), level, true)
                    .expect("encodes")
            })
        });
    }
    group.bench_function("fast-static-tiles+static-layer", |b| {
        b.iter(|| encoder.encode(&pixmap, &Provenance::default(), &mut png))
    });
    group.finish();
}

criterion_group!(benches, end_to_end, stages, compression);
criterion_main!(benches);
