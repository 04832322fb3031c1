//! The shape of a body that collides: a disc or a convex polygon, in coordinates whose
//! origin is the body's centre of mass and which turn with the body.
//!
//! A body at centre of mass r and angle θ has its shape point q at r + R(θ)·q in the
//! world. Boxes are convex polygons of four vertices. Everything here is geometry of
//! one shape at one pose; what two shapes do to each other is in `narrow_phase.rs`.

use glam::DVec2;
use parry2d_f64::shape::{Ball, ConvexPolygon, Cuboid};

use crate::sim::rigid::rotate;

/// A body's shape as the contact stages see it.
#[derive(Clone, Debug)]
pub enum ColliderShape {
    /// A disc of this radius about the centre of mass.
    Disc { radius: f64 },
    /// A convex polygon: vertices counter-clockwise, relative to the centre of mass,
    /// and the same polygon as parry's shape for its contact queries.
    Convex {
        points: Vec<DVec2>,
        shape: Box<ConvexPolygon>,
        /// The same shape as parry's box, when it is one (its half-extents).
        cuboid: Option<Cuboid>,
    },
}

/// One colliding body: which body it is, its shape, and the sizes the stages use.
#[derive(Clone, Debug)]
pub struct Collider {
    /// The body's index in the simulation's arrays.
    pub body: usize,
    /// Its shape about its centre of mass.
    pub shape: ColliderShape,
    /// The distance from the centre of mass to the farthest point of the shape: no
    /// point of the body moves faster than |v| + |ω|·reach.
    pub reach: f64,
    /// The body's smallest width (a disc's diameter; a polygon's least distance between
    /// two parallel lines that hold it), from which the default tolerance is taken.
    pub size: f64,
    /// The coefficient of restitution the body asks for (the scene's unless it gives
    /// its own).
    pub restitution: f64,
    /// The friction coefficient the body asks for (the scene's unless it gives its
    /// own); a pair uses √(μ_a·μ_b).
    pub friction: f64,
}

/// Why a polygon cannot collide.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PolygonProblem {
    /// Fewer than three distinct vertices, or no area.
    Degenerate,
    /// A vertex turns the other way from the rest: the polygon is not convex.
    NotConvex,
}

impl std::fmt::Display for PolygonProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            PolygonProblem::Degenerate => "degenerate (no area)",
            PolygonProblem::NotConvex => "not convex",
        })
    }
}

/// Returns why a polygon cannot collide, or `None` when it is convex.
pub fn convexity_problem(points: &[DVec2]) -> Option<PolygonProblem> {
    convexity(points).err()
}

impl Collider {
    /// Returns the collider with friction coefficient μ.
    pub fn with_friction(mut self, mu: f64) -> Self {
        self.friction = mu;
        self
    }

    /// Returns the collider of a disc.
    pub fn disc(body: usize, radius: f64, restitution: f64) -> Self {
        Collider {
            body,
            shape: ColliderShape::Disc { radius },
            reach: radius,
            size: 2.0 * radius,
            restitution,
            friction: 0.0,
        }
    }

    /// Returns the collider of a box of width w and height h centred on its centre of
    /// mass, or why it cannot collide (sides so small or so unequal that its area
    /// rounds to nothing).
    pub fn rectangle(
        body: usize,
        width: f64,
        height: f64,
        restitution: f64,
    ) -> Result<Self, PolygonProblem> {
        let (x, y) = (0.5 * width, 0.5 * height);
        let points = vec![
            DVec2::new(-x, -y),
            DVec2::new(x, -y),
            DVec2::new(x, y),
            DVec2::new(-x, y),
        ];
        let mut c = Self::polygon(body, points, restitution)?;
        if let ColliderShape::Convex { cuboid, .. } = &mut c.shape {
            *cuboid = Some(Cuboid::new(to_parry(DVec2::new(x, y))));
        }
        Ok(c)
    }

    /// Returns the collider of a convex polygon whose vertices are given relative to
    /// its centre of mass, in either turning order, or why it cannot collide.
    pub fn polygon(
        body: usize,
        mut points: Vec<DVec2>,
        restitution: f64,
    ) -> Result<Self, PolygonProblem> {
        if convexity(&points)? < 0.0 {
            points.reverse();
        }
        let parry_points = points.iter().map(|p| to_parry(*p)).collect();
        let shape =
            ConvexPolygon::from_convex_polyline(parry_points).ok_or(PolygonProblem::Degenerate)?;
        let reach = points.iter().map(|p| p.length()).fold(0.0, f64::max);
        let size = min_width(&points);
        Ok(Collider {
            body,
            shape: ColliderShape::Convex {
                points,
                shape: Box::new(shape),
                cuboid: None,
            },
            reach,
            size,
            restitution,
            friction: 0.0,
        })
    }

    /// Returns the world bounding box (min, max) of the shape with its centre of mass
    /// at `r`, turned by θ given as (sin θ, cos θ).
    pub fn aabb(&self, r: DVec2, sin_cos: (f64, f64)) -> (DVec2, DVec2) {
        match &self.shape {
            ColliderShape::Disc { radius } => (r - *radius, r + *radius),
            ColliderShape::Convex { points, .. } => {
                let mut lo = DVec2::splat(f64::INFINITY);
                let mut hi = DVec2::splat(f64::NEG_INFINITY);
                for p in points {
                    let w = r + rotate(sin_cos, *p);
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
                (lo, hi)
            }
        }
    }

    /// Returns parry's disc for a disc collider.
    pub(super) fn ball(&self) -> Option<Ball> {
        match self.shape {
            ColliderShape::Disc { radius } => Some(Ball::new(radius)),
            ColliderShape::Convex { .. } => None,
        }
    }
}

/// Returns the sign of a polygon's turning (+1 counter-clockwise, -1 clockwise), or why
/// it is not a convex polygon: every corner must turn the same way (a straight corner,
/// cross product zero, turns neither way and is allowed).
pub fn convexity(points: &[DVec2]) -> Result<f64, PolygonProblem> {
    let n = points.len();
    if n < 3 {
        return Err(PolygonProblem::Degenerate);
    }
    let mut sign = 0.0;
    let mut area2 = 0.0;
    for i in 0..n {
        let (a, b, c) = (points[i], points[(i + 1) % n], points[(i + 2) % n]);
        // The turn at b: (b - a)⊥·(c - b), positive for a left (counter-clockwise) turn.
        let turn = (b - a).perp_dot(c - b);
        area2 += a.perp_dot(b);
        if turn != 0.0 {
            if sign == 0.0 {
                sign = turn.signum();
            } else if turn.signum() != sign {
                return Err(PolygonProblem::NotConvex);
            }
        }
    }
    // A convex polygon turns once around: its corners' turns agree with its area's
    // sign. A star whose every corner turns left winds twice and is caught here by the
    // total of its exterior angles, checked as the edges' directions going once round.
    if sign == 0.0 || area2 == 0.0 || area2.signum() != sign || winds_more_than_once(points) {
        return Err(if sign == 0.0 || area2 == 0.0 {
            PolygonProblem::Degenerate
        } else {
            PolygonProblem::NotConvex
        });
    }
    Ok(sign)
}

/// Returns true when the edges' directions go round more than once (a pentagram, say),
/// which no simple convex polygon does: the sum of the angles turned at the corners is
/// ±2π for a convex polygon and ±4π or more for a star.
fn winds_more_than_once(points: &[DVec2]) -> bool {
    let n = points.len();
    let mut total = 0.0;
    for i in 0..n {
        let (a, b, c) = (points[i], points[(i + 1) % n], points[(i + 2) % n]);
        let (u, v) = (b - a, c - b);
        total += u.perp_dot(v).atan2(u.dot(v));
    }
    total.abs() > 3.0 * std::f64::consts::PI
}

/// Returns the least width of a convex polygon: for each edge, the farthest vertex's
/// distance from that edge's line; the least over edges (the least width of a convex
/// polygon is reached with one side of the strip along an edge).
fn min_width(points: &[DVec2]) -> f64 {
    let n = points.len();
    let mut least = f64::INFINITY;
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        let edge = b - a;
        let len = edge.length();
        if len == 0.0 {
            continue;
        }
        // The distance of p from the line through a along `edge`: |edge⊥·(p - a)|/|edge|.
        let far = points
            .iter()
            .map(|p| (edge.perp_dot(*p - a) / len).abs())
            .fold(0.0, f64::max);
        least = least.min(far);
    }
    least
}

/// Converts a vector to parry's type (the same numbers in another crate's glam).
#[inline(always)]
pub(super) fn to_parry(v: DVec2) -> parry2d_f64::math::Vector {
    parry2d_f64::math::Vector::new(v.x, v.y)
}

/// Converts a vector from parry's type.
#[inline(always)]
pub(super) fn from_parry(v: parry2d_f64::math::Vector) -> DVec2 {
    DVec2::new(v.x, v.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polygons_are_checked_for_convexity_and_turned_counter_clockwise() {
        let square_cw = vec![
            DVec2::new(-1.0, -1.0),
            DVec2::new(-1.0, 1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, -1.0),
        ];
        let c = Collider::polygon(0, square_cw, 1.0).expect("a square is convex");
        let ColliderShape::Convex { points, .. } = &c.shape else {
            panic!("a polygon collider is convex");
        };
        assert!(convexity(points).expect("convex") > 0.0);
        assert_eq!(c.size, 2.0);
        assert!((c.reach - 2f64.sqrt()).abs() < 1e-15);
        let arrow = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(0.0, 2.0),
            DVec2::new(0.5, 1.0),
        ];
        assert_eq!(convexity(&arrow), Err(PolygonProblem::NotConvex));
        let star: Vec<DVec2> = (0..5)
            .map(|k| {
                let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
                DVec2::new(a.cos(), a.sin())
            })
            .collect();
        assert_eq!(convexity(&star), Err(PolygonProblem::NotConvex));
        let line = vec![DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)];
        assert_eq!(convexity(&line), Err(PolygonProblem::Degenerate));
    }

    #[test]
    fn a_turned_box_has_the_bounding_box_of_its_turned_corners() {
        let c = Collider::rectangle(0, 2.0, 1.0, 1.0).expect("a box");
        let quarter = std::f64::consts::FRAC_PI_2.sin_cos();
        let (lo, hi) = c.aabb(DVec2::new(10.0, 0.0), quarter);
        assert!((lo - DVec2::new(9.5, -1.0)).length() < 1e-15);
        assert!((hi - DVec2::new(10.5, 1.0)).length() < 1e-15);
        assert_eq!(c.size, 1.0);
    }
}
