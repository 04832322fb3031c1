//! Figures: the article's figures built in as scenes, and single frames of any scene
//! drawn to one PNG.
//!
//! A built-in figure is an ordinary scene file under `scenes/figures/`, embedded with
//! `include_str!`, so the file a user copies and edits is the one the binary draws.
//! [`render_frame`] simulates a scene up to one frame (keeping trails and traces) and
//! draws it exactly as `physframes render` would; the golden tests use it too.

use std::path::Path;

use glam::DVec2;
use tiny_skia::Pixmap;

use crate::error::{Error, Result};
use crate::history::HistoryWriter;
use crate::pipeline;
use crate::render::layers::TraceRecorder;
use crate::render::{encode_png, ArrowScales, Compression, FrameView, Renderer};
use crate::scene::{parse, Scene};

/// A figure built into the binary.
#[derive(Clone, Copy, Debug)]
pub struct BuiltIn {
    /// The name `physframes figure NAME` takes.
    pub name: &'static str,
    /// One line saying what it shows.
    pub description: &'static str,
    /// The scene file it was embedded from, relative to the crate.
    pub path: &'static str,
    /// The scene file's text.
    pub text: &'static str,
}

/// The built-in figures, in the article's order.
pub const BUILT_INS: &[BuiltIn] = &[
    BuiltIn {
        name: "slope-field",
        description: "Figure 2: the slope field of dy/dx = 2x with y = x² and the family y = x² + C",
        path: "scenes/figures/slope-field.toml",
        text: include_str!("../../scenes/figures/slope-field.toml"),
    },
    BuiltIn {
        name: "drag-field",
        description: "Figure 3: the field of dv/dt = -v/m (m = 1), exact decays v0·exp(-t/m) and Euler's steps",
        path: "scenes/figures/drag-field.toml",
        text: include_str!("../../scenes/figures/drag-field.toml"),
    },
];

/// Returns the built-in figure with this name.
pub fn built_in(name: &str) -> Option<&'static BuiltIn> {
    BUILT_INS.iter().find(|b| b.name == name)
}

/// Loads a built-in figure by name, or else a scene file by path.
pub fn load(name_or_path: &str) -> Result<Scene> {
    if let Some(b) = built_in(name_or_path) {
        return parse(Path::new(b.path), b.text).map_err(Error::Scene);
    }
    let path = Path::new(name_or_path);
    if !path.exists() && !name_or_path.ends_with(".toml") {
        let names: Vec<&str> = BUILT_INS.iter().map(|b| b.name).collect();
        return Err(Error::Usage(format!(
            "`{name_or_path}` is neither a built-in figure ({}) nor a scene file",
            names.join(", ")
        )));
    }
    Ok(Scene::load(path)?)
}

/// Simulates `scene` up to frame `frame` and draws that frame, exactly as
/// `physframes render` draws it.
///
/// ```
/// use std::path::Path;
/// use physframes::{figures, scene};
///
/// let text = r##"
///     [render]
///     width = 64
///     height = 48
///     fps = 10
///     view = { min = [-2.0, -1.5], max = [2.0, 1.5] }
///     [[body]]
///     mass = 1.0
///     velocity = [1.0, 0.0]
///     color = "#ff0000"
///     shape = { circle = { radius = 0.3 } }
/// "##;
/// let scene = scene::parse(Path::new("one.toml"), text).expect("a valid scene");
/// let pixmap = figures::render_frame(&scene, 0).expect("drawn");
/// assert_eq!((pixmap.width(), pixmap.height()), (64, 48));
/// // The red disc is at the centre of the image at t = 0; the corner is background.
/// let centre = pixmap.pixel(32, 24).expect("inside");
/// assert_eq!((centre.red(), centre.green()), (255, 0));
/// assert_eq!(pixmap.pixel(0, 0).expect("inside").red(), 255);
/// assert_eq!(pixmap.pixel(0, 0).expect("inside").green(), 255);
/// ```
pub fn render_frame(scene: &Scene, frame: u64) -> Result<Pixmap> {
    let frame_count = scene.render.frame_count;
    if frame >= frame_count {
        return Err(Error::Usage(format!(
            "frame {frame} is past the scene's last frame {}",
            frame_count - 1
        )));
    }
    let mut sim = scene.simulation();
    let mut force = vec![DVec2::ZERO; scene.bodies.len()];
    sim.net_forces(&mut force);
    let renderer = Renderer::new(scene, ArrowScales::fit(scene, &sim.state().vel, &force));
    let mut trail: HistoryWriter<std::sync::Arc<[DVec2]>> = HistoryWriter::new();
    let mut traces = TraceRecorder::new(scene);
    let mut compared = crate::compare::Comparison::new(scene);
    let mut comparison = None;
    for k in 0..=frame {
        sim.advance_to(scene.frame_time(k))
            .map_err(|b| Error::BlowUp(crate::blowup::blow_up_message(scene, &b)))?;
        let state = sim.state();
        if scene.render.trails {
            trail.push(std::sync::Arc::from(state.pos.as_slice()));
        }
        if let Some(c) = &mut compared {
            comparison = Some(c.advance_to(state.t));
        }
        if let Some(traces) = &mut traces {
            traces.record(state.t, &state.pos, &state.vel);
        }
    }
    if renderer.needs_forces() {
        sim.net_forces(&mut force);
    }
    let state = sim.state();
    let view = FrameView {
        index: frame,
        t: state.t,
        pos: &state.pos,
        vel: &state.vel,
        angle: renderer.needs_angles().then_some(state.angle.as_slice()),
        force: renderer.needs_forces().then_some(force.as_slice()),
        trail: scene.render.trails.then_some(trail.history()),
        traces: traces.as_ref().map(|t| t.history()),
        compare: comparison.as_ref(),
    };
    Ok(renderer.draw(&view))
}

/// Draws frame `frame` of `scene` and encodes it as PNG with the scene's provenance.
pub fn render_png(scene: &Scene, frame: u64, compression: Compression) -> Result<Vec<u8>> {
    let pixmap = render_frame(scene, frame)?;
    let provenance = pipeline::provenance(
        scene,
        scene.simulation.integrator,
        scene.frame_time(frame),
        frame,
    );
    encode_png(&pixmap, &provenance, compression)
        .map_err(|e| Error::Runtime(format!("cannot encode the figure: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_figure_is_a_valid_scene_named_like_its_file() {
        for b in BUILT_INS {
            let scene = load(b.name).unwrap_or_else(|e| panic!("{}: {e}", b.name));
            assert_eq!(scene.name, b.name);
            assert!(scene.layers.axes.is_some(), "{}: a figure has axes", b.name);
            let on_disk =
                std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(b.path))
                    .expect("the embedded file exists");
            assert_eq!(on_disk, b.text, "{}: one source", b.name);
        }
    }
}
