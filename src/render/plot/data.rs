//! The data helpers: lines, markers, arrows, slope segments and filled rectangles in
//! data coordinates, mapped to pixels and clipped to the inside of the frame.

use tiny_skia::{Color, FillRule, Mask, Paint, Path, PathBuilder, Pixmap, Rect, Transform};

use super::*;

impl Chart {
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
    pub(super) fn mask_for(&self, pixmap: &Pixmap) -> Option<&Mask> {
        let fits = (pixmap.width(), pixmap.height()) == self.canvas;
        debug_assert!(fits, "draw into a pixmap of the chart's canvas size");
        if fits {
            self.clip.as_ref()
        } else {
            None
        }
    }

    /// The plot area grown by `margin` pixels, as (left, top, right, bottom).
    pub(super) fn expanded_plot(&self, margin: f64) -> (f64, f64, f64, f64) {
        (
            f64::from(self.plot.left()) - margin,
            f64::from(self.plot.top()) - margin,
            f64::from(self.plot.right()) + margin,
            f64::from(self.plot.bottom()) + margin,
        )
    }

    pub(super) fn arrow_between(
        &self,
        pixmap: &mut Pixmap,
        a: (f64, f64),
        b: (f64, f64),
        style: &ArrowStyle,
    ) {
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
}

pub(super) fn push_marker(
    builder: &mut PathBuilder,
    shape: MarkerShape,
    x: f32,
    y: f32,
    size: f32,
) {
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

pub(super) fn fill_marker_path(
    pixmap: &mut Pixmap,
    path: &Path,
    style: &MarkerStyle,
    mask: Option<&Mask>,
) {
    fill_path(pixmap, path, style.fill, mask);
    if let Some((color, width)) = style.edge {
        stroke_path(pixmap, path, &LineStyle::solid(color, width), mask);
    }
}

pub(super) fn fill_rect(pixmap: &mut Pixmap, rect: Rect, color: Color, mask: Option<&Mask>) {
    let mut paint = Paint::default();
    paint.set_color(color);
    paint.anti_alias = false;
    pixmap.fill_rect(rect, &paint, Transform::identity(), mask);
}

pub(super) fn fill_path(pixmap: &mut Pixmap, path: &Path, color: Color, mask: Option<&Mask>) {
    let mut paint = Paint::default();
    paint.set_color(color);
    paint.anti_alias = true;
    pixmap.fill_path(path, &paint, FillRule::Winding, Transform::identity(), mask);
}

pub(super) fn stroke_path(
    pixmap: &mut Pixmap,
    path: &Path,
    style: &LineStyle,
    mask: Option<&Mask>,
) {
    let mut paint = Paint::default();
    paint.set_color(style.color);
    paint.anti_alias = true;
    pixmap.stroke_path(path, &paint, &style.stroke(), Transform::identity(), mask);
}

/// Moves `p` to the nearest position where a line `width` wide covers whole pixels: a
/// pixel centre for odd widths, a pixel edge for even ones.
pub(super) fn snap(p: f32, width: f32) -> f32 {
    if (width.round() as i64) % 2 == 1 {
        (p - 0.5).round() + 0.5
    } else {
        p.round()
    }
}

pub(super) fn inside(bounds: (f64, f64, f64, f64), p: (f64, f64)) -> bool {
    p.0 >= bounds.0 && p.0 <= bounds.2 && p.1 >= bounds.1 && p.1 <= bounds.3
}

/// Clips the segment from `a` to `b` to `bounds` (left, top, right, bottom) with the
/// Liang–Barsky method. Returns `None` when no part of it lies inside.
pub(super) fn clip_segment(
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
