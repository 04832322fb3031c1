//! Curve layers: exact curves y = f(x) (and families of them), numerical solutions of
//! dy/dx = f(x, y) with their step points, and traces of the simulation's state.

use std::sync::Arc;

use glam::DVec2;
use tiny_skia::{Color, Pixmap};

use super::super::plot::{Chart, LineStyle, MarkerShape, MarkerStyle};
use super::{color, dash};
use crate::history::{HistoryWriter, PointHistory};
use crate::scene::layers::{Curve, CurveKind, BODY_QUANTITIES, MAX_SOLUTION_STEPS};
use crate::scene::Scene;

/// Draws an exact or numerical curve at time `t`.
pub fn draw(chart: &Chart, pixmap: &mut Pixmap, curve: &Curve, t: f64, scale: f32) {
    let style = line_style(curve, scale);
    let mut values = curve.slots.values.clone();
    if let Some(slot) = curve.slots.time {
        values[slot] = t;
    }
    match &curve.kind {
        CurveKind::Exact { y, family, samples } => {
            let (x0, x1) = (chart.spec().x.min, chart.spec().x.max);
            let one = [0.0];
            let members: Vec<(Option<usize>, f64)> = match family {
                Some((slot, list)) => list.iter().map(|v| (Some(*slot), *v)).collect(),
                None => one.iter().map(|v| (None, *v)).collect(),
            };
            let n = *samples;
            for (slot, member) in members {
                if let Some(slot) = slot {
                    values[slot] = member;
                }
                let points = (0..n).map(|i| {
                    // x_i = x0 + i·(x1 - x0)/(n - 1), from the left edge to the right.
                    let x = x0 + f64::from(i) * (x1 - x0) / f64::from(n - 1);
                    values[0] = x;
                    (x, y.eval(&values))
                });
                let points: Vec<(f64, f64)> = points.collect();
                chart.polyline(pixmap, points, &style);
            }
        }
        CurveKind::Solution {
            f,
            start,
            h,
            method,
            end,
            markers,
        } => {
            let points = solution_points(f, &mut values, *start, *h, *method, *end);
            chart.polyline(pixmap, points.iter().copied(), &style);
            if *markers {
                let size = (2.5 * curve.width as f32 + 2.0) * scale;
                chart.markers(
                    pixmap,
                    points.iter().copied(),
                    &MarkerStyle::new(MarkerShape::Circle, size, color(curve.color)),
                );
            }
        }
        CurveKind::Trace { .. } => {}
    }
}

/// Returns the step points (x_n, y_n) of the numerical solution of dy/dx = f(x, y)
/// from `start`; y_{n+1} is exactly what the method's step gives, e.g. for Euler
/// y_{n+1} = y_n + h·f(x_n, y_n).
pub fn solution_points(
    f: &crate::scene::expr::Expr,
    values: &mut [f64],
    start: DVec2,
    h: f64,
    method: crate::sim::ScalarMethod,
    end: f64,
) -> Vec<(f64, f64)> {
    method.solve(
        |x, y| {
            values[0] = x;
            values[1] = y;
            f.eval(values)
        },
        (start.x, start.y),
        h,
        end,
        MAX_SOLUTION_STEPS,
    )
}

/// Draws a trace: its points at frames 0 ..= k as a line, and a marker at frame k.
pub fn draw_trace(
    chart: &Chart,
    pixmap: &mut Pixmap,
    curve: &Curve,
    history: &PointHistory,
    index: usize,
    scale: f32,
) {
    let points: Vec<(f64, f64)> = history
        .iter()
        .filter_map(|frame| frame.get(index).map(|p| (p.x, p.y)))
        .collect();
    chart.polyline(pixmap, points.iter().copied(), &line_style(curve, scale));
    if let Some(last) = points.last() {
        let mut marker = MarkerStyle::new(MarkerShape::Circle, 9.0 * scale, color(curve.color));
        marker.edge = Some((Color::WHITE, 1.5 * scale));
        chart.markers(pixmap, [*last], &marker);
    }
}

fn line_style(curve: &Curve, scale: f32) -> LineStyle {
    LineStyle::solid(color(curve.color), (curve.width as f32 * scale).max(0.1))
        .dashed(dash(curve.dash))
}

/// Evaluates a scene's trace curves at every frame, on the simulation's thread, and
/// keeps one point per trace per frame so far. It is the one writer of its history, so
/// it is not `Clone`.
#[derive(Debug)]
pub struct TraceRecorder {
    /// The traces' x and y expressions with their slot values.
    traces: Vec<(Curve, Vec<f64>)>,
    history: HistoryWriter<Arc<[DVec2]>>,
}

impl TraceRecorder {
    /// Returns a recorder for the scene's traces, or `None` when it has none.
    pub fn new(scene: &Scene) -> Option<TraceRecorder> {
        let traces: Vec<(Curve, Vec<f64>)> = scene
            .layers
            .curves
            .iter()
            .filter(|c| matches!(c.kind, CurveKind::Trace { .. }))
            .map(|c| (c.clone(), c.slots.values.clone()))
            .collect();
        (!traces.is_empty()).then_some(TraceRecorder {
            traces,
            history: HistoryWriter::new(),
        })
    }

    /// Records the traces' points for the state (t, positions, velocities) of the next
    /// frame. A trace reads slot 0 as t and slots 1 + 5i .. 6 + 5i as body i's x, y, vx,
    /// vy and speed.
    pub fn record(&mut self, t: f64, pos: &[DVec2], vel: &[DVec2]) {
        let n = BODY_QUANTITIES.len();
        let points: Vec<DVec2> = self
            .traces
            .iter_mut()
            .map(|(curve, values)| {
                values[0] = t;
                for (i, (p, v)) in pos.iter().zip(vel).enumerate() {
                    let base = 1 + n * i;
                    if base + n <= values.len() {
                        values[base..base + n].copy_from_slice(&[p.x, p.y, v.x, v.y, v.length()]);
                    }
                }
                match &curve.kind {
                    CurveKind::Trace { x, y } => DVec2::new(x.eval(values), y.eval(values)),
                    _ => DVec2::NAN,
                }
            })
            .collect();
        self.history.push(Arc::from(points));
    }

    /// The points of every frame recorded so far; a clone of it is a frame's snapshot,
    /// which costs the same at every frame.
    pub fn history(&self) -> &PointHistory {
        self.history.history()
    }
}
