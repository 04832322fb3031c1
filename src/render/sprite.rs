//! Sprites: a small body's look rasterised once per sub-pixel phase, then stamped.
//!
//! A frame of ten thousand circles spends nearly all its time in the rasteriser's set-up
//! for each tiny path. A body whose look many bodies share is instead rasterised once
//! per render at each of `PHASES`×`PHASES` sub-pixel offsets, and every frame blends
//! the right one into place.
//!
//! A sprite keeps, for each pixel, the anti-aliasing coverage of the fill and of the
//! outline as tiny-skia computes them, and the stamp blends the two colours with the
//! arithmetic of tiny-skia's 8-bit pipeline, in the same order: so stamping a look at a
//! position snapped to 1/`PHASES` pixel gives the bytes that drawing its paths there
//! gives. The look's outline is put on a fine grid first ([`GRID`]) so that its
//! coverage does not depend on which whole pixel it is drawn at. Against paths drawn at
//! the unsnapped position, the difference is that of moving the shape by at most
//! 1/(2·`PHASES`) pixel; `tests/integration/perf.rs` measures both.

use std::sync::Arc;

use tiny_skia::{Color, Pixmap};

use super::bodies::BodyLook;
use super::damage::TileMask;

/// Sub-pixel phases per axis: positions are snapped to 1/8 of a pixel.
pub const PHASES: u32 = 8;

/// The largest look, as a radius in pixels, that is stamped rather than drawn: larger
/// ones are few on screen and cost memory as sprites (64 phases of a 2·r square).
pub const MAX_SPRITE_REACH: f32 = 24.0;

/// The grid, in pixels, that a stamped look's outline points are rounded to (see
/// [`BodyLook::on_grid`]), so that the sprite and the path agree sample for sample.
pub const GRID: f32 = 1.0 / 256.0;

/// A look rasterised once at every sub-pixel phase, stamped in its colours.
///
/// The coverage depends only on the look's geometry, so looks that differ only in
/// colour share it ([`SpriteSheet::coverage`], [`SpriteSheet::with_coverage`]).
#[derive(Clone, Debug)]
pub struct SpriteSheet {
    coverage: Arc<SpriteCoverage>,
    fill: Ink,
    edge: Ink,
}

/// The coverage of a look's fill and outline at every sub-pixel phase, whatever its
/// colours.
#[derive(Debug)]
pub struct SpriteCoverage {
    sprites: Vec<Sprite>,
}

/// A paint's colour as tiny-skia's 8-bit pipeline holds it: premultiplied bytes, and
/// whether it is opaque (tiny-skia then blends by linear interpolation with the
/// coverage, otherwise by scaling the colour by the coverage and compositing over).
#[derive(Clone, Copy, Debug)]
pub struct Ink {
    rgba: [u16; 4],
    opaque: bool,
}

/// One phase of a look: coverage of the fill and of the outline for each pixel of the
/// smallest rectangle that either touches.
#[derive(Clone, Debug)]
pub(crate) struct Sprite {
    /// The offset of the sprite's top-left pixel from the whole-pixel part of the
    /// snapped position.
    pub(crate) dx: i32,
    pub(crate) dy: i32,
    pub(crate) width: usize,
    pub(crate) height: usize,
    /// (fill coverage, outline coverage) for each pixel, row after row.
    coverage: Vec<[u8; 2]>,
    /// For each row, the columns a..b from its first covered pixel to its last: what
    /// a stamp changes there (a disc's rows are narrower than its rectangle at the
    /// top and the bottom).
    spans: Vec<(usize, usize)>,
}

impl SpriteSheet {
    /// Rasterises an outline look at every phase, or returns `None` when it is too
    /// large to stamp or is not an outline.
    pub fn new(look: &BodyLook) -> Option<Self> {
        Some(Self::with_coverage(Self::coverage(look)?, look))
    }

    /// Returns a sheet that stamps `coverage`, rasterised from a look of the same
    /// geometry as `look`, in `look`'s colours.
    pub fn with_coverage(coverage: Arc<SpriteCoverage>, look: &BodyLook) -> Self {
        let (fill, edge) = look.colors();
        SpriteSheet {
            coverage,
            fill: Ink::of(fill),
            edge: Ink::of(edge),
        }
    }

    /// Rasterises the coverage of an outline look's fill and outline at every phase,
    /// or returns `None` when the look is too large to stamp or is not an outline.
    pub fn coverage(look: &BodyLook) -> Option<Arc<SpriteCoverage>> {
        if !look.is_outline() {
            return None;
        }
        let look = look.on_grid(GRID);
        let reach = look.reach();
        if reach.is_nan() || reach > MAX_SPRITE_REACH {
            return None;
        }
        // Room for the outline's half-width and anti-aliasing on every side.
        let pad = (reach + 3.0).ceil() as i32;
        let side = (2 * pad + 2) as u32;
        let mut sprites = Vec::with_capacity((PHASES * PHASES) as usize);
        for j in 0..PHASES {
            for i in 0..PHASES {
                let (x, y) = (
                    pad as f32 + i as f32 / PHASES as f32,
                    pad as f32 + j as f32 / PHASES as f32,
                );
                // Opaque white over transparent black leaves the coverage in alpha.
                let mut fill = Pixmap::new(side, side)?;
                look.draw_outline(&mut fill, x, y, Some(Color::WHITE), None);
                let mut edge = Pixmap::new(side, side)?;
                look.draw_outline(&mut edge, x, y, None, Some(Color::WHITE));
                sprites.push(Sprite::trimmed(&fill, &edge, -pad, -pad));
            }
        }
        Some(Arc::new(SpriteCoverage { sprites }))
    }

    /// Returns the pixels that [`SpriteSheet::stamp`] at (x, y) may change, columns
    /// x0..x1 and rows y0..y1 as (x0, y0, x1, y1), which may reach outside the pixmap:
    /// the sprite's trimmed rectangle at its snapped position.
    pub fn footprint(&self, x: f32, y: f32) -> (i64, i64, i64, i64) {
        let (ix, i) = snap(x);
        let (iy, j) = snap(y);
        let sprite = &self.coverage.sprites[(j * PHASES + i) as usize];
        let (x0, y0) = (ix + i64::from(sprite.dx), iy + i64::from(sprite.dy));
        (x0, y0, x0 + sprite.width as i64, y0 + sprite.height as i64)
    }

    /// Marks in `mask` the tiles of the pixels that [`SpriteSheet::stamp`] at (x, y)
    /// may change, row by row (see `Sprite::mark_tiles`).
    pub fn mark_tiles(&self, mask: &mut TileMask, x: f32, y: f32) {
        let (ix, i) = snap(x);
        let (iy, j) = snap(y);
        let sprite = &self.coverage.sprites[(j * PHASES + i) as usize];
        sprite.mark_tiles(mask, ix + i64::from(sprite.dx), iy + i64::from(sprite.dy));
    }

    /// Stamps the look with its centre at pixel (x, y), snapped to the nearest
    /// 1/`PHASES` of a pixel. Parts outside the pixmap are skipped.
    pub fn stamp(&self, pixmap: &mut Pixmap, x: f32, y: f32) {
        let (ix, i) = snap(x);
        let (iy, j) = snap(y);
        let sprite = &self.coverage.sprites[(j * PHASES + i) as usize];
        sprite.stamp(
            pixmap,
            ix + i64::from(sprite.dx),
            iy + i64::from(sprite.dy),
            self.fill,
            self.edge,
        );
    }
}

impl Ink {
    /// Returns a colour as tiny-skia's 8-bit pipeline paints it.
    pub fn of(color: Color) -> Ink {
        let c = color.premultiply().to_color_u8();
        Ink {
            rgba: [c.red(), c.green(), c.blue(), c.alpha()].map(u16::from),
            opaque: c.alpha() == 255,
        }
    }

    /// Returns the ink's premultiplied channels, red, green, blue and alpha.
    pub fn rgba(&self) -> [u16; 4] {
        self.rgba
    }

    /// Returns true when the ink is opaque, so that [`Ink::blend`] interpolates.
    pub fn is_opaque(&self) -> bool {
        self.opaque
    }

    /// Blends this ink with coverage `c` over the pixel `d`, as tiny-skia's 8-bit
    /// pipeline does, with div255(v) = (v + 255) >> 8:
    /// opaque ink: d' = div255(d·(255 - c) + s·c) (linear interpolation);
    /// otherwise: s' = div255(s·c), then d' = s' + div255(d·(255 - s'_a)) (source over).
    /// Both leave d unchanged when c = 0.
    #[inline(always)]
    pub fn blend(&self, d: &mut [u8], c: u8) {
        let c = u16::from(c);
        let div255 = |v: u16| (v + 255) >> 8;
        if self.opaque && c == 255 {
            // div255(s·255) = s: the colour itself, without reading the pixel.
            for (d, s) in d.iter_mut().zip(self.rgba) {
                *d = s as u8;
            }
        } else if self.opaque {
            for (d, s) in d.iter_mut().zip(self.rgba) {
                *d = div255(u16::from(*d) * (255 - c) + s * c) as u8;
            }
        } else {
            let s = self.rgba.map(|v| div255(v * c));
            let inv = 255 - s[3];
            for (d, s) in d.iter_mut().zip(s) {
                *d = (s + div255(u16::from(*d) * inv)) as u8;
            }
        }
    }
}

/// Splits a pixel coordinate snapped to 1/`PHASES` into its whole pixel and phase:
/// q = round(x·PHASES), whole = ⌊q / PHASES⌋, phase = q mod PHASES.
#[inline]
fn snap(x: f32) -> (i64, u32) {
    snap_to(x, PHASES)
}

/// Splits a pixel coordinate snapped to 1/`phases` into its whole pixel and phase.
#[inline]
pub(crate) fn snap_to(x: f32, phases: u32) -> (i64, u32) {
    let q = (f64::from(x) * f64::from(phases)).round() as i64;
    let p = i64::from(phases);
    (q.div_euclid(p), q.rem_euclid(p) as u32)
}

/// What a sprite or a picture keeps of a `width` × `height` pixmap: the smallest
/// rectangle holding every pixel whose value `at(x, y)` is `drawn`, as its top-left
/// pixel (x0, y0), its width and height, and its values row after row; `None` when no
/// pixel is drawn.
pub(crate) fn trim<T>(
    width: usize,
    height: usize,
    at: impl Fn(usize, usize) -> T,
    drawn: impl Fn(&T) -> bool,
) -> Option<(usize, usize, usize, usize, Vec<T>)> {
    let (mut x0, mut y0, mut x1, mut y1) = (width, height, 0, 0);
    for y in 0..height {
        for x in 0..width {
            if drawn(&at(x, y)) {
                x0 = x0.min(x);
                y0 = y0.min(y);
                x1 = x1.max(x + 1);
                y1 = y1.max(y + 1);
            }
        }
    }
    if x0 >= x1 {
        return None;
    }
    let mut kept = Vec::with_capacity((x1 - x0) * (y1 - y0));
    for y in y0..y1 {
        kept.extend((x0..x1).map(|x| at(x, y)));
    }
    Some((x0, y0, x1 - x0, y1 - y0, kept))
}

impl Sprite {
    /// Keeps the smallest rectangle holding every pixel that the fill or the outline
    /// covers at all; (dx, dy) is where the pixmaps' top-left sits relative to the
    /// position they were drawn for.
    pub(crate) fn trimmed(fill: &Pixmap, edge: &Pixmap, dx: i32, dy: i32) -> Sprite {
        let (w, h) = (fill.width() as usize, fill.height() as usize);
        let (fill, edge) = (fill.data(), edge.data());
        // Each row's first and last pixel that either layer covers at all (alpha not
        // zero), found in one pass over the row's pixels, and the box around them.
        let mut rows = Vec::with_capacity(h);
        let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
        for y in 0..h {
            let (f, e) = (
                &fill[4 * y * w..4 * (y + 1) * w],
                &edge[4 * y * w..4 * (y + 1) * w],
            );
            let covered = |x: &usize| f[4 * x + 3] | e[4 * x + 3] != 0;
            let span = (0..w).find(covered).map(|a| {
                let b = (a..w).rfind(covered).map_or(a, |l| l + 1);
                (a, b)
            });
            if let Some((a, b)) = span {
                (x0, x1) = (x0.min(a), x1.max(b));
                (y0, y1) = (y0.min(y), y + 1);
            }
            rows.push(span);
        }
        if x0 >= x1 {
            return Sprite {
                dx,
                dy,
                width: 0,
                height: 0,
                coverage: Vec::new(),
                spans: Vec::new(),
            };
        }
        let (width, height) = (x1 - x0, y1 - y0);
        let mut coverage = Vec::with_capacity(width * height);
        for y in y0..y1 {
            coverage.extend((x0..x1).map(|x| {
                let k = 4 * (y * w + x) + 3;
                [fill[k], edge[k]]
            }));
        }
        // A row's span relative to the box; (0, 0) for a row that nothing covers.
        let spans = rows[y0..y1]
            .iter()
            .map(|span| span.map_or((0, 0), |(a, b)| (a - x0, b - x0)))
            .collect();
        Sprite {
            dx: dx + x0 as i32,
            dy: dy + y0 as i32,
            width,
            height,
            coverage,
            spans,
        }
    }

    /// Marks in `mask` the tiles of every pixel that [`Sprite::stamp`] with the
    /// sprite's top-left pixel at (x, y) may change, row by row: each row's span of
    /// covered pixels, not the sprite's whole rectangle.
    pub(crate) fn mark_tiles(&self, mask: &mut TileMask, x: i64, y: i64) {
        let (w, h) = mask.size();
        let (w, h) = (i64::from(w), i64::from(h));
        for (row, &(a, b)) in self.spans.iter().enumerate() {
            let py = y + row as i64;
            let (x0, x1) = ((x + a as i64).max(0), (x + b as i64).min(w));
            if py >= 0 && py < h && x0 < x1 {
                mask.mark_span(x0 as usize, x1 as usize, py as usize);
            }
        }
    }

    /// Asks for the cache lines of the sprite's coverage and row spans.
    pub(crate) fn prefetch(&self) {
        // Coverage is two bytes a pixel: one request per 64-byte line.
        for k in (0..self.coverage.len()).step_by(32) {
            super::raster::prefetch(&self.coverage, k);
        }
        super::raster::prefetch(&self.spans, 0);
    }

    /// Blends one layer only, the fill (0) or the outline (1), in `ink`, with the
    /// sprite's top-left pixel at (x, y).
    pub(crate) fn stamp_layer(&self, pixmap: &mut Pixmap, x: i64, y: i64, layer: usize, ink: Ink) {
        // Rows of eight pixels or more eight at a time (the same bytes).
        let avx2 = crate::render::raster::avx2_available();
        self.rows(pixmap, x, y, |pixels, covers| {
            if avx2 && covers.len() >= 8 {
                // SAFETY: the processor has AVX2.
                unsafe { crate::render::raster::stamp_layer_row(pixels, covers, layer, &ink) };
                return;
            }
            for (d, c) in pixels.chunks_exact_mut(4).zip(covers) {
                if c[layer] != 0 {
                    ink.blend(d, c[layer]);
                }
            }
        });
    }

    /// Blends the fill, then the outline, with the sprite's top-left pixel at (x, y).
    pub(crate) fn stamp(&self, pixmap: &mut Pixmap, x: i64, y: i64, fill: Ink, edge: Ink) {
        // Rows of four pixels or more eight and four at a time (the same bytes);
        // shorter ones without the call.
        let avx2 = crate::render::raster::avx2_available();
        self.rows(pixmap, x, y, |pixels, covers| {
            if avx2 && covers.len() >= 4 {
                // SAFETY: the processor has AVX2.
                unsafe { crate::render::raster::stamp_row(pixels, covers, &fill, &edge) };
                return;
            }
            for (d, [c_fill, c_edge]) in pixels.chunks_exact_mut(4).zip(covers) {
                if *c_fill != 0 {
                    fill.blend(d, *c_fill);
                }
                if *c_edge != 0 {
                    edge.blend(d, *c_edge);
                }
            }
        });
    }

    /// Calls `blend` with each row of the pixmap's pixels under the sprite placed with
    /// its top-left pixel at (x, y), and the sprite's coverage there; parts outside
    /// the pixmap are skipped.
    #[inline(always)]
    fn rows(
        &self,
        pixmap: &mut Pixmap,
        x: i64,
        y: i64,
        mut blend: impl FnMut(&mut [u8], &[[u8; 2]]),
    ) {
        let Some((cx0, cy0, cx1, cy1)) = visible(pixmap, x, y, self.width, self.height) else {
            return;
        };
        let (pw, w) = (i64::from(pixmap.width()), self.width as i64);
        let data = pixmap.data_mut();
        let run = (cx1 - cx0) as usize;
        for row in cy0..cy1 {
            let src = (row * w + cx0) as usize;
            let dst = 4 * ((y + row) * pw + x + cx0) as usize;
            blend(
                &mut data[dst..dst + 4 * run],
                &self.coverage[src..src + run],
            );
        }
    }
}

/// Returns the part of a `width` × `height` rectangle placed with its top-left pixel
/// at (x, y) that lies inside the pixmap, as the rectangle's columns cx0..cx1 and rows
/// cy0..cy1, or `None` when none does.
pub(crate) fn visible(
    pixmap: &Pixmap,
    x: i64,
    y: i64,
    width: usize,
    height: usize,
) -> Option<(i64, i64, i64, i64)> {
    let (pw, ph) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
    let (w, h) = (width as i64, height as i64);
    let (cx0, cy0) = ((-x).max(0), (-y).max(0));
    let (cx1, cy1) = (w.min(pw - x), h.min(ph - y));
    (cx0 < cx1 && cy0 < cy1).then_some((cx0, cy0, cx1, cy1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapping_splits_whole_pixels_and_phases() {
        assert_eq!(snap(10.0), (10, 0));
        assert_eq!(snap(10.5), (10, 4));
        assert_eq!(snap(10.93), (10, 7));
        assert_eq!(snap(10.95), (11, 0));
        assert_eq!(snap(-0.125), (-1, 7));
        assert_eq!(snap(-3.0), (-3, 0));
    }

    #[test]
    fn a_stamps_tiles_are_marked_row_by_row() {
        // A disc with an outline: the tiles marked are those of the pixels whose
        // coverage is not zero, row by row, wherever the sprite is placed (partly
        // outside the frame too), and the stamp changes no pixel outside them.
        use crate::render::damage::TILE_PIXELS;
        use tiny_skia::{FillRule, Paint, PathBuilder, Stroke, Transform};
        let (mut fill, mut edge) = (
            Pixmap::new(21, 21).expect("size"),
            Pixmap::new(21, 21).expect("size"),
        );
        let disc = PathBuilder::from_circle(10.3, 10.6, 7.0).expect("a circle");
        let paint = Paint::default();
        fill.fill_path(
            &disc,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
        let stroke = Stroke {
            width: 1.5,
            ..Stroke::default()
        };
        edge.stroke_path(&disc, &paint, &stroke, Transform::identity(), None);
        let sprite = Sprite::trimmed(&fill, &edge, -10, -10);
        let (w, h) = (37u32, 19u32);
        for (x, y) in [(3, 4), (0, 0), (-5, 7), (30, 2), (33, -4), (12, 15), (9, 1)] {
            let mut mask = TileMask::new(w, h);
            mask.clear();
            sprite.mark_tiles(&mut mask, x, y);
            let mut expected = TileMask::new(w, h);
            expected.clear();
            for row in 0..sprite.height {
                for col in 0..sprite.width {
                    let (px, py) = (x + col as i64, y + row as i64);
                    let inside = (0..i64::from(w)).contains(&px) && (0..i64::from(h)).contains(&py);
                    if inside && sprite.coverage[row * sprite.width + col] != [0, 0] {
                        expected.mark(px as usize, py as usize);
                    }
                }
            }
            let mut pixmap = Pixmap::new(w, h).expect("size");
            pixmap.fill(Color::WHITE);
            let before = pixmap.clone();
            let red = Color::from_rgba8(200, 30, 30, 255);
            sprite.stamp(&mut pixmap, x, y, Ink::of(Color::BLACK), Ink::of(red));
            for py in 0..h as usize {
                assert_eq!(mask.row(py), expected.row(py), "at ({x}, {y}), row {py}");
                for px in 0..w as usize {
                    let k = 4 * (py * w as usize + px);
                    if pixmap.data()[k..k + 4] != before.data()[k..k + 4] {
                        let t = px / TILE_PIXELS as usize;
                        assert!((mask.row(py)[t / 64] >> (t % 64)) & 1 == 1, "({px}, {py})");
                    }
                }
            }
        }
    }
}
