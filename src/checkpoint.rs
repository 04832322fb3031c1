//! Checkpoints: the simulation's exact state at a frame, saved so that a later run (a
//! shard of frames A..B, on this machine or another) starts there instead of at t = 0.
//!
//! A checkpoint holds the exact f64 bits of the state after frame k: the step count and
//! t, every position, velocity, angle and angular velocity, and, when trails are drawn,
//! the positions at every earlier frame (a trail needs them all). A restored simulation continues bit for bit
//! as the original run, so a shard's frames equal a single run's byte for byte.
//!
//! A checkpoint is keyed by the scene's hash (which covers `--set` overrides), the
//! integrator, dt, the number of bodies, whether trails are on, and the program
//! version; a checkpoint with another key is never used. Only methods that keep no
//! state from one step to the next can resume from positions and velocities alone;
//! for any other method (an adaptive method's step size, a cached acceleration)
//! checkpoints are refused with a message rather than silently wrong.
//!
//! File format (`checkpoint-<key>-<frame>.bin`, written atomically): the line
//! `physframes checkpoint 3`, one line of JSON with the key fields and sizes, then the
//! payload as little-endian f64: positions (x, y per body), velocities, angles and
//! angular velocities (θ, ω per body), then the trail (x, y per body per earlier
//! frame), then the resting contacts' warm start (four words a point), then each
//! collider's time at rest (one word each; infinity for a body asleep). The JSON
//! records the payload's SHA-256. (Version 1, before bodies turned, had no θ and ω;
//! version 2, before bodies slept, had no times at rest; their files are not read.)

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec2;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::{Error, Result};
use crate::history::{HistoryWriter, PointHistory};
use crate::output::write_atomic;
use crate::scene::Scene;
use crate::sim::contacts::WarmPoint;
use crate::sim::{IntegratorKind, Simulation, State};

/// The integration methods whose whole state between steps is t, the positions and the
/// velocities, so that a checkpoint restores them exactly. A method is added here only
/// after `restoring_is_bit_exact_for_every_supported_method` covers it.
const METHODS_WITHOUT_STEP_STATE: &[&str] =
    &["euler", "symplectic-euler", "midpoint", "heun", "rk4"];

/// The first line of every checkpoint file.
const MAGIC: &str = "physframes checkpoint 3\n";

/// Where checkpoints live and how often a render writes them.
#[derive(Clone, Debug)]
pub struct CheckpointOptions {
    /// The folder checkpoints are read from and written to.
    pub dir: PathBuf,
    /// Write a checkpoint after every frame that is a multiple of this; `None` only
    /// reads them.
    pub every: Option<u64>,
}

/// Returns `Ok` when checkpoints can restore a run of `kind` exactly, or else says why
/// not.
pub fn supports(kind: IntegratorKind) -> std::result::Result<(), String> {
    if METHODS_WITHOUT_STEP_STATE.contains(&kind.name()) {
        return Ok(());
    }
    Err(format!(
        "checkpoints are not available for integrator `{kind}`: it may keep state from one step to the next (an adaptive step size, a cached acceleration) that a checkpoint of positions and velocities cannot restore exactly; checkpoints work with: {}",
        METHODS_WITHOUT_STEP_STATE.join(", ")
    ))
}

/// The identity of a run: which checkpoints belong to it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunKey {
    pub scene_hash: String,
    pub integrator: String,
    /// The bits of dt.
    pub dt_bits: u64,
    pub bodies: usize,
    pub trails: bool,
    pub program_version: String,
}

impl RunKey {
    /// Returns the key of a render of `scene` with `integrator`.
    pub fn new(scene: &Scene, integrator: IntegratorKind) -> Self {
        RunKey {
            scene_hash: scene.source.hash.clone(),
            integrator: integrator.name().to_string(),
            dt_bits: scene.simulation.dt.to_bits(),
            bodies: scene.bodies.len(),
            trails: scene.render.trails,
            program_version: env!("CARGO_PKG_VERSION").to_string(),
        }
    }

    /// Returns a short hexadecimal digest of the key, used in file names.
    pub fn digest(&self) -> String {
        let json = serde_json::to_string(self).unwrap_or_default();
        hex(&Sha256::digest(json.as_bytes()))[..16].to_string()
    }

    fn file_name(&self, frame: u64) -> String {
        format!("checkpoint-{}-{frame:06}.bin", self.digest())
    }
}

/// The state of a run after one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    /// The frame k whose state this is.
    pub frame: u64,
    /// Steps taken from t = 0.
    pub steps: u64,
    pub t: f64,
    pub pos: Vec<DVec2>,
    pub vel: Vec<DVec2>,
    pub angle: Vec<f64>,
    pub omega: Vec<f64>,
    /// Positions at frames 0 .. frame (not including it), when trails are on.
    pub trail: Vec<Arc<[DVec2]>>,
    /// The resting contacts' impulses, which start the next step's solver: part of the
    /// state of a scene with collisions.
    pub contacts: Vec<WarmPoint>,
    /// Each collider's time at rest, `f64::INFINITY` for one asleep: part of the state
    /// of a scene whose bodies sleep (empty otherwise).
    pub sleep: Vec<f64>,
}

/// The JSON line of a checkpoint file.
#[derive(Debug, Serialize, Deserialize)]
struct Header {
    key: RunKey,
    frame: u64,
    steps: u64,
    t_bits: u64,
    trail_frames: u64,
    #[serde(default)]
    contact_points: u64,
    #[serde(default)]
    sleep_entries: u64,
    payload_sha256: String,
}

impl Checkpoint {
    /// Records the simulation's state after frame `frame`; `history` holds the
    /// positions at frames 0 ..= frame when trails are on, and is empty otherwise. The
    /// trail is copied out of the shared history (one pointer a frame), which the file
    /// needs anyway.
    pub fn capture(frame: u64, sim: &Simulation, history: &PointHistory) -> Self {
        let state = sim.state();
        Checkpoint {
            frame,
            steps: sim.steps(),
            t: state.t,
            pos: state.pos.clone(),
            vel: state.vel.clone(),
            angle: state.angle.clone(),
            omega: state.omega.clone(),
            trail: history
                .iter()
                .take(usize::try_from(frame).unwrap_or(usize::MAX))
                .cloned()
                .collect(),
            contacts: sim.contacts().map_or_else(Vec::new, |c| c.warm_start()),
            sleep: sim
                .contacts()
                .map_or_else(Vec::new, |c| c.sleep_state().to_vec()),
        }
    }

    /// Rebuilds the simulation of `scene` at this checkpoint.
    pub fn restore(&self, scene: &Scene, integrator: IntegratorKind) -> Simulation {
        let mut state = State::new(self.t, self.pos.clone(), self.vel.clone());
        state.angle.clone_from(&self.angle);
        state.omega.clone_from(&self.omega);
        let mut sim = scene
            .simulation_from(state, integrator)
            .continuing(scene.initial_state().t, self.steps);
        sim.set_contact_warm_start(&self.contacts);
        sim.set_contact_sleep_state(&self.sleep);
        sim
    }

    /// Serialises the checkpoint.
    fn to_bytes(&self, key: &RunKey) -> Vec<u8> {
        let mut payload = Vec::with_capacity(16 * self.pos.len() * (3 + self.trail.len()));
        let mut put = |v: &DVec2| {
            payload.extend_from_slice(&v.x.to_bits().to_le_bytes());
            payload.extend_from_slice(&v.y.to_bits().to_le_bytes());
        };
        self.pos.iter().for_each(&mut put);
        self.vel.iter().for_each(&mut put);
        // (θ, ω) of each body, as one pair.
        for (theta, omega) in self.angle.iter().zip(&self.omega) {
            put(&DVec2::new(*theta, *omega));
        }
        for frame in &self.trail {
            frame.iter().for_each(&mut put);
        }
        // Each warm-start point as two pairs of words: (i·2³² + j, features) and
        // (P_n, P_t).
        for &(i, j, id, pn, pt) in &self.contacts {
            let pair = (u64::from(i) << 32) | u64::from(j);
            payload.extend_from_slice(&pair.to_le_bytes());
            payload.extend_from_slice(&id.to_le_bytes());
            payload.extend_from_slice(&pn.to_bits().to_le_bytes());
            payload.extend_from_slice(&pt.to_bits().to_le_bytes());
        }
        // Each collider's time at rest, as the bits of an f64.
        for still in &self.sleep {
            payload.extend_from_slice(&still.to_bits().to_le_bytes());
        }
        let header = Header {
            key: key.clone(),
            frame: self.frame,
            steps: self.steps,
            t_bits: self.t.to_bits(),
            trail_frames: self.trail.len() as u64,
            contact_points: self.contacts.len() as u64,
            sleep_entries: self.sleep.len() as u64,
            payload_sha256: hex(&Sha256::digest(&payload)),
        };
        let mut out = Vec::with_capacity(payload.len() + 512);
        out.extend_from_slice(MAGIC.as_bytes());
        // A header of plain fields always serialises.
        let json = serde_json::to_string(&header).unwrap_or_default();
        let _ = writeln!(out, "{json}");
        out.extend_from_slice(&payload);
        out
    }

    /// Reads a checkpoint, returning `None` unless it is complete, intact and of `key`.
    fn from_bytes(bytes: &[u8], key: &RunKey) -> Option<Self> {
        let rest = bytes.strip_prefix(MAGIC.as_bytes())?;
        let newline = rest.iter().position(|b| *b == b'\n')?;
        let header: Header = serde_json::from_slice(&rest[..newline]).ok()?;
        let payload = &rest[newline + 1..];
        if header.key != *key || hex(&Sha256::digest(payload)) != header.payload_sha256 {
            return None;
        }
        let n = key.bodies;
        let frames = usize::try_from(header.trail_frames).ok()?;
        let expected_frames = if key.trails { header.frame } else { 0 };
        let points = usize::try_from(header.contact_points).ok()?;
        let sleep_entries = usize::try_from(header.sleep_entries).ok()?;
        let state_bytes = 16 * n * (3 + frames);
        if header.trail_frames != expected_frames
            || payload.len() != state_bytes + 32 * points + 8 * sleep_entries
        {
            return None;
        }
        let (payload, rest) = payload.split_at(state_bytes);
        let (warm, sleep) = rest.split_at(32 * points);
        let word = |c: &[u8]| u64::from_le_bytes(c.try_into().unwrap_or_default());
        let contacts = warm
            .chunks_exact(32)
            .map(|c| {
                let pair = word(&c[..8]);
                (
                    (pair >> 32) as u32,
                    pair as u32,
                    word(&c[8..16]),
                    f64::from_bits(word(&c[16..24])),
                    f64::from_bits(word(&c[24..32])),
                )
            })
            .collect();
        let vectors: Vec<DVec2> = payload
            .chunks_exact(16)
            .map(|c| {
                let x = u64::from_le_bytes(c[..8].try_into().unwrap_or_default());
                let y = u64::from_le_bytes(c[8..].try_into().unwrap_or_default());
                DVec2::new(f64::from_bits(x), f64::from_bits(y))
            })
            .collect();
        Some(Checkpoint {
            frame: header.frame,
            steps: header.steps,
            t: f64::from_bits(header.t_bits),
            pos: vectors[..n].to_vec(),
            vel: vectors[n..2 * n].to_vec(),
            angle: vectors[2 * n..3 * n].iter().map(|p| p.x).collect(),
            omega: vectors[2 * n..3 * n].iter().map(|p| p.y).collect(),
            trail: vectors[3 * n..]
                .chunks_exact(n.max(1))
                .map(Arc::from)
                .collect(),
            contacts,
            sleep: sleep
                .chunks_exact(8)
                .map(|c| f64::from_bits(word(c)))
                .collect(),
        })
    }
}

/// Writes checkpoints of one run as it goes.
#[derive(Debug)]
pub struct CheckpointWriter {
    dir: PathBuf,
    key: RunKey,
    every: u64,
    written: u64,
}

impl CheckpointWriter {
    /// Prepares to write a checkpoint every `every` frames into `dir`.
    pub fn new(dir: &Path, key: RunKey, every: u64) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io("cannot create", dir, e))?;
        Ok(CheckpointWriter {
            dir: dir.to_path_buf(),
            key,
            every: every.max(1),
            written: 0,
        })
    }

    /// Called after the simulation reaches frame `frame`: writes a checkpoint when the
    /// frame is a positive multiple of the interval and none is there yet.
    pub fn after_frame(
        &mut self,
        frame: u64,
        sim: &Simulation,
        history: &PointHistory,
    ) -> Result<()> {
        if frame == 0 || !frame.is_multiple_of(self.every) {
            return Ok(());
        }
        let path = self.dir.join(self.key.file_name(frame));
        if path.exists() {
            return Ok(());
        }
        let bytes = Checkpoint::capture(frame, sim, history).to_bytes(&self.key);
        write_atomic(&path, &bytes)?;
        self.written += 1;
        Ok(())
    }

    /// Returns how many checkpoints this writer wrote.
    pub fn written(&self) -> u64 {
        self.written
    }
}

/// What [`save_run`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SaveReport {
    /// Checkpoints written.
    pub written: u64,
    /// The frame the simulation started from (0, or an earlier checkpoint's).
    pub started_from_frame: u64,
}

/// Simulates `scene` up to frame `end - 1`, drawing nothing, and writes a checkpoint
/// into `dir` every `every` frames: the cheap first stage of a render spread over
/// several machines. Starts from the latest checkpoint already there.
pub fn save_run(scene: &Scene, dir: &Path, every: u64, end: u64) -> Result<SaveReport> {
    let integrator = scene.simulation.integrator;
    supports(integrator).map_err(Error::Usage)?;
    let key = RunKey::new(scene, integrator);
    let mut writer = CheckpointWriter::new(dir, key.clone(), every)?;
    let start = nearest(dir, &key, end.saturating_sub(1));
    let (mut sim, mut history, first) = match &start {
        Some(c) => (
            c.restore(scene, integrator),
            c.trail.iter().cloned().collect(),
            c.frame,
        ),
        None => (scene.simulation_with(integrator), HistoryWriter::new(), 0),
    };
    for k in first..end {
        sim.advance_to(scene.frame_time(k)).map_err(|b| {
            Error::BlowUp(format!(
                "{}\ncheckpoints before it were written",
                crate::blowup::blow_up_message(scene, &b)
            ))
        })?;
        if scene.render.trails {
            history.push(Arc::from(sim.state().pos.as_slice()));
        }
        writer.after_frame(k, &sim, history.history())?;
    }
    Ok(SaveReport {
        written: writer.written(),
        started_from_frame: first,
    })
}

/// Returns the latest checkpoint of run `key` in `dir` at or before frame `frame`, if
/// there is a usable one. A missing folder, another run's files and damaged files are
/// not errors: they are simply not used.
pub fn nearest(dir: &Path, key: &RunKey, frame: u64) -> Option<Checkpoint> {
    let prefix = format!("checkpoint-{}-", key.digest());
    let mut found: Vec<(u64, PathBuf)> = std::fs::read_dir(dir)
        .ok()?
        .flatten()
        .filter_map(|entry| {
            let name = entry.file_name();
            let k = name
                .to_str()?
                .strip_prefix(&prefix)?
                .strip_suffix(".bin")?
                .parse::<u64>()
                .ok()?;
            (k <= frame).then(|| (k, entry.path()))
        })
        .collect();
    found.sort();
    found.into_iter().rev().find_map(|(k, path)| {
        let bytes = std::fs::read(&path).ok()?;
        Checkpoint::from_bytes(&bytes, key).filter(|c| c.frame == k)
    })
}

/// Returns bytes as lowercase hexadecimal.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse;

    const SCENE: &str = r#"
[simulation]
dt = 0.01
duration = 1.0
[render]
width = 32
height = 32
fps = 25
trails = true
view = { min = [-5.0, -5.0], max = [5.0, 5.0] }
[[body]]
name = "a"
mass = 1.0
velocity = [1.0, 0.5]
[[body]]
name = "b"
mass = 2.0
position = [1.0, 0.0]
[[force]]
kind = "spring"
a = "a"
b = "b"
stiffness = 3.0
[[force]]
kind = "force"
f1 = [0.3, 0.1]
"#;

    fn scene() -> Scene {
        parse(Path::new("t.toml"), SCENE).expect("a valid scene")
    }

    /// The scene above with bodies that turn: the spring hooked off both centres of
    /// mass, a torque on one and angular drag on the other.
    fn turning_scene() -> Scene {
        let text = SCENE.replace(
            "stiffness = 3.0",
            "stiffness = 3.0\na_at = [0.1, 0.05]\nb_at = [-0.2, 0.0]\n[[force]]\nkind = \"torque\"\ntau = 0.4\nbodies = [\"a\"]\n[[force]]\nkind = \"angular-drag\"\nk = 0.1\nbodies = [\"b\"]",
        );
        parse(Path::new("t.toml"), &text).expect("a valid scene")
    }

    #[test]
    fn restoring_is_bit_exact_for_every_supported_method() {
        for scene in [scene(), turning_scene()] {
            restoring_is_bit_exact(&scene);
        }
    }

    fn restoring_is_bit_exact(scene: &Scene) {
        let turns = scene.system().spins();
        for kind in IntegratorKind::ALL
            .iter()
            .copied()
            .filter(|k| supports(*k).is_ok())
        {
            let mut straight = Simulation::new(
                scene.system(),
                scene.initial_state(),
                kind,
                scene.simulation.dt,
            );
            let mut history: HistoryWriter<Arc<[DVec2]>> = HistoryWriter::new();
            for k in 0..=10 {
                straight.advance_to(scene.frame_time(k)).expect("finite");
                history.push(Arc::from(straight.state().pos.as_slice()));
            }
            let checkpoint = Checkpoint::capture(10, &straight, history.history());
            // The trail holds the positions at frames 0 .. 10, not frame 10's own.
            let first_ten: Vec<Arc<[DVec2]>> = history.history().iter().take(10).cloned().collect();
            assert_eq!(checkpoint.trail, first_ten);
            let key = RunKey::new(scene, kind);
            let bytes = checkpoint.to_bytes(&key);
            let read = Checkpoint::from_bytes(&bytes, &key).expect("reads back");
            assert_eq!(read, checkpoint, "{kind}");
            let mut resumed = read.restore(scene, kind);
            straight.advance_to(scene.frame_time(25)).expect("finite");
            resumed.advance_to(scene.frame_time(25)).expect("finite");
            let (a, b) = (straight.state(), resumed.state());
            assert_eq!(a.t.to_bits(), b.t.to_bits(), "{kind}: t");
            for (p, q) in a.pos.iter().chain(&a.vel).zip(b.pos.iter().chain(&b.vel)) {
                assert_eq!(p.x.to_bits(), q.x.to_bits(), "{kind}");
                assert_eq!(p.y.to_bits(), q.y.to_bits(), "{kind}");
            }
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a.angle), bits(&b.angle), "{kind}: θ");
            assert_eq!(bits(&a.omega), bits(&b.omega), "{kind}: ω");
            // In the turning scene, the angles did move.
            assert_eq!(a.omega.iter().any(|w| *w != 0.0), turns, "{kind}");
        }
    }

    #[test]
    fn a_checkpoint_of_another_run_or_a_damaged_one_is_not_read() {
        let scene = scene();
        let key = RunKey::new(&scene, IntegratorKind::Euler);
        let sim = Simulation::new(
            scene.system(),
            scene.initial_state(),
            IntegratorKind::Euler,
            scene.simulation.dt,
        );
        let history: HistoryWriter<Arc<[DVec2]>> = vec![Arc::from(&[DVec2::ONE, DVec2::X][..]); 3]
            .into_iter()
            .collect();
        let bytes = Checkpoint::capture(2, &sim, history.history()).to_bytes(&key);
        assert_eq!(
            Checkpoint::from_bytes(&bytes, &key).map(|c| c.trail.len()),
            Some(2)
        );
        let mut other = key.clone();
        other.scene_hash = "0".repeat(64);
        assert!(Checkpoint::from_bytes(&bytes, &other).is_none());
        let mut damaged = bytes.clone();
        let last = damaged.len() - 1;
        damaged[last] ^= 1;
        assert!(Checkpoint::from_bytes(&damaged, &key).is_none());
        assert!(Checkpoint::from_bytes(&bytes[..bytes.len() - 8], &key).is_none());
    }

    /// A box that falls asleep on a floor, and a ball that wakes it at about 1.3 s.
    const SLEEPING: &str = r#"
[simulation]
dt = 0.004166666666666667
duration = 3.0
[render]
width = 32
height = 32
fps = 30
view = { min = [-2.0, -1.0], max = [2.0, 10.0] }
[contacts]
restitution = 0.3
friction = 0.5
[[body]]
name = "floor"
static = true
position = [0.0, -0.5]
shape = { box = { width = 4.0, height = 1.0 } }
[[body]]
name = "box"
mass = 1.0
position = [0.0, 0.25]
shape = { box = { width = 0.5, height = 0.5 } }
[[body]]
name = "ball"
mass = 1.0
position = [0.1, 8.6]
shape = { circle = { radius = 0.1 } }
[[force]]
kind = "gravity"
"#;

    #[test]
    fn a_checkpoint_carries_which_bodies_sleep() {
        let scene = parse(Path::new("t.toml"), SLEEPING).expect("a valid scene");
        let kind = IntegratorKind::Euler;
        let key = RunKey::new(&scene, kind);
        let mut straight = scene.simulation();
        // Frame 30 (t = 1 s): the box has slept since 0.5 s; the ball still falls.
        straight.advance_to(scene.frame_time(30)).expect("finite");
        let history: HistoryWriter<Arc<[DVec2]>> = HistoryWriter::new();
        let checkpoint = Checkpoint::capture(30, &straight, history.history());
        assert_eq!(checkpoint.sleep.len(), 3);
        assert_eq!(checkpoint.sleep[1], f64::INFINITY, "the box sleeps");
        assert!(checkpoint.sleep[2].is_finite(), "the ball is awake");
        let read = Checkpoint::from_bytes(&checkpoint.to_bytes(&key), &key).expect("reads");
        assert_eq!(read, checkpoint);
        let mut resumed = read.restore(&scene, kind);
        let sleep = |sim: &Simulation| sim.contacts().map(|c| c.sleep_state().to_vec());
        assert_eq!(sleep(&resumed), sleep(&straight));
        let end = scene.frame_time(90);
        for sim in [&mut straight, &mut resumed] {
            sim.advance_to(end).expect("finite");
        }
        let bits = |sim: &Simulation| {
            let s = sim.state();
            let mut v: Vec<u64> = s
                .pos
                .iter()
                .chain(&s.vel)
                .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
                .collect();
            v.extend(s.angle.iter().chain(&s.omega).map(|x| x.to_bits()));
            v
        };
        assert_eq!(bits(&straight), bits(&resumed));
        assert_eq!(sleep(&straight), sleep(&resumed));
        // The ball did strike the box after the checkpoint.
        assert!(straight.state().pos[2].y < 1.0);
    }

    #[test]
    fn methods_that_may_keep_step_state_are_refused() {
        assert!(supports(IntegratorKind::Euler).is_ok());
        assert!(!METHODS_WITHOUT_STEP_STATE.contains(&"dopri5"));
    }
}
