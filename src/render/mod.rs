//! The renderer: one frame's state in, one pixmap out.
//!
//! Rendering reads simulation state and never changes it. Everything that does not
//! move (the background, and later axes and fields) is drawn once per render into a
//! static layer that each frame starts from; everything that moves (bodies, arrows) is
//! drawn over it, and trails over a worker's copy of it that gains each frame's new
//! segments ([`trails`]). Geometry is f64 in the world and f32 in pixels.
//!
//! Drawing skips what a frame does not show: bodies outside the image are not drawn,
//! bodies that look alike share one prepared look wherever they stand in the file
//! ([`looks`]), small geometries that many bodies share are stamped from pre-rendered
//! sprites ([`sprite`], and [`turning`] at angle bins) instead of being rasterised
//! body by body, and arrows and other turning outlines are filled by a scan converter
//! without tiny-skia's set-up per path ([`raster`]).

pub mod arrows;
pub mod bodies;
pub mod camera;
pub mod clip;
pub mod compare;
pub mod damage;
pub mod encode;
pub mod fastpng;
pub mod layers;
pub mod looks;
mod moving;
pub mod picture;
pub mod plot;
pub mod points;
pub mod raster;
pub mod springs;
pub mod sprite;
pub mod text;
pub mod ticks;
pub mod trails;
pub mod turning;

use glam::DVec2;
use tiny_skia::{Color, Pixmap};

pub use camera::Camera;
pub use damage::{Damage, PixelRect};
pub use encode::{encode_png, encode_png_into, Compression, Provenance};

use crate::history::PointHistory;
use crate::scene::Scene;
pub use arrows::ArrowScales;
use clip::ClipRect;
use damage::{copy_rect, copy_tiles, copy_tiles_outside, Marking};
use looks::Look;
use moving::ArrowMarks;
use trails::{SharedTrails, TrailFrame, TrailLayer, TrailStyle};

/// The state of one frame, as the renderer sees it.
#[derive(Clone, Copy, Debug)]
pub struct FrameView<'a> {
    /// The frame number k.
    pub index: u64,
    /// The simulated time of the frame.
    pub t: f64,
    /// Centre-of-mass positions.
    pub pos: &'a [DVec2],
    /// Centre-of-mass velocities; may be empty when no body shows its velocity
    /// ([`Renderer::needs_velocities`]).
    pub vel: &'a [DVec2],
    /// Every body's angle θ, when some body turns ([`Renderer::needs_angles`]); a body
    /// that never turns is drawn at its constant angle whatever this holds.
    pub angle: Option<&'a [f64]>,
    /// Net forces, when some body shows its force arrow.
    pub force: Option<&'a [DVec2]>,
    /// The positions at every frame so far (0 ..= index), when trails are on: a
    /// snapshot of the history the simulation thread appends to, shared with the other
    /// frames rather than copied into each.
    pub trail: Option<&'a PointHistory>,
    /// The points of the scene's trace curves at every frame so far (0 ..= index), one
    /// per trace, when the scene has traces (see [`layers::TraceRecorder`]); shared like
    /// `trail`.
    pub traces: Option<&'a PointHistory>,
    /// The compared runs at this frame, when the scene sets `compare`.
    pub compare: Option<&'a crate::compare::CompareFrame>,
}

/// Draws frames of one scene.
pub struct Renderer {
    camera: Camera,
    width: u32,
    height: u32,
    clip: ClipRect,
    static_layer: Pixmap,
    /// The background colour while the static layer is nothing else: then a frame
    /// starts with a fill, which writes memory without reading a copy's source.
    plain: Option<Color>,
    /// The distinct looks of the scene's bodies: bodies alike (a swarm's members, say)
    /// share one, prepared once.
    looks: Vec<Look>,
    /// The look of every body, as an index into `looks`.
    look_of: Vec<u32>,
    /// The bodies that show a velocity or force arrow, in increasing order.
    arrow_bodies: Vec<u32>,
    /// For each body, whether it is static and so drawn in the static layer rather
    /// than in every frame; empty when no body is static.
    still: Vec<bool>,
    arrows: ArrowScales,
    /// The colours of the bodies' trails.
    trails: TrailStyle,
    /// Axes, fields, curves, legend and HUD.
    overlay: layers::Overlay,
    /// The springs, when the scene shows them.
    springs: Option<springs::Springs>,
    /// True when some body turns during the run.
    turning: bool,
    /// The simulated time of the last frame, for the comparison's error strip.
    duration: f64,
    /// Whether arrows and turning bodies take the fast paths (sprites, [`raster`]) or
    /// tiny-skia's paths, the reference they are tested against.
    drawing: BodyDrawing,
    /// True when turning convex outlines are drawn by the scan converter: with the fast
    /// paths, when at least [`SPRITE_MIN_BODIES`] bodies have them, so that scenes of a
    /// few bodies are drawn exactly as their paths.
    turning_fast: bool,
    /// Whether convex outlines that never turn and have no sprite go through the scan
    /// converter ([`BodyLook::draw_fast`]): when at least [`SPRITE_MIN_BODIES`] moving
    /// bodies are drawn that way.
    fixed_fast: bool,
    /// The compared runs' rings as pictures, made when a frame first needs them.
    ghost_rings: compare::GhostRings,
}

pub use looks::SPRITE_MIN_BODIES;

/// Pixels added to a body's reach for the rectangle it damages: the outline's
/// half-width and anti-aliasing take at most 3 (a sprite pads by as much), and one more
/// is spare.
pub const DAMAGE_MARGIN: f32 = 4.0;

/// How bodies and arrows are drawn: the fast ways (sprites for small looks many bodies
/// share, [`raster`] for arrows and turning boxes), or everything as tiny-skia's paths.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BodyDrawing {
    /// Stamp small geometries shared by at least [`SPRITE_MIN_BODIES`] bodies from sprites;
    /// draw the others as paths. The default.
    #[default]
    Sprites,
    /// Draw every body and arrow as tiny-skia's paths, bodies at their exact
    /// positions: the reference the fast ways are tested against.
    Paths,
}

impl Renderer {
    /// Prepares everything about a scene's frames that does not change between them.
    pub fn new(scene: &Scene, arrows: ArrowScales) -> Self {
        Self::with_drawing(scene, arrows, BodyDrawing::default())
    }

    /// Like [`Renderer::new`], choosing how bodies are drawn.
    pub fn with_drawing(scene: &Scene, arrows: ArrowScales, drawing: BodyDrawing) -> Self {
        Self::build(scene, arrows, drawing, 0)
    }

    /// Like [`Renderer::new`], making the sprites it makes before the first frame on
    /// `threads` threads (0: one per core), as a render's `--threads` asks. The
    /// frames do not depend on it.
    pub fn with_threads(scene: &Scene, arrows: ArrowScales, threads: usize) -> Self {
        Self::build(scene, arrows, BodyDrawing::default(), threads)
    }

    fn build(scene: &Scene, arrows: ArrowScales, drawing: BodyDrawing, threads: usize) -> Self {
        let r = &scene.render;
        // One transform for bodies and layers: the camera of the axes' plot area when
        // the scene has `[axes]`, else the view fitted to the whole image.
        let (overlay, camera) = layers::Overlay::new(scene);
        let mut static_layer = Pixmap::new(r.width, r.height)
            .expect("the scene validator keeps image sides between 1 and 16384");
        let background = bodies::color(r.background, 1.0);
        static_layer.fill(background);
        overlay.draw_static(&mut static_layer);
        // With `show_bodies = false` the bodies and their arrows are not drawn (trails are).
        let shown = if r.show_bodies {
            scene.bodies.as_slice()
        } else {
            &[]
        };
        // Bodies that look alike share one look, wherever they stand in the file.
        let looks::Looks { looks, look_of } =
            looks::Looks::with_threads(shown, &camera, drawing, threads);
        // Trails in each body's colour at 55% opacity, the bodies drawn or not.
        let trails = TrailStyle::new(scene.bodies.iter().map(|b| bodies::color(b.color, 0.55)));
        let turning_fast = drawing == BodyDrawing::Sprites
            && look_of
                .iter()
                .filter(|&&l| {
                    let body = &looks[l as usize].body;
                    body.turns_fast() || body.turns_general() || body.rolls_fast()
                })
                .count()
                >= SPRITE_MIN_BODIES;
        // So do convex outlines that never turn and are not stamped (boxes of many
        // sizes, or each at an angle of its own), when many bodies are.
        let fixed_fast = drawing == BodyDrawing::Sprites
            && look_of
                .iter()
                .zip(shown)
                .filter(|(&l, b)| {
                    let look = &looks[l as usize];
                    !b.is_static
                        && look.sprite.is_none()
                        && look.turning.is_none()
                        && look.body.draws_fast()
                })
                .count()
                >= SPRITE_MIN_BODIES;
        // Static bodies never move: they are drawn once, into the static layer, over its
        // fields and curves as every body is, and wiped from the margins of a plot with
        // axes as every body is at each frame. Frames then skip them.
        let still: Vec<bool> = shown.iter().map(|b| b.is_static).collect();
        if still.iter().any(|s| *s) {
            let before = overlay.body_area().map(|area| (area, static_layer.clone()));
            for (i, b) in shown.iter().enumerate().filter(|(_, b)| b.is_static) {
                let look = &looks[look_of[i] as usize].body;
                let (x, y) = camera.to_pixel(b.position);
                if !look.is_outside(x, y, r.width, r.height) {
                    look.draw(&mut static_layer, x, y);
                }
            }
            if let Some((area, before)) = before {
                layers::restore_outside(&mut static_layer, &before, area);
            }
        }
        let still = if still.iter().any(|s| *s) {
            still
        } else {
            Vec::new()
        };
        // A frame may start with a plain fill only while the static layer is nothing
        // but the background (static bodies drawn in it included).
        let first = static_layer.pixels()[0];
        let plain = static_layer
            .pixels()
            .iter()
            .all(|p| *p == first)
            .then_some(background);
        let arrow_bodies = shown
            .iter()
            .enumerate()
            .filter(|(_, b)| b.show_velocity || b.show_force)
            .map(|(i, _)| i as u32)
            .collect();
        Renderer {
            camera,
            width: r.width,
            height: r.height,
            clip: ClipRect::guard(r.width, r.height),
            static_layer,
            plain,
            looks,
            look_of,
            arrow_bodies,
            still,
            arrows,
            trails,
            overlay,
            springs: springs::Springs::new(scene),
            turning: scene.bodies.iter().any(|b| b.turns),
            duration: scene.frame_time(r.frame_count - 1).max(f64::MIN_POSITIVE),
            drawing,
            turning_fast,
            fixed_fast,
            ghost_rings: compare::GhostRings::default(),
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

    /// Returns the guard band that geometry is clipped to before it is drawn.
    pub fn clip(&self) -> &ClipRect {
        &self.clip
    }

    /// Returns the static layer that every frame starts from.
    pub fn static_layer(&self) -> &Pixmap {
        &self.static_layer
    }

    /// Returns the static layer, to draw on it what does not move (axes, fields,
    /// labels) before the first frame. It is drawn once per render; every frame starts
    /// from a copy of it.
    pub fn static_layer_mut(&mut self) -> &mut Pixmap {
        self.plain = None;
        &mut self.static_layer
    }

    /// Returns true when every pixel of the static layer is opaque. Drawing over an
    /// opaque pixel with source-over leaves it opaque, so then every frame is opaque
    /// and the encoder need not check.
    pub fn frames_are_opaque(&self) -> bool {
        self.static_layer.pixels().iter().all(|p| p.alpha() == 255)
    }

    /// Returns true when some body shows its velocity, so frames need velocities;
    /// otherwise [`FrameView::vel`] may be empty.
    pub fn needs_velocities(&self) -> bool {
        self.looks.iter().any(|l| l.body.show_velocity)
    }

    /// Returns true when some body turns during the run, so frames need every body's
    /// angle ([`FrameView::angle`]) to draw it or a spring's end on it.
    pub fn needs_angles(&self) -> bool {
        self.turning
    }

    /// Returns true when some body shows its net force, so frames need forces.
    pub fn needs_forces(&self) -> bool {
        self.looks.iter().any(|l| l.body.show_force)
    }

    /// Returns a new pixmap the size of a frame, ready for [`Renderer::draw_into`].
    pub fn new_frame(&self) -> Pixmap {
        self.static_layer.clone()
    }

    /// Draws one frame into a new pixmap.
    pub fn draw(&self, frame: &FrameView<'_>) -> Pixmap {
        let mut pixmap = self.static_layer.clone();
        self.draw_into(frame, &mut pixmap);
        pixmap
    }

    /// Draws one frame into a new pixmap by the plainest path: the static layer (with
    /// the trails so far, drawn afresh), then every pass over all of it, as for a frame
    /// that draws more than the damage can hold. The reference the faster paths
    /// ([`Renderer::draw_damaged`], [`Renderer::draw_trail_frame`]) are tested
    /// against: their pixels must be these.
    pub fn draw_every_pass(&self, frame: &FrameView<'_>) -> Pixmap {
        let mut pixmap = self.static_layer.clone();
        if frame.trail.is_some() {
            // A whole frame with trails takes that path already, with a fresh layer.
            self.draw_with_trails(frame, &mut pixmap, &mut Damage::whole(), &mut None);
        } else {
            self.draw_moving(frame, &mut pixmap);
        }
        pixmap
    }

    /// Rasterises, into `shared`, the trail segments of the frames of `history` that it
    /// has not rasterised yet, so that the workers drawing those frames find them done
    /// ([`TrailFrame::sharing`]).
    pub fn rasterise_trails(&self, shared: &SharedTrails, history: &crate::history::PointHistory) {
        shared.advance(
            history,
            (&self.trails, &self.camera, &self.clip, &self.static_layer),
        );
    }

    /// Returns a new layer for the trails, when frames show trails: a worker keeps one
    /// and hands it to [`Renderer::draw_with_trails`] with each frame it draws.
    pub fn new_trail_layer(&self) -> TrailLayer {
        TrailLayer::new(&self.static_layer)
    }

    /// Draws one frame into `pixmap`, which must have the frame's size (as from
    /// [`Renderer::new_frame`]): a worker reuses one pixmap for all its frames, so no
    /// frame allocates.
    pub fn draw_into(&self, frame: &FrameView<'_>, pixmap: &mut Pixmap) {
        self.draw_damaged(frame, pixmap, &mut Damage::whole());
    }

    /// Draws one frame into `pixmap`, which holds the last frame drawn into it, with
    /// `damage` saying where that frame differs from the static layer (a pixmap from
    /// [`Renderer::new_frame`] has no damage). Only the damage is restored from the
    /// static layer before drawing; afterwards `damage` says where the new frame
    /// differs from the static layer: the rectangle of every body when only bodies
    /// are drawn (over a static layer that may hold axes and fields), the whole frame
    /// otherwise. The pixels are those of [`Renderer::draw_into`], whatever the damage.
    pub fn draw_damaged(&self, frame: &FrameView<'_>, pixmap: &mut Pixmap, damage: &mut Damage) {
        self.draw_with_trails(frame, pixmap, damage, &mut None);
    }

    /// Draws one frame like [`Renderer::draw_damaged`], bringing the worker's trail
    /// layer `trails` (made when first needed) up to the frame when it shows trails, so
    /// that only the segments since the worker's last frame are drawn. The pixels do
    /// not depend on the layer's past: a fresh layer gives the same frame.
    pub fn draw_with_trails(
        &self,
        frame: &FrameView<'_>,
        pixmap: &mut Pixmap,
        damage: &mut Damage,
        trails: &mut Option<TrailLayer>,
    ) {
        assert_eq!(
            (pixmap.width(), pixmap.height()),
            (self.width, self.height),
            "draw_into needs a pixmap the size of the frame"
        );
        if let Some(history) = frame.trail {
            // The frame starts from the static layer with the trails so far over it.
            let layer = trails.get_or_insert_with(|| self.new_trail_layer());
            layer.advance(
                &self.trails,
                &self.camera,
                &self.clip,
                &self.static_layer,
                history,
            );
            pixmap.data_mut().copy_from_slice(layer.base().data());
            damage.set_whole();
            self.draw_moving(frame, pixmap);
            return;
        }
        self.restore(pixmap, damage);
        if self.damage_holds_all(frame) {
            damage.clear();
            // Springs' coils under the bodies, each in the box around its ends grown by
            // its reach.
            self.draw_springs(frame, pixmap);
            if let Some(springs) = &self.springs {
                let (size, at) = ((self.width, self.height), (frame.pos, frame.angle));
                springs.add_boxes(size, &self.camera, at, damage);
            }
            self.draw_bodies(frame, pixmap, Some(damage), None);
            // With axes, bodies are wiped from the margins again, which returns those
            // pixels to the static layer: only where the bodies drew, after which the
            // damage keeps to the plot; or, when the damage is whole, every margin.
            if let (Some(area), Some(inside)) = (self.overlay.body_area(), self.body_rect()) {
                if damage.is_whole() {
                    layers::restore_outside(pixmap, &self.static_layer, area);
                } else {
                    damage.keep_inside(inside, |r| copy_rect(pixmap, &self.static_layer, r));
                }
            }
            // The legend and the HUD over everything, in boxes the damage holds.
            let (width, height) = (self.width, self.height);
            self.draw_boxes(frame, pixmap, |r| damage.add_rect(r, width, height));
        } else {
            damage.set_whole();
            self.draw_moving(frame, pixmap);
        }
    }

    /// Draws one frame with trails for a worker that encodes each frame against the
    /// last one it drew ([`fastpng::FrameCoder`]): `pixmap` holds the last frame drawn
    /// with `state` (or anything, before the first), and afterwards holds this frame,
    /// the pixels of [`Renderer::draw_into`], while `state.changed()` marks the tiles
    /// where it may differ from the last frame.
    ///
    /// The worker's trail layer gains the segments since its last frame and marks the
    /// tiles they changed; the pixmap is brought to the layer by copying those tiles and
    /// the last frame's bodies' rectangles from it, and the bodies are drawn over it,
    /// their rectangles kept for the next frame, and so is the HUD's box. Arrows mark
    /// the tiles of the pixels they may change, row by row ([`arrows::mark_arrow`]),
    /// unless the marks cover more than a third of the frame, and so do springs' coils
    /// ([`springs::Springs::mark`]). With axes, the marked tiles outside the plot go
    /// back to the static layer. A frame that draws more over the trails (a legend,
    /// layers that change in time, compared runs) marks every tile.
    pub fn draw_trail_frame(
        &self,
        frame: &FrameView<'_>,
        pixmap: &mut Pixmap,
        state: &mut TrailFrame,
    ) {
        assert_eq!(
            (pixmap.width(), pixmap.height()),
            (self.width, self.height),
            "draw_trail_frame needs a pixmap the size of the frame"
        );
        let Some(history) = frame.trail else {
            self.draw_into(frame, pixmap);
            state.bodies.set_whole();
            state.changed.set_whole();
            return;
        };
        let shared = &state.shared;
        let layer = state.layer.get_or_insert_with(|| {
            let mut layer = self.new_trail_layer();
            if let Some((shared, worker)) = shared {
                layer.share(std::sync::Arc::clone(shared), *worker);
            }
            layer
        });
        layer.advance(
            &self.trails,
            &self.camera,
            &self.clip,
            &self.static_layer,
            history,
        );
        // Where the pixmap differs from the layer now: where the layer changed, and
        // under the last frame's bodies.
        state.changed.clear();
        layer.take_changed(&mut state.changed);
        state.changed.add_damage(&state.bodies);
        state.changed.add_mask(&state.body_tiles);
        if state.changed.is_whole() {
            pixmap.data_mut().copy_from_slice(layer.base().data());
        } else {
            copy_tiles(pixmap, layer.base(), &state.changed);
        }
        if self.marks_its_tiles(frame) {
            state.bodies.clear();
            state.body_tiles.clear();
            self.draw_springs(frame, pixmap);
            self.draw_bodies(
                frame,
                pixmap,
                Some(&mut state.bodies),
                Some(&mut state.body_tiles),
            );
            // The springs' coils, drawn under the bodies, are marked after them: with
            // the bodies' marks counted, springs that would take the mask past a third
            // of the frame's tiles (to be compressed whole) leave it whole unmarked, as
            // do springs that would mark more than an eighth of them on their own: the
            // coils' tiles are coded afresh every frame, and past that their marks cost
            // more than the tiles left alone save. (Pairs of discs joined by springs,
            // with trails, 1280×720, their coils about 4, 9 and 17% of the tiles: a
            // render's CPU time 33% and 10% less marked, 12% more; `builds-pairs`.)
            let limit = state.changed.tiles() / 3;
            if let Some(springs) = &self.springs {
                let mut marks = Marking::new(&mut state.body_tiles, limit);
                let (size, budget) = ((self.width, self.height), state.changed.tiles() / 8);
                let at = (frame.pos, frame.angle);
                springs.mark(size, &self.camera, at, (&mut marks, budget));
            }
            state.changed.add_damage(&state.bodies);
            state.changed.add_mask(&state.body_tiles);
            // Arrows over the trails mark their tiles row by row, as stamps do, until
            // the frame is to be compressed whole.
            let marks = ArrowMarks {
                frame: &mut state.changed,
                next: &mut state.body_tiles,
                limit,
            };
            self.draw_arrows(frame, pixmap, Some(marks));
            // With axes, the margins around the plot go back to the static layer where
            // anything drew over them (the trails, too, which the layer keeps there):
            // where the marks say, or everywhere once the frame is whole.
            if let (Some(area), Some(inside)) = (self.overlay.body_area(), self.body_rect()) {
                if state.changed.is_whole() {
                    layers::restore_outside(pixmap, &self.static_layer, area);
                } else {
                    copy_tiles_outside(pixmap, &self.static_layer, &state.changed, inside);
                }
            }
            let (width, height) = (self.width, self.height);
            let bodies = &mut state.bodies;
            self.draw_boxes(frame, pixmap, |r| bodies.add_rect(r, width, height));
            state.changed.add_damage(&state.bodies);
            // Long arrows on many bodies, or many large bodies, mark much of the
            // frame; past a third of its tiles, compressing every row whole costs less
            // than the tiles' bookkeeping (docs/performance-log.md, arrows over trails;
            // 500 turning dumbbells marked 41 to 46%: 1.96 ms by tiles, 1.69 whole,
            // `trail_probe`).
            let marked = state.changed.count();
            if 3 * marked > state.changed.tiles() {
                state.changed.set_whole();
            }
        } else {
            self.draw_moving(frame, pixmap);
            state.bodies.set_whole();
            state.changed.set_whole();
        }
    }

    /// The pixels that bodies may show, when the margins around them are wiped after
    /// the bodies are drawn (a frame with axes), inside the frame.
    fn body_rect(&self) -> Option<PixelRect> {
        let area = self.overlay.body_area()?;
        let clamp = |v: i32, max: u32| v.clamp(0, max as i32) as u32;
        Some(PixelRect {
            x0: clamp(area.left(), self.width),
            y0: clamp(area.top(), self.height),
            x1: clamp(area.right(), self.width),
            y1: clamp(area.bottom(), self.height),
        })
    }

    /// Draws the legend and the HUD, those the scene shows, over everything, and gives
    /// `add` the pixels each may have touched (x0, y0, x1, y1), for the damage.
    fn draw_boxes(
        &self,
        frame: &FrameView<'_>,
        pixmap: &mut Pixmap,
        mut add: impl FnMut((i64, i64, i64, i64)),
    ) {
        if let Some(r) = self.overlay.draw_legend(pixmap) {
            add(r);
        }
        if let Some(r) = self.overlay.draw_hud(pixmap, frame) {
            add(r);
        }
    }

    /// Returns true when a frame draws nothing over the static layer but springs,
    /// bodies and, perhaps, the legend and the HUD, whose extents the damage holds: no
    /// arrows, comparison runs or layer that changes in time.
    fn damage_holds_all(&self, frame: &FrameView<'_>) -> bool {
        self.arrow_bodies.is_empty() && self.marks_its_tiles(frame)
    }

    /// Returns true when a frame draws nothing over the static layer and the trails
    /// but springs, bodies, their arrows and, perhaps, the legend and the HUD: what a
    /// trail frame can mark tile by tile.
    fn marks_its_tiles(&self, frame: &FrameView<'_>) -> bool {
        frame.compare.is_none()
            && (!self.overlay.draws_over_frames() || self.overlay.draws_only_boxes())
    }

    /// Makes `pixmap` a copy of the static layer again, rewriting only its damage. A
    /// plain background is filled whole once the damage passes a fifth of the frame:
    /// filling writes and reads nothing, where copying rectangles reads the layer too.
    /// (`sizes-1000`, its rectangles 24% of the frame: a render's CPU time 1.15 s by
    /// rectangles, 0.86 filled; `sh benches/builds-pairs.sh`, 8 pairs.)
    fn restore(&self, pixmap: &mut Pixmap, damage: &Damage) {
        let frame = u64::from(self.width) * u64::from(self.height);
        if damage.is_whole() || (self.plain.is_some() && 5 * damage.area() > frame) {
            match self.plain {
                Some(background) => pixmap.fill(background),
                None => pixmap.data_mut().copy_from_slice(self.static_layer.data()),
            }
            return;
        }
        for r in damage.rects() {
            copy_rect(pixmap, &self.static_layer, *r);
        }
    }

    /// Draws the springs' coils, when the scene shows them.
    fn draw_springs(&self, frame: &FrameView<'_>, pixmap: &mut Pixmap) {
        if let Some(springs) = &self.springs {
            let fast =
                self.drawing == BodyDrawing::Sprites && springs.len() >= springs::FAST_MIN_SPRINGS;
            springs.draw(
                pixmap,
                (&self.camera, &self.clip),
                (frame.pos, frame.angle),
                fast,
            );
        }
    }

    /// Draws everything that moves over a copy of the static layer (with the trails
    /// over it, when frames show trails): springs, then bodies in index order, then
    /// arrows.
    fn draw_moving(&self, frame: &FrameView<'_>, pixmap: &mut Pixmap) {
        self.draw_springs(frame, pixmap);
        self.draw_bodies(frame, pixmap, None, None);
        self.draw_arrows(frame, pixmap, None);
        self.overlay.draw_frame(pixmap, &self.static_layer, frame);
        if let Some(compare) = frame.compare {
            let rings = (self.drawing == BodyDrawing::Sprites).then_some(&self.ghost_rings);
            compare::draw(pixmap, &self.camera, compare, self.duration, rings);
        }
    }
}
