//! The polygons of strokes as tiny-skia's stroker builds them: a line's rectangle, a
//! line with round caps, and the ring of a convex outline's stroke.

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
