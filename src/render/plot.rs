//! A reusable 2-D chart, like a small matplotlib `Axes`.
//!
//! A [`ChartSpec`] says what the chart shows (data ranges, scales, titles, legend, theme);
//! [`Chart::new`] or [`Chart::in_region`] lays it out once: margins are computed from the
//! real sizes of the tick labels and titles, ticks are chosen for the room the plot area
//! has, and a clip mask for the plot area is built. After that:
//!
//! - [`Chart::draw_static`] draws the background, grid, frame, ticks, tick labels and
//!   titles. They never change between frames, so draw them once (or take
//!   [`Chart::static_pixmap`]) and copy that pixmap at the start of every frame.
//! - The data helpers ([`Chart::polyline`], [`Chart::markers`], [`Chart::arrow`],
//!   [`Chart::slope_segments`], [`Chart::fill_rect`], ...) take data coordinates in `f64`,
//!   map them with [`DataToPixel`], and draw clipped to the inside of the frame.
//! - [`Chart::draw_legend`] draws the legend box last, on top of the data.
//!
//! Geometry is computed in `f64` from data and handed to tiny-skia in `f32`. The frame,
//! ticks and grid lines are snapped to pixel centres so 1-pixel lines stay crisp.
//! Defaults match matplotlib's at 100 dpi: 10 pt text is 14 px, ticks are 3.5 px long,
//! data lines are 1.5 px wide.

use tiny_skia::{
    Color, FillRule, IntRect, LineCap, LineJoin, Mask, Paint, Path, PathBuilder, Pixmap, Rect,
    Stroke, StrokeDash, Transform,
};

use super::text::{Font, HAlign, TextStyle, VAlign};
use super::ticks::{linear_ticks, log10_ticks, AxisTicks, LogLabelStyle};

/// How data values are spread along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Scale {
    /// Equal data steps take equal pixel steps.
    #[default]
    Linear,
    /// Equal ratios take equal pixel steps; only positive values can be shown.
    Log10,
}

/// One axis: its data range, scale and title.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The data value at the left (x) or bottom (y) edge of the plot area.
    pub min: f64,
    /// The data value at the right (x) or top (y) edge of the plot area.
    pub max: f64,
    /// Linear or logarithmic.
    pub scale: Scale,
    /// The axis title, units included, e.g. "time t (s)". Empty for none.
    pub title: String,
    /// How decades are labelled on a log axis.
    pub log_labels: LogLabelStyle,
}

impl Axis {
    /// A linear axis from `min` to `max`.
    pub fn linear(min: f64, max: f64, title: impl Into<String>) -> Self {
        Self {
            min,
            max,
            scale: Scale::Linear,
            title: title.into(),
            log_labels: LogLabelStyle::default(),
        }
    }

    /// A base-10 logarithmic axis from `min` to `max` (both positive).
    pub fn log10(min: f64, max: f64, title: impl Into<String>) -> Self {
        Self {
            scale: Scale::Log10,
            ..Self::linear(min, max, title)
        }
    }

    fn ticks(&self, target: usize) -> AxisTicks {
        match self.scale {
            Scale::Linear => linear_ticks(self.min, self.max, target),
            Scale::Log10 => log10_ticks(self.min, self.max, target, self.log_labels),
        }
    }
}

/// Which way tick marks point from the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TickDirection {
    /// Into the plot area.
    #[default]
    In,
    /// Away from the plot area, into the margin.
    Out,
}

/// A corner of the plot area, for placing the legend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Corner {
    /// Top right, the default.
    #[default]
    TopRight,
    /// Top left.
    TopLeft,
    /// Bottom right.
    BottomRight,
    /// Bottom left.
    BottomLeft,
}

/// Sizes and colours of the chart's furniture.
#[derive(Clone, Debug, PartialEq)]
pub struct Theme {
    /// Fill of the whole chart region; `None` leaves the pixmap as it is.
    pub background: Option<Color>,
    /// Fill of the plot area, drawn over `background`; `None` for none.
    pub plot_background: Option<Color>,
    /// Colour of the frame and the tick marks.
    pub frame_color: Color,
    /// Colour of all text.
    pub text_color: Color,
    /// Colour of the grid lines.
    pub grid_color: Color,
    /// Whether grid lines are drawn at the major ticks.
    pub grid: bool,
    /// Size of tick labels, in pixels per em.
    pub tick_label_px: f32,
    /// Size of axis titles, in pixels per em.
    pub axis_title_px: f32,
    /// Size of the chart title, in pixels per em.
    pub title_px: f32,
    /// Size of legend labels, in pixels per em.
    pub legend_px: f32,
    /// Length of a major tick mark, in pixels.
    pub tick_length: f32,
    /// Length of a minor tick mark, in pixels.
    pub minor_tick_length: f32,
    /// Width of tick marks and grid lines, in pixels.
    pub tick_width: f32,
    /// Width of the frame line, in pixels.
    pub frame_width: f32,
    /// Which way tick marks point.
    pub tick_direction: TickDirection,
    /// Empty space around the whole chart, in pixels.
    pub padding: f32,
    /// Gap between a tick mark (or the frame) and its label, in pixels.
    pub label_gap: f32,
    /// Gap between tick labels and the axis title, in pixels.
    pub title_gap: f32,
    /// Smallest distance between neighbouring tick labels, in pixels.
    pub min_label_spacing: f32,
    /// Where the legend sits.
    pub legend_corner: Corner,
}

impl Default for Theme {
    /// matplotlib's defaults at 100 dpi: 10 pt labels, 12 pt title, 3.5 pt ticks.
    fn default() -> Self {
        Self {
            background: Some(Color::WHITE),
            plot_background: None,
            frame_color: Color::BLACK,
            text_color: Color::BLACK,
            grid_color: Color::from_rgba8(0xb0, 0xb0, 0xb0, 0x99),
            grid: false,
            tick_label_px: 14.0,
            axis_title_px: 14.0,
            title_px: 17.0,
            legend_px: 14.0,
            tick_length: 3.5,
            minor_tick_length: 2.0,
            tick_width: 1.0,
            frame_width: 1.0,
            tick_direction: TickDirection::In,
            padding: 8.0,
            label_gap: 7.0,
            title_gap: 7.0,
            min_label_spacing: 12.0,
            legend_corner: Corner::TopRight,
        }
    }
}

impl Theme {
    /// Returns this theme with every length multiplied by `factor`, for larger or smaller
    /// images (for example `2.0` for a 1600×1200 figure).
    pub fn scaled(&self, factor: f32) -> Theme {
        Theme {
            tick_label_px: self.tick_label_px * factor,
            axis_title_px: self.axis_title_px * factor,
            title_px: self.title_px * factor,
            legend_px: self.legend_px * factor,
            tick_length: self.tick_length * factor,
            minor_tick_length: self.minor_tick_length * factor,
            tick_width: self.tick_width * factor,
            frame_width: self.frame_width * factor,
            padding: self.padding * factor,
            label_gap: self.label_gap * factor,
            title_gap: self.title_gap * factor,
            min_label_spacing: self.min_label_spacing * factor,
            ..self.clone()
        }
    }
}

/// A dash pattern, scaled by the line width as matplotlib does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Dash {
    /// A continuous line.
    #[default]
    Solid,
    /// Long dashes.
    Dashed,
    /// Dots.
    Dotted,
    /// Alternating dashes and dots.
    DashDot,
}

impl Dash {
    /// The on/off lengths in pixels for a line `width` wide, or `None` when solid.
    fn intervals(self, width: f32) -> Option<Vec<f32>> {
        let w = width.max(1.0);
        let unit: &[f32] = match self {
            Dash::Solid => return None,
            Dash::Dashed => &[3.7, 1.6],
            Dash::Dotted => &[1.0, 1.65],
            Dash::DashDot => &[6.4, 1.6, 1.0, 1.6],
        };
        Some(unit.iter().map(|u| u * w).collect())
    }
}

/// How a line is stroked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineStyle {
    /// Stroke colour.
    pub color: Color,
    /// Width in pixels.
    pub width: f32,
    /// Dash pattern.
    pub dash: Dash,
}

impl LineStyle {
    /// A solid line.
    pub fn solid(color: Color, width: f32) -> Self {
        Self {
            color,
            width,
            dash: Dash::Solid,
        }
    }

    /// Returns this style with another dash pattern.
    pub fn dashed(mut self, dash: Dash) -> Self {
        self.dash = dash;
        self
    }

    fn stroke(&self) -> Stroke {
        Stroke {
            width: self.width,
            line_cap: LineCap::Butt,
            line_join: LineJoin::Round,
            dash: self
                .dash
                .intervals(self.width)
                .and_then(|d| StrokeDash::new(d, 0.0)),
            ..Stroke::default()
        }
    }
}

/// The shape of a marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MarkerShape {
    /// A disc.
    #[default]
    Circle,
    /// An axis-aligned square.
    Square,
    /// A square standing on one corner.
    Diamond,
    /// A triangle pointing up.
    Triangle,
}

/// How point markers are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkerStyle {
    /// Shape.
    pub shape: MarkerShape,
    /// Diameter (circle) or side (square) in pixels.
    pub size: f32,
    /// Fill colour.
    pub fill: Color,
    /// Outline colour and width, or `None` for no outline.
    pub edge: Option<(Color, f32)>,
}

impl MarkerStyle {
    /// A filled marker without an outline.
    pub fn new(shape: MarkerShape, size: f32, fill: Color) -> Self {
        Self {
            shape,
            size,
            fill,
            edge: None,
        }
    }
}

/// How arrows are drawn: a stroked shaft and a filled triangular head.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArrowStyle {
    /// Colour of shaft and head.
    pub color: Color,
    /// Width of the shaft in pixels.
    pub width: f32,
    /// Length of the head along the arrow, in pixels.
    pub head_length: f32,
    /// Width of the head across the arrow, in pixels.
    pub head_width: f32,
}

impl ArrowStyle {
    /// An arrow with a head sized for a shaft `width` wide.
    pub fn new(color: Color, width: f32) -> Self {
        Self {
            color,
            width,
            head_length: 4.0 + 3.0 * width,
            head_width: 3.0 + 2.5 * width,
        }
    }
}

/// What a legend entry shows beside its label.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LegendSample {
    /// A short stretch of line.
    Line(LineStyle),
    /// One marker.
    Marker(MarkerStyle),
    /// A filled square, for areas and heatmaps.
    Patch(Color),
    /// A short stretch of line with one marker in its middle, for series drawn as both.
    LineMarker(LineStyle, MarkerStyle),
}

/// One row of the legend.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// What the row shows.
    pub sample: LegendSample,
    /// The text beside it.
    pub label: String,
}

impl LegendEntry {
    /// A row with a line sample.
    pub fn line(style: LineStyle, label: impl Into<String>) -> Self {
        Self {
            sample: LegendSample::Line(style),
            label: label.into(),
        }
    }

    /// A row with a marker sample.
    pub fn marker(style: MarkerStyle, label: impl Into<String>) -> Self {
        Self {
            sample: LegendSample::Marker(style),
            label: label.into(),
        }
    }

    /// A row with a line sample that carries a marker in its middle.
    pub fn line_marker(line: LineStyle, marker: MarkerStyle, label: impl Into<String>) -> Self {
        Self {
            sample: LegendSample::LineMarker(line, marker),
            label: label.into(),
        }
    }
}

/// Everything a chart shows apart from the data.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartSpec {
    /// The horizontal axis.
    pub x: Axis,
    /// The vertical axis.
    pub y: Axis,
    /// A title above the plot area, or empty for none.
    pub title: String,
    /// Legend rows, top to bottom; empty for no legend.
    pub legend: Vec<LegendEntry>,
    /// Sizes and colours.
    pub theme: Theme,
}

impl ChartSpec {
    /// A chart of `x` against `y` with the default theme, no title and no legend.
    pub fn new(x: Axis, y: Axis) -> Self {
        Self {
            x,
            y,
            title: String::new(),
            legend: Vec::new(),
            theme: Theme::default(),
        }
    }

    /// Returns this spec with a title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = title.into();
        self
    }

    /// Returns this spec with grid lines on or off.
    pub fn grid(mut self, on: bool) -> Self {
        self.theme.grid = on;
        self
    }

    /// Returns this spec with one more legend row.
    pub fn legend_entry(mut self, entry: LegendEntry) -> Self {
        self.legend.push(entry);
        self
    }

    /// Returns this spec with another theme.
    pub fn theme(mut self, theme: Theme) -> Self {
        self.theme = theme;
        self
    }
}

/// Why a chart cannot be laid out.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ChartError {
    /// An axis range is empty, reversed or not finite.
    #[error("the {axis} axis range [{min}, {max}] must be finite with min < max")]
    BadRange {
        /// "x" or "y".
        axis: &'static str,
        /// The range's start.
        min: f64,
        /// The range's end.
        max: f64,
    },
    /// A log axis range includes zero or negative values.
    #[error("the {axis} axis is logarithmic, so its range [{min}, {max}] must be positive")]
    LogRangeNotPositive {
        /// "x" or "y".
        axis: &'static str,
        /// The range's start.
        min: f64,
        /// The range's end.
        max: f64,
    },
    /// The region is too small for the labels and titles.
    #[error("a {width}×{height} pixel region leaves no room for the plot area")]
    TooSmall {
        /// Region width.
        width: u32,
        /// Region height.
        height: u32,
    },
    /// The region does not lie inside the canvas.
    #[error("the region {region:?} does not fit in a {width}×{height} canvas")]
    RegionOutsideCanvas {
        /// The requested region as (x, y, width, height).
        region: (i32, i32, u32, u32),
        /// Canvas width.
        width: u32,
        /// Canvas height.
        height: u32,
    },
}

/// Maps one axis from data values to pixel positions.
#[derive(Clone, Copy, Debug, PartialEq)]
struct AxisMap {
    scale: Scale,
    /// The range's ends in scaled units (the data or its log10).
    u0: f64,
    u1: f64,
    /// Where those ends land, in pixels.
    p0: f64,
    p1: f64,
    /// Pixels per scaled unit, (p1 - p0)/(u1 - u0), computed once.
    ppu: f64,
}

impl AxisMap {
    fn new(axis: &Axis, p0: f64, p1: f64) -> Self {
        let scaled = |v: f64| match axis.scale {
            Scale::Linear => v,
            Scale::Log10 => v.log10(),
        };
        let (u0, u1) = (scaled(axis.min), scaled(axis.max));
        Self {
            scale: axis.scale,
            u0,
            u1,
            p0,
            p1,
            ppu: (p1 - p0) / (u1 - u0),
        }
    }

    /// A linear axis through pixel `p0` at the value `u0`, with `ppu` pixels per unit.
    fn affine(u0: f64, p0: f64, ppu: f64) -> Self {
        Self {
            scale: Scale::Linear,
            u0,
            u1: u0 + 1.0,
            p0,
            p1: p0 + ppu,
            ppu,
        }
    }

    fn pixels_per_unit(&self) -> f64 {
        self.ppu
    }

    /// The pixel position of `v`; NaN when `v` cannot be shown (not positive on a log axis).
    fn map(&self, v: f64) -> f64 {
        let u = match self.scale {
            Scale::Linear => v,
            Scale::Log10 if v > 0.0 => v.log10(),
            Scale::Log10 => f64::NAN,
        };
        self.p0 + (u - self.u0) * self.pixels_per_unit()
    }

    /// The data value at pixel position `p`.
    fn unmap(&self, p: f64) -> f64 {
        let u = self.u0 + (p - self.p0) / self.pixels_per_unit();
        match self.scale {
            Scale::Linear => u,
            Scale::Log10 => 10f64.powf(u),
        }
    }

    /// Pixels moved per data unit at `v`: the derivative of [`AxisMap::map`].
    fn derivative(&self, v: f64) -> f64 {
        match self.scale {
            Scale::Linear => self.pixels_per_unit(),
            Scale::Log10 => self.pixels_per_unit() / (v * std::f64::consts::LN_10),
        }
    }
}

/// One linear axis as `(v0, p0, ppu)`: the pixel is p = p0 + (v - v0)·ppu.
pub type AxisCoefficients = (f64, f64, f64);

/// The data → pixel transform of a chart: f64 data in, f32 pixels out, y pointing down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DataToPixel {
    x: AxisMap,
    y: AxisMap,
}

impl DataToPixel {
    /// The linear transform p = p0 + (v - v0)·ppu on each axis, from `(v0, p0, ppu)` for
    /// x and for y (a y axis pointing up has a negative `ppu`).
    pub fn affine(x: (f64, f64, f64), y: (f64, f64, f64)) -> Self {
        Self {
            x: AxisMap::affine(x.0, x.1, x.2),
            y: AxisMap::affine(y.0, y.1, y.2),
        }
    }

    /// The coefficients `(v0, p0, ppu)` of x and y when both axes are linear, such that
    /// p = p0 + (v - v0)·ppu reproduces [`DataToPixel::apply_f64`] exactly.
    pub fn linear_coefficients(&self) -> Option<(AxisCoefficients, AxisCoefficients)> {
        let linear = self.x.scale == Scale::Linear && self.y.scale == Scale::Linear;
        linear.then_some((
            (self.x.u0, self.x.p0, self.x.ppu),
            (self.y.u0, self.y.p0, self.y.ppu),
        ))
    }

    /// The pixel position of the data point `(x, y)`. A coordinate that a log axis cannot
    /// show (zero or negative) maps to NaN.
    pub fn apply(&self, x: f64, y: f64) -> (f32, f32) {
        let (px, py) = self.apply_f64(x, y);
        (px as f32, py as f32)
    }

    /// Like [`DataToPixel::apply`], without rounding to f32.
    pub fn apply_f64(&self, x: f64, y: f64) -> (f64, f64) {
        (self.x.map(x), self.y.map(y))
    }

    /// The data point at pixel position `(px, py)`.
    pub fn invert(&self, px: f32, py: f32) -> (f64, f64) {
        (self.x.unmap(f64::from(px)), self.y.unmap(f64::from(py)))
    }

    /// The unit pixel direction of the data-space direction `(dx, dy)` at the data point
    /// `(x, y)`. The x and y scales may differ (and on log axes vary from point to point),
    /// so the direction is pushed through the transform's derivative there. Returns `None`
    /// for a zero or non-finite direction.
    pub fn direction(&self, x: f64, y: f64, dx: f64, dy: f64) -> Option<(f64, f64)> {
        let px = dx * self.x.derivative(x);
        let py = dy * self.y.derivative(y);
        let length = px.hypot(py);
        (length.is_finite() && length > 0.0).then(|| (px / length, py / length))
    }
}

/// A laid-out chart. See the module documentation for how it is used.
#[derive(Clone, Debug)]
pub struct Chart {
    spec: ChartSpec,
    canvas: (u32, u32),
    region: IntRect,
    /// The plot area in pixels: the frame's outer edges.
    plot: IntRect,
    /// Width of the frame, rounded up to whole pixels for the clip.
    frame_px: u32,
    x_ticks: AxisTicks,
    y_ticks: AxisTicks,
    map: DataToPixel,
    /// The inside of the frame; `None` when the plot area is the whole canvas.
    clip: Option<Mask>,
}

impl Chart {
    /// Lays out a chart that fills a `width × height` pixmap.
    pub fn new(spec: ChartSpec, width: u32, height: u32) -> Result<Chart, ChartError> {
        let region = IntRect::from_xywh(0, 0, width, height)
            .ok_or(ChartError::TooSmall { width, height })?;
        Chart::in_region(spec, width, height, region)
    }

    /// Lays out a chart inside `region` of a `canvas_width × canvas_height` pixmap, so
    /// several charts can share one image.
    pub fn in_region(
        spec: ChartSpec,
        canvas_width: u32,
        canvas_height: u32,
        region: IntRect,
    ) -> Result<Chart, ChartError> {
        check_axis("x", &spec.x)?;
        check_axis("y", &spec.y)?;
        let fits = region.x() >= 0
            && region.y() >= 0
            && region.right() as i64 <= i64::from(canvas_width)
            && region.bottom() as i64 <= i64::from(canvas_height);
        if !fits {
            return Err(ChartError::RegionOutsideCanvas {
                region: (region.x(), region.y(), region.width(), region.height()),
                width: canvas_width,
                height: canvas_height,
            });
        }
        let too_small = ChartError::TooSmall {
            width: region.width(),
            height: region.height(),
        };
        let layout = Layout::compute(&spec, region).ok_or(too_small.clone())?;
        let frame_px = spec.theme.frame_width.ceil().max(0.0) as u32;
        let half = f64::from(spec.theme.frame_width) / 2.0;
        let plot = layout.plot;
        let map = DataToPixel {
            x: AxisMap::new(
                &spec.x,
                f64::from(plot.left()) + half,
                f64::from(plot.right()) - half,
            ),
            y: AxisMap::new(
                &spec.y,
                f64::from(plot.bottom()) - half,
                f64::from(plot.top()) + half,
            ),
        };
        let mut clip = Mask::new(canvas_width, canvas_height).ok_or(too_small.clone())?;
        let inside = IntRect::from_ltrb(
            plot.left() + frame_px as i32,
            plot.top() + frame_px as i32,
            plot.right() - frame_px as i32,
            plot.bottom() - frame_px as i32,
        )
        .ok_or(too_small)?;
        clip.fill_path(
            &PathBuilder::from_rect(inside.to_rect()),
            FillRule::Winding,
            false,
            Transform::identity(),
        );
        Ok(Chart {
            spec,
            canvas: (canvas_width, canvas_height),
            region,
            plot,
            frame_px,
            x_ticks: layout.x_ticks,
            y_ticks: layout.y_ticks,
            map,
            clip: Some(clip),
        })
    }

    /// A chart without furniture whose plot area is the whole `width × height` canvas
    /// and whose data → pixel transform is `map`: the data helpers then draw a world
    /// scene's layers with the camera's own transform, clipped only by the canvas.
    pub fn bare(width: u32, height: u32, map: DataToPixel) -> Result<Chart, ChartError> {
        let plot = IntRect::from_xywh(0, 0, width, height)
            .ok_or(ChartError::TooSmall { width, height })?;
        let (lo, hi) = (
            map.invert(0.0, height as f32),
            map.invert(width as f32, 0.0),
        );
        let mut spec = ChartSpec::new(Axis::linear(lo.0, hi.0, ""), Axis::linear(lo.1, hi.1, ""));
        spec.theme.frame_width = 0.0;
        Ok(Chart {
            spec,
            canvas: (width, height),
            region: plot,
            plot,
            frame_px: 0,
            x_ticks: AxisTicks::default(),
            y_ticks: AxisTicks::default(),
            map,
            clip: None,
        })
    }

    /// The inside of the frame, where data is drawn, as (left, top, right, bottom).
    pub fn inner_area(&self) -> IntRect {
        let f = self.frame_px as i32;
        IntRect::from_ltrb(
            self.plot.left() + f,
            self.plot.top() + f,
            self.plot.right() - f,
            self.plot.bottom() - f,
        )
        .unwrap_or(self.plot)
    }

    /// What the chart shows.
    pub fn spec(&self) -> &ChartSpec {
        &self.spec
    }

    /// The plot area in canvas pixels: the outer edges of the frame.
    pub fn plot_area(&self) -> IntRect {
        self.plot
    }

    /// The chart's region in canvas pixels.
    pub fn region(&self) -> IntRect {
        self.region
    }

    /// The ticks on the x axis.
    pub fn x_ticks(&self) -> &AxisTicks {
        &self.x_ticks
    }

    /// The ticks on the y axis.
    pub fn y_ticks(&self) -> &AxisTicks {
        &self.y_ticks
    }

    /// The data → pixel transform.
    pub fn transform(&self) -> &DataToPixel {
        &self.map
    }

    /// The pixel position of the data point `(x, y)`; shorthand for `transform().apply`.
    pub fn to_px(&self, x: f64, y: f64) -> (f32, f32) {
        self.map.apply(x, y)
    }

    /// A new canvas-sized pixmap with the static part drawn, to copy for every frame.
    pub fn static_pixmap(&self) -> Pixmap {
        let mut pixmap = Pixmap::new(self.canvas.0, self.canvas.1)
            .expect("the canvas size was checked when the chart was laid out");
        self.draw_static(&mut pixmap);
        pixmap
    }

    /// Draws the background, grid, frame, ticks, tick labels and titles.
    pub fn draw_static(&self, pixmap: &mut Pixmap) {
        let theme = &self.spec.theme;
        if let Some(color) = theme.background {
            fill_rect(pixmap, self.region.to_rect(), color, None);
        }
        if let Some(color) = theme.plot_background {
            fill_rect(pixmap, self.plot.to_rect(), color, None);
        }
        if theme.grid {
            self.draw_grid(pixmap);
        }
        self.draw_ticks(pixmap);
        self.draw_frame(pixmap);
        self.draw_labels(pixmap);
    }

    /// Draws the legend box in its corner of the plot area; call it after the data.
    pub fn draw_legend(&self, pixmap: &mut Pixmap) {
        let Some(legend) = LegendLayout::compute(&self.spec, self.plot, self.frame_px) else {
            return;
        };
        let theme = &self.spec.theme;
        let font = Font::dejavu_sans();
        let frame = legend.frame;
        fill_rect(
            pixmap,
            frame,
            Color::from_rgba8(255, 255, 255, 0xcc),
            self.clip.as_ref(),
        );
        let border = PathBuilder::from_rect(
            Rect::from_ltrb(
                frame.left() + 0.5,
                frame.top() + 0.5,
                frame.right() - 0.5,
                frame.bottom() - 0.5,
            )
            .unwrap_or(frame),
        );
        stroke_path(
            pixmap,
            &border,
            &LineStyle::solid(Color::from_rgba8(0xcc, 0xcc, 0xcc, 0xff), 1.0),
            None,
        );
        let text = TextStyle::new(theme.legend_px, theme.text_color);
        for (entry, row) in self.spec.legend.iter().zip(&legend.rows) {
            let mid = row.baseline - 0.5 * font.cap_height(theme.legend_px);
            draw_sample(
                pixmap,
                &entry.sample,
                row.sample_left,
                row.sample_right,
                mid,
            );
            font.draw(pixmap, &entry.label, row.text_left, row.baseline, &text);
        }
    }

    /// Draws a polyline through data points, clipped to the plot area. A point that cannot
    /// be shown (non-finite, or not positive on a log axis) breaks the line.
    pub fn polyline(
        &self,
        pixmap: &mut Pixmap,
        points: impl IntoIterator<Item = (f64, f64)>,
        style: &LineStyle,
    ) {
        let bounds = self.expanded_plot(f64::from(style.width) + 2.0);
        let mut builder = PathBuilder::new();
        let mut previous: Option<(f64, f64)> = None;
        let mut pen: Option<(f64, f64)> = None;
        for (x, y) in points {
            let p = self.map.apply_f64(x, y);
            if !(p.0.is_finite() && p.1.is_finite()) {
                previous = None;
                continue;
            }
            if let Some(q) = previous {
                if let Some((a, b)) = clip_segment(q, p, bounds) {
                    if pen != Some(a) {
                        builder.move_to(a.0 as f32, a.1 as f32);
                    }
                    builder.line_to(b.0 as f32, b.1 as f32);
                    pen = Some(b);
                }
            }
            previous = Some(p);
        }
        if let Some(path) = builder.finish() {
            stroke_path(pixmap, &path, style, self.mask_for(pixmap));
        }
    }

    /// Draws one marker at each data point, clipped to the plot area.
    pub fn markers(
        &self,
        pixmap: &mut Pixmap,
        points: impl IntoIterator<Item = (f64, f64)>,
        style: &MarkerStyle,
    ) {
        let bounds = self.expanded_plot(f64::from(style.size));
        let mut builder = PathBuilder::new();
        for (x, y) in points {
            let (px, py) = self.map.apply_f64(x, y);
            if inside(bounds, (px, py)) {
                push_marker(&mut builder, style.shape, px as f32, py as f32, style.size);
            }
        }
        if let Some(path) = builder.finish() {
            fill_marker_path(pixmap, &path, style, self.mask_for(pixmap));
        }
    }

    /// Draws an arrow from the data point `from` to `from + delta`, clipped to the plot
    /// area. Both ends are mapped, so the arrow points the right way on screen however
    /// differently the axes are scaled.
    pub fn arrow(
        &self,
        pixmap: &mut Pixmap,
        from: (f64, f64),
        delta: (f64, f64),
        style: &ArrowStyle,
    ) {
        let a = self.map.apply_f64(from.0, from.1);
        let b = self.map.apply_f64(from.0 + delta.0, from.1 + delta.1);
        self.arrow_between(pixmap, a, b, style);
    }

    /// Draws an arrow `length_px` pixels long from the data point `from`, pointing along
    /// the data-space direction `direction` (as in a direction field, where only the
    /// direction matters). Draws nothing for a zero direction.
    pub fn arrow_px(
        &self,
        pixmap: &mut Pixmap,
        from: (f64, f64),
        direction: (f64, f64),
        length_px: f32,
        style: &ArrowStyle,
    ) {
        let Some((ux, uy)) = self.map.direction(from.0, from.1, direction.0, direction.1) else {
            return;
        };
        let a = self.map.apply_f64(from.0, from.1);
        let length = f64::from(length_px);
        let b = (a.0 + ux * length, a.1 + uy * length);
        self.arrow_between(pixmap, a, b, style);
    }

    /// Draws a short segment `length_px` long centred on each `(x, y, slope)`, with the
    /// slope `dy/dx` in data units: a slope field. All segments form one path, so
    /// hundreds draw in one call.
    pub fn slope_segments(
        &self,
        pixmap: &mut Pixmap,
        segments: impl IntoIterator<Item = (f64, f64, f64)>,
        length_px: f32,
        style: &LineStyle,
    ) {
        let half = 0.5 * f64::from(length_px);
        let width = 0.5 * f64::from(style.width);
        let bounds = self.expanded_plot(half + f64::from(style.width));
        let mut builder = PathBuilder::new();
        for (x, y, slope) in segments {
            let centre = self.map.apply_f64(x, y);
            if !inside(bounds, centre) {
                continue;
            }
            // A vertical segment for an infinite slope, like dx = 0.
            let direction = if slope.is_finite() {
                self.map.direction(x, y, 1.0, slope)
            } else if slope.is_nan() {
                None
            } else {
                self.map.direction(x, y, 0.0, 1.0)
            };
            let Some((ux, uy)) = direction else { continue };
            if style.dash == Dash::Solid {
                // A solid segment is a thin rectangle; filling it directly skips the
                // general stroker, which is most of the cost for hundreds of segments.
                let (nx, ny) = (-uy * width, ux * width);
                let (ax, ay) = (centre.0 - ux * half, centre.1 - uy * half);
                let (bx, by) = (centre.0 + ux * half, centre.1 + uy * half);
                builder.move_to((ax + nx) as f32, (ay + ny) as f32);
                builder.line_to((bx + nx) as f32, (by + ny) as f32);
                builder.line_to((bx - nx) as f32, (by - ny) as f32);
                builder.line_to((ax - nx) as f32, (ay - ny) as f32);
                builder.close();
            } else {
                builder.move_to((centre.0 - ux * half) as f32, (centre.1 - uy * half) as f32);
                builder.line_to((centre.0 + ux * half) as f32, (centre.1 + uy * half) as f32);
            }
        }
        if let Some(path) = builder.finish() {
            if style.dash == Dash::Solid {
                fill_path(pixmap, &path, style.color, self.mask_for(pixmap));
            } else {
                stroke_path(pixmap, &path, style, self.mask_for(pixmap));
            }
        }
    }

    /// Fills the data rectangle with corners `(x0, y0)` and `(x1, y1)`, clipped to the plot
    /// area. Edges are rounded to whole pixels without anti-aliasing, so neighbouring
    /// cells of a heatmap meet without seams or overlaps.
    pub fn fill_rect(
        &self,
        pixmap: &mut Pixmap,
        corner0: (f64, f64),
        corner1: (f64, f64),
        color: Color,
    ) {
        let a = self.map.apply_f64(corner0.0, corner0.1);
        let b = self.map.apply_f64(corner1.0, corner1.1);
        let bounds = self.expanded_plot(1.0);
        let clamp_x = |v: f64| v.clamp(bounds.0, bounds.2).round() as f32;
        let clamp_y = |v: f64| v.clamp(bounds.1, bounds.3).round() as f32;
        if !(a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite()) {
            return;
        }
        let (l, r) = (clamp_x(a.0.min(b.0)), clamp_x(a.0.max(b.0)));
        let (t, bot) = (clamp_y(a.1.min(b.1)), clamp_y(a.1.max(b.1)));
        if let Some(rect) = Rect::from_ltrb(l, t, r, bot) {
            let mut paint = Paint::default();
            paint.set_color(color);
            paint.anti_alias = false;
            pixmap.fill_rect(rect, &paint, Transform::identity(), self.mask_for(pixmap));
        }
    }

    /// Fills a grid of cells: cell `(i, j)` spans `x_edges[i]..x_edges[i + 1]` and
    /// `y_edges[j]..y_edges[j + 1]` and gets `color(i, j)`.
    pub fn fill_cells(
        &self,
        pixmap: &mut Pixmap,
        x_edges: &[f64],
        y_edges: &[f64],
        mut color: impl FnMut(usize, usize) -> Color,
    ) {
        for (j, y) in y_edges.windows(2).enumerate() {
            for (i, x) in x_edges.windows(2).enumerate() {
                self.fill_rect(pixmap, (x[0], y[0]), (x[1], y[1]), color(i, j));
            }
        }
    }

    /// The clip mask, when it fits `pixmap`; a pixmap of another size is drawn unclipped.
    fn mask_for(&self, pixmap: &Pixmap) -> Option<&Mask> {
        let fits = (pixmap.width(), pixmap.height()) == self.canvas;
        debug_assert!(fits, "draw into a pixmap of the chart's canvas size");
        if fits {
            self.clip.as_ref()
        } else {
            None
        }
    }

    /// The plot area grown by `margin` pixels, as (left, top, right, bottom).
    fn expanded_plot(&self, margin: f64) -> (f64, f64, f64, f64) {
        (
            f64::from(self.plot.left()) - margin,
            f64::from(self.plot.top()) - margin,
            f64::from(self.plot.right()) + margin,
            f64::from(self.plot.bottom()) + margin,
        )
    }

    fn arrow_between(&self, pixmap: &mut Pixmap, a: (f64, f64), b: (f64, f64), style: &ArrowStyle) {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let length = dx.hypot(dy);
        if !(length.is_finite() && length > 0.0) {
            return;
        }
        let bounds = self.expanded_plot(length + f64::from(style.head_length));
        if !inside(bounds, a) {
            return;
        }
        let (ux, uy) = (dx / length, dy / length);
        // A head longer than two thirds of the arrow shrinks with it.
        let shrink = (length / (1.5 * f64::from(style.head_length))).min(1.0);
        let head_length = f64::from(style.head_length) * shrink;
        let head_half = 0.5 * f64::from(style.head_width) * shrink;
        let base = (b.0 - ux * head_length, b.1 - uy * head_length);
        let mask = self.mask_for(pixmap);
        // The shaft stops inside the head so its square end cannot show beside the tip.
        let shaft_end = (b.0 - ux * head_length * 0.5, b.1 - uy * head_length * 0.5);
        let mut shaft = PathBuilder::new();
        shaft.move_to(a.0 as f32, a.1 as f32);
        shaft.line_to(shaft_end.0 as f32, shaft_end.1 as f32);
        if let Some(path) = shaft.finish() {
            stroke_path(
                pixmap,
                &path,
                &LineStyle::solid(style.color, style.width),
                mask,
            );
        }
        let mut head = PathBuilder::new();
        head.move_to(b.0 as f32, b.1 as f32);
        head.line_to(
            (base.0 - uy * head_half) as f32,
            (base.1 + ux * head_half) as f32,
        );
        head.line_to(
            (base.0 + uy * head_half) as f32,
            (base.1 - ux * head_half) as f32,
        );
        head.close();
        if let Some(path) = head.finish() {
            fill_path(pixmap, &path, style.color, mask);
        }
    }

    fn draw_grid(&self, pixmap: &mut Pixmap) {
        let theme = &self.spec.theme;
        let style = LineStyle::solid(theme.grid_color, theme.tick_width);
        let inner = self.frame_px as f32 + 0.5;
        let (l, t, r, b) = self.plot_ltrb();
        let mut builder = PathBuilder::new();
        for tick in &self.x_ticks.major {
            let x = snap(self.map.x.map(tick.value) as f32, theme.tick_width);
            if x > l + inner && x < r - inner {
                builder.move_to(x, t);
                builder.line_to(x, b);
            }
        }
        for tick in &self.y_ticks.major {
            let y = snap(self.map.y.map(tick.value) as f32, theme.tick_width);
            if y > t + inner && y < b - inner {
                builder.move_to(l, y);
                builder.line_to(r, y);
            }
        }
        if let Some(path) = builder.finish() {
            stroke_path(pixmap, &path, &style, self.clip.as_ref());
        }
    }

    fn draw_ticks(&self, pixmap: &mut Pixmap) {
        let theme = &self.spec.theme;
        let sign = match theme.tick_direction {
            TickDirection::In => -1.0,
            TickDirection::Out => 1.0,
        };
        let half_frame = 0.5 * theme.frame_width;
        let (l, _, _, b) = self.plot_ltrb();
        let (x_axis, y_axis) = (b - half_frame, l + half_frame);
        let mut builder = PathBuilder::new();
        let mut tick = |value_px: f32, length: f32, horizontal_axis: bool| {
            if !value_px.is_finite() {
                return;
            }
            let p = snap(value_px, theme.tick_width);
            if horizontal_axis {
                builder.move_to(p, x_axis);
                builder.line_to(p, x_axis + sign * length);
            } else {
                builder.move_to(y_axis, p);
                builder.line_to(y_axis - sign * length, p);
            }
        };
        for t in &self.x_ticks.major {
            tick(self.map.x.map(t.value) as f32, theme.tick_length, true);
        }
        for &v in &self.x_ticks.minor {
            tick(self.map.x.map(v) as f32, theme.minor_tick_length, true);
        }
        for t in &self.y_ticks.major {
            tick(self.map.y.map(t.value) as f32, theme.tick_length, false);
        }
        for &v in &self.y_ticks.minor {
            tick(self.map.y.map(v) as f32, theme.minor_tick_length, false);
        }
        if let Some(path) = builder.finish() {
            let style = LineStyle::solid(theme.frame_color, theme.tick_width);
            stroke_path(pixmap, &path, &style, None);
        }
    }

    fn draw_frame(&self, pixmap: &mut Pixmap) {
        let theme = &self.spec.theme;
        let half = 0.5 * theme.frame_width;
        let (l, t, r, b) = self.plot_ltrb();
        if let Some(rect) = Rect::from_ltrb(l + half, t + half, r - half, b - half) {
            let style = LineStyle::solid(theme.frame_color, theme.frame_width);
            let mut builder = PathBuilder::new();
            builder.push_rect(rect);
            if let Some(path) = builder.finish() {
                let stroke = Stroke {
                    line_join: LineJoin::Miter,
                    ..style.stroke()
                };
                let mut paint = Paint::default();
                paint.set_color(style.color);
                paint.anti_alias = true;
                pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
            }
        }
    }

    fn draw_labels(&self, pixmap: &mut Pixmap) {
        let theme = &self.spec.theme;
        let font = Font::dejavu_sans();
        let (l, t, r, b) = self.plot_ltrb();
        let out = tick_overhang(theme);
        let x_row = label_row(font, &self.x_ticks, theme.tick_label_px);
        let x_baseline = self.x_label_baseline();
        let tick_style = TextStyle::new(theme.tick_label_px, theme.text_color);
        for tick in &self.x_ticks.major {
            let x = self.map.x.map(tick.value) as f32;
            let style = tick_style.anchor(HAlign::Center, VAlign::Baseline);
            font.draw(pixmap, &tick.label, x, x_baseline, &style);
        }
        // Y tick labels end `label_gap` left of the ticks, centred on them.
        let y_label_right = l - out - theme.label_gap;
        for tick in &self.y_ticks.major {
            let y = self.map.y.map(tick.value) as f32;
            let style = tick_style.anchor(HAlign::Right, VAlign::Middle);
            font.draw(pixmap, &tick.label, y_label_right, y.round(), &style);
        }
        let title_cap = font.cap_height(theme.axis_title_px);
        let centre_x = 0.5 * (l + r);
        let centre_y = 0.5 * (t + b);
        if !self.spec.x.title.is_empty() {
            let y = x_baseline + x_row.1 + theme.title_gap + title_cap;
            let style = TextStyle::new(theme.axis_title_px, theme.text_color)
                .anchor(HAlign::Center, VAlign::Baseline);
            font.draw(pixmap, &self.spec.x.title, centre_x, y.round(), &style);
        }
        if !self.spec.y.title.is_empty() {
            // Rotated a quarter turn, the title's tops face left, so its baseline is its
            // right-hand edge, one cap height in from the padding.
            let x = self.region.x() as f32 + theme.padding + title_cap;
            let style = TextStyle::new(theme.axis_title_px, theme.text_color)
                .anchor(HAlign::Center, VAlign::Baseline)
                .rotated(90.0);
            font.draw(pixmap, &self.spec.y.title, x.round(), centre_y, &style);
        }
        if !self.spec.title.is_empty() {
            let y = self.region.y() as f32 + theme.padding + font.cap_height(theme.title_px);
            let style = TextStyle::new(theme.title_px, theme.text_color)
                .anchor(HAlign::Center, VAlign::Baseline);
            font.draw(pixmap, &self.spec.title, centre_x, y.round(), &style);
        }
    }

    /// The baseline of the x tick labels: they hang below the frame with their ink top
    /// `label_gap` below the ticks.
    fn x_label_baseline(&self) -> f32 {
        let theme = &self.spec.theme;
        let font = Font::dejavu_sans();
        let x_row = label_row(font, &self.x_ticks, theme.tick_label_px);
        (self.plot.bottom() as f32 + tick_overhang(theme) + theme.label_gap + x_row.0).round()
    }

    fn plot_ltrb(&self) -> (f32, f32, f32, f32) {
        (
            self.plot.left() as f32,
            self.plot.top() as f32,
            self.plot.right() as f32,
            self.plot.bottom() as f32,
        )
    }
}

/// The first ten colours of matplotlib's "tab10" cycle, for distinguishable lines.
pub fn palette(index: usize) -> Color {
    const TAB10: [(u8, u8, u8); 10] = [
        (0x1f, 0x77, 0xb4),
        (0xff, 0x7f, 0x0e),
        (0x2c, 0xa0, 0x2c),
        (0xd6, 0x27, 0x28),
        (0x94, 0x67, 0xbd),
        (0x8c, 0x56, 0x4b),
        (0xe3, 0x77, 0xc2),
        (0x7f, 0x7f, 0x7f),
        (0xbc, 0xbd, 0x22),
        (0x17, 0xbe, 0xcf),
    ];
    let (r, g, b) = TAB10[index % TAB10.len()];
    Color::from_rgba8(r, g, b, 255)
}

/// Where the plot area and the ticks end up for a spec and a region.
struct Layout {
    plot: IntRect,
    x_ticks: AxisTicks,
    y_ticks: AxisTicks,
}

impl Layout {
    /// Computes margins from the text that surrounds the plot area. Returns `None` when
    /// the region is too small to leave a plot area.
    ///
    /// The vertical margins do not depend on tick values, so they come first; then the y
    /// ticks are chosen for the plot height, their widest label sets the left margin, and
    /// the x ticks are chosen for the remaining width.
    fn compute(spec: &ChartSpec, region: IntRect) -> Option<Layout> {
        let theme = &spec.theme;
        let font = Font::dejavu_sans();
        let out = tick_overhang(theme);
        let tick_cap = font.cap_height(theme.tick_label_px);
        let title_cap = font.cap_height(theme.axis_title_px);
        let title_descent = font.measure("", theme.axis_title_px).descent;
        let (rx, ry) = (region.x() as f32, region.y() as f32);
        let (rw, rh) = (region.width() as f32, region.height() as f32);

        let top = if spec.title.is_empty() {
            // Leave room for the top half of the top y tick label, which is centred on the
            // frame; superscripts reach higher than digits.
            let ink_up = label_row(font, &spec.y.ticks(10), theme.tick_label_px).0;
            theme.padding.max(ink_up - 0.5 * tick_cap + 2.0)
        } else {
            let title = font.measure("", theme.title_px);
            theme.padding + font.cap_height(theme.title_px) + title.descent + theme.title_gap
        };
        // The x tick label row: measured on sample labels first, exactly later.
        let x_title_room = if spec.x.title.is_empty() {
            0.0
        } else {
            theme.title_gap + title_cap + title_descent
        };
        let bottom_without_labels = theme.padding + x_title_room + out + theme.label_gap;
        let x_row_guess = tick_cap + 0.25 * theme.tick_label_px;
        let plot_top = (ry + top).round();
        let plot_bottom = (ry + rh - bottom_without_labels - x_row_guess).round();
        let height = plot_bottom - plot_top;
        if height < 10.0 {
            return None;
        }

        let y_ticks = fit_ticks(&spec.y, height, |ticks, spacing| {
            spacing >= tick_cap + theme.min_label_spacing * 0.5 || ticks.major.len() <= 2
        });
        let widest_y = y_ticks
            .major
            .iter()
            .map(|t| font.measure(&t.label, theme.tick_label_px).width)
            .fold(0.0f32, f32::max);
        let y_title_room = if spec.y.title.is_empty() {
            0.0
        } else {
            title_cap + title_descent + theme.title_gap
        };
        let left = theme.padding + y_title_room + widest_y + theme.label_gap + out;
        let plot_left = (rx + left).round();

        // Reserve half of a typical wide x label on the right, where the last label may
        // be centred on the frame.
        let probe = spec.x.ticks(10);
        let half_widest_x = probe
            .major
            .iter()
            .map(|t| 0.5 * font.measure(&t.label, theme.tick_label_px).width)
            .fold(0.0f32, f32::max);
        let plot_right = (rx + rw - theme.padding.max(half_widest_x + 2.0)).round();
        let width = plot_right - plot_left;
        if width < 10.0 {
            return None;
        }
        let x_ticks = fit_ticks(&spec.x, width, |ticks, spacing| {
            let widest = ticks
                .major
                .iter()
                .map(|t| font.measure(&t.label, theme.tick_label_px).width)
                .fold(0.0f32, f32::max);
            spacing >= widest + theme.min_label_spacing || ticks.major.len() <= 2
        });
        // If the last label still pokes out of the region, pull the right edge in; the
        // tick values stay the same and only move a little.
        let map = AxisMap::new(&spec.x, f64::from(plot_left), f64::from(plot_right));
        let overhang = x_ticks
            .major
            .last()
            .map(|t| {
                let half = 0.5 * font.measure(&t.label, theme.tick_label_px).width;
                map.map(t.value) as f32 + half + 2.0 - (rx + rw)
            })
            .unwrap_or(0.0);
        let plot_right = plot_right - overhang.max(0.0).ceil();
        // Now that the x labels are known, the bottom margin is exact.
        let (row_up, row_down) = label_row(font, &x_ticks, theme.tick_label_px);
        let plot_bottom_exact = (ry + rh - bottom_without_labels - (row_up + row_down)).round();
        // Keep the height the y ticks were chosen for unless the real labels need more.
        let plot_bottom = plot_bottom.min(plot_bottom_exact);
        let plot = IntRect::from_ltrb(
            plot_left as i32,
            plot_top as i32,
            plot_right as i32,
            plot_bottom as i32,
        )?;
        Some(Layout {
            plot,
            x_ticks,
            y_ticks,
        })
    }
}

/// Chooses ticks for `axis` along `length_px`: starting from about one tick per 80 pixels,
/// asks for fewer until `fits(ticks, smallest spacing in pixels)` holds.
fn fit_ticks(axis: &Axis, length_px: f32, fits: impl Fn(&AxisTicks, f32) -> bool) -> AxisTicks {
    let map = AxisMap::new(axis, 0.0, f64::from(length_px));
    let mut target = ((length_px / 80.0).round() as usize).clamp(2, 10);
    loop {
        let ticks = axis.ticks(target);
        let spacing = ticks
            .major
            .windows(2)
            .map(|w| (map.map(w[1].value) - map.map(w[0].value)).abs() as f32)
            .fold(f32::INFINITY, f32::min);
        if target <= 1 || fits(&ticks, spacing) {
            return ticks;
        }
        target -= 1;
    }
}

/// How far ticks reach out of the frame.
fn tick_overhang(theme: &Theme) -> f32 {
    match theme.tick_direction {
        TickDirection::In => 0.0,
        TickDirection::Out => theme.tick_length,
    }
}

/// The ink above and below the baseline shared by a row of tick labels: at least the
/// height of a digit above, so rows of different labels line up the same.
fn label_row(font: &Font, ticks: &AxisTicks, size_px: f32) -> (f32, f32) {
    ticks
        .major
        .iter()
        .map(|t| font.ink_extent(&t.label, size_px))
        .fold((font.cap_height(size_px), 0.0f32), |(u, d), (tu, td)| {
            (u.max(tu), d.max(td))
        })
}

/// Legend geometry: the box and each row's sample and text positions.
struct LegendLayout {
    frame: Rect,
    rows: Vec<LegendRow>,
}

struct LegendRow {
    sample_left: f32,
    sample_right: f32,
    text_left: f32,
    baseline: f32,
}

impl LegendLayout {
    /// Sizes follow matplotlib's legend: a 2 em sample, 0.8 em before the text, 0.4 em
    /// of padding, rows 1.5 em apart, 0.5 em from the frame.
    fn compute(spec: &ChartSpec, plot: IntRect, frame_px: u32) -> Option<LegendLayout> {
        if spec.legend.is_empty() {
            return None;
        }
        let font = Font::dejavu_sans();
        let em = spec.theme.legend_px;
        let cap = font.cap_height(em);
        let widest = spec
            .legend
            .iter()
            .map(|e| font.measure(&e.label, em).width)
            .fold(0.0f32, f32::max);
        let pad = (0.5 * em).round();
        let pitch = (1.45 * em).round();
        let width = (2.0 * pad + 2.0 * em + 0.8 * em + widest).ceil();
        let height = 2.0 * pad + pitch * (spec.legend.len() as f32 - 1.0) + cap + 0.3 * em;
        let height = height.ceil();
        let inset = frame_px as f32 + (0.5 * em).round();
        let (l, t, r, b) = (
            plot.left() as f32 + inset,
            plot.top() as f32 + inset,
            plot.right() as f32 - inset,
            plot.bottom() as f32 - inset,
        );
        let (left, top) = match spec.theme.legend_corner {
            Corner::TopRight => (r - width, t),
            Corner::TopLeft => (l, t),
            Corner::BottomRight => (r - width, b - height),
            Corner::BottomLeft => (l, b - height),
        };
        let frame = Rect::from_xywh(left, top, width, height)?;
        let rows = (0..spec.legend.len())
            .map(|i| LegendRow {
                sample_left: left + pad,
                sample_right: left + pad + 2.0 * em,
                text_left: left + pad + 2.8 * em,
                baseline: (top + pad + cap + 0.1 * em + pitch * i as f32).round(),
            })
            .collect();
        Some(LegendLayout { frame, rows })
    }
}

fn draw_sample(pixmap: &mut Pixmap, sample: &LegendSample, left: f32, right: f32, mid: f32) {
    match sample {
        LegendSample::Line(style) => {
            let mut builder = PathBuilder::new();
            builder.move_to(left, mid);
            builder.line_to(right, mid);
            if let Some(path) = builder.finish() {
                stroke_path(pixmap, &path, style, None);
            }
        }
        LegendSample::Marker(style) => {
            let mut builder = PathBuilder::new();
            push_marker(
                &mut builder,
                style.shape,
                0.5 * (left + right),
                mid,
                style.size,
            );
            if let Some(path) = builder.finish() {
                fill_marker_path(pixmap, &path, style, None);
            }
        }
        LegendSample::LineMarker(line, marker) => {
            draw_sample(pixmap, &LegendSample::Line(*line), left, right, mid);
            draw_sample(pixmap, &LegendSample::Marker(*marker), left, right, mid);
        }
        LegendSample::Patch(color) => {
            let side = 0.7 * (right - left) / 2.0;
            let centre = 0.5 * (left + right);
            if let Some(rect) = Rect::from_ltrb(
                centre - side,
                mid - 0.5 * side,
                centre + side,
                mid + 0.5 * side,
            ) {
                fill_rect(pixmap, rect, *color, None);
            }
        }
    }
}

fn push_marker(builder: &mut PathBuilder, shape: MarkerShape, x: f32, y: f32, size: f32) {
    let r = 0.5 * size;
    match shape {
        MarkerShape::Circle => builder.push_circle(x, y, r),
        MarkerShape::Square => {
            if let Some(rect) = Rect::from_ltrb(x - r, y - r, x + r, y + r) {
                builder.push_rect(rect);
            }
        }
        MarkerShape::Diamond => {
            // A square of the same area turned by 45°: its half-diagonal is r·√2.
            let d = r * std::f32::consts::SQRT_2;
            builder.move_to(x, y - d);
            builder.line_to(x + d, y);
            builder.line_to(x, y + d);
            builder.line_to(x - d, y);
            builder.close();
        }
        MarkerShape::Triangle => {
            // An equilateral triangle centred on its centroid, with its circumradius
            // 1.2·r so that it looks as large as a disc of radius r.
            let c = 1.2 * r;
            let (half_base, below) = (c * 0.866_025_4, 0.5 * c);
            builder.move_to(x, y - c);
            builder.line_to(x + half_base, y + below);
            builder.line_to(x - half_base, y + below);
            builder.close();
        }
    }
}

fn fill_marker_path(pixmap: &mut Pixmap, path: &Path, style: &MarkerStyle, mask: Option<&Mask>) {
    fill_path(pixmap, path, style.fill, mask);
    if let Some((color, width)) = style.edge {
        stroke_path(pixmap, path, &LineStyle::solid(color, width), mask);
    }
}

fn fill_rect(pixmap: &mut Pixmap, rect: Rect, color: Color, mask: Option<&Mask>) {
    let mut paint = Paint::default();
    paint.set_color(color);
    paint.anti_alias = false;
    pixmap.fill_rect(rect, &paint, Transform::identity(), mask);
}

fn fill_path(pixmap: &mut Pixmap, path: &Path, color: Color, mask: Option<&Mask>) {
    let mut paint = Paint::default();
    paint.set_color(color);
    paint.anti_alias = true;
    pixmap.fill_path(path, &paint, FillRule::Winding, Transform::identity(), mask);
}

fn stroke_path(pixmap: &mut Pixmap, path: &Path, style: &LineStyle, mask: Option<&Mask>) {
    let mut paint = Paint::default();
    paint.set_color(style.color);
    paint.anti_alias = true;
    pixmap.stroke_path(path, &paint, &style.stroke(), Transform::identity(), mask);
}

/// Moves `p` to the nearest position where a line `width` wide covers whole pixels: a
/// pixel centre for odd widths, a pixel edge for even ones.
fn snap(p: f32, width: f32) -> f32 {
    if (width.round() as i64) % 2 == 1 {
        (p - 0.5).round() + 0.5
    } else {
        p.round()
    }
}

fn inside(bounds: (f64, f64, f64, f64), p: (f64, f64)) -> bool {
    p.0 >= bounds.0 && p.0 <= bounds.2 && p.1 >= bounds.1 && p.1 <= bounds.3
}

/// Clips the segment from `a` to `b` to `bounds` (left, top, right, bottom) with the
/// Liang–Barsky method. Returns `None` when no part of it lies inside.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    bounds: (f64, f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - bounds.0),
        (dx, bounds.2 - a.0),
        (-dy, a.1 - bounds.1),
        (dy, bounds.3 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

fn check_axis(name: &'static str, axis: &Axis) -> Result<(), ChartError> {
    let (min, max) = (axis.min, axis.max);
    if !(min.is_finite() && max.is_finite() && min < max) {
        return Err(ChartError::BadRange {
            axis: name,
            min,
            max,
        });
    }
    if axis.scale == Scale::Log10 && min <= 0.0 {
        return Err(ChartError::LogRangeNotPositive {
            axis: name,
            min,
            max,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn transparent_theme() -> Theme {
        Theme {
            background: None,
            ..Theme::default()
        }
    }

    fn chart(x: Axis, y: Axis, width: u32, height: u32) -> Chart {
        Chart::new(
            ChartSpec::new(x, y).theme(transparent_theme()),
            width,
            height,
        )
        .expect("a valid chart")
    }

    /// The bounding box `(x0, y0, x1, y1)`, inclusive, of pixels that are not transparent.
    fn ink_box(pixmap: &Pixmap) -> Option<(u32, u32, u32, u32)> {
        let w = pixmap.width();
        pixmap
            .pixels()
            .iter()
            .enumerate()
            .filter(|(_, p)| p.alpha() != 0)
            .map(|(i, _)| (i as u32 % w, i as u32 / w))
            .fold(None, |acc, (x, y)| {
                Some(match acc {
                    None => (x, y, x, y),
                    Some((a, b, c, d)) => (a.min(x), b.min(y), c.max(x), d.max(y)),
                })
            })
    }

    fn blank(chart: &Chart) -> Pixmap {
        Pixmap::new(chart.canvas.0, chart.canvas.1).expect("a canvas")
    }

    #[test]
    fn data_corners_map_to_the_frame_line_centres() {
        let c = chart(
            Axis::linear(-2.0, 2.0, "x"),
            Axis::log10(1e-6, 1e2, "y"),
            800,
            600,
        );
        let p = c.plot_area();
        let (l, t, r, b) = (
            p.left() as f32,
            p.top() as f32,
            p.right() as f32,
            p.bottom() as f32,
        );
        assert_eq!(c.to_px(-2.0, 1e-6), (l + 0.5, b - 0.5));
        assert_eq!(c.to_px(2.0, 1e2), (r - 0.5, t + 0.5));
        // The middle of the data is the middle of the frame; on a log axis, the middle
        // decade.
        let (mx, my) = c.to_px(0.0, 1e-2);
        assert!((mx - 0.5 * (l + r)).abs() < 1e-3 && (my - 0.5 * (t + b)).abs() < 1e-3);
        // Points a log axis cannot show map to NaN, not to a wild number.
        assert!(c.to_px(0.0, 0.0).1.is_nan() && c.to_px(0.0, -1.0).1.is_nan());
        let (x, y) = c.transform().invert(mx, my);
        assert!(
            x.abs() < 1e-9 && (y / 1e-2 - 1.0).abs() < 1e-9,
            "({x}, {y})"
        );
    }

    #[test]
    fn a_data_direction_follows_the_axis_scales() {
        // x spans 100 units and y spans 1, so one y unit is far more pixels than one x unit.
        let c = chart(
            Axis::linear(0.0, 100.0, "x"),
            Axis::linear(0.0, 1.0, "y"),
            800,
            600,
        );
        let m = c.transform();
        let (ux, uy) = m.direction(50.0, 0.5, 0.0, 1.0).expect("a direction");
        assert!(
            ux.abs() < 1e-12 && (uy + 1.0).abs() < 1e-12,
            "+y is straight up"
        );
        let (ux, uy) = m.direction(50.0, 0.5, 1.0, 0.0).expect("a direction");
        assert!((ux - 1.0).abs() < 1e-12 && uy.abs() < 1e-12, "+x is right");
        // (1, 1) in data space: the pixel vector is (kx, -ky) with kx = width/100 and
        // ky = height/1.
        let p = c.plot_area();
        let kx = f64::from(p.width() - 1) / 100.0;
        let ky = f64::from(p.height() - 1);
        let (ux, uy) = m.direction(50.0, 0.5, 1.0, 1.0).expect("a direction");
        let n = kx.hypot(ky);
        assert!((ux - kx / n).abs() < 1e-9 && (uy + ky / n).abs() < 1e-9);
        assert_eq!(m.direction(50.0, 0.5, 0.0, 0.0), None);
        // On a log axis one decade is the same number of pixels anywhere, so the pixel
        // slope of y ∝ x (a line of slope 1 in log-log) is the same at every point.
        let c = chart(
            Axis::log10(1e-3, 1e3, "x"),
            Axis::log10(1e-3, 1e3, "y"),
            600,
            600,
        );
        let a = c
            .transform()
            .direction(1e-2, 1e-2, 1.0, 1.0)
            .expect("a direction");
        let b = c
            .transform()
            .direction(1e2, 1e2, 1.0, 1.0)
            .expect("a direction");
        assert!((a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9);
    }

    #[test]
    fn an_arrow_along_plus_y_points_up_on_screen() {
        let c = chart(
            Axis::linear(0.0, 100.0, "x"),
            Axis::linear(0.0, 1.0, "y"),
            800,
            600,
        );
        let mut pixmap = blank(&c);
        let style = ArrowStyle::new(Color::BLACK, 2.0);
        c.arrow(&mut pixmap, (50.0, 0.2), (0.0, 0.5), &style);
        let (x0, y0, x1, y1) = ink_box(&pixmap).expect("the arrow has ink");
        let (base_x, base_y) = c.to_px(50.0, 0.2);
        let (_, tip_y) = c.to_px(50.0, 0.7);
        assert!(tip_y < base_y, "the tip is above the base on screen");
        assert!((y0 as f32 - tip_y).abs() <= 1.0 && ((y1 + 1) as f32 - base_y).abs() <= 1.0);
        assert!((x0 as f32) < base_x && (x1 as f32) > base_x && x1 - x0 <= 14);
        // The head, at the top, is wider than the shaft at the bottom.
        let row_width = |y: u32| {
            (0..800)
                .filter(|&x| pixmap.pixel(x, y).is_some_and(|p| p.alpha() > 0))
                .count()
        };
        assert!(row_width(y0 + 6) > 2 * row_width(y1 - 5));
        // The fixed-length form points the same way and is as long as asked.
        let mut pixmap = blank(&c);
        c.arrow_px(&mut pixmap, (50.0, 0.2), (0.0, 1e-3), 40.0, &style);
        let (_, y0, _, y1) = ink_box(&pixmap).expect("the arrow has ink");
        assert!((y1 - y0) as f32 >= 39.0 && (y1 - y0) as f32 <= 42.0);
        assert!(((y1 + 1) as f32 - base_y).abs() <= 1.0);
    }

    #[test]
    fn slope_segments_have_the_slope_on_screen() {
        let c = chart(
            Axis::linear(-2.0, 2.0, "x"),
            Axis::linear(-1.0, 4.0, "y"),
            800,
            600,
        );
        let style = LineStyle::solid(Color::BLACK, 1.0);
        // Slope 0 is a horizontal segment of the requested length.
        let mut pixmap = blank(&c);
        c.slope_segments(&mut pixmap, [(0.0, 1.0, 0.0)], 20.0, &style);
        let (x0, y0, x1, y1) = ink_box(&pixmap).expect("the segment has ink");
        assert!((x1 - x0 + 1) >= 20 && (x1 - x0 + 1) <= 22 && y1 - y0 <= 2);
        // An infinite slope is vertical.
        let mut pixmap = blank(&c);
        c.slope_segments(&mut pixmap, [(0.0, 1.0, f64::INFINITY)], 20.0, &style);
        let (x0, _, x1, _) = ink_box(&pixmap).expect("the segment has ink");
        assert!(x1 - x0 <= 2);
        // A slope of (y pixels per unit) / (x pixels per unit)... inverted is 45° on screen.
        let m = c.transform();
        let (kx, ky) = (m.x.pixels_per_unit(), -m.y.pixels_per_unit());
        let (ux, uy) = m.direction(0.0, 1.0, 1.0, kx / ky).expect("a direction");
        assert!((ux - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12 && (ux + uy).abs() < 1e-12);
    }

    #[test]
    fn data_never_paints_outside_the_frame() {
        let c = chart(
            Axis::linear(0.0, 1.0, "x"),
            Axis::linear(0.0, 1.0, "y"),
            400,
            300,
        );
        let mut pixmap = blank(&c);
        let thick = LineStyle::solid(Color::BLACK, 9.0);
        c.polyline(
            &mut pixmap,
            [(-1e9, -1e9), (0.5, 0.5), (1e12, -3.0)],
            &thick,
        );
        c.markers(
            &mut pixmap,
            [(0.0, 0.0), (1.0, 1.0), (1.0, 0.0)],
            &MarkerStyle::new(MarkerShape::Square, 30.0, Color::BLACK),
        );
        c.arrow(
            &mut pixmap,
            (0.9, 0.9),
            (0.5, 0.5),
            &ArrowStyle::new(Color::BLACK, 3.0),
        );
        c.fill_rect(&mut pixmap, (-5.0, -5.0), (0.1, 5.0), Color::BLACK);
        let (x0, y0, x1, y1) = ink_box(&pixmap).expect("something was drawn");
        let p = c.plot_area();
        // The frame is one pixel wide; the inside starts one pixel in.
        assert_eq!((x0 as i32, y0 as i32), (p.left() + 1, p.top() + 1));
        assert_eq!((x1 as i32, y1 as i32), (p.right() - 2, p.bottom() - 2));
    }

    #[test]
    fn points_a_log_axis_cannot_show_break_the_line() {
        let c = chart(
            Axis::linear(0.0, 4.0, "t"),
            Axis::log10(1e-3, 1e1, "E"),
            400,
            300,
        );
        let mut pixmap = blank(&c);
        let style = LineStyle::solid(Color::BLACK, 1.5);
        c.polyline(
            &mut pixmap,
            [(0.0, 1.0), (1.0, 0.0), (2.0, -1.0), (3.0, f64::NAN)],
            &style,
        );
        assert_eq!(
            ink_box(&pixmap),
            None,
            "no two neighbouring points can be shown"
        );
        c.polyline(
            &mut pixmap,
            [(0.0, 1.0), (1.0, 0.0), (3.0, 1.0), (4.0, 1.0)],
            &style,
        );
        let (x0, _, _, _) = ink_box(&pixmap).expect("the last two points are joined");
        assert!(x0 as f32 >= c.to_px(3.0, 1.0).0 - 1.0);
    }

    #[test]
    fn heatmap_cells_tile_without_gaps() {
        let c = chart(
            Axis::linear(0.0, 7.0, "x"),
            Axis::linear(0.0, 3.0, "y"),
            417,
            311,
        );
        let mut pixmap = blank(&c);
        let edges = |n: usize, max: f64| {
            (0..=n)
                .map(|i| max * i as f64 / n as f64)
                .collect::<Vec<_>>()
        };
        let color =
            |i: usize, j: usize| Color::from_rgba8((i * 30) as u8, (j * 80) as u8, 128, 255);
        c.fill_cells(&mut pixmap, &edges(7, 7.0), &edges(3, 3.0), color);
        let p = c.plot_area();
        for y in p.top() + 1..p.bottom() - 1 {
            for x in p.left() + 1..p.right() - 1 {
                let alpha = pixmap.pixel(x as u32, y as u32).map(|p| p.alpha());
                assert_eq!(alpha, Some(255), "pixel ({x}, {y})");
            }
        }
    }

    /// Lays out a chart and checks that its text boxes neither overlap each other nor
    /// leave the region, and that the plot area lies inside the region.
    fn check_layout(spec: ChartSpec, width: u32, height: u32) {
        let c = Chart::new(spec, width, height).expect("a valid chart");
        let theme = &c.spec.theme;
        let font = Font::dejavu_sans();
        let p = c.plot_area();
        assert!(p.left() > 0 && p.top() > 0);
        assert!(p.right() < width as i32 && p.bottom() < height as i32);
        assert!(c.x_ticks().major.len() >= 2 && c.y_ticks().major.len() >= 2);
        let mut previous_right = f32::NEG_INFINITY;
        for t in &c.x_ticks().major {
            let w = font.measure(&t.label, theme.tick_label_px).width;
            let x = c.to_px(t.value, c.spec.y.min).0;
            assert!(
                x - 0.5 * w >= 0.0 && x + 0.5 * w <= width as f32,
                "{:?}",
                t.label
            );
            assert!(
                x - 0.5 * w > previous_right + 4.0,
                "x labels overlap at {:?}",
                t.label
            );
            previous_right = x + 0.5 * w;
        }
        // Y labels are centred half a cap height below their ink's digit tops.
        let half_cap = 0.5 * font.cap_height(theme.tick_label_px);
        let mut previous_top = f32::INFINITY;
        let mut boxes = Vec::new();
        for t in &c.y_ticks().major {
            let w = font.measure(&t.label, theme.tick_label_px).width;
            let (up, down) = font.ink_extent(&t.label, theme.tick_label_px);
            let y = c.to_px(c.spec.x.min, t.value).1;
            let (top, bottom) = (y + half_cap - up, y + half_cap + down);
            assert!(
                p.left() as f32 - w > 0.0,
                "y label {:?} leaves the region",
                t.label
            );
            assert!(
                bottom < previous_top - 4.0,
                "y labels overlap at {:?}",
                t.label
            );
            assert!(top >= 0.0, "y label {:?} leaves the region", t.label);
            previous_top = top;
            boxes.push((
                p.left() as f32 - theme.label_gap - w,
                top,
                p.left() as f32,
                bottom,
            ));
        }
        // No x label touches a y label, which can happen in the bottom-left corner.
        let baseline = c.x_label_baseline();
        for t in &c.x_ticks().major {
            let w = font.measure(&t.label, theme.tick_label_px).width;
            let (up, down) = font.ink_extent(&t.label, theme.tick_label_px);
            let x = c.to_px(t.value, c.spec.y.min).0;
            let b = (x - 0.5 * w, baseline - up, x + 0.5 * w, baseline + down);
            for a in &boxes {
                let apart = b.0 >= a.2 || a.0 >= b.2 || b.1 >= a.3 + 1.0 || a.1 >= b.3 + 1.0;
                assert!(apart, "x label {:?} {b:?} touches a y label {a:?}", t.label);
            }
        }
    }

    #[test]
    fn layouts_keep_labels_apart_and_inside() {
        let spec = |x: Axis, y: Axis| ChartSpec::new(x, y).title("A title");
        check_layout(
            spec(Axis::linear(-2.0, 2.0, "x"), Axis::linear(-1.0, 4.0, "y")),
            800,
            600,
        );
        check_layout(
            spec(Axis::linear(0.0, 1e7, "n"), Axis::linear(-3e-5, 3e-5, "e")),
            800,
            600,
        );
        check_layout(
            spec(
                Axis::linear(-1234.5, 98765.4, "x"),
                Axis::linear(0.0, 1.0, ""),
            ),
            400,
            300,
        );
        check_layout(
            spec(Axis::log10(1e-12, 1.0, "h"), Axis::log10(1e-9, 1e-2, "err")),
            400,
            300,
        );
        check_layout(
            spec(Axis::log10(2.0, 60.0, "n"), Axis::linear(0.0, 0.7, "")),
            320,
            240,
        );
        let big = ChartSpec::new(
            Axis::linear(0.0, 5.0, "t (s)"),
            Axis::linear(-0.5, 2.5, "v (m/s)"),
        )
        .theme(Theme::default().scaled(2.0));
        check_layout(big, 1600, 1200);
    }

    #[test]
    fn bad_specs_are_errors() {
        let ok = Axis::linear(0.0, 1.0, "");
        let new = |x: Axis, y: Axis, w, h| Chart::new(ChartSpec::new(x, y), w, h).map(|_| ());
        assert!(matches!(
            new(Axis::linear(1.0, 1.0, ""), ok.clone(), 400, 300),
            Err(ChartError::BadRange { axis: "x", .. })
        ));
        assert!(matches!(
            new(ok.clone(), Axis::linear(0.0, f64::NAN, ""), 400, 300),
            Err(ChartError::BadRange { axis: "y", .. })
        ));
        assert!(matches!(
            new(ok.clone(), Axis::log10(0.0, 1.0, ""), 400, 300),
            Err(ChartError::LogRangeNotPositive { axis: "y", .. })
        ));
        assert!(matches!(
            new(ok.clone(), ok.clone(), 40, 30),
            Err(ChartError::TooSmall { .. })
        ));
        let region = IntRect::from_xywh(500, 0, 400, 300).expect("a rect");
        assert!(matches!(
            Chart::in_region(ChartSpec::new(ok.clone(), ok), 800, 300, region),
            Err(ChartError::RegionOutsideCanvas { .. })
        ));
    }

    #[test]
    fn a_chart_in_a_region_stays_in_it() {
        let region = IntRect::from_xywh(400, 20, 380, 260).expect("a rect");
        let spec = ChartSpec::new(Axis::linear(0.0, 1.0, "x"), Axis::linear(0.0, 1.0, "y"))
            .title("right half")
            .legend_entry(LegendEntry::line(
                LineStyle::solid(Color::BLACK, 1.5),
                "a line",
            ));
        let c = Chart::in_region(spec, 800, 300, region).expect("a valid chart");
        let mut pixmap = Pixmap::new(800, 300).expect("a canvas");
        c.draw_static(&mut pixmap);
        c.polyline(
            &mut pixmap,
            [(0.0, 0.0), (1.0, 1.0)],
            &LineStyle::solid(Color::BLACK, 2.0),
        );
        c.draw_legend(&mut pixmap);
        assert_eq!(ink_box(&pixmap), Some((400, 20, 779, 279)));
    }

    #[test]
    fn the_static_part_is_deterministic_and_reusable() {
        let spec = ChartSpec::new(Axis::linear(0.0, 5.0, "t"), Axis::log10(1e-3, 1e1, "E"))
            .title("Energy")
            .grid(true);
        let a = Chart::new(spec.clone(), 640, 480)
            .expect("a valid chart")
            .static_pixmap();
        let b = Chart::new(spec, 640, 480).expect("a valid chart");
        let mut frame = b.static_pixmap();
        assert_eq!(a.data(), frame.data());
        b.polyline(
            &mut frame,
            [(0.0, 1.0), (5.0, 2.0)],
            &LineStyle::solid(Color::BLACK, 1.5),
        );
        assert_ne!(a.data(), frame.data());
        // Copying the static pixmap resets a frame.
        frame.data_mut().copy_from_slice(a.data());
        assert_eq!(a.data(), frame.data());
    }

    #[test]
    fn liang_barsky_clipping() {
        let bounds = (0.0, 0.0, 10.0, 10.0);
        assert_eq!(
            clip_segment((-5.0, 5.0), (15.0, 5.0), bounds),
            Some(((0.0, 5.0), (10.0, 5.0)))
        );
        assert_eq!(
            clip_segment((1.0, 1.0), (2.0, 2.0), bounds),
            Some(((1.0, 1.0), (2.0, 2.0)))
        );
        assert_eq!(clip_segment((-5.0, -5.0), (-1.0, 20.0), bounds), None);
        assert_eq!(clip_segment((11.0, 0.0), (20.0, 10.0), bounds), None);
    }
}
