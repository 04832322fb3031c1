//! Drawing a comparison: each compared run's bodies as coloured rings (ghosts) over the
//! main run, and a strip along the bottom plotting each integrator's error against time.

use tiny_skia::{Color, IntRect, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::camera::Camera;
use super::plot::{palette, Axis, Chart, ChartSpec, LegendEntry, LineStyle};
use crate::compare::CompareFrame;

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
/// compares leaves room for it at the bottom of its view.
pub fn draw(pixmap: &mut Pixmap, camera: &Camera, frame: &CompareFrame, duration: f64) {
    let (width, height) = (pixmap.width(), pixmap.height());
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    let stroke = Stroke {
        width: 2.0,
        ..Stroke::default()
    };
    for (i, ghost) in frame.ghosts.iter().enumerate() {
        let Some(pos) = &ghost.pos else { continue };
        paint.set_color(run_color(frame, i));
        for p in pos {
            let (x, y) = camera.to_pixel(*p);
            // Rings outside the image, or at positions too far to draw safely, are skipped.
            if !(x > -10.0 && y > -10.0 && x < width as f32 + 10.0 && y < height as f32 + 10.0) {
                continue;
            }
            if let Some(ring) = PathBuilder::from_circle(x, y, 7.0) {
                pixmap.stroke_path(&ring, &paint, &stroke, Transform::identity(), None);
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
