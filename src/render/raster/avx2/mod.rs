//! Convex rows covered and blended with AVX2: the bytes of [`super::convex`]'s
//! eight-pixel blend (`eight.rs`), with a pixel row's work in a few wide registers.
//!
//! A thin shape (a turning box's outline; once, arrows, which are now covered by
//! ramps in `ramps/`) is mostly rows of three to six pixels, so what a row costs around its one
//! eight-pixel blend (asking each chain for four crossings, rounding them to columns,
//! finding the pixels they touch) cost more than the blend. Here, where both chains go
//! on with one edge each through a whole pixel row, which is most rows of a shaft, the
//! row's eight crossings are one register, x + k·dx for sub-rows k = 1..4 past the
//! last one asked for (exact in 32-bit lanes, below), and are rounded, ordered and
//! reduced to the row's pixels together. The coverage of eight pixels by four sub-rows
//! is two registers of sixteen 16-bit lanes (sub-rows 0 and 1, then 2 and 3, eight
//! pixels each), and the blend of eight pixels two more (each pixel's four channels);
//! a row of four pixels or fewer, most rows of a steep arrow, takes one of each. Where
//! a chain turns a corner, starts or ends inside a row, its crossings are asked for one
//! by one, as in `convex.rs`, and the row goes on as the others. Every operation is on
//! integers, so the bytes do not depend on the register width: a unit test draws
//! thousands of shapes both ways and compares them byte for byte.
//!
//! The arithmetic is that of `eight.rs`: a span a..b of quarter-pixel columns adds to
//! pixel x, whose columns are 4x..4x + 4, the overlap o = clamp(b - 4x, 0, 4) - clamp(a -
//! 4x, 0, 4) times 16, less 1 where the row's last sub-row covers it whole (o = 4), so
//! that a covered pixel sums to 255; a sum c is capped as Skia caps it, c - (c >> 8),
//! at most 255; and the blend is [`Ink::blend`]'s (div255(v) = (v + 255) >> 8).
//!
//! `coverage.rs` blends coverages given pixel by pixel (a coil's, a sprite's fill and
//! edge) eight pixels at a time with [`mix`], the same bytes as [`Ink::blend`].

use std::arch::x86_64::*;

use super::convex::{blend_tail, weighed, Chains, RowSpans};
use super::eight::prefetch;
use crate::render::sprite::Ink;

mod coverage;
pub(in crate::render::raster) use coverage::blend_coverage;
pub(crate) use coverage::{stamp_layer_row, stamp_row};

/// The widest image drawn here. Crossings are 16.16 fixed point of quarter-pixel
/// columns, below 4 · 4096 · 65536 = 2^30 inside an image this wide (the chains are
/// cut to the image), so that 32-bit lanes hold them, and the sums of a crossing and
/// a step, with room to spare. Wider images take the 64-bit path in `convex.rs`.
pub(super) const MAX_WIDTH: usize = 4096;

/// Returns true when the processor has AVX2 (checked once, then cached by the
/// standard library).
pub(crate) fn available() -> bool {
    is_x86_feature_detected!("avx2")
}

/// Byte indices that take 16-bit words `lo` into the low half of a register and `hi`
/// into the high half, each word named by its index in a 128-bit source repeated in
/// both halves (for `_mm256_shuffle_epi8`).
pub(super) const fn words(lo: [u8; 8], hi: [u8; 8]) -> [u8; 32] {
    let mut out = [0u8; 32];
    let mut i = 0;
    while i < 8 {
        out[2 * i] = 2 * lo[i];
        out[2 * i + 1] = 2 * lo[i] + 1;
        out[16 + 2 * i] = 2 * hi[i];
        out[16 + 2 * i + 1] = 2 * hi[i] + 1;
        i += 1;
    }
    out
}

/// From the words a0..a3, b0..b3: a0 in eight lanes then a1 in eight, a2 then a3, b0
/// then b1, b2 then b3 (each sub-row's span against the row's eight pixels).
const SELECT_A01: [u8; 32] = words([0; 8], [1; 8]);
const SELECT_A23: [u8; 32] = words([2; 8], [3; 8]);
const SELECT_B01: [u8; 32] = words([4; 8], [5; 8]);
const SELECT_B23: [u8; 32] = words([6; 8], [7; 8]);
/// From the words c0..c7: each pixel's coverage in its four channels' lanes, pixels
/// 0 to 3, then 4 to 7.
const SELECT_C0: [u8; 32] = words([0, 0, 0, 0, 1, 1, 1, 1], [2, 2, 2, 2, 3, 3, 3, 3]);
const SELECT_C1: [u8; 32] = words([4, 4, 4, 4, 5, 5, 5, 5], [6, 6, 6, 6, 7, 7, 7, 7]);
/// For four pixels: a0..a3 and b0..b3 each in four lanes (pixel j of sub-row k in
/// lane 4k + j).
const SELECT_A4: [u8; 32] = words([0, 0, 0, 0, 1, 1, 1, 1], [2, 2, 2, 2, 3, 3, 3, 3]);
const SELECT_B4: [u8; 32] = words([4, 4, 4, 4, 5, 5, 5, 5], [6, 6, 6, 6, 7, 7, 7, 7]);
/// The first quarter-pixel column of each lane's pixel, relative to the first pixel's.
const LANES: [i16; 16] = [0, 4, 8, 12, 16, 20, 24, 28, 0, 4, 8, 12, 16, 20, 24, 28];
/// 1 in the lanes of the row's last sub-row (whose whole pixel weighs 63, not 64).
const SHORT: [i16; 16] = [0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1];
/// The same for four pixels of four sub-rows.
const LANES4: [i16; 16] = [0, 4, 8, 12, 0, 4, 8, 12, 0, 4, 8, 12, 0, 4, 8, 12];
const SHORT4: [i16; 16] = [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1];

/// Loads 32 bytes of byte indices.
#[inline(always)]
pub(super) fn bytes(v: &[u8; 32]) -> __m256i {
    // SAFETY: `v` is 32 bytes; the load is unaligned.
    unsafe { _mm256_loadu_si256(v.as_ptr().cast()) }
}

/// Loads sixteen 16-bit lanes.
#[inline(always)]
fn words16(v: &[i16; 16]) -> __m256i {
    // SAFETY: `v` is 32 bytes; the load is unaligned.
    unsafe { _mm256_loadu_si256(v.as_ptr().cast()) }
}

/// Blends `ink` into the pixels `data` of an image `width` × `height` (`width` at most
/// [`MAX_WIDTH`]) with the coverage of the chains' convex polygon, which has no hole:
/// the bytes of `convex::blend_plain_sse2`.
///
/// # Safety
/// The processor must have AVX2 ([`available`]).
#[target_feature(enable = "avx2")]
pub(super) unsafe fn blend_plain(
    data: &mut [u8],
    width: usize,
    height: usize,
    chains: &mut Chains,
    ink: Ink,
) {
    // An opaque ink and a translucent one each get their own loop, without a test of
    // the ink in every row and every pixel.
    if ink.is_opaque() {
        plain_rows::<true>(data, width, height, chains, &ink);
    } else {
        plain_rows::<false>(data, width, height, chains, &ink);
    }
}

/// [`blend_plain`]'s rows, for an ink that is opaque when `O` (compiled inside it).
#[inline(always)]
unsafe fn plain_rows<const O: bool>(
    data: &mut [u8],
    width: usize,
    height: usize,
    chains: &mut Chains,
    ink: &Ink,
) {
    let (first, end) = chains.rows_within(height);
    let max_column = _mm_set1_epi32(4 * width as i32);
    let mut sy = first;
    while sy < end {
        if let Some((stop, [(x0, dx0), (x1, dx1)])) = chains.straight(sy, end) {
            // Both chains cross sub-rows sy..=stop with one edge each, at x + k·dx for
            // the k-th sub-row past the one last asked for (x): sub-rows 1..4 of both
            // chains in one register, then four more each row. A lane's value is exact
            // while it is a crossing inside the image (below 2^30); past `stop` it may
            // wrap, and is not used.
            let at = |x: i64, dx: i64, k: i64| (x + k * dx) as i32;
            let mut xs = _mm256_setr_epi32(
                at(x0, dx0, 1),
                at(x0, dx0, 2),
                at(x0, dx0, 3),
                at(x0, dx0, 4),
                at(x1, dx1, 1),
                at(x1, dx1, 2),
                at(x1, dx1, 3),
                at(x1, dx1, 4),
            );
            let (s0, s1) = ((4 * dx0) as i32, (4 * dx1) as i32);
            let step = _mm256_setr_epi32(s0, s0, s0, s0, s1, s1, s1, s1);
            let start = sy;
            while sy + 3 <= stop {
                let (a, b, lo, hi) = columns(xs, max_column, width);
                blend_row::<O>(data, width, (sy >> 2) as usize, a, b, lo, hi, ink);
                xs = _mm256_add_epi32(xs, step);
                sy += 4;
            }
            chains.advance(sy - start);
            continue;
        }
        // A row where a chain turns a corner, starts or ends: its crossings one by one.
        let py = (sy >> 2) as usize;
        let RowSpans { a, b, lo, hi, next } = chains.row_spans(sy, end, width);
        sy = next;
        let lanes =
            |v: [i64; 4]| _mm_setr_epi32(v[0] as i32, v[1] as i32, v[2] as i32, v[3] as i32);
        blend_row::<O>(data, width, py, lanes(a), lanes(b), lo, hi, ink);
    }
}

/// Blends `ink` with the coverage of a convex polygon less a convex hole (a ring): the
/// bytes of `convex::scan_convex`. Where every sub-row of a pixel row has two spans,
/// one each side of the hole, and the pixels the left ones touch all lie left of those
/// the right ones touch (every row of a ring but its top and bottom, and where the
/// hole is less than a pixel wide), the row is two rows of one span a sub-row, covered
/// and blended eight pixels at a time as a polygon without a hole is: each pixel takes
/// coverage from one side only. The other rows go pixel by pixel (`convex::put_row`).
/// (A ring's rows went pixel by pixel, a fifth of the frame's time for boxes each at
/// an angle of its own, `sizes-1000`; and each side's blend was a call until this loop
/// was compiled with AVX2, which lets it be inlined.)
///
/// # Safety
/// The processor must have AVX2 ([`available`]), and the image must be at most
/// [`MAX_WIDTH`] wide.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn blend_holed(
    data: &mut [u8],
    width: usize,
    height: usize,
    chains: &mut Chains,
    ink: Ink,
) {
    let (first, end) = chains.rows_within(height);
    let mut sy = first;
    while sy < end {
        let Some(row) = super::convex::holed_row(chains, &mut sy, end, width) else {
            continue;
        };
        if row.n == 8 {
            let side = |first: usize| {
                let a: [i64; 4] = std::array::from_fn(|k| row.spans[2 * k + first].0);
                let b: [i64; 4] = std::array::from_fn(|k| row.spans[2 * k + first].1);
                let lo = a.iter().map(|a| a >> 2).min().unwrap_or(0);
                let hi = b.iter().map(|b| (b + 3) >> 2).max().unwrap_or(0);
                (a, b, lo, hi.min(width as i64))
            };
            let (left, right) = (side(0), side(1));
            if left.3 <= right.2 {
                for (a, b, lo, hi) in [left, right] {
                    // SAFETY: the processor has AVX2 and the image is at most
                    // MAX_WIDTH wide (the caller's promise), and a..b are columns of
                    // it.
                    unsafe { blend_spans(data, width, row.py, (a, b), (lo, hi), &ink) };
                }
                continue;
            }
        }
        super::convex::put_row(&row, width, &mut |i, c| {
            ink.blend(&mut data[4 * i..4 * i + 4], c);
        });
    }
}

/// Blends `ink` into pixels lo..hi of pixel row `py` (clipped to `width`, at most
/// [`MAX_WIDTH`]) with the coverage of one span a[k]..b[k] of quarter-pixel columns in
/// each sub-row k: a side of a ring's row (`convex.rs`), blended as a row of a polygon
/// without a hole is.
///
/// # Safety
/// The processor must have AVX2 ([`available`]); it is inlined into
/// [`blend_holed`], which has it.
#[inline(always)]
pub(super) unsafe fn blend_spans(
    data: &mut [u8],
    width: usize,
    py: usize,
    (a, b): ([i64; 4], [i64; 4]),
    (lo, hi): (i64, i64),
    ink: &Ink,
) {
    let lanes = |v: [i64; 4]| _mm_setr_epi32(v[0] as i32, v[1] as i32, v[2] as i32, v[3] as i32);
    if ink.is_opaque() {
        blend_row::<true>(data, width, py, lanes(a), lanes(b), lo, hi, ink);
    } else {
        blend_row::<false>(data, width, py, lanes(a), lanes(b), lo, hi, ink);
    }
}

/// From the crossings of a pixel row's four sub-rows by both chains (lanes 0..4 and
/// 4..8 of `xs`), the row's spans a..b of quarter-pixel columns (a = b = 0 for a
/// sub-row without one) and the pixels lo..hi they touch, clipped to `width`.
#[inline]
#[target_feature(enable = "avx2")]
fn columns(xs: __m256i, max_column: __m128i, width: usize) -> (__m128i, __m128i, i64, i64) {
    let swapped = _mm256_permute2x128_si256::<1>(xs, xs);
    let left = _mm256_castsi256_si128(_mm256_min_epi32(xs, swapped));
    let right = _mm256_castsi256_si128(_mm256_max_epi32(xs, swapped));
    // column(v) = ((v + 0x8000) >> 16), clamped to the image's columns 0..=4·width.
    let column = |v: __m128i| {
        let c = _mm_srai_epi32::<16>(_mm_add_epi32(v, _mm_set1_epi32(0x8000)));
        _mm_min_epi32(_mm_max_epi32(c, _mm_setzero_si128()), max_column)
    };
    let (a, b) = (column(left), column(right));
    let some = _mm_cmpgt_epi32(b, a);
    let (a, b) = (_mm_and_si128(a, some), _mm_and_si128(b, some));
    // lo = min(a >> 2) and hi = max((b + 3) >> 2) over the sub-rows with a span.
    let lo = _mm_srai_epi32::<2>(_mm_blendv_epi8(_mm_set1_epi32(i32::MAX), a, some));
    let hi = _mm_and_si128(
        _mm_srai_epi32::<2>(_mm_add_epi32(b, _mm_set1_epi32(3))),
        some,
    );
    let lo = _mm_min_epi32(lo, _mm_shuffle_epi32::<0b01_00_11_10>(lo));
    let lo = _mm_min_epi32(lo, _mm_shuffle_epi32::<0b10_11_00_01>(lo));
    let hi = _mm_max_epi32(hi, _mm_shuffle_epi32::<0b01_00_11_10>(hi));
    let hi = _mm_max_epi32(hi, _mm_shuffle_epi32::<0b10_11_00_01>(hi));
    let (lo, hi) = (_mm_cvtsi128_si32(lo), _mm_cvtsi128_si32(hi));
    (a, b, i64::from(lo), i64::from(hi).min(width as i64))
}

/// Blends `ink` (opaque when `O`) into pixels lo..hi of pixel row `py` with the
/// coverage of the spans a..b (quarter-pixel columns, one sub-row per lane): eight
/// pixels at a time, one by one where eight would pass the image's right edge.
///
/// It carries no `target_feature` of its own, so that it can be inlined (a function
/// with one cannot be `inline(always)`); it is used only inside the AVX2 functions
/// here, which give it theirs. Called row by row, it cost an arrow a tenth of its
/// time in the call and the values spilled around it (`arrow_probe`: 1000 arrows
/// 1.25 ms called, 1.09 inlined).
///
/// # Safety
/// The processor must have AVX2.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn blend_row<const O: bool>(
    data: &mut [u8],
    width: usize,
    py: usize,
    a: __m128i,
    b: __m128i,
    lo: i64,
    hi: i64,
    ink: &Ink,
) {
    if lo >= hi {
        return;
    }
    let base = py * width;
    // The pixels two rows down, where the shape most likely goes on (as `convex.rs`).
    let ahead = 4 * (base + 2 * width);
    prefetch(data, ahead + 4 * lo as usize);
    prefetch(data, ahead + 4 * hi as usize);
    // In an opaque ink, the pixels every sub-row covers whole (coverage 64·3 + 63 =
    // 255) take the ink's colour, as `Ink::blend` gives it, without a blend: pixels
    // ⌈a/4⌉..⌊b/4⌋ of every sub-row's span (none when a sub-row has no span, whose
    // lanes are 0..0).
    // Only a row of at least eight pixels can have eight of them (a thin shape's rows,
    // most of an arrow's, skip the search).
    let (core_lo, core_hi) = if O && hi - lo >= 8 {
        core(a, b)
    } else {
        (hi, hi)
    };
    let mut x = lo;
    while x + 8 <= width as i64 && x < hi {
        let k = 4 * (base + x as usize);
        if x >= core_lo && core_hi - x >= 8 {
            fill_colour(&mut data[k..4 * (base + core_hi as usize)], ink);
            x = core_hi;
            continue;
        }
        if hi - x <= 4 {
            let px: &mut [u8; 16] = (&mut data[k..k + 16])
                .try_into()
                .expect("four pixels are 16 bytes");
            blend4::<O>(px, x, a, b, ink);
            x = hi;
            break;
        }
        let px: &mut [u8; 32] = (&mut data[k..k + 32])
            .try_into()
            .expect("eight pixels are 32 bytes");
        blend8::<O>(px, x, a, b, ink);
        x += 8;
    }
    if x < hi {
        let (mut sa, mut sb) = ([0i32; 4], [0i32; 4]);
        // SAFETY: each store is of 16 bytes into a 16-byte array.
        unsafe {
            _mm_storeu_si128(sa.as_mut_ptr().cast(), a);
            _mm_storeu_si128(sb.as_mut_ptr().cast(), b);
        }
        let spans = weighed(sa.map(i64::from), sb.map(i64::from));
        blend_tail(data, base, x, hi, &spans, ink);
    }
}

/// The pixels ⌈a/4⌉..⌊b/4⌋ that all four sub-rows' spans a..b (quarter-pixel columns,
/// one per lane) cover whole; an empty range when they cover none.
#[inline]
#[target_feature(enable = "avx2")]
fn core(a: __m128i, b: __m128i) -> (i64, i64) {
    let lo = _mm_srai_epi32::<2>(_mm_add_epi32(a, _mm_set1_epi32(3)));
    let hi = _mm_srai_epi32::<2>(b);
    let lo = _mm_max_epi32(lo, _mm_shuffle_epi32::<0b01_00_11_10>(lo));
    let lo = _mm_max_epi32(lo, _mm_shuffle_epi32::<0b10_11_00_01>(lo));
    let hi = _mm_min_epi32(hi, _mm_shuffle_epi32::<0b01_00_11_10>(hi));
    let hi = _mm_min_epi32(hi, _mm_shuffle_epi32::<0b10_11_00_01>(hi));
    (
        i64::from(_mm_cvtsi128_si32(lo)),
        i64::from(_mm_cvtsi128_si32(hi)),
    )
}

/// Writes an opaque ink's colour into every pixel of `px`, eight at a time.
#[inline]
#[target_feature(enable = "avx2")]
fn fill_colour(px: &mut [u8], ink: &Ink) {
    let [r, g, b, a] = ink.rgba().map(|v| v as u8);
    let colour = u32::from_le_bytes([r, g, b, a]);
    let eight = _mm256_set1_epi32(colour as i32);
    let mut chunks = px.chunks_exact_mut(32);
    for chunk in &mut chunks {
        // SAFETY: each chunk is 32 bytes, stored unaligned.
        unsafe { _mm256_storeu_si256(chunk.as_mut_ptr().cast(), eight) };
    }
    for p in chunks.into_remainder().chunks_exact_mut(4) {
        p.copy_from_slice(&colour.to_le_bytes());
    }
}

/// The spans a..b as 16-bit columns relative to pixel x0's first (4·x0), clamped
/// where every lane's clamp below gives the same (as `eight.rs`'s `relative`): the
/// words a0..a3, b0..b3, in both halves of the register.
#[inline]
#[target_feature(enable = "avx2")]
fn relative(a: __m128i, b: __m128i, x0: i64) -> __m256i {
    let origin = _mm_set1_epi32((4 * x0) as i32);
    let ab = _mm_packs_epi32(_mm_sub_epi32(a, origin), _mm_sub_epi32(b, origin));
    let ab = _mm_min_epi16(_mm_max_epi16(ab, _mm_set1_epi16(-8)), _mm_set1_epi16(40));
    _mm256_broadcastsi128_si256(ab)
}

/// The overlaps o = clamp(b - 4x, 0, 4) - clamp(a - 4x, 0, 4) of the spans in `a`
/// and `b` (one lane per pixel and sub-row) with the pixels whose first columns,
/// relative to the first pixel's, are `lanes`; then 16·o, less 1 in the `short` lanes
/// (the row's last sub-row) where a pixel is covered whole.
#[inline]
#[target_feature(enable = "avx2")]
fn weights(a: __m256i, b: __m256i, lanes: __m256i, short: __m256i) -> __m256i {
    let (zero, four) = (_mm256_setzero_si256(), _mm256_set1_epi16(4));
    let clamp = |v: __m256i| _mm256_min_epi16(_mm256_max_epi16(v, zero), four);
    let o = _mm256_sub_epi16(
        clamp(_mm256_sub_epi16(b, lanes)),
        clamp(_mm256_sub_epi16(a, lanes)),
    );
    let whole = _mm256_and_si256(_mm256_cmpeq_epi16(o, four), short);
    _mm256_sub_epi16(_mm256_slli_epi16::<4>(o), whole)
}

/// Caps summed coverage as Skia's runs do: a sum of 256 becomes 255, (c - (c >> 8)),
/// at most 255.
#[inline]
#[target_feature(enable = "avx2")]
fn cap(c: __m128i) -> __m128i {
    _mm_min_epi16(
        _mm_sub_epi16(c, _mm_srli_epi16::<8>(c)),
        _mm_set1_epi16(255),
    )
}

/// Blends `ink` into four pixels `d` (their channels as 16-bit lanes) with coverage
/// `cover` (each pixel's in its four channels' lanes): [`Ink::blend`]'s arithmetic.
#[inline]
#[target_feature(enable = "avx2")]
pub(super) fn mix<const O: bool>(d: __m256i, cover: __m256i, ink: &Ink) -> __m256i {
    let [r, g, b, a] = ink.rgba().map(|v| v as i16);
    let s = _mm256_setr_epi16(r, g, b, a, r, g, b, a, r, g, b, a, r, g, b, a);
    let ff = _mm256_set1_epi16(255);
    let div = |v: __m256i| _mm256_srli_epi16::<8>(_mm256_add_epi16(v, ff));
    if O {
        // div255(d·(255 - c) + s·c).
        let keep = _mm256_mullo_epi16(d, _mm256_sub_epi16(ff, cover));
        div(_mm256_add_epi16(keep, _mm256_mullo_epi16(s, cover)))
    } else {
        // s' = div255(s·c), then s' + div255(d·(255 - s'_a)).
        let src = div(_mm256_mullo_epi16(s, cover));
        let alpha = _mm256_shufflehi_epi16::<0xff>(_mm256_shufflelo_epi16::<0xff>(src));
        _mm256_add_epi16(src, div(_mm256_mullo_epi16(d, _mm256_sub_epi16(ff, alpha))))
    }
}

/// Blends `ink` into the eight pixels `px` that start at pixel x0 with the coverage
/// of the spans a..b, one sub-row per lane.
#[inline]
#[target_feature(enable = "avx2")]
fn blend8<const O: bool>(px: &mut [u8; 32], x0: i64, a: __m128i, b: __m128i, ink: &Ink) {
    let ab = relative(a, b, x0);
    let pick = |select: &[u8; 32]| _mm256_shuffle_epi8(ab, bytes(select));
    // Sub-rows 0 and 1 (no short lanes), then 2 and 3.
    let (lanes, short) = (words16(&LANES), words16(&SHORT));
    let w01 = weights(
        pick(&SELECT_A01),
        pick(&SELECT_B01),
        lanes,
        _mm256_setzero_si256(),
    );
    let w23 = weights(pick(&SELECT_A23), pick(&SELECT_B23), lanes, short);
    let sum = _mm256_add_epi16(w01, w23);
    let c = cap(_mm_add_epi16(
        _mm256_castsi256_si128(sum),
        _mm256_extracti128_si256::<1>(sum),
    ));
    blend8_covered::<O>(px, _mm256_broadcastsi128_si256(c), ink);
}

/// Blends `ink` into the eight pixels `px` with coverages `c` (eight 16-bit words, in
/// both halves of the register): [`mix`] on each half's four pixels.
#[inline]
#[target_feature(enable = "avx2")]
pub(super) fn blend8_covered<const O: bool>(px: &mut [u8; 32], c: __m256i, ink: &Ink) {
    let ptr = px.as_mut_ptr() as *mut __m256i;
    // SAFETY: `px` is 32 bytes, loaded unaligned.
    let p = unsafe { _mm256_loadu_si256(ptr) };
    let out = [
        mix::<O>(
            _mm256_cvtepu8_epi16(_mm256_castsi256_si128(p)),
            _mm256_shuffle_epi8(c, bytes(&SELECT_C0)),
            ink,
        ),
        mix::<O>(
            _mm256_cvtepu8_epi16(_mm256_extracti128_si256::<1>(p)),
            _mm256_shuffle_epi8(c, bytes(&SELECT_C1)),
            ink,
        ),
    ];
    // The pack interleaves the halves (pixels 0-1, 4-5, 2-3, 6-7); put them in order.
    let packed = _mm256_permute4x64_epi64::<0b11_01_10_00>(_mm256_packus_epi16(out[0], out[1]));
    // SAFETY: `px` is 32 bytes, stored unaligned.
    unsafe { _mm256_storeu_si256(ptr, packed) };
}

/// Blends `ink` into the four pixels `px` that start at pixel x0 with the coverage of
/// the spans a..b: [`blend8`]'s bytes for a row of at most four pixels, which is most
/// rows of a steep arrow, in half the work.
#[inline]
#[target_feature(enable = "avx2")]
fn blend4<const O: bool>(px: &mut [u8; 16], x0: i64, a: __m128i, b: __m128i, ink: &Ink) {
    let ab = relative(a, b, x0);
    // Pixel j of sub-row k in lane 4k + j.
    let w = weights(
        _mm256_shuffle_epi8(ab, bytes(&SELECT_A4)),
        _mm256_shuffle_epi8(ab, bytes(&SELECT_B4)),
        words16(&LANES4),
        words16(&SHORT4),
    );
    // Sub-rows 0 + 2 and 1 + 3, then all four, in lanes 0..4.
    let half = _mm_add_epi16(_mm256_castsi256_si128(w), _mm256_extracti128_si256::<1>(w));
    let c = cap(_mm_add_epi16(half, _mm_unpackhi_epi64(half, half)));
    let cover = _mm256_shuffle_epi8(_mm256_broadcastsi128_si256(c), bytes(&SELECT_C0));
    let ptr = px.as_mut_ptr() as *mut __m128i;
    // SAFETY: `px` is 16 bytes, loaded and stored unaligned.
    let d = _mm256_cvtepu8_epi16(unsafe { _mm_loadu_si128(ptr) });
    let out = mix::<O>(d, cover, ink);
    let packed = _mm_packus_epi16(
        _mm256_castsi256_si128(out),
        _mm256_extracti128_si256::<1>(out),
    );
    unsafe { _mm_storeu_si128(ptr, packed) };
}

#[cfg(test)]
mod tests {
    use super::super::convex::{blend_plain_sse2, Chains};
    use super::super::Point;
    use super::*;
    use tiny_skia::Color;

    /// A generator of numbers in 0..1 (a 64-bit linear congruential one's top bits).
    fn uniform(mut state: u64) -> impl FnMut() -> f32 {
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn wide_rows_blend_the_bytes_of_eight_pixels_at_a_time() {
        if !available() {
            eprintln!("no AVX2 here: nothing to compare");
            return;
        }
        let mut next = uniform(7);
        // An odd width, so that rows end in pixels blended one by one, a wide one, and
        // the widest drawn here, whose crossings near its right edge reach 2^30.
        for (width, height, shapes) in [
            (157usize, 93usize, 3000),
            (1280, 64, 600),
            (MAX_WIDTH, 24, 300),
        ] {
            let mut background = vec![0u8; 4 * width * height];
            for v in &mut background {
                *v = (next() * 256.0) as u8;
            }
            let (mut wide, mut eight) = (background.clone(), background.clone());
            let mut chains = Chains::default();
            for k in 0..shapes {
                // Thin bars at any angle (an arrow's shaft), triangles (its head) and
                // pentagons, from a pixel to past the image, some across its edges.
                let (cx, cy) = (
                    next() * (width as f32 + 40.0) - 20.0,
                    next() * (height as f32 + 40.0) - 20.0,
                );
                let size = 0.5 + next() * if k % 5 == 0 { 150.0 } else { 30.0 };
                let turn = next() * std::f32::consts::TAU;
                let (s, c) = turn.sin_cos();
                let points: Vec<Point> = match k % 3 {
                    0 => {
                        let (h, w) = (size, 0.5 + next() * 2.0);
                        [(-h, -w), (h, -w), (h, w), (-h, w)]
                            .iter()
                            .map(|&(u, v)| (cx + u * c - v * s, cy + u * s + v * c))
                            .collect()
                    }
                    n => (0..2 + 3 * n)
                        .map(|i| {
                            let t = turn + i as f32 * std::f32::consts::TAU / (2 + 3 * n) as f32;
                            (cx + size * t.cos(), cy + size * t.sin())
                        })
                        .collect(),
                };
                let alpha = if k % 2 == 0 {
                    255
                } else {
                    (next() * 255.0) as u8
                };
                let ink = Ink::of(Color::from_rgba8(
                    (next() * 255.0) as u8,
                    (next() * 255.0) as u8,
                    (next() * 255.0) as u8,
                    alpha,
                ));
                chains.set(&points, &[], (width, height));
                // SAFETY: the processor has AVX2, checked above.
                unsafe { blend_plain(&mut wide, width, height, &mut chains, ink) };
                chains.set(&points, &[], (width, height));
                blend_plain_sse2(&mut eight, width, height, &mut chains, ink);
                assert!(wide == eight, "shape {k} of {width} × {height}: {points:?}");
            }
            // The shapes drew something: most of the image's bytes changed.
            let changed = wide.iter().zip(&background).filter(|(a, b)| a != b).count();
            assert!(
                2 * changed > wide.len(),
                "{changed} bytes of {} changed",
                wide.len()
            );
        }
    }
}
