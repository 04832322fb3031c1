//! Scenes: the TOML file format, its validation, and the checked [`Scene`] that the
//! rest of the program trusts.
//!
//! A scene file is read once. [`raw`] gives every value the byte span it came from;
//! `validate` checks every rule and reports all problems with their file, line and
//! column; what passes is a [`Scene`] in which every number is finite and in range and
//! every name resolves. Code downstream never re-checks the scene, and a scene that
//! validates cannot make a step panic.

mod color;
mod diagnostic;
pub mod expr;
mod frontend;
mod inertia;
pub mod layers;
mod overrides;
pub mod raw;
mod slices;
pub mod swarm;
mod validate;

use std::path::{Path, PathBuf};

use glam::DVec2;

pub use color::Rgba;
pub use diagnostic::{Diagnostic, SceneError, Sources};
pub use frontend::{hash_with_overrides, parse, parse_with_overrides};
pub use layers::Layers;
pub use validate::{MAX_BODIES, MAX_BODY_STEPS, MAX_FRAMES, MAX_IMAGE_SIDE, MAX_STEPS};

use crate::sim::contacts::{Collider, PolygonProblem};
use crate::sim::{Contacts, ForceSpec, IntegratorKind, Simulation, State, System, Tolerances};

/// A validated scene, ready to simulate and render.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The scene's name: the `name` key, or the file's stem.
    pub name: String,
    /// Where the scene came from.
    pub source: Source,
    /// How to integrate.
    pub simulation: SimulationSettings,
    /// How to draw.
    pub render: RenderSettings,
    /// The bodies, in file order; a body's index is its position here.
    pub bodies: Vec<Body>,
    /// The forces, in file order.
    pub forces: Vec<ForceSpec>,
    /// Axes, fields and curves drawn with the bodies (see [`layers`]).
    pub layers: Layers,
    /// Collisions, when the scene has a `[contacts]` table.
    pub contacts: Option<ContactSettings>,
}

/// The `[contacts]` table, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSettings {
    /// The scene's coefficient of restitution e, 0 ≤ e ≤ 1 (default 1); a body's
    /// `restitution` overrides it, and a pair uses the larger of its two values.
    pub restitution: f64,
    /// An absolute contact tolerance for every pair, or `None` for
    /// [`crate::sim::contacts::DEFAULT_TOLERANCE`] times the smaller body's size.
    pub tolerance: Option<f64>,
    /// The scene's friction coefficient μ ≥ 0 (default 0); a body's `friction`
    /// overrides it, and a pair uses √(μ_a·μ_b).
    pub friction: f64,
    /// How contacts rest (see [`crate::sim::contacts::Resting`]).
    pub resting: crate::sim::contacts::Resting,
    /// The bodies that collide, in body order: circles, boxes and convex polygons.
    pub bodies: Vec<usize>,
}

/// Where a scene came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Source {
    /// The path the user gave.
    pub path: PathBuf,
    /// The SHA-256 of the file's bytes, in lowercase hexadecimal; with overrides, of
    /// the file's bytes followed by each override (see [`hash_with_overrides`]).
    pub hash: String,
    /// The `--set KEY=VALUE` overrides applied to the file, in order.
    pub overrides: Vec<String>,
}

/// The `[simulation]` table, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationSettings {
    /// The integration method.
    pub integrator: IntegratorKind,
    /// The step h.
    pub dt: f64,
    /// The simulated time asked for.
    pub duration: f64,
    /// The error tolerances of the adaptive `dopri5` (`rtol`, `atol`); unused by the
    /// fixed-step methods.
    pub tolerances: Tolerances,
    /// Other runs of the same scene to draw beside the main one, as ghosts.
    pub compare: Vec<CompareRun>,
}

/// One entry of `compare`: another integrator, or the closed-form solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompareRun {
    Integrator(IntegratorKind),
    Exact,
}

/// The `[render]` table, checked, with the frame timing derived from it.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels, 1 to 16384.
    pub width: u32,
    /// Image height in pixels, 1 to 16384.
    pub height: u32,
    /// Frames per second of simulated time.
    pub fps: f64,
    /// The world rectangle to show.
    pub view: View,
    /// The background colour.
    pub background: Rgba,
    /// Whether to draw the path of each centre of mass so far.
    pub trails: bool,
    /// World length of a velocity arrow per unit of speed; `None` fits it to the
    /// fastest body at t = 0.
    pub velocity_scale: Option<f64>,
    /// World length of a force arrow per unit of force; `None` fits it to the
    /// largest force at t = 0.
    pub force_scale: Option<f64>,
    /// Whether each frame shows a line with t and the frame number.
    pub hud: bool,
    /// Whether the bodies (and their arrows) are drawn; their trails are drawn when
    /// `trails` is set either way (a phase plot may show only traces or paths).
    pub show_bodies: bool,
    /// Whether springs are drawn, as coils between their ends, under the bodies.
    pub show_springs: bool,
    /// Steps between two frames: 1/fps = steps_per_frame·dt.
    pub steps_per_frame: u64,
    /// Number of frames: k = 0 ..= floor(duration·fps).
    pub frame_count: u64,
}

/// A rectangle of the world, min < max on both axes; y points up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub min: DVec2,
    pub max: DVec2,
}

impl View {
    /// Returns the pixels per world unit that fit this view inside a `width` × `height`
    /// image with square world units: s = min(W / view width, H / view height).
    pub fn fit_scale(&self, width: u32, height: u32) -> f64 {
        let extent = self.max - self.min;
        (f64::from(width) / extent.x).min(f64::from(height) / extent.y)
    }
}

impl Shape {
    /// Returns the distance from the centre of mass to the farthest point of the
    /// shape, in world units.
    pub fn reach(&self) -> f64 {
        match self {
            Shape::Circle { radius } => *radius,
            Shape::Box { width, height } => 0.5 * width.hypot(*height),
            Shape::Polygon { points } => points.iter().map(|p| p.length()).fold(0.0, f64::max),
            Shape::Points { points } => {
                points.iter().map(|p| p.offset.length()).fold(0.0, f64::max)
            }
        }
    }
}

/// The largest size a body may have on screen, in pixels. Far larger shapes are
/// certainly a mistake of units, and would overflow the rasteriser's fixed-point
/// arithmetic.
pub const MAX_SHAPE_PIXELS: f64 = 1e6;

/// One body: hot initial state for the simulation, cold looks for the renderer.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: String,
    /// The total mass M.
    pub mass: f64,
    /// The initial position of the centre of mass.
    pub position: DVec2,
    /// The initial velocity of the centre of mass.
    pub velocity: DVec2,
    /// The initial orientation θ in radians, counter-clockwise: the body's points p
    /// (body coordinates) start at position + R(θ)·(p - centre).
    pub angle: f64,
    /// The initial angular velocity ω = dθ/dt.
    pub angular_velocity: f64,
    /// The moment of inertia I about the centre of mass: from the shape and mass, or
    /// the scene's `inertia`. Zero only for a body of point masses all at one point,
    /// which cannot turn.
    pub inertia: f64,
    /// The centre of mass c in body coordinates, the coordinates in which the scene
    /// writes polygon points, point-mass offsets, forces' `at` and springs' anchors
    /// (a circle's and a box's centre is their origin).
    pub centre: DVec2,
    /// True when something may turn the body during the run (it spins at the start, or
    /// a torque, a force off its centre of mass or a spring anchored off it acts on
    /// it); the renderer then draws it at each frame's angle.
    pub turns: bool,
    /// What to draw, relative to the centre of mass, at angle 0.
    pub shape: Shape,
    pub color: Rgba,
    pub show_velocity: bool,
    pub show_force: bool,
    /// True for an immovable body (`static = true`): infinite mass and moment of
    /// inertia, which forces do not move; `mass` and `inertia` are then 0.
    pub is_static: bool,
    /// The body's own coefficient of restitution, which overrides the scene's.
    pub restitution: Option<f64>,
    /// The body's own friction coefficient, which overrides the scene's.
    pub friction: Option<f64>,
}

/// A body's outline, in world units relative to its centre of mass.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Circle {
        radius: f64,
    },
    Box {
        width: f64,
        height: f64,
    },
    /// A polygon of uniform density; vertices relative to its area centroid.
    Polygon {
        points: Vec<DVec2>,
    },
    /// A body made of point masses; offsets relative to the centre of mass.
    Points {
        points: Vec<PointMass>,
    },
}

/// One point mass of a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMass {
    /// The offset from the body's centre of mass.
    pub offset: DVec2,
    pub mass: f64,
}

impl Scene {
    /// Reads and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene, LoadError> {
        Self::load_with(path, &[])
    }

    /// Reads a scene file, applies `--set KEY=VALUE` overrides in order, and validates
    /// the result; a problem in an override is reported in that override.
    pub fn load_with(path: &Path, overrides: &[String]) -> Result<Scene, LoadError> {
        let bytes = std::fs::read(path).map_err(|e| LoadError::Io {
            path: path.to_path_buf(),
            source: e,
        })?;
        let text = String::from_utf8(bytes).map_err(|e| LoadError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidData, e),
        })?;
        frontend::parse_with_overrides(path, &text, overrides).map_err(LoadError::Invalid)
    }

    /// Returns the time of frame k, t = k·steps_per_frame·dt (= k/fps to 1e-9).
    pub fn frame_time(&self, k: u64) -> f64 {
        (k * self.render.steps_per_frame) as f64 * self.simulation.dt
    }

    /// Returns the total number of steps to reach the last frame.
    pub fn total_steps(&self) -> u64 {
        (self.render.frame_count - 1) * self.render.steps_per_frame
    }

    /// Returns the masses, moments of inertia and forces, for the simulation.
    pub fn system(&self) -> System {
        System::rigid(
            self.bodies.iter().map(|b| b.mass).collect(),
            self.bodies.iter().map(|b| b.inertia).collect(),
            self.bodies.iter().map(|b| b.centre).collect(),
            &self.forces,
        )
    }

    /// Returns a simulation of this scene from t = 0 with its integrator, step and
    /// tolerances.
    pub fn simulation(&self) -> Simulation {
        self.simulation_with(self.simulation.integrator)
    }

    /// Returns a simulation of this scene from t = 0 with another integrator.
    pub fn simulation_with(&self, integrator: IntegratorKind) -> Simulation {
        self.simulation_from(self.initial_state(), integrator)
    }

    /// Returns a simulation of this scene from a given state (a checkpoint's, say),
    /// with its step, tolerances and collisions.
    pub fn simulation_from(&self, state: State, integrator: IntegratorKind) -> Simulation {
        let sim = Simulation::new(self.system(), state, integrator, self.simulation.dt)
            .with_tolerances(self.simulation.tolerances);
        match self.contacts() {
            Some(c) => sim.with_contacts(c),
            None => sim,
        }
    }

    /// Returns the colliding bodies of a scene with `[contacts]`.
    pub fn contacts(&self) -> Option<Contacts> {
        let restless = self.restless();
        Some(
            contacts_of(&self.bodies, self.contacts.as_ref()?)
                .with_restless(|b| restless.get(b).copied().unwrap_or(true)),
        )
    }

    /// Returns, for each body, whether it must never sleep: a force that changes with
    /// time acts on it, or a spring ties it to another body (whose motion would change
    /// the spring's pull on a sleeping body without waking it).
    pub fn restless(&self) -> Vec<bool> {
        let n = self.bodies.len();
        let mut restless = vec![false; n];
        for f in &self.forces {
            match f {
                ForceSpec::TimeVarying { f1, bodies, .. } if *f1 != glam::DVec2::ZERO => {
                    for (i, r) in restless.iter_mut().enumerate() {
                        *r |= bodies.contains(i);
                    }
                }
                ForceSpec::Spring {
                    a,
                    b: crate::sim::forces::Anchor::Body(b),
                    ..
                } => {
                    for k in [*a as usize, *b as usize] {
                        if let Some(r) = restless.get_mut(k) {
                            *r = true;
                        }
                    }
                }
                _ => {}
            }
        }
        restless
    }

    /// Returns the state at t = 0.
    pub fn initial_state(&self) -> State {
        let mut state = State::new(
            0.0,
            self.bodies.iter().map(|b| b.position).collect(),
            self.bodies.iter().map(|b| b.velocity).collect(),
        );
        state.angle = self.bodies.iter().map(|b| b.angle).collect();
        state.omega = self.bodies.iter().map(|b| b.angular_velocity).collect();
        state
    }

    /// Returns the bodies' names, indexed like the simulation's arrays.
    pub fn body_names(&self) -> Vec<&str> {
        self.bodies.iter().map(|b| b.name.as_str()).collect()
    }
}

/// Returns the colliders of the bodies `[contacts]` selects, each with its
/// restitution (its own, or the scene's).
pub(crate) fn contacts_of(bodies: &[Body], settings: &ContactSettings) -> Contacts {
    // Validation refuses a colliding body whose collider cannot be built.
    let colliders = settings
        .bodies
        .iter()
        .filter_map(|&i| collider_of(i, &bodies[i], settings).ok())
        .collect();
    Contacts::new(colliders, settings.tolerance).with_resting(settings.resting)
}

/// Returns the collider of body i, with its restitution and friction (its own, or the
/// scene's), or why its shape cannot collide.
pub(crate) fn collider_of(
    i: usize,
    b: &Body,
    settings: &ContactSettings,
) -> Result<Collider, PolygonProblem> {
    let e = b.restitution.unwrap_or(settings.restitution);
    let mu = b.friction.unwrap_or(settings.friction);
    let c = match &b.shape {
        Shape::Circle { radius } => Ok(Collider::disc(i, *radius, e)),
        Shape::Box { width, height } => Collider::rectangle(i, *width, *height, e),
        Shape::Polygon { points } => Collider::polygon(i, points.clone(), e),
        Shape::Points { .. } => Err(PolygonProblem::Degenerate),
    };
    c.map(|c| c.with_friction(mu))
}

/// Sets [`Body::turns`] on every body that something may turn during the run: one
/// that spins at the start, or one on which a torque, a force off its centre of mass
/// or a spring anchored off it acts.
pub(crate) fn mark_turning(bodies: &mut [Body], forces: &[ForceSpec]) {
    let centre: Vec<DVec2> = bodies.iter().map(|b| b.centre).collect();
    let mut turned = vec![false; bodies.len()];
    crate::sim::forces::ForceSet::new(forces, bodies.len(), Some(&centre))
        .mark_torque_targets(&centre, &mut turned);
    for (body, torqued) in bodies.iter_mut().zip(turned) {
        // Nothing turns a static body (1/I = 0).
        body.turns = !body.is_static && (torqued || body.angular_velocity != 0.0);
    }
}

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("cannot read scene file {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file was read but is not a valid scene.
    #[error("{0}")]
    Invalid(SceneError),
}
