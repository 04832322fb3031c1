//! Field layers: slope segments and arrows on a grid of points across the plot area.
//!
//! Directions are data-space vectors pushed through the chart's transform
//! ([`super::super::plot::DataToPixel::direction`]), so a segment of slope 2 looks like
//! slope 2 against the axes whatever the view's aspect ratio. (matplotlib's `quiver`
//! draws arrow angles in screen space unless told `angles="xy"`; this is that pitfall
//! avoided.)

use tiny_skia::{Color, Pixmap};

use super::super::plot::{ArrowStyle, Chart, LineStyle};
use super::color;
use crate::scene::layers::{ArrowLength, Field, FieldFunction};

/// One grid point's value: where, which data-space direction, and its magnitude.
struct Sample {
    at: (f64, f64),
    direction: (f64, f64),
    magnitude: f64,
}

/// Draws a field at time `t`.
pub fn draw(chart: &Chart, pixmap: &mut Pixmap, field: &Field, t: f64, scale: f32) {
    let spec = chart.spec();
    let (x0, x1, y0, y1) = (spec.x.min, spec.x.max, spec.y.min, spec.y.max);
    let [nx, ny] = field.grid;
    let inner = chart.inner_area();
    // A cell's smaller side in pixels sets the segment or arrow length.
    let cell_px =
        (f64::from(inner.width()) / f64::from(nx)).min(f64::from(inner.height()) / f64::from(ny));
    let length = field.size * cell_px;
    let samples = sample(field, t, (x0, x1, y0, y1));
    let largest = samples.iter().map(|s| s.magnitude).fold(0.0, f64::max);
    let smallest = samples
        .iter()
        .map(|s| s.magnitude)
        .fold(f64::INFINITY, f64::min);
    let base = color(field.color);
    let width = (field.width as f32 * scale).max(0.1);
    let paint = |m: f64| -> Color {
        if field.color_by_magnitude && largest > smallest {
            viridis((m - smallest) / (largest - smallest))
        } else {
            base
        }
    };
    match &field.function {
        FieldFunction::Slope(_) => {
            if field.color_by_magnitude {
                for s in &samples {
                    let style = LineStyle::solid(paint(s.magnitude), width);
                    let slope = s.direction.1 / s.direction.0;
                    chart.slope_segments(pixmap, [(s.at.0, s.at.1, slope)], length as f32, &style);
                }
            } else {
                let style = LineStyle::solid(base, width);
                let segments = samples
                    .iter()
                    .map(|s| (s.at.0, s.at.1, s.direction.1 / s.direction.0));
                chart.slope_segments(pixmap, segments, length as f32, &style);
            }
        }
        FieldFunction::Direction(_) | FieldFunction::Vector(..) => {
            for s in &samples {
                // Normalised: every arrow `length` long. Scaled: the longest arrow is
                // `length` long and the others shrink with their magnitude.
                let px = match field.length {
                    ArrowLength::Normalised => length,
                    ArrowLength::Scaled if largest > 0.0 => length * s.magnitude / largest,
                    ArrowLength::Scaled => 0.0,
                };
                if px < 0.5 {
                    continue;
                }
                let style = ArrowStyle::new(paint(s.magnitude), width);
                chart.arrow_px(pixmap, s.at, s.direction, px as f32, &style);
            }
        }
    }
}

/// Evaluates the field at the centres of an nx × ny grid of cells over the ranges,
/// skipping points where it is not finite.
fn sample(field: &Field, t: f64, (x0, x1, y0, y1): (f64, f64, f64, f64)) -> Vec<Sample> {
    let [nx, ny] = field.grid;
    let mut values = field.slots.values.clone();
    if let Some(slot) = field.slots.time {
        values[slot] = t;
    }
    let mut out = Vec::with_capacity((nx * ny) as usize);
    for j in 0..ny {
        // Cell centres: y_j = y0 + (j + 1/2)·(y1 - y0)/ny, and likewise for x.
        let y = y0 + (f64::from(j) + 0.5) * (y1 - y0) / f64::from(ny);
        for i in 0..nx {
            let x = x0 + (f64::from(i) + 0.5) * (x1 - x0) / f64::from(nx);
            values[0] = x;
            values[1] = y;
            let (direction, magnitude) = match &field.function {
                FieldFunction::Slope(f) => {
                    let slope = f.eval(&values);
                    ((1.0, slope), slope.abs())
                }
                FieldFunction::Direction(f) => {
                    let slope = f.eval(&values);
                    ((1.0, slope), 1.0f64.hypot(slope))
                }
                FieldFunction::Vector(fx, fy) => {
                    let v = (fx.eval(&values), fy.eval(&values));
                    (v, v.0.hypot(v.1))
                }
            };
            // A slope field draws an infinite slope as a vertical segment; arrows need
            // finite vectors.
            let keep = match field.function {
                FieldFunction::Slope(_) => !direction.1.is_nan(),
                _ => direction.0.is_finite() && direction.1.is_finite(),
            };
            if keep {
                out.push(Sample {
                    at: (x, y),
                    direction,
                    magnitude,
                });
            }
        }
    }
    out
}

/// matplotlib's "viridis" colour map at 0 ≤ u ≤ 1, interpolated linearly between nine
/// of its colours.
pub fn viridis(u: f64) -> Color {
    const STOPS: [(u8, u8, u8); 9] = [
        (0x44, 0x01, 0x54),
        (0x47, 0x2c, 0x7a),
        (0x3b, 0x51, 0x8b),
        (0x2c, 0x71, 0x8e),
        (0x21, 0x90, 0x8d),
        (0x27, 0xad, 0x81),
        (0x5c, 0xc8, 0x63),
        (0xaa, 0xdc, 0x32),
        (0xfd, 0xe7, 0x25),
    ];
    let u = if u.is_finite() {
        u.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = u * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (f64::from(a) + f * (f64::from(b) - f64::from(a))).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    Color::from_rgba8(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2), 255)
}
