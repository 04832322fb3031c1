//! The figure parts of a scene: the `[axes]` table, `[[field]]` layers and `[[curve]]`
//! layers, from their raw TOML to checked values with compiled expressions.
//!
//! Every expression is compiled here, once, with the names it may read; a bad one is
//! reported at the offending token inside its string. Each layer records the *slots* it
//! reads (see [`super::expr`]): the horizontal variable, the vertical variable, the time
//! `t` (unless an axis is called `t`), then the layer's parameters in the order written.

mod curves;
mod fields;
mod values;

use curves::as_strings;

use std::collections::BTreeMap;

use glam::DVec2;
use serde::Deserialize;
use toml::Spanned;

use super::expr::{self, Expr};
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
    /// Slot names: horizontal, vertical, \[t,\] parameters (for traces: t, body values,
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
pub(super) const MAX_GRID: i64 = 500;
/// The most steps a numerical solution may take.
pub const MAX_SOLUTION_STEPS: usize = 100_000;

/// Curve kinds and the keys each takes besides `kind`, `params`, `variables`, `color`,
/// `width`, `dash` and `label`.
pub(super) const CURVE_KINDS: &[(&str, &[&str])] = &[
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
}
