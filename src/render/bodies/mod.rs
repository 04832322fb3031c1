//! The moving layers: how each body looks and is drawn. Its velocity and force arrows
//! are drawn by [`super::arrows`].

use glam::DVec2;
use tiny_skia::{
    Color, FillRule, LineJoin, Paint, Path, PathBuilder, PathSegment, Pixmap, Stroke, Transform,
};

mod orientation;

pub use super::arrows::{draw_arrow, draw_arrow_path, mark_arrow};
use super::camera::Camera;
use super::raster;
use super::sprite::{Ink, MAX_SPRITE_REACH};
use crate::scene::{Body, Rgba, Shape};
use crate::sim::rigid::rotate;

/// How a body is drawn, prepared once per render in pixel units.
///
/// A body that never turns is prepared at its (constant) angle, and drawn like any
/// other. A body that turns is prepared at angle 0 and drawn turned by its angle at
/// each frame ([`BodyLook::draw_turned`]); a turning circle, which looks the same at
/// every angle, shows its angle with a radius line from its centre to its rim.
#[derive(Clone, Debug)]
pub struct BodyLook {
    /// The outline around the centre of mass, in pixels (y down).
    outline: Option<Path>,
    /// True when the body turns during the run, so that each frame gives its angle.
    turns: bool,
    /// For a circle that turns, the length of its orientation line in pixels.
    marker: Option<f32>,
    /// The point masses' discs and the bars joining them to the centre, for bodies of
    /// point masses.
    points: Option<(Path, Path)>,
    /// For bodies of point masses, each mass's offset in pixels and its disc's radius.
    masses: Option<Vec<((f32, f32), f32)>>,
    fill: Color,
    edge: Color,
    /// A radius in pixels that encloses everything drawn for the body.
    reach: f32,
    /// For a circle, its radius in pixels.
    circle: Option<f32>,
    /// For a body whose outline is convex (a box, a convex polygon), the outline and
    /// its stroke prepared for the scan converter: at angle 0 when the body turns, at
    /// its fixed angle when it does not.
    turned: Option<TurnedOutline>,
    /// For a body whose outline is a polygon that is not convex, the polygon and its
    /// stroke (the capsules of its edges) for the general scan, prepared as `turned`.
    general: Option<GeneralOutline>,
    /// For a circle too large to stamp, its polygon and ring for the scan converter,
    /// turning or not: the ring's sides are its curve moved a stroke's half-width out
    /// and in, so that in opaque colours the outer side filled in the edge's colour and
    /// the inner side over it in the fill's give the look ([`raster::fill_layers`]).
    disc: Option<TurnedOutline>,
    pub show_velocity: bool,
    pub show_force: bool,
}

/// A turning convex outline as [`raster`] draws it: the outline's points at angle 0 as
/// tiny-skia's path holds them, and the ring its stroke covers, turned and placed at
/// each frame by the transform tiny-skia would apply to the paths.
#[derive(Clone, Debug)]
struct TurnedOutline {
    fill: Vec<raster::Point>,
    ring: raster::Ring,
}

/// A polygon outline that is not convex as [`raster::fill_outline`] draws it: its
/// points and its stroke's polygons, the capsules of its edges.
#[derive(Clone, Debug)]
struct GeneralOutline {
    fill: Vec<raster::Point>,
    stroke: Vec<Vec<raster::Point>>,
}

/// The largest reach, in pixels, of an outline drawn by the general scan: farther
/// points could leave the band where its fixed-point arithmetic is tiny-skia's.
const MAX_GENERAL_REACH: f32 = 2048.0;

/// Half the width of every outline's stroke, in pixels.
const OUTLINE_HALF_WIDTH: f64 = 0.75;

/// Returns a colour from straight RGBA bytes, with alpha scaled by `alpha`.
pub fn color(c: Rgba, alpha: f32) -> Color {
    let [r, g, b, a] = c.0;
    Color::from_rgba8(r, g, b, (f32::from(a) * alpha).round() as u8)
}

/// Returns a darker shade of a colour, for outlines.
fn darker(c: Rgba) -> Rgba {
    let [r, g, b, a] = c.0;
    let d = |v: u8| (f32::from(v) * 0.6).round() as u8;
    Rgba([d(r), d(g), d(b), a])
}

impl BodyLook {
    /// Prepares the look of a body for a camera: turned by its constant angle when it
    /// never turns, at angle 0 when it does.
    pub fn new(body: &Body, camera: &Camera) -> Self {
        let s = camera.scale() as f32;
        // A body that never turns is drawn at its initial angle: its points are turned
        // once, here, in the world (R(θ)·p, counter-clockwise), then taken to pixels.
        let turn = (!body.turns && body.angle != 0.0).then(|| body.angle.sin_cos());
        let px = |p: DVec2| {
            let p = turn.map_or(p, |sc| rotate(sc, p));
            let (x, y) = camera.to_pixel_vector(p);
            (x, y)
        };
        let mut reach = 0.0f32;
        let mut outline = None;
        let mut points = None;
        let mut point_masses = None;
        let mut marker = None;
        let mut circle = None;
        match &body.shape {
            Shape::Circle { radius } => {
                let r = (*radius as f32 * s).max(0.5);
                reach = r;
                circle = Some(r);
                outline = PathBuilder::from_circle(0.0, 0.0, r);
                marker = body.turns.then_some(r);
            }
            Shape::Box { width, height } if turn.is_some() => {
                // A box turned once for good is the polygon of its corners.
                let (w, h) = (0.5 * width, 0.5 * height);
                let corners =
                    [(-w, -h), (w, -h), (w, h), (-w, h)].map(|(x, y)| px(DVec2::new(x, y)));
                reach = 0.5 * ((*width * *width + *height * *height).sqrt() as f32 * s).max(1.0);
                let mut pb = PathBuilder::new();
                pb.move_to(corners[0].0, corners[0].1);
                for (x, y) in &corners[1..] {
                    pb.line_to(*x, *y);
                }
                pb.close();
                outline = pb.finish();
            }
            Shape::Box { width, height } => {
                let (w, h) = ((*width as f32 * s).max(1.0), (*height as f32 * s).max(1.0));
                reach = 0.5 * (w * w + h * h).sqrt();
                outline = tiny_skia::Rect::from_xywh(-0.5 * w, -0.5 * h, w, h)
                    .map(PathBuilder::from_rect);
            }
            Shape::Polygon { points } => {
                let mut pb = PathBuilder::new();
                for (i, p) in points.iter().enumerate() {
                    let (x, y) = px(*p);
                    reach = reach.max((x * x + y * y).sqrt());
                    if i == 0 {
                        pb.move_to(x, y);
                    } else {
                        pb.line_to(x, y);
                    }
                }
                pb.close();
                outline = pb.finish();
            }
            Shape::Points { points: masses } => {
                // Each point mass is a disc whose area grows with its mass, from 3 to 9
                // pixels of radius; thin bars join them to the centre of mass.
                let heaviest = masses.iter().map(|p| p.mass).fold(0.0, f64::max);
                let mut discs = PathBuilder::new();
                let mut bars = PathBuilder::new();
                let mut kept = Vec::with_capacity(masses.len());
                for p in masses {
                    let (x, y) = px(p.offset);
                    let r = 3.0 + 6.0 * (p.mass / heaviest).sqrt() as f32;
                    kept.push(((x, y), r));
                    discs.push_circle(x, y, r);
                    bars.move_to(0.0, 0.0);
                    bars.line_to(x, y);
                    reach = reach.max((x * x + y * y).sqrt() + r);
                }
                if let (Some(d), Some(b)) = (discs.finish(), bars.finish()) {
                    points = Some((d, b));
                    point_masses = Some(kept);
                }
                reach = reach.max(6.0);
            }
        }
        // A disc too large to stamp may be drawn by the scan converter, turning or not,
        // as a polygon on its circle's curve; its stroke is the ring between the curves
        // a half-width w outside and inside it, the inner side wound against the outer.
        // Larger ones (past the general scan's reach, whose points would also grow
        // without bound) stay paths.
        let disc = circle
            .filter(|&r| r > MAX_SPRITE_REACH && r <= MAX_GENERAL_REACH)
            .and_then(|r| raster::disc(r, OUTLINE_HALF_WIDTH as f32))
            .map(|[fill, outer, mut inner]| {
                inner.reverse();
                TurnedOutline {
                    fill,
                    ring: raster::Ring {
                        outer,
                        inner: Some(inner),
                    },
                }
            });
        // An outline that is convex may be drawn by the scan converter.
        let turned = outline
            .as_ref()
            .filter(|_| points.is_none())
            .and_then(|path| {
                let fill: Vec<raster::Point> = path.points().iter().map(|p| (p.x, p.y)).collect();
                let is_polygon = path.segments().all(|s| {
                    matches!(
                        s,
                        PathSegment::MoveTo(_) | PathSegment::LineTo(_) | PathSegment::Close
                    )
                });
                let ring = raster::Ring::of_convex(&fill, OUTLINE_HALF_WIDTH)?;
                is_polygon.then_some(TurnedOutline { fill, ring })
            });
        // An outline of straight edges that is not convex goes through the general
        // scan: the polygon, and its stroke as the union of its edges' capsules.
        let general = outline
            .as_ref()
            .filter(|_| turned.is_none() && points.is_none() && reach <= MAX_GENERAL_REACH)
            .filter(|path| {
                path.segments().all(|s| {
                    matches!(
                        s,
                        PathSegment::MoveTo(_) | PathSegment::LineTo(_) | PathSegment::Close
                    )
                })
            })
            .map(|path| {
                let fill: Vec<raster::Point> = path.points().iter().map(|p| (p.x, p.y)).collect();
                let mut stroke = Vec::with_capacity(fill.len());
                for (k, &a) in fill.iter().enumerate() {
                    let b = fill[(k + 1) % fill.len()];
                    if a == b {
                        continue;
                    }
                    let mut capsule = Vec::new();
                    raster::capsule(
                        (f64::from(a.0), f64::from(a.1)),
                        (f64::from(b.0), f64::from(b.1)),
                        OUTLINE_HALF_WIDTH,
                        &mut capsule,
                    );
                    stroke.push(capsule);
                }
                GeneralOutline { fill, stroke }
            });
        BodyLook {
            outline,
            turns: body.turns,
            turned,
            general,
            disc,
            marker,
            points,
            masses: point_masses,
            fill: color(body.color, 1.0),
            edge: color(darker(body.color), 1.0),
            reach,
            circle,
            show_velocity: body.show_velocity,
            show_force: body.show_force,
        }
    }

    /// For a body of point masses, each mass's offset from the centre of mass in
    /// pixels (at angle 0 if the body turns) and its disc's radius in pixels.
    pub fn point_masses(&self) -> Option<Vec<((f32, f32), f32)>> {
        self.masses.clone()
    }

    /// Returns a radius in pixels, around the centre of mass, that encloses the shape.
    pub fn reach(&self) -> f32 {
        self.reach
    }

    /// Returns true when the body turns during the run, so that it is drawn with
    /// [`BodyLook::draw_turned`] at each frame's angle.
    pub fn turns(&self) -> bool {
        self.turns
    }

    /// Returns true when the look, turned, is the look itself plus its orientation
    /// line: a circle. Such a look may still be stamped from a sprite, and then needs
    /// only [`BodyLook::draw_orientation`] over it.
    pub fn turns_by_marker(&self) -> bool {
        self.marker.is_some()
    }

    /// Returns true for a body of point masses.
    pub fn has_points(&self) -> bool {
        self.points.is_some()
    }

    /// Returns a circle's radius in pixels; `None` for other shapes.
    pub fn circle_radius(&self) -> Option<f32> {
        self.circle
    }

    /// Returns a circle's look with its radius, in pixels, changed to `radius`, for the
    /// sprite of a snapped radius ([`super::looks`]); `None` for other shapes.
    pub fn with_radius(&self, radius: f32) -> Option<BodyLook> {
        self.circle?;
        Some(BodyLook {
            outline: PathBuilder::from_circle(0.0, 0.0, radius),
            reach: radius,
            circle: Some(radius),
            ..self.clone()
        })
    }

    /// Returns true when the look is an outline alone (a circle, box or polygon),
    /// which can be pre-rendered as a sprite; bodies of point masses also draw the
    /// centre-of-mass marker and are drawn as paths.
    pub fn is_outline(&self) -> bool {
        self.outline.is_some() && self.points.is_none()
    }

    /// Returns the look with its outline's points rounded to multiples of `step`
    /// pixels (a power of two). Translating such points by a multiple of `step` is
    /// exact in f32 anywhere in an image of up to 2^15 pixels when `step` ≥ 2^-8, so the
    /// look rasterises the same, sample for sample, at every whole pixel: what sprites
    /// need. Rounding by at most step/2 is far below what anti-aliasing resolves.
    pub fn on_grid(&self, step: f32) -> BodyLook {
        let snap = |v: f32| (v / step).round() * step;
        let outline = self.outline.as_ref().and_then(|path| {
            let mut pb = PathBuilder::new();
            for segment in path.segments() {
                match segment {
                    PathSegment::MoveTo(p) => pb.move_to(snap(p.x), snap(p.y)),
                    PathSegment::LineTo(p) => pb.line_to(snap(p.x), snap(p.y)),
                    PathSegment::QuadTo(p, q) => {
                        pb.quad_to(snap(p.x), snap(p.y), snap(q.x), snap(q.y))
                    }
                    PathSegment::CubicTo(p, q, r) => pb.cubic_to(
                        snap(p.x),
                        snap(p.y),
                        snap(q.x),
                        snap(q.y),
                        snap(r.x),
                        snap(r.y),
                    ),
                    PathSegment::Close => pb.close(),
                }
            }
            pb.finish()
        });
        BodyLook {
            outline,
            ..self.clone()
        }
    }

    /// Returns true when nothing drawn for a body at pixel (x, y) can touch the image.
    pub fn is_outside(&self, x: f32, y: f32, width: u32, height: u32) -> bool {
        let r = self.reach + 2.0;
        // Written so that a position that is not a number counts as outside.
        !(x + r >= 0.0 && y + r >= 0.0 && x - r <= width as f32 && y - r <= height as f32)
    }

    /// Returns the colours of an outline body: its fill, then its edge.
    pub fn colors(&self) -> (Color, Color) {
        (self.fill, self.edge)
    }

    /// Draws the body with its centre of mass at pixel (x, y).
    pub fn draw(&self, pixmap: &mut Pixmap, x: f32, y: f32) {
        if self.outline.is_some() {
            self.draw_outline(pixmap, x, y, Some(self.fill), Some(self.edge));
        }
        self.draw_points(pixmap, x, y, Transform::from_translate(x, y));
    }

    /// Draws a body that turns, with its centre of mass at pixel (x, y) and turned by
    /// `theta` radians counter-clockwise in the world.
    ///
    /// The world's y axis points up and the image's down, so a world rotation R(θ)
    /// is, on pixel offsets (X, Y) from the centre, X' = cos θ·X + sin θ·Y and
    /// Y' = -sin θ·X + cos θ·Y.
    pub fn draw_turned(&self, pixmap: &mut Pixmap, x: f32, y: f32, theta: f64) {
        self.draw_turned_with(pixmap, x, y, theta, false);
    }

    /// Draws a body that turns like [`BodyLook::draw_turned`], a convex outline (a box
    /// or a convex polygon) through the scan converter: its fill has the bytes of
    /// tiny-skia's path, and its stroke differs only by how the rounded corners are cut
    /// into chords (`tests/integration/every_scene.rs` bounds the difference). Other
    /// looks are drawn as paths.
    pub fn draw_turned_fast(&self, pixmap: &mut Pixmap, x: f32, y: f32, theta: f64) {
        self.draw_turned_with(pixmap, x, y, theta, true);
    }

    /// Returns the half-width and half-height, in pixels, of the box around everything
    /// [`BodyLook::draw_turned_fast`] draws for a turning convex outline at `theta`:
    /// the outline's points turned, grown by the stroke's half-width and a pixel of
    /// anti-aliasing. `None` for other looks.
    pub fn turned_extent(&self, theta: f64) -> Option<(f32, f32)> {
        let turned = self.turned.as_ref()?;
        let (s, c) = theta.sin_cos();
        let (s, c) = (s as f32, c as f32);
        let (mut ex, mut ey) = (0.0f32, 0.0f32);
        for &(x, y) in &turned.fill {
            // The turn of draw_turned: X' = c·X + s·Y, Y' = -s·X + c·Y.
            ex = ex.max((c * x + s * y).abs());
            ey = ey.max((c * y - s * x).abs());
        }
        let grow = OUTLINE_HALF_WIDTH as f32 + 1.0;
        Some((ex + grow, ey + grow))
    }

    /// Returns the box, as offsets in pixels from the centre of mass (left, top,
    /// right, bottom), around everything drawn for a look that never turns and is an
    /// outline alone: the outline's bounds grown by the stroke's half-width (its joins
    /// are round, so the stroke lies within that of the outline) and a pixel to spare
    /// for anti-aliasing's rounding. Tighter than the square of the look's reach,
    /// which holds the look at every angle: for a box twice as wide as high, about
    /// half its tiles. `None` for other looks.
    pub fn fixed_box(&self) -> Option<[f32; 4]> {
        if self.turns || self.points.is_some() {
            return None;
        }
        let b = self.outline.as_ref()?.bounds();
        let grow = OUTLINE_HALF_WIDTH as f32 + 1.0;
        Some([
            b.left() - grow,
            b.top() - grow,
            b.right() + grow,
            b.bottom() + grow,
        ])
    }

    /// Returns the box, as offsets in pixels from the centre of mass (left, top,
    /// right, bottom), around everything drawn for a body of point masses turned by
    /// `theta` (`None`: at its fixed angle): each mass's disc with its 1-pixel outline,
    /// and the centre-of-mass marker, grown by a pixel to spare. The bars from the
    /// centre to the masses lie inside: each is 1.5 pixels wide, ends in a disc of
    /// at least 3 pixels' radius and starts inside the marker. For a dumbbell about
    /// half the square of its reach. `None` for other looks.
    pub fn points_box(&self, theta: Option<f64>) -> Option<[f32; 4]> {
        let masses = self.masses.as_ref()?;
        let (s, c) = theta
            .filter(|_| self.turns)
            .map_or((0.0, 1.0), f64::sin_cos);
        let (s, c) = (s as f32, c as f32);
        let m = MARKER_REACH + 1.0;
        let mut b = [-m, -m, m, m];
        for &((x, y), r) in masses {
            // The turn of `PointLayers::draw`: (X, Y) -> (c·X + s·Y, -s·X + c·Y).
            let (px, py) = (c * x + s * y, -s * x + c * y);
            let e = r + 0.5 + 1.0;
            b = [
                b[0].min(px - e),
                b[1].min(py - e),
                b[2].max(px + e),
                b[3].max(py + e),
            ];
        }
        Some(b)
    }

    /// Draws the look as [`BodyLook::draw_turned_fast`] does through the scan
    /// converter (a convex outline, or a polygon that is not convex), its fill into
    /// `fill` and its stroke into `edge`, both in `ink`, placed and turned by `at`;
    /// returns false, drawing nothing, for other looks.
    pub fn draw_fast_apart(
        &self,
        fill: &mut Pixmap,
        edge: &mut Pixmap,
        at: Transform,
        ink: Ink,
    ) -> bool {
        if let Some(general) = &self.general {
            raster::fill_outline_apart(fill, edge, &general.fill, &general.stroke, at, ink);
            return true;
        }
        if let Some(turned) = &self.turned {
            raster::fill_turned_apart(fill, edge, &turned.fill, &turned.ring, at, ink);
            return true;
        }
        false
    }

    /// Returns true when [`BodyLook::draw_turned_fast`] draws this look through the
    /// scan converter: a turning convex outline.
    pub fn turns_fast(&self) -> bool {
        self.turns && self.turned.is_some()
    }

    /// Returns true when [`BodyLook::draw_fast`] draws this look through the scan
    /// converter: an outline of straight edges (convex or not) that never turns.
    pub fn draws_fast(&self) -> bool {
        !self.turns && (self.turned.is_some() || self.general.is_some() || self.disc.is_some())
    }

    /// Returns true when [`BodyLook::draw_turned_fast`] draws this look through the
    /// scan converter: a turning disc too large to stamp, with its orientation line.
    pub fn rolls_fast(&self) -> bool {
        self.turns && self.disc.is_some()
    }

    /// Returns true when [`BodyLook::draw_turned_fast`] draws this look through the
    /// general scan: a turning polygon that is not convex.
    pub fn turns_general(&self) -> bool {
        self.turns && self.general.is_some()
    }

    /// Draws a convex outline that never turns (a box, or a convex polygon, at its
    /// fixed angle) with its centre of mass at pixel (x, y), through the scan
    /// converter: the bytes of [`BodyLook::draw`] for the fill, and for the stroke a
    /// difference only where its round joins are cut into chords, as
    /// [`BodyLook::draw_turned_fast`] draws a turning one. Other looks are drawn by
    /// [`BodyLook::draw`].
    pub fn draw_fast(&self, pixmap: &mut Pixmap, x: f32, y: f32) {
        if let (Some(general), false) = (&self.general, self.turns) {
            raster::fill_outline(
                pixmap,
                &general.fill,
                &general.stroke,
                Transform::from_translate(x, y),
                Ink::of(self.fill),
                Ink::of(self.edge),
            );
            return;
        }
        if let (Some(disc), false) = (&self.disc, self.turns) {
            self.draw_scanned(pixmap, disc, Transform::from_translate(x, y));
            return;
        }
        match (&self.turned, self.turns) {
            (Some(turned), false) => {
                self.draw_scanned(pixmap, turned, Transform::from_translate(x, y))
            }
            _ => self.draw(pixmap, x, y),
        }
    }

    /// Draws a convex outline (or a disc's polygon) through the scan converter, placed
    /// by `at`: in opaque colours, its ring's outer side in the edge's colour and its
    /// inner side over it in the fill's, two fills without a hole
    /// ([`raster::fill_layers`]); otherwise (or when the outline is too thin to have
    /// an inner side) its fill and then its ring, scanned with its hole. The layers
    /// differ from the fill then the ring only where the fill's edge crosses a pixel:
    /// along a straight edge by at most 1/64 of the fill's difference from what lies
    /// under it (the fill's edge and each side lie 0.75 pixel apart), a quarter at
    /// most anywhere. They cost about half the ring's scan: 1000 turning boxes of
    /// their own sizes drew in 1.3 ms a frame instead of 2.4 (docs/performance-log.md).
    fn draw_scanned(&self, pixmap: &mut Pixmap, outline: &TurnedOutline, at: Transform) {
        let (fill, edge) = (Ink::of(self.fill), Ink::of(self.edge));
        let layers = fill.is_opaque() && edge.is_opaque();
        match &outline.ring.inner {
            Some(inner) if layers => {
                raster::fill_layers(pixmap, &outline.ring.outer, inner, at, [edge, fill]);
            }
            _ => raster::fill_turned(pixmap, &outline.fill, &outline.ring, at, fill, edge),
        }
    }

    fn draw_turned_with(&self, pixmap: &mut Pixmap, x: f32, y: f32, theta: f64, fast: bool) {
        if let (true, Some(disc)) = (fast, &self.disc) {
            // A disc looks the same at every angle: it is drawn unturned, then its
            // orientation line.
            self.draw_scanned(pixmap, disc, Transform::from_translate(x, y));
            self.draw_orientation_fast(pixmap, x, y, theta);
            return;
        }
        if self.marker.is_some() {
            self.draw(pixmap, x, y);
            self.draw_orientation(pixmap, x, y, theta);
            return;
        }
        let (s, c) = theta.sin_cos();
        let (s, c) = (s as f32, c as f32);
        let at = Transform::from_row(c, -s, s, c, x, y);
        if let (true, Some(general)) = (fast, &self.general) {
            raster::fill_outline(
                pixmap,
                &general.fill,
                &general.stroke,
                at,
                Ink::of(self.fill),
                Ink::of(self.edge),
            );
            return;
        }
        if let (true, Some(turned)) = (fast, &self.turned) {
            self.draw_scanned(pixmap, turned, at);
            return;
        }
        if let Some(outline) = &self.outline {
            let mut paint = Paint {
                anti_alias: true,
                ..Paint::default()
            };
            paint.set_color(self.fill);
            pixmap.fill_path(outline, &paint, FillRule::Winding, at, None);
            paint.set_color(self.edge);
            pixmap.stroke_path(outline, &paint, &outline_stroke(), at, None);
        }
        self.draw_points(pixmap, x, y, at);
    }

    /// Draws an outline body's fill, then its edge, each in the colour given (or not
    /// at all for `None`), with its centre of mass at pixel (x, y).
    pub fn draw_outline(
        &self,
        pixmap: &mut Pixmap,
        x: f32,
        y: f32,
        fill: Option<Color>,
        edge: Option<Color>,
    ) {
        let at = Transform::from_translate(x, y);
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        if let Some(outline) = &self.outline {
            if let Some(fill) = fill {
                paint.set_color(fill);
                pixmap.fill_path(outline, &paint, FillRule::Winding, at, None);
            }
            if let Some(edge) = edge {
                paint.set_color(edge);
                pixmap.stroke_path(outline, &paint, &outline_stroke(), at, None);
            }
        }
    }

    /// Draws a body of point masses: bars, discs (placed by `at`, which takes the
    /// body's offsets to pixels) and the centre-of-mass marker at pixel (x, y).
    fn draw_points(&self, pixmap: &mut Pixmap, x: f32, y: f32, at: Transform) {
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        if let Some((discs, bars)) = &self.points {
            paint.set_color(self.edge);
            let stroke = Stroke {
                width: 1.5,
                ..Stroke::default()
            };
            pixmap.stroke_path(bars, &paint, &stroke, at, None);
            paint.set_color(self.fill);
            pixmap.fill_path(discs, &paint, FillRule::Winding, at, None);
            paint.set_color(self.edge);
            pixmap.stroke_path(discs, &paint, &Stroke::default(), at, None);
            draw_centre_of_mass_marker(pixmap, x, y);
        }
    }
}

/// The stroke of every outline: 1.5 pixels, with round joins.
fn outline_stroke() -> Stroke {
    Stroke {
        width: 1.5,
        line_join: LineJoin::Round,
        ..Stroke::default()
    }
}

/// The radius of the centre-of-mass marker in pixels.
const MARKER_RADIUS: f32 = 5.0;

/// How far the centre-of-mass marker reaches from its centre, in pixels: its radius
/// and half its 1-pixel ring.
pub const MARKER_REACH: f32 = MARKER_RADIUS + 0.5;

/// Draws the classic centre-of-mass symbol: a circle with two opposite quarters filled.
pub fn draw_centre_of_mass_marker(pixmap: &mut Pixmap, x: f32, y: f32) {
    let r = MARKER_RADIUS;
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    let at = Transform::from_translate(x, y);
    if let Some(disc) = PathBuilder::from_circle(0.0, 0.0, r) {
        paint.set_color(Color::WHITE);
        pixmap.fill_path(&disc, &paint, FillRule::Winding, at, None);
    }
    // Two quarter discs: from angle 0 to 90° and from 180° to 270°, as wedges.
    let mut pb = PathBuilder::new();
    for start in [0.0f32, std::f32::consts::PI] {
        pb.move_to(0.0, 0.0);
        let steps = 8;
        for i in 0..=steps {
            let a = start + std::f32::consts::FRAC_PI_2 * i as f32 / steps as f32;
            pb.line_to(r * a.cos(), -r * a.sin());
        }
        pb.close();
    }
    paint.set_color(Color::BLACK);
    if let Some(wedges) = pb.finish() {
        pixmap.fill_path(&wedges, &paint, FillRule::Winding, at, None);
    }
    if let Some(ring) = PathBuilder::from_circle(0.0, 0.0, r) {
        pixmap.stroke_path(&ring, &paint, &Stroke::default(), at, None);
    }
}
