//! What the fast paths promise: swarms are reproducible, skipping and stamping give
//! the pictures drawing every path would, and the bytes and bits do not depend on the
//! number of threads or on the processor's vector width. Speed itself is measured by
//! the benches (`cargo bench`) and `physframes bench`, not here.

use glam::DVec2;
use physframes::render::bodies::BodyLook;
use physframes::render::sprite::{SpriteSheet, GRID, PHASES};
use physframes::render::{ArrowScales, BodyDrawing, Camera, FrameView, Renderer};
use physframes::scene::{parse, Scene, Shape};
use physframes::sim::chunks::use_wide_vectors;
use physframes::sim::{Selection, Simulation, State};
use tiny_skia::{Color, Pixmap};

use crate::util::{assert_same_bits, diff, example, run, scene, stderr, stdout, Sandbox};

const SWARM: &str = r##"
[render]
width = 320
height = 180
view = { min = [0.0, 0.0], max = [16.0, 9.0] }

[[body]]
name = "probe"
mass = 2.0

[[swarm]]
name = "dust"
count = 10000
seed = 7
mass = 1.0
position = { min = [0.0, 0.0], max = [10.0, 10.0] }
velocity = { min = [-1.0, -1.0], max = [1.0, 1.0] }
shape = { circle = { radius = 0.05 } }
color = "#3366cc"

[[force]]
kind = "drag"
bodies = ["dust"]

[[force]]
kind = "gravity"
bodies = ["dust17", "probe"]
"##;

#[test]
fn a_swarm_gives_the_same_bodies_for_the_same_seed_everywhere() {
    let s = scene(SWARM);
    assert_eq!(s.bodies.len(), 10_001);
    assert_eq!(s.bodies[0].name, "probe");
    // Members follow the [[body]] bodies and are named by their number. The expected
    // values come from an independent SplitMix64 with the reference constants.
    let expect = [
        (
            0,
            [
                3.8982974839127147,
                0.1678829452815611,
                0.8015213612137668,
                0.16586058605615617,
            ],
        ),
        (
            17,
            [
                9.849697299722354,
                9.54085705342843,
                -0.27167713327906595,
                -0.9499023529005415,
            ],
        ),
        (
            9999,
            [
                9.697912297264907,
                9.416600594862928,
                -0.4227778117731753,
                0.2258063943628732,
            ],
        ),
    ];
    for (i, [x, y, vx, vy]) in expect {
        let b = &s.bodies[1 + i];
        assert_eq!(b.name, format!("dust{i}"));
        assert_eq!(b.position, DVec2::new(x, y), "dust{i}");
        assert_eq!(b.velocity, DVec2::new(vx, vy), "dust{i}");
        assert_eq!(b.mass, 1.0);
        assert_eq!(b.shape, Shape::Circle { radius: 0.05 });
    }
}

#[test]
fn growing_a_swarm_leaves_its_earlier_members_where_they_were() {
    let small = scene(&SWARM.replace("count = 10000", "count = 20"));
    let large = scene(SWARM);
    assert_eq!(small.bodies[..21], large.bodies[..21]);
}

#[test]
fn forces_select_a_whole_swarm_by_its_name_or_one_member() {
    let s = scene(SWARM);
    let selections: Vec<Selection> = s
        .forces
        .iter()
        .map(|f| match f {
            physframes::sim::ForceSpec::Drag { bodies, .. }
            | physframes::sim::ForceSpec::Gravity { bodies, .. } => bodies.clone(),
            other => panic!("unexpected force {other:?}"),
        })
        .collect();
    assert_eq!(
        selections,
        [
            Selection::Range {
                start: 1,
                end: 10_001
            },
            Selection::Bodies(vec![0, 18]),
        ]
    );
}

#[test]
fn swarm_mistakes_are_reported_with_their_place() {
    let check = |text: &str, needle: &str| {
        let e = match parse(std::path::Path::new("test.toml"), text) {
            Ok(_) => panic!("should be rejected: {needle}"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(needle), "expected `{needle}` in:\n{e}");
    };
    check(
        &SWARM.replace("\"dust17\"", "\"dust10000\""),
        "no body is named `dust10000`",
    );
    check(
        &SWARM
            .replace("name = \"probe\"", "name = \"dust3\"")
            .replace("\"probe\"]", "\"dust4\"]"),
        "body `dust3` has a name that swarm `dust` uses",
    );
    check(
        &SWARM.replace("name = \"dust\"", "name = \"dust2\""),
        "swarm name `dust2` cannot name members",
    );
    check(
        &SWARM.replace("count = 10000", "count = 0"),
        "`count` must be from 1",
    );
    check(
        &SWARM.replace("max = [10.0, 10.0]", "max = [-10.0, 10.0]"),
        "`position` has min above max",
    );
    check(
        &SWARM.replace("bodies = [\"dust\"]", "bodies = [\"dust\", \"dust5\"]"),
        "selects body `dust5` a second time",
    );
    let spring = format!(
        "{SWARM}\n[[force]]\nkind = \"spring\"\na = \"dust\"\nb = [0.0, 0.0]\nstiffness = 1.0\n"
    );
    check(&spring, "`dust` is a swarm of 10000 bodies, not one body");
}

/// A swarm large enough that the step runs on several threads, with every force family
/// that acts body by body, some on part of the swarm, and unequal masses.
fn big_swarm(extra: &str) -> Scene {
    scene(&format!(
        r##"
[simulation]
dt = 0.001
[render]
fps = 100
view = {{ min = [-10.0, -10.0], max = [10.0, 10.0] }}
[[body]]
name = "heavy"
mass = 3.0
position = [1.0, 2.0]
[[swarm]]
name = "a"
count = 150000
seed = 3
mass = 1.0
position = {{ min = [-5.0, -5.0], max = [5.0, 5.0] }}
velocity = {{ min = [-1.0, -1.0], max = [1.0, 1.0] }}
[[swarm]]
name = "b"
count = 70001
seed = 4
mass = 0.5
position = {{ min = [-5.0, -5.0], max = [5.0, 5.0] }}
[[force]]
kind = "gravity"
[[force]]
kind = "drag"
k = 0.3
bodies = ["a"]
[[force]]
kind = "quadratic-drag"
c = 0.01
bodies = ["b", "heavy"]
[[force]]
kind = "force"
f1 = [0.5, 0.0]
[[force]]
kind = "central"
strength = 2.0
bodies = ["a", "b"]
{extra}
"##
    ))
}

#[test]
fn the_step_gives_the_same_bits_for_any_thread_count_and_vector_width() {
    for extra in [
        "",
        "[[force]]\nkind = \"spring\"\na = \"a0\"\nb = \"b7\"\nstiffness = 4.0\n",
    ] {
        let s = big_swarm(extra);
        let one = run(&s, 12, 1);
        let two = run(&s, 12, 2);
        let three = run(&s, 12, 3);
        assert_same_bits(&one, &two, "1 and 2 threads");
        assert_same_bits(&one, &three, "1 and 3 threads");
        use_wide_vectors(false);
        let narrow = run(&s, 12, 2);
        use_wide_vectors(true);
        assert_same_bits(&one, &narrow, "with and without AVX2");
        assert!(one.pos.iter().any(|p| *p != DVec2::ZERO));
    }
}

#[test]
fn the_chunked_step_equals_explicit_euler_written_out() {
    // r(t + h) = r(t) + h·v(t); v(t + h) = v(t) + h·a(t), with a from the system's
    // whole-array accelerations: the fused, chunked, threaded step must match it.
    let s = big_swarm("");
    let system = s.system();
    let h = s.simulation.dt;
    let mut state = s.initial_state();
    let mut acc = vec![DVec2::ZERO; state.len()];
    for n in 0..5 {
        let t = n as f64 * h;
        system.accelerations(t, &state.pos, &state.vel, &mut acc);
        for ((r, v), a) in state.pos.iter_mut().zip(&mut state.vel).zip(&acc) {
            *r += h * *v;
            *v += h * *a;
        }
    }
    assert_same_bits(&state, &run(&s, 5, 2), "written out and chunked");
}

#[test]
fn a_blow_up_inside_a_swarm_is_still_found_and_named() {
    let s = scene(
        r##"
[simulation]
dt = 0.01
[render]
fps = 10
view = { min = [0.0, 0.0], max = [1.0, 1.0] }
[[swarm]]
name = "dust"
count = 100000
seed = 1
mass = 1.0
position = { min = [0.0, 0.0], max = [1.0, 1.0] }
velocity = { min = [1.0, 1.0], max = [2.0, 2.0] }
[[force]]
kind = "drag"
k = 1000.0
bodies = ["dust99999"]
"##,
    );
    let mut sim = Simulation::new(
        s.system(),
        s.initial_state(),
        s.simulation.integrator,
        s.simulation.dt,
    );
    let b = sim.run_steps(1000).expect_err("h·k/m = 10 blows up");
    assert_eq!(b.body, 99_999);
    assert_eq!(b.quantity, "velocity");
}

#[test]
fn a_stamped_sprite_equals_its_paths_drawn_at_the_snapped_position() {
    let camera = Camera::fit(
        physframes::scene::View {
            min: DVec2::ZERO,
            max: DVec2::new(16.0, 9.0),
        },
        1280,
        720,
    );
    let s = scene(SWARM);
    let shapes = [
        (Shape::Circle { radius: 0.03 }, [0x33, 0x66, 0xcc, 0xff]),
        (Shape::Circle { radius: 0.2 }, [0xcc, 0x33, 0x33, 0x80]),
        (
            Shape::Box {
                width: 0.3,
                height: 0.1,
            },
            [0x2c, 0xa0, 0x2c, 0xff],
        ),
        (
            Shape::Polygon {
                points: vec![
                    DVec2::new(-0.1, -0.05),
                    DVec2::new(0.12, -0.04),
                    DVec2::new(0.0, 0.1),
                ],
            },
            [0x94, 0x67, 0xbd, 0xc0],
        ),
    ];
    for (shape, color) in shapes {
        let mut body = s.bodies[1].clone();
        body.shape = shape.clone();
        body.color = physframes::scene::Rgba(color);
        let look = BodyLook::new(&body, &camera);
        let sheet = SpriteSheet::new(&look).expect("small enough to stamp");
        let on_grid = look.on_grid(GRID);
        let mut largest = 0;
        for k in 0..400u32 {
            // Positions on a 1/100-pixel lattice, so every phase is met.
            let x = 20.0 + (k % 20) as f32 * 1.01 + (k / 20) as f32 * 0.013;
            let y = 20.0 + (k / 20) as f32 * 1.07;
            let mut stamped = Pixmap::new(64, 64).expect("pixmap");
            stamped.fill(Color::from_rgba8(250, 240, 230, 255));
            let mut drawn = stamped.clone();
            sheet.stamp(&mut stamped, x, y);
            let snap = |v: f32| (v * PHASES as f32).round() / PHASES as f32;
            on_grid.draw(&mut drawn, snap(x), snap(y));
            largest = largest.max(diff(&stamped, &drawn).0);
        }
        assert!(largest <= 1, "{shape:?}: largest difference {largest}/255");
    }
}

#[test]
fn stamping_looks_like_drawing_every_path_at_its_exact_position() {
    // Against paths at unsnapped positions the difference is what moving a shape by at
    // most 1/16 pixel makes: tiny-skia samples coverage on a 4 × 4 grid, so an edge
    // pixel can change by up to 4 of its 16 samples (64/255); few pixels change.
    let text = std::fs::read_to_string(example("bench/circles-1000.toml")).expect("scene");
    stamped_against_paths(&scene(&text), 50_000, 3.0);
}

#[test]
fn discs_of_a_thousand_radii_are_stamped_and_look_like_their_paths() {
    // Every disc has a radius of its own, as when a user scatters balls of many sizes:
    // each is stamped from the sprite of its radius snapped to 1/8 pixel. The radius
    // and the position each move an edge by at most 1/16 pixel, together less than
    // the quarter pixel between tiny-skia's samples, so the largest difference is
    // bounded as for snapping the position alone. The mean grows: two independent
    // displacements of the same spread add in quadrature, so the bound on the mean is
    // √2 times the position's alone.
    let mut text = String::from(
        "[render]\nwidth = 1280\nheight = 720\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    let mut next = crate::util::uniform(12345);
    for _ in 0..1000 {
        let (px, py, r) = (
            0.5 + 15.0 * next(),
            0.5 + 8.0 * next(),
            0.03 + 0.07 * next(),
        );
        text += &format!(
            "[[body]]\nmass = 1.0\nposition = [{px}, {py}]\nshape = {{ circle = {{ radius = {r} }} }}\n"
        );
    }
    let s = scene(&text);
    let radii: std::collections::HashSet<u64> = s
        .bodies
        .iter()
        .map(|b| match b.shape {
            Shape::Circle { radius } => radius.to_bits(),
            _ => 0,
        })
        .collect();
    assert_eq!(radii.len(), 1000, "every radius its own");
    let looks = physframes::render::looks::Looks::new(
        &s.bodies,
        &Camera::fit(s.render.view, s.render.width, s.render.height),
        BodyDrawing::Sprites,
    );
    assert!(
        looks.looks.iter().all(|l| l.sprite.is_some()),
        "every disc is stamped"
    );
    stamped_against_paths(&s, 50_000, 3.0 * std::f64::consts::SQRT_2);
}

#[test]
fn discs_too_large_to_stamp_are_scanned_as_polygons_and_look_like_their_paths() {
    // Balls of many sizes, most of them too large for a sprite (a radius over 24
    // pixels), with the orientation line the stamped discs have on the turning ones
    // (32/255 from its path at most, `every_scene.rs`). Each disc is a polygon on the
    // curve of tiny-skia's circle (within 1/32 pixel) and its stroke the ring between
    // that curve moved 0.75 pixel out and in, so they differ from the paths only on
    // the rim, in two ways. Where a curve runs nearly level, a shift of a hundredth of
    // a pixel between tiny-skia's flattening of its curves and ours moves a sub-row's
    // crossing by a pixel: a quarter of a pixel's coverage, 64/255 of a channel at
    // most. And in opaque colours the ring's outer side is filled in the edge's
    // colour and its inner side in the fill's over it, which differs from the fill
    // then the stroke, where the fill's edge and a side of the ring cross one pixel,
    // by at most a quarter of the difference between the fill and what lies under it
    // (`raster::fill_layers`): 64/255 more at most; and where the orientation line's
    // cap meets the rim, its 32 more. Only pixels within a pixel of the three curves
    // (the rim, 3.5 pixels wide: 7πr pixels for a disc of radius r) or of an
    // orientation line (3.5·r) can differ.
    let s = large_bodies(2024, |next, _| {
        format!("{{ circle = {{ radius = {} }} }}", 0.2 + 0.7 * next())
    });
    let looks = physframes::render::looks::Looks::new(
        &s.bodies,
        &Camera::fit(s.render.view, s.render.width, s.render.height),
        BodyDrawing::Sprites,
    );
    let scanned = |fast: fn(&physframes::render::bodies::BodyLook) -> bool| {
        looks
            .looks
            .iter()
            .filter(|l| l.sprite.is_none() && fast(&l.body))
            .count()
    };
    let (still, turning) = (scanned(|b| b.draws_fast()), scanned(|b| b.rolls_fast()));
    assert!(
        still > 30 && turning > 30,
        "{still} still and {turning} turning discs drawn as polygons"
    );
    let rims = |b: &physframes::scene::Body| match b.shape {
        Shape::Circle { radius } => {
            let r = 80.0 * radius;
            7.0 * std::f64::consts::PI * r + if b.turns { 3.5 * r } else { 0.0 }
        }
        _ => 0.0,
    };
    large_against_paths(&s, "discs", 64 + 64 + 32, rims);
}

#[test]
fn boxes_and_polygons_too_large_to_stamp_are_filled_in_layers_and_look_like_their_paths() {
    // Crates and wedges too large for a sprite (over 24 pixels from the centre to a
    // corner). They are scanned as smaller ones are, whose stroke differs from
    // tiny-skia's only where its round joins are cut into chords, by 29/255 at most
    // (`every_scene.rs`); in opaque colours the ring's outer side is filled in the
    // edge's colour and its inner side over it in the fill's, which adds at most a
    // quarter of the fill's difference from what lies under it, where the fill's edge
    // crosses a pixel (`raster::fill_layers`): 64/255. Only pixels within a pixel of
    // the three outlines (the fill's edge and the ring's two sides, 3.5 pixels in all)
    // can differ.
    let s = large_bodies(77, |next, k| {
        let (w, h) = (0.5 + 0.8 * next(), 0.5 + 0.8 * next());
        if k % 3 == 0 {
            format!("{{ polygon = {{ points = [[0.0, 0.0], [{w}, 0.1], [0.2, {h}]] }} }}")
        } else {
            format!("{{ box = {{ width = {w}, height = {h} }} }}")
        }
    });
    let rims = |b: &physframes::scene::Body| {
        let perimeter = match &b.shape {
            Shape::Box { width, height } => 2.0 * (width + height),
            Shape::Polygon { points } => (0..points.len())
                .map(|i| (points[(i + 1) % points.len()] - points[i]).length())
                .sum(),
            _ => 0.0,
        };
        3.5 * 80.0 * perimeter
    };
    large_against_paths(&s, "boxes and wedges", 29 + 64, rims);
}

/// A 1280 × 720 scene (80 pixels a world unit) of 120 bodies of `shape(next, k)`, as a
/// user writes them: at random places and angles, in the default colours but every
/// tenth translucent (its stroke then goes through the ring's scan, not two fills),
/// every other one turning.
fn large_bodies(seed: u64, shape: impl Fn(&mut dyn FnMut() -> f64, usize) -> String) -> Scene {
    let mut text = String::from(
        "[render]\nwidth = 1280\nheight = 720\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    let mut next = crate::util::uniform(seed);
    for k in 0..120 {
        let (px, py) = (0.5 + 15.0 * next(), 0.5 + 8.0 * next());
        let shape = shape(&mut next, k);
        let angle = 6.0 * next();
        let color = if k % 10 == 0 {
            "color = \"#3366cc80\"\n"
        } else {
            ""
        };
        let turning = if k % 2 == 1 {
            "angular_velocity = 1.0\n"
        } else {
            ""
        };
        text += &format!(
            "[[body]]\nmass = 1.0\nposition = [{px}, {py}]\nshape = {shape}\nangle = {angle}\n{color}{turning}"
        );
    }
    scene(&text)
}

/// Draws the scene's first frame the fast ways and as paths, and checks that no channel
/// differs by more than `largest`/255, and that fewer pixels differ than lie on the
/// bodies' rims (`rims` of each body, in pixels), of the more than 300,000 covered.
fn large_against_paths(
    s: &Scene,
    what: &str,
    bound: u8,
    rims: impl Fn(&physframes::scene::Body) -> f64,
) {
    let (fast, paths, _) = crate::util::first_frame_both_ways(s);
    let (largest, count) = diff(&fast, &paths);
    let covered = paths
        .pixels()
        .iter()
        .filter(|p| (p.red(), p.green(), p.blue()) != (255, 255, 255))
        .count();
    eprintln!(
        "large {what} against exact paths: largest {largest}/255, {count} of {covered} covered pixels differ"
    );
    assert!(largest <= bound, "largest difference {largest}/255");
    let rims: f64 = s.bodies.iter().map(rims).sum();
    assert!(
        (count as f64) < rims,
        "{count} pixels differ, {rims} on the rims"
    );
    assert!(covered > 300_000, "the {what} cover {covered} pixels");
}

/// Draws the scene's first frame with sprites and with paths, and checks that they
/// differ as moving each edge by less than a quarter pixel may: no channel by more
/// than 64/255, and by less than `mean_bound`/255 on average over the `min_touched` or
/// more pixels the bodies touch.
fn stamped_against_paths(s: &Scene, min_touched: usize, mean_bound: f64) {
    let (stamped, drawn, _) = crate::util::first_frame_both_ways(s);
    let (largest, count) = diff(&stamped, &drawn);
    let touched: Vec<usize> = (0..drawn.pixels().len())
        .filter(|&i| drawn.pixels()[i] != stamped.pixels()[i] || drawn.pixels()[i].red() != 255)
        .collect();
    // The mean difference, over the pixels the circles touch, of the largest channel.
    let total: u64 = touched
        .iter()
        .map(|&i| {
            let (p, q) = (drawn.pixels()[i], stamped.pixels()[i]);
            u64::from(
                p.red()
                    .abs_diff(q.red())
                    .max(p.green().abs_diff(q.green()))
                    .max(p.blue().abs_diff(q.blue())),
            )
        })
        .sum();
    let mean = total as f64 / touched.len() as f64;
    eprintln!(
        "sprites against exact paths: largest {largest}/255, {count} of {} touched pixels differ, mean {mean:.2}/255",
        touched.len()
    );
    assert!(largest <= 64, "largest difference {largest}/255");
    assert!(
        mean < mean_bound,
        "mean difference {mean}/255 over the circles"
    );
    assert!(
        touched.len() > min_touched,
        "the circles cover {} pixels",
        touched.len()
    );
}

#[test]
fn a_frame_drawn_into_a_reused_pixmap_equals_a_fresh_one_and_skips_what_is_outside() {
    let s = scene(SWARM);
    let renderer = Renderer::new(
        &s,
        ArrowScales {
            velocity: 1.0,
            force: 1.0,
        },
    );
    let mut state = s.initial_state();
    let mut reused = renderer.new_frame();
    reused.fill(Color::from_rgba8(1, 2, 3, 255));
    fn view(state: &State) -> FrameView<'_> {
        FrameView {
            index: 0,
            t: 0.0,
            pos: &state.pos,
            vel: &[],
            angle: None,
            force: None,
            trail: None,
            traces: None,
            compare: None,
        }
    }
    renderer.draw_into(&view(&state), &mut reused);
    assert_eq!(reused.data(), renderer.draw(&view(&state)).data());
    // Far outside the image, or not a number: nothing is drawn.
    for p in state.pos.iter_mut() {
        *p = DVec2::new(-1e30, f64::NAN);
    }
    assert_eq!(
        renderer.draw(&view(&state)).data(),
        renderer.new_frame().data()
    );
}

#[test]
fn a_swarm_renders_the_same_bytes_with_any_number_of_threads() {
    let sandbox = Sandbox::new();
    let scene_path = example("bench/circles-1000.toml");
    for (dir, threads) in [("a", "1"), ("b", "2"), ("c", "3")] {
        let out = sandbox.run(&[
            "render",
            &scene_path,
            "--out",
            dir,
            "--threads",
            threads,
            "--frames",
            "0..12",
            "--quiet",
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    }
    for k in 0..12 {
        let name = format!("frame_{k:06}.png");
        let a = std::fs::read(sandbox.path(&format!("a/{name}"))).expect("a");
        for other in ["b", "c"] {
            let b = std::fs::read(sandbox.path(&format!("{other}/{name}"))).expect("b");
            assert!(a == b, "{name} differs between 1 and {other} threads");
        }
    }
}

#[test]
fn bench_prints_frames_per_second_and_nanoseconds_per_body_step() {
    let sandbox = Sandbox::new();
    let scene_path = example("drag.toml");
    let out = sandbox.run(&["bench", &scene_path, "--repeat", "1", "--frames", "0..5"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("frames/s") && text.contains("bytes/frame"),
        "{text}"
    );
    let row = text
        .lines()
        .find(|l| l.starts_with("drag "))
        .unwrap_or_else(|| panic!("no row for drag in:\n{text}"));
    let fields: Vec<&str> = row.split_whitespace().collect();
    assert_eq!(fields[1..3], ["3", "5"], "{row}");
    assert!(fields[3].parse::<f64>().is_ok_and(|f| f > 0.0), "{row}");
    let out = sandbox.run(&["bench", &scene_path, "--repeat", "2", "--simulate-only"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let row = text
        .lines()
        .find(|l| l.starts_with("drag "))
        .unwrap_or_else(|| panic!("no row for drag in:\n{text}"));
    let fields: Vec<&str> = row.split_whitespace().collect();
    assert_eq!(fields[1..3], ["3", "500"], "{row}");
    assert!(text.contains("ns/body-step"), "{text}");
    // Explicit Euler under drag on bodies of equal mass: the hand-written loop of the
    // same physics is timed too, with the ratio of the pipeline's time to its.
    let hand = text
        .lines()
        .find(|l| l.trim_start().starts_with("hand-written loop"))
        .unwrap_or_else(|| panic!("no hand-written row in:\n{text}"));
    let fields: Vec<&str> = hand.split_whitespace().collect();
    assert_eq!(fields[2..4], ["3", "500"], "{hand}");
    assert_eq!(fields[fields.len() - 2], "pipeline/hand-written", "{hand}");
    let ratio = fields[fields.len() - 1].parse::<f64>();
    assert!(ratio.is_ok_and(|r| r > 0.0), "{hand}");
    // Springs are not what the hand-written loop computes: no such row.
    let out = sandbox.run(&[
        "bench",
        &example("spring.toml"),
        "--repeat",
        "1",
        "--simulate-only",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.lines().any(|l| l.starts_with("spring ")), "{text}");
    assert!(!text.contains("hand-written"), "{text}");
    // It writes nothing where it runs.
    assert!(sandbox.list(".").is_empty(), "{:?}", sandbox.list("."));
}

#[test]
fn bench_gives_each_scene_the_median_of_its_ratios_round_by_round_and_their_range() {
    let sandbox = Sandbox::new();
    let (drag, spring) = (example("drag.toml"), example("spring.toml"));
    let bench = |repeat: &str| {
        let out = sandbox.run(&[
            "bench",
            &spring,
            "--reference",
            &drag,
            "--repeat",
            repeat,
            "--frames",
            "0..3",
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        stdout(&out)
    };
    let row = |text: &str, name: &str| -> Vec<String> {
        text.lines()
            .find(|l| l.starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("no row for {name} in:\n{text}"))
            .split_whitespace()
            .map(str::to_string)
            .collect()
    };
    let text = bench("3");
    // The scene's row: the median of three rounds, which lies between the lowest and
    // the highest, printed after the row.
    let other = row(&text, "spring");
    let ratio: f64 = other[4].parse().expect("a ratio");
    let n = other.len();
    assert_eq!(
        other[n - 4..n - 2],
        ["rounds".to_string(), other[n - 3].clone()]
    );
    assert_eq!(other[n - 2], "to", "{text}");
    let low: f64 = other[n - 3].parse().expect("the lowest round");
    let high: f64 = other[n - 1].parse().expect("the highest round");
    assert!(
        0.0 < low && low <= ratio && ratio <= high && high.is_finite(),
        "{text}"
    );
    assert!(text.contains("the median of the rounds"), "{text}");
    // One round has no range to give.
    let text = bench("1");
    assert!(!text.contains("rounds "), "{text}");
    let other = row(&text, "spring");
    assert!(other[4].parse::<f64>().is_ok_and(|r| r > 0.0), "{text}");
}

#[test]
fn bench_with_out_keeps_only_the_last_runs_frames_of_each_scene() {
    let sandbox = Sandbox::new();
    let scene_path = example("drag.toml");
    let bench = |frames: &str, out: &str| {
        sandbox.run(&[
            "bench",
            &scene_path,
            "--repeat",
            "2",
            "--frames",
            frames,
            "--out",
            out,
        ])
    };
    let out = bench("0..3", "b");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // Each run rendered into its own temporary folder; only the last run's is left,
    // under the scene's name.
    assert_eq!(sandbox.list("b"), ["drag"]);
    assert_eq!(
        sandbox.frames("b/drag"),
        ["frame_000000.png", "frame_000001.png", "frame_000002.png"]
    );
    assert_eq!(sandbox.manifest("b/drag")["frames_written"], 3);
    // A second bench replaces the folder rather than adding to it or beside it.
    let out = bench("0..2", "b");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(sandbox.list("b"), ["drag"]);
    assert_eq!(
        sandbox.frames("b/drag"),
        ["frame_000000.png", "frame_000001.png"]
    );
    // A folder of the scene's name that bench did not keep, such as a render's, is
    // never replaced: the bench stops before measuring, and leaves nothing behind.
    sandbox.write("c/drag/frame_000000.png", "not bench's");
    let out = bench("0..3", "c");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("not written by"), "{}", stderr(&out));
    assert_eq!(sandbox.list("c"), ["drag"]);
    assert_eq!(sandbox.list("c/drag"), ["frame_000000.png"]);
}

#[test]
fn frames_compressed_with_reused_static_tiles_decode_to_the_same_pixels() {
    let text = std::fs::read_to_string(example("bench/circles-1000.toml")).expect("scene");
    // Many bodies touch every row; three leave most rows as the static layer drew them.
    for s in [
        scene(&text),
        scene(&text.replace("count = 1000", "count = 3")),
    ] {
        check_static_tiles(&s);
    }
}

fn check_static_tiles(s: &Scene) {
    use physframes::pipeline::{render_prepared, RenderOptions};
    use physframes::render::bodies::draw_arrow;
    use physframes::render::Compression;

    // A static layer of arrows, as a vector field would draw.
    let field = |r: &mut Renderer| {
        let clip = *r.clip();
        let layer = r.static_layer_mut();
        for k in 0..300 {
            let (x, y) = (f64::from(k % 30) * 43.0, f64::from(k / 30) * 71.0 + 9.0);
            let grey = Color::from_rgba8(0x88, 0x88, 0x88, 0xff);
            draw_arrow(
                layer,
                &clip,
                (x, y),
                (25.0, 9.0 - f64::from(k % 7)),
                grey,
                1.0,
            );
        }
    };
    let sandbox = Sandbox::new();
    for (dir, compression) in [("tiles", Compression::Fast), ("png", Compression::Fastest)] {
        let options = RenderOptions {
            out_dir: sandbox.path(dir),
            frames: Some(0..8),
            threads: 2,
            compression,
            progress: false,
        };
        render_prepared(s, &options, field).expect("renders");
    }
    for k in 0..8 {
        let name = format!("frame_{k:06}.png");
        let a = image::open(sandbox.path(&format!("tiles/{name}"))).expect("decodes");
        let b = image::open(sandbox.path(&format!("png/{name}"))).expect("decodes");
        assert!(a.to_rgba8() == b.to_rgba8(), "{name}: pixels differ");
    }
}

#[test]
fn drawing_from_the_last_frames_damage_gives_the_pixels_of_a_whole_redraw() {
    // 20 stamped circles and six bodies drawn as paths (a box, a box at a fixed
    // angle, a polygon, a thin sharp one, a body of two point masses, a larger
    // circle), some crossing the edges,
    // moving over a static layer with detail; one pixmap reused from frame to frame as
    // a render's workers do. A body that never turns marks the box of its outline,
    // grown for its stroke and a pixel more (the box grown by less than the stroke's
    // half-width fails this test). Their rectangles stay under a quarter of the
    // frame, past which the damage would be whole.
    const BODIES: &str = r##"
[render]
width = 160
height = 90
view = { min = [0.0, 0.0], max = [16.0, 9.0] }
[[body]]
name = "box"
mass = 1.0
position = [3.0, 3.0]
shape = { box = { width = 1.2, height = 0.5 } }
[[body]]
name = "crate"
mass = 1.0
position = [6.0, 7.0]
angle = 0.7
shape = { box = { width = 0.9, height = 0.3 } }
[[body]]
name = "wedge"
mass = 1.0
position = [12.0, 6.0]
shape = { polygon = { points = [[0.0, 0.0], [0.8, 0.1], [0.2, 0.6]] } }
[[body]]
name = "needle"
mass = 1.0
position = [9.0, 2.0]
shape = { polygon = { points = [[-0.9, 0.0], [0.9, 0.05], [0.0, 0.12]] } }
[[body]]
name = "dumbbell"
position = [13.0, 2.5]
angle = 0.4
points = [{ offset = [-0.6, 0.0], mass = 1.0 }, { offset = [0.5, 0.2], mass = 2.0 }]
[[body]]
name = "big"
mass = 1.0
position = [8.0, 4.5]
shape = { circle = { radius = 0.6 } }
[[swarm]]
name = "dust"
count = 20
seed = 3
mass = 1.0
position = { min = [-0.5, -0.5], max = [16.5, 9.5] }
shape = { circle = { radius = 0.15 } }
"##;
    // Alone, and under axes and a field drawn once (frames then also wipe bodies
    // from the margins, which keeps the damage a cover of every change).
    check_damage(&scene(BODIES));
    check_damage(&scene(&format!(
        "{BODIES}\n[axes]\ntitle = \"t\"\n[[field]]\nkind = \"vector\"\nf = [\"-y\", \"x\"]\n"
    )));
    // With the HUD, whose text changes every frame: its box joins the damage, alone
    // and inside a plot (in a larger frame, where the box is a small part of it).
    let hud = BODIES.replace(
        "width = 160\nheight = 90\n",
        "width = 480\nheight = 270\nhud = true\n",
    );
    assert!(hud.contains("hud = true"), "the HUD is on");
    check_damage(&scene(&hud));
    check_damage(&scene(&format!("{hud}\n[axes]\ntitle = \"t\"\n")));
    // With springs shown, each coil in the box around its ends grown by its reach:
    // two drawn as tiny-skia's strokes, between bodies and to a fixed point, and 20
    // covered by distance, the others from members of the swarm to fixed points near
    // them; alone and under axes.
    let shown = hud.replacen(
        "width = 480\nheight = 270\nhud = true\n",
        "width = 960\nheight = 540\nhud = true\nshow_springs = true\n",
        1,
    );
    let two = "[[force]]\nkind = \"spring\"\na = \"box\"\nb = \"crate\"\nstiffness = 1.0\n\
        [[force]]\nkind = \"spring\"\na = \"wedge\"\nb = [11.0, 5.0]\nstiffness = 1.0\n";
    let dust = &scene(&shown).initial_state().pos[6..];
    let many: String = (0..18)
        .map(|i| {
            let to = dust[i] + DVec2::new(0.2, 0.15);
            format!(
                "[[force]]\nkind = \"spring\"\na = \"dust{i}\"\nb = [{}, {}]\nstiffness = 1.0\n",
                to.x, to.y
            )
        })
        .collect();
    for springs in [format!("{shown}\n{two}"), format!("{shown}\n{two}{many}")] {
        assert!(springs.contains("show_springs"), "springs shown");
        // (Moving a fifth as far, so that the coils stay short enough for their boxes
        // to stay under a quarter of the frame.)
        check_damage_moving(&scene(&springs), 0.2);
        check_damage_moving(&scene(&format!("{springs}\n[axes]\ntitle = \"t\"\n")), 0.2);
    }
    // With a legend, drawn over the bodies every frame in a box the damage holds, as
    // the HUD's, in a corner where bodies pass under it.
    for corner in ["top-right", "bottom-left"] {
        check_damage(&scene(&format!(
            "{hud}\n[axes]\ntitle = \"t\"\nlegend = \"{corner}\"\n{LEGEND_CURVE}"
        )));
    }
}

/// A curve with a label, which a scene's legend lists.
const LEGEND_CURVE: &str =
    "[[curve]]\nkind = \"exact\"\ny = \"0.5*x\"\nlabel = \"y = x/2, a long label\"\n";

#[test]
fn frames_under_axes_keep_their_margins_when_the_damage_is_whole() {
    // Large bodies, some across the plot's edges, whose rectangles pass a quarter of
    // the frame (the damage is then whole), with springs and without: every pixel
    // outside the plot is the static layer's in every frame, as the invariant of
    // frames with axes asks. (A whole damage once skipped wiping the margins.)
    let mut text = String::from(
        "[render]\nwidth = 480\nheight = 270\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n\
         [axes]\ntitle = \"Margins\"\nx_label = \"x\"\ny_label = \"y\"\n",
    );
    for i in 0..24 {
        let (x, y) = ((i * 7 % 17) as f64 - 0.5, (i * 5 % 10) as f64 - 0.5);
        text.push_str(&format!(
            "[[body]]\nname = \"b{i}\"\nmass = 1.0\nposition = [{x}, {y}]\nshape = {{ circle = {{ radius = 1.1 }} }}\n"
        ));
    }
    let springs: String = (0..6)
        .map(|i| {
            format!(
                "[[force]]\nkind = \"spring\"\na = \"b{i}\"\nb = \"b{}\"\nstiffness = 1.0\n",
                i + 6
            )
        })
        .collect();
    let shown = text.replacen("[render]\n", "[render]\nshow_springs = true\n", 1);
    for text in [text.clone(), format!("{shown}{springs}")] {
        let s = scene(&text);
        let renderer = Renderer::new(
            &s,
            ArrowScales {
                velocity: 1.0,
                force: 1.0,
            },
        );
        let area = renderer.overlay().body_area().expect("a plot with bodies");
        let inside = |x: i32, y: i32| {
            (area.left()..area.right()).contains(&x) && (area.top()..area.bottom()).contains(&y)
        };
        let initial = s.initial_state();
        let mut pixmap = renderer.new_frame();
        let mut damage = physframes::render::Damage::default();
        let mut whole_seen = false;
        for k in 0..6 {
            let pos: Vec<DVec2> = initial
                .pos
                .iter()
                .enumerate()
                .map(|(i, p)| *p + k as f64 * DVec2::new(0.05 * (i % 3) as f64, -0.07))
                .collect();
            let view = FrameView {
                index: k,
                t: 0.0,
                pos: &pos,
                vel: &[],
                angle: None,
                force: None,
                trail: None,
                traces: None,
                compare: None,
            };
            renderer.draw_damaged(&view, &mut pixmap, &mut damage);
            whole_seen |= damage.is_whole();
            let width = pixmap.width() as usize;
            let layer = renderer.static_layer().data();
            for (j, (a, b)) in pixmap.data().chunks(4).zip(layer.chunks(4)).enumerate() {
                let (x, y) = ((j % width) as i32, (j / width) as i32);
                assert!(
                    inside(x, y) || a == b,
                    "frame {k}: margin pixel ({x}, {y}) is not the static layer's"
                );
            }
        }
        assert!(whole_seen, "the damage should pass a quarter of the frame");
    }
}

/// Draws a dozen frames of moving bodies into one reused pixmap from the last frame's
/// damage, and checks each against a whole redraw and against its own damage.
fn check_damage(s: &Scene) {
    check_damage_moving(s, 1.0);
}

/// [`check_damage`], the bodies moving `speed` times as far from frame to frame.
fn check_damage_moving(s: &Scene, speed: f64) {
    let mut renderer = Renderer::new(
        s,
        ArrowScales {
            velocity: 1.0,
            force: 1.0,
        },
    );
    {
        let clip = *renderer.clip();
        let layer = renderer.static_layer_mut();
        for k in 0..12 {
            let at = (13.0 * k as f64, 7.0 * k as f64);
            let grey = Color::from_rgba8(0x88, 0x88, 0x88, 0xff);
            physframes::render::bodies::draw_arrow(layer, &clip, at, (20.0, 9.0), grey, 1.0);
        }
    }
    let initial = s.initial_state();
    let mut pixmap = renderer.new_frame();
    let mut damage = physframes::render::Damage::default();
    let mut damaged_some = false;
    for k in 0..12 {
        // Each body moves on its own line, some by fractions of a pixel, some by many.
        let pos: Vec<DVec2> = initial
            .pos
            .iter()
            .enumerate()
            .map(|(i, p)| {
                *p + speed * k as f64 * DVec2::new(0.013 * i as f64, -0.071 * (i % 5) as f64)
            })
            .collect();
        let view = FrameView {
            index: k,
            t: 0.0,
            pos: &pos,
            vel: &[],
            angle: None,
            force: None,
            trail: None,
            traces: None,
            compare: None,
        };
        renderer.draw_damaged(&view, &mut pixmap, &mut damage);
        let whole = renderer.draw(&view);
        // And those are the pixels of every pass drawn over the whole frame (the
        // path shared by redraws could hide a mistake from the comparison above).
        assert!(
            whole.data() == renderer.draw_every_pass(&view).data(),
            "frame {k} differs from every pass drawn whole"
        );
        assert!(
            pixmap.data() == whole.data(),
            "frame {k} differs from a redraw"
        );
        // Outside the damage, every pixel is the static layer's.
        assert!(!damage.is_whole());
        let mut outside = renderer.static_layer().clone();
        let width = outside.width() as usize;
        for r in damage.rects() {
            for y in r.y0 as usize..r.y1 as usize {
                let row = 4 * y * width;
                let span = row + 4 * r.x0 as usize..row + 4 * r.x1 as usize;
                outside.data_mut()[span.clone()].copy_from_slice(&pixmap.data()[span]);
            }
        }
        assert!(
            outside.data() == pixmap.data(),
            "frame {k} drew outside its damage"
        );
        damaged_some |= !damage.rects().is_empty();
    }
    assert!(damaged_some);
}

#[test]
fn a_picture_of_point_masses_looks_like_its_paths_at_the_snapped_position() {
    // A body of point masses that never turns is laid over the frame as a picture of
    // its six paths drawn over transparent black. Against the paths drawn one after
    // another at the snapped position, what differs is the 8-bit rounding of each
    // blend (tiny-skia's div255 rounds up by at most one level): the paths round once
    // each over the frame, the picture once each over transparent black and once more
    // laid over the frame. At most four paths overlap at a pixel (a bar, a disc, its
    // outline, the marker's ring), so at most 4/255. Measured: 4/255, on a quarter of
    // the pixels the body covers.
    use physframes::render::picture::PictureSheet;
    use physframes::scene::PointMass;
    let camera = Camera::fit(
        physframes::scene::View {
            min: DVec2::ZERO,
            max: DVec2::new(16.0, 9.0),
        },
        1280,
        720,
    );
    let s = scene(SWARM);
    let mut body = s.bodies[1].clone();
    body.shape = Shape::Points {
        points: vec![
            PointMass {
                offset: DVec2::new(-0.1, 0.02),
                mass: 1.0,
            },
            PointMass {
                offset: DVec2::new(0.08, -0.03),
                mass: 3.0,
            },
        ],
    };
    body.color = physframes::scene::Rgba([0x1f, 0x77, 0xb4, 0xff]);
    let look = BodyLook::new(&body, &camera);
    assert!(look.has_points());
    let sheet = PictureSheet::new(&look, 24.0).expect("small enough");
    let (mut largest, mut count, mut covered) = (0, 0, 0);
    for k in 0..400u32 {
        let x = 24.0 + (k % 20) as f32 * 1.01 + (k / 20) as f32 * 0.013;
        let y = 24.0 + (k / 20) as f32 * 1.07;
        let mut stamped = Pixmap::new(72, 72).expect("pixmap");
        stamped.fill(Color::from_rgba8(250, 240, 230, 255));
        let mut drawn = stamped.clone();
        let background = stamped.clone();
        sheet.stamp(&mut stamped, x, y);
        let snap = |v: f32| (v * PHASES as f32).round() / PHASES as f32;
        look.draw(&mut drawn, snap(x), snap(y));
        let (l, c) = diff(&stamped, &drawn);
        largest = largest.max(l);
        count += c;
        covered += diff(&drawn, &background).1;
    }
    eprintln!("picture against paths at the snapped position: {count} of {covered} pixels differ, by {largest}/255 at most");
    assert!(covered > 20_000, "the body covers {covered} pixels");
    assert!(largest <= 4, "largest difference {largest}/255");
}

#[test]
fn ghost_rings_of_many_bodies_are_stamped_and_look_like_their_paths() {
    // 300 bodies compared with RK4: each frame rings the compared run's 300 positions.
    // From 16 ghosts on they are stamped from pictures of the ring at 8 × 8 sub-pixel
    // phases, which differ from the ring stroked at the exact position as moving it by
    // at most 1/16 pixel along each axis does, as every sprite (64/255 at most).
    let mut text = String::from(
        "[simulation]\nduration = 1.0\ncompare = [\"rk4\"]\n[render]\nwidth = 640\nheight = 360\nshow_bodies = false\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    let mut next = crate::util::uniform(4242);
    for _ in 0..300 {
        let (px, py, vx, vy) = (
            0.5 + 15.0 * next(),
            0.5 + 8.0 * next(),
            next() - 0.5,
            next() - 0.5,
        );
        text +=
            &format!("[[body]]\nmass = 1.0\nposition = [{px}, {py}]\nvelocity = [{vx}, {vy}]\n");
    }
    text += "[[force]]\nkind = \"drag\"\nk = 0.7\n";
    let s = scene(&text);
    let mut comparison = physframes::compare::Comparison::new(&s).expect("compare is set");
    let t = s.frame_time(5);
    let compared = comparison.advance_to(t);
    let state = s.initial_state();
    let view = FrameView {
        index: 5,
        t,
        pos: &state.pos,
        vel: &[],
        angle: None,
        force: None,
        trail: None,
        traces: None,
        compare: Some(&compared),
    };
    let (stamped, drawn, background) = crate::util::frame_both_ways(&s, &view);
    // Above the error strip (the bottom quarter, drawn alike both ways): the largest
    // channel difference, and its mean over the pixels the rings cover.
    let above = tiny_skia::IntRect::from_xywh(0, 0, 640, 360 - 360 / 4).expect("a rectangle");
    let top = |p: &tiny_skia::Pixmap| p.clone_rect(above).expect("inside");
    let (a, b, c) = (top(&stamped), top(&drawn), top(&background));
    let largest = diff(&a, &b).0;
    let covered = diff(&b, &c).1.max(diff(&a, &c).1);
    let mean = crate::util::total_difference(&a, &b) as f64 / covered as f64;
    eprintln!("ghost rings: {covered} pixels covered, by {mean:.2}/255 on average and {largest}/255 at most");
    assert!(covered > 20_000, "the rings cover {covered} pixels");
    // Stamped, not stroked: snapping moves some edge.
    assert!(largest > 0, "the rings are stamped");
    assert!(largest <= 64, "rings differ by {largest}/255");
    // Measured 5.0: every pixel of a ring two pixels wide is an edge pixel, where the
    // snap moves coverage, so the mean over them is above the discs' (3·√2 allowed).
    assert!(mean <= 6.0, "rings differ by {mean:.2}/255 on average");
    // The strip is the same both ways.
    let strip = tiny_skia::IntRect::from_xywh(0, 270, 640, 90).expect("a rectangle");
    assert!(
        stamped.clone_rect(strip) == drawn.clone_rect(strip),
        "the error strip"
    );
}
