//! Checks of single values in layers: names, expressions (with located errors inside
//! the string), required keys, colours, fractions and line widths.

use super::expr::{self, Expr, ExprError};
use super::{Diagnostic, Rgba};
use toml::Spanned;

use super::*;

impl LayerCheck<'_> {
    /// Checks a variable name given in `variables`.
    pub(super) fn name(&mut self, n: &Spanned<String>) -> bool {
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
    pub(super) fn expression(&mut self, raw: &Spanned<String>, names: &[&str]) -> Option<Expr> {
        match expr::compile(raw.get_ref(), names) {
            Ok(e) => Some(e),
            Err(e) => {
                self.expression_error(raw, e);
                None
            }
        }
    }

    pub(super) fn expression_error(&mut self, raw: &Spanned<String>, e: ExprError) {
        let span = expr::file_span(self.text, raw, e.range);
        let mut d = Diagnostic::at(span, e.message).label(e.label);
        if let Some(hint) = e.hint {
            d = d.hint(hint);
        }
        self.error(d);
    }

    pub(super) fn required<'b, T>(
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

    pub(super) fn color(&mut self, raw: Option<&Spanned<String>>, default: Rgba) -> Option<Rgba> {
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

    pub(super) fn fraction(
        &mut self,
        raw: Option<&Spanned<f64>>,
        key: &str,
        default: f64,
    ) -> Option<f64> {
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
            .label(crate::numbers::readable(v)),
        );
        None
    }

    pub(super) fn line_width(&mut self, raw: Option<&Spanned<f64>>, default: f64) -> Option<f64> {
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
            .label(crate::numbers::readable(v)),
        );
        None
    }
}
