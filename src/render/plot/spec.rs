//! What a chart shows: its axes and their scales, the theme, the styles of lines,
//! markers and arrows, legend entries, and the spec that gathers them; and the errors of
//! a spec that cannot be laid out.

use tiny_skia::{Color, LineCap, LineJoin, Stroke, StrokeDash};

use crate::render::ticks::{linear_ticks, log10_ticks, AxisTicks, LogLabelStyle};

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

    pub(super) fn ticks(&self, target: usize) -> AxisTicks {
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
    pub(super) fn intervals(self, width: f32) -> Option<Vec<f32>> {
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

    pub(super) fn stroke(&self) -> Stroke {
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

pub(super) fn check_axis(name: &'static str, axis: &Axis) -> Result<(), ChartError> {
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
