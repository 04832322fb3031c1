//! `[[field]]` tables: slope and arrow fields of an expression over the axes' grid.

use super::{Diagnostic, Rgba};
use std::collections::BTreeMap;
use toml::Spanned;

use super::*;

impl LayerCheck<'_> {
    pub(super) fn field(&mut self, f: &RawField) -> Option<Field> {
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

    pub(super) fn field_function(
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

    /// The slots of a field or an exact or solution curve: the axis variables, the time
    /// t unless an axis has that name, then the parameters.
    pub(super) fn axis_slots(
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
}
