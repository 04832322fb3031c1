//! A turning circle's orientation line, the line from its centre to its rim along its
//! body x axis: as tiny-skia's stroked path, and through the scan converter.

use tiny_skia::{LineCap, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::super::raster;
use super::super::sprite::Ink;
use super::BodyLook;

/// The width, in pixels, of a turning circle's orientation line.
const ORIENTATION_WIDTH: f32 = 1.5;

impl BodyLook {
    /// Draws a turning circle's orientation: a line from its centre at pixel (x, y) to
    /// its rim in the direction of its body x axis, turned by `theta` (the world's
    /// counter-clockwise, so (cos θ, -sin θ) in pixels).
    pub fn draw_orientation(&self, pixmap: &mut Pixmap, x: f32, y: f32, theta: f64) {
        let Some(r) = self.marker else {
            return;
        };
        let (s, c) = theta.sin_cos();
        let mut pb = PathBuilder::new();
        pb.move_to(x, y);
        pb.line_to(x + r * c as f32, y - r * s as f32);
        let Some(line) = pb.finish() else {
            return;
        };
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        paint.set_color(self.edge);
        let stroke = Stroke {
            width: ORIENTATION_WIDTH,
            line_cap: LineCap::Round,
            ..Stroke::default()
        };
        pixmap.stroke_path(&line, &paint, &stroke, Transform::identity(), None);
    }

    /// Returns the pixels, as columns x0..x1 and rows y0..y1 in (x0, y0, x1, y1), that
    /// a turning circle's orientation line at `theta` may change with the circle's
    /// centre at pixel (x, y): the box of its ends grown by the round caps' half-width,
    /// a pixel to spare, rounded out. `None` for other looks.
    pub fn orientation_box(&self, x: f32, y: f32, theta: f64) -> Option<(i64, i64, i64, i64)> {
        let r = self.marker?;
        let (s, c) = theta.sin_cos();
        let tip = (x + r * c as f32, y - r * s as f32);
        let grow = 0.5 * ORIENTATION_WIDTH + 1.0;
        Some((
            (x.min(tip.0) - grow).floor() as i64,
            (y.min(tip.1) - grow).floor() as i64,
            (x.max(tip.0) + grow).ceil() as i64,
            (y.max(tip.1) + grow).ceil() as i64,
        ))
    }

    /// Draws a turning circle's orientation as [`BodyLook::draw_orientation`] does,
    /// through the scan converter: the stroke's polygon (the line with round caps, each
    /// cap's half circle cut into six 30° chords, within 0.026 pixel of the arc) filled
    /// with tiny-skia's coverage, without its set-up per path. It differs from the path
    /// only where a chord and tiny-skia's curve put a crossing on different sides of a
    /// quarter-pixel sample (`tests/integration/every_scene.rs` bounds it). Used where
    /// the disc is a stamped sprite: a pile of rolling discs draws thousands a frame.
    pub fn draw_orientation_fast(&self, pixmap: &mut Pixmap, x: f32, y: f32, theta: f64) {
        let Some(r) = self.marker else {
            return;
        };
        let (s, c) = theta.sin_cos();
        // The line's ends as the path takes them, in f32.
        let tip = (x + r * c as f32, y - r * s as f32);
        let mut outline = Vec::with_capacity(14);
        raster::capsule(
            (f64::from(x), f64::from(y)),
            (f64::from(tip.0), f64::from(tip.1)),
            f64::from(ORIENTATION_WIDTH) / 2.0,
            &mut outline,
        );
        raster::fill_convex(pixmap, &outline, Ink::of(self.edge));
    }
}
