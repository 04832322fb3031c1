//! Bodies of point masses drawn fast: the same layers as their paths, each by the
//! fastest exact-enough means.
//!
//! A body of point masses is drawn ([`BodyLook::draw_turned`]) as bars from its centre
//! of mass to each mass (a 1.5-pixel stroke with butt ends, in the edge colour), then
//! a disc at each mass (filled, then a 1-pixel outline), then the centre-of-mass marker,
//! which does not turn. As tiny-skia paths that is six paths a body, about 34 µs: 1000
//! turning dumbbells ran at a twentieth of the speed of 1000 discs. A picture at angle
//! bins (as a turning box has) would cost megabytes per colour. Instead, for a look
//! that [`super::looks::SPRITE_MIN_BODIES`] or more turning bodies share:
//!
//! - each bar is the rectangle tiny-skia's stroker makes of it ([`raster::bar`]),
//!   turned with the body and filled by the convex scan converter, which gives a
//!   convex polygon tiny-skia's coverage;
//! - each disc is stamped from sprites of its radius with a 1-pixel outline, at its
//!   turned centre snapped to 1/[`PHASES`] pixel, as every disc sprite; all discs'
//!   fills first, then all outlines, in the order of the paths;
//! - the marker is a picture ([`super::picture`]) at the snapped centre.
//!
//! A body of point masses that never turns and that 16 bodies share is a picture of
//! its own ([`super::picture`]). One that fewer share, each of its own masses, in a
//! scene of 16 or more bodies of point masses, is drawn by layers too, turning or not,
//! with its discs' radii snapped to 1/[`PHASES`] pixel so that bodies of nearby masses
//! share their sprites (as discs of their own radii do, `looks::snap_radius`). Unturned,
//! tiny-skia draws the discs' 1-pixel outlines as hairlines, and so do their sprites.
//!
//! What differs from the paths: the snapped positions (1/16 pixel along each axis at
//! most), and the bars, filled one by one rather than as one path, blend twice where
//! they overlap, which for bars that leave the centre more than a few degrees apart is
//! within the marker's opaque disc, which covers it. `tests/integration/every_scene.rs`
//! bounds the difference.

use std::collections::HashMap;
use std::sync::Arc;

use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::bodies::{draw_centre_of_mass_marker, BodyLook, MARKER_REACH};
use super::looks::snap_radius;
use super::picture::PictureSheet;
use super::raster;
use super::sprite::{snap_to, Ink, Sprite, PHASES};

/// The half-width of a bar: tiny-skia's 1.5-pixel stroke.
const BAR_HALF_WIDTH: f32 = 0.75;

/// The fill and outline coverage of a point mass's disc, at every phase.
#[derive(Debug)]
pub struct DiscSprites {
    sprites: Vec<Sprite>,
}

impl DiscSprites {
    /// Rasterises a disc of radius `r` pixels and its 1-pixel outline, as
    /// [`BodyLook::draw_turned`] draws a point mass (or [`BodyLook::draw`], unturned,
    /// when `hairline`), at every phase.
    fn new(r: f32, hairline: bool) -> Option<Self> {
        let pad = (r + 3.0).ceil() as i32;
        let side = (2 * pad + 2) as u32;
        let white = Paint {
            anti_alias: true,
            shader: tiny_skia::Shader::SolidColor(Color::WHITE),
            ..Paint::default()
        };
        let mut sprites = Vec::with_capacity((PHASES * PHASES) as usize);
        for j in 0..PHASES {
            for i in 0..PHASES {
                let x = pad as f32 + i as f32 / PHASES as f32;
                let y = pad as f32 + j as f32 / PHASES as f32;
                let disc = PathBuilder::from_circle(x, y, r)?;
                // Opaque white over transparent black leaves the coverage in alpha.
                let mut fill = Pixmap::new(side, side)?;
                fill.fill_path(
                    &disc,
                    &white,
                    FillRule::Winding,
                    Transform::identity(),
                    None,
                );
                // The outline as tiny-skia strokes it: unturned, as a hairline;
                // under a turn, as the stroker's ring, filled.
                let mut edge = Pixmap::new(side, side)?;
                if hairline {
                    let stroke = Stroke::default();
                    edge.stroke_path(&disc, &white, &stroke, Transform::identity(), None);
                } else {
                    let ring = disc.stroke(&Stroke::default(), 1.0)?;
                    let id = Transform::identity();
                    edge.fill_path(&ring, &white, FillRule::Winding, id, None);
                }
                sprites.push(Sprite::trimmed(&fill, &edge, -pad, -pad));
            }
        }
        Some(DiscSprites { sprites })
    }

    /// Returns the sprite for a disc centred at pixel (x, y), and where its top-left
    /// pixel goes.
    fn at(&self, x: f32, y: f32) -> (&Sprite, i64, i64) {
        let (ix, i) = snap_to(x, PHASES);
        let (iy, j) = snap_to(y, PHASES);
        let s = &self.sprites[(j * PHASES + i) as usize];
        (s, ix + i64::from(s.dx), iy + i64::from(s.dy))
    }
}

/// What a scene's point-mass looks drawn by layers share: disc sprites by radius and
/// outline, and the marker's picture.
#[derive(Default)]
pub struct PointSprites {
    discs: HashMap<(u32, bool), Option<Arc<DiscSprites>>>,
    marker: Option<Option<Arc<PictureSheet>>>,
}

impl PointSprites {
    /// Returns the drawing by layers of `look`, a body of point masses, with its discs'
    /// radii snapped to 1/[`PHASES`] pixel when `snap`; or `None` when it is not one or
    /// its sprites cannot be made.
    pub fn layers(&mut self, look: &BodyLook, snap: bool) -> Option<TurningPoints> {
        let turns = look.turns();
        let masses = look.point_masses()?;
        let marker = self
            .marker
            .get_or_insert_with(|| {
                PictureSheet::of_drawing(MARKER_REACH, |pixmap, x, y| {
                    draw_centre_of_mass_marker(pixmap, x, y)
                })
            })
            .clone()?;
        let mut points = Vec::with_capacity(masses.len());
        for (offset, r) in masses {
            let r = if snap { snap_radius(r) } else { r };
            let sprites = self
                .discs
                .entry((r.to_bits(), !turns))
                .or_insert_with(|| DiscSprites::new(r, !turns).map(Arc::new))
                .clone()?;
            points.push((offset, sprites));
        }
        let (fill, edge) = look.colors();
        Some(TurningPoints {
            turns,
            points,
            marker,
            fill: Ink::of(fill),
            edge: Ink::of(edge),
        })
    }
}

/// A body of point masses, drawn by the scan converter and sprites.
#[derive(Clone, Debug)]
pub struct TurningPoints {
    /// Whether it turns; if not, its offsets hold its fixed angle already.
    turns: bool,
    /// Each mass's offset from the centre of mass in pixels at angle 0, and its disc.
    points: Vec<((f32, f32), Arc<DiscSprites>)>,
    marker: Arc<PictureSheet>,
    fill: Ink,
    edge: Ink,
}

impl TurningPoints {
    /// Draws the body with its centre of mass at pixel (x, y), turned by `theta`
    /// radians counter-clockwise in the world if it turns, as
    /// [`BodyLook::draw_turned`] (or unturned, [`BodyLook::draw`]) does, and returns
    /// true; or draws nothing and returns false for a turning body without an angle,
    /// or at an angle where tiny-skia draws the discs' 1-pixel outlines as hairlines (a
    /// multiple of a right angle, as a body that starts at angle 0 has in its first
    /// frame), for the path to draw.
    pub fn draw(&self, pixmap: &mut Pixmap, x: f32, y: f32, theta: Option<f64>) -> bool {
        let at = if self.turns {
            let Some(theta) = theta else {
                return false;
            };
            let (s, c) = theta.sin_cos();
            let (s, c) = (s as f32, c as f32);
            // tiny-skia strokes as a hairline when both turned unit vectors have a
            // `fast_len` (the larger component plus half the smaller) of at most 1.
            let fast_len = |a: f32, b: f32| a.abs().max(b.abs()) + 0.5 * a.abs().min(b.abs());
            if fast_len(c, s) <= 1.0 {
                return false;
            }
            // The path's transform: (X, Y) -> (c·X + s·Y + x, -s·X + c·Y + y).
            Transform::from_row(c, -s, s, c, x, y)
        } else {
            Transform::from_translate(x, y)
        };
        let turn = |p: (f32, f32)| {
            let mut q = [tiny_skia::Point::from_xy(p.0, p.1)];
            at.map_points(&mut q);
            (q[0].x, q[0].y)
        };
        // The bars: each the stroker's rectangle from the centre to the mass, turned.
        for (offset, _) in &self.points {
            if let Some(corners) = raster::bar((0.0, 0.0), *offset, BAR_HALF_WIDTH) {
                raster::fill_convex(pixmap, &corners.map(turn), self.edge);
            }
        }
        // The discs' fills, then their outlines, as the paths are drawn.
        for (offset, discs) in &self.points {
            let (cx, cy) = turn(*offset);
            let (sprite, sx, sy) = discs.at(cx, cy);
            sprite.stamp_layer(pixmap, sx, sy, 0, self.fill);
        }
        for (offset, discs) in &self.points {
            let (cx, cy) = turn(*offset);
            let (sprite, sx, sy) = discs.at(cx, cy);
            sprite.stamp_layer(pixmap, sx, sy, 1, self.edge);
        }
        self.marker.stamp(pixmap, x, y);
        true
    }
}
