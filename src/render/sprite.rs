//! Sprites: a small body's look rendered once per sub-pixel phase, then stamped.
//!
//! A frame of ten thousand circles spends nearly all its time in the rasteriser's set-up
//! for each tiny path. A body whose look many bodies share is instead drawn once per
//! render at each of `PHASES`×`PHASES` sub-pixel offsets, and every frame copies the
//! right one into place with source-over compositing.
//!
//! tiny-skia's anti-aliasing samples coverage on a 4 × 4 grid in each pixel, so a
//! sprite of phase (i, j) (offset (i, j)/`PHASES` pixels) matches what drawing the path
//! at that offset gives, up to the rounding of 8-bit compositing: the stamp composites
//! the sprite's premultiplied pixels with the same formula tiny-skia uses,
//! d' = s + (d·(255 - s_a) + 255)/256, but drawing the fill and then the outline
//! rounds after each, stamping after both. A body's position is snapped to the nearest
//! 1/`PHASES` of a pixel before it is stamped. `tests/integration/perf.rs` measures the
//! difference against drawing every path.

use tiny_skia::Pixmap;

use super::bodies::BodyLook;

/// Sub-pixel phases per axis: positions are snapped to 1/8 of a pixel.
pub const PHASES: u32 = 8;

/// The largest look, as a radius in pixels, that is stamped rather than drawn: larger
/// ones are few on screen and cost memory as sprites (64 phases of a 2·r square).
pub const MAX_SPRITE_REACH: f32 = 24.0;

/// The grid, in pixels, that a stamped look's outline points are rounded to (see
/// [`BodyLook::on_grid`]), so that the sprite and the path agree sample for sample.
pub const GRID: f32 = 1.0 / 256.0;

/// A look drawn once at every sub-pixel phase.
#[derive(Clone, Debug)]
pub struct SpriteSheet {
    sprites: Vec<Sprite>,
}

/// One phase of a look: premultiplied RGBA rows, trimmed to the pixels it touches.
#[derive(Clone, Debug)]
struct Sprite {
    /// The offset of the sprite's top-left pixel from the whole-pixel part of the
    /// snapped position.
    dx: i32,
    dy: i32,
    width: usize,
    height: usize,
    /// Premultiplied RGBA, `width`·`height`·4 bytes, row after row.
    rgba: Vec<u8>,
}

impl SpriteSheet {
    /// Renders a look at every phase, or returns `None` when it is too large to stamp.
    /// The look is first put on the [`GRID`].
    pub fn new(look: &BodyLook) -> Option<Self> {
        let look = look.on_grid(GRID);
        let reach = look.reach();
        if !(reach <= MAX_SPRITE_REACH) {
            return None;
        }
        // Room for the outline's half-width and anti-aliasing on every side.
        let pad = (reach + 3.0).ceil() as i32;
        let side = (2 * pad + 2) as u32;
        let mut sprites = Vec::with_capacity((PHASES * PHASES) as usize);
        for j in 0..PHASES {
            for i in 0..PHASES {
                let mut pixmap = Pixmap::new(side, side)?;
                let fx = i as f32 / PHASES as f32;
                let fy = j as f32 / PHASES as f32;
                look.draw(&mut pixmap, pad as f32 + fx, pad as f32 + fy);
                sprites.push(Sprite::trimmed(&pixmap, -pad, -pad));
            }
        }
        Some(SpriteSheet { sprites })
    }

    /// Stamps the look with its centre at pixel (x, y), snapped to the nearest
    /// 1/`PHASES` of a pixel. Parts outside the pixmap are skipped.
    pub fn stamp(&self, pixmap: &mut Pixmap, x: f32, y: f32) {
        let (ix, i) = snap(x);
        let (iy, j) = snap(y);
        let sprite = &self.sprites[(j * PHASES + i) as usize];
        sprite.stamp(pixmap, ix + sprite.dx as i64, iy + sprite.dy as i64);
    }
}

/// Splits a pixel coordinate snapped to 1/`PHASES` into its whole pixel and phase:
/// q = round(x·PHASES), whole = ⌊q / PHASES⌋, phase = q mod PHASES.
#[inline]
fn snap(x: f32) -> (i64, u32) {
    let q = (f64::from(x) * f64::from(PHASES)).round() as i64;
    let p = i64::from(PHASES);
    (q.div_euclid(p), q.rem_euclid(p) as u32)
}

impl Sprite {
    /// Keeps the smallest rectangle of `pixmap` holding every pixel that is not fully
    /// transparent; (dx, dy) is where the pixmap's top-left sits relative to the
    /// position it was drawn for.
    fn trimmed(pixmap: &Pixmap, dx: i32, dy: i32) -> Sprite {
        let (w, h) = (pixmap.width() as usize, pixmap.height() as usize);
        let data = pixmap.data();
        let alpha = |x: usize, y: usize| data[4 * (y * w + x) + 3];
        let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
        for y in 0..h {
            for x in 0..w {
                if alpha(x, y) != 0 {
                    x0 = x0.min(x);
                    y0 = y0.min(y);
                    x1 = x1.max(x + 1);
                    y1 = y1.max(y + 1);
                }
            }
        }
        if x0 >= x1 {
            return Sprite {
                dx,
                dy,
                width: 0,
                height: 0,
                rgba: Vec::new(),
            };
        }
        let mut rgba = Vec::with_capacity((x1 - x0) * (y1 - y0) * 4);
        for y in y0..y1 {
            rgba.extend_from_slice(&data[4 * (y * w + x0)..4 * (y * w + x1)]);
        }
        Sprite {
            dx: dx + x0 as i32,
            dy: dy + y0 as i32,
            width: x1 - x0,
            height: y1 - y0,
            rgba,
        }
    }

    /// Composites the sprite with its top-left pixel at (x, y), source over.
    fn stamp(&self, pixmap: &mut Pixmap, x: i64, y: i64) {
        let (pw, ph) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
        let (w, h) = (self.width as i64, self.height as i64);
        // The part of the sprite inside the pixmap: columns cx0..cx1, rows cy0..cy1.
        let (cx0, cy0) = ((-x).max(0), (-y).max(0));
        let (cx1, cy1) = (w.min(pw - x), h.min(ph - y));
        if cx0 >= cx1 || cy0 >= cy1 {
            return;
        }
        let data = pixmap.data_mut();
        let run = 4 * (cx1 - cx0) as usize;
        for row in cy0..cy1 {
            let src_start = 4 * (row * w + cx0) as usize;
            let dst_start = 4 * ((y + row) * pw + x + cx0) as usize;
            let src = &self.rgba[src_start..src_start + run];
            let dst = &mut data[dst_start..dst_start + run];
            for (d, s) in dst.chunks_exact_mut(4).zip(src.chunks_exact(4)) {
                // Source over, premultiplied, as tiny-skia's 8-bit pipeline computes it:
                // d' = s + (d·(255 - s_a) + 255) >> 8, exact when s_a is 0 or 255.
                let inv = 255 - u16::from(s[3]);
                for c in 0..4 {
                    d[c] = s[c] + ((u16::from(d[c]) * inv + 255) >> 8) as u8;
                }
            }
        }
    }
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
}
