//! Shared helpers: scenes from text, and the real binary run in a temporary folder.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use physframes::scene::{parse, Scene};

/// Parses scene text as if it were the file `test.toml`, failing the test with the
/// rendered diagnostics when it is invalid.
pub fn scene(text: &str) -> Scene {
    match parse(Path::new("test.toml"), text) {
        Ok(scene) => scene,
        Err(e) => panic!("the test scene should be valid:\n{e}"),
    }
}

/// A temporary folder in which the binary runs; removed when dropped.
pub struct Sandbox {
    pub dir: tempfile::TempDir,
}

impl Sandbox {
    pub fn new() -> Self {
        Sandbox {
            dir: tempfile::tempdir().expect("a temporary folder"),
        }
    }

    pub fn path(&self, relative: &str) -> PathBuf {
        self.dir.path().join(relative)
    }

    /// Writes a file into the sandbox and returns its path.
    pub fn write(&self, relative: &str, text: &str) -> PathBuf {
        let path = self.path(relative);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("create folders");
        }
        std::fs::write(&path, text).expect("write a test file");
        path
    }

    /// Runs `physframes` with `args` inside the sandbox.
    pub fn run(&self, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_physframes"))
            .args(args)
            .current_dir(self.dir.path())
            .output()
            .expect("the physframes binary runs")
    }

    /// Runs `physframes` with `args` inside the sandbox, with extra environment
    /// variables.
    pub fn run_with_env(&self, args: &[&str], env: &[(&str, &std::ffi::OsStr)]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_physframes"))
            .args(args)
            .envs(env.iter().copied())
            .current_dir(self.dir.path())
            .output()
            .expect("the physframes binary runs")
    }

    /// Starts `physframes` with `args` inside the sandbox without waiting for it; its
    /// output is discarded.
    pub fn spawn(&self, args: &[&str]) -> std::process::Child {
        Command::new(env!("CARGO_BIN_EXE_physframes"))
            .args(args)
            .current_dir(self.dir.path())
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("the physframes binary starts")
    }

    /// Returns the names of the PNG frames in a folder of the sandbox, sorted.
    pub fn frames(&self, relative: &str) -> Vec<String> {
        self.list(relative)
            .into_iter()
            .filter(|f| f.starts_with("frame_") && f.ends_with(".png"))
            .collect()
    }

    /// Reads `manifest.json` from a folder of the sandbox.
    pub fn manifest(&self, relative: &str) -> serde_json::Value {
        let path = self.path(relative).join("manifest.json");
        let text = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{} exists: {e}", path.display()));
        serde_json::from_str(&text).expect("manifest.json is JSON")
    }

    /// Asserts that two folders of the sandbox hold the same frames, byte for byte.
    pub fn assert_same_frames(&self, a: &str, b: &str) {
        let (fa, fb) = (self.frames(a), self.frames(b));
        assert_eq!(fa, fb, "{a} and {b} hold different frames");
        assert!(!fa.is_empty(), "{a} holds no frame");
        for f in &fa {
            let x = std::fs::read(self.path(a).join(f)).expect("frame");
            let y = std::fs::read(self.path(b).join(f)).expect("frame");
            assert!(x == y, "{f} differs between {a} and {b}");
        }
    }

    /// Lists the file names in a folder of the sandbox, sorted.
    pub fn list(&self, relative: &str) -> Vec<String> {
        let mut names: Vec<String> = match std::fs::read_dir(self.path(relative)) {
            Ok(entries) => entries
                .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
                .collect(),
            Err(_) => Vec::new(),
        };
        names.sort();
        names
    }
}

/// Returns the path of an example scene shipped in `scenes/`.
pub fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

/// Returns the process's standard error as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Returns the process's standard output as text.
pub fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A small valid scene that tests break one line at a time, or override.
pub const GOOD_SCENE: &str = r#"name = "t"
[simulation]
dt = 0.01
duration = 1.0
[render]
width = 64
height = 48
fps = 25
view = { min = [-1.0, -1.0], max = [1.0, 1.0] }
[[body]]
name = "puck"
mass = 1.0
velocity = [1.0, 0.0]
[[force]]
kind = "drag"
k = 1.0
"#;

/// Returns the largest channel difference between two pixmaps and how many pixels
/// differ at all.
pub fn diff(a: &tiny_skia::Pixmap, b: &tiny_skia::Pixmap) -> (u8, usize) {
    diff_beyond(a, b, 0)
}

/// Returns the largest channel difference between two pixmaps and how many pixels
/// differ by more than `slack` in some channel.
pub fn diff_beyond(a: &tiny_skia::Pixmap, b: &tiny_skia::Pixmap, slack: u8) -> (u8, usize) {
    let mut largest = 0;
    let mut count = 0;
    for (p, q) in a.data().chunks_exact(4).zip(b.data().chunks_exact(4)) {
        let d = p
            .iter()
            .zip(q)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        largest = largest.max(d);
        count += usize::from(d > slack);
    }
    (largest, count)
}

/// Returns the first pixel, as (x, y), that differs between two pixmaps of a mask's
/// size outside the tiles the mask marks; `None` when every change is marked.
pub fn change_outside(
    mask: &physframes::render::damage::TileMask,
    a: &tiny_skia::Pixmap,
    b: &tiny_skia::Pixmap,
) -> Option<(usize, usize)> {
    let width = a.width() as usize;
    for y in 0..a.height() as usize {
        for x in 0..width {
            let p = 4 * (y * width + x);
            let marked = mask.row(y)[x / 8 / 64] >> (x / 8 % 64) & 1 == 1;
            if !marked && a.data()[p..p + 4] != b.data()[p..p + 4] {
                return Some((x, y));
            }
        }
    }
    None
}

/// Returns the sum, over all pixels, of the largest channel difference between two
/// pixmaps: divided by the pixels a drawing covers, its mean difference there.
pub fn total_difference(a: &tiny_skia::Pixmap, b: &tiny_skia::Pixmap) -> u64 {
    a.data()
        .chunks_exact(4)
        .zip(b.data().chunks_exact(4))
        .map(|(p, q)| {
            u64::from(
                p.iter()
                    .zip(q)
                    .map(|(x, y)| x.abs_diff(*y))
                    .max()
                    .unwrap_or(0),
            )
        })
        .sum()
}

/// Draws a scene's first frame the fast ways (sprites, the scan converter, pictures)
/// and as tiny-skia's paths, and returns both and the frame without bodies.
pub fn first_frame_both_ways(
    s: &Scene,
) -> (tiny_skia::Pixmap, tiny_skia::Pixmap, tiny_skia::Pixmap) {
    let state = s.initial_state();
    let view = physframes::render::FrameView {
        index: 0,
        t: 0.0,
        pos: &state.pos,
        vel: &[],
        angle: Some(&state.angle),
        force: None,
        trail: None,
        traces: None,
        compare: None,
    };
    frame_both_ways(s, &view)
}

/// Draws `view` of a scene the fast ways and as tiny-skia's paths (arrows at one world
/// unit per unit), and returns both and the frame without bodies.
pub fn frame_both_ways(
    s: &Scene,
    view: &physframes::render::FrameView<'_>,
) -> (tiny_skia::Pixmap, tiny_skia::Pixmap, tiny_skia::Pixmap) {
    use physframes::render::{ArrowScales, BodyDrawing, Renderer};
    let arrows = ArrowScales {
        velocity: 1.0,
        force: 1.0,
    };
    let fast = Renderer::with_drawing(s, arrows, BodyDrawing::Sprites).draw(view);
    let paths = Renderer::with_drawing(s, arrows, BodyDrawing::Paths);
    (fast, paths.draw(view), paths.new_frame())
}

/// A seeded generator of numbers in (0, 1) (Park and Miller's minimal standard), for
/// scenes of many bodies that every run draws alike.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut x = seed;
    move || {
        x = x * 16807 % 2_147_483_647;
        x as f64 / 2_147_483_647.0
    }
}

/// Returns the state after `steps` steps of the scene's integrator on a pool of
/// `threads`.
pub fn run(scene: &Scene, steps: u64, threads: usize) -> physframes::sim::State {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let mut sim = physframes::sim::Simulation::new(
        scene.system(),
        scene.initial_state(),
        scene.simulation.integrator,
        scene.simulation.dt,
    );
    pool.install(|| sim.run_steps(steps)).expect("finite");
    sim.state().clone()
}

/// Compares two states bit for bit, naming the first body that differs.
pub fn assert_same_bits(a: &physframes::sim::State, b: &physframes::sim::State, what: &str) {
    for (i, ((pa, va), (pb, vb))) in a
        .pos
        .iter()
        .zip(&a.vel)
        .zip(b.pos.iter().zip(&b.vel))
        .enumerate()
    {
        let bits = |v: &glam::DVec2| (v.x.to_bits(), v.y.to_bits());
        assert!(
            bits(pa) == bits(pb) && bits(va) == bits(vb),
            "{what}: body {i} differs: {pa:?} {va:?} vs {pb:?} {vb:?}"
        );
    }
}

/// Renders the scene at `path` whole (with `single` added) and again as two shards
/// (each with its `shards` flags added) that start from checkpoints written every
/// `every` frames, and checks that the second shard started from a checkpoint and that
/// the frames are the same bytes.
pub fn assert_shards_equal_a_single_run(
    path: &str,
    every: &str,
    single: &[&str],
    shards: [&[&str]; 2],
) {
    let dir = Sandbox::new();
    let out_single = dir.path("single");
    let mut args = vec!["render", path, "--out", out_single.to_str().expect("utf-8")];
    args.extend_from_slice(single);
    let out = dir.run(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let frames = dir.frames("single").len();
    let ck = dir.path("ck");
    let ck = ck.to_str().expect("utf-8");
    let out = dir.run(&["checkpoint", path, "--every", every, "--checkpoint-dir", ck]);
    assert!(out.status.success(), "{}", stderr(&out));
    let half = frames / 2;
    let sharded = dir.path("sharded");
    for (range, extra) in [format!("..{half}"), format!("{half}..")]
        .iter()
        .zip(shards)
    {
        let mut args = vec![
            "render",
            path,
            "--out",
            sharded.to_str().expect("utf-8"),
            "--frames",
            range,
            "--checkpoint-dir",
            ck,
        ];
        args.extend_from_slice(extra);
        let out = dir.run(&args);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    assert!(dir.manifest("sharded")["started_from_frame"].as_u64() > Some(0));
    dir.assert_same_frames("single", "sharded");
}
