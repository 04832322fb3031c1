//! `[[curve]]` tables: exact curves, numerical solutions of an ODE, and traces of a
//! body's quantities, with their parameters and slots.

use super::expr::{self};
use super::{Diagnostic, Rgba};
use crate::sim::ScalarMethod;
use glam::DVec2;
use std::collections::BTreeMap;
use std::ops::Range;
use toml::Spanned;

use super::*;

impl LayerCheck<'_> {
    pub(super) fn curve(&mut self, index: usize, raw: &Spanned<RawCurve>) -> Option<Curve> {
        let c = raw.get_ref();
        let kind = c.kind.get_ref().as_str();
        let Some((_, allowed)) = CURVE_KINDS.iter().find(|(k, _)| *k == kind) else {
            self.error(
                Diagnostic::at(c.kind.span(), format!("unknown curve kind `{kind}`"))
                    .label("not a curve physframes knows")
                    .hint("expected `exact` (y from an expression), `solution` (a numerical solution of dy/dx = f) or `trace` (the simulation's state, frame by frame)"),
            );
            return None;
        };
        let mut stray = false;
        for (key, span) in present_curve_keys(c) {
            if !allowed.contains(&key) {
                self.error(
                    Diagnostic::at(span, format!("`{key}` does not apply to a `{kind}` curve"))
                        .label("not used by this kind")
                        .hint(format!("a `{kind}` curve takes: {}", allowed.join(", "))),
                );
                stray = true;
            }
        }
        let slots = if kind == "trace" {
            if let Some(v) = &c.variables {
                self.error(
                    Diagnostic::at(v.span(), "`variables` does not apply to a `trace` curve")
                        .hint("a trace reads `t` and `body.x`, `body.y`, `body.vx`, `body.vy`, `body.speed`"),
                );
                stray = true;
            }
            self.trace_slots(c.params.as_ref())
        } else {
            self.axis_slots(c.variables.as_ref(), c.params.as_ref())
        };
        let width = self.line_width(c.width.as_ref(), 1.5);
        let color = self.color(c.color.as_ref(), Rgba::palette(index));
        let dash = match &c.dash {
            None => Some(LineDash::Solid),
            Some(d) => match d.get_ref().as_str() {
                "solid" => Some(LineDash::Solid),
                "dashed" => Some(LineDash::Dashed),
                "dotted" => Some(LineDash::Dotted),
                "dashdot" | "dash-dot" => Some(LineDash::DashDot),
                other => {
                    self.error(
                        Diagnostic::at(d.span(), format!("unknown dash `{other}`"))
                            .hint("write dash = \"solid\", \"dashed\", \"dotted\" or \"dashdot\""),
                    );
                    None
                }
            },
        };
        let mut slots = slots?;
        // A family's parameter needs no entry in `params`: it gets a slot of its own.
        if let (true, Some(family)) = (kind == "exact", &c.family) {
            for name in family.get_ref().keys() {
                if !slots.names.contains(name) && expr::is_valid_name(name) {
                    slots.names.push(name.clone());
                    slots.values.push(0.0);
                }
            }
        }
        let names: Vec<String> = slots.names.clone();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let kind_value = match kind {
            "exact" => self.exact(raw, &names, &slots),
            "solution" => self.solution(raw, &names),
            _ => self.trace(raw, &names),
        };
        let kind_value = kind_value?;
        slots.time_dependent = slots.time.is_some_and(|t| match &kind_value {
            CurveKind::Exact { y, .. } => y.reads(t),
            CurveKind::Solution { f, .. } => f.reads(t),
            CurveKind::Trace { .. } => false,
        });
        if stray {
            return None;
        }
        Some(Curve {
            kind: kind_value,
            slots,
            color: color?,
            width: width?,
            dash: dash?,
            label: c.label.as_ref().map(|l| l.get_ref().clone()),
        })
    }

    pub(super) fn exact(
        &mut self,
        raw: &Spanned<RawCurve>,
        names: &[&str],
        slots: &Slots,
    ) -> Option<CurveKind> {
        let c = raw.get_ref();
        let y = self.required(raw, &c.y, "y", "y = \"x^2\"");
        let family = match &c.family {
            None => Some(None),
            Some(f) => {
                let entries: Vec<_> = f.get_ref().iter().collect();
                match entries.as_slice() {
                    [(name, values)] => match slots.names.iter().position(|n| n == *name) {
                        Some(slot) if slot >= 2 && Some(slot) != slots.time => {
                            let vals = values.get_ref().clone();
                            if vals.is_empty() || vals.iter().any(|v| !v.is_finite()) {
                                self.error(
                                    Diagnostic::at(
                                        values.span(),
                                        "a family needs one or more finite values",
                                    )
                                    .hint("e.g. family = { C = [-2, -1, 0, 1, 2] }"),
                                );
                                None
                            } else {
                                Some(Some((slot, vals)))
                            }
                        }
                        _ => {
                            self.error(
                                Diagnostic::at(f.span(), format!("`{name}` cannot name the family's parameter"))
                                    .hint("name it with a letter then letters, digits or `_`, not an axis variable, `t`, a function or a constant"),
                            );
                            None
                        }
                    },
                    _ => {
                        self.error(
                            Diagnostic::at(f.span(), "a family varies exactly one parameter")
                                .hint("e.g. family = { C = [-2, -1, 0, 1, 2] }"),
                        );
                        None
                    }
                }
            }
        };
        let samples = match &c.samples {
            None => Some(400),
            Some(s) => {
                let n = *s.get_ref();
                if (2..=100_000).contains(&n) {
                    Some(n as u32)
                } else {
                    self.error(
                        Diagnostic::at(s.span(), "`samples` must be from 2 to 100000")
                            .label(format!("{n}")),
                    );
                    None
                }
            }
        };
        let y = y.and_then(|y| self.expression(y, names));
        Some(CurveKind::Exact {
            y: y?,
            family: family?,
            samples: samples?,
        })
    }

    pub(super) fn solution(
        &mut self,
        raw: &Spanned<RawCurve>,
        names: &[&str],
    ) -> Option<CurveKind> {
        let c = raw.get_ref();
        let f = self
            .required(raw, &c.f, "f", "f = \"-v/m\"")
            .and_then(|f| self.expression(f, names));
        let start = self
            .required(raw, &c.start, "start", "start = [0.0, 3.0]")
            .and_then(|s| {
                let [x, y] = *s.get_ref();
                if x.is_finite() && y.is_finite() {
                    Some(DVec2::new(x, y))
                } else {
                    self.error(Diagnostic::at(
                        s.span(),
                        "`start` must be two finite numbers",
                    ));
                    None
                }
            });
        let h = self.required(raw, &c.h, "h", "h = 0.5").and_then(|h| {
            let v = *h.get_ref();
            if v.is_finite() && v > 0.0 {
                Some(v)
            } else {
                self.error(
                    Diagnostic::at(h.span(), "the step `h` must be > 0")
                        .label(crate::numbers::readable(v)),
                );
                None
            }
        });
        let method = match &c.method {
            None => Some(ScalarMethod::Euler),
            Some(m) => match m.get_ref().parse::<ScalarMethod>() {
                Ok(m) => Some(m),
                Err(message) => {
                    self.error(Diagnostic::at(m.span(), message).label("not a method"));
                    None
                }
            },
        };
        let default_end = self.view.map(|v| v.max.x);
        let end = match &c.end {
            Some(e) if e.get_ref().is_finite() => Some(*e.get_ref()),
            Some(e) => {
                self.error(Diagnostic::at(e.span(), "`end` must be a finite number"));
                None
            }
            None => default_end,
        };
        let (start, h, end) = (start?, h?, end?);
        if end <= start.x {
            let span = c.end.as_ref().map_or(raw.span(), |e| e.span());
            self.error(
                Diagnostic::at(
                    span,
                    format!(
                        "the solution ends at {end}, not after its start x = {}",
                        start.x
                    ),
                )
                .hint("`end` (by default the view's right edge) must lie right of `start`"),
            );
            return None;
        }
        let steps = (end - start.x) / h;
        if steps > MAX_SOLUTION_STEPS as f64 {
            let span = c.h.as_ref().map_or(raw.span(), |h| h.span());
            self.error(
                Diagnostic::at(
                    span,
                    format!(
                        "the solution would take {steps:.0} steps, more than {MAX_SOLUTION_STEPS}"
                    ),
                )
                .hint("a figure shows a few steps: take a larger `h`"),
            );
            return None;
        }
        Some(CurveKind::Solution {
            f: f?,
            start,
            h,
            method: method?,
            end,
            markers: c.markers.as_ref().is_none_or(|m| *m.get_ref()),
        })
    }

    pub(super) fn trace(&mut self, raw: &Spanned<RawCurve>, names: &[&str]) -> Option<CurveKind> {
        let c = raw.get_ref();
        let x = self
            .required(raw, &c.x, "x", "x = \"t\"")
            .and_then(|x| self.expression(x, names));
        let y = self
            .required(raw, &c.y, "y", "y = \"puck.vx\"")
            .and_then(|y| self.expression(y, names));
        Some(CurveKind::Trace { x: x?, y: y? })
    }

    /// The slots of a trace: t, then every body's quantities, then the parameters.
    pub(super) fn trace_slots(
        &mut self,
        params: Option<&Spanned<BTreeMap<String, Spanned<f64>>>>,
    ) -> Option<Slots> {
        let mut names = vec!["t".to_string()];
        for body in self.bodies {
            for q in BODY_QUANTITIES {
                names.push(format!("{body}.{q}"));
            }
        }
        self.with_params(names, Some(0), params)
    }

    pub(super) fn with_params(
        &mut self,
        mut names: Vec<String>,
        time: Option<usize>,
        params: Option<&Spanned<BTreeMap<String, Spanned<f64>>>>,
    ) -> Option<Slots> {
        let mut values = vec![0.0; names.len()];
        let mut ok = true;
        if let Some(p) = params {
            for (name, value) in p.get_ref() {
                if !expr::is_valid_name(name) || names.contains(name) {
                    self.error(
                        Diagnostic::at(p.span(), format!("`{name}` cannot name a parameter"))
                            .hint(format!(
                                "a parameter's name is a letter then letters, digits or `_`, and is none of {}, a function or a constant (e, E, PI)",
                                names.iter().take(3).map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
                            )),
                    );
                    ok = false;
                } else if !value.get_ref().is_finite() {
                    self.error(Diagnostic::at(
                        value.span(),
                        format!("parameter `{name}` must be finite"),
                    ));
                    ok = false;
                } else {
                    names.push(name.clone());
                    values.push(*value.get_ref());
                }
            }
        }
        ok.then_some(Slots {
            names,
            values,
            time,
            time_dependent: false,
        })
    }
}

/// Returns the strings of a value that is a string or an array of strings, each with
/// its span, or `None` for anything else.
pub(super) fn as_strings(text: &str, raw: &Spanned<toml::Value>) -> Option<Vec<Spanned<String>>> {
    match raw.get_ref() {
        toml::Value::String(s) => Some(vec![Spanned::new(raw.span(), s.clone())]),
        toml::Value::Array(items) => {
            // toml::Value keeps no spans for array items, so each string is found in
            // the file's text inside the array, in order.
            let mut from = raw.span().start;
            let mut out = Vec::new();
            for item in items {
                let s = item.as_str()?;
                let span = find_string_literal(text, from, raw.span().end, s).unwrap_or(raw.span());
                from = span.end.min(raw.span().end);
                out.push(Spanned::new(span, s.to_string()));
            }
            Some(out)
        }
        _ => None,
    }
}

/// Finds the next string literal in `text[from..to]` whose value is `value`, written
/// plainly between double or single quotes.
pub(super) fn find_string_literal(
    text: &str,
    from: usize,
    to: usize,
    value: &str,
) -> Option<Range<usize>> {
    let region = text.get(from..to)?;
    for quote in ['"', '\''] {
        let literal = format!("{quote}{value}{quote}");
        if let Some(i) = region.find(&literal) {
            return Some(from + i..from + i + literal.len());
        }
    }
    None
}

/// Returns each kind-specific key of a curve that is present, with its span.
pub(super) fn present_curve_keys(c: &RawCurve) -> Vec<(&'static str, Range<usize>)> {
    let spans = [
        ("x", c.x.as_ref().map(|v| v.span())),
        ("y", c.y.as_ref().map(|v| v.span())),
        ("family", c.family.as_ref().map(|v| v.span())),
        ("samples", c.samples.as_ref().map(|v| v.span())),
        ("f", c.f.as_ref().map(|v| v.span())),
        ("start", c.start.as_ref().map(|v| v.span())),
        ("h", c.h.as_ref().map(|v| v.span())),
        ("method", c.method.as_ref().map(|v| v.span())),
        ("end", c.end.as_ref().map(|v| v.span())),
        ("markers", c.markers.as_ref().map(|v| v.span())),
    ];
    spans
        .into_iter()
        .filter_map(|(k, s)| s.map(|s| (k, s)))
        .collect()
}
