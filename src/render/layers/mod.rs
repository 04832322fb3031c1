//! The figure layers of a frame: axes, fields, curves, traces, the legend and the HUD.
//!
//! [`Overlay::new`] decides the one transform of a render. With an `[axes]` table the
//! view is laid out as a [`Chart`] (ticks at 1-2-5 values, labels, titles, legend) and
//! the camera is taken from the chart's plot area, exactly; without one the camera fits
//! the view into the whole image as before, and a bare chart with the camera's own
//! transform draws the layers. Either way bodies, fields and curves go through one map.
//!
//! What never changes (axes, static fields, exact and numerical curves) is drawn once
//! into the static layer by [`Overlay::draw_static`]; [`Overlay::draw_frame`] adds what
//! does (traces, fields and curves that read t, the legend over the data, the HUD).

mod curves;
mod fields;
mod hud;

use glam::DVec2;
use tiny_skia::{Color, IntRect, Pixmap};

pub use curves::{solution_points, TraceRecorder};

use super::camera::Camera;
use super::plot::{Axis, Chart, ChartSpec, Corner, Dash, LegendEntry, LineStyle, Theme};
use super::FrameView;
use crate::history::PointHistory;
use crate::scene::layers::{Aspect, CurveKind, LegendCorner, LineDash};
use crate::scene::{Rgba, Scene, View};

/// The size figures are designed at; larger images scale text and lines up.
const DESIGN_SIZE: (f64, f64) = (800.0, 600.0);

/// Everything a render draws besides the background and the bodies.
pub struct Overlay {
    chart: Chart,
    /// Whether the chart's furniture (frame, ticks, labels) is drawn.
    axes: bool,
    /// The pixels the legend may touch (x0, y0, x1, y1), when it is drawn: its box,
    /// grown by 2 pixels for the anti-aliasing of its border, which lies on the box's
    /// edge.
    legend: Option<(i64, i64, i64, i64)>,
    /// Whether the margins outside the plot area are restored after the bodies are
    /// drawn, so bodies never cover the axes.
    restore_margins: bool,
    layers: crate::scene::Layers,
    /// Lengths in pixels are multiplied by this, for images larger than 800×600.
    scale: f32,
    hud: bool,
    frame_count: u64,
    fps: f64,
}

impl Overlay {
    /// Lays out the axes (when the scene has them) and returns the overlay with the
    /// camera that bodies and layers share.
    pub fn new(scene: &Scene) -> (Overlay, Camera) {
        let r = &scene.render;
        let scale = figure_scale(r.width, r.height);
        let layers = &scene.layers;
        let axes = layers.axes.as_ref().and_then(|a| {
            let spec = chart_spec(scene, a, scale);
            layout(spec, a.aspect, r.view, r.width, r.height)
        });
        let (chart, camera, has_axes) = match axes {
            Some(chart) => {
                let camera = camera_of(&chart, r.width, r.height)
                    .unwrap_or_else(|| Camera::fit(r.view, r.width, r.height));
                (chart, camera, true)
            }
            None => {
                let camera = Camera::fit(r.view, r.width, r.height);
                let (x, y) = camera.coefficients();
                let map = super::plot::DataToPixel::affine(x, y);
                let chart = match Chart::bare(r.width, r.height, map) {
                    Ok(chart) => chart,
                    Err(_) => unreachable!("the scene validator keeps image sides at least 1"),
                };
                (chart, camera, false)
            }
        };
        let legend = has_axes
            && layers.axes.as_ref().is_some_and(|a| a.legend.is_some())
            && !chart.spec().legend.is_empty();
        let legend = chart.legend_box().filter(|_| legend).map(|r| {
            (
                r.left().floor() as i64 - 2,
                r.top().floor() as i64 - 2,
                r.right().ceil() as i64 + 2,
                r.bottom().ceil() as i64 + 2,
            )
        });
        let bodies_drawn = r.show_bodies && !scene.bodies.is_empty();
        let overlay = Overlay {
            chart,
            axes: has_axes,
            legend,
            restore_margins: has_axes && bodies_drawn,
            layers: layers.clone(),
            scale,
            hud: r.hud,
            frame_count: r.frame_count,
            fps: r.fps,
        };
        (overlay, camera)
    }

    /// The chart that lays out the axes (a bare one without `[axes]`).
    pub fn chart(&self) -> &Chart {
        &self.chart
    }

    /// Returns true when frames draw something over the static layer other than
    /// restoring its margins: a legend, the HUD or a layer that changes in time.
    pub fn draws_over_frames(&self) -> bool {
        self.legend.is_some() || self.hud || self.layers.has_dynamic_layers()
    }

    /// The pixels that bodies may show, when the margins around them are wiped after
    /// the bodies are drawn (a frame with axes): everything outside is the static
    /// layer's in every frame.
    pub fn body_area(&self) -> Option<IntRect> {
        self.restore_margins.then(|| self.chart.inner_area())
    }

    /// Draws the axes and every layer that does not change between frames.
    pub fn draw_static(&self, pixmap: &mut Pixmap) {
        if self.axes {
            self.chart.draw_static(pixmap);
        }
        self.draw_layers(pixmap, 0.0, false, None);
    }

    /// Draws what changes from frame to frame over a copy of the static layer.
    pub fn draw_frame(&self, pixmap: &mut Pixmap, static_layer: &Pixmap, frame: &FrameView<'_>) {
        if self.restore_margins {
            restore_outside(pixmap, static_layer, self.chart.inner_area());
        }
        self.draw_layers(pixmap, frame.t, true, frame.traces);
        self.draw_legend(pixmap);
        self.draw_hud(pixmap, frame);
    }

    /// Returns true when all that frames draw over the static layer, besides restoring
    /// its margins, is the legend and the HUD: boxes of known extent, which the damage
    /// can hold.
    pub fn draws_only_boxes(&self) -> bool {
        !self.layers.has_dynamic_layers()
    }

    /// Draws the legend, when the scene has one, and returns the pixels it may have
    /// touched (x0, y0, x1, y1), for the damage.
    pub fn draw_legend(&self, pixmap: &mut Pixmap) -> Option<(i64, i64, i64, i64)> {
        let touched = self.legend?;
        self.chart.draw_legend(pixmap);
        Some(touched)
    }

    /// Draws the HUD, when the scene shows it, and returns the pixels it may have
    /// touched (x0, y0, x1, y1), for the damage.
    pub fn draw_hud(
        &self,
        pixmap: &mut Pixmap,
        frame: &FrameView<'_>,
    ) -> Option<(i64, i64, i64, i64)> {
        self.hud.then(|| {
            hud::draw(
                pixmap,
                self.chart.inner_area(),
                frame.t,
                frame.index,
                self.frame_count,
                self.fps,
                self.scale,
            )
        })
    }

    /// Draws the static (`dynamic == false`) or the dynamic layers at time `t`.
    fn draw_layers(
        &self,
        pixmap: &mut Pixmap,
        t: f64,
        dynamic: bool,
        traces: Option<&PointHistory>,
    ) {
        let layers = &self.layers;
        for field in &layers.fields {
            if field.slots.time_dependent == dynamic {
                fields::draw(&self.chart, pixmap, field, t, self.scale);
            }
        }
        let mut trace_index = 0;
        for curve in &layers.curves {
            if let CurveKind::Trace { .. } = curve.kind {
                if dynamic {
                    if let Some(history) = traces {
                        curves::draw_trace(
                            &self.chart,
                            pixmap,
                            curve,
                            history,
                            trace_index,
                            self.scale,
                        );
                    }
                }
                trace_index += 1;
            } else if curve.slots.time_dependent == dynamic {
                curves::draw(&self.chart, pixmap, curve, t, self.scale);
            }
        }
    }
}

/// Returns the factor by which lengths in pixels grow for an image larger than the
/// 800×600 figures are designed at, like a higher dpi in matplotlib: min(W/800, H/600),
/// kept between 0.75 and 4.
pub fn figure_scale(width: u32, height: u32) -> f32 {
    let f = (f64::from(width) / DESIGN_SIZE.0).min(f64::from(height) / DESIGN_SIZE.1);
    f.clamp(0.75, 4.0) as f32
}

/// Converts a scene colour to a tiny-skia colour.
fn color(c: Rgba) -> Color {
    let [r, g, b, a] = c.0;
    Color::from_rgba8(r, g, b, a)
}

/// Converts a scene dash to a chart dash.
fn dash(d: LineDash) -> Dash {
    match d {
        LineDash::Solid => Dash::Solid,
        LineDash::Dashed => Dash::Dashed,
        LineDash::Dotted => Dash::Dotted,
        LineDash::DashDot => Dash::DashDot,
    }
}

/// Builds the chart's description from the `[axes]` table and the layers' labels.
fn chart_spec(scene: &Scene, a: &crate::scene::layers::AxesSettings, scale: f32) -> ChartSpec {
    let view = scene.render.view;
    let mut theme = Theme::default().scaled(scale);
    theme.background = None;
    theme.grid = a.grid;
    theme.legend_corner = match a.legend {
        Some(LegendCorner::TopLeft) => Corner::TopLeft,
        Some(LegendCorner::BottomRight) => Corner::BottomRight,
        Some(LegendCorner::BottomLeft) => Corner::BottomLeft,
        Some(LegendCorner::TopRight) | None => Corner::TopRight,
    };
    let mut spec = ChartSpec::new(
        Axis::linear(view.min.x, view.max.x, a.x_label.clone()),
        Axis::linear(view.min.y, view.max.y, a.y_label.clone()),
    )
    .title(a.title.clone())
    .theme(theme);
    for field in &scene.layers.fields {
        if let Some(label) = &field.label {
            let style = LineStyle::solid(color(field.color), field.width as f32 * scale);
            spec.legend.push(LegendEntry::line(style, label.clone()));
        }
    }
    for curve in &scene.layers.curves {
        if let Some(label) = &curve.label {
            let style = LineStyle::solid(color(curve.color), curve.width as f32 * scale)
                .dashed(dash(curve.dash));
            spec.legend.push(LegendEntry::line(style, label.clone()));
        }
    }
    spec
}

/// Lays out the chart. With square units, the axis ranges grow about the view's centre
/// until one world unit takes as many pixels on both axes (matplotlib's
/// `set_aspect("equal", adjustable="datalim")`); tick labels change the plot area a
/// little, so this repeats until the plot area stops moving.
fn layout(spec: ChartSpec, aspect: Aspect, view: View, width: u32, height: u32) -> Option<Chart> {
    let mut chart = Chart::new(spec.clone(), width, height).ok()?;
    if aspect == Aspect::Auto {
        return Some(chart);
    }
    let centre = 0.5 * (view.min + view.max);
    let extent = view.max - view.min;
    for _ in 0..6 {
        let ((_, _, sx), (_, _, sy)) = chart.transform().linear_coefficients()?;
        // Pixel spans of the axes: the view's extent times pixels per unit.
        let span = DVec2::new(
            sx.abs() * (chart.spec().x.max - chart.spec().x.min),
            sy.abs() * (chart.spec().y.max - chart.spec().y.min),
        );
        // s = min(W / view width, H / view height); each half-range is then span/(2s).
        let s = (span.x / extent.x).min(span.y / extent.y);
        let half = span / (2.0 * s);
        let mut next = spec.clone();
        next.x.min = centre.x - half.x;
        next.x.max = centre.x + half.x;
        next.y.min = centre.y - half.y;
        next.y.max = centre.y + half.y;
        let previous = chart.plot_area();
        chart = Chart::new(next, width, height).ok()?;
        if chart.plot_area() == previous {
            break;
        }
    }
    Some(chart)
}

/// The camera with exactly the chart's transform.
fn camera_of(chart: &Chart, width: u32, height: u32) -> Option<Camera> {
    let (x, y) = chart.transform().linear_coefficients()?;
    Some(Camera::affine(x, y, width, height))
}

/// Copies every pixel outside `inside` from `source` into `pixmap`.
pub(crate) fn restore_outside(pixmap: &mut Pixmap, source: &Pixmap, inside: IntRect) {
    let width = pixmap.width() as usize;
    let height = pixmap.height() as usize;
    if (source.width() as usize, source.height() as usize) != (width, height) {
        return;
    }
    let stride = 4 * width;
    let (l, r) = (
        inside.left().clamp(0, width as i32) as usize,
        inside.right().clamp(0, width as i32) as usize,
    );
    let (t, b) = (
        inside.top().clamp(0, height as i32) as usize,
        inside.bottom().clamp(0, height as i32) as usize,
    );
    let from = source.data();
    let to = pixmap.data_mut();
    for row in 0..height {
        let line = row * stride..(row + 1) * stride;
        if row < t || row >= b {
            to[line.clone()].copy_from_slice(&from[line]);
        } else {
            let start = row * stride;
            to[start..start + 4 * l].copy_from_slice(&from[start..start + 4 * l]);
            to[start + 4 * r..start + stride].copy_from_slice(&from[start + 4 * r..start + stride]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse;
    use std::path::Path;

    fn scene(text: &str) -> Scene {
        match parse(Path::new("test.toml"), text) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn equal_aspect_axes_give_square_units_and_contain_the_view() {
        let s = scene(
            "[render]\nview = { min = [-1.0, -3.0], max = [10.0, 3.0] }\n[axes]\ntitle = \"t\"\n[[body]]\nmass = 1\n",
        );
        let (overlay, camera) = Overlay::new(&s);
        let scale = camera.scale_xy();
        assert!(((scale.x - scale.y) / scale.x).abs() < 1e-3, "{scale:?}");
        let spec = overlay.chart().spec();
        assert!(spec.x.min <= -1.0 + 1e-9 && spec.x.max >= 10.0 - 1e-9);
        assert!(spec.y.min <= -3.0 + 1e-9 && spec.y.max >= 3.0 - 1e-9);
        // The camera and the chart are one transform.
        let p = DVec2::new(2.5, 1.25);
        let (cx, cy) = camera.to_pixel_f64(p);
        let (mx, my) = overlay.chart().transform().apply_f64(p.x, p.y);
        assert_eq!((cx, cy), (mx, my));
    }

    #[test]
    fn auto_aspect_axes_fill_the_plot_area_with_the_view() {
        let s = scene(
            "[render]\nview = { min = [0.0, -0.5], max = [5.0, 3.5] }\n[axes]\nx_label = \"t\"\n",
        );
        let (overlay, camera) = Overlay::new(&s);
        let spec = overlay.chart().spec();
        assert_eq!(
            (spec.x.min, spec.x.max, spec.y.min, spec.y.max),
            (0.0, 5.0, -0.5, 3.5)
        );
        let scale = camera.scale_xy();
        assert!((scale.x / scale.y - 1.0).abs() > 0.05, "{scale:?}");
    }

    #[test]
    fn margins_are_restored_from_the_static_layer() {
        let mut a = Pixmap::new(10, 10).expect("pixmap");
        let mut b = Pixmap::new(10, 10).expect("pixmap");
        a.fill(Color::BLACK);
        b.fill(Color::WHITE);
        let inside = IntRect::from_ltrb(2, 3, 8, 7).expect("rect");
        restore_outside(&mut a, &b, inside);
        for y in 0..10 {
            for x in 0..10 {
                let p = a.pixel(x, y).expect("pixel");
                let inner = (2..8).contains(&x) && (3..7).contains(&y);
                assert_eq!(p.red() == 0, inner, "({x}, {y})");
            }
        }
    }
}
