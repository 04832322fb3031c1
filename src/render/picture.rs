//! Picture sprites: a body of point masses that never turns, drawn once per sub-pixel
//! phase in its colours over a transparent pixmap, then laid over each frame.
//!
//! A body of point masses is six tiny-skia paths (the bars, the discs, their outlines,
//! and the centre-of-mass marker's disc, wedges and ring) in five colours, about 25 µs a
//! frame: 1000 of them ran at a fourteenth of the speed of 1000 discs. A sprite of
//! [`super::sprite`] holds a fill and an outline coverage, not six layers, so these
//! bodies are instead drawn whole, at each of [`PHASES`] × [`PHASES`] sub-pixel
//! offsets, over a transparent pixmap, and the premultiplied picture is laid over the
//! frame by tiny-skia's source-over: d' = s + div255(d·(255 - s_a)).
//!
//! Opaque paths drawn one after another over a pixel with coverages c1, c2, ... leave
//! d·(1 - c1)(1 - c2)... plus each colour weighted by its coverage and what covers it
//! later, exactly what laying the picture of the same paths over transparent black on
//! the pixel leaves; so a picture equals drawing the paths at the snapped position but
//! for the 8-bit rounding of each path's blend (tested: at most a few 255ths), and
//! differs from drawing them at the exact position as moving them by at most 1/16
//! pixel along each axis does, as every sprite. A picture is laid eight pixels at a
//! time where the processor has AVX2, the same bytes.

use std::sync::Arc;

use tiny_skia::Pixmap;

use super::bodies::BodyLook;
use super::sprite::{snap_to, trim, visible, PHASES};

/// A look drawn whole at every phase, premultiplied.
#[derive(Debug)]
pub struct PictureSheet {
    pictures: Vec<Picture>,
}

#[derive(Debug)]
struct Picture {
    /// The offset of the picture's top-left pixel from the whole-pixel part of the
    /// snapped position.
    dx: i32,
    dy: i32,
    width: usize,
    height: usize,
    /// Premultiplied RGBA, row after row.
    rgba: Vec<[u8; 4]>,
}

impl PictureSheet {
    /// Draws `look` at every phase, or returns `None` when it reaches farther than
    /// `max_reach` pixels or turns.
    pub fn new(look: &BodyLook, max_reach: f32) -> Option<Arc<Self>> {
        let reach = look.reach();
        if look.turns() || reach.is_nan() || reach > max_reach {
            return None;
        }
        Self::of_drawing(reach, |pixmap, x, y| look.draw(pixmap, x, y))
    }

    /// Draws with `draw` (which draws something centred at pixel (x, y) within `reach`
    /// pixels of it) at every phase.
    pub fn of_drawing(reach: f32, draw: impl Fn(&mut Pixmap, f32, f32)) -> Option<Arc<Self>> {
        // Room for the outlines' half-widths and anti-aliasing on every side.
        let pad = (reach + 3.0).ceil() as i32;
        let side = (2 * pad + 2) as u32;
        let mut pictures = Vec::with_capacity((PHASES * PHASES) as usize);
        for j in 0..PHASES {
            for i in 0..PHASES {
                let (x, y) = (
                    pad as f32 + i as f32 / PHASES as f32,
                    pad as f32 + j as f32 / PHASES as f32,
                );
                let mut pixmap = Pixmap::new(side, side)?;
                draw(&mut pixmap, x, y);
                pictures.push(Picture::trimmed(&pixmap, -pad, -pad));
            }
        }
        Some(Arc::new(PictureSheet { pictures }))
    }

    /// Returns the picture for pixel (x, y), with the whole pixel its top-left sits on.
    fn picture(&self, x: f32, y: f32) -> (&Picture, i64, i64) {
        let (ix, i) = snap_to(x, PHASES);
        let (iy, j) = snap_to(y, PHASES);
        let p = &self.pictures[(j * PHASES + i) as usize];
        (p, ix + i64::from(p.dx), iy + i64::from(p.dy))
    }

    /// Returns the pixels that [`PictureSheet::stamp`] at (x, y) may change, columns
    /// x0..x1 and rows y0..y1 as (x0, y0, x1, y1), which may reach outside the pixmap.
    pub fn footprint(&self, x: f32, y: f32) -> (i64, i64, i64, i64) {
        let (p, x0, y0) = self.picture(x, y);
        (x0, y0, x0 + p.width as i64, y0 + p.height as i64)
    }

    /// Lays the look's picture over the pixmap with its centre of mass at pixel (x, y),
    /// snapped to the nearest 1/`PHASES` of a pixel. Parts outside are skipped.
    pub fn stamp(&self, pixmap: &mut Pixmap, x: f32, y: f32) {
        let (p, x, y) = self.picture(x, y);
        let Some((cx0, cy0, cx1, cy1)) = visible(pixmap, x, y, p.width, p.height) else {
            return;
        };
        let (pw, w) = (i64::from(pixmap.width()), p.width as i64);
        let data = pixmap.data_mut();
        let run = (cx1 - cx0) as usize;
        let avx2 = is_x86_feature_detected!("avx2");
        for row in cy0..cy1 {
            let src = (row * w + cx0) as usize;
            let dst = 4 * ((y + row) * pw + x + cx0) as usize;
            let (d, s) = (&mut data[dst..dst + 4 * run], &p.rgba[src..src + run]);
            if avx2 {
                // SAFETY: the processor has AVX2.
                unsafe { over_avx2(d, s) };
            } else {
                over(d, s);
            }
        }
    }
}

/// Lays premultiplied pixels `src` over the pixels `dst` (four bytes each, as many),
/// source over: d' = s + div255(d·(255 - s_a)), a transparent pixel skipped and an
/// opaque one copied.
fn over(dst: &mut [u8], src: &[[u8; 4]]) {
    let div255 = |v: u16| (v + 255) >> 8;
    for (d, s) in dst.chunks_exact_mut(4).zip(src) {
        match s[3] {
            0 => {}
            255 => d.copy_from_slice(s),
            a => {
                let inv = 255 - u16::from(a);
                for (d, &s) in d.iter_mut().zip(s) {
                    *d = (u16::from(s) + div255(u16::from(*d) * inv)) as u8;
                }
            }
        }
    }
}

/// [`over`] eight pixels at a time in AVX2 registers, without its cases, which the
/// formula meets on its own: a transparent pixel (all zero, premultiplied) leaves d, for
/// div255(d·255) = d, and an opaque one gives s, for div255(0) = 0. Nor does a sum pass
/// 255: s ≤ s_a and div255(d·(255 - s_a)) ≤ 255 - s_a. So the bytes are the same (a
/// unit test compares the two). Eight transparent pixels are skipped at once.
///
/// # Safety
/// The processor must have AVX2.
#[target_feature(enable = "avx2")]
unsafe fn over_avx2(dst: &mut [u8], src: &[[u8; 4]]) {
    use std::arch::x86_64::*;
    let ff = _mm256_set1_epi16(255);
    let mut dst8 = dst.chunks_exact_mut(32);
    let mut src8 = src.chunks_exact(8);
    for (d, s) in (&mut dst8).zip(&mut src8) {
        // SAFETY: eight pixels are 32 bytes, loaded and stored unaligned.
        let sv = unsafe { _mm256_loadu_si256(s.as_ptr().cast()) };
        if _mm256_testz_si256(sv, sv) != 0 {
            continue;
        }
        let ptr = d.as_mut_ptr() as *mut __m256i;
        let dv = unsafe { _mm256_loadu_si256(ptr) };
        let half = |s: __m128i, d: __m128i| {
            let (s, d) = (_mm256_cvtepu8_epi16(s), _mm256_cvtepu8_epi16(d));
            // Each pixel's alpha in its four channels' lanes.
            let a = _mm256_shufflehi_epi16::<0xff>(_mm256_shufflelo_epi16::<0xff>(s));
            let keep = _mm256_mullo_epi16(d, _mm256_sub_epi16(ff, a));
            _mm256_add_epi16(s, _mm256_srli_epi16::<8>(_mm256_add_epi16(keep, ff)))
        };
        let lo = half(_mm256_castsi256_si128(sv), _mm256_castsi256_si128(dv));
        let hi = half(
            _mm256_extracti128_si256::<1>(sv),
            _mm256_extracti128_si256::<1>(dv),
        );
        // The pack interleaves the halves; put the pixels back in order.
        let packed = _mm256_permute4x64_epi64::<0b11_01_10_00>(_mm256_packus_epi16(lo, hi));
        unsafe { _mm256_storeu_si256(ptr, packed) };
    }
    over(dst8.into_remainder(), src8.remainder());
}

impl Picture {
    /// Keeps the smallest rectangle of the pixmap holding every pixel drawn; (dx, dy)
    /// is where its top-left sits relative to the position it was drawn for.
    fn trimmed(pixmap: &Pixmap, dx: i32, dy: i32) -> Picture {
        let (w, h) = (pixmap.width() as usize, pixmap.height() as usize);
        let at = |x: usize, y: usize| {
            let k = 4 * (y * w + x);
            let d = pixmap.data();
            [d[k], d[k + 1], d[k + 2], d[k + 3]]
        };
        let Some((x0, y0, width, height, rgba)) = trim(w, h, at, |p| p[3] != 0) else {
            return Picture {
                dx,
                dy,
                width: 0,
                height: 0,
                rgba: Vec::new(),
            };
        };
        Picture {
            dx: dx + x0 as i32,
            dy: dy + y0 as i32,
            width,
            height,
            rgba,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pictures_laid_eight_pixels_at_a_time_are_laid_pixel_by_pixel() {
        // Premultiplied pixels of every kind (transparent, opaque, between, and runs of
        // eight transparent ones) over random pixels, rows of every length up to 40:
        // the AVX2 loop gives the bytes of the loop pixel by pixel.
        if !is_x86_feature_detected!("avx2") {
            eprintln!("no AVX2 here: nothing to compare");
            return;
        }
        let mut byte = crate::render::raster::test_bytes(0x2545_F491_4F6C_DD1Du64);
        for len in 0..=40usize {
            for round in 0..50 {
                let src: Vec<[u8; 4]> = (0..len)
                    .map(|i| {
                        let a = match (byte() % 4, round % 3, i / 8 % 2) {
                            (_, 0, 1) | (0, _, _) => 0,
                            (1, _, _) => 255,
                            _ => byte(),
                        };
                        // Premultiplied: no channel above alpha.
                        let c = |v: u8| (u16::from(v) * u16::from(a) / 255) as u8;
                        [c(byte()), c(byte()), c(byte()), a]
                    })
                    .collect();
                let dst: Vec<u8> = (0..4 * len).map(|_| byte()).collect();
                let (mut one, mut eight) = (dst.clone(), dst);
                over(&mut one, &src);
                // SAFETY: the processor has AVX2 (checked above).
                unsafe { over_avx2(&mut eight, &src) };
                assert_eq!(eight, one, "{len} pixels, {src:?}");
            }
        }
    }
}
