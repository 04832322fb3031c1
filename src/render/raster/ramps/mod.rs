//! Arrows' shafts and heads covered by ramps, not by tiny-skia's samples.
//!
//! A shape here is the intersection of a few slabs. Each slab k is a linear function
//! of the pixel, t_k = nx_k·x + ny_k·y + d_k, with the slab's width in pixels along a
//! unit normal (nx_k, ny_k), and it covers a pixel by the ramp
//!
//!   v_k = clamp(min(t_k + g_k, h_k - t_k), 0, 1),
//!
//! which rises from 0 to 1 across the half pixel either side of one side of the slab
//! and falls again across the other. A pixel's coverage is the product of its ramps.
//! An arrow's shaft is two slabs (across it, of its width; along it, of its length),
//! its head three (each edge a slab open on one side: h = +∞).
//!
//! Along a row or a column a ramp is the pixel's exact area inside the slab's side,
//! and a rectangle along the rows is covered exactly; a side at an angle is off by at
//! most 0.043 of a pixel (at 45°, where the exact area is a parabola about the ramp),
//! and where two sides cross one pixel (a corner) their product stands for the area.
//! tiny-skia's own coverage is four sub-rows of quarter-pixel columns;
//! `tests/integration/every_scene.rs` bounds the difference between the two, and
//! `docs/performance.md` states it.
//!
//! Why: an arrow is some 60 pixel rows of three to eight pixels. With tiny-skia's
//! arithmetic a row costs 11 to 18 ns (four sub-rows' crossings, their spans summed)
//! however it is vectorised. A ramp is a multiply, an add and four comparisons for
//! eight pixels at once, with no branch on where the sides fall, and a steep shaft's
//! rows of at most four pixels go two to a register.
//!
//! A shape's rows are laid out first (`Ramps::row_layout`, eight rows to a register
//! in `avx2::lay_out`): each row's pixels lo..hi that may be covered and each slab's t
//! at pixel lo, T. A pixel's t is then T + nx·(x - lo), in f32, by the same operations
//! in the same order on every processor: two narrow rows (at most four pixels each) or
//! eight pixels of a row to an AVX2 register, one pixel at a time without AVX2 or
//! before the image's right edge, the same bytes (tested). The blend is
//! [`Ink::blend`]'s.

use std::cell::RefCell;

use tiny_skia::Pixmap;

use super::floor;
use crate::render::sprite::Ink;

/// A pixel whose coverage rounds to a byte above zero lies at least 1/510 of a pixel
/// inside every ramp; the columns a row is searched over are widened by this much,
/// far more than f32's rounding of them, so that no such pixel is missed.
const SLACK: f32 = 0.01;

/// A shape of `E` slabs (the module's comment), in coordinates relative to a whole
/// pixel near it, so that f32 keeps a thousandth of a pixel however large the image.
#[derive(Clone, Copy, Debug)]
pub struct Ramps<const E: usize> {
    /// Each slab's t = nx·x + ny·y + d at pixel (x, y) relative to `origin` (the
    /// half pixel to the pixel's centre is in d), and its ramp's g and h.
    nx: [f32; E],
    ny: [f32; E],
    d: [f32; E],
    g: [f32; E],
    h: [f32; E],
    origin: (i64, i64),
    /// The pixel rows first..end that may be covered.
    rows: (i64, i64),
    /// Where each slab bounds a row's covered pixels, linear in the row y (relative
    /// to the origin): x > lo.0 + lo.1·y and x < hi.0 + hi.1·y, widened by
    /// [`SLACK`]; a slab level with the rows bounds nothing (±1e9).
    lo: [(f32, f32); E],
    hi: [(f32, f32); E],
}

/// A slab in f64 before it is stored: unit normal, offset at pixel centres relative
/// to the origin, and the ramp's g and h.
struct Slab {
    n: (f64, f64),
    d: f64,
    g: f64,
    h: f64,
}

impl<const E: usize> Ramps<E> {
    /// Stores `slabs` relative to `origin`, covering at most rows `rows` (before the
    /// image cuts them); `None` when anything is not finite.
    fn from_slabs(slabs: [Slab; E], origin: (f64, f64), rows: (f64, f64)) -> Option<Self> {
        let finite = slabs
            .iter()
            .all(|s| s.n.0.is_finite() && s.n.1.is_finite() && s.d.is_finite() && s.g.is_finite())
            && rows.0.is_finite()
            && rows.1.is_finite();
        if !finite {
            return None;
        }
        let clamp = |v: f64| v.clamp(-1e9, 1e9);
        let oy = origin.1 as i64;
        let mut r = Ramps {
            nx: [0.0; E],
            ny: [0.0; E],
            d: [0.0; E],
            g: [0.0; E],
            h: [0.0; E],
            origin: (origin.0 as i64, oy),
            // Rows whose centre may lie inside, one to spare each side.
            rows: (
                oy + floor(clamp(rows.0 - 0.5)),
                oy + floor(clamp(rows.1 - 0.5)) + 2,
            ),
            lo: [(-1e9, 0.0); E],
            hi: [(1e9, 0.0); E],
        };
        for (k, s) in slabs.iter().enumerate() {
            let (nx, ny) = s.n;
            (r.nx[k], r.ny[k], r.d[k]) = (nx as f32, ny as f32, s.d as f32);
            (r.g[k], r.h[k]) = (s.g as f32, s.h as f32);
            // t = nx·x + ny·y + d is inside the ramp's rise and fall, -g < t < h, for
            // x between (-g - ny·y - d)/nx and (h - ny·y - d)/nx; a slab (nearly) level
            // with the rows bounds only rows.
            if nx.abs() <= 1e-6 {
                continue;
            }
            let slope = -ny / nx;
            let a = (-s.g - s.d) / nx;
            let b = if s.h.is_finite() {
                (s.h - s.d) / nx
            } else {
                nx.signum() * 1e9
            };
            let (l, h) = if nx > 0.0 { (a, b) } else { (b, a) };
            r.lo[k] = ((clamp(l) - f64::from(SLACK)) as f32, slope as f32);
            r.hi[k] = ((clamp(h) + f64::from(SLACK)) as f32, slope as f32);
        }
        Some(r)
    }

    /// The pixel rows first..end that may be covered in an image `height` high.
    fn rows_within(&self, height: usize) -> (i64, i64) {
        (self.rows.0.max(0), self.rows.1.min(height as i64))
    }

    /// Row `y`'s layout in an image `width` wide: its pixels lo..hi that may be
    /// covered (empty when lo >= hi: the integers strictly between the slabs' bounds,
    /// cut to the image), and each slab's t at pixel lo,
    /// T = nx·(lo - ox) + (ny·(y - oy) + d). Every pixel's t is then T + nx·(x - lo).
    /// `avx2::lay_out` does the same eight rows at a time, operation for operation.
    #[inline(always)]
    fn row_layout(&self, y: i64, width: usize) -> (i32, i32, [f32; E]) {
        let yr = (y - self.origin.1) as f32;
        let (mut lo, mut hi) = (-1e9f32, 1e9f32);
        for k in 0..E {
            let l = self.lo[k].0 + self.lo[k].1 * yr;
            let h = self.hi[k].0 + self.hi[k].1 * yr;
            lo = if l > lo { l } else { lo };
            hi = if h < hi { h } else { hi };
        }
        // Cut to one pixel either side of the image before rounding.
        let ox = self.origin.0 as i32;
        let (left, right) = ((-1 - ox) as f32, (width as i32 + 1 - ox) as f32);
        let lo = if lo > left { lo } else { left };
        let lo = if lo < right { lo } else { right };
        let hi = if hi < right { hi } else { right };
        let hi = if hi > left { hi } else { left };
        let lo = (lo.floor() as i32 + 1 + ox).max(0);
        let hi = (hi.ceil() as i32 + ox).min(width as i32);
        let xr = (lo - ox) as f32;
        let t = std::array::from_fn(|k| self.nx[k] * xr + (self.ny[k] * yr + self.d[k]));
        (lo, hi, t)
    }

    /// The coverage in 0..=255 of the pixel `off` pixels right of its row's first,
    /// whose slabs' t there are `t`: round(255 · Π_k clamp(min(t_k + g_k, h_k - t_k),
    /// 0, 1)) with t_k = T_k + nx_k·off, ties to even, min and max taken as the
    /// registers take them.
    #[inline(always)]
    fn coverage(&self, t: [f32; E], off: f32) -> u8 {
        let min = |a: f32, b: f32| if a < b { a } else { b };
        let max = |a: f32, b: f32| if a > b { a } else { b };
        let mut cov = 1.0f32;
        for k in 0..E {
            let t = t[k] + self.nx[k] * off;
            let v = min(t + self.g[k], self.h[k] - t);
            cov *= max(min(v, 1.0), 0.0);
        }
        (cov * 255.0).round_ties_even() as u8
    }
}

/// A shape's rows laid out ([`Ramps::row_layout`]): for n rows from the first, each
/// row's pixels lo..hi, and slab k's T for row j at `t[k * stride + j]`, with room to
/// spare after each (a register's worth).
#[derive(Default)]
struct Rows {
    lo: Vec<i32>,
    hi: Vec<i32>,
    t: Vec<f32>,
    stride: usize,
    /// Where the AVX2 path has them (`avx2::lay_out`): each row's byte offset of
    /// its pixel lo in the image, and whether the row is narrow (at most four pixels
    /// from lo, all inside the image: all ones) or not (zero).
    at: Vec<i32>,
    narrow: Vec<i32>,
}

impl Rows {
    /// Room for n rows of E slabs, rounded up to whole registers of eight rows.
    fn clear(&mut self, n: usize, slabs: usize) {
        let stride = n.div_ceil(8) * 8 + 8;
        self.stride = stride;
        // Grown, never shrunk: a shaft and a head take turns.
        if self.lo.len() < stride {
            self.lo.resize(stride, 0);
            self.hi.resize(stride, 0);
            self.at.resize(stride, 0);
            self.narrow.resize(stride, 0);
        }
        if self.t.len() < slabs * stride {
            self.t.resize(slabs * stride, 0.0);
        }
    }

    /// Row j's slabs' terms.
    #[inline(always)]
    fn terms<const E: usize>(&self, j: usize) -> [f32; E] {
        std::array::from_fn(|k| self.t[k * self.stride + j])
    }
}

thread_local! {
    static ROWS: RefCell<Rows> = RefCell::new(Rows::default());
}

impl Ramps<2> {
    /// The shaft of an arrow: the rectangle of half-width `half` about the segment
    /// from `a` to `b` (pixels), with square ends there, as tiny-skia strokes a line
    /// with butt caps; `None` when it has no length or is not finite.
    pub fn shaft(a: (f64, f64), b: (f64, f64), half: f64) -> Option<Self> {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt();
        Self::shaft_along(a, (dx / len, dy / len), len, half)
    }

    /// [`Ramps::shaft`] from `a` along the unit vector `unit` for `len` pixels, for
    /// a caller that has them (no square root).
    pub fn shaft_along(a: (f64, f64), unit: (f64, f64), len: f64, half: f64) -> Option<Self> {
        if !(len > 1e-9 && len.is_finite() && half > 0.0) {
            return None;
        }
        let (ux, uy) = unit;
        let dy = len * uy;
        let origin = (floor(a.0) as f64, floor(a.1) as f64);
        // The start relative to the origin, less the half pixel to pixel centres.
        let (px, py) = (a.0 - origin.0 - 0.5, a.1 - origin.1 - 0.5);
        // Across: t = n·(p - a), the signed distance from the axis; covered for
        // |t| < half, ramped over a half pixel each side.
        let (nx, ny) = (-uy, ux);
        let across = Slab {
            n: (nx, ny),
            d: -(nx * px + ny * py),
            g: half + 0.5,
            h: half + 0.5,
        };
        // Along: t = u·(p - a), from 0 at the start to len at the end.
        let along = Slab {
            n: (ux, uy),
            d: -(ux * px + uy * py),
            g: 0.5,
            h: len + 0.5,
        };
        // The rectangle grown by half a pixel: its corners' rows.
        let ey = (half + 0.5) * ny;
        let sy = 0.5 * uy;
        let ys = [
            py + 0.5 - sy + ey,
            py + 0.5 - sy - ey,
            py + 0.5 + dy + sy + ey,
            py + 0.5 + dy + sy - ey,
        ];
        let top = ys.iter().copied().fold(f64::INFINITY, f64::min);
        let bottom = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Self::from_slabs([across, along], origin, (top, bottom))
    }
}

impl Ramps<3> {
    /// An arrow's head: the triangle from its tip back `len` pixels along the unit
    /// vector -`unit` to its base, `len` wide there (each edge a slab open on its
    /// outer side); `None` when not finite or without length.
    pub fn head(tip: (f64, f64), unit: (f64, f64), len: f64) -> Option<Self> {
        if !(len > 1e-9 && len.is_finite()) {
            return None;
        }
        let origin = (floor(tip.0) as f64, floor(tip.1) as f64);
        // The tip relative to the origin, less the half pixel to pixel centres.
        let (px, py) = (tip.0 - origin.0 - 0.5, tip.1 - origin.1 - 0.5);
        let (ux, uy) = unit;
        let (nx, ny) = (-uy, ux);
        let edge = |mx: f64, my: f64, at: (f64, f64)| Slab {
            n: (mx, my),
            d: -(mx * at.0 + my * at.1),
            g: 0.5,
            h: f64::INFINITY,
        };
        // The base, facing the tip: u·(p - base) >= 0.
        let base = edge(ux, uy, (px - len * ux, py - len * uy));
        // The sides: with p - tip = a·u + c·n, inside where -a - 2|c| >= 0, so each
        // side's unit normal is (-u ∓ 2n)/√5.
        let r5 = 1.0 / 5f64.sqrt();
        let left = edge(-(ux + 2.0 * nx) * r5, -(uy + 2.0 * ny) * r5, (px, py));
        let right = edge(-(ux - 2.0 * nx) * r5, -(uy - 2.0 * ny) * r5, (px, py));
        Self::from_edges([base, left, right], origin)
    }

    /// Stores a triangle's three edges (slabs open on their outer side), with the
    /// rows of the triangle grown by half a pixel.
    fn from_edges(slabs: [Slab; 3], origin: (f64, f64)) -> Option<Self> {
        // The triangle grown by half a pixel along each edge's normal: its corners,
        // where neighbouring grown edges cross (further out at a sharp corner).
        let (mut top, mut bottom) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..3 {
            let (a, b) = (&slabs[k], &slabs[(k + 1) % 3]);
            // n_a·q + d_a + 1/2 = 0 and n_b·q + d_b + 1/2 = 0, for q a pixel's
            // centre less a half pixel; the row is q.y + 1/2.
            let det = a.n.0 * b.n.1 - a.n.1 * b.n.0;
            let y = (b.n.0 * (a.d + 0.5) - a.n.0 * (b.d + 0.5)) / det + 0.5;
            top = top.min(y);
            bottom = bottom.max(y);
        }
        Self::from_slabs(slabs, origin, (top, bottom))
    }
}

/// Fills `ramps`' shape with `ink` (the module's comment).
pub fn fill_ramps<const E: usize>(pixmap: &mut Pixmap, ramps: &Ramps<E>, ink: Ink) {
    fill_with(pixmap, ramps, ink, Path::Avx2);
}

/// Which registers [`fill_with`] may use: AVX2 where the processor has it, or none
/// (pixel by pixel). Both give the same bytes (tested).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    Avx2,
    #[cfg_attr(not(test), allow(dead_code))]
    Pixels,
}

/// [`fill_ramps`] by the registers `path` allows.
fn fill_with<const E: usize>(pixmap: &mut Pixmap, ramps: &Ramps<E>, ink: Ink, path: Path) {
    let (width, height) = (pixmap.width() as usize, pixmap.height() as usize);
    let (first, end) = ramps.rows_within(height);
    if first >= end {
        return;
    }
    let data = pixmap.data_mut();
    let n = (end - first) as usize;
    ROWS.with(|rows| {
        let rows = &mut rows.borrow_mut();
        rows.clear(n, E);
        #[cfg(target_arch = "x86_64")]
        // Byte offsets into the image as i32 (`Rows::at`).
        if path != Path::Pixels
            && width >= 8
            && data.len() < i32::MAX as usize
            && super::avx2::available()
        {
            // SAFETY: the processor has AVX2, just checked, and the image is at least
            // eight pixels wide.
            unsafe {
                avx2::lay_out(ramps, first, n, width, rows);
                avx2::fill(data, width, first, n, ramps, rows, &ink);
            }
            return;
        }
        let _ = path;
        for j in 0..n {
            let (lo, hi, t) = ramps.row_layout(first + j as i64, width);
            rows.lo[j] = lo;
            rows.hi[j] = hi;
            let stride = rows.stride;
            for (k, t) in t.into_iter().enumerate() {
                rows.t[k * stride + j] = t;
            }
            fill_row(data, width, first + j as i64, ramps, rows, j, lo, &ink);
        }
    })
}

/// Blends row j of `rows` (image row `y`) from pixel `from` to its end pixel by
/// pixel: every pixel's bytes on every processor.
#[allow(clippy::too_many_arguments)]
#[inline]
fn fill_row<const E: usize>(
    data: &mut [u8],
    width: usize,
    y: i64,
    r: &Ramps<E>,
    rows: &Rows,
    j: usize,
    from: i32,
    ink: &Ink,
) {
    let (lo, hi) = (rows.lo[j], rows.hi[j]);
    let t = rows.terms::<E>(j);
    for x in from..hi {
        let c = r.coverage(t, (x - lo) as f32);
        let k = 4 * (y as usize * width + x as usize);
        ink.blend(&mut data[k..k + 4], c);
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(test)]
mod tests;
