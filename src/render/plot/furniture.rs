//! The chart's furniture, drawn once into the static layer: grid, ticks, frame, tick
//! labels and titles; and the samples of the legend's rows.

use tiny_skia::{LineJoin, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

use super::*;
use crate::render::text::{Font, HAlign, TextStyle, VAlign};

impl Chart {
    pub(super) fn draw_grid(&self, pixmap: &mut Pixmap) {
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

    pub(super) fn draw_ticks(&self, pixmap: &mut Pixmap) {
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

    pub(super) fn draw_frame(&self, pixmap: &mut Pixmap) {
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

    pub(super) fn draw_labels(&self, pixmap: &mut Pixmap) {
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
    pub(super) fn x_label_baseline(&self) -> f32 {
        let theme = &self.spec.theme;
        let font = Font::dejavu_sans();
        let x_row = label_row(font, &self.x_ticks, theme.tick_label_px);
        (self.plot.bottom() as f32 + tick_overhang(theme) + theme.label_gap + x_row.0).round()
    }

    pub(super) fn plot_ltrb(&self) -> (f32, f32, f32, f32) {
        (
            self.plot.left() as f32,
            self.plot.top() as f32,
            self.plot.right() as f32,
            self.plot.bottom() as f32,
        )
    }
}

pub(super) fn draw_sample(
    pixmap: &mut Pixmap,
    sample: &LegendSample,
    left: f32,
    right: f32,
    mid: f32,
) {
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
