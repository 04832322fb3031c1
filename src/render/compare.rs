//! Drawing a comparison: each compared run's bodies as coloured rings (ghosts) over the
//! main run, and a strip along the bottom plotting each integrator's error against time.

use std::sync::{Arc, Mutex};

use tiny_skia::{Color, IntRect, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::camera::Camera;
use super::picture::PictureSheet;
use super::plot::{palette, Axis, Chart, ChartSpec, LegendEntry, LineStyle};
use super::SPRITE_MIN_BODIES;
use crate::compare::CompareFrame;

/// A ghost's ring: its radius and stroke width, in pixels.
const RING_RADIUS: f32 = 7.0;
const RING_WIDTH: f32 = 2.0;

/// The ghosts' rings drawn once per colour at every sub-pixel phase
/// ([`PictureSheet`]), for compared runs of many bodies: a ring stroked as a tiny-skia
/// path costs some 15 µs, a thousand a frame for each compared run. A picture laid at
/// a position snapped to 1/8 pixel differs from the path at the exact position as
/// every sprite does (tested).
#[derive(Debug, Default)]
pub struct GhostRings {
    /// The sheets made so far, by colour (RGBA).
    sheets: Mutex<Vec<([u8; 4], Arc<PictureSheet>)>>,
}

impl GhostRings {
    /// Returns the sheet of rings in `color`, drawing it the first time.
    fn sheet(&self, color: Color) -> Option<Arc<PictureSheet>> {
        let c = color.to_color_u8();
        let key = [c.red(), c.green(), c.blue(), c.alpha()];
        let mut sheets = self.sheets.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, sheet)) = sheets.iter().find(|(k, _)| *k == key) {
            return Some(Arc::clone(sheet));
        }
        let sheet = PictureSheet::of_drawing(RING_RADIUS + RING_WIDTH, |pixmap, x, y| {
            ring(pixmap, x, y, color)
        })?;
        sheets.push((key, Arc::clone(&sheet)));
        Some(sheet)
    }
}

/// Strokes a ghost's ring centred at pixel (x, y) in `color`.
fn ring(pixmap: &mut Pixmap, x: f32, y: f32, color: Color) {
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    paint.set_color(color);
    let stroke = Stroke {
        width: RING_WIDTH,
        ..Stroke::default()
    };
    if let Some(ring) = PathBuilder::from_circle(x, y, RING_RADIUS) {
        pixmap.stroke_path(&ring, &paint, &stroke, Transform::identity(), None);
    }
}

/// Returns the colour of compared run `i`: the exact path black, integrators from
/// matplotlib's cycle, skipping its first colour, which bodies use by default.
fn run_color(frame: &CompareFrame, i: usize) -> Color {
    if frame.ghosts[i].label == "exact" {
        Color::BLACK
    } else {
        palette(i + 1)
    }
}

/// Draws the ghosts and the error strip of one frame. The strip covers the bottom
/// quarter of the image (when the image is at least 240 pixels tall), so a scene that
/// compares leaves room for it at the bottom of its view. With `rings`, a run of at
/// least [`SPRITE_MIN_BODIES`] ghosts is stamped from pictures of its ring; otherwise
/// each ring is a tiny-skia path.
pub fn draw(
    pixmap: &mut Pixmap,
    camera: &Camera,
    frame: &CompareFrame,
    duration: f64,
    rings: Option<&GhostRings>,
) {
    let (width, height) = (pixmap.width(), pixmap.height());
    for (i, ghost) in frame.ghosts.iter().enumerate() {
        let Some(pos) = &ghost.pos else { continue };
        let color = run_color(frame, i);
        let sheet = rings
            .filter(|_| pos.len() >= SPRITE_MIN_BODIES)
            .and_then(|r| r.sheet(color));
        for p in pos {
            let (x, y) = camera.to_pixel(*p);
            // Rings outside the image, or at positions too far to draw safely, are skipped.
            if !(x > -10.0 && y > -10.0 && x < width as f32 + 10.0 && y < height as f32 + 10.0) {
                continue;
            }
            match &sheet {
                Some(sheet) => sheet.stamp(pixmap, x, y),
                None => ring(pixmap, x, y, color),
            }
        }
    }
    draw_error_strip(pixmap, frame, duration);
}

/// Draws the strip: error (log scale) against time, one line per integrator.
fn draw_error_strip(pixmap: &mut Pixmap, frame: &CompareFrame, duration: f64) {
    let (width, height) = (pixmap.width(), pixmap.height());
    if height < 240 || width < 320 || frame.error_labels.is_empty() {
        return;
    }
    let strip = height / 4;
    let Some(region) = IntRect::from_xywh(0, (height - strip) as i32, width, strip) else {
        return;
    };
    // The y range covers every positive error so far, padded by half a decade.
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for (_, row) in frame.errors.iter() {
        for e in row.iter().filter(|e| e.is_finite() && **e > 0.0) {
            lo = lo.min(*e);
            hi = hi.max(*e);
        }
    }
    if !(lo.is_finite() && hi > 0.0) {
        (lo, hi) = (1e-16, 1.0);
    }
    let (lo, hi) = (lo / 3.0, (hi * 3.0).max(lo * 30.0));
    let mut spec = ChartSpec::new(
        Axis::linear(0.0, duration, "time t"),
        Axis::log10(lo, hi, format!("error vs {}", frame.reference)),
    );
    spec.theme = spec.theme.scaled(0.8);
    spec.theme.background = Some(Color::WHITE);
    let colors: Vec<Color> = frame
        .error_labels
        .iter()
        .map(|label| {
            let i = frame
                .ghosts
                .iter()
                .position(|g| &g.label == label)
                .unwrap_or(0);
            run_color(frame, i)
        })
        .collect();
    for (label, color) in frame.error_labels.iter().zip(&colors) {
        spec = spec.legend_entry(LegendEntry::line(
            LineStyle::solid(*color, 1.5),
            label.clone(),
        ));
    }
    let Ok(chart) = Chart::in_region(spec, width, height, region) else {
        return;
    };
    chart.draw_static(pixmap);
    for (j, color) in colors.iter().enumerate() {
        let points = frame
            .errors
            .iter()
            .filter_map(|(t, row)| row.get(j).map(|e| (*t, *e)))
            .filter(|(_, e)| e.is_finite() && *e > 0.0);
        chart.polyline(pixmap, points, &LineStyle::solid(*color, 1.5));
    }
    chart.draw_legend(pixmap);
}
