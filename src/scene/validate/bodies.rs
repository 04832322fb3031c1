//! `[[body]]` tables: mass, shape or point masses, position, velocity, angle and
//! spin, the moment of inertia, the colour; and the checks that need every body.

use std::collections::HashMap;
use std::ops::Range;

use glam::DVec2;
use toml::Spanned;

use super::Validator;
use crate::numbers::Readable;
use crate::scene::raw::{RawBody, RawShape};
use crate::scene::MAX_SHAPE_PIXELS;
use crate::scene::{Body, Diagnostic, PointMass, RenderSettings, Rgba, Shape, View};

impl Validator {
    pub(super) fn bodies(
        &mut self,
        raw: &[Spanned<RawBody>],
        view: Option<View>,
    ) -> Option<Vec<Body>> {
        let mut seen: HashMap<String, Range<usize>> = HashMap::new();
        let mut bodies = Vec::with_capacity(raw.len());
        let mut ok = true;
        // The default radius: 1.5% of the view's smaller side, so a body is visible
        // whatever the scale of the world.
        let default_radius = view.map_or(0.1, |v| 0.015 * (v.max - v.min).min_element());
        for (i, rb) in raw.iter().enumerate() {
            match self.body(i, rb, default_radius) {
                Some(body) => {
                    let span = rb.get_ref().name.as_ref().map_or(rb.span(), |n| n.span());
                    if seen.contains_key(&body.name) {
                        self.error(
                            Diagnostic::at(span, format!("two bodies are named `{}`", body.name))
                                .label("a second body with this name")
                                .hint("forces name bodies, so each name must be unique"),
                        );
                        ok = false;
                    } else {
                        seen.insert(body.name.clone(), span);
                    }
                    bodies.push(body);
                }
                None => ok = false,
            }
        }
        ok.then_some(bodies)
    }

    pub(super) fn body(
        &mut self,
        i: usize,
        raw: &Spanned<RawBody>,
        default_radius: f64,
    ) -> Option<Body> {
        let b = raw.get_ref();
        let name = b
            .name
            .as_ref()
            .map_or_else(|| format!("body{i}"), |n| n.get_ref().clone());
        let position = match &b.position {
            Some(p) => self.vec2(p, "position"),
            None => Some(DVec2::ZERO),
        };
        let velocity = match &b.velocity {
            Some(v) => self.vec2(v, "velocity"),
            None => Some(DVec2::ZERO),
        };
        let color = match &b.color {
            Some(c) => self.color(c),
            None => Some(Rgba::palette(i)),
        };
        let fixed = b.fixed.as_ref().is_some_and(|f| *f.get_ref());
        let restitution = b.restitution.as_ref().map(|e| self.restitution(e));
        let friction = match b
            .friction
            .as_ref()
            .map(|m| self.non_negative(m, "friction"))
        {
            None => None,
            Some(Some(m)) => Some(m),
            Some(None) => return None,
        };
        if fixed {
            return self
                .static_body(raw, name, default_radius, color?, restitution)
                .map(|b| Body { friction, ..b });
        }
        // The mass and the shape come together: either `mass` with an optional `shape`,
        // or `points`, from which both follow (Equations 7-11).
        let mass_and_shape = match (&b.mass, &b.points) {
            (Some(m), Some(p)) => {
                self.error(
                    Diagnostic::at(
                        p.span(),
                        format!("body `{name}` has both `mass` and `points`"),
                    )
                    .label("the mass of a body of points is the sum of its points' masses")
                    .hint(format!("remove `mass = {}` or `points`", m.get_ref())),
                );
                None
            }
            (None, None) => {
                self.error(
                    Diagnostic::at(raw.span(), format!("body `{name}` has no mass"))
                        .hint("add `mass = 1.0` (or `points = [...]` for a body of point masses)"),
                );
                None
            }
            (Some(m), None) => {
                let mass = self.positive(m, "mass");
                let shape = match &b.shape {
                    Some(s) => self.shape(s),
                    None => Some((
                        Shape::Circle {
                            radius: default_radius,
                        },
                        DVec2::ZERO,
                    )),
                };
                mass.zip(shape)
            }
            (None, Some(points)) => {
                if let Some(s) = &b.shape {
                    self.error(
                        Diagnostic::at(
                            s.span(),
                            format!("body `{name}` has both `shape` and `points`"),
                        )
                        .hint("a body of point masses is drawn as its points; remove `shape`"),
                    );
                    None
                } else {
                    self.point_masses(points)
                }
            }
        };
        let angle = b
            .angle
            .as_ref()
            .map_or(Some(0.0), |a| self.finite(a, "angle"));
        let angular_velocity = b
            .angular_velocity
            .as_ref()
            .map_or(Some(0.0), |w| self.finite(w, "angular_velocity"));
        let inertia = b.inertia.as_ref().map(|i| self.positive(i, "inertia"));
        let (mass, (shape, centroid)) = mass_and_shape?;
        let angle = angle?;
        let inertia = match inertia {
            Some(given) => given?,
            None => self.shape_inertia(raw.span(), &name, &shape, mass)?,
        };
        Some(Body {
            name,
            mass,
            // The centre of mass sits at `position` plus the centroid of the shape or of
            // the point masses (Equation 8), turned with the body: r = p + R(θ)·c.
            position: position? + turned(angle, centroid),
            velocity: velocity?,
            angle,
            angular_velocity: angular_velocity?,
            inertia,
            centre: centroid,
            turns: false,
            shape,
            color: color?,
            show_velocity: b.show_velocity.as_ref().is_some_and(|s| *s.get_ref()),
            show_force: b.show_force.as_ref().is_some_and(|s| *s.get_ref()),
            is_static: false,
            restitution: match restitution {
                Some(e) => Some(e?),
                None => None,
            },
            friction,
        })
    }

    /// A body with `static = true`: immovable, so it has no mass, velocity, spin or
    /// moment of inertia to give (each is an error), only a shape, a place and an angle.
    fn static_body(
        &mut self,
        raw: &Spanned<RawBody>,
        name: String,
        default_radius: f64,
        color: Rgba,
        restitution: Option<Option<f64>>,
    ) -> Option<Body> {
        let b = raw.get_ref();
        let mut ok = true;
        let given = [
            ("mass", b.mass.as_ref().map(|m| m.span())),
            ("velocity", b.velocity.as_ref().map(|v| v.span())),
            (
                "angular_velocity",
                b.angular_velocity.as_ref().map(|w| w.span()),
            ),
            ("inertia", b.inertia.as_ref().map(|m| m.span())),
            ("points", b.points.as_ref().map(|p| p.span())),
        ];
        for (key, span) in given {
            if let Some(span) = span {
                self.error(
                    Diagnostic::at(span, format!("static body `{name}` cannot have `{key}`"))
                        .label("a static body never moves: its mass and moment of inertia are infinite")
                        .hint(format!("remove `{key}`, or `static = true` to make the body move")),
                );
                ok = false;
            }
        }
        let position = match &b.position {
            Some(p) => self.vec2(p, "position"),
            None => Some(DVec2::ZERO),
        };
        let angle = b
            .angle
            .as_ref()
            .map_or(Some(0.0), |a| self.finite(a, "angle"));
        let shape = match &b.shape {
            Some(s) => self.shape(s),
            None => Some((
                Shape::Circle {
                    radius: default_radius,
                },
                DVec2::ZERO,
            )),
        };
        let (shape, centroid) = shape?;
        let (angle, position) = (angle?, position?);
        let restitution = match restitution {
            Some(e) => Some(e?),
            None => None,
        };
        ok.then(|| Body {
            name,
            // 1/M = 0 and 1/I = 0: the system reads a mass of 0 as immovable.
            mass: 0.0,
            inertia: 0.0,
            position: position + turned(angle, centroid),
            velocity: DVec2::ZERO,
            angle,
            angular_velocity: 0.0,
            centre: centroid,
            turns: false,
            shape,
            color,
            show_velocity: b.show_velocity.as_ref().is_some_and(|s| *s.get_ref()),
            show_force: b.show_force.as_ref().is_some_and(|s| *s.get_ref()),
            is_static: true,
            restitution,
            friction: None,
        })
    }

    /// Returns the moment of inertia of a shape of mass `mass`, or reports one too large
    /// to be a number (a huge mass and size), or negative (an outline that crosses
    /// itself), at the body or swarm (`span`).
    pub(super) fn shape_inertia(
        &mut self,
        span: Range<usize>,
        name: &str,
        shape: &Shape,
        mass: f64,
    ) -> Option<f64> {
        let inertia = shape.inertia(mass);
        if inertia.is_finite() && inertia >= 0.0 {
            return Some(inertia);
        }
        if inertia < 0.0 {
            // Found by the mutated-scene tests: the plate formula's signed terms sum
            // to a negative moment for an outline that crosses itself.
            self.error(
                Diagnostic::at(
                    span,
                    format!("the polygon of body `{name}` crosses itself"),
                )
                .label(format!("its moment of inertia comes out as {}", Readable(inertia)))
                .hint("list the points in order around the outline, without crossings, or give `inertia` yourself"),
            );
            return None;
        }
        self.error(
            Diagnostic::at(
                span,
                format!("the moment of inertia of body `{name}` is too large to compute"),
            )
            .label(format!("M·r² overflows: {inertia}"))
            .hint("use smaller units, or give `inertia` yourself"),
        );
        None
    }

    /// Returns the shape, with vertices relative to its centroid, and that centroid
    /// relative to the body's `position`.
    pub(super) fn shape(&mut self, raw: &Spanned<RawShape>) -> Option<(Shape, DVec2)> {
        let s = raw.get_ref();
        let given = [s.circle.is_some(), s.rect.is_some(), s.polygon.is_some()];
        if given.iter().filter(|g| **g).count() != 1 {
            self.error(
                Diagnostic::at(
                    raw.span(),
                    "a shape must be exactly one of `circle`, `box` or `polygon`",
                )
                .hint("e.g. shape = { circle = { radius = 0.2 } }"),
            );
            return None;
        }
        if let Some(c) = &s.circle {
            let radius = self.positive(&c.get_ref().radius, "radius")?;
            return Some((Shape::Circle { radius }, DVec2::ZERO));
        }
        if let Some(b) = &s.rect {
            let width = self.positive(&b.get_ref().width, "width");
            let height = self.positive(&b.get_ref().height, "height");
            return Some((
                Shape::Box {
                    width: width?,
                    height: height?,
                },
                DVec2::ZERO,
            ));
        }
        let polygon = s.polygon.as_ref()?;
        let points_raw = &polygon.get_ref().points;
        let mut points = Vec::new();
        for p in points_raw.get_ref() {
            points.push(self.vec2(p, "polygon point")?);
        }
        let (area, centroid) = polygon_area_centroid(&points);
        if points.len() < 3 || area == 0.0 || !area.is_finite() || !centroid.is_finite() {
            self.error(
                Diagnostic::at(
                    points_raw.span(),
                    "a polygon needs at least 3 points enclosing some area",
                )
                .label(format!(
                    "{} points, area {}",
                    points.len(),
                    Readable(area.abs())
                )),
            );
            return None;
        }
        let points = points.into_iter().map(|p| p - centroid).collect();
        Some((Shape::Polygon { points }, centroid))
    }

    /// Returns the total mass, the shape of point masses (offsets relative to the
    /// centre of mass), and the centre of mass relative to the body's `position`.
    pub(super) fn point_masses(
        &mut self,
        raw: &Spanned<Vec<Spanned<crate::scene::raw::RawPointMass>>>,
    ) -> Option<(f64, (Shape, DVec2))> {
        if raw.get_ref().is_empty() {
            self.error(
                Diagnostic::at(raw.span(), "`points` is empty")
                    .hint("give at least one point mass"),
            );
            return None;
        }
        let mut points = Vec::new();
        let mut ok = true;
        for p in raw.get_ref() {
            let offset = self.vec2(&p.get_ref().offset, "offset");
            let mass = self.positive(&p.get_ref().mass, "mass");
            match (offset, mass) {
                (Some(offset), Some(mass)) => points.push(PointMass { offset, mass }),
                _ => ok = false,
            }
        }
        if !ok {
            return None;
        }
        // M = Σ m_i; r_CM = Σ m_i·r_i / M (Equation 8), here relative to `position`.
        let total: f64 = points.iter().map(|p| p.mass).sum();
        let centre = points
            .iter()
            .fold(DVec2::ZERO, |acc, p| acc + p.mass * p.offset)
            / total;
        if !total.is_finite() || !centre.is_finite() {
            self.error(Diagnostic::at(
                raw.span(),
                "the point masses' total or centre of mass overflows",
            ));
            return None;
        }
        let points = points
            .into_iter()
            .map(|p| PointMass {
                offset: p.offset - centre,
                mass: p.mass,
            })
            .collect();
        Some((total, (Shape::Points { points }, centre)))
    }

    /// Rejects bodies that would span more than a million pixels on screen.
    pub(super) fn shapes_fit_the_rasteriser(
        &mut self,
        raw: &[Spanned<RawBody>],
        bodies: &[Body],
        render: &RenderSettings,
    ) {
        let scale = render.view.fit_scale(render.width, render.height);
        for (b, rb) in bodies.iter().zip(raw) {
            let pixels = b.shape.reach() * scale;
            if pixels > MAX_SHAPE_PIXELS {
                let span = rb.get_ref().shape.as_ref().map_or(rb.span(), |s| s.span());
                self.error(
                    Diagnostic::at(
                        span,
                        format!("body `{}` would span {pixels:.3e} pixels", b.name),
                    )
                    .label("far larger than the image")
                    .hint("check the units: the shape is measured in world units, like the view"),
                );
            }
        }
    }

    /// Rejects a body that something turns but that has no moment of inertia: point
    /// masses that all sit at its centre of mass (a swarm's shapes always have one).
    pub(super) fn turning_bodies_have_inertia(
        &mut self,
        raw: &[Spanned<RawBody>],
        bodies: &[Body],
    ) -> Option<()> {
        let mut ok = true;
        for (r, b) in raw.iter().zip(bodies) {
            if b.turns && b.inertia == 0.0 {
                self.error(
                    Diagnostic::at(
                        r.span(),
                        format!("body `{}` is turned but has no moment of inertia", b.name),
                    )
                    .label("its point masses all sit at its centre of mass, so I = 0")
                    .hint("give it `inertia = ...` (kg·m²), or spread its points out"),
                );
                ok = false;
            }
        }
        ok.then_some(())
    }
}

/// Returns R(θ)·p, the offset p turned with a body at angle θ; exactly p at θ = 0, so
/// that a body that is not turned starts where it always did.
pub(super) fn turned(theta: f64, p: DVec2) -> DVec2 {
    if theta == 0.0 {
        p
    } else {
        crate::sim::rigid::rotate(theta.sin_cos(), p)
    }
}

/// Returns the signed area of a polygon and its area centroid (the shoelace formula):
/// A = ½ Σ (x_i·y_{i+1} - x_{i+1}·y_i), C = Σ (p_i + p_{i+1})·cross_i / (6A).
pub(super) fn polygon_area_centroid(points: &[DVec2]) -> (f64, DVec2) {
    let mut area2 = 0.0;
    let mut c = DVec2::ZERO;
    for (i, p) in points.iter().enumerate() {
        let q = points[(i + 1) % points.len()];
        let cross = p.x * q.y - q.x * p.y;
        area2 += cross;
        c += (*p + q) * cross;
    }
    if area2 == 0.0 {
        return (0.0, DVec2::ZERO);
    }
    (0.5 * area2, c / (3.0 * area2))
}
