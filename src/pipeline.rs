//! The render pipeline: the simulation steps on one thread and hands the state at each
//! frame time through a bounded queue to a pool of threads that draw, encode and write.
//!
//! Files are named by frame number, so the order in which workers finish does not
//! matter, and each frame is drawn only from its own snapshot, so the bytes are the
//! same whatever the number of threads. The queue is bounded, so memory does not grow
//! with the number of frames (trails, when asked for, keep one position per body per
//! frame, which they need). The trail and trace histories are appended to once and
//! shared by every frame ([`crate::history`]): a job holds an `Arc` and a length, not a
//! copy of every frame before it.

use std::ops::Range;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use glam::DVec2;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::blowup::{blow_up_message, EnergyWatch};
use crate::checkpoint::{Checkpoint, CheckpointOptions, CheckpointWriter, RunKey};
use crate::error::{Error, Result};
use crate::history::{HistoryWriter, PointHistory};
use crate::output::{self, Failure, Manifest, Timings};
use tiny_skia::Pixmap;

use crate::render::fastpng::{FrameCoder, StaticPng};
use crate::render::layers::TraceRecorder;
use crate::render::trails::SharedTrails;
use crate::render::trails::{TrailFrame, TrailLayer};
use crate::render::{
    encode_png_into, ArrowScales, Compression, Damage, FrameView, Provenance, Renderer,
};
use crate::scene::Scene;
use crate::sim::{BlowUp, IntegratorKind};

/// What to render and how.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// The folder frames and the manifest go to.
    pub out_dir: PathBuf,
    /// The frames to draw, half-open; `None` draws them all.
    pub frames: Option<Range<u64>>,
    /// Threads that draw and encode; 0 means one per core.
    pub threads: usize,
    pub compression: Compression,
    /// Whether to show a progress bar (it is hidden anyway when stderr is no terminal).
    pub progress: bool,
}

/// What a render can do beyond [`RenderOptions`]: keep finished frames and use
/// checkpoints. Kept apart so that code that builds `RenderOptions` stays as it is.
#[derive(Clone, Debug, Default)]
pub struct RenderExtras {
    /// Keep the frames in the folder that this run would write identically
    /// ([`output::reusable_frames`]), and draw only the others.
    pub resume: bool,
    /// Start from the nearest checkpoint at or before the first frame, and write
    /// checkpoints when asked; `None` uses none.
    pub checkpoints: Option<CheckpointOptions>,
    /// Write the collision log (one row per impulse of the steps this run simulates)
    /// to this CSV file.
    pub events: Option<PathBuf>,
}

/// What a finished render did.
#[derive(Clone, Debug)]
pub struct RenderReport {
    pub manifest: Manifest,
    pub manifest_path: PathBuf,
    /// What the first and the last frames drawn cost, to show whether a late frame
    /// costs more than an early one (as redrawing every trail whole would).
    pub edge_costs: EdgeCosts,
}

/// How many frames at each end of a render [`EdgeCosts`] sums.
pub const EDGE_FRAMES: u64 = 100;

/// The seconds that drawing, encoding and writing took for the first and for the last
/// [`EDGE_FRAMES`] frames of the range asked for (fewer when the range is shorter, and
/// the two overlap when it holds fewer than twice as many), summed over the frames, so
/// that the two compare whatever the number of threads.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EdgeCosts {
    /// Frames at each end that the sums cover.
    pub frames: u64,
    pub first_s: f64,
    pub last_s: f64,
    /// Of those, the seconds spent writing the files: the operating system's part,
    /// which grows as its page cache fills while the program's part stays flat.
    pub first_write_s: f64,
    pub last_write_s: f64,
}

/// One frame's snapshot, handed from the simulation to a worker.
struct Job {
    index: u64,
    t: f64,
    pos: Arc<[DVec2]>,
    /// Velocities, when some body shows its velocity arrow; empty otherwise.
    vel: Vec<DVec2>,
    /// Angles, when some body turns.
    angle: Option<Vec<f64>>,
    force: Option<Vec<DVec2>>,
    /// Positions at frames 0 ..= index, when trails are on.
    trail: Option<PointHistory>,
    /// Trace curves' points at frames 0 ..= index, when the scene has traces.
    traces: Option<PointHistory>,
    /// The compared runs, when the scene sets `compare`.
    compare: Option<Arc<crate::compare::CompareFrame>>,
}

/// Stage times summed over the workers, in nanoseconds.
#[derive(Default)]
struct StageClock {
    draw: AtomicU64,
    encode: AtomicU64,
    write: AtomicU64,
    /// Draw, encode and write of the first and last [`EDGE_FRAMES`] frames, and the
    /// write alone.
    first: AtomicU64,
    last: AtomicU64,
    first_write: AtomicU64,
    last_write: AtomicU64,
}

impl StageClock {
    fn add(counter: &AtomicU64, since: Instant) -> Instant {
        let now = Instant::now();
        counter.fetch_add((now - since).as_nanos() as u64, Ordering::Relaxed);
        now
    }

    /// Adds one frame's whole cost, from `since`, and its writing's, `write` seconds'
    /// worth of nanoseconds, to the sums of the ends of `range` it belongs to.
    fn add_edges(&self, range: &Range<u64>, index: u64, since: Instant, write: u64) {
        let nanos = since.elapsed().as_nanos() as u64;
        if index < range.start.saturating_add(EDGE_FRAMES) {
            self.first.fetch_add(nanos, Ordering::Relaxed);
            self.first_write.fetch_add(write, Ordering::Relaxed);
        }
        if index >= range.end.saturating_sub(EDGE_FRAMES) {
            self.last.fetch_add(nanos, Ordering::Relaxed);
            self.last_write.fetch_add(write, Ordering::Relaxed);
        }
    }
}

/// Returns the provenance written into every frame of a scene.
pub fn provenance(scene: &Scene, integrator: IntegratorKind, t: f64, frame: u64) -> Provenance {
    Provenance::default()
        .with(
            "Software",
            format!("physframes {}", env!("CARGO_PKG_VERSION")),
        )
        .with("physframes:scene", &scene.name)
        .with("physframes:scene-hash", &scene.source.hash)
        .with("physframes:integrator", integrator)
        .with("physframes:dt", scene.simulation.dt)
        .with("physframes:t", t)
        .with("physframes:frame", frame)
}

/// Renders a scene's frames into `options.out_dir` and writes its manifest.
///
/// On a numerical blow-up the frames already written stay valid, the manifest records
/// the failure, and the error is [`Error::BlowUp`].
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<RenderReport> {
    render_full(scene, options, &RenderExtras::default(), |_| {})
}

/// Renders like [`render`], resuming and using checkpoints as `extras` asks.
pub fn render_with(
    scene: &Scene,
    options: &RenderOptions,
    extras: &RenderExtras,
) -> Result<RenderReport> {
    render_full(scene, options, extras, |_| {})
}

/// Like [`render`], letting `prepare` draw more static layers into the renderer once,
/// before the first frame: every frame starts from a copy of them.
pub fn render_prepared(
    scene: &Scene,
    options: &RenderOptions,
    prepare: impl FnOnce(&mut Renderer),
) -> Result<RenderReport> {
    render_full(scene, options, &RenderExtras::default(), prepare)
}

/// Renders with every option: resume and checkpoints, and extra static layers.
fn render_full(
    scene: &Scene,
    options: &RenderOptions,
    extras: &RenderExtras,
    prepare: impl FnOnce(&mut Renderer),
) -> Result<RenderReport> {
    let wall = Instant::now();
    let frame_count = scene.render.frame_count;
    let range = options.frames.clone().unwrap_or(0..frame_count);
    if range.start >= range.end || range.end > frame_count {
        return Err(Error::Usage(format!(
            "--frames {}..{} is outside the scene's frames 0..{frame_count}",
            range.start, range.end
        )));
    }
    let dir = &options.out_dir;
    if dir.exists() && !dir.is_dir() {
        return Err(Error::Usage(format!(
            "--out {} is not a folder; frames need a folder of their own\nhint: name a folder, such as output/NAME",
            dir.display()
        )));
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io("cannot create", dir, e))?;
    if options.frames.is_none() {
        // Frames of an earlier, longer run of this scene must not stay mixed in.
        output::remove_frames(dir, |k| k >= frame_count)?;
    }

    let integrator = scene.simulation.integrator;
    // Frames that a killed run of the same scene and settings finished are kept.
    let reused = if extras.resume {
        output::reusable_frames(
            dir,
            range.clone(),
            scene.render.width,
            scene.render.height,
            |k| provenance(scene, integrator, scene.frame_time(k), k),
        )?
    } else {
        Default::default()
    };
    let mut sim = scene.simulation_with(integrator);
    let mut force = vec![DVec2::ZERO; scene.bodies.len()];
    sim.net_forces(&mut force);
    let arrows = ArrowScales::fit(scene, &sim.state().vel, &force);
    let threads = crate::threads::or_cores(options.threads);
    let mut renderer = Renderer::with_threads(scene, arrows, threads);
    prepare(&mut renderer);
    // Only what the frames show is copied out of the simulation for them.
    let needs_forces = renderer.needs_forces();
    let needs_velocities = renderer.needs_velocities();
    let needs_angles = renderer.needs_angles();
    let opaque = renderer.frames_are_opaque();
    let trails = scene.render.trails;

    // The default compression encodes the static layer once, on all the threads;
    // what it needs (opaque frames) is checked here, and the png crate encodes
    // otherwise.
    let static_png = (opaque && options.compression == Compression::Fast)
        .then(|| StaticPng::with_threads(renderer.static_layer(), threads))
        .flatten();
    // The run starts from the nearest checkpoint at or before its first frame, if any.
    // Trace curves need every frame's values from t = 0, which checkpoints do not hold,
    // so a scene with traces always starts at t = 0.
    let key = RunKey::new(scene, integrator);
    // Comparisons, like traces, keep a history from t = 0.
    let has_traces = TraceRecorder::new(scene).is_some() || !scene.simulation.compare.is_empty();
    let start: Option<Checkpoint> = extras
        .checkpoints
        .as_ref()
        .filter(|_| crate::checkpoint::supports(integrator).is_ok() && !has_traces)
        .and_then(|c| crate::checkpoint::nearest(&c.dir, &key, range.start));
    let mut checkpoints = match extras
        .checkpoints
        .as_ref()
        .and_then(|c| Some((c, c.every?)))
    {
        Some((c, every)) => Some(CheckpointWriter::new(&c.dir, key.clone(), every)?),
        None => None,
    };
    let progress = progress_bar(
        options.progress,
        range.end - range.start - reused.len() as u64,
    );
    let clock = StageClock::default();
    let stop = AtomicBool::new(false);
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    let written = AtomicU64::new(0);
    let (sender, receiver) = crossbeam_channel::bounded::<Job>(2 * threads);
    let shared_trails = Arc::new(SharedTrails::new(threads));
    // Workers take their trail segments from `shared_trails` when they encode frames
    // against the frame before (`draw_and_write`), which they do whenever they can.
    let share_trails = trails
        && static_png.is_some()
        && FrameCoder::new(scene.render.width, scene.render.height).is_some();
    let mut simulate = Duration::ZERO;
    let mut blow_up: Option<(BlowUp, u64)> = None;
    let names = scene.body_names();
    let mut events = match &extras.events {
        Some(path) => Some(output::EventLog::create(path)?),
        None => None,
    };

    std::thread::scope(|scope| {
        for worker in 0..threads {
            let receiver = receiver.clone();
            let range = &range;
            let (renderer, clock, stop, first_error, written, progress, static_png) = (
                &renderer,
                &clock,
                &stop,
                &first_error,
                &written,
                &progress,
                &static_png,
            );
            let shared_trails = &shared_trails;
            scope.spawn(move || {
                // Each worker draws every frame into one pixmap and encodes into one
                // buffer, so no frame allocates an image.
                let mut buffers = Buffers {
                    pixmap: renderer.new_frame(),
                    damage: Damage::default(),
                    png: Vec::new(),
                    opaque,
                    static_png: static_png.as_ref(),
                    trails: None,
                    trail_frame: None,
                    shared_trails: (shared_trails, worker),
                };
                for job in receiver {
                    if stop.load(Ordering::Relaxed) {
                        continue;
                    }
                    let started = Instant::now();
                    let done = draw_and_write(
                        scene,
                        integrator,
                        renderer,
                        &job,
                        dir,
                        options,
                        clock,
                        &mut buffers,
                    );
                    let write = *done.as_ref().unwrap_or(&0);
                    clock.add_edges(range, job.index, started, write);
                    match done {
                        Ok(_) => {
                            written.fetch_add(1, Ordering::Relaxed);
                            progress.inc(1);
                        }
                        Err(e) => {
                            stop.store(true, Ordering::Relaxed);
                            let mut slot = first_error.lock().unwrap_or_else(|p| p.into_inner());
                            slot.get_or_insert(e);
                        }
                    }
                }
            });
        }
        drop(receiver);

        // The simulation runs only as far as the last frame asked for.
        let mut history: HistoryWriter<Arc<[DVec2]>> = HistoryWriter::new();
        let mut traces = TraceRecorder::new(scene);
        let energy_watch = EnergyWatch::new(&sim);
        let mut comparison = crate::compare::Comparison::new(scene);
        let mut first = 0;
        if let Some(c) = &start {
            sim = c.restore(scene, integrator);
            history = c.trail.iter().cloned().collect();
            first = c.frame;
        }
        sim.record_contacts(events.is_some());
        for k in first..range.end {
            if stop.load(Ordering::Relaxed) {
                break;
            }
            let started = Instant::now();
            let advanced = sim
                .advance_to(scene.frame_time(k))
                .and_then(|()| energy_watch.check(&sim));
            if let Some(log) = &mut events {
                if let Err(e) = log.write(&sim.take_contact_events(), &names) {
                    stop.store(true, Ordering::Relaxed);
                    let mut slot = first_error.lock().unwrap_or_else(|p| p.into_inner());
                    slot.get_or_insert(e);
                    break;
                }
            }
            if let Err(e) = advanced {
                simulate += started.elapsed();
                blow_up = Some((e, k));
                break;
            }
            let state = sim.state();
            // Compared runs advance at every frame, drawn or not, to keep their errors.
            let compare = comparison.as_mut().map(|c| Arc::new(c.advance_to(state.t)));
            let pos: Arc<[DVec2]> = Arc::from(state.pos.as_slice());
            if trails {
                history.push(Arc::clone(&pos));
                // Each frame's trail segments are rasterised once, here, for every
                // worker's layer, while the workers draw the frames before.
                if share_trails {
                    renderer.rasterise_trails(&shared_trails, history.history());
                }
            }
            if let Some(traces) = &mut traces {
                traces.record(state.t, &state.pos, &state.vel);
            }
            if let Some(Err(e)) = checkpoints
                .as_mut()
                .map(|c| c.after_frame(k, &sim, history.history()))
            {
                stop.store(true, Ordering::Relaxed);
                let mut slot = first_error.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(e);
                break;
            }
            if k < range.start || reused.contains(&k) {
                simulate += started.elapsed();
                continue;
            }
            let force = needs_forces.then(|| {
                let mut f = vec![DVec2::ZERO; state.len()];
                sim.net_forces(&mut f);
                f
            });
            let job = Job {
                index: k,
                t: state.t,
                pos,
                vel: if needs_velocities {
                    state.vel.clone()
                } else {
                    Vec::new()
                },
                angle: needs_angles.then(|| state.angle.clone()),
                force,
                // Snapshots of the shared histories: an `Arc` and a length each.
                trail: trails.then(|| history.history().clone()),
                traces: traces.as_ref().map(|r| r.history().clone()),
                compare,
            };
            simulate += started.elapsed();
            if sender.send(job).is_err() {
                break;
            }
        }
        drop(sender);
    });
    progress.finish_and_clear();
    if let Some(log) = events {
        log.finish()?;
    }

    let frames_written = written.load(Ordering::Relaxed);
    let nanos = |c: &AtomicU64| c.load(Ordering::Relaxed) as f64 * 1e-9;
    let timings = Timings {
        simulate_s: simulate.as_secs_f64(),
        draw_s: nanos(&clock.draw),
        encode_s: nanos(&clock.encode),
        write_s: nanos(&clock.write),
        wall_s: wall.elapsed().as_secs_f64(),
    };
    let io_error = first_error.into_inner().unwrap_or_else(|p| p.into_inner());
    let failure = match (&blow_up, &io_error) {
        (Some((b, k)), _) => {
            // Frames from an earlier run past the blow-up would be mixed in: remove them.
            let end = range.end;
            output::remove_frames(dir, |j| j >= *k && j < end)?;
            Some(Failure {
                kind: "blow-up".into(),
                message: blow_up_message(scene, b),
                body: Some(scene.bodies[b.body].name.clone()),
                step: Some(b.step),
                t: Some(b.t),
            })
        }
        (None, Some(e)) => Some(Failure {
            kind: "error".into(),
            message: e.to_string(),
            body: None,
            step: None,
            t: None,
        }),
        (None, None) => None,
    };
    let manifest = Manifest {
        scene: scene.name.clone(),
        scene_file: scene.source.path.display().to_string(),
        scene_hash: scene.source.hash.clone(),
        integrator: integrator.to_string(),
        dt: scene.simulation.dt,
        fps: scene.render.fps,
        steps_per_frame: scene.render.steps_per_frame,
        frame_count,
        frames_requested: [range.start, range.end],
        frames_written,
        frames_reused: reused.len() as u64,
        started_from_frame: start.as_ref().map_or(0, |c| c.frame),
        checkpoints_written: checkpoints.as_ref().map_or(0, |c| c.written()),
        scene_overrides: scene.source.overrides.clone(),
        width: scene.render.width,
        height: scene.render.height,
        program_version: env!("CARGO_PKG_VERSION").to_string(),
        status: if failure.is_none() {
            "complete"
        } else {
            "failed"
        }
        .into(),
        failure,
        timings,
    };
    let manifest_path = dir.join("manifest.json");
    let json = serde_json::to_string_pretty(&manifest)
        .map_err(|e| Error::Runtime(format!("cannot serialise the manifest: {e}")))?;
    output::write_atomic(&manifest_path, format!("{json}\n").as_bytes())?;
    if let Some(e) = io_error {
        return Err(e);
    }
    if let Some((b, _)) = blow_up {
        return Err(Error::BlowUp(format!(
            "{}\n{frames_written} frames written before it stay valid; see {}",
            blow_up_message(scene, &b),
            manifest_path.display()
        )));
    }
    Ok(RenderReport {
        manifest,
        manifest_path,
        edge_costs: EdgeCosts {
            frames: EDGE_FRAMES.min(range.end - range.start),
            first_s: nanos(&clock.first),
            last_s: nanos(&clock.last),
            first_write_s: nanos(&clock.first_write),
            last_write_s: nanos(&clock.last_write),
        },
    })
}

/// What a worker reuses from frame to frame.
struct Buffers<'a> {
    pixmap: Pixmap,
    /// Where `pixmap` differs from the static layer.
    damage: Damage,
    png: Vec<u8>,
    /// Whether every frame is opaque, so the encoder need not check.
    opaque: bool,
    /// The static layer's compressed tiles, for the default compression.
    static_png: Option<&'a StaticPng>,
    /// The static layer with the trails so far, when frames show trails and are not
    /// encoded against the frame before.
    trails: Option<TrailLayer>,
    /// With the default compression, frames with trails are encoded against the last
    /// frame the worker drew: its trail layer and bodies, and the encoder that keeps
    /// the last frame's bits.
    trail_frame: Option<(TrailFrame, FrameCoder)>,
    /// The render's trail segments, rasterised once for all its workers, and this
    /// worker's number.
    shared_trails: (&'a Arc<SharedTrails>, usize),
}

/// Draws, encodes and writes one frame, adding each stage's time to the clock, and
/// returns the nanoseconds the writing took.
#[allow(clippy::too_many_arguments)]
fn draw_and_write(
    scene: &Scene,
    integrator: IntegratorKind,
    renderer: &Renderer,
    job: &Job,
    dir: &std::path::Path,
    options: &RenderOptions,
    clock: &StageClock,
    buffers: &mut Buffers<'_>,
) -> Result<u64> {
    let started = Instant::now();
    let view = FrameView {
        index: job.index,
        t: job.t,
        pos: &job.pos,
        vel: &job.vel,
        angle: job.angle.as_deref(),
        force: job.force.as_deref(),
        trail: job.trail.as_ref(),
        traces: job.traces.as_ref(),
        compare: job.compare.as_deref(),
    };
    let provenance = provenance(scene, integrator, job.t, job.index);
    let (width, height) = (buffers.pixmap.width(), buffers.pixmap.height());
    // Frames with trails and the default compression: drawn and encoded against the
    // last frame this worker drew. The PNG does not depend on which frame that was.
    let incremental = job.trail.is_some() && buffers.static_png.is_some();
    if incremental && buffers.trail_frame.is_none() {
        let (shared, worker) = buffers.shared_trails;
        let shared = Arc::clone(shared);
        buffers.trail_frame = FrameCoder::new(width, height)
            .map(|coder| (TrailFrame::sharing(width, height, shared, worker), coder));
    }
    if let (true, Some((state, coder))) = (incremental, &mut buffers.trail_frame) {
        renderer.draw_trail_frame(&view, &mut buffers.pixmap, state);
        let drawn = StageClock::add(&clock.draw, started);
        let png = coder.encode(&buffers.pixmap, state.changed(), &provenance);
        let encoded = StageClock::add(&clock.encode, drawn);
        output::write_atomic(&dir.join(output::frame_file_name(job.index)), png)?;
        let written = StageClock::add(&clock.write, encoded);
        return Ok((written - encoded).as_nanos() as u64);
    }
    renderer.draw_with_trails(
        &view,
        &mut buffers.pixmap,
        &mut buffers.damage,
        &mut buffers.trails,
    );
    let drawn = StageClock::add(&clock.draw, started);
    match buffers.static_png {
        Some(encoder) => encoder.encode_damaged(
            &buffers.pixmap,
            &buffers.damage,
            &provenance,
            &mut buffers.png,
        ),
        None => encode_png_into(
            &mut buffers.png,
            &buffers.pixmap,
            &provenance,
            options.compression,
            buffers.opaque,
        )
        .map_err(|e| Error::Runtime(format!("cannot encode frame {}: {e}", job.index)))?,
    }
    let encoded = StageClock::add(&clock.encode, drawn);
    output::write_atomic(&dir.join(output::frame_file_name(job.index)), &buffers.png)?;
    let written = StageClock::add(&clock.write, encoded);
    Ok((written - encoded).as_nanos() as u64)
}

fn progress_bar(show: bool, len: u64) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(
        "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} frames ({per_sec}, {eta} left)",
    ) {
        bar.set_style(style);
    }
    bar
}
