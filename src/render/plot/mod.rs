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
//!
//! The chart lives in several files: `spec.rs` holds what a chart shows (axes, theme,
//! line, marker and arrow styles, legend entries, the spec and its errors);
//! `transform.rs` the map from data to pixels; `layout.rs` how margins, ticks and the
//! legend's box are fitted to the room there is; `furniture.rs` the grid, ticks, frame
//! and labels; `data.rs` the clipped data helpers. This file holds the [`Chart`] itself:
//! its construction, accessors, and the two drawing entry points.

mod data;
mod furniture;
mod layout;
mod spec;
mod transform;

use tiny_skia::{Color, FillRule, IntRect, Mask, PathBuilder, Pixmap, Rect, Transform};

use super::text::{Font, TextStyle};
use super::ticks::AxisTicks;

use data::{fill_marker_path, fill_rect, push_marker, snap, stroke_path};
use furniture::draw_sample;
use layout::{label_row, tick_overhang, Layout, LegendLayout};
pub use spec::*;
pub use transform::*;

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

    /// The legend's box, when the chart has a legend: everything
    /// [`Chart::draw_legend`] draws lies inside it (its entries are laid out within).
    pub fn legend_box(&self) -> Option<Rect> {
        LegendLayout::compute(&self.spec, self.plot, self.frame_px).map(|legend| legend.frame)
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

#[cfg(test)]
mod tests;
