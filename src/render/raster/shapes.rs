//! The polygons of strokes as tiny-skia's stroker builds them: a line's rectangle, a
//! line with round caps, and the ring of a convex outline's stroke; and a disc too
//! large to stamp, as polygons on tiny-skia's curve for its circle.

use tiny_skia::{PathBuilder, PathSegment};

use super::{signed_area, Point};

/// Returns the rectangle that tiny-skia's stroker makes of a line from `a` to `b` with
/// butt caps and half-width `h`, computed as it computes it (in f32, with its own
/// normalisation), or nothing when the line has no direction.
pub fn bar(a: Point, b: Point, h: f32) -> Option<[Point; 4]> {
    let mut unit = tiny_skia::Point::zero();
    if !unit.set_normalize(b.0 - a.0, b.1 - a.1) {
        return None;
    }
    // The unit normal turned counter-clockwise, (x, y) -> (y, -x), times the radius.
    let (nx, ny) = (unit.y * h, -unit.x * h);
    Some([
        (a.0 + nx, a.1 + ny),
        (b.0 + nx, b.1 + ny),
        (b.0 - nx, b.1 - ny),
        (a.0 - nx, a.1 - ny),
    ])
}

/// The largest angle, in radians, of the chords that a round join or cap is cut into:
/// 30°, so that a chord lies within r·(1 - cos 15°) < 0.035·r of its arc (under 0.026
/// pixel for an outline's 0.75-pixel half-width, a tenth of a quarter-pixel sample).
const CHORD: f64 = std::f64::consts::PI / 6.0;

/// Appends the arc of radius `r` around `centre` from angle `from` to angle `to`
/// (radians, the shorter way round), cut into chords of at most [`CHORD`].
fn arc(out: &mut Vec<Point>, centre: (f64, f64), r: f64, from: f64, to: f64) {
    let mut sweep = to - from;
    while sweep > std::f64::consts::PI {
        sweep -= std::f64::consts::TAU;
    }
    while sweep < -std::f64::consts::PI {
        sweep += std::f64::consts::TAU;
    }
    // A quarter turn is three chords, not four for a rounding error in the division.
    let steps = (sweep.abs() / CHORD - 1e-9).ceil().max(1.0) as usize;
    for k in 0..=steps {
        let t = from + sweep * k as f64 / steps as f64;
        out.push((
            (centre.0 + r * t.cos()) as f32,
            (centre.1 + r * t.sin()) as f32,
        ));
    }
}

/// The turns of a round cap's chord ends from the line's direction, in steps of
/// [`CHORD`] from -90° to +90°, as (cos, sin).
const CAP: [(f64, f64); 7] = [
    (0.0, -1.0),
    (0.5, -0.866_025_403_784_438_6),
    (0.866_025_403_784_438_6, -0.5),
    (1.0, 0.0),
    (0.866_025_403_784_438_6, 0.5),
    (0.5, 0.866_025_403_784_438_6),
    (0.0, 1.0),
];

/// Returns the outline of the disc of radius `r` swept along the segment from `a` to
/// `b`: a line with round caps, each cap's half circle cut into six 30° chords.
pub fn capsule(a: (f64, f64), b: (f64, f64), r: f64, out: &mut Vec<Point>) {
    out.clear();
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = (dx * dx + dy * dy).sqrt();
    // The unit direction (any, for a dot) and the cap's points turned from it.
    let (ux, uy) = if len > 0.0 {
        (dx / len, dy / len)
    } else {
        (1.0, 0.0)
    };
    for (centre, sign) in [(b, 1.0), (a, -1.0)] {
        for (c, s) in CAP {
            let (x, y) = (sign * (ux * c - uy * s), sign * (uy * c + ux * s));
            out.push(((centre.0 + r * x) as f32, (centre.1 + r * y) as f32));
        }
    }
}

/// The two sides of a convex polygon's outline stroked `r` pixels each way with round
/// joins: the outer side (the polygon grown by `r`, its corners rounded) and the inner
/// one (the polygon shrunk by `r`), or no inner side when the polygon is too thin to
/// have one. The stroke covers what lies inside the first and outside the second.
#[derive(Clone, Debug)]
pub struct Ring {
    pub outer: Vec<Point>,
    pub inner: Option<Vec<Point>>,
}

impl Ring {
    /// Returns the ring of a convex polygon's outline, or `None` when the polygon is
    /// not convex (or has no area).
    pub fn of_convex(points: &[Point], r: f64) -> Option<Ring> {
        // Repeated points (a closing point equal to the first, say) make no edge.
        let mut p: Vec<(f64, f64)> = Vec::with_capacity(points.len());
        for &(x, y) in points {
            let q = (f64::from(x), f64::from(y));
            if p.last() != Some(&q) {
                p.push(q);
            }
        }
        while p.len() > 1 && p.first() == p.last() {
            p.pop();
        }
        let n = p.len();
        if n < 3 {
            return None;
        }
        let area: f64 = (0..n)
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % n]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum();
        if area == 0.0 || !area.is_finite() {
            return None;
        }
        // With the area's sign s, the outward normal of the edge a -> b is
        // s·(dy, -dx)/|d| in these (y-down) coordinates; a convex polygon turns the
        // same way at every corner.
        let s = area.signum();
        let mut normals = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (p[i], p[(i + 1) % n]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len = (dx * dx + dy * dy).sqrt();
            if len == 0.0 {
                return None;
            }
            normals.push((s * dy / len, -s * dx / len));
        }
        for i in 0..n {
            let (m, k) = (normals[(i + n - 1) % n], normals[i]);
            // The cross product of consecutive normals has the same sign at every
            // corner of a convex polygon.
            if s * (m.0 * k.1 - m.1 * k.0) < -1e-12 {
                return None;
            }
        }
        let mut outer = Vec::with_capacity(n * 8);
        for i in 0..n {
            let (m, k) = (normals[(i + n - 1) % n], normals[i]);
            arc(&mut outer, p[i], r, m.1.atan2(m.0), k.1.atan2(k.0));
        }
        // The inner side: the polygon cut by every edge moved inward by r.
        let mut inner = p.clone();
        let corners = p;
        for i in 0..n {
            let (a, k) = (corners[i], normals[i]);
            // Keep the points q with k·(q - a) ≤ -r.
            let keep = |q: (f64, f64)| k.0 * (q.0 - a.0) + k.1 * (q.1 - a.1) + r;
            inner = clip(&inner, keep);
            if inner.len() < 3 {
                break;
            }
        }
        let inner = (inner.len() >= 3)
            .then(|| inner.iter().map(|&(x, y)| (x as f32, y as f32)).collect())
            .filter(|i: &Vec<Point>| signed_area(i).abs() > 1e-9)
            .map(|mut i| {
                // Wound against the outer side, so that the nonzero rule leaves it out.
                if signed_area(&i) * signed_area(&outer) > 0.0 {
                    i.reverse();
                }
                i
            });
        Some(Ring { outer, inner })
    }
}

/// Keeps the part of a convex polygon where `f` ≤ 0 (Sutherland–Hodgman against one
/// line; `f` is affine).
fn clip(points: &[(f64, f64)], f: impl Fn((f64, f64)) -> f64) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(points.len() + 1);
    for i in 0..points.len() {
        let (a, b) = (points[i], points[(i + 1) % points.len()]);
        let (fa, fb) = (f(a), f(b));
        if fa <= 0.0 {
            out.push(a);
        }
        if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
            let t = fa / (fa - fb);
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    out
}

/// The farthest, in pixels, that the polygon of [`disc`] lies from the curve
/// of tiny-skia's circle.
pub const DISC_POLYGON_TOLERANCE: f32 = 1.0 / 32.0;

/// Returns the polygon that stands for the circle of radius `r` pixels centred on the
/// origin, for the scan converter, and the polygons `w` outside and inside it, the
/// sides of its stroke's ring: points on the curve tiny-skia fills for the circle
/// (`PathBuilder::from_circle`: four conics turned into quadratic Béziers within 1/4
/// pixel of the circle), each quadratic cut into as many chords as keep every chord
/// within [`DISC_POLYGON_TOLERANCE`] of it, and those points moved w along the radius
/// out and in. A quadratic's chords of m equal steps in t lie within |p0 - 2·p1 +
/// p2|/(4·m²) of it, so m = ⌈√(|p0 - 2·p1 + p2| / (4·tolerance))⌉. `None` when the
/// circle has no path (a radius that is not positive and finite) or when w ≥ r.
pub fn disc(r: f32, w: f32) -> Option<[Vec<Point>; 3]> {
    // A NaN radius or width fails this too.
    if w.partial_cmp(&r) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let path = PathBuilder::from_circle(0.0, 0.0, r)?;
    let mut fill: Vec<Point> = Vec::new();
    let mut last = (0.0f32, 0.0f32);
    for segment in path.segments() {
        match segment {
            PathSegment::MoveTo(p) | PathSegment::LineTo(p) => {
                last = (p.x, p.y);
                fill.push(last);
            }
            PathSegment::QuadTo(c, p) => {
                let (dx, dy) = (last.0 - 2.0 * c.x + p.x, last.1 - 2.0 * c.y + p.y);
                let bend = (dx * dx + dy * dy).sqrt();
                let m = (bend / (4.0 * DISC_POLYGON_TOLERANCE))
                    .sqrt()
                    .ceil()
                    .max(1.0) as usize;
                for k in 1..=m {
                    // B(t) = (1 - t)²·p0 + 2t(1 - t)·p1 + t²·p2.
                    let t = k as f32 / m as f32;
                    let (a, b, e) = ((1.0 - t) * (1.0 - t), 2.0 * t * (1.0 - t), t * t);
                    fill.push((
                        a * last.0 + b * c.x + e * p.x,
                        a * last.1 + b * c.y + e * p.y,
                    ));
                }
                last = (p.x, p.y);
            }
            // A circle's path holds neither.
            PathSegment::CubicTo(..) | PathSegment::Close => {}
        }
    }
    // The contour ends where it began.
    if fill.len() > 1 && fill.first() == fill.last() {
        fill.pop();
    }
    let moved = |d: f32| -> Vec<Point> {
        fill.iter()
            .map(|&(x, y)| {
                let k = 1.0 + d / (x * x + y * y).sqrt();
                (k * x, k * y)
            })
            .collect()
    };
    let (outer, inner) = (moved(w), moved(-w));
    Some([fill, outer, inner])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The disc's polygon lies on tiny-skia's curve for the circle, which is within a
    /// quarter pixel of the circle, its chords within the tolerance; the ring's sides
    /// lie the half-width out and in; all three are convex (the scan converter's
    /// chains need it); and the corners grow as √r, not as r.
    #[test]
    fn a_discs_polygons_follow_its_circle() {
        let mut counts = Vec::new();
        for r in [24.5f32, 60.0, 400.0, 2000.0] {
            let [fill, outer, inner] = disc(r, 0.75).expect("a disc");
            let distance = |p: &Point| f64::from(p.0).hypot(f64::from(p.1));
            let quarter = 0.25 + f64::from(DISC_POLYGON_TOLERANCE);
            for (points, radius) in [(&fill, r), (&outer, r + 0.75), (&inner, r - 0.75)] {
                for p in points.iter() {
                    let d = distance(p);
                    // A quarter pixel, and the f32 rounding of coordinates near r.
                    assert!(
                        (d - f64::from(radius)).abs() <= 0.25 + 1e-5 * f64::from(r),
                        "r = {r}: a corner at {d} for {radius}"
                    );
                }
                // A chord's middle is no farther inside than the tolerance allows.
                for (k, a) in points.iter().enumerate() {
                    let b = points[(k + 1) % points.len()];
                    let middle = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
                    assert!(distance(&middle) >= f64::from(radius) - quarter - 1e-3);
                }
                assert!(
                    super::super::Ring::of_convex(points, 0.5).is_some(),
                    "r = {r}: convex"
                );
            }
            assert_eq!((fill.len(), inner.len()), (outer.len(), outer.len()));
            counts.push(fill.len() as f64);
        }
        // 24.5 → 2000 is 82 times the radius: about 9 times the corners.
        let growth = counts[3] / counts[0];
        assert!((5.0..15.0).contains(&growth), "{counts:?}");
        assert!(disc(0.5, 0.75).is_none() && disc(f32::NAN, 0.75).is_none());
    }
}
