//! The real binary on the example scenes: frames, manifest, provenance, determinism,
//! frame ranges, stale frames, blow-ups and CSV export.

use std::path::Path;

use physframes::sim::Simulation;

use crate::util::{example, scene, stderr, stdout, Sandbox};

const EXAMPLES: &[(&str, u64)] = &[
    ("projectile.toml", 101),
    ("drag.toml", 126),
    ("terminal-velocity.toml", 101),
    ("spring.toml", 151),
    ("centre-of-mass.toml", 101),
    ("compare.toml", 51),
    ("drag-phase.toml", 126),
];

fn manifest(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).expect("manifest.json exists");
    serde_json::from_str(&text).expect("manifest.json is JSON")
}

/// Returns the iTXt chunks of a PNG file as (keyword, text) pairs.
fn text_chunks(path: &Path) -> Vec<(String, String)> {
    let file = std::fs::File::open(path).expect("frame exists");
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let reader = decoder.read_info().expect("a PNG");
    reader
        .info()
        .utf8_text
        .iter()
        .map(|c| (c.keyword.clone(), c.get_text().expect("text")))
        .collect()
}

#[test]
fn every_example_scene_renders_all_its_frames_and_a_manifest() {
    for (name, frames) in EXAMPLES {
        let sandbox = Sandbox::new();
        let out = sandbox.run(&["render", &example(name), "--out", "frames", "--quiet"]);
        assert_eq!(out.status.code(), Some(0), "{name}: {}", stderr(&out));
        let files = sandbox.list("frames");
        assert_eq!(
            files.len() as u64,
            frames + 1,
            "{name}: frames and manifest"
        );
        assert_eq!(files[0], "frame_000000.png");
        assert_eq!(
            files[*frames as usize - 1],
            format!("frame_{:06}.png", frames - 1)
        );
        let m = manifest(&sandbox.path("frames/manifest.json"));
        assert_eq!(m["frame_count"], *frames);
        assert_eq!(m["frames_written"], *frames);
        assert_eq!(m["status"], "complete");
        assert_eq!(m["integrator"], "euler");
        assert_eq!(m["width"], 800);
        assert_eq!(m["program_version"], env!("CARGO_PKG_VERSION"));
        assert_eq!(m["scene_hash"].as_str().map(str::len), Some(64));
        let last = sandbox.path(&format!("frames/frame_{:06}.png", frames - 1));
        let image = image::open(&last).expect("the last frame decodes");
        assert_eq!((image.width(), image.height()), (800, 600), "{name}");
    }
}

#[test]
fn the_default_output_folder_is_output_slash_scene_name() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["render", &example("drag.toml"), "--frames", "0..2"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        sandbox.list("output/drag"),
        vec!["frame_000000.png", "frame_000001.png", "manifest.json"]
    );
}

#[test]
fn every_frame_carries_its_provenance() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "render",
        &example("drag.toml"),
        "--out",
        "f",
        "--frames",
        "10",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let chunks = text_chunks(&sandbox.path("f/frame_000010.png"));
    let get = |k: &str| {
        chunks
            .iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.clone())
            .unwrap_or_else(|| panic!("no `{k}` chunk in {chunks:?}"))
    };
    assert_eq!(get("physframes:scene"), "drag");
    assert_eq!(get("physframes:integrator"), "euler");
    assert_eq!(get("physframes:dt"), "0.01");
    assert_eq!(get("physframes:t"), "0.4");
    assert_eq!(get("physframes:frame"), "10");
    let m = manifest(&sandbox.path("f/manifest.json"));
    assert_eq!(
        get("physframes:scene-hash"),
        m["scene_hash"].as_str().expect("hash")
    );
    assert!(get("Software").starts_with("physframes "));
}

#[test]
fn the_same_scene_gives_identical_bytes_on_every_run_and_thread_count() {
    let sandbox = Sandbox::new();
    for (dir, threads) in [("a", "1"), ("b", "2"), ("c", "3")] {
        let out = sandbox.run(&[
            "render",
            &example("spring.toml"),
            "--out",
            dir,
            "--threads",
            threads,
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    }
    let frames: Vec<String> = sandbox
        .list("a")
        .into_iter()
        .filter(|f| f.ends_with(".png"))
        .collect();
    assert_eq!(frames.len(), 151);
    for f in &frames {
        let a = std::fs::read(sandbox.path(&format!("a/{f}"))).expect("a");
        for other in ["b", "c"] {
            let b = std::fs::read(sandbox.path(&format!("{other}/{f}"))).expect("b");
            assert!(a == b, "{f} differs between runs");
        }
    }
}

#[test]
fn a_frame_range_draws_only_those_frames_and_leaves_the_rest() {
    let sandbox = Sandbox::new();
    std::fs::create_dir_all(sandbox.path("f")).expect("dir");
    sandbox.write("f/frame_000000.png", "an older frame outside the range");
    let out = sandbox.run(&[
        "render",
        &example("drag.toml"),
        "--out",
        "f",
        "--frames",
        "3..=5",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        sandbox.list("f"),
        vec![
            "frame_000000.png",
            "frame_000003.png",
            "frame_000004.png",
            "frame_000005.png",
            "manifest.json"
        ]
    );
    assert_eq!(
        std::fs::read_to_string(sandbox.path("f/frame_000000.png")).expect("kept"),
        "an older frame outside the range"
    );
    // A frame drawn alone equals the same frame of a full run: the simulation still
    // starts at t = 0.
    let full = sandbox.run(&["render", &example("drag.toml"), "--out", "full"]);
    assert_eq!(full.status.code(), Some(0));
    assert_eq!(
        std::fs::read(sandbox.path("f/frame_000004.png")).expect("ranged"),
        std::fs::read(sandbox.path("full/frame_000004.png")).expect("full")
    );
}

#[test]
fn frames_of_an_earlier_longer_run_do_not_stay_mixed_in() {
    let sandbox = Sandbox::new();
    let long = std::fs::read_to_string(example("drag.toml")).expect("example");
    let short = long.replace("duration = 5.0", "duration = 1.0");
    sandbox.write("drag.toml", &long);
    assert_eq!(
        sandbox
            .run(&["render", "drag.toml", "--out", "f"])
            .status
            .code(),
        Some(0)
    );
    assert_eq!(sandbox.list("f").len(), 127);
    sandbox.write("drag.toml", &short);
    assert_eq!(
        sandbox
            .run(&["render", "drag.toml", "--out", "f"])
            .status
            .code(),
        Some(0)
    );
    let files = sandbox.list("f");
    assert_eq!(files.len(), 27, "26 frames and the manifest: {files:?}");
    assert_eq!(files[25], "frame_000025.png");
}

#[test]
fn unstable_drag_is_stopped_by_its_growing_energy_at_the_first_frame() {
    // h·k/m = 10: |v| grows 9 times a step, so by frame 1 (step 4) the kinetic energy is
    // 9^8 ≈ 4.3e7 times its start, far past the limit of 10, and the run stops there.
    let text = std::fs::read_to_string(example("drag.toml"))
        .expect("example")
        .replace("k = 1.0", "k = 1000.0");
    let sandbox = Sandbox::new();
    sandbox.write("unstable.toml", &text);
    let out = sandbox.run(&["render", "unstable.toml", "--out", "f"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(err.contains("energy grew past 10 times"), "{err}");
    assert!(err.contains("body `fastest`"), "{err}");
    assert!(err.contains("dt ≤ 2·m/k = 0.002"), "{err}");
    let m = manifest(&sandbox.path("f/manifest.json"));
    assert_eq!(m["failure"]["step"], 4);
    assert_eq!(m["frames_written"], 1);
}

#[test]
fn a_blow_up_stops_with_the_body_step_and_exit_code_3() {
    // h·k/m = 0.01·1000 = 10: each step multiplies v by -9. The fastest puck (v0 = 9)
    // goes first: its drag force k·v = 1000·9·9^n passes f64::MAX ≈ 1.8e308 when
    // n > (308.25 - 3.95)/0.954 ≈ 319, so the velocity turns infinite at step 320.
    // A time-varying force (zero here) is an energy source, which turns the energy
    // watch off, so this run goes on until the state itself overflows.
    let text = std::fs::read_to_string(example("drag.toml"))
        .expect("example")
        .replace("k = 1.0", "k = 1000.0")
        + "\n[[force]]\nkind = \"force\"\n";
    let sandbox = Sandbox::new();
    sandbox.write("unstable.toml", &text);
    let out = sandbox.run(&["render", "unstable.toml", "--out", "f"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(err.contains("body `fastest`"), "{err}");
    assert!(err.contains("at step "), "{err}");
    assert!(err.contains("dt ≤ 2·m/k"), "{err}");
    let m = manifest(&sandbox.path("f/manifest.json"));
    assert_eq!(m["status"], "failed");
    assert_eq!(m["failure"]["kind"], "blow-up");
    assert_eq!(m["failure"]["body"], "fastest");
    let step = m["failure"]["step"].as_u64().expect("step");
    assert_eq!(step, 320);
    let written = m["frames_written"].as_u64().expect("count");
    let pngs: Vec<String> = sandbox
        .list("f")
        .into_iter()
        .filter(|f| f.ends_with(".png"))
        .collect();
    assert_eq!(pngs.len() as u64, written);
    assert_eq!(written, step / 4 + 1 - u64::from(step.is_multiple_of(4)));
    for f in &pngs {
        image::open(sandbox.path(&format!("f/{f}"))).expect("every frame written stays valid");
    }
}

#[test]
fn check_prints_a_summary() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["check", &example("spring.toml")]);
    assert_eq!(out.status.code(), Some(0));
    let text = stdout(&out);
    assert!(text.contains("scene `spring`"), "{text}");
    assert!(text.contains("3000 steps"), "{text}");
    assert!(text.contains("151 at 25 fps (20 steps a frame)"), "{text}");
    assert!(text.contains("bodies: 2"), "{text}");
    assert!(text.contains("forces: 1"), "{text}");
    assert!(!sandbox.path("output").exists(), "check writes nothing");
}

#[test]
fn export_writes_round_trip_numbers_equal_to_the_simulation() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["export", &example("spring.toml"), "--out", "t.csv"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let csv = std::fs::read_to_string(sandbox.path("t.csv")).expect("csv");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("t,body,x,y,vx,vy,angle,omega"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 151 * 2);
    // The last frame's rows equal the library's state bit for bit.
    let s = scene(&std::fs::read_to_string(example("spring.toml")).expect("example"));
    let mut sim = Simulation::new(
        s.system(),
        s.initial_state(),
        s.simulation.integrator,
        s.simulation.dt,
    );
    sim.run_steps(s.total_steps()).expect("finite");
    for (i, row) in rows[rows.len() - 2..].iter().enumerate() {
        let num = |j: usize| row[j].parse::<f64>().expect("a number");
        assert_eq!(row[1], s.bodies[i].name);
        assert_eq!(num(0), sim.state().t);
        assert_eq!(num(2), sim.state().pos[i].x);
        assert_eq!(num(3), sim.state().pos[i].y);
        assert_eq!(num(4), sim.state().vel[i].x);
        assert_eq!(num(5), sim.state().vel[i].y);
        // Nothing turns these bodies: every angle and angular velocity stays 0.
        assert_eq!((num(6), num(7)), (0.0, 0.0));
    }
    // --every-step: the initial state and one row set per step, to standard output.
    let out = sandbox.run(&["export", &example("spring.toml"), "--every-step"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out).lines().count(), 1 + (3000 + 1) * 2);
    assert!(!sandbox.path("output").exists(), "export draws nothing");
}

/// `--out` may name a named pipe or a device such as `/dev/null`: the bytes go into it,
/// and it stays what it was. (Renaming the finished file over it, as for a regular
/// file, once turned a machine's `/dev/null` into a regular file.) A pipe in the
/// sandbox stands for the device, so that a regression fails here and harms nothing.
#[cfg(unix)]
#[test]
fn export_into_a_pipe_writes_through_it_and_leaves_it_a_pipe() {
    use std::os::unix::fs::FileTypeExt;
    let sandbox = Sandbox::new();
    let pipe = sandbox.path("pipe");
    let made = std::process::Command::new("mkfifo").arg(&pipe).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("skipped: `mkfifo` is not available");
        return;
    }
    let reader = {
        let pipe = pipe.clone();
        std::thread::spawn(move || std::fs::read(pipe).expect("read the pipe"))
    };
    let out = sandbox.run(&["export", &example("spring.toml"), "--out", "pipe"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let kind = pipe.symlink_metadata().expect("the pipe").file_type();
    assert!(kind.is_fifo(), "the pipe was replaced by a regular file");
    let through_pipe = reader.join().expect("the reader");
    let out = sandbox.run(&["export", &example("spring.toml"), "--out", "t.csv"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let to_file = std::fs::read(sandbox.path("t.csv")).expect("csv");
    assert!(to_file.len() > 1000, "{} bytes", to_file.len());
    assert_eq!(through_pipe, to_file, "the same rows through the pipe");
}

#[test]
fn export_to_a_folder_is_refused_before_the_simulation() {
    let sandbox = Sandbox::new();
    std::fs::create_dir(sandbox.path("rows")).expect("a folder");
    let out = sandbox.run(&["export", &example("spring.toml"), "--out", "rows"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("rows is a folder"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn render_into_a_file_is_refused_with_what_to_do() {
    let sandbox = Sandbox::new();
    sandbox.write("frames", "not a folder");
    let out = sandbox.run(&["render", &example("spring.toml"), "--out", "frames"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("--out frames is not a folder"),
        "{}",
        stderr(&out)
    );
    assert_eq!(
        std::fs::read_to_string(sandbox.path("frames")).expect("kept"),
        "not a folder"
    );
}

#[test]
fn a_scene_too_stiff_for_dopri5_stops_with_a_message_instead_of_running_forever() {
    // k/m = 1e12: dopri5's step must stay under 3.3e-12 to be stable, so one frame of
    // 0.04 s would take about 1e10 steps; the budget of 1e6 steps stops it.
    let text = r#"
        [simulation]
        integrator = "dopri5"
        dt = 0.01
        duration = 1.0
        [render]
        fps = 25
        width = 64
        height = 48
        view = { min = [-1.0, -1.0], max = [1.0, 1.0] }
        [[body]]
        mass = 1e-9
        velocity = [1.0, 0.0]
        [[force]]
        kind = "drag"
        k = 1000.0
    "#;
    let sandbox = Sandbox::new();
    sandbox.write("stiff.toml", text);
    let out = sandbox.run(&["render", "stiff.toml", "--out", "f"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains("too stiff for an explicit adaptive method"),
        "{err}"
    );
    let m = manifest(&sandbox.path("f/manifest.json"));
    assert_eq!(m["status"], "failed");
    assert_eq!(m["frames_written"], 1);
}

#[test]
fn energy_growing_without_a_source_stops_the_run_before_it_overflows() {
    // An undamped spring with ω = 10 and explicit Euler at dt = 0.01: the energy grows
    // by exactly 1 + (h·ω)² = 1.01 per step, so it passes 10 times its start after
    // ln 10 / ln 1.01 ≈ 231.4 steps, at frame 58 (4 steps a frame), long before overflow.
    let text = r#"
        [simulation]
        dt = 0.01
        duration = 5.0
        [render]
        fps = 25
        width = 64
        height = 48
        view = { min = [-3.0, -3.0], max = [3.0, 3.0] }
        [[body]]
        name = "bob"
        mass = 1.0
        position = [1.0, 0.0]
        [[force]]
        kind = "spring"
        a = "bob"
        b = [0.0, 0.0]
        stiffness = 100.0
    "#;
    let sandbox = Sandbox::new();
    sandbox.write("spring.toml", text);
    let out = sandbox.run(&["render", "spring.toml", "--out", "f"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(err.contains("energy grew past 10 times"), "{err}");
    assert!(err.contains("body `bob`"), "{err}");
    assert!(err.contains("never stable on an undamped spring"), "{err}");
    let m = manifest(&sandbox.path("f/manifest.json"));
    assert_eq!(m["failure"]["step"], 232);
    assert_eq!(m["frames_written"], 58);
    // The same scene with symplectic Euler keeps its energy and renders every frame.
    let out = sandbox.run(&[
        "render",
        "spring.toml",
        "--out",
        "g",
        "--integrator",
        "symplectic-euler",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // And export stops the same way.
    let out = sandbox.run(&["export", "spring.toml", "--out", "t.csv"]);
    assert_eq!(out.status.code(), Some(3));
}
