//! Springs, drawn as coils between their ends when the scene asks (`show_springs`).
//!
//! An end is a body point, which moves and turns with its body, or a fixed point. The
//! coil is a zigzag of a fixed number of turns and a fixed width in pixels between two
//! short straight leads, so a stretched spring's turns spread out and a compressed
//! one's bunch up, as a real coil's do.
//!
//! A coil is tiny-skia's stroke of its polyline, round-joined, when a scene shows few
//! springs. A scene that shows many (a cloth of a thousand bodies has two thousand) has
//! them covered by the distance to the line instead ([`raster::stroke_polyline`]):
//! 1935 coils drew in 9.5 ms instead of 71, within a bound of tiny-skia's pixels
//! stated there.

use glam::DVec2;
use tiny_skia::{Color, LineCap, LineJoin, Paint, Pixmap, Stroke, Transform};

use super::camera::Camera;
use super::clip::ClipRect;
use super::damage::{Damage, Marking};
use super::raster;
use super::sprite::Ink;
use crate::scene::Scene;
use crate::sim::rigid::rotate;
use crate::sim::{Anchor, ForceSpec};

/// The zigzag's half-turns.
const HALF_TURNS: usize = 12;
/// The zigzag's width, from its axis to a corner, in pixels.
const WIDTH: f64 = 5.0;
/// The share of the length taken by each straight lead.
const LEAD: f64 = 0.12;

/// One end of a drawn spring.
#[derive(Clone, Debug)]
enum End {
    /// A point of body `body`: its arm from the centre of mass in body axes, and the
    /// body's constant angle when it never turns (`None` when it does).
    Body {
        body: usize,
        arm: DVec2,
        fixed_angle: Option<f64>,
    },
    /// A fixed point of the world.
    Point(DVec2),
}

impl End {
    /// Returns where the end is in the world, given the bodies' positions and, when
    /// some body turns, their angles.
    fn world(&self, pos: &[DVec2], angle: Option<&[f64]>) -> DVec2 {
        match *self {
            End::Point(p) => p,
            End::Body {
                body,
                arm,
                fixed_angle,
            } => {
                if arm == DVec2::ZERO {
                    return pos[body];
                }
                let theta = fixed_angle.or(angle.map(|a| a[body])).unwrap_or(0.0);
                // r + R(θ)·(at - c).
                pos[body] + rotate(theta.sin_cos(), arm)
            }
        }
    }
}

/// The springs of a scene, ready to draw.
#[derive(Clone, Debug)]
pub struct Springs {
    springs: Vec<(End, End)>,
}

/// From how many springs a scene's coils are covered by distance rather than stroked
/// as tiny-skia's paths: as many as share a sprite ([`super::looks::SPRITE_MIN_BODIES`]),
/// so that the examples' few springs keep tiny-skia's bytes.
pub const FAST_MIN_SPRINGS: usize = super::looks::SPRITE_MIN_BODIES;

/// The coils' colour.
fn coil_color() -> Color {
    Color::from_rgba8(0x55, 0x55, 0x55, 0xff)
}

/// The coils' stroke width, in pixels.
const STROKE: f32 = 1.3;

/// How far from the line between a coil's ends its stroke may reach, in pixels: its
/// points lie within [`WIDTH`] of the line (the zigzag's corners on it, the leads along
/// it, and the segments between them), and the stroke, round-joined and round-capped,
/// within half its width of them. (A covered pixel's centre lies within 1/2 more, by
/// [`raster::stroke_polyline`]'s ramp, and a pixel tiny-skia's scan converter touches
/// within 0.83: the margin `raster::capsule_spans` adds.)
const REACH: f64 = WIDTH + STROKE as f64 / 2.0;

impl Springs {
    /// Returns the scene's springs when it shows them, or `None`.
    pub fn new(scene: &Scene) -> Option<Self> {
        if !scene.render.show_springs {
            return None;
        }
        let body_end = |i: u32, at: Option<DVec2>| {
            let b = &scene.bodies[i as usize];
            End::Body {
                body: i as usize,
                arm: at.map_or(DVec2::ZERO, |p| p - b.centre),
                fixed_angle: (!b.turns).then_some(b.angle),
            }
        };
        let springs: Vec<(End, End)> = scene
            .forces
            .iter()
            .filter_map(|f| match f {
                ForceSpec::Spring {
                    a, b, a_at, b_at, ..
                } => Some((
                    body_end(*a, *a_at),
                    match b {
                        Anchor::Body(j) => body_end(*j, *b_at),
                        Anchor::Point(p) => End::Point(*p),
                    },
                )),
                _ => None,
            })
            .collect();
        (!springs.is_empty()).then_some(Springs { springs })
    }

    /// Returns how many springs are drawn.
    pub fn len(&self) -> usize {
        self.springs.len()
    }

    /// Returns true when there is no spring to draw (never, for springs made by
    /// [`Springs::new`]).
    pub fn is_empty(&self) -> bool {
        self.springs.is_empty()
    }

    /// Marks the tiles of every pixel a coil at the bodies' positions `pos` and angles
    /// `angle` may change, row by row: those within `REACH` of the line between its
    /// ends, grown as `raster::capsule_spans` grows them. When the coils would mark more
    /// tiles, by `Springs::tiles_estimate`, than `marks` has room for or than
    /// `budget`, the mask is made whole at once instead: in the first case marking them
    /// would be lost work, in the second it would cost more than it saves.
    pub fn mark(
        &self,
        size: (u32, u32),
        camera: &Camera,
        (pos, angle): (&[DVec2], Option<&[f64]>),
        (marks, budget): (&mut Marking<'_>, usize),
    ) {
        let estimate = self.tiles_estimate(camera, (pos, angle));
        if estimate > marks.room().min(budget) as f64 {
            marks.make_whole();
            return;
        }
        for (a, b) in &self.springs {
            let from = camera.to_pixel_f64(a.world(pos, angle));
            let to = camera.to_pixel_f64(b.world(pos, angle));
            raster::capsule_spans(size, from, to, REACH, |y, x0, x1| marks.span(x0, x1, y));
            marks.check();
            if marks.is_done() {
                return;
            }
        }
    }

    /// Adds to `damage` the box of every pixel a coil at the bodies' positions `pos`
    /// and angles `angle` may change: the box around its ends, grown by `REACH` and
    /// 2 pixels more (a pixel the stroke touches has its centre within 0.83 of it,
    /// `raster::capsule_spans`, and the box is of whole pixels).
    pub fn add_boxes(
        &self,
        (width, height): (u32, u32),
        camera: &Camera,
        (pos, angle): (&[DVec2], Option<&[f64]>),
        damage: &mut Damage,
    ) {
        let r = REACH + 2.0;
        for (a, b) in &self.springs {
            if damage.is_whole() {
                return;
            }
            let (x0, y0) = camera.to_pixel_f64(a.world(pos, angle));
            let (x1, y1) = camera.to_pixel_f64(b.world(pos, angle));
            if !(x0.is_finite() && y0.is_finite() && x1.is_finite() && y1.is_finite()) {
                damage.set_whole();
                return;
            }
            // Clamped well outside the frame first: the casts saturate, and the damage
            // keeps to the frame.
            let bound = |v: f64| v.clamp(-1e9, 1e9) as i64;
            let rect = (
                bound((x0.min(x1) - r).floor()),
                bound((y0.min(y1) - r).floor()),
                bound((x0.max(x1) + r).ceil()) + 1,
                bound((y0.max(y1) + r).ceil()) + 1,
            );
            damage.add_rect(rect, width, height);
        }
    }

    /// About how many tiles the coils' marks cover, overlaps counted as often as they
    /// occur: each coil's capsule of radius R (its [`REACH`], grown by
    /// `raster::capsule_spans`'s margin) and length L covers some (L + 2R)·2R pixels
    /// over |Δy| + 2R rows, and so about a tile for every 8 of its pixels and one more,
    /// cut in two, at each row's ends.
    fn tiles_estimate(&self, camera: &Camera, (pos, angle): (&[DVec2], Option<&[f64]>)) -> f64 {
        let r = REACH + 1.0;
        let tile = f64::from(super::damage::TILE_PIXELS);
        self.springs
            .iter()
            .map(|(a, b)| {
                let (x0, y0) = camera.to_pixel_f64(a.world(pos, angle));
                let (x1, y1) = camera.to_pixel_f64(b.world(pos, angle));
                let length = (x1 - x0).hypot(y1 - y0);
                let rows = (y1 - y0).abs() + 2.0 * r;
                (length + 2.0 * r) * 2.0 * r / tile + rows
            })
            .sum()
    }

    /// Draws every spring between its ends at the bodies' positions `pos` and, when
    /// some body turns, angles `angle`: as tiny-skia's strokes, or, when `fast`,
    /// covered by distance ([`raster::stroke_polyline`]).
    pub fn draw(
        &self,
        pixmap: &mut Pixmap,
        (camera, clip): (&Camera, &ClipRect),
        (pos, angle): (&[DVec2], Option<&[f64]>),
        fast: bool,
    ) {
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        paint.set_color(coil_color());
        let stroke = Stroke {
            width: STROKE,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Stroke::default()
        };
        let ink = Ink::of(coil_color());
        let mut pieces = Vec::new();
        for (a, b) in &self.springs {
            let from = camera.to_pixel_f64(a.world(pos, angle));
            let to = camera.to_pixel_f64(b.world(pos, angle));
            let points = coil(from, to);
            if !fast {
                if let Some(path) = clip.polyline(points) {
                    pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
                }
                continue;
            }
            // A coil inside the guard band is stroked as it is: its points lie within
            // WIDTH of the line between its ends (REACH leaves room for rounding), and
            // a segment inside is its own cut.
            let inside = |(x, y): (f64, f64)| {
                x - REACH > clip.x0
                    && x + REACH < clip.x1
                    && y - REACH > clip.y0
                    && y + REACH < clip.y1
            };
            if inside(from) && inside(to) {
                raster::stroke_polyline(pixmap, &points, f64::from(STROKE), ink);
                continue;
            }
            // The coil cut to the guard band as the path would be, piece by piece.
            pieces.clear();
            for pair in points.windows(2) {
                let Some((c, d)) = clip.segment(pair[0], pair[1]) else {
                    flush(pixmap, &mut pieces, ink);
                    continue;
                };
                if pieces.last() != Some(&c) {
                    flush(pixmap, &mut pieces, ink);
                    pieces.push(c);
                }
                pieces.push(d);
            }
            flush(pixmap, &mut pieces, ink);
        }
    }
}

/// Strokes the polyline `points` holds, if any, and empties it.
fn flush(pixmap: &mut Pixmap, points: &mut Vec<(f64, f64)>, ink: Ink) {
    if !points.is_empty() {
        raster::stroke_polyline(pixmap, points, f64::from(STROKE), ink);
        points.clear();
    }
}

/// Returns the points of a coil from pixel `from` to pixel `to`: a straight lead, a
/// zigzag of [`HALF_TURNS`] half-turns of width [`WIDTH`], and another lead. A spring
/// shorter than its zigzag is wide, or not finite, is a straight line.
fn coil(from: (f64, f64), to: (f64, f64)) -> Vec<(f64, f64)> {
    let (dx, dy) = (to.0 - from.0, to.1 - from.1);
    let length = (dx * dx + dy * dy).sqrt();
    if !length.is_finite() || length <= 4.0 * WIDTH {
        return vec![from, to];
    }
    let (ux, uy) = (dx / length, dy / length);
    // The unit normal, a quarter turn from the axis.
    let (nx, ny) = (-uy, ux);
    let at = |s: f64, side: f64| {
        (
            from.0 + ux * s * length + nx * side * WIDTH,
            from.1 + uy * s * length + ny * side * WIDTH,
        )
    };
    let mut points = Vec::with_capacity(HALF_TURNS + 4);
    points.push(from);
    points.push(at(LEAD, 0.0));
    let span = 1.0 - 2.0 * LEAD;
    for k in 0..HALF_TURNS {
        // Corners midway along each half-turn, alternating sides.
        let s = LEAD + span * (k as f64 + 0.5) / HALF_TURNS as f64;
        points.push(at(s, if k % 2 == 0 { 1.0 } else { -1.0 }));
    }
    points.push(at(1.0 - LEAD, 0.0));
    points.push(to);
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::damage::TileMask;

    #[test]
    fn the_estimate_of_a_coils_tiles_is_within_a_tile_a_row_of_those_it_marks() {
        let text = "[render]\nwidth = 1280\nheight = 720\nshow_springs = true\n\
            view = { min = [0.0, 0.0], max = [16.0, 9.0] }\n\
            [[body]]\nname = \"a\"\nmass = 1.0\nposition = [0.0, 0.0]\n\
            [[body]]\nname = \"b\"\nmass = 1.0\nposition = [1.0, 0.0]\n\
            [[force]]\nkind = \"spring\"\na = \"a\"\nb = \"b\"\nstiffness = 1.0\n";
        let scene = crate::scene::parse(std::path::Path::new("s.toml"), text).expect("valid");
        let springs = Springs::new(&scene).expect("shown");
        let size = (scene.render.width, scene.render.height);
        let camera = Camera::fit(scene.render.view, size.0, size.1);
        let r = REACH + 1.0;
        for length in [0.0, 0.1, 0.5, 2.0, 8.0] {
            for step in 0..12 {
                let theta = f64::from(step) * std::f64::consts::PI / 12.0 + 0.1;
                // About the view's centre, inside the frame.
                let half = 0.5 * length * DVec2::new(theta.cos(), theta.sin());
                let pos = [DVec2::new(8.0, 4.5) - half, DVec2::new(8.0, 4.5) + half];
                let mut mask = TileMask::new(size.0, size.1);
                mask.clear();
                let mut marks = Marking::new(&mut mask, usize::MAX);
                springs.mark(size, &camera, (&pos, None), (&mut marks, usize::MAX));
                let marked = mask.count() as f64;
                let estimate = springs.tiles_estimate(&camera, (&pos, None));
                // The capsule's pixels, A = 2rL + πr² near enough, make rows of spans
                // that each cover from w/8 to w/8 + 2 tiles, or some A/8 + rows in
                // all; the estimate counts its ends as squares, (4 - π)r² pixels
                // more, and the rows' spans are whole pixels, up to 2 more a row.
                let rows = (pos[1].y - pos[0].y).abs() * 80.0 + 2.0 * r;
                let bound = 1.25 * rows + (4.0 - std::f64::consts::PI) * r * r / 8.0;
                assert!(
                    (estimate - marked).abs() <= bound,
                    "length {length}, angle {theta}: estimate {estimate}, marked {marked}, bound {bound}"
                );
            }
        }
    }

    #[test]
    fn a_coil_runs_from_end_to_end_within_its_width() {
        let points = coil((10.0, 20.0), (110.0, 20.0));
        assert_eq!(points.first(), Some(&(10.0, 20.0)));
        assert_eq!(points.last(), Some(&(110.0, 20.0)));
        assert_eq!(points.len(), HALF_TURNS + 4);
        for (x, y) in &points {
            assert!((10.0..=110.0).contains(x));
            assert!((y - 20.0).abs() <= WIDTH + 1e-12);
        }
        // Too short, or not finite: a straight line.
        assert_eq!(coil((0.0, 0.0), (3.0, 4.0)).len(), 2);
        assert_eq!(coil((0.0, 0.0), (f64::NAN, 4.0)).len(), 2);
    }
}
