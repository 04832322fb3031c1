//! `[[force]]` tables: each kind and the keys it takes, checked into a [`ForceSpec`].

use std::ops::Range;

use glam::DVec2;
use toml::Spanned;

use super::names::Names;
use super::Validator;
use crate::scene::raw::RawForce;
use crate::scene::Diagnostic;
use crate::sim::{Anchor, ForceSpec};

/// The force keys other than `kind`, in the order the schema lists them.
pub(super) const FORCE_KEYS: &[&str] = &[
    "bodies",
    "g",
    "k",
    "c",
    "f0",
    "f1",
    "a",
    "b",
    "stiffness",
    "rest_length",
    "damping",
    "centre",
    "strength",
    "tau",
    "at",
    "a_at",
    "b_at",
];

/// The force kinds and the keys each takes.
pub(super) const FORCE_KINDS: &[(&str, &[&str])] = &[
    ("gravity", &["g", "bodies"]),
    ("drag", &["k", "bodies"]),
    ("quadratic-drag", &["c", "bodies"]),
    ("force", &["f0", "f1", "at", "bodies"]),
    (
        "spring",
        &[
            "a",
            "b",
            "stiffness",
            "rest_length",
            "damping",
            "a_at",
            "b_at",
        ],
    ),
    ("central", &["centre", "strength", "bodies"]),
    ("torque", &["tau", "bodies"]),
    ("angular-drag", &["k", "bodies"]),
];

impl Validator {
    pub(super) fn forces(
        &mut self,
        raw: &[Spanned<RawForce>],
        names: &Names,
    ) -> Option<Vec<ForceSpec>> {
        let mut forces = Vec::new();
        let mut ok = true;
        for f in raw {
            match self.force(f, names) {
                Some(force) => forces.push(force),
                None => ok = false,
            }
        }
        ok.then_some(forces)
    }

    pub(super) fn force(&mut self, raw: &Spanned<RawForce>, names: &Names) -> Option<ForceSpec> {
        let f = raw.get_ref();
        let kind = f.kind.get_ref().as_str();
        let Some((_, allowed)) = FORCE_KINDS.iter().find(|(k, _)| *k == kind) else {
            let kinds: Vec<&str> = FORCE_KINDS.iter().map(|(k, _)| *k).collect();
            self.error(
                Diagnostic::at(f.kind.span(), format!("unknown force kind `{kind}`"))
                    .label("not a force physframes knows")
                    .hint(format!("expected one of: {}", kinds.join(", "))),
            );
            return None;
        };
        // Keys that belong to other kinds are mistakes, not silently ignored values.
        let mut stray = false;
        for (key, span) in present_force_keys(f) {
            if !allowed.contains(&key) {
                self.error(
                    Diagnostic::at(span, format!("`{key}` does not apply to a `{kind}` force"))
                        .label("not used by this kind")
                        .hint(format!("a `{kind}` force takes: {}", allowed.join(", "))),
                );
                stray = true;
            }
        }
        let bodies = self.selection(f.bodies.as_ref(), names);
        let spec = match kind {
            "gravity" => {
                let g = match &f.g {
                    Some(g) => self.vec2(g, "g"),
                    None => Some(DVec2::new(0.0, -9.81)),
                };
                ForceSpec::Gravity {
                    g: g?,
                    bodies: bodies?,
                }
            }
            "drag" => {
                let k = match &f.k {
                    Some(k) => self.non_negative(k, "k"),
                    None => Some(1.0),
                };
                ForceSpec::Drag {
                    k: k?,
                    bodies: bodies?,
                }
            }
            "quadratic-drag" => {
                let c = self.required(raw, &f.c, "c", "c = 0.1")?;
                let c = self.non_negative(c, "c");
                ForceSpec::QuadraticDrag {
                    c: c?,
                    bodies: bodies?,
                }
            }
            "force" => {
                let f0 =
                    f.f0.as_ref()
                        .map_or(Some(DVec2::ZERO), |v| self.vec2(v, "f0"));
                let f1 =
                    f.f1.as_ref()
                        .map_or(Some(DVec2::ZERO), |v| self.vec2(v, "f1"));
                let at = self.optional_vec2(f.at.as_ref(), "at");
                ForceSpec::TimeVarying {
                    f0: f0?,
                    f1: f1?,
                    bodies: bodies?,
                    at: at?,
                }
            }
            "torque" => {
                let tau = self.required(raw, &f.tau, "tau", "tau = 1.0")?;
                let tau = self.finite(tau, "tau");
                ForceSpec::Torque {
                    tau: tau?,
                    bodies: bodies?,
                }
            }
            "angular-drag" => {
                let k = self.required(raw, &f.k, "k", "k = 0.1")?;
                let k = self.non_negative(k, "k");
                ForceSpec::AngularDrag {
                    k: k?,
                    bodies: bodies?,
                }
            }
            "spring" => self.spring(raw, names)?,
            "central" => {
                let centre = f
                    .centre
                    .as_ref()
                    .map_or(Some(DVec2::ZERO), |v| self.vec2(v, "centre"));
                let strength = self.required(raw, &f.strength, "strength", "strength = 1.0")?;
                let strength = self.finite(strength, "strength");
                ForceSpec::Central {
                    centre: centre?,
                    strength: strength?,
                    bodies: bodies?,
                }
            }
            _ => return None,
        };
        (!stray).then_some(spec)
    }

    pub(super) fn spring(&mut self, raw: &Spanned<RawForce>, names: &Names) -> Option<ForceSpec> {
        let f = raw.get_ref();
        let a_raw = self.required(raw, &f.a, "a", "a = \"first-body\"");
        let b_raw = self.required(raw, &f.b, "b", "b = \"other-body\" or b = [0.0, 0.0]");
        let stiffness = self
            .required(raw, &f.stiffness, "stiffness", "stiffness = 10.0")
            .and_then(|s| self.non_negative(s, "stiffness"));
        let rest_length = f
            .rest_length
            .as_ref()
            .map_or(Some(0.0), |r| self.non_negative(r, "rest_length"));
        let damping = f
            .damping
            .as_ref()
            .map_or(Some(0.0), |d| self.non_negative(d, "damping"));
        let a = a_raw.and_then(|a| self.body_index(a, names));
        let b = b_raw.and_then(|b| match b.get_ref() {
            toml::Value::String(name) => self
                .body_index(&Spanned::new(b.span(), name.clone()), names)
                .map(Anchor::Body),
            toml::Value::Array(items) => {
                let xy: Vec<f64> = items
                    .iter()
                    .filter_map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
                    .collect();
                if items.len() == 2 && xy.len() == 2 && xy.iter().all(|x| x.is_finite()) {
                    Some(Anchor::Point(DVec2::new(xy[0], xy[1])))
                } else {
                    self.error(
                        Diagnostic::at(b.span(), "a fixed spring end must be two finite numbers")
                            .hint("e.g. b = [0.0, 0.0]"),
                    );
                    None
                }
            }
            _ => {
                self.error(
                    Diagnostic::at(b.span(), "`b` must be a body's name or a point [x, y]")
                        .hint("e.g. b = \"anchor\" or b = [0.0, 0.0]"),
                );
                None
            }
        });
        let a_at = self.optional_vec2(f.a_at.as_ref(), "a_at");
        let b_at = self.optional_vec2(f.b_at.as_ref(), "b_at");
        let (a, b) = (a?, b?);
        if b == Anchor::Body(a) {
            self.error(
                Diagnostic::at(raw.span(), "a spring joins a body to itself")
                    .hint("give `a` and `b` different bodies, or a fixed point for `b`"),
            );
            return None;
        }
        let (a_at, b_at) = (a_at?, b_at?);
        if let (Anchor::Point(p), Some(raw_b_at)) = (b, &f.b_at) {
            self.error(
                Diagnostic::at(
                    raw_b_at.span(),
                    "`b_at` places the spring's end on body `b`, but `b` is a fixed point",
                )
                .label("a fixed point has no body coordinates")
                .hint(format!(
                    "remove `b_at`: the spring's end is the point b = [{}, {}] itself",
                    p.x, p.y
                )),
            );
            return None;
        }
        Some(ForceSpec::Spring {
            a,
            b,
            stiffness: stiffness?,
            rest_length: rest_length?,
            damping: damping?,
            a_at,
            b_at,
        })
    }
}

/// Returns each key of a force table that is present, with its span.
pub(super) fn present_force_keys(f: &RawForce) -> Vec<(&'static str, Range<usize>)> {
    let spans = [
        f.bodies.as_ref().map(|v| v.span()),
        f.g.as_ref().map(|v| v.span()),
        f.k.as_ref().map(|v| v.span()),
        f.c.as_ref().map(|v| v.span()),
        f.f0.as_ref().map(|v| v.span()),
        f.f1.as_ref().map(|v| v.span()),
        f.a.as_ref().map(|v| v.span()),
        f.b.as_ref().map(|v| v.span()),
        f.stiffness.as_ref().map(|v| v.span()),
        f.rest_length.as_ref().map(|v| v.span()),
        f.damping.as_ref().map(|v| v.span()),
        f.centre.as_ref().map(|v| v.span()),
        f.strength.as_ref().map(|v| v.span()),
        f.tau.as_ref().map(|v| v.span()),
        f.at.as_ref().map(|v| v.span()),
        f.a_at.as_ref().map(|v| v.span()),
        f.b_at.as_ref().map(|v| v.span()),
    ];
    FORCE_KEYS
        .iter()
        .zip(spans)
        .filter_map(|(k, s)| s.map(|s| (*k, s)))
        .collect()
}
