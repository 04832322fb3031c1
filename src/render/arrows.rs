//! Velocity and force arrows: the scales that size them for a run, and their shaft
//! and head, covered by ramps ([`super::raster::fill_ramps`]: within a stated bound of
//! tiny-skia's coverage, at a fraction of its cost), or as tiny-skia's paths (the
//! reference they are tested against, and what hairlines use).

use glam::DVec2;
use tiny_skia::{Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::clip::ClipRect;
use super::damage::TileMask;
use super::raster;
use super::sprite::Ink;
use crate::scene::Scene;

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

/// Where an arrow's parts lie in pixels: the shaft from its start to the head's base,
/// and the head's tip and two back corners, each as tiny-skia receives it (f32).
struct ArrowGeometry {
    /// The shaft's ends, clipped to the guard band, or `None` when it lies outside.
    shaft: Option<((f64, f64), (f64, f64))>,
    /// The head's triangle, or `None` when its tip is outside the guard band.
    head: Option<[(f32, f32); 3]>,
}

/// An arrow from pixel (x, y) along the pixel vector (dx, dy), before clipping: its
/// direction and length, its head's length (which follows the stroke width but never
/// exceeds half the arrow's length), the head's base on the shaft, and the tip.
struct ArrowLayout {
    unit: (f64, f64),
    len: f64,
    head: f64,
    base: (f64, f64),
    tip: (f64, f64),
}

impl ArrowLayout {
    /// `None` when the arrow is shorter than half a pixel or not finite: nothing is
    /// drawn.
    fn new((x, y): (f64, f64), (dx, dy): (f64, f64), width: f32) -> Option<Self> {
        let len = (dx * dx + dy * dy).sqrt();
        if len < 0.5 || !len.is_finite() {
            return None;
        }
        let (ux, uy) = (dx / len, dy / len);
        let head = (4.0 * f64::from(width) + 4.0).min(0.5 * len);
        Some(ArrowLayout {
            unit: (ux, uy),
            len,
            head,
            base: (x + dx - ux * head, y + dy - uy * head),
            tip: (x + dx, y + dy),
        })
    }
}

impl ArrowGeometry {
    /// Lays out an arrow from pixel (x, y) along the pixel vector (dx, dy)
    /// ([`ArrowLayout`]) and clips it; `None` when nothing is drawn.
    fn new(clip: &ClipRect, at: (f64, f64), d: (f64, f64), width: f32) -> Option<Self> {
        let ArrowLayout {
            unit: (ux, uy),
            len: _,
            head,
            base,
            tip,
        } = ArrowLayout::new(at, d, width)?;
        let (x, y) = at;
        let half = 0.5 * head;
        Some(ArrowGeometry {
            shaft: clip.segment((x, y), base),
            head: clip.contains(tip.0, tip.1).then_some([
                (tip.0 as f32, tip.1 as f32),
                ((base.0 - uy * half) as f32, (base.1 + ux * half) as f32),
                ((base.0 + uy * half) as f32, (base.1 - ux * half) as f32),
            ]),
        })
    }
}

/// Draws an arrow from pixel (x, y) along the pixel vector (dx, dy), with a head whose
/// size follows the stroke width but never exceeds half the arrow's length. The shaft
/// is clipped to the guard band, and the head is drawn only when the tip is inside it.
///
/// The shaft (a stroke wider than a pixel: the rectangle of its half-width about the
/// line, with square ends, as tiny-skia strokes it) and the head (a triangle) are each
/// covered by the product of a ramp across each of their sides
/// ([`raster::fill_ramps`]), not by tiny-skia's four sub-rows of quarter-pixel
/// columns: a pixel differs from [`draw_arrow_path`]'s by at most 0.293 of the ink's
/// contrast with what lies under it, and by 0.02 on average over an arrow's pixels
/// (`tests/integration/every_scene.rs`). Strokes of a pixel or less, which tiny-skia
/// draws as hairlines, are drawn by [`draw_arrow_path`].
pub fn draw_arrow(
    pixmap: &mut Pixmap,
    clip: &ClipRect,
    at: (f64, f64),
    d: (f64, f64),
    c: Color,
    width: f32,
) {
    if width <= 1.0 {
        draw_arrow_path(pixmap, clip, at, d, c, width);
        return;
    }
    let Some(ArrowLayout {
        unit,
        len,
        head,
        base,
        tip,
    }) = ArrowLayout::new(at, d, width)
    else {
        return;
    };
    let ink = Ink::of(c);
    // The shaft clipped to the guard band (where it reaches outside), the head drawn
    // only when its tip is inside it: as ArrowGeometry lays them out for tiny-skia.
    let half = 0.5 * f64::from(width);
    let shaft = if clip.contains(at.0, at.1) && clip.contains(base.0, base.1) {
        raster::Ramps::shaft_along(at, unit, len - head, half)
    } else {
        clip.segment(at, base)
            .and_then(|(a, b)| raster::Ramps::shaft(a, b, half))
    };
    if let Some(shaft) = shaft {
        raster::fill_ramps(pixmap, &shaft, ink);
    }
    if clip.contains(tip.0, tip.1) {
        if let Some(head) = raster::Ramps::head(tip, unit, head) {
            raster::fill_ramps(pixmap, &head, ink);
        }
    }
}

/// Marks in `mask` the tiles of every pixel that [`draw_arrow`] (or
/// [`draw_arrow_path`]) with the same arguments may change, row by row: the pixels
/// near its shaft, within its half-width of the line from `at` to the head's base, and
/// those near its head, within half the head's width of the line from the base to the
/// tip, each grown as `raster::capsule_spans` grows them. A frame with trails then
/// compresses afresh only those tiles, not the whole frame.
pub fn mark_arrow(mask: &mut TileMask, at: (f64, f64), d: (f64, f64), width: f32) {
    arrow_spans(mask.size(), at, d, width, |y, x0, x1| {
        mask.mark_span(x0, x1, y)
    });
}

/// Calls `span(y, first, end)` for the columns first..end of each row y, in an image
/// of `size`, that [`mark_arrow`] marks: the pixels the arrow may change, row by row,
/// a row perhaps in two spans (the shaft's and the head's).
pub(crate) fn arrow_spans(
    size: (u32, u32),
    at: (f64, f64),
    d: (f64, f64),
    width: f32,
    mut span: impl FnMut(usize, usize, usize),
) {
    let Some(ArrowLayout {
        head, base, tip, ..
    }) = ArrowLayout::new(at, d, width)
    else {
        return;
    };
    // A stroke wider than a pixel is a rectangle half its width about the line.
    // tiny-skia draws narrower ones as anti-aliased hairlines, which stray further: a
    // pixel whose centre lies 2.1 pixels from the line was drawn (an arrow from inside
    // the image to far outside it, in the test of this function), so they are taken
    // as two pixels wide each side. (Bodies' arrows are 2 pixels wide.)
    let shaft = if width > 1.0 {
        0.5 * f64::from(width)
    } else {
        2.0
    };
    for (a, b, half) in [(at, base, shaft), (base, tip, 0.5 * head)] {
        raster::capsule_spans(size, a, b, half, &mut span);
    }
}

/// Draws an arrow as [`draw_arrow`] does, with tiny-skia's paths: a stroked shaft and
/// a filled head. The reference for [`draw_arrow`], and what it uses for hairlines.
pub fn draw_arrow_path(
    pixmap: &mut Pixmap,
    clip: &ClipRect,
    at: (f64, f64),
    d: (f64, f64),
    c: Color,
    width: f32,
) {
    let Some(arrow) = ArrowGeometry::new(clip, at, d, width) else {
        return;
    };
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    paint.set_color(c);
    if let Some((a, b)) = arrow.shaft {
        let mut pb = PathBuilder::new();
        pb.move_to(a.0 as f32, a.1 as f32);
        pb.line_to(b.0 as f32, b.1 as f32);
        let stroke = Stroke {
            width,
            line_cap: LineCap::Butt,
            ..Stroke::default()
        };
        if let Some(shaft) = pb.finish() {
            pixmap.stroke_path(&shaft, &paint, &stroke, Transform::identity(), None);
        }
    }
    let Some([tip, left, right]) = arrow.head else {
        return;
    };
    let mut pb = PathBuilder::new();
    pb.move_to(tip.0, tip.1);
    pb.line_to(left.0, left.1);
    pb.line_to(right.0, right.1);
    pb.close();
    if let Some(path) = pb.finish() {
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}
