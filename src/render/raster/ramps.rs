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
//! Each pixel's coverage is computed from its own coordinates (not stepped from its
//! neighbours'), in f32, by the same operations in the same order on every processor:
//! eight pixels at a time with AVX2, one by one without it, the same bytes (tested).
//! The blend is [`Ink::blend`]'s.

use std::cell::RefCell;

use tiny_skia::Pixmap;

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

/// ⌊v⌋ for |v| < 2^52 without a call into the maths library (the default target
/// has no rounding instruction); v is first cut to ±1e9.
#[inline(always)]
fn floor(v: f64) -> f64 {
    let v = v.clamp(-1e9, 1e9);
    let t = v as i64 as f64;
    if t > v {
        t - 1.0
    } else {
        t
    }
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
                oy + floor(rows.0 - 0.5) as i64,
                oy + floor(rows.1 - 0.5) as i64 + 2,
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
        let origin = (floor(a.0), floor(a.1));
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
    /// A triangle (an arrow's head), its points in pixels in either winding; `None`
    /// when it has no area or is not finite.
    pub fn triangle(points: [(f64, f64); 3]) -> Option<Self> {
        let origin = (floor(points[0].0), floor(points[0].1));
        let rel = points.map(|p| (p.0 - origin.0, p.1 - origin.1));
        let mean = (
            (rel[0].0 + rel[1].0 + rel[2].0) / 3.0,
            (rel[0].1 + rel[1].1 + rel[2].1) / 3.0,
        );
        let mut slabs = [(); 3].map(|_| Slab {
            n: (0.0, 0.0),
            d: 0.0,
            g: 0.5,
            h: f64::INFINITY,
        });
        for (i, slab) in slabs.iter_mut().enumerate() {
            let (a, b) = (rel[i], rel[(i + 1) % 3]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len = (dx * dx + dy * dy).sqrt();
            if !(len > 1e-9 && len.is_finite()) {
                return None;
            }
            // The edge's unit normal towards the inside (where the mean lies).
            let (mut nx, mut ny) = (dy / len, -dx / len);
            if nx * (mean.0 - a.0) + ny * (mean.1 - a.1) < 0.0 {
                (nx, ny) = (-nx, -ny);
            }
            // t = n·(p - a) at pixel centres p: the distance inside the edge.
            slab.n = (nx, ny);
            slab.d = -(nx * (a.0 - 0.5) + ny * (a.1 - 0.5));
        }
        // No area: the mean on an edge's line.
        if slabs.iter().any(|s| {
            let t = s.n.0 * (mean.0 - 0.5) + s.n.1 * (mean.1 - 0.5) + s.d;
            t.abs() < 1e-9
        }) {
            return None;
        }
        Self::from_edges(slabs, origin)
    }

    /// An arrow's head: the triangle from its tip back `len` pixels along the unit
    /// vector -`unit` to its base, `len` wide there, as [`Ramps::triangle`] of those
    /// points would be but without their square roots; `None` when not finite or
    /// without length.
    pub fn head(tip: (f64, f64), unit: (f64, f64), len: f64) -> Option<Self> {
        if !(len > 1e-9 && len.is_finite()) {
            return None;
        }
        let origin = (floor(tip.0), floor(tip.1));
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
mod avx2 {
    use std::arch::x86_64::*;

    use super::{fill_row, Ramps, Rows};
    use crate::render::raster::prefetch;

    /// How many rows ahead [`fill`] asks for pixels.
    const AHEAD: usize = 4;
    use crate::render::sprite::Ink;

    /// The rows laid out in `rows` (from image row `first`) eight pixels a register,
    /// with [`super::fill_row`]'s bytes. Two rows of at most four pixels each (a steep
    /// shaft's) share a register; other rows take eight pixels a register from their
    /// first. Pixels a register would take past the image's right edge are blended
    /// one by one.
    ///
    /// # Safety
    /// The processor must have AVX2, and the image must be at least eight pixels wide.
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    pub(super) unsafe fn fill<const E: usize>(
        data: &mut [u8],
        width: usize,
        first: i64,
        n: usize,
        r: &Ramps<E>,
        rows: &Rows,
        ink: &Ink,
    ) {
        let k = Kernel::new(r, ink);
        let mut j = 0;
        while j < n {
            // The pixels four rows on, which the rows laid out already give: an
            // arrow's few pixels a row are each a line of memory to wait for.
            if j + AHEAD + 1 < n {
                prefetch(data, rows.at[j + AHEAD] as usize);
                prefetch(data, rows.at[j + AHEAD + 1] as usize);
            }
            if j + 1 < n && rows.narrow[j] & rows.narrow[j + 1] != 0 {
                k.pair(data, rows, j);
                j += 2;
                continue;
            }
            k.row(data, width, first + j as i64, rows, j);
            j += 1;
        }
    }

    /// [`Ramps::row_layout`] of rows first..first + n into `rows`, eight rows a
    /// register, operation for operation (the same values).
    #[target_feature(enable = "avx2")]
    pub(super) fn lay_out<const E: usize>(
        r: &Ramps<E>,
        first: i64,
        n: usize,
        width: usize,
        rows: &mut Rows,
    ) {
        let ox = r.origin.0 as i32;
        let (left, right) = (
            _mm256_set1_ps((-1 - ox) as f32),
            _mm256_set1_ps((width as i32 + 1 - ox) as f32),
        );
        let iota = _mm256_setr_ps(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0);
        let lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        let (five, last) = (_mm256_set1_epi32(5), _mm256_set1_epi32(width as i32 - 3));
        let (one, oxv, zero, w) = (
            _mm256_set1_epi32(1),
            _mm256_set1_epi32(ox),
            _mm256_setzero_si256(),
            _mm256_set1_epi32(width as i32),
        );
        let stride = rows.stride;
        let mut j = 0;
        while j < n {
            // Rows j..j + 8 (relative to the origin, exact in f32).
            let yr = _mm256_add_ps(_mm256_set1_ps((first + j as i64 - r.origin.1) as f32), iota);
            let (mut lo, mut hi) = (_mm256_set1_ps(-1e9), _mm256_set1_ps(1e9));
            for k in 0..E {
                let l = _mm256_add_ps(
                    _mm256_set1_ps(r.lo[k].0),
                    _mm256_mul_ps(_mm256_set1_ps(r.lo[k].1), yr),
                );
                let h = _mm256_add_ps(
                    _mm256_set1_ps(r.hi[k].0),
                    _mm256_mul_ps(_mm256_set1_ps(r.hi[k].1), yr),
                );
                // max(a, b) is a > b ? a : b, min(a, b) a < b ? a : b: as the scalar.
                lo = _mm256_max_ps(l, lo);
                hi = _mm256_min_ps(h, hi);
            }
            let lo = _mm256_min_ps(_mm256_max_ps(lo, left), right);
            let hi = _mm256_max_ps(_mm256_min_ps(hi, right), left);
            let lo = _mm256_add_epi32(_mm256_cvttps_epi32(_mm256_floor_ps(lo)), one);
            let lo = _mm256_max_epi32(_mm256_add_epi32(lo, oxv), zero);
            let hi = _mm256_add_epi32(_mm256_cvttps_epi32(_mm256_ceil_ps(hi)), oxv);
            let hi = _mm256_min_epi32(hi, w);
            let xr = _mm256_cvtepi32_ps(_mm256_sub_epi32(lo, oxv));
            // Each row's byte offset of its pixel lo, 4·(y·width + lo) (the image
            // holds under 2^31 bytes), and whether hi - lo <= 4 and lo <= width - 4.
            let ys = _mm256_add_epi32(_mm256_set1_epi32((first + j as i64) as i32), lanes);
            let at = _mm256_slli_epi32(_mm256_add_epi32(_mm256_mullo_epi32(ys, w), lo), 2);
            let narrow = _mm256_and_si256(
                _mm256_cmpgt_epi32(five, _mm256_sub_epi32(hi, lo)),
                _mm256_cmpgt_epi32(last, lo),
            );
            // SAFETY: the rows hold whole registers of eight past n (Rows::clear).
            unsafe {
                _mm256_storeu_si256(rows.lo[j..j + 8].as_mut_ptr().cast(), lo);
                _mm256_storeu_si256(rows.hi[j..j + 8].as_mut_ptr().cast(), hi);
                _mm256_storeu_si256(rows.at[j..j + 8].as_mut_ptr().cast(), at);
                _mm256_storeu_si256(rows.narrow[j..j + 8].as_mut_ptr().cast(), narrow);
            }
            for k in 0..E {
                let y_term = _mm256_add_ps(
                    _mm256_mul_ps(_mm256_set1_ps(r.ny[k]), yr),
                    _mm256_set1_ps(r.d[k]),
                );
                let t = _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(r.nx[k]), xr), y_term);
                let at = k * stride + j;
                // SAFETY: as above.
                unsafe { _mm256_storeu_ps(rows.t[at..at + 8].as_mut_ptr(), t) };
            }
            j += 8;
        }
    }

    /// What every register of one shape needs, set once.
    struct Kernel<'a, const E: usize> {
        r: &'a Ramps<E>,
        nx: [__m256; E],
        g: [__m256; E],
        h: [__m256; E],
        /// nx·(0, 1, 2, 3, 0, 1, 2, 3): what a pixel of a pair adds to its row's t.
        pair_off: [__m256; E],
        /// The ink's premultiplied channels, four pixels' worth.
        s: __m256i,
        opaque: bool,
        ink: Ink,
    }

    impl<'a, const E: usize> Kernel<'a, E> {
        #[inline]
        #[target_feature(enable = "avx2")]
        fn new(r: &'a Ramps<E>, ink: &Ink) -> Self {
            let [sr, sg, sb, sa] = ink.rgba().map(|v| v as i16);
            let four = _mm256_setr_ps(0.0, 1.0, 2.0, 3.0, 0.0, 1.0, 2.0, 3.0);
            Kernel {
                r,
                nx: r.nx.map(|v| _mm256_set1_ps(v)),
                g: r.g.map(|v| _mm256_set1_ps(v)),
                h: r.h.map(|v| _mm256_set1_ps(v)),
                pair_off: r.nx.map(|v| _mm256_mul_ps(_mm256_set1_ps(v), four)),
                s: _mm256_setr_epi16(
                    sr, sg, sb, sa, sr, sg, sb, sa, sr, sg, sb, sa, sr, sg, sb, sa,
                ),
                opaque: ink.is_opaque(),
                ink: *ink,
            }
        }

        /// The coverage in 0..=255 (32-bit lanes) of the pixels whose slabs' t are
        /// `t`: [`Ramps::coverage`]'s operations lane by lane.
        #[inline]
        #[target_feature(enable = "avx2")]
        fn cover(&self, t: [__m256; E]) -> __m256i {
            let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
            let mut cov = one;
            for ((t, g), h) in t.iter().zip(&self.g).zip(&self.h) {
                let v = _mm256_min_ps(_mm256_add_ps(*t, *g), _mm256_sub_ps(*h, *t));
                cov = _mm256_mul_ps(cov, _mm256_max_ps(_mm256_min_ps(v, one), zero));
            }
            // round(255·cov), ties to even (the default rounding mode).
            _mm256_cvtps_epi32(_mm256_mul_ps(cov, _mm256_set1_ps(255.0)))
        }

        /// Blends eight pixels `px` (as loaded: pixels 0..4 in the low half, 4..8 in
        /// the high) with coverage `c` (32-bit lanes in the same order): [`Ink::blend`]'s
        /// arithmetic.
        #[inline]
        #[target_feature(enable = "avx2")]
        fn blend(&self, px: __m256i, c: __m256i) -> __m256i {
            // Each pixel's coverage in its four 16-bit words, in the order unpacking
            // its bytes gives: pixels 0, 1, 4, 5, then 2, 3, 6, 7.
            const Z: i8 = -128;
            let lo = _mm256_setr_epi8(
                0, Z, 0, Z, 0, Z, 0, Z, 4, Z, 4, Z, 4, Z, 4, Z, 0, Z, 0, Z, 0, Z, 0, Z, 4, Z, 4, Z,
                4, Z, 4, Z,
            );
            let hi = _mm256_setr_epi8(
                8, Z, 8, Z, 8, Z, 8, Z, 12, Z, 12, Z, 12, Z, 12, Z, 8, Z, 8, Z, 8, Z, 8, Z, 12, Z,
                12, Z, 12, Z, 12, Z,
            );
            let (clo, chi) = (_mm256_shuffle_epi8(c, lo), _mm256_shuffle_epi8(c, hi));
            let z = _mm256_setzero_si256();
            let (dlo, dhi) = (_mm256_unpacklo_epi8(px, z), _mm256_unpackhi_epi8(px, z));
            if self.opaque {
                _mm256_packus_epi16(opaque_over(dlo, clo, self.s), opaque_over(dhi, chi, self.s))
            } else {
                _mm256_packus_epi16(source_over(dlo, clo, self.s), source_over(dhi, chi, self.s))
            }
        }

        /// Rows j and j + 1 of `rows`, both narrow, four pixels each from each row's
        /// first, in one register.
        #[inline]
        #[target_feature(enable = "avx2")]
        fn pair(&self, data: &mut [u8], rows: &Rows, j: usize) {
            // Each slab's terms of both rows, lanes 0..4 row j's, 4..8 row j + 1's.
            let pick = _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1);
            let t: [__m256; E] = std::array::from_fn(|k| {
                let at = k * rows.stride + j;
                let two: &[f32; 2] = rows.t[at..at + 2].try_into().expect("two terms");
                // SAFETY: two floats, an unaligned 64-bit load.
                let two = unsafe { _mm_castpd_ps(_mm_load_sd(two.as_ptr().cast())) };
                let both = _mm256_permutevar8x32_ps(_mm256_castps128_ps256(two), pick);
                _mm256_add_ps(both, self.pair_off[k])
            });
            let c = self.cover(t);
            let (ia, ib) = (rows.at[j] as usize, rows.at[j + 1] as usize);
            debug_assert!(
                ia + 16 <= ib && ib + 16 <= data.len(),
                "two rows' four pixels"
            );
            // SAFETY: both rows are narrow (`lay_out`): their pixels lo..lo + 4 lie
            // inside the image, rows apart, so 16 bytes at each of ia and ib lie inside
            // `data` and do not overlap; unaligned loads and stores.
            unsafe {
                let (pa, pb) = (data.as_mut_ptr().add(ia), data.as_mut_ptr().add(ib));
                let px = _mm256_set_m128i(
                    _mm_loadu_si128(pb.cast_const().cast()),
                    _mm_loadu_si128(pa.cast_const().cast()),
                );
                let out = self.blend(px, c);
                _mm_storeu_si128(pa.cast(), _mm256_castsi256_si128(out));
                _mm_storeu_si128(pb.cast(), _mm256_extracti128_si256(out, 1));
            }
        }

        /// Row j of `rows` (image row y), eight pixels a register, the pixels past
        /// the last whole register inside the image one by one.
        #[inline]
        #[target_feature(enable = "avx2")]
        fn row(&self, data: &mut [u8], width: usize, y: i64, rows: &Rows, j: usize) {
            let (lo, hi) = (rows.lo[j], rows.hi[j]);
            let terms: [__m256; E] = rows.terms::<E>(j).map(|v| _mm256_set1_ps(v));
            let iota = _mm256_setr_ps(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0);
            let mut x = lo;
            while x < hi && x + 8 <= width as i32 {
                let off = _mm256_add_ps(_mm256_set1_ps((x - lo) as f32), iota);
                let t: [__m256; E] = std::array::from_fn(|k| {
                    _mm256_add_ps(terms[k], _mm256_mul_ps(self.nx[k], off))
                });
                let c = self.cover(t);
                let i = 4 * (y as usize * width + x as usize);
                let px: &mut [u8; 32] = (&mut data[i..i + 32]).try_into().expect("eight pixels");
                // SAFETY: 32 bytes, an unaligned load and store.
                unsafe {
                    let out = self.blend(_mm256_loadu_si256(px.as_ptr().cast()), c);
                    _mm256_storeu_si256(px.as_mut_ptr().cast(), out);
                }
                x += 8;
            }
            if x < hi {
                fill_row(data, width, y, self.r, rows, j, x, &self.ink);
            }
        }
    }

    /// Linear interpolation of four pixels' 16-bit channels `d` towards the opaque
    /// ink `s` by the coverage `c`: div255(d·(255 - c) + s·c), [`Ink::blend`]'s.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn opaque_over(d: __m256i, c: __m256i, s: __m256i) -> __m256i {
        let w255 = _mm256_set1_epi16(255);
        let v = _mm256_add_epi16(
            _mm256_mullo_epi16(d, _mm256_sub_epi16(w255, c)),
            _mm256_mullo_epi16(s, c),
        );
        _mm256_srli_epi16(_mm256_add_epi16(v, w255), 8)
    }

    /// The translucent ink `s` scaled by the coverage `c` and composited over four
    /// pixels' 16-bit channels `d`: s' = div255(s·c), d' = s' + div255(d·(255 - s'_a)),
    /// [`Ink::blend`]'s.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn source_over(d: __m256i, c: __m256i, s: __m256i) -> __m256i {
        let w255 = _mm256_set1_epi16(255);
        // Each pixel's alpha word into its four (words 3 and 7 of each 128-bit half).
        let alpha = _mm256_setr_epi8(
            6, 7, 6, 7, 6, 7, 6, 7, 14, 15, 14, 15, 14, 15, 14, 15, 6, 7, 6, 7, 6, 7, 6, 7, 14, 15,
            14, 15, 14, 15, 14, 15,
        );
        let sc = _mm256_srli_epi16(_mm256_add_epi16(_mm256_mullo_epi16(s, c), w255), 8);
        let inv = _mm256_sub_epi16(w255, _mm256_shuffle_epi8(sc, alpha));
        let dd = _mm256_srli_epi16(_mm256_add_epi16(_mm256_mullo_epi16(d, inv), w255), 8);
        _mm256_add_epi16(sc, dd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiny_skia::Color;

    /// A pixmap `w` × `h` of one colour.
    fn canvas(w: u32, h: u32) -> Pixmap {
        let mut p = Pixmap::new(w, h).expect("pixmap");
        p.fill(Color::from_rgba8(250, 248, 240, 255));
        p
    }

    /// A small deterministic generator (Park–Miller), in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0 * 48_271 % 0x7fff_ffff;
            self.0 as f64 / f64::from(0x7fff_ffffu32)
        }
    }

    #[test]
    fn registers_and_pixels_give_the_same_bytes() {
        // Shafts and heads of every direction, size and place, inside the image and
        // across each of its edges, in opaque and translucent inks, over pixels
        // already drawn: AVX2 and pixel by pixel leave the same bytes. (On a
        // processor without AVX2, the paths are one and the test says nothing.)
        let inks = [
            Ink::of(Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff)),
            Ink::of(Color::from_rgba8(0xc0, 0x39, 0x2b, 0x99)),
        ];
        let mut rng = Rng(7);
        for (w, h) in [(97u32, 61u32), (8, 40), (200, 9), (7, 30)] {
            let mut canvases = [canvas(w, h), canvas(w, h)];
            let paths = [Path::Avx2, Path::Pixels];
            for k in 0..900 {
                let ink = inks[k % 2];
                let at = (
                    rng.next() * f64::from(w + 20) - 10.0,
                    rng.next() * f64::from(h + 20) - 10.0,
                );
                let a = rng.next() * std::f64::consts::TAU;
                let len = 0.3 + rng.next() * [4.0, 30.0, 150.0][k % 3];
                let (u, v) = (a.cos(), a.sin());
                let end = (at.0 + len * u, at.1 + len * v);
                let half = 0.3 + rng.next() * 2.0;
                for (canvas, path) in canvases.iter_mut().zip(paths) {
                    if k % 2 == 0 {
                        if let Some(r) = Ramps::shaft(at, end, half) {
                            fill_with(canvas, &r, ink, path);
                        }
                    } else if let Some(r) = Ramps::head(end, (u, v), len.min(14.0)) {
                        fill_with(canvas, &r, ink, path);
                    }
                }
            }
            let [avx2, pixels] = &canvases;
            assert!(avx2.data() == pixels.data(), "{w} × {h}");
        }
    }

    #[test]
    fn a_rectangle_along_the_rows_covers_each_pixel_by_its_area() {
        // A shaft along a row or a column is a rectangle of pixels' exact areas: each
        // ramp is the overlap of a pixel with the slab along one axis, and their
        // product the overlap's area. White ink over black leaves 255 × area, rounded,
        // in every channel. The corners are chosen so that no 255 × area falls within
        // 0.01 of a half (f32's error in the ramps is far below that).
        for (a, b, half) in [
            ((2.27, 4.61), (11.83, 4.61), 1.19),
            ((5.7, 1.13), (5.7, 9.35), 0.9),
            ((11.77, 6.45), (2.21, 6.45), 2.07),
        ] {
            let mut p = Pixmap::new(16, 12).expect("pixmap");
            p.fill(Color::BLACK);
            let r = Ramps::shaft(a, b, half).expect("a shaft");
            fill_ramps(&mut p, &r, Ink::of(Color::WHITE));
            let (x0, x1) = (a.0.min(b.0), a.0.max(b.0));
            let (y0, y1) = (a.1.min(b.1), a.1.max(b.1));
            let (x0, x1, y0, y1) = if a.1 == b.1 {
                (x0, x1, y0 - half, y1 + half)
            } else {
                (x0 - half, x1 + half, y0, y1)
            };
            for y in 0..12 {
                for x in 0..16 {
                    let over = |p: f64, lo: f64, hi: f64| (hi.min(p + 1.0) - lo.max(p)).max(0.0);
                    let area = over(f64::from(x), x0, x1) * over(f64::from(y), y0, y1);
                    let want = (255.0 * area).round();
                    assert!(
                        ((255.0 * area).fract() - 0.5).abs() > 0.01,
                        "({x}, {y}) too near a half"
                    );
                    let got = p.data()[4 * (y * 16 + x) as usize];
                    assert_eq!(f64::from(got), want, "pixel ({x}, {y}) of {a:?}..{b:?}");
                }
            }
        }
    }

    #[test]
    fn a_slanted_side_is_within_its_stated_bound_of_the_exact_area() {
        // A side at an angle θ: the exact area of a pixel inside it is a trapezoid's
        // integral in the distance d of the pixel's centre, the ramp clamp(d + 1/2, 0,
        // 1) its straight-line stand-in; they differ most at 45°, by (√2/2 - 1/2)^2 =
        // 0.0429 of a pixel. Here a long shaft at many angles, its far side inside
        // the image only: each pixel far from the shaft's ends is compared with its
        // exact area inside the near side (computed by cutting the pixel's square,
        // in f64), within 0.0429 and a level's rounding.
        for step in 0..24 {
            let angle = 0.05 + f64::from(step) * std::f64::consts::FRAC_PI_2 / 24.0;
            let (u, v) = (angle.cos(), angle.sin());
            let mut p = Pixmap::new(64, 64).expect("pixmap");
            p.fill(Color::BLACK);
            // Half-width 200 about a line through (32, 32) + 200·n: the near side
            // passes through (32, 32), along (u, v), the inside towards +n.
            let n = (-v, u);
            let c = (32.0 + 200.0 * n.0, 32.0 + 200.0 * n.1);
            let a = (c.0 - 400.0 * u, c.1 - 400.0 * v);
            let b = (c.0 + 400.0 * u, c.1 + 400.0 * v);
            let r = Ramps::shaft(a, b, 200.0).expect("a shaft");
            fill_ramps(&mut p, &r, Ink::of(Color::WHITE));
            for y in 0..64 {
                for x in 0..64 {
                    let exact = area_inside((f64::from(x), f64::from(y)), (32.0, 32.0), n);
                    let got = f64::from(p.data()[4 * (y * 64 + x) as usize]) / 255.0;
                    assert!(
                        (got - exact).abs() <= 0.0429 + 0.5 / 255.0 + 1e-6,
                        "angle {angle}: pixel ({x}, {y}) {got} against {exact}"
                    );
                }
            }
        }
    }

    /// The area of the unit pixel with top-left corner `p` on the side n·(q - o) >= 0
    /// of the line through `o` with unit normal `n`: the pixel's square cut by the
    /// line (Sutherland–Hodgman), then the shoelace formula.
    fn area_inside(p: (f64, f64), o: (f64, f64), n: (f64, f64)) -> f64 {
        let square = [
            (p.0, p.1),
            (p.0 + 1.0, p.1),
            (p.0 + 1.0, p.1 + 1.0),
            (p.0, p.1 + 1.0),
        ];
        let side = |q: (f64, f64)| n.0 * (q.0 - o.0) + n.1 * (q.1 - o.1);
        let mut cut = Vec::new();
        for i in 0..4 {
            let (a, b) = (square[i], square[(i + 1) % 4]);
            let (sa, sb) = (side(a), side(b));
            if sa >= 0.0 {
                cut.push(a);
            }
            if (sa >= 0.0) != (sb >= 0.0) {
                let t = sa / (sa - sb);
                cut.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
        }
        let m = cut.len();
        (0..m)
            .map(|i| {
                let (a, b) = (cut[i], cut[(i + 1) % m]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum::<f64>()
            .abs()
            / 2.0
    }
}
