//! The map from data coordinates to pixels, axis by axis, linear or logarithmic.

use super::*;

/// Maps one axis from data values to pixel positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct AxisMap {
    pub(super) scale: Scale,
    /// The range's ends in scaled units (the data or its log10).
    pub(super) u0: f64,
    pub(super) u1: f64,
    /// Where those ends land, in pixels.
    pub(super) p0: f64,
    pub(super) p1: f64,
    /// Pixels per scaled unit, (p1 - p0)/(u1 - u0), computed once.
    pub(super) ppu: f64,
}

impl AxisMap {
    pub(super) fn new(axis: &Axis, p0: f64, p1: f64) -> Self {
        let scaled = |v: f64| match axis.scale {
            Scale::Linear => v,
            Scale::Log10 => v.log10(),
        };
        let (u0, u1) = (scaled(axis.min), scaled(axis.max));
        Self {
            scale: axis.scale,
            u0,
            u1,
            p0,
            p1,
            ppu: (p1 - p0) / (u1 - u0),
        }
    }

    /// A linear axis through pixel `p0` at the value `u0`, with `ppu` pixels per unit.
    pub(super) fn affine(u0: f64, p0: f64, ppu: f64) -> Self {
        Self {
            scale: Scale::Linear,
            u0,
            u1: u0 + 1.0,
            p0,
            p1: p0 + ppu,
            ppu,
        }
    }

    pub(super) fn pixels_per_unit(&self) -> f64 {
        self.ppu
    }

    /// The pixel position of `v`; NaN when `v` cannot be shown (not positive on a log axis).
    pub(super) fn map(&self, v: f64) -> f64 {
        let u = match self.scale {
            Scale::Linear => v,
            Scale::Log10 if v > 0.0 => v.log10(),
            Scale::Log10 => f64::NAN,
        };
        self.p0 + (u - self.u0) * self.pixels_per_unit()
    }

    /// The data value at pixel position `p`.
    pub(super) fn unmap(&self, p: f64) -> f64 {
        let u = self.u0 + (p - self.p0) / self.pixels_per_unit();
        match self.scale {
            Scale::Linear => u,
            Scale::Log10 => 10f64.powf(u),
        }
    }

    /// Pixels moved per data unit at `v`: the derivative of [`AxisMap::map`].
    pub(super) fn derivative(&self, v: f64) -> f64 {
        match self.scale {
            Scale::Linear => self.pixels_per_unit(),
            Scale::Log10 => self.pixels_per_unit() / (v * std::f64::consts::LN_10),
        }
    }
}

/// One linear axis as `(v0, p0, ppu)`: the pixel is p = p0 + (v - v0)·ppu.
pub type AxisCoefficients = (f64, f64, f64);

/// The data → pixel transform of a chart: f64 data in, f32 pixels out, y pointing down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DataToPixel {
    pub(super) x: AxisMap,
    pub(super) y: AxisMap,
}

impl DataToPixel {
    /// The linear transform p = p0 + (v - v0)·ppu on each axis, from `(v0, p0, ppu)` for
    /// x and for y (a y axis pointing up has a negative `ppu`).
    pub fn affine(x: (f64, f64, f64), y: (f64, f64, f64)) -> Self {
        Self {
            x: AxisMap::affine(x.0, x.1, x.2),
            y: AxisMap::affine(y.0, y.1, y.2),
        }
    }

    /// The coefficients `(v0, p0, ppu)` of x and y when both axes are linear, such that
    /// p = p0 + (v - v0)·ppu reproduces [`DataToPixel::apply_f64`] exactly.
    pub fn linear_coefficients(&self) -> Option<(AxisCoefficients, AxisCoefficients)> {
        let linear = self.x.scale == Scale::Linear && self.y.scale == Scale::Linear;
        linear.then_some((
            (self.x.u0, self.x.p0, self.x.ppu),
            (self.y.u0, self.y.p0, self.y.ppu),
        ))
    }

    /// The pixel position of the data point `(x, y)`. A coordinate that a log axis cannot
    /// show (zero or negative) maps to NaN.
    pub fn apply(&self, x: f64, y: f64) -> (f32, f32) {
        let (px, py) = self.apply_f64(x, y);
        (px as f32, py as f32)
    }

    /// Like [`DataToPixel::apply`], without rounding to f32.
    pub fn apply_f64(&self, x: f64, y: f64) -> (f64, f64) {
        (self.x.map(x), self.y.map(y))
    }

    /// The data point at pixel position `(px, py)`.
    pub fn invert(&self, px: f32, py: f32) -> (f64, f64) {
        (self.x.unmap(f64::from(px)), self.y.unmap(f64::from(py)))
    }

    /// The unit pixel direction of the data-space direction `(dx, dy)` at the data point
    /// `(x, y)`. The x and y scales may differ (and on log axes vary from point to point),
    /// so the direction is pushed through the transform's derivative there. Returns `None`
    /// for a zero or non-finite direction.
    pub fn direction(&self, x: f64, y: f64, dx: f64, dy: f64) -> Option<(f64, f64)> {
        let px = dx * self.x.derivative(x);
        let py = dy * self.y.derivative(y);
        let length = px.hypot(py);
        (length.is_finite() && length > 0.0).then(|| (px / length, py / length))
    }
}
