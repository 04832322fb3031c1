//! Blends of a coverage given pixel by pixel, eight pixels at a time with AVX2: a
//! coil's coverage (`lines.rs`), and a sprite's fill and edge coverages
//! (`sprite.rs`). Each gives the bytes of [`Ink::blend`] called pixel by pixel for
//! each nonzero coverage: its arithmetic is [`super::mix`]'s, which is `Ink::blend`'s
//! in 16-bit lanes, and a coverage of 0 leaves a pixel as it is (div255(255·d) = d,
//! div255(s·0) = 0), so a group of eight is blended whole whatever its zeros.

use std::arch::x86_64::*;

use super::{blend8_covered, bytes, mix, words};
use crate::render::sprite::Ink;

/// Blends `ink` into the pixels `px` (four bytes each) with a coverage byte each from
/// `cover` (as many as there are pixels): [`Ink::blend`]'s bytes, eight pixels in two
/// registers at a time, eight uncovered pixels skipped at once. A pixel of coverage 0
/// in a group is blended with the rest and keeps its bytes, for div255(255·d) = d and
/// div255(s·0) = 0.
///
/// # Safety
/// The processor must have AVX2 ([`super::available`]).
#[target_feature(enable = "avx2")]
pub(in crate::render::raster) unsafe fn blend_coverage(px: &mut [u8], cover: &[u8], ink: &Ink) {
    debug_assert_eq!(px.len(), 4 * cover.len());
    if ink.is_opaque() {
        blend_coverage_with::<true>(px, cover, ink);
    } else {
        blend_coverage_with::<false>(px, cover, ink);
    }
}

/// [`blend_coverage`] for an opaque ink (`O`) or a translucent one.
#[inline]
#[target_feature(enable = "avx2")]
fn blend_coverage_with<const O: bool>(px: &mut [u8], cover: &[u8], ink: &Ink) {
    let mut pixels = px.chunks_exact_mut(32);
    let mut covers = cover.chunks_exact(8);
    for (p8, c8) in (&mut pixels).zip(&mut covers) {
        let c = u64::from_le_bytes(c8.try_into().expect("eight coverages"));
        if c == 0 {
            continue;
        }
        // The eight coverages as words in both halves.
        let c = _mm256_broadcastsi128_si256(_mm_cvtepu8_epi16(_mm_cvtsi64_si128(c as i64)));
        let p8: &mut [u8; 32] = p8.try_into().expect("eight pixels are 32 bytes");
        blend8_covered::<O>(p8, c, ink);
    }
    let rest = pixels.into_remainder().chunks_exact_mut(4);
    for (p, &c) in rest.zip(covers.remainder()) {
        if c != 0 {
            ink.blend(p, c);
        }
    }
}

/// Blends `ink` into the pixels `px` (four bytes each) with one of each pixel's two
/// coverages in `covers` (as many as there are pixels), the fill's (`layer` 0) or the
/// outline's (1): [`blend_coverage`]'s bytes, which are [`Ink::blend`]'s, eight pixels
/// at a time, eight uncovered pixels skipped at once. A body of point masses draws its
/// discs' fills, then their outlines, a layer at a time.
///
/// # Safety
/// The processor must have AVX2 ([`super::available`]).
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn stamp_layer_row(px: &mut [u8], covers: &[[u8; 2]], layer: usize, ink: &Ink) {
    debug_assert_eq!(px.len(), 4 * covers.len());
    debug_assert!(layer < 2);
    if ink.is_opaque() {
        stamp_layer_row_with::<true>(px, covers, layer, ink);
    } else {
        stamp_layer_row_with::<false>(px, covers, layer, ink);
    }
}

/// [`stamp_layer_row`] for an opaque ink (`O`) or a translucent one.
#[inline]
#[target_feature(enable = "avx2")]
fn stamp_layer_row_with<const O: bool>(px: &mut [u8], covers: &[[u8; 2]], layer: usize, ink: &Ink) {
    // Bytes layer, layer + 2, ..., layer + 14 of eight pairs, then zeros.
    let l = layer as i8;
    let pick = _mm_setr_epi8(
        l,
        l + 2,
        l + 4,
        l + 6,
        l + 8,
        l + 10,
        l + 12,
        l + 14,
        -1,
        -1,
        -1,
        -1,
        -1,
        -1,
        -1,
        -1,
    );
    let mut pixels = px.chunks_exact_mut(32);
    let mut groups = covers.chunks_exact(8);
    for (p8, c8) in (&mut pixels).zip(&mut groups) {
        // SAFETY: eight pairs of coverages are 16 bytes, loaded unaligned.
        let c = _mm_shuffle_epi8(unsafe { _mm_loadu_si128(c8.as_ptr().cast()) }, pick);
        if _mm_testz_si128(c, c) != 0 {
            continue;
        }
        // The eight coverages as words in both halves.
        let c = _mm256_broadcastsi128_si256(_mm_cvtepu8_epi16(c));
        let p8: &mut [u8; 32] = p8.try_into().expect("eight pixels are 32 bytes");
        blend8_covered::<O>(p8, c, ink);
    }
    let rest = pixels.into_remainder().chunks_exact_mut(4);
    for (p, c) in rest.zip(groups.remainder()) {
        if c[layer] != 0 {
            ink.blend(p, c[layer]);
        }
    }
}

/// From the words f0, e0, f1, e1, f2, e2, f3, e3 (four pixels' fill and edge coverages,
/// in both halves): each pixel's fill coverage in its four channels' lanes, then its
/// edge coverage so.
const SELECT_FILL: [u8; 32] = words([0, 0, 0, 0, 2, 2, 2, 2], [4, 4, 4, 4, 6, 6, 6, 6]);
const SELECT_EDGE: [u8; 32] = words([1, 1, 1, 1, 3, 3, 3, 3], [5, 5, 5, 5, 7, 7, 7, 7]);

/// Stamps a row of a sprite: blends `fill`, then `edge`, into the pixels `px` (four
/// bytes each) with each pixel's coverages [fill, edge] from `covers` (as many as
/// there are pixels): the bytes of [`Ink::blend`] called for each nonzero coverage,
/// eight pixels in two registers at a time, eight uncovered pixels skipped at once,
/// then four in one register where four are left. A
/// coverage of 0 in a group blended whole leaves the pixel's bytes (div255(255·d) =
/// d, div255(s·0) = 0), and one of 255 in an opaque ink gives the ink's colour, as
/// `Ink::blend`'s shortcut does.
///
/// # Safety
/// The processor must have AVX2 ([`super::available`]).
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn stamp_row(px: &mut [u8], covers: &[[u8; 2]], fill: &Ink, edge: &Ink) {
    debug_assert_eq!(px.len(), 4 * covers.len());
    match (fill.is_opaque(), edge.is_opaque()) {
        (true, true) => stamp_row_with::<true, true>(px, covers, fill, edge),
        (true, false) => stamp_row_with::<true, false>(px, covers, fill, edge),
        (false, true) => stamp_row_with::<false, true>(px, covers, fill, edge),
        (false, false) => stamp_row_with::<false, false>(px, covers, fill, edge),
    }
}

/// [`stamp_row`] for a fill opaque or not (`F`) and an edge opaque or not (`E`).
#[inline]
#[target_feature(enable = "avx2")]
fn stamp_row_with<const F: bool, const E: bool>(
    px: &mut [u8],
    covers: &[[u8; 2]],
    fill: &Ink,
    edge: &Ink,
) {
    let mut pixels = px.chunks_exact_mut(32);
    let mut groups = covers.chunks_exact(8);
    for (p8, c8) in (&mut pixels).zip(&mut groups) {
        // SAFETY: eight pairs of coverages are 16 bytes, loaded unaligned.
        let c = unsafe { _mm_loadu_si128(c8.as_ptr().cast()) };
        if _mm_testz_si128(c, c) != 0 {
            continue;
        }
        // Pixels 0 to 3's coverages as words in both halves, then pixels 4 to 7's.
        let w = _mm256_cvtepu8_epi16(c);
        let quads = [
            _mm256_permute2x128_si256::<0x00>(w, w),
            _mm256_permute2x128_si256::<0x11>(w, w),
        ];
        let ptr = p8.as_mut_ptr() as *mut __m256i;
        // SAFETY: the chunk is 32 bytes, loaded and stored unaligned.
        let p = unsafe { _mm256_loadu_si256(ptr) };
        let d = [
            _mm256_cvtepu8_epi16(_mm256_castsi256_si128(p)),
            _mm256_cvtepu8_epi16(_mm256_extracti128_si256::<1>(p)),
        ];
        let out = [0, 1].map(|k| {
            let filled = mix::<F>(
                d[k],
                _mm256_shuffle_epi8(quads[k], bytes(&SELECT_FILL)),
                fill,
            );
            mix::<E>(
                filled,
                _mm256_shuffle_epi8(quads[k], bytes(&SELECT_EDGE)),
                edge,
            )
        });
        // The pack interleaves the halves; put the pixels back in order.
        let packed = _mm256_permute4x64_epi64::<0b11_01_10_00>(_mm256_packus_epi16(out[0], out[1]));
        unsafe { _mm256_storeu_si256(ptr, packed) };
    }
    // Four of the pixels left in one register, when there are four.
    let (mut rest, mut left) = (pixels.into_remainder(), groups.remainder());
    if left.len() >= 4 {
        let (p4, more) = rest.split_at_mut(16);
        // SAFETY: four pairs of coverages are 8 bytes, four pixels 16, both loaded (and
        // the pixels stored) unaligned.
        let c = unsafe { _mm_loadl_epi64(left.as_ptr().cast()) };
        if _mm_testz_si128(c, c) == 0 {
            let quad = _mm256_broadcastsi128_si256(_mm_cvtepu8_epi16(c));
            let ptr = p4.as_mut_ptr() as *mut __m128i;
            let d = _mm256_cvtepu8_epi16(unsafe { _mm_loadu_si128(ptr) });
            let filled = mix::<F>(d, _mm256_shuffle_epi8(quad, bytes(&SELECT_FILL)), fill);
            let out = mix::<E>(filled, _mm256_shuffle_epi8(quad, bytes(&SELECT_EDGE)), edge);
            let packed = _mm_packus_epi16(
                _mm256_castsi256_si128(out),
                _mm256_extracti128_si256::<1>(out),
            );
            unsafe { _mm_storeu_si128(ptr, packed) };
        }
        (rest, left) = (more, &left[4..]);
    }
    for (d, &[f, e]) in rest.chunks_exact_mut(4).zip(left) {
        if f != 0 {
            fill.blend(d, f);
        }
        if e != 0 {
            edge.blend(d, e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiny_skia::Color;

    /// A coverage: 0 and 255 often, whole groups of eight left at 0 in a third of the
    /// rows, and anything between.
    fn coverage(byte: &mut impl FnMut() -> u8, round: usize, i: usize) -> u8 {
        match (byte() % 4, round % 3, i / 8 % 2) {
            (_, 0, 1) | (0, _, _) => 0,
            (1, _, _) => 255,
            _ => byte(),
        }
    }

    /// Calls `check(covers, pixels)` for rows of every length up to 40, twenty of each:
    /// pairs of coverages from [`coverage`] over random pixels.
    fn each_row(byte: &mut impl FnMut() -> u8, mut check: impl FnMut(&[[u8; 2]], Vec<u8>)) {
        for len in 0..=40usize {
            for round in 0..20 {
                let covers: Vec<[u8; 2]> = (0..len)
                    .map(|i| [coverage(byte, round, i), coverage(byte, round, i)])
                    .collect();
                let pixels: Vec<u8> = (0..4 * len).map(|_| byte()).collect();
                check(&covers, pixels);
            }
        }
    }

    #[test]
    fn a_sprites_row_stamped_eight_pixels_at_a_time_is_stamped_pixel_by_pixel() {
        // Fill then edge, each opaque or translucent, over random pixels, rows of every
        // length up to 40: the bytes of `Ink::blend` for each nonzero coverage.
        if !super::super::available() {
            eprintln!("no AVX2 here: nothing to compare");
            return;
        }
        let mut byte = crate::render::raster::test_bytes(0x9E37_79B9_7F4A_7C15);
        let opaque = Ink::of(Color::from_rgba8(0x1f, 0x77, 0xb4, 0xff));
        let dark = Ink::of(Color::from_rgba8(0x10, 0x3c, 0x5a, 0xff));
        let faint = Ink::of(Color::from_rgba8(0xd6, 0x27, 0x28, 0x80));
        let ghost = Ink::of(Color::from_rgba8(0x2c, 0xa0, 0x2c, 0x03));
        for (fill, edge) in [
            (opaque, dark),
            (opaque, faint),
            (faint, dark),
            (faint, ghost),
        ] {
            each_row(&mut byte, |covers, pixels| {
                let mut one = pixels.clone();
                for (d, &[f, e]) in one.chunks_exact_mut(4).zip(covers) {
                    if f != 0 {
                        fill.blend(d, f);
                    }
                    if e != 0 {
                        edge.blend(d, e);
                    }
                }
                let mut eight = pixels;
                // SAFETY: the processor has AVX2 (checked above).
                unsafe { stamp_row(&mut eight, covers, &fill, &edge) };
                assert_eq!(eight, one, "{fill:?} then {edge:?}, {covers:?}");
            });
        }
    }

    #[test]
    fn a_layer_stamped_eight_pixels_at_a_time_is_blended_pixel_by_pixel() {
        // `stamp_layer_row` with either layer, for opaque, translucent and faint inks
        // and rows of every length up to 40 (eight at a time, the rest one by one):
        // the bytes of `Ink::blend` for each nonzero coverage of that layer, the other
        // layer's coverage left alone.
        if !super::super::available() {
            eprintln!("no AVX2 here: nothing to compare");
            return;
        }
        let mut byte = crate::render::raster::test_bytes(0xD1B5_4A32_D192_ED03);
        let inks = [
            Ink::of(Color::from_rgba8(0x1f, 0x77, 0xb4, 0xff)),
            Ink::of(Color::from_rgba8(0xd6, 0x27, 0x28, 0x80)),
            Ink::of(Color::from_rgba8(0x2c, 0xa0, 0x2c, 0x03)),
        ];
        for ink in inks {
            for layer in 0..2 {
                each_row(&mut byte, |covers, pixels| {
                    let mut one = pixels.clone();
                    for (d, c) in one.chunks_exact_mut(4).zip(covers) {
                        if c[layer] != 0 {
                            ink.blend(d, c[layer]);
                        }
                    }
                    let mut eight = pixels;
                    // SAFETY: the processor has AVX2 (checked above).
                    unsafe { stamp_layer_row(&mut eight, covers, layer, &ink) };
                    assert_eq!(eight, one, "{ink:?}, layer {layer}, {covers:?}");
                });
            }
        }
    }
}
