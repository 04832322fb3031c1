//! The renderer: one frame's state in, one pixmap out.
//!
//! Rendering reads simulation state and never changes it. Everything that does not
//! move (the background, and later axes and fields) is drawn once per render into a
//! static layer that each frame starts from; everything that moves (trails, bodies,
//! arrows) is drawn over it. Geometry is f64 in the world and f32 in pixels.

pub mod bodies;
pub mod camera;
pub mod clip;
pub mod encode;
pub mod layers;
pub mod plot;
pub mod text;
pub mod ticks;

use std::sync::Arc;

use glam::DVec2;
use tiny_skia::{Color, Pixmap};

pub use camera::Camera;
pub use encode::{encode_png, Compression, Provenance};

use crate::scene::Scene;
use bodies::{draw_arrow, BodyLook};
use clip::ClipRect;

/// The state of one frame, as the renderer sees it.
#[derive(Clone, Copy, Debug)]
pub struct FrameView<'a> {
    /// The frame number k.
    pub index: u64,
    /// The simulated time of the frame.
    pub t: f64,
    /// Centre-of-mass positions.
    pub pos: &'a [DVec2],
    /// Centre-of-mass velocities.
    pub vel: &'a [DVec2],
    /// Net forces, when some body shows its force arrow.
    pub force: Option<&'a [DVec2]>,
    /// The positions at every frame so far (0 ..= index), when trails are on.
    pub trail: Option<&'a [Arc<[DVec2]>]>,
    /// The points of the scene's trace curves at every frame so far (0 ..= index), one
    /// per trace, when the scene has traces (see [`layers::TraceRecorder`]).
    pub traces: Option<&'a [Arc<[DVec2]>]>,
}

/// World length per unit of velocity and per unit of force, for the arrows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArrowScales {
    /// World units per unit of speed (that is, seconds).
    pub velocity: f64,
    /// World units per unit of force.
    pub force: f64,
}

impl ArrowScales {
    /// Uses the scene's `velocity_scale` and `force_scale`, or else chooses scales so
    /// that the longest arrow at the start of the run spans a fifth of the view's
    /// shorter side. The scales stay fixed for the whole run, so arrow lengths can be
    /// compared between frames.
    pub fn fit(scene: &Scene, vel: &[DVec2], force: &[DVec2]) -> Self {
        let view = scene.render.view;
        let target = 0.2 * (view.max - view.min).min_element();
        let longest = |xs: &[DVec2], shown: &dyn Fn(usize) -> bool| {
            xs.iter()
                .enumerate()
                .filter(|(i, _)| shown(*i))
                .map(|(_, v)| v.length())
                .fold(0.0, f64::max)
        };
        let v = longest(vel, &|i| scene.bodies[i].show_velocity);
        let f = longest(force, &|i| scene.bodies[i].show_force);
        let r = &scene.render;
        ArrowScales {
            velocity: r
                .velocity_scale
                .unwrap_or(if v > 0.0 { target / v } else { target }),
            force: r
                .force_scale
                .unwrap_or(if f > 0.0 { target / f } else { target }),
        }
    }
}

/// Draws frames of one scene.
pub struct Renderer {
    camera: Camera,
    width: u32,
    height: u32,
    clip: ClipRect,
    static_layer: Pixmap,
    looks: Vec<BodyLook>,
    arrows: ArrowScales,
    /// Axes, fields, curves, legend and HUD.
    overlay: layers::Overlay,
}

/// The colour of velocity arrows.
fn velocity_color() -> Color {
    Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff)
}

/// The colour of force arrows.
fn force_color() -> Color {
    Color::from_rgba8(0xc0, 0x39, 0x2b, 0xff)
}

impl Renderer {
    /// Prepares everything about a scene's frames that does not change between them.
    pub fn new(scene: &Scene, arrows: ArrowScales) -> Self {
        let r = &scene.render;
        // One transform for bodies and layers: the camera of the axes' plot area when
        // the scene has `[axes]`, else the view fitted to the whole image.
        let (overlay, camera) = layers::Overlay::new(scene);
        let mut static_layer = Pixmap::new(r.width, r.height)
            .expect("the scene validator keeps image sides between 1 and 16384");
        static_layer.fill(bodies::color(r.background, 1.0));
        overlay.draw_static(&mut static_layer);
        let looks = if r.show_bodies {
            scene
                .bodies
                .iter()
                .map(|b| BodyLook::new(b, &camera))
                .collect()
        } else {
            Vec::new()
        };
        Renderer {
            camera,
            width: r.width,
            height: r.height,
            clip: ClipRect::guard(r.width, r.height),
            static_layer,
            looks,
            arrows,
            overlay,
        }
    }

    /// Returns the layers drawn around and over the bodies.
    pub fn overlay(&self) -> &layers::Overlay {
        &self.overlay
    }

    /// Returns the camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Returns true when some body shows its net force, so frames need forces.
    pub fn needs_forces(&self) -> bool {
        self.looks.iter().any(|l| l.show_force)
    }

    /// Draws one frame.
    pub fn draw(&self, frame: &FrameView<'_>) -> Pixmap {
        let mut pixmap = self.static_layer.clone();
        if let Some(trail) = frame.trail {
            for (i, look) in self.looks.iter().enumerate() {
                look.draw_trail(&mut pixmap, &self.camera, &self.clip, trail, i);
            }
        }
        for (i, look) in self.looks.iter().enumerate() {
            let (x, y) = self.camera.to_pixel(frame.pos[i]);
            if !look.is_outside(x, y, self.width, self.height) {
                look.draw(&mut pixmap, x, y);
            }
        }
        for (i, look) in self.looks.iter().enumerate() {
            let at = self.camera.to_pixel_f64(frame.pos[i]);
            if look.show_velocity {
                let d = self
                    .camera
                    .to_pixel_vector_f64(self.arrows.velocity * frame.vel[i]);
                draw_arrow(&mut pixmap, &self.clip, at, d, velocity_color(), 2.0);
            }
            if let (true, Some(force)) = (look.show_force, frame.force) {
                let d = self
                    .camera
                    .to_pixel_vector_f64(self.arrows.force * force[i]);
                draw_arrow(&mut pixmap, &self.clip, at, d, force_color(), 2.0);
            }
        }
        self.overlay
            .draw_frame(&mut pixmap, &self.static_layer, frame);
        pixmap
    }
}
