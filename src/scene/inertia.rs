//! Moments of inertia of a body's shape about its centre of mass, for uniform density
//! (or the point masses themselves): what makes a torque turn a body fast or slowly,
//! α = τ/I.

use super::Shape;

impl Shape {
    /// Returns the moment of inertia about the centre of mass of a body of mass `mass`
    /// with this shape, whose points are relative to the centre of mass:
    ///
    /// - a disc of radius r: I = M·r²/2;
    /// - a box w × h: I = M·(w² + h²)/12;
    /// - a polygon, as a uniform plate: with c_i = x_i·y_{i+1} - x_{i+1}·y_i, area
    ///   A = ½·Σ c_i and density ρ = M/A, I = (ρ/12)·Σ c_i·(x_i² + x_i·x_{i+1} +
    ///   x_{i+1}² + y_i² + y_i·y_{i+1} + y_{i+1}²), taken here about the centroid
    ///   itself, where the vertices are (so no parallel-axis correction is needed);
    ///   either winding gives the same I, since A and every c_i change sign together;
    /// - point masses: I = Σ m_i·|r_i - r_CM|², `mass` being their sum.
    pub fn inertia(&self, mass: f64) -> f64 {
        match self {
            // I = M·r²/2.
            Shape::Circle { radius } => 0.5 * mass * radius * radius,
            // I = M·(w² + h²)/12.
            Shape::Box { width, height } => mass * (width * width + height * height) / 12.0,
            Shape::Polygon { points } => {
                let n = points.len();
                let (mut twice_area, mut sum) = (0.0, 0.0);
                for i in 0..n {
                    let (p, q) = (points[i], points[(i + 1) % n]);
                    // c_i = x_i·y_{i+1} - x_{i+1}·y_i.
                    let c = p.x * q.y - q.x * p.y;
                    twice_area += c;
                    sum +=
                        c * (p.x * p.x + p.x * q.x + q.x * q.x + p.y * p.y + p.y * q.y + q.y * q.y);
                }
                // I = (ρ/12)·Σ c_i·(…), ρ = M/A = 2M/(2A).
                (2.0 * mass / twice_area) * sum / 12.0
            }
            // I = Σ m_i·|r_i - r_CM|², the offsets being from the centre of mass.
            Shape::Points { points } => points
                .iter()
                .map(|p| p.mass * p.offset.length_squared())
                .sum(),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;
    use crate::scene::PointMass;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-14 * b.abs()
    }

    #[test]
    fn every_shape_gives_its_formula() {
        let m = 3.0;
        assert!(close(
            Shape::Circle { radius: 0.5 }.inertia(m),
            m * 0.25 / 2.0
        ));
        let b = Shape::Box {
            width: 2.0,
            height: 0.5,
        };
        assert!(close(b.inertia(m), m * (4.0 + 0.25) / 12.0));
        // The unit square about its centre, as a polygon in either winding, is the box.
        let square: Vec<DVec2> = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .iter()
            .map(|&(x, y)| DVec2::new(x, y))
            .collect();
        let ccw = Shape::Polygon {
            points: square.clone(),
        };
        let cw = Shape::Polygon {
            points: square.into_iter().rev().collect(),
        };
        assert!(close(ccw.inertia(m), m / 6.0));
        assert!(close(cw.inertia(m), m / 6.0));
        // A right triangle with legs a and b about its centroid: M·(a² + b²)/18.
        let (a, bl) = (3.0, 1.5);
        let centroid = DVec2::new(a / 3.0, bl / 3.0);
        let tri = Shape::Polygon {
            points: [DVec2::ZERO, DVec2::new(a, 0.0), DVec2::new(0.0, bl)]
                .iter()
                .map(|p| *p - centroid)
                .collect(),
        };
        assert!(close(tri.inertia(m), m * (a * a + bl * bl) / 18.0));
        // Two point masses 1 and 3 at distance 2: I = μ·d² with μ = 1·3/(1 + 3).
        let dumbbell = Shape::Points {
            points: vec![
                PointMass {
                    offset: DVec2::new(-1.5, 0.0),
                    mass: 1.0,
                },
                PointMass {
                    offset: DVec2::new(0.5, 0.0),
                    mass: 3.0,
                },
            ],
        };
        assert!(close(dumbbell.inertia(4.0), 0.75 * 4.0));
    }
}
