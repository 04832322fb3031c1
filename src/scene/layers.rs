//! The figure parts of a scene: the `[axes]` table, `[[field]]` layers and `[[curve]]`
//! layers, from their raw TOML to checked values with compiled expressions.
//!
//! Every expression is compiled here, once, with the names it may read; a bad one is
//! reported at the offending token inside its string. Each layer records the *slots* it
//! reads (see [`super::expr`]): the horizontal variable, the vertical variable, the time
//! `t` (unless an axis is called `t`), then the layer's parameters in the order written.

use std::collections::BTreeMap;
use std::ops::Range;

use glam::DVec2;
use serde::Deserialize;
use toml::Spanned;

use super::expr::{self, Expr, ExprError};
use super::{Diagnostic, Rgba, View};
use crate::sim::ScalarMethod;

/// The `[axes]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawAxes {
    pub title: Option<Spanned<String>>,
    pub x_label: Option<Spanned<String>>,
    pub y_label: Option<Spanned<String>>,
    pub grid: Option<Spanned<bool>>,
    pub legend: Option<Spanned<toml::Value>>,
    pub aspect: Option<Spanned<String>>,
}

/// One `[[field]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawField {
    pub kind: Spanned<String>,
    pub f: Spanned<toml::Value>,
    pub params: Option<Spanned<BTreeMap<String, Spanned<f64>>>>,
    pub variables: Option<Spanned<Vec<Spanned<String>>>>,
    pub grid: Option<Spanned<[i64; 2]>>,
    pub length: Option<Spanned<String>>,
    pub size: Option<Spanned<f64>>,
    pub color: Option<Spanned<String>>,
    pub color_by_magnitude: Option<Spanned<bool>>,
    pub width: Option<Spanned<f64>>,
    pub label: Option<Spanned<String>>,
}

/// One `[[curve]]`. Every kind's keys are optional here; validation checks which apply.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawCurve {
    pub kind: Spanned<String>,
    pub params: Option<Spanned<BTreeMap<String, Spanned<f64>>>>,
    pub variables: Option<Spanned<Vec<Spanned<String>>>>,
    pub color: Option<Spanned<String>>,
    pub width: Option<Spanned<f64>>,
    pub dash: Option<Spanned<String>>,
    pub label: Option<Spanned<String>>,
    pub x: Option<Spanned<String>>,
    pub y: Option<Spanned<String>>,
    pub family: Option<Spanned<BTreeMap<String, Spanned<Vec<f64>>>>>,
    pub samples: Option<Spanned<i64>>,
    pub f: Option<Spanned<String>>,
    pub start: Option<Spanned<[f64; 2]>>,
    pub h: Option<Spanned<f64>>,
    pub method: Option<Spanned<String>>,
    pub end: Option<Spanned<f64>>,
    pub markers: Option<Spanned<bool>>,
}

/// The figure parts of a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layers {
    /// Axes around the view, when the scene has an `[axes]` table.
    pub axes: Option<AxesSettings>,
    /// Fields, drawn in file order under the curves.
    pub fields: Vec<Field>,
    /// Curves, drawn in file order over the fields.
    pub curves: Vec<Curve>,
}

impl Layers {
    /// Returns true when some layer changes from frame to frame.
    pub fn has_dynamic_layers(&self) -> bool {
        self.fields.iter().any(|f| f.slots.time_dependent)
            || self.curves.iter().any(|c| c.is_dynamic())
    }
}

/// The `[axes]` table, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct AxesSettings {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub grid: bool,
    /// Where the legend goes; `None` hides it.
    pub legend: Option<LegendCorner>,
    pub aspect: Aspect,
}

/// How the view is fitted into the plot area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aspect {
    /// Square world units: the view grows along one axis to fill the plot area.
    Equal,
    /// Each axis has its own scale and the view fills the plot area exactly.
    Auto,
}

/// A corner of the plot area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LegendCorner {
    TopRight,
    TopLeft,
    BottomRight,
    BottomLeft,
}

/// The names a layer's expressions read and the values of its constant slots.
#[derive(Clone, Debug, PartialEq)]
pub struct Slots {
    /// Slot names: horizontal, vertical, [t,] parameters (for traces: t, body values,
    /// parameters).
    pub names: Vec<String>,
    /// Initial slot values: zero for variables, the value for parameters.
    pub values: Vec<f64>,
    /// The slot of the time t, when it is not an axis.
    pub time: Option<usize>,
    /// Whether some expression reads the time slot, so the layer changes every frame.
    pub time_dependent: bool,
}

/// A field layer: segments or arrows on a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub function: FieldFunction,
    pub slots: Slots,
    /// Grid points across and up the view.
    pub grid: [u32; 2],
    pub length: ArrowLength,
    /// The fraction of a grid cell a segment or the longest arrow spans.
    pub size: f64,
    pub color: Rgba,
    pub color_by_magnitude: bool,
    /// Line width in pixels.
    pub width: f64,
    pub label: Option<String>,
}

/// What a field shows at each grid point.
#[derive(Clone, Debug, PartialEq)]
pub enum FieldFunction {
    /// A slope field of dy/dx = f: segments along (1, f).
    Slope(Expr),
    /// Arrows of (1, f), the direction of a solution of dy/dx = f.
    Direction(Expr),
    /// Arrows of the pair (fx, fy).
    Vector(Expr, Expr),
}

/// How long a field's arrows are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArrowLength {
    /// Every arrow has the same length.
    Normalised,
    /// Arrow length is proportional to the vector's magnitude.
    Scaled,
}

/// A curve layer.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    pub kind: CurveKind,
    pub slots: Slots,
    pub color: Rgba,
    /// Line width in pixels.
    pub width: f64,
    pub dash: LineDash,
    pub label: Option<String>,
}

impl Curve {
    /// Returns true when the curve changes from frame to frame.
    pub fn is_dynamic(&self) -> bool {
        matches!(self.kind, CurveKind::Trace { .. }) || self.slots.time_dependent
    }
}

/// What a curve draws.
#[derive(Clone, Debug, PartialEq)]
pub enum CurveKind {
    /// y = f(x) sampled across the view, once per value of the family parameter.
    Exact {
        y: Expr,
        /// The family's parameter slot and its values.
        family: Option<(usize, Vec<f64>)>,
        samples: u32,
    },
    /// The numerical solution of dy/dx = f from `start` with step `h`.
    Solution {
        f: Expr,
        start: DVec2,
        h: f64,
        method: ScalarMethod,
        end: f64,
        markers: bool,
    },
    /// The point (x, y) of the simulation's state at each frame so far, with a marker at
    /// the current frame.
    Trace { x: Expr, y: Expr },
}

/// A dash pattern for curves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineDash {
    Solid,
    Dashed,
    Dotted,
    DashDot,
}

/// The quantities of each body that a trace may read, as `body.quantity`.
pub const BODY_QUANTITIES: &[&str] = &["x", "y", "vx", "vy", "speed"];

/// The most grid points a field may have along one side.
const MAX_GRID: i64 = 500;
/// The most steps a numerical solution may take.
pub const MAX_SOLUTION_STEPS: usize = 100_000;

/// Curve kinds and the keys each takes besides `kind`, `params`, `variables`, `color`,
/// `width`, `dash` and `label`.
const CURVE_KINDS: &[(&str, &[&str])] = &[
    ("exact", &["y", "family", "samples"]),
    ("solution", &["f", "start", "h", "method", "end", "markers"]),
    ("trace", &["x", "y"]),
];

/// Validates the `[axes]`, `[[field]]` and `[[curve]]` parts of a scene.
pub struct LayerCheck<'a> {
    /// The scene file's text, for locating errors inside strings.
    pub text: &'a str,
    /// Where problems go.
    pub diagnostics: &'a mut Vec<Diagnostic>,
    /// Every body's name.
    pub bodies: &'a [String],
    /// Whether bodies are drawn (they need square units by default).
    pub bodies_drawn: bool,
    /// The view, when valid.
    pub view: Option<View>,
}

impl LayerCheck<'_> {
    /// Checks everything and returns the layers, or `None` after recording problems.
    pub fn run(
        mut self,
        axes: Option<&Spanned<RawAxes>>,
        fields: &[Spanned<RawField>],
        curves: &[Spanned<RawCurve>],
    ) -> Option<Layers> {
        let before = self.diagnostics.len();
        let axes = axes.map(|a| self.axes(a.get_ref()));
        let fields: Vec<Option<Field>> = fields.iter().map(|f| self.field(f.get_ref())).collect();
        let curves: Vec<Option<Curve>> = curves
            .iter()
            .enumerate()
            .map(|(i, c)| self.curve(i, c))
            .collect();
        if self.diagnostics.len() != before {
            return None;
        }
        Some(Layers {
            axes: axes.flatten(),
            fields: fields.into_iter().collect::<Option<_>>()?,
            curves: curves.into_iter().collect::<Option<_>>()?,
        })
    }

    fn error(&mut self, d: Diagnostic) {
        self.diagnostics.push(d);
    }

    fn axes(&mut self, a: &RawAxes) -> Option<AxesSettings> {
        let text =
            |s: &Option<Spanned<String>>| s.as_ref().map_or(String::new(), |s| s.get_ref().clone());
        let legend = match &a.legend {
            None => Some(Some(LegendCorner::TopRight)),
            Some(v) => match v.get_ref() {
                toml::Value::Boolean(true) => Some(Some(LegendCorner::TopRight)),
                toml::Value::Boolean(false) => Some(None),
                toml::Value::String(s) => match s.as_str() {
                    "top-right" => Some(Some(LegendCorner::TopRight)),
                    "top-left" => Some(Some(LegendCorner::TopLeft)),
                    "bottom-right" => Some(Some(LegendCorner::BottomRight)),
                    "bottom-left" => Some(Some(LegendCorner::BottomLeft)),
                    "off" => Some(None),
                    "on" => Some(Some(LegendCorner::TopRight)),
                    _ => None,
                },
                _ => None,
            },
        };
        let legend = match legend {
            Some(l) => Some(l),
            None => {
                let span = a.legend.as_ref().map_or(0..0, |l| l.span());
                self.error(
                    Diagnostic::at(span, "`legend` must be true, false or a corner")
                        .hint("write legend = \"top-right\", \"top-left\", \"bottom-right\", \"bottom-left\", true or false"),
                );
                None
            }
        };
        let aspect = match &a.aspect {
            None if self.bodies_drawn => Some(Aspect::Equal),
            None => Some(Aspect::Auto),
            Some(s) => match s.get_ref().as_str() {
                "equal" => Some(Aspect::Equal),
                "auto" => Some(Aspect::Auto),
                other => {
                    self.error(
                        Diagnostic::at(s.span(), format!("unknown aspect `{other}`"))
                            .label("not an aspect")
                            .hint("write aspect = \"equal\" (square world units) or \"auto\" (fill the plot area)"),
                    );
                    None
                }
            },
        };
        Some(AxesSettings {
            title: text(&a.title),
            x_label: text(&a.x_label),
            y_label: text(&a.y_label),
            grid: a.grid.as_ref().is_some_and(|g| *g.get_ref()),
            legend: legend?,
            aspect: aspect?,
        })
    }

    fn field(&mut self, f: &RawField) -> Option<Field> {
        let kind = f.kind.get_ref().as_str();
        if !matches!(kind, "slope" | "vector") {
            self.error(
                Diagnostic::at(f.kind.span(), format!("unknown field kind `{kind}`"))
                    .label("not a field physframes knows")
                    .hint("expected `slope` (segments of dy/dx = f) or `vector` (arrows of (1, f) or of [fx, fy])"),
            );
            return None;
        }
        let slots = self.axis_slots(f.variables.as_ref(), f.params.as_ref());
        let names = slots.as_ref().map(|s| s.names.clone());
        let function = names.and_then(|names| {
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            self.field_function(kind, &f.f, &names)
        });
        if kind == "slope" {
            if let Some(length) = &f.length {
                self.error(
                    Diagnostic::at(length.span(), "`length` applies to vector fields only").hint(
                        "a slope field's segments all have the same length; set `size` instead",
                    ),
                );
            }
        }
        let grid = match &f.grid {
            None => Some([20, 15]),
            Some(g) => {
                let [nx, ny] = *g.get_ref();
                if (1..=MAX_GRID).contains(&nx) && (1..=MAX_GRID).contains(&ny) {
                    Some([nx as u32, ny as u32])
                } else {
                    self.error(
                        Diagnostic::at(
                            g.span(),
                            format!("`grid` must be two counts from 1 to {MAX_GRID}"),
                        )
                        .label(format!("[{nx}, {ny}]")),
                    );
                    None
                }
            }
        };
        let length = match &f.length {
            None => Some(ArrowLength::Normalised),
            Some(l) => match l.get_ref().as_str() {
                "normalised" | "normalized" => Some(ArrowLength::Normalised),
                "scaled" => Some(ArrowLength::Scaled),
                other => {
                    self.error(
                        Diagnostic::at(l.span(), format!("unknown arrow length `{other}`"))
                            .hint("write length = \"normalised\" (all the same) or \"scaled\" (by magnitude)"),
                    );
                    None
                }
            },
        };
        let size = self.fraction(f.size.as_ref(), "size", 0.7);
        let width = self.line_width(f.width.as_ref(), if kind == "slope" { 1.2 } else { 1.0 });
        let color = self.color(f.color.as_ref(), Rgba([0x55, 0x55, 0x55, 0xff]));
        let mut slots = slots?;
        let function = function?;
        slots.time_dependent = slots.time.is_some_and(|t| match &function {
            FieldFunction::Slope(e) | FieldFunction::Direction(e) => e.reads(t),
            FieldFunction::Vector(a, b) => a.reads(t) || b.reads(t),
        });
        Some(Field {
            function,
            slots,
            grid: grid?,
            length: length?,
            size: size?,
            color: color?,
            color_by_magnitude: f.color_by_magnitude.as_ref().is_some_and(|c| *c.get_ref()),
            width: width?,
            label: f.label.as_ref().map(|l| l.get_ref().clone()),
        })
    }

    fn field_function(
        &mut self,
        kind: &str,
        raw: &Spanned<toml::Value>,
        names: &[&str],
    ) -> Option<FieldFunction> {
        let strings = as_strings(self.text, raw);
        match (kind, strings.as_deref()) {
            ("slope", Some([f])) => self.expression(f, names).map(FieldFunction::Slope),
            ("vector", Some([f])) => self.expression(f, names).map(FieldFunction::Direction),
            ("vector", Some([fx, fy])) => {
                let fx = self.expression(fx, names);
                let fy = self.expression(fy, names);
                Some(FieldFunction::Vector(fx?, fy?))
            }
            _ => {
                let want = if kind == "slope" {
                    "a slope field's `f` must be one expression, e.g. f = \"2*x\""
                } else {
                    "a vector field's `f` must be an expression (arrows of (1, f)) or a pair, e.g. f = [\"-y\", \"x\"]"
                };
                self.error(Diagnostic::at(raw.span(), want).label("not an expression"));
                None
            }
        }
    }

    fn curve(&mut self, index: usize, raw: &Spanned<RawCurve>) -> Option<Curve> {
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

    fn exact(
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

    fn solution(&mut self, raw: &Spanned<RawCurve>, names: &[&str]) -> Option<CurveKind> {
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
                    Diagnostic::at(h.span(), "the step `h` must be > 0").label(format!("{v}")),
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

    fn trace(&mut self, raw: &Spanned<RawCurve>, names: &[&str]) -> Option<CurveKind> {
        let c = raw.get_ref();
        let x = self
            .required(raw, &c.x, "x", "x = \"t\"")
            .and_then(|x| self.expression(x, names));
        let y = self
            .required(raw, &c.y, "y", "y = \"puck.vx\"")
            .and_then(|y| self.expression(y, names));
        Some(CurveKind::Trace { x: x?, y: y? })
    }

    /// The slots of a field or an exact or solution curve: the axis variables, the time
    /// t unless an axis has that name, then the parameters.
    fn axis_slots(
        &mut self,
        variables: Option<&Spanned<Vec<Spanned<String>>>>,
        params: Option<&Spanned<BTreeMap<String, Spanned<f64>>>>,
    ) -> Option<Slots> {
        let mut names = vec!["x".to_string(), "y".to_string()];
        if let Some(v) = variables {
            match v.get_ref().as_slice() {
                [a, b] if a.get_ref() != b.get_ref() => {
                    let mut ok = true;
                    for n in [a, b] {
                        ok &= self.name(n);
                    }
                    if !ok {
                        return None;
                    }
                    names = vec![a.get_ref().clone(), b.get_ref().clone()];
                }
                _ => {
                    self.error(
                        Diagnostic::at(v.span(), "`variables` names the horizontal and the vertical axis: two different names")
                            .hint("e.g. variables = [\"t\", \"v\"]"),
                    );
                    return None;
                }
            }
        }
        let time = if names.iter().any(|n| n == "t") {
            None
        } else {
            names.push("t".into());
            Some(2)
        };
        self.with_params(names, time, params)
    }

    /// The slots of a trace: t, then every body's quantities, then the parameters.
    fn trace_slots(
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

    fn with_params(
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

    /// Checks a variable name given in `variables`.
    fn name(&mut self, n: &Spanned<String>) -> bool {
        if expr::is_valid_name(n.get_ref()) && !n.get_ref().contains('.') {
            return true;
        }
        self.error(
            Diagnostic::at(n.span(), format!("`{}` cannot name a variable", n.get_ref()))
                .hint("a letter then letters, digits or `_`; not a function or a constant such as e or PI"),
        );
        false
    }

    /// Compiles an expression, reporting a problem inside the string.
    fn expression(&mut self, raw: &Spanned<String>, names: &[&str]) -> Option<Expr> {
        match expr::compile(raw.get_ref(), names) {
            Ok(e) => Some(e),
            Err(e) => {
                self.expression_error(raw, e);
                None
            }
        }
    }

    fn expression_error(&mut self, raw: &Spanned<String>, e: ExprError) {
        let span = expr::file_span(self.text, raw, e.range);
        let mut d = Diagnostic::at(span, e.message).label(e.label);
        if let Some(hint) = e.hint {
            d = d.hint(hint);
        }
        self.error(d);
    }

    fn required<'b, T>(
        &mut self,
        table: &Spanned<RawCurve>,
        value: &'b Option<Spanned<T>>,
        key: &str,
        example: &str,
    ) -> Option<&'b Spanned<T>> {
        if value.is_none() {
            let kind = table.get_ref().kind.get_ref();
            self.error(
                Diagnostic::at(table.span(), format!("a `{kind}` curve needs `{key}`"))
                    .hint(format!("add `{example}`")),
            );
        }
        value.as_ref()
    }

    fn color(&mut self, raw: Option<&Spanned<String>>, default: Rgba) -> Option<Rgba> {
        let Some(raw) = raw else {
            return Some(default);
        };
        let c = Rgba::parse(raw.get_ref());
        if c.is_none() {
            self.error(
                Diagnostic::at(raw.span(), format!("`{}` is not a colour", raw.get_ref()))
                    .hint("write #rrggbb, #rrggbbaa or #rgb, e.g. \"#cc3333\""),
            );
        }
        c
    }

    fn fraction(&mut self, raw: Option<&Spanned<f64>>, key: &str, default: f64) -> Option<f64> {
        let Some(raw) = raw else {
            return Some(default);
        };
        let v = *raw.get_ref();
        if v.is_finite() && v > 0.0 && v <= 2.0 {
            return Some(v);
        }
        self.error(
            Diagnostic::at(
                raw.span(),
                format!("`{key}` must be a fraction of a grid cell, > 0 and ≤ 2"),
            )
            .label(format!("{v}")),
        );
        None
    }

    fn line_width(&mut self, raw: Option<&Spanned<f64>>, default: f64) -> Option<f64> {
        let Some(raw) = raw else {
            return Some(default);
        };
        let v = *raw.get_ref();
        if v.is_finite() && v > 0.0 && v <= 50.0 {
            return Some(v);
        }
        self.error(
            Diagnostic::at(
                raw.span(),
                "`width` must be a line width in pixels, > 0 and ≤ 50",
            )
            .label(format!("{v}")),
        );
        None
    }
}

/// Returns the strings of a value that is a string or an array of strings, each with
/// its span, or `None` for anything else.
fn as_strings(text: &str, raw: &Spanned<toml::Value>) -> Option<Vec<Spanned<String>>> {
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
fn find_string_literal(text: &str, from: usize, to: usize, value: &str) -> Option<Range<usize>> {
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
fn present_curve_keys(c: &RawCurve) -> Vec<(&'static str, Range<usize>)> {
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
