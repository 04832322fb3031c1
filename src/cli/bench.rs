//! `physframes bench`: how fast this machine simulates, draws, encodes and writes.
//!
//! Each scene is rendered `--repeat` times, every run into a fresh temporary folder that
//! is removed once the run is measured, so that runs neither pile up frames (on tmpfs,
//! in memory) nor find other runs' files where they write. With `--out DIR` the folders
//! are made inside DIR and the last run's frames are kept as `DIR/<scene name>/`. The
//! median run is reported, with the time per frame of each stage as the manifest
//! records it. The scenes run round by round, each once a round, so that a change in
//! the machine's speed falls on all of them; each one's frame rate is also given as a
//! ratio to the reference scene's (`circles-1000` unless `--reference` says otherwise)
//! measured in the same rounds, which compares across runs on a shared machine where
//! absolute rates do not. The ratio is taken round by round, each scene's run over the
//! reference's run of the same round, and the median of the rounds is shown, with the
//! lowest and highest round after the row: on a shared machine one round's ratio can
//! be a quarter off, and the spread says how far to trust the median. Scenes with
//! trails also give what their first and last hundred frames cost, which should be
//! alike. `--simulate-only` times the simulation alone, stepping the
//! scene's `Simulation` from t = 0 to its last frame with nothing drawn or written, and
//! reports nanoseconds per body-step; for a scene of explicit Euler under gravity and
//! linear drag on equal masses, it times the hand-written loop of the same physics
//! ([`HandWrittenEuler`]) in turn with it, and reports the ratio of the two.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::{parse_frames, SceneArgs};
use crate::error::{Error, Result};
use crate::pipeline::{self, EdgeCosts, RenderOptions};
use crate::render::Compression;
use crate::scene::Scene;
use crate::sim::HandWrittenEuler;

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Scene files to measure [default: every scene in scenes/ and scenes/bench/].
    scenes: Vec<PathBuf>,
    /// Runs per scene; the median is reported.
    #[arg(long, value_name = "N", default_value_t = 3)]
    repeat: usize,
    /// Threads that draw and encode frames, and that step large swarms with
    /// --simulate-only [default: one per core].
    #[arg(long, value_name = "N", default_value_t = 0)]
    threads: usize,
    /// PNG compression: fastest, fast or best.
    #[arg(long, value_name = "LEVEL", default_value = "fast")]
    compression: String,
    /// Render only these frames: A..B (B excluded), A..=B, A.., ..B or A.
    #[arg(long, value_name = "RANGE")]
    frames: Option<String>,
    /// Time the simulation alone: nothing is drawn, encoded or written. For explicit
    /// Euler under gravity and linear drag on bodies of equal mass, also time a
    /// hand-written loop of the same physics, in turn with it, and print the ratio.
    #[arg(long)]
    simulate_only: bool,
    /// Render each run into a temporary folder inside DIR instead of the system's, and
    /// keep the last run's frames of each scene as DIR/<scene name>/, replacing the
    /// folder an earlier bench kept there and never any other [default: keep nothing].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Use this integrator instead of each scene's.
    #[arg(long, value_name = "NAME")]
    integrator: Option<String>,
    /// The scene whose frame rate the ratio column divides by, measured in the same
    /// run (added to the scenes when not among them), or `none` [default:
    /// scenes/bench/circles-1000.toml when it is there].
    #[arg(long, value_name = "SCENE")]
    reference: Option<PathBuf>,
}

/// One rendering run's figures.
struct RenderRun {
    frames: u64,
    wall_s: f64,
    /// Seconds per frame: simulate, draw, encode, write (the last three summed over
    /// threads).
    stages: [f64; 4],
    bytes_per_frame: f64,
    /// What the first and last hundred frames cost.
    edges: EdgeCosts,
}

pub fn run(args: BenchArgs) -> Result<()> {
    if args.repeat == 0 {
        return Err(Error::Usage("--repeat must be at least 1".into()));
    }
    let compression = args
        .compression
        .parse::<Compression>()
        .map_err(Error::Usage)?;
    let scenes = if args.scenes.is_empty() {
        default_scenes()?
    } else {
        args.scenes.clone()
    };
    let threads = crate::threads::or_cores(args.threads);
    let mut out = format!(
        "physframes {} bench: {} threads, {} run(s) per scene, median shown; load average {}\n",
        env!("CARGO_PKG_VERSION"),
        threads,
        args.repeat,
        load_average()
    );
    if args.simulate_only {
        out.push_str(&format!(
            "{:<28} {:>9} {:>7} {:>12} {:>16}\n",
            "scene", "bodies", "steps", "seconds", "ns/body-step"
        ));
        super::say(&out)?;
        for path in &scenes {
            let scene = load(path, &args)?;
            super::say(&simulate_line(&scene, threads, args.repeat)?)?;
        }
        return Ok(());
    }
    // The reference scene, when there is one, is measured with the others.
    let reference = match &args.reference {
        Some(r) if r.as_os_str() == "none" => None,
        Some(r) => Some(r.clone()),
        None => Some(PathBuf::from(REFERENCE)).filter(|p| p.is_file()),
    };
    let mut loaded = Vec::with_capacity(scenes.len() + 1);
    for path in &scenes {
        loaded.push(load(path, &args)?);
    }
    let listed = |name: &str| loaded.iter().position(|s: &Scene| s.name == name);
    let reference = match reference {
        Some(path) => {
            let scene = load(&path, &args)?;
            Some(match listed(&scene.name) {
                Some(i) => i,
                None => {
                    loaded.insert(0, scene);
                    0
                }
            })
        }
        None => None,
    };
    out.push_str(&format!(
        "{:<28} {:>9} {:>6} {:>9} {:>7} {:>9} {:>9} {:>9} {:>9} {:>11}\n",
        "scene",
        "bodies",
        "frames",
        "frames/s",
        "ratio",
        "sim ms",
        "draw ms",
        "enc ms",
        "write ms",
        "bytes/frame"
    ));
    out.push_str(&format!(
        "{:<28} {:>9} {:>6} {:>9} {:>7} {:>39} {:>11}\n",
        "", "", "", "", "", "(per frame, summed over threads)", ""
    ));
    super::say(&out)?;
    let mut plans = Vec::with_capacity(loaded.len());
    for scene in &loaded {
        let frames = args
            .frames
            .as_deref()
            .map(|f| parse_frames(f, scene.render.frame_count))
            .transpose()?;
        // The last run's frames are kept, when --out is given.
        let kept = args.out.as_ref().map(|dir| dir.join(&scene.name));
        if let Some(kept) = &kept {
            check_replaceable(kept)?;
        }
        plans.push((frames, kept));
    }
    // Round by round, every scene once a round, so that a change in the machine's
    // speed during the bench falls on every scene, the reference included.
    let mut runs: Vec<Vec<RenderRun>> = loaded.iter().map(|_| Vec::new()).collect();
    for round in 0..args.repeat {
        for ((scene, (frames, kept)), runs) in loaded.iter().zip(&plans).zip(&mut runs) {
            let keep_as = kept.as_deref().filter(|_| round + 1 == args.repeat);
            runs.push(render_once(
                scene,
                &args,
                threads,
                compression,
                frames.clone(),
                keep_as,
            )?);
        }
    }
    let rate = |m: &RenderRun| m.frames as f64 / m.wall_s;
    // Each round's ratio: a scene's frame rate over the reference's in the same round,
    // the two measured seconds apart, so that the machine's drift between rounds
    // cancels.
    let ratios: Vec<Option<RoundRatios>> = runs
        .iter()
        .map(|scene_runs| {
            let reference_runs = &runs[reference?];
            Some(RoundRatios::of(
                scene_runs
                    .iter()
                    .zip(reference_runs)
                    .map(|(s, r)| rate(s) / rate(r))
                    .collect(),
            ))
        })
        .collect();
    let medians: Vec<RenderRun> = runs
        .into_iter()
        .map(|mut runs| {
            runs.sort_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
            runs.swap_remove(runs.len() / 2)
        })
        .collect();
    let mut table = String::new();
    for (i, ((scene, m), ratios)) in loaded.iter().zip(&medians).zip(&ratios).enumerate() {
        let ms = |s: f64| s * 1e3;
        let ratio = ratios
            .as_ref()
            .map_or("-".to_string(), |r| format!("{:.2}", r.median));
        let after = match ratios {
            _ if Some(i) == reference => "  (reference)".to_string(),
            Some(r) if args.repeat > 1 => format!("  rounds {:.2} to {:.2}", r.low, r.high),
            _ => String::new(),
        };
        table.push_str(&format!(
            "{:<28} {:>9} {:>6} {:>9.1} {:>7} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {:>11.0}{}\n",
            scene.name,
            scene.bodies.len(),
            m.frames,
            rate(m),
            ratio,
            ms(m.stages[0]),
            ms(m.stages[1]),
            ms(m.stages[2]),
            ms(m.stages[3]),
            m.bytes_per_frame,
            after
        ));
        // With trails, whether a late frame costs more than an early one.
        if scene.render.trails {
            let e = &m.edges;
            table.push_str(&format!(
                "  first {} frames {:.1} ms, last {} frames {:.1} ms (draw, encode, write); \
                 without writing {:.1} and {:.1} ms\n",
                e.frames,
                ms(e.first_s),
                e.frames,
                ms(e.last_s),
                ms(e.first_s - e.first_write_s),
                ms(e.last_s - e.last_write_s)
            ));
        }
    }
    match (reference, &args.reference) {
        (Some(i), _) => table.push_str(&format!(
            "ratio: frames/s over those of {} in the same round, the median of the rounds; \
             rounds: the lowest and highest single round\n",
            loaded[i].name
        )),
        (None, Some(_)) => table.push_str("ratio: none (--reference none)\n"),
        (None, None) => table.push_str(&format!(
            "ratio: none, for {REFERENCE} is not here; give --reference SCENE\n"
        )),
    }
    super::say(&table)?;
    Ok(())
}

/// A scene's ratios to the reference scene, one a round: their median, lowest and
/// highest.
struct RoundRatios {
    median: f64,
    low: f64,
    high: f64,
}

impl RoundRatios {
    fn of(mut ratios: Vec<f64>) -> Self {
        ratios.sort_by(f64::total_cmp);
        let n = ratios.len();
        // The mean of the middle two for an even count.
        let median = 0.5 * (ratios[(n - 1) / 2] + ratios[n / 2]);
        RoundRatios {
            median,
            low: ratios[0],
            high: ratios[n - 1],
        }
    }
}

/// The scene whose frame rate the others' are divided by, when `--reference` is not
/// given and the file is there.
const REFERENCE: &str = "scenes/bench/circles-1000.toml";

/// Loads a scene as bench measures it: with the integrator asked for, no overrides.
fn load(path: &Path, args: &BenchArgs) -> Result<Scene> {
    SceneArgs {
        scene: path.to_path_buf(),
        integrator: args.integrator.clone(),
        set: Vec::new(),
    }
    .load()
}

/// Returns every `.toml` file in `scenes/` and `scenes/bench/`, sorted.
fn default_scenes() -> Result<Vec<PathBuf>> {
    let mut found = Vec::new();
    for dir in ["scenes", "scenes/bench"] {
        let Ok(entries) = std::fs::read_dir(dir) else {
            continue;
        };
        let mut here: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        here.sort();
        found.extend(here);
    }
    if found.is_empty() {
        return Err(Error::Usage(
            "no scene given, and no scenes/ folder here; name the scene files to measure".into(),
        ));
    }
    Ok(found)
}

/// The file that marks a folder of frames kept by `bench`, which a later bench of the
/// same scene may replace.
const KEPT_MARKER: &str = ".physframes-bench";

/// Fails when `kept` exists but is not a folder that `bench` kept, so that bench never
/// removes a render or anything else of the user's that happens to have the scene's name.
fn check_replaceable(kept: &Path) -> Result<()> {
    if kept.symlink_metadata().is_err() || kept.join(KEPT_MARKER).is_file() {
        return Ok(());
    }
    Err(Error::Usage(format!(
        "{} exists and was not written by `physframes bench`, which would replace it; \
         remove it or choose another --out",
        kept.display()
    )))
}

/// Renders a scene once into a fresh temporary folder and returns its figures. The
/// folder is then removed, or, when `keep_as` is given, moved there in place of the
/// folder an earlier bench kept. Neither is part of the times measured, which the
/// manifest records during the render.
fn render_once(
    scene: &Scene,
    args: &BenchArgs,
    threads: usize,
    compression: Compression,
    frames: Option<std::ops::Range<u64>>,
    keep_as: Option<&Path>,
) -> Result<RenderRun> {
    let parent = match &args.out {
        Some(dir) => {
            std::fs::create_dir_all(dir).map_err(|e| Error::io("cannot create", dir, e))?;
            dir.clone()
        }
        None => std::env::temp_dir(),
    };
    // Listed while it exists, so that Ctrl-C removes it too.
    let (folder, listed) = crate::interrupt::create_listed(
        || {
            tempfile::Builder::new()
                .prefix("physframes-bench-")
                .tempdir_in(&parent)
        },
        |d| d.path(),
    )
    .map_err(|e| Error::io("cannot create a folder in", &parent, e))?;
    let folder = BenchFolder {
        dir: folder,
        _listed: listed,
    };
    let folder_path = folder.dir.path();
    let options = RenderOptions {
        out_dir: folder_path.to_path_buf(),
        frames,
        threads,
        compression,
        progress: false,
    };
    let report = pipeline::render(scene, &options)?;
    let m = &report.manifest;
    let n = m.frames_written.max(1) as f64;
    let bytes = frame_bytes(folder_path)?;
    let t = &m.timings;
    let run = RenderRun {
        frames: m.frames_written,
        wall_s: t.wall_s,
        stages: [
            t.simulate_s / n,
            t.draw_s / n,
            t.encode_s / n,
            t.write_s / n,
        ],
        bytes_per_frame: bytes as f64 / n,
        edges: report.edge_costs,
    };
    let BenchFolder { dir, _listed } = folder;
    match keep_as {
        Some(kept) => keep(dir, kept)?,
        // Removing the folder now, rather than leaving it to `Drop`, reports a failure:
        // a folder left behind would again fill DIR run by run.
        None => {
            let path = dir.path().to_path_buf();
            dir.close()
                .map_err(|e| Error::io("cannot remove", path, e))?;
        }
    }
    Ok(run)
}

/// A run's temporary folder, listed with [`crate::interrupt`] while it exists.
struct BenchFolder {
    // Dropped first: the folder is removed before it leaves the list.
    dir: tempfile::TempDir,
    _listed: crate::interrupt::Listed,
}

/// Moves a run's folder of frames to `kept`, replacing the folder an earlier bench kept
/// there. The temporary folder was made in `kept`'s parent, so this is a rename on one
/// filesystem, not a copy.
fn keep(folder: tempfile::TempDir, kept: &Path) -> Result<()> {
    let marker = folder.path().join(KEPT_MARKER);
    std::fs::write(
        &marker,
        "Frames kept by `physframes bench`; the next bench of this scene with the same \
         --out replaces this folder.\n",
    )
    .map_err(|e| Error::io("cannot write", marker, e))?;
    // Checked again in case the folder appeared while the scene was being measured.
    check_replaceable(kept)?;
    if kept.symlink_metadata().is_ok() {
        std::fs::remove_dir_all(kept).map_err(|e| Error::io("cannot remove", kept, e))?;
    }
    // On failure, `folder` is dropped here and the temporary folder removed with it.
    std::fs::rename(folder.path(), kept)
        .map_err(|e| Error::io("cannot move frames to", kept, e))?;
    // The frames are now at `kept`; nothing is left for `folder` to remove.
    let _ = folder.keep();
    Ok(())
}

/// Returns the total size of the frame files in a folder.
fn frame_bytes(dir: &Path) -> Result<u64> {
    let mut total = 0;
    for (_, path) in crate::output::list_frames(dir)? {
        total += std::fs::metadata(&path)
            .map_err(|e| Error::io("cannot read", path.clone(), e))?
            .len();
    }
    Ok(total)
}

/// Steps a scene's simulation to its last frame `repeat` times on a pool of `threads`
/// threads and formats the median time per body-step.
///
/// When the scene is one that [`HandWrittenEuler`] reproduces (explicit Euler, gravity
/// and linear drag on every body, equal masses), the hand-written loop is run from the
/// same initial state in turn with the pipeline, `repeat` times each, which one first
/// alternating between rounds so that a change in the machine's speed falls on both; a
/// second line gives its median and the ratio of the two medians.
fn simulate_line(scene: &Scene, threads: usize, repeat: usize) -> Result<String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Runtime(format!("cannot start {threads} threads: {e}")))?;
    let steps = scene.total_steps();
    let initial = scene.initial_state();
    // The hand-written loop knows nothing of collisions.
    let mut hand = HandWrittenEuler::new(
        &scene.system(),
        scene.simulation.integrator,
        scene.simulation.dt,
        &initial,
    )
    .filter(|_| scene.contacts.is_none());
    let time_pipeline = || -> Result<f64> {
        let mut sim = scene.simulation_with(scene.simulation.integrator);
        let started = Instant::now();
        let result = pool.install(|| sim.run_steps(steps));
        let elapsed = started.elapsed().as_secs_f64();
        result.map_err(|b| Error::BlowUp(crate::blowup::blow_up_message(scene, &b)))?;
        Ok(elapsed)
    };
    let time_hand = |hand: &mut HandWrittenEuler| {
        hand.set_state(&initial);
        let started = Instant::now();
        pool.install(|| hand.run_steps(steps));
        started.elapsed().as_secs_f64()
    };
    let mut seconds = Vec::with_capacity(repeat);
    let mut hand_seconds = Vec::with_capacity(repeat);
    for round in 0..repeat {
        match &mut hand {
            Some(hand) if round % 2 == 1 => {
                hand_seconds.push(time_hand(hand));
                seconds.push(time_pipeline()?);
            }
            Some(hand) => {
                seconds.push(time_pipeline()?);
                hand_seconds.push(time_hand(hand));
            }
            None => seconds.push(time_pipeline()?),
        }
    }
    let median = |mut s: Vec<f64>| {
        s.sort_by(f64::total_cmp);
        s[s.len() / 2]
    };
    let body_steps = (steps as f64 * scene.bodies.len() as f64).max(1.0);
    let row = |name: &str, seconds: f64| {
        format!(
            "{:<28} {:>9} {:>7} {:>12.4} {:>16.3}",
            name,
            scene.bodies.len(),
            steps,
            seconds,
            seconds * 1e9 / body_steps
        )
    };
    let pipeline_median = median(seconds);
    let mut out = row(&scene.name, pipeline_median) + "\n";
    if hand.is_some() {
        let hand_median = median(hand_seconds);
        out.push_str(&row("  hand-written loop", hand_median));
        out.push_str(&format!(
            "   pipeline/hand-written {:.2}\n",
            pipeline_median / hand_median
        ));
    }
    Ok(out)
}

/// Returns the one-minute load average, or "unknown": a busy machine gives slower,
/// noisier figures.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "unknown".into())
}
