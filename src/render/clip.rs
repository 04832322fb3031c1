//! Clipping geometry to a guard band around the image before it reaches tiny-skia.
//!
//! tiny-skia 0.12 can panic when it fills or strokes paths whose coordinates lie very
//! far outside the image (an integer overflow in its anti-aliased scan converter;
//! linebender/resvg#940, linebender/tiny-skia#178). A simulation that is about to blow
//! up produces exactly such coordinates. So every polyline and arrow is clipped here,
//! in f64, to the image grown by a guard band wider than any stroke; the visible
//! result is the same, and tiny-skia only ever sees coordinates near the image.

use tiny_skia::{Path, PathBuilder};

/// How far beyond the image edges geometry is kept, in pixels.
pub const GUARD: f64 = 64.0;

/// A rectangle in pixel coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipRect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl ClipRect {
    /// The image `width` × `height` grown by the guard band on every side.
    pub fn guard(width: u32, height: u32) -> Self {
        ClipRect {
            x0: -GUARD,
            y0: -GUARD,
            x1: f64::from(width) + GUARD,
            y1: f64::from(height) + GUARD,
        }
    }

    /// Returns true when the point lies inside the rectangle.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }

    /// Clips the segment from a to b (Liang–Barsky). Returns the part inside, or `None`
    /// when nothing of it is inside or an end is not finite.
    ///
    /// With p(u) = a + u·(b - a), each edge gives an inequality p_k·u ≤ q_k; u is
    /// narrowed to [u0, u1] by every edge, and the segment survives if u0 ≤ u1.
    pub fn segment(&self, a: (f64, f64), b: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
        if !(a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite()) {
            return None;
        }
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let mut u0 = 0.0f64;
        let mut u1 = 1.0f64;
        for (p, q) in [
            (-dx, a.0 - self.x0),
            (dx, self.x1 - a.0),
            (-dy, a.1 - self.y0),
            (dy, self.y1 - a.1),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else {
                let u = q / p;
                if p < 0.0 {
                    u0 = u0.max(u);
                } else {
                    u1 = u1.min(u);
                }
            }
        }
        if u0 > u1 {
            return None;
        }
        // In exact arithmetic the clipped ends lie on the rectangle; with ends far away
        // (1e50 pixels, say) a + u·d cancels catastrophically and can land anywhere, so
        // the ends are clamped back into the rectangle. That moves them by no more than
        // the round-off, and guarantees the rasteriser only sees safe coordinates.
        let at = |u: f64| {
            (
                (a.0 + u * dx).clamp(self.x0, self.x1),
                (a.1 + u * dy).clamp(self.y0, self.y1),
            )
        };
        Some((
            if u0 > 0.0 { at(u0) } else { a },
            if u1 < 1.0 { at(u1) } else { b },
        ))
    }

    /// Builds a path through the points, clipped: parts outside the rectangle are
    /// dropped and the path resumes where the polyline comes back in.
    pub fn polyline(&self, points: impl IntoIterator<Item = (f64, f64)>) -> Option<Path> {
        let mut pb = PathBuilder::new();
        let mut previous: Option<(f64, f64)> = None;
        // The last point added to the path, to know whether a piece continues it.
        let mut pen: Option<(f64, f64)> = None;
        for p in points {
            if let Some(a) = previous {
                if let Some((c, d)) = self.segment(a, p) {
                    if pen != Some(c) {
                        pb.move_to(c.0 as f32, c.1 as f32);
                    }
                    pb.line_to(d.0 as f32, d.1 as f32);
                    pen = Some(d);
                } else {
                    pen = None;
                }
            }
            previous = Some(p);
        }
        pb.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_inside_are_kept_as_they_are() {
        let r = ClipRect::guard(100, 100);
        assert_eq!(
            r.segment((1.0, 2.0), (50.0, 60.0)),
            Some(((1.0, 2.0), (50.0, 60.0)))
        );
    }

    #[test]
    fn segments_crossing_an_edge_end_on_it() {
        let r = ClipRect::guard(100, 100);
        let (a, b) = r.segment((50.0, 50.0), (1e300, 50.0)).expect("crosses");
        assert_eq!(a, (50.0, 50.0));
        assert_eq!(b, (164.0, 50.0));
        let (a, b) = r
            .segment((-1e3, -1e3), (1e3, 1e3))
            .expect("diagonal crosses");
        assert!(
            (a.0 + 64.0).abs() < 1e-9 && (a.1 + 64.0).abs() < 1e-9,
            "{a:?}"
        );
        assert!(
            (b.0 - 164.0).abs() < 1e-9 && (b.1 - 164.0).abs() < 1e-9,
            "{b:?}"
        );
        // Ends at ±1e20 are known only to about 1e4 pixels (their ulp), so the exact
        // crossing is not defined; what matters is that the result stays on the line
        // and inside the guard band, where the rasteriser is safe.
        let (a, b) = r
            .segment((-1e20, -1e20), (1e20, 1e20))
            .expect("diagonal crosses");
        for p in [a, b] {
            assert!(r.contains(p.0, p.1) && p.0 == p.1, "{p:?}");
        }
    }

    #[test]
    fn segments_outside_or_not_finite_vanish() {
        let r = ClipRect::guard(100, 100);
        assert_eq!(r.segment((-1000.0, 0.0), (-500.0, 50.0)), None);
        assert_eq!(r.segment((0.0, 0.0), (f64::NAN, 5.0)), None);
        assert_eq!(r.segment((0.0, 0.0), (f64::INFINITY, 5.0)), None);
    }

    #[test]
    fn far_away_ends_never_come_back_outside_the_rectangle() {
        let r = ClipRect::guard(64, 48);
        // Ends near 1e50 pixels, as a body about to blow up produces: whatever survives
        // the clip must lie inside the guard band.
        let ends = [
            ((1e50, 1e50), (1.00001e50, -0.9e50)),
            ((-3.3e49, 2e50), (4e50, -1e49)),
            ((5.0, 5.0), (-7e300, 3e299)),
        ];
        for (a, b) in ends {
            if let Some((c, d)) = r.segment(a, b) {
                for p in [c, d] {
                    assert!(r.contains(p.0, p.1), "{a:?}-{b:?} clipped to {p:?}");
                }
            }
        }
    }

    #[test]
    fn a_polyline_leaving_and_returning_becomes_two_pieces_within_the_guard() {
        let r = ClipRect::guard(100, 100);
        let path = r
            .polyline([(10.0, 10.0), (1e9, 10.0), (1e9, 20.0), (10.0, 20.0)])
            .expect("a path");
        let b = path.bounds();
        assert!(b.right() <= 164.0 && b.left() >= 10.0, "{b:?}");
    }
}
