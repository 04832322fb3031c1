//! Checks of single values: required keys, colours, finite, positive and non-negative
//! numbers, and vectors of two finite numbers.

use glam::DVec2;
use toml::Spanned;

use super::Validator;
use crate::numbers::Readable;
use crate::scene::raw::{RawForce, RawVec2};
use crate::scene::{Diagnostic, Rgba};

impl Validator {
    pub(super) fn required<'a, T>(
        &mut self,
        table: &Spanned<RawForce>,
        value: &'a Option<Spanned<T>>,
        key: &str,
        example: &str,
    ) -> Option<&'a Spanned<T>> {
        if value.is_none() {
            let kind = table.get_ref().kind.get_ref();
            self.error(
                Diagnostic::at(table.span(), format!("a `{kind}` force needs `{key}`"))
                    .hint(format!("add `{example}`")),
            );
        }
        value.as_ref()
    }

    pub(super) fn color(&mut self, raw: &Spanned<String>) -> Option<Rgba> {
        let c = Rgba::parse(raw.get_ref());
        if c.is_none() {
            self.error(
                Diagnostic::at(raw.span(), format!("`{}` is not a colour", raw.get_ref()))
                    .hint("write #rrggbb, #rrggbbaa or #rgb, e.g. \"#cc3333\""),
            );
        }
        c
    }

    pub(super) fn finite(&mut self, raw: &Spanned<f64>, key: &str) -> Option<f64> {
        let v = *raw.get_ref();
        if v.is_finite() {
            return Some(v);
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be a finite number"))
                .label(format!("{} is not finite", Readable(v))),
        );
        None
    }

    /// Checks a coefficient of restitution: 0 ≤ e ≤ 1.
    pub(super) fn restitution(&mut self, raw: &Spanned<f64>) -> Option<f64> {
        let v = self.finite(raw, "restitution")?;
        if (0.0..=1.0).contains(&v) {
            return Some(v);
        }
        self.error(
            Diagnostic::at(raw.span(), "`restitution` must be between 0 and 1")
                .label(format!("{v} is outside 0 ≤ e ≤ 1"))
                .hint("e = 1 is elastic (bounces back at full speed), e = 0 plastic (no bounce)"),
        );
        None
    }

    pub(super) fn positive(&mut self, raw: &Spanned<f64>, key: &str) -> Option<f64> {
        let v = self.finite(raw, key)?;
        if v > 0.0 {
            return Some(v);
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be > 0"))
                .label(format!("{} is not positive", Readable(v))),
        );
        None
    }

    pub(super) fn non_negative(&mut self, raw: &Spanned<f64>, key: &str) -> Option<f64> {
        let v = self.finite(raw, key)?;
        if v >= 0.0 {
            return Some(v);
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be ≥ 0"))
                .label(format!("{} is negative", Readable(v))),
        );
        None
    }

    /// Checks an optional vector: `Some(None)` when absent, `None` after an error.
    pub(super) fn optional_vec2(
        &mut self,
        raw: Option<&Spanned<RawVec2>>,
        key: &str,
    ) -> Option<Option<DVec2>> {
        match raw {
            Some(v) => self.vec2(v, key).map(Some),
            None => Some(None),
        }
    }

    pub(super) fn vec2(&mut self, raw: &Spanned<RawVec2>, key: &str) -> Option<DVec2> {
        let RawVec2([x, y]) = *raw.get_ref();
        if x.is_finite() && y.is_finite() {
            return Some(DVec2::new(x, y));
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be two finite numbers"))
                .label(format!("[{}, {}] is not finite", Readable(x), Readable(y))),
        );
        None
    }
}
