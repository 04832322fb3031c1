//! Edges cut to the image as tiny-skia cuts them before it scan-converts a path that
//! reaches outside the image, so that such a path's coverage is tiny-skia's too.
//!
//! tiny-skia (Skia's `SkEdgeClipper` and `SkLineClipper`) fills a path whose bounds,
//! rounded out to whole pixels, lie inside the image from its edges as they are. For
//! any other path it first cuts every line to the image, in f32 (with f64 for the
//! crossings): the part above or below the image is dropped, and a part to its left or
//! right becomes a vertical line along the image's side, over the rows it spans. A line
//! cut so starts at a new point, and its fixed-point slope and sub-row crossings follow
//! from that point: inside the image they may differ by a quarter-pixel sample from the
//! uncut line's in every sub-row. Cutting the same way here, with the same arithmetic,
//! gives the same edges and so the same bytes.

use super::Point;

/// The image a path is filled into, and whether tiny-skia cuts the path's edges to it.
#[derive(Clone, Copy, Debug)]
pub(super) struct ImageClip {
    right: f32,
    bottom: f32,
    contained: bool,
}

impl ImageClip {
    /// Decides, as tiny-skia's anti-aliased `fill_path` does, whether the path of these
    /// contours is filled into an image `width` × `height` uncut: when its bounds,
    /// floored and ceiled to whole pixels (at least one pixel wide and high), lie in
    /// the image.
    pub(super) fn new(width: usize, height: usize, contours: &[&[Point]]) -> Self {
        let (mut l, mut t, mut r, mut b) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
        for &(x, y) in contours.iter().flat_map(|c| c.iter()) {
            (l, t, r, b) = (l.min(x), t.min(y), r.max(x), b.max(y));
        }
        let whole = |v: f32| v as i64;
        let (l, t) = (whole(l.floor()), whole(t.floor()));
        let (r, b) = (whole(r.ceil()), whole(b.ceil()));
        let contained = l >= 0
            && t >= 0
            && l + (r - l).max(1) <= width as i64
            && t + (b - t).max(1) <= height as i64;
        ImageClip {
            right: width as f32,
            bottom: height as f32,
            contained,
        }
    }

    /// Whether the path is filled uncut: every line of it is itself.
    #[inline]
    pub(super) fn contained(&self) -> bool {
        self.contained
    }

    /// Calls `push` with each line that the line p0 → p1 of the path becomes: itself
    /// when the path is not cut, otherwise none, one, two or three lines, in the
    /// line's direction, as tiny-skia's line clipper cuts it to the image.
    #[inline]
    pub(super) fn cut(&self, p0: Point, p1: Point, mut push: impl FnMut(Point, Point)) {
        if self.contained {
            push(p0, p1);
            return;
        }
        let src = [p0, p1];
        let (top, bottom, left, right) = (0.0f32, self.bottom, 0.0f32, self.right);
        let (i0, i1) = if src[0].1 < src[1].1 { (0, 1) } else { (1, 0) };
        // Wholly above or below the image: nothing.
        if src[i1].1 <= top || src[i0].1 >= bottom {
            return;
        }
        // Cut in y to one line, tmp[0] → tmp[1].
        let mut tmp = src;
        if src[i0].1 < top {
            tmp[i0] = (x_at_y(&src, top), top);
        }
        if tmp[i1].1 > bottom {
            tmp[i1] = (x_at_y(&src, bottom), bottom);
        }
        // Then in x, into lines that each lie within the image's columns, ordered by
        // increasing x and turned back to the line's direction at the end.
        let (i0, i1, mut reverse) = if src[0].0 < src[1].0 {
            (0, 1, false)
        } else {
            (1, 0, true)
        };
        let mut points = [(0.0f32, 0.0f32); 4];
        let count;
        if tmp[i1].0 <= left || tmp[i0].0 >= right {
            // Wholly to one side: a vertical line along that side, in the line's own
            // direction.
            let side = if tmp[i1].0 <= left { left } else { right };
            points[0] = (side, tmp[0].1);
            points[1] = (side, tmp[1].1);
            count = 1;
            reverse = false;
        } else {
            let mut k = 0;
            if tmp[i0].0 < left {
                points[0] = (left, tmp[i0].1);
                points[1] = (left, y_at_x_pinned(&tmp, left));
                k = 1;
            } else {
                points[0] = tmp[i0];
            }
            k += 1;
            if tmp[i1].0 > right {
                points[k] = (right, y_at_x_pinned(&tmp, right));
                k += 1;
                points[k] = (right, tmp[i1].1);
            } else {
                points[k] = tmp[i1];
            }
            count = k;
        }
        if reverse {
            points[..=count].reverse();
        }
        for pair in points[..=count].windows(2) {
            push(pair[0], pair[1]);
        }
    }
}

/// The x where the line src crosses the row y: x0 + (y − y0)·(x1 − x0)/(y1 − y0) in
/// f64, held between x0 and x1; the mean of x0 and x1 for a line within 1/4096 pixel
/// of level.
fn x_at_y(src: &[Point; 2], y: f32) -> f32 {
    let [(x0, y0), (x1, y1)] = *src;
    if (y1 - y0).abs() <= 1.0 / 4096.0 {
        return (x0 + x1) * 0.5;
    }
    let (x0, y0, x1, y1) = (f64::from(x0), f64::from(y0), f64::from(x1), f64::from(y1));
    let x = x0 + (f64::from(y) - y0) * (x1 - x0) / (y1 - y0);
    pin(x, x0, x1) as f32
}

/// The y where the line src crosses the column x: y0 + (x − x0)·(y1 − y0)/(x1 − x0) in
/// f64, rounded to f32 and then held between y0 and y1; the mean of y0 and y1 for a
/// line within 1/4096 pixel of upright.
fn y_at_x_pinned(src: &[Point; 2], x: f32) -> f32 {
    let [(x0, y0), (x1, y1)] = *src;
    let y = if (x1 - x0).abs() <= 1.0 / 4096.0 {
        (y0 + y1) * 0.5
    } else {
        let (fx0, fy0, fx1, fy1) = (f64::from(x0), f64::from(y0), f64::from(x1), f64::from(y1));
        (fy0 + (f64::from(x) - fx0) * (fy1 - fy0) / (fx1 - fx0)) as f32
    };
    pin(y, y0, y1)
}

/// Holds `v` between two limits given in either order.
fn pin<T: PartialOrd + Copy>(v: T, a: T, b: T) -> T {
    let (lo, hi) = if b < a { (b, a) } else { (a, b) };
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cut(clip: &ImageClip, p0: Point, p1: Point) -> Vec<(Point, Point)> {
        let mut lines = Vec::new();
        clip.cut(p0, p1, |a, b| lines.push((a, b)));
        lines
    }

    #[test]
    fn a_path_inside_the_image_is_not_cut() {
        let square: &[Point] = &[(0.0, 0.0), (10.0, 0.0), (10.0, 8.0), (0.0, 8.0)];
        let clip = ImageClip::new(10, 8, &[square]);
        assert!(clip.contained);
        assert_eq!(
            cut(&clip, (-5.0, 1.0), (3.0, 2.0)),
            [((-5.0, 1.0), (3.0, 2.0))]
        );
        // A point past the right edge by a little puts the path outside.
        let wider: &[Point] = &[(0.0, 0.0), (10.01, 0.0), (10.0, 8.0)];
        assert!(!ImageClip::new(10, 8, &[wider]).contained);
    }

    #[test]
    fn lines_are_cut_to_rows_and_turned_vertical_beside_the_image() {
        let outside: &[Point] = &[(-1.0, -1.0), (20.0, 20.0)];
        let clip = ImageClip::new(10, 8, &[outside]);
        // Above, below: nothing.
        assert!(cut(&clip, (1.0, -3.0), (5.0, 0.0)).is_empty());
        assert!(cut(&clip, (1.0, 8.0), (5.0, 9.0)).is_empty());
        // Across the top: from where it crosses row 0.
        assert_eq!(
            cut(&clip, (2.0, -2.0), (4.0, 2.0)),
            [((3.0, 0.0), (4.0, 2.0))]
        );
        // Wholly to the left: along column 0, in the line's direction.
        assert_eq!(
            cut(&clip, (-3.0, 6.0), (-1.0, 2.0)),
            [((0.0, 6.0), (0.0, 2.0))]
        );
        // From the left across the right side, going up: three lines, the crossings
        // at x = 0 (y = 5) and x = 10 (y = 2.5), in the line's direction.
        assert_eq!(
            cut(&clip, (-2.0, 5.5), (12.0, 2.0)),
            [
                ((0.0, 5.5), (0.0, 5.0)),
                ((0.0, 5.0), (10.0, 2.5)),
                ((10.0, 2.5), (10.0, 2.0))
            ]
        );
        // The same line the other way round.
        assert_eq!(
            cut(&clip, (12.0, 2.0), (-2.0, 5.5)),
            [
                ((10.0, 2.0), (10.0, 2.5)),
                ((10.0, 2.5), (0.0, 5.0)),
                ((0.0, 5.0), (0.0, 5.5))
            ]
        );
    }
}
