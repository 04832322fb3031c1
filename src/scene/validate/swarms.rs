//! `[[swarm]]` tables: many bodies alike but for their seeded random initial state,
//! expanded into ordinary bodies after the `[[body]]` ones.

use glam::DVec2;
use toml::Spanned;

use super::bodies::turned;
use super::names::SwarmName;
use super::{Validator, MAX_BODIES};
use crate::numbers::Readable;
use crate::scene::raw::{RawBody, RawRange, RawScalarRange, RawSwarm};
use crate::scene::swarm::{
    grid_position, member_spin, member_state, split_member_name, Uniform1, Uniform2,
};
use crate::scene::MAX_SHAPE_PIXELS;
use crate::scene::{Body, Diagnostic, RenderSettings, Rgba, Shape, View};

impl Validator {
    /// Checks every `[[swarm]]` and builds its members, which follow the `[[body]]`
    /// bodies in file order. Returns the swarms' names and index ranges (for forces,
    /// even when a member is invalid) and the members.
    pub(super) fn swarms(
        &mut self,
        raw: &[Spanned<RawSwarm>],
        raw_bodies: &[Spanned<RawBody>],
        body_names: &[String],
        view: Option<View>,
    ) -> (Vec<SwarmName>, Option<Vec<Body>>) {
        let mut names = Vec::new();
        let mut members = Vec::new();
        let mut ok = true;
        let mut first = raw_bodies.len() as u64;
        let default_radius = view.map_or(0.1, |v| 0.015 * (v.max - v.min).min_element());
        for rs in raw {
            let s = rs.get_ref();
            let name = self.swarm_name(&s.name, &names, raw_bodies, body_names);
            let count = *s.count.get_ref();
            let count = if count < 1 || first + count as u64 > MAX_BODIES {
                self.error(
                    Diagnostic::at(
                        s.count.span(),
                        format!("`count` must be from 1 to {}", MAX_BODIES - first),
                    )
                    .label(format!("{count} bodies"))
                    .hint(format!(
                        "a scene holds at most {MAX_BODIES} bodies, swarms included"
                    )),
                );
                None
            } else {
                Some(count as u64)
            };
            let seed = match &s.seed {
                None => Some(0),
                Some(seed) if *seed.get_ref() >= 0 => Some(*seed.get_ref() as u64),
                Some(seed) => {
                    self.error(
                        Diagnostic::at(seed.span(), "`seed` must be ≥ 0")
                            .label(format!("{} is negative", seed.get_ref())),
                    );
                    None
                }
            };
            let mass = self.positive(&s.mass, "mass");
            let angle = self.optional_scalar_range(s.angle.as_ref(), "angle");
            let spin = self.optional_scalar_range(s.angular_velocity.as_ref(), "angular_velocity");
            let position = self.range(&s.position, "position");
            let velocity = match &s.velocity {
                Some(v) => self.range(v, "velocity"),
                None => Some(Uniform2 {
                    min: DVec2::ZERO,
                    max: DVec2::ZERO,
                }),
            };
            let shape = match &s.shape {
                Some(shape) => self.shape(shape),
                None => Some((
                    Shape::Circle {
                        radius: default_radius,
                    },
                    DVec2::ZERO,
                )),
            };
            let color = match &s.color {
                Some(c) => self.color(c),
                None => Some(Rgba::palette(first as usize)),
            };
            if let (Some(name), Some(count)) = (&name, count) {
                names.push(SwarmName {
                    name: name.clone(),
                    first: first as u32,
                    count: count as u32,
                });
            }
            let (
                Some(name),
                Some(count),
                Some(seed),
                Some(mass),
                Some(position),
                Some(velocity),
                Some((shape, centroid)),
                Some(color),
            ) = (name, count, seed, mass, position, velocity, shape, color)
            else {
                ok = false;
                first += count.unwrap_or(0);
                continue;
            };
            let (Some(angle), Some(spin)) = (angle, spin) else {
                ok = false;
                first += count;
                continue;
            };
            let grid = match s.layout.as_ref() {
                None => false,
                Some(l) if l.get_ref() == "random" => false,
                Some(l) if l.get_ref() == "grid" => true,
                Some(l) => {
                    self.error(
                        Diagnostic::at(l.span(), format!("unknown layout `{}`", l.get_ref()))
                            .hint("`layout` is \"random\" (the default: uniform in `position`) or \"grid\" (one member per cell of a grid filling `position`)"),
                    );
                    ok = false;
                    first += count;
                    continue;
                }
            };
            let friction = match s
                .friction
                .as_ref()
                .map(|m| self.non_negative(m, "friction"))
            {
                None => None,
                Some(Some(m)) => Some(m),
                Some(None) => {
                    ok = false;
                    first += count;
                    continue;
                }
            };
            let restitution = match s.restitution.as_ref().map(|e| self.restitution(e)) {
                None => None,
                Some(Some(e)) => Some(e),
                Some(None) => {
                    ok = false;
                    first += count;
                    continue;
                }
            };
            // Found by the mutated-scene tests: a swarm's shape was not held to the
            // rules a body's is (a finite moment of inertia, not negative).
            let Some(inertia) = self.shape_inertia(rs.span(), &format!("{name}0"), &shape, mass)
            else {
                ok = false;
                first += count;
                continue;
            };
            members.reserve(count as usize);
            for i in 0..count {
                let (mut r, v) = member_state(seed, i, position, velocity);
                if grid {
                    r = grid_position(i, count, position);
                }
                // A swarm that gives no angle or angular velocity draws none: its
                // members are the bodies it always gave.
                let (theta, omega) = match (angle, spin) {
                    (None, None) => (0.0, 0.0),
                    (angle, spin) => member_spin(
                        seed,
                        i,
                        angle.unwrap_or(Uniform1 { min: 0.0, max: 0.0 }),
                        spin.unwrap_or(Uniform1 { min: 0.0, max: 0.0 }),
                    ),
                };
                members.push(Body {
                    name: format!("{name}{i}"),
                    mass,
                    // As for a body, the centre of mass is the drawn position plus the
                    // shape's centroid (nonzero only for polygons), turned with it.
                    position: r + turned(theta, centroid),
                    velocity: v,
                    angle: theta,
                    angular_velocity: omega,
                    inertia,
                    centre: centroid,
                    turns: false,
                    shape: shape.clone(),
                    color,
                    show_velocity: false,
                    show_force: false,
                    is_static: false,
                    restitution,
                    friction,
                });
            }
            first += count;
        }
        (names, ok.then_some(members))
    }

    /// Checks a swarm's name: unique, not ending in a digit (so that member names
    /// of different swarms cannot meet), and clashing with no body.
    pub(super) fn swarm_name(
        &mut self,
        raw: &Spanned<String>,
        earlier: &[SwarmName],
        raw_bodies: &[Spanned<RawBody>],
        body_names: &[String],
    ) -> Option<String> {
        let name = raw.get_ref();
        let valid = !name.is_empty() && !name.ends_with(|c: char| c.is_ascii_digit());
        if !valid {
            self.error(
                Diagnostic::at(
                    raw.span(),
                    format!("swarm name `{name}` cannot name members"),
                )
                .label("members are named by appending 0, 1, 2, …")
                .hint("use a name that does not end in a digit, e.g. \"dust\""),
            );
            return None;
        }
        if earlier.iter().any(|s| s.name == *name) {
            self.error(
                Diagnostic::at(raw.span(), format!("two swarms are named `{name}`"))
                    .hint("forces select a swarm by its name, so each must be unique"),
            );
            return None;
        }
        let mut ok = true;
        for (rb, body) in raw_bodies.iter().zip(body_names) {
            let clash =
                body == name || split_member_name(body).is_some_and(|(prefix, _)| prefix == name);
            if clash {
                let span = rb.get_ref().name.as_ref().map_or(rb.span(), |n| n.span());
                self.error(
                    Diagnostic::at(
                        span,
                        format!("body `{body}` has a name that swarm `{name}` uses"),
                    )
                    .label("clashes with the swarm or one of its members")
                    .hint(format!(
                        "swarm `{name}` names its members {name}0, {name}1, …; rename the body or the swarm"
                    )),
                );
                ok = false;
            }
        }
        ok.then(|| name.clone())
    }

    /// Rejects swarms whose shape would span more than a million pixels on screen.
    pub(super) fn swarm_shapes_fit_the_rasteriser(
        &mut self,
        raw: &[Spanned<RawSwarm>],
        swarms: &[SwarmName],
        members: &[Body],
        render: &RenderSettings,
    ) {
        let scale = render.view.fit_scale(render.width, render.height);
        let mut start = 0usize;
        for (rs, s) in raw.iter().zip(swarms) {
            let Some(first) = members.get(start) else {
                return;
            };
            let pixels = first.shape.reach() * scale;
            if pixels > MAX_SHAPE_PIXELS {
                let span = rs.get_ref().shape.as_ref().map_or(rs.span(), |s| s.span());
                self.error(
                    Diagnostic::at(
                        span,
                        format!(
                            "the members of swarm `{}` would span {pixels:.3e} pixels",
                            s.name
                        ),
                    )
                    .label("far larger than the image")
                    .hint("check the units: the shape is measured in world units, like the view"),
                );
            }
            start += s.count as usize;
        }
    }

    /// Checks a rectangle `{ min = [x0, y0], max = [x1, y1] }` with min ≤ max.
    /// Checks an optional interval `{ min, max }` of finite numbers with min ≤ max:
    /// `Some(None)` when absent, `None` after an error.
    pub(super) fn optional_scalar_range(
        &mut self,
        raw: Option<&Spanned<RawScalarRange>>,
        key: &str,
    ) -> Option<Option<Uniform1>> {
        let Some(raw) = raw else {
            return Some(None);
        };
        let r = raw.get_ref();
        let min = self.finite(&r.min, &format!("{key}.min"));
        let max = self.finite(&r.max, &format!("{key}.max"));
        let (min, max) = (min?, max?);
        if min <= max && (max - min).is_finite() {
            return Some(Some(Uniform1 { min, max }));
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` has min above max"))
                .label(format!("min = {}, max = {}", Readable(min), Readable(max)))
                .hint("give min ≤ max"),
        );
        None
    }

    pub(super) fn range(&mut self, raw: &Spanned<RawRange>, key: &str) -> Option<Uniform2> {
        let r = raw.get_ref();
        let min = self.vec2(&r.min, &format!("{key}.min"));
        let max = self.vec2(&r.max, &format!("{key}.max"));
        let (min, max) = (min?, max?);
        if min.x <= max.x && min.y <= max.y && (max - min).is_finite() {
            return Some(Uniform2 { min, max });
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` has min above max"))
                .label("min must not exceed max on either axis")
                .hint(format!(
                    "min = [{}, {}] and max = [{}, {}]",
                    min.x, min.y, max.x, max.y
                )),
        );
        None
    }
}
