//! `manifest.json`: what a render made, from what, and how long each stage took.

use serde::Serialize;

/// Seconds spent in each stage. Drawing, encoding and writing run on several threads,
/// so their sums can exceed the wall-clock time.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Timings {
    pub simulate_s: f64,
    pub draw_s: f64,
    pub encode_s: f64,
    pub write_s: f64,
    pub wall_s: f64,
}

/// How a run that did not finish ended.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Failure {
    pub kind: String,
    pub message: String,
    pub body: Option<String>,
    pub step: Option<u64>,
    pub t: Option<f64>,
}

/// The contents of `manifest.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Manifest {
    pub scene: String,
    pub scene_file: String,
    pub scene_hash: String,
    pub integrator: String,
    pub dt: f64,
    pub fps: f64,
    pub steps_per_frame: u64,
    /// Every frame the scene has: k = 0 ..= floor(duration·fps).
    pub frame_count: u64,
    /// The frames this run was asked to draw, half-open: [first, end).
    pub frames_requested: [u64; 2],
    /// How many frames this run wrote.
    pub frames_written: u64,
    /// How many frames in the range `--resume` kept from an earlier run instead of
    /// drawing them again.
    pub frames_reused: u64,
    /// The frame the simulation started from: 0, or the frame of the checkpoint it was
    /// restored from.
    pub started_from_frame: u64,
    /// How many checkpoints this run wrote.
    pub checkpoints_written: u64,
    /// The `--set KEY=VALUE` overrides applied to the scene file, in order; the scene
    /// hash covers them.
    pub scene_overrides: Vec<String>,
    pub width: u32,
    pub height: u32,
    pub program_version: String,
    /// "complete" or "failed".
    pub status: String,
    pub failure: Option<Failure>,
    pub timings: Timings,
}
