//! Ramps eight pixels a register with AVX2: the rows laid out eight at a time, then two
//! narrow rows (a steep shaft's) or eight pixels of a row to a register, with the
//! bytes of the pixel-by-pixel path in `mod.rs` (tested).

use std::arch::x86_64::*;

use super::{fill_row, Ramps, Rows};
use crate::render::raster::prefetch;
use crate::render::sprite::Ink;

/// How many rows ahead [`fill`] asks for pixels.
const AHEAD: usize = 4;

/// The rows laid out in `rows` (from image row `first`) eight pixels a register,
/// with [`super::fill_row`]'s bytes. Two rows of at most four pixels each (a steep
/// shaft's) share a register; other rows take eight pixels a register from their
/// first. Pixels a register would take past the image's right edge are blended
/// one by one.
///
/// # Safety
/// The processor must have AVX2, the image must be at least eight pixels wide, and
/// `rows` must have been laid out by `lay_out` for rows first..first + n of this image
/// (its byte offsets and narrow rows are trusted, unchecked).
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
            0, Z, 0, Z, 0, Z, 0, Z, 4, Z, 4, Z, 4, Z, 4, Z, 0, Z, 0, Z, 0, Z, 0, Z, 4, Z, 4, Z, 4,
            Z, 4, Z,
        );
        let hi = _mm256_setr_epi8(
            8, Z, 8, Z, 8, Z, 8, Z, 12, Z, 12, Z, 12, Z, 12, Z, 8, Z, 8, Z, 8, Z, 8, Z, 12, Z, 12,
            Z, 12, Z, 12, Z,
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
            let t: [__m256; E] =
                std::array::from_fn(|k| _mm256_add_ps(terms[k], _mm256_mul_ps(self.nx[k], off)));
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
        6, 7, 6, 7, 6, 7, 6, 7, 14, 15, 14, 15, 14, 15, 14, 15, 6, 7, 6, 7, 6, 7, 6, 7, 14, 15, 14,
        15, 14, 15, 14, 15,
    );
    let sc = _mm256_srli_epi16(_mm256_add_epi16(_mm256_mullo_epi16(s, c), w255), 8);
    let inv = _mm256_sub_epi16(w255, _mm256_shuffle_epi8(sc, alpha));
    let dd = _mm256_srli_epi16(_mm256_add_epi16(_mm256_mullo_epi16(d, inv), w255), 8);
    _mm256_add_epi16(sc, dd)
}
