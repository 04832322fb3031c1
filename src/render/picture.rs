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
//! pixel along each axis does, as every sprite.

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
        let div255 = |v: u16| (v + 255) >> 8;
        for row in cy0..cy1 {
            let src = (row * w + cx0) as usize;
            let dst = 4 * ((y + row) * pw + x + cx0) as usize;
            for (d, s) in data[dst..dst + 4 * run]
                .chunks_exact_mut(4)
                .zip(&p.rgba[src..src + run])
            {
                match s[3] {
                    0 => {}
                    255 => d.copy_from_slice(s),
                    a => {
                        // Source over, premultiplied: d' = s + div255(d·(255 - s_a)).
                        let inv = 255 - u16::from(a);
                        for (d, &s) in d.iter_mut().zip(s) {
                            *d = (u16::from(s) + div255(u16::from(*d) * inv)) as u8;
                        }
                    }
                }
            }
        }
    }
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
