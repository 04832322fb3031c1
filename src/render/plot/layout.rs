//! Fitting a chart to its room: the plot area, margins measured from the real sizes of
//! the tick labels and titles, ticks chosen for the length an axis has, and the
//! legend's box.

use tiny_skia::{IntRect, Rect};

use super::*;
use crate::render::text::Font;
use crate::render::ticks::AxisTicks;

/// Where the plot area and the ticks end up for a spec and a region.
pub(super) struct Layout {
    pub(super) plot: IntRect,
    pub(super) x_ticks: AxisTicks,
    pub(super) y_ticks: AxisTicks,
}

impl Layout {
    /// Computes margins from the text that surrounds the plot area. Returns `None` when
    /// the region is too small to leave a plot area.
    ///
    /// The vertical margins do not depend on tick values, so they come first; then the y
    /// ticks are chosen for the plot height, their widest label sets the left margin, and
    /// the x ticks are chosen for the remaining width.
    pub(super) fn compute(spec: &ChartSpec, region: IntRect) -> Option<Layout> {
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
pub(super) fn fit_ticks(
    axis: &Axis,
    length_px: f32,
    fits: impl Fn(&AxisTicks, f32) -> bool,
) -> AxisTicks {
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
pub(super) fn tick_overhang(theme: &Theme) -> f32 {
    match theme.tick_direction {
        TickDirection::In => 0.0,
        TickDirection::Out => theme.tick_length,
    }
}

/// The ink above and below the baseline shared by a row of tick labels: at least the
/// height of a digit above, so rows of different labels line up the same.
pub(super) fn label_row(font: &Font, ticks: &AxisTicks, size_px: f32) -> (f32, f32) {
    ticks
        .major
        .iter()
        .map(|t| font.ink_extent(&t.label, size_px))
        .fold((font.cap_height(size_px), 0.0f32), |(u, d), (tu, td)| {
            (u.max(tu), d.max(td))
        })
}

/// Legend geometry: the box and each row's sample and text positions.
pub(super) struct LegendLayout {
    pub(super) frame: Rect,
    pub(super) rows: Vec<LegendRow>,
}

pub(super) struct LegendRow {
    pub(super) sample_left: f32,
    pub(super) sample_right: f32,
    pub(super) text_left: f32,
    pub(super) baseline: f32,
}

impl LegendLayout {
    /// Sizes follow matplotlib's legend: a 2 em sample, 0.8 em before the text, 0.4 em
    /// of padding, rows 1.5 em apart, 0.5 em from the frame.
    pub(super) fn compute(spec: &ChartSpec, plot: IntRect, frame_px: u32) -> Option<LegendLayout> {
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
