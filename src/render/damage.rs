//! Damage: where a frame may differ from the static layer it was drawn over.
//!
//! A frame of bodies moving over a static layer changes only the pixels under the
//! bodies. The renderer records the rectangle of every body it draws; the next frame
//! drawn into the same pixmap restores only those rectangles from the static layer
//! instead of copying the whole layer, and the encoder compresses afresh only the tiles
//! they cover, copying the static layer's compressed bits everywhere else. A frame that
//! draws anything whose extent is not tracked (arrows, springs, a legend, layers that
//! change in time) is damaged whole, and both stages then do what they would do
//! without damage. The HUD is tracked: its box is a rectangle like a body's.
//!
//! Frames with trails are compared with the frame before instead of the static layer:
//! a [`TileMask`] marks the tiles of 8 pixels where the trail layer gained segments and
//! where the bodies of either frame lie, and the frame coder compresses only those.
//!
//! The invariant: every pixel outside the damage equals the static layer's pixel. The
//! damage is a superset of what was drawn, never a subset; a rectangle too large costs
//! time, one too small would cost correctness, so the margins are generous.

use tiny_skia::Pixmap;

/// A rectangle of whole pixels, x0..x1 by y0..y1 (half-open), inside the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

/// The part of a frame that may differ from the static layer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Damage {
    rects: Vec<PixelRect>,
    /// The sum of the rectangles' areas, in pixels.
    area: u64,
    whole: bool,
    /// Whether rectangles over a quarter of the frame make the damage whole.
    bounded: bool,
}

impl Default for Damage {
    /// No damage: the pixmap is a copy of the static layer.
    fn default() -> Self {
        Damage {
            rects: Vec::new(),
            area: 0,
            whole: false,
            bounded: true,
        }
    }
}

impl Damage {
    /// Damage everywhere: nothing is known about the pixmap.
    pub fn whole() -> Self {
        Damage {
            whole: true,
            ..Damage::default()
        }
    }

    /// No damage, and rectangles that never make it whole however much they cover:
    /// for a frame encoded tile by tile against the frame before
    /// ([`crate::render::fastpng::FrameCoder`]), where the rectangles only mark tiles.
    pub fn unbounded() -> Self {
        Damage {
            bounded: false,
            ..Damage::default()
        }
    }

    /// Returns true when the whole frame may differ from the static layer.
    pub fn is_whole(&self) -> bool {
        self.whole
    }

    /// Returns the sum of the rectangles' areas in pixels (overlaps counted twice).
    pub fn area(&self) -> u64 {
        self.area
    }

    /// Returns the damaged rectangles (meaningful only when not [`Damage::is_whole`]).
    pub fn rects(&self) -> &[PixelRect] {
        &self.rects
    }

    /// Forgets all damage: the pixmap equals the static layer again.
    pub fn clear(&mut self) {
        self.rects.clear();
        self.area = 0;
        self.whole = false;
    }

    /// Marks the whole frame as damaged.
    pub fn set_whole(&mut self) {
        self.rects.clear();
        self.area = 0;
        self.whole = true;
    }

    /// Adds the pixels of columns x0..x1 and rows y0..y1, clamped to a frame of
    /// `width` × `height`. Once the rectangles cover a quarter of the frame (overlaps
    /// counted twice), the damage becomes whole: restoring and encoding rectangle by
    /// rectangle would then cost more than doing the whole frame, and recording more of
    /// them would be wasted. Below it the encoder weighs the tiles against whole rows
    /// itself (`StaticPng::tiles_pay`, which knows how busy the static layer is).
    pub fn add_rect(&mut self, (x0, y0, x1, y1): (i64, i64, i64, i64), width: u32, height: u32) {
        if self.whole {
            return;
        }
        let clamp = |v: i64, max: u32| v.clamp(0, i64::from(max)) as u32;
        let rect = PixelRect {
            x0: clamp(x0, width),
            y0: clamp(y0, height),
            x1: clamp(x1, width),
            y1: clamp(y1, height),
        };
        if rect.x0 < rect.x1 && rect.y0 < rect.y1 {
            self.area += u64::from(rect.x1 - rect.x0) * u64::from(rect.y1 - rect.y0);
            if self.bounded && 4 * self.area > u64::from(width) * u64::from(height) {
                self.set_whole();
            } else {
                self.rects.push(rect);
            }
        }
    }

    /// Keeps only the damage inside columns x0..x1 and rows y0..y1, after `restore`
    /// has been called with each part of each rectangle outside them (at most four
    /// bands: above, below, left and right), which returns those pixels to the
    /// static layer. Whole damage stays whole.
    pub fn keep_inside(&mut self, inside: PixelRect, mut restore: impl FnMut(PixelRect)) {
        if self.whole {
            return;
        }
        self.area = 0;
        self.rects.retain_mut(|r| {
            let band = |x0, y0, x1, y1| PixelRect { x0, y0, x1, y1 };
            let (y0, y1) = (r.y0.max(inside.y0), r.y1.min(inside.y1));
            let parts = [
                band(r.x0, r.y0, r.x1, r.y1.min(inside.y0)),
                band(r.x0, r.y0.max(inside.y1), r.x1, r.y1),
                band(r.x0, y0, r.x1.min(inside.x0), y1),
                band(r.x0.max(inside.x1), y0, r.x1, y1),
            ];
            for part in parts {
                if part.x0 < part.x1 && part.y0 < part.y1 {
                    restore(part);
                }
            }
            *r = band(r.x0.max(inside.x0), y0, r.x1.min(inside.x1), y1);
            r.x0 < r.x1 && r.y0 < r.y1
        });
        self.area = self
            .rects
            .iter()
            .map(|r| u64::from(r.x1 - r.x0) * u64::from(r.y1 - r.y0))
            .sum();
    }

    /// Adds the pixels that a square of half-side `reach` around pixel position
    /// (x, y) touches, within a frame of `width` × `height`. A position that is not a
    /// number damages the whole frame, since nothing is known of where it drew.
    pub fn add_around(&mut self, x: f32, y: f32, reach: f32, width: u32, height: u32) {
        if self.whole {
            return;
        }
        let (x0, x1) = ((x - reach).floor(), (x + reach).ceil());
        let (y0, y1) = ((y - reach).floor(), (y + reach).ceil());
        if !(x0.is_finite() && x1.is_finite() && y0.is_finite() && y1.is_finite()) {
            self.set_whole();
            return;
        }
        // Clamped to a range where `as i64` is exact, then to the frame.
        let int = |v: f32| v.clamp(-1.0e9, 1.0e9) as i64;
        self.add_rect((int(x0), int(y0), int(x1), int(y1)), width, height);
    }
}

/// Pixels of 8 along a row that may differ between two frames: one bit per tile of 8
/// pixels (bit t % 64 of word t / 64 of the row), row by row. Eight pixels are one
/// tile of the PNG encoder's filtered rows, so the mask says directly which tiles it
/// must compress afresh.
#[derive(Clone, Debug)]
pub struct TileMask {
    width: u32,
    height: u32,
    /// Words per row.
    words: usize,
    bits: Vec<u64>,
    /// Set when nothing is known: every tile may differ.
    whole: bool,
}

/// Pixels per tile of a [`TileMask`].
pub const TILE_PIXELS: u32 = 8;

impl TileMask {
    /// A mask of a frame `width` × `height`, every tile marked (nothing is known yet).
    pub fn new(width: u32, height: u32) -> Self {
        let words = (width.div_ceil(TILE_PIXELS) as usize).div_ceil(64);
        TileMask {
            width,
            height,
            words,
            bits: vec![0; words * height as usize],
            whole: true,
        }
    }

    /// Returns true when every tile is marked.
    pub fn is_whole(&self) -> bool {
        self.whole
    }

    /// Marks every tile.
    pub fn set_whole(&mut self) {
        self.whole = true;
    }

    /// Unmarks every tile.
    pub fn clear(&mut self) {
        self.bits.fill(0);
        self.whole = false;
    }

    /// The frame's width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Row y's bits (all ones when the mask is whole is not reflected here: check
    /// [`TileMask::is_whole`] first).
    #[inline]
    pub fn row(&self, y: usize) -> &[u64] {
        &self.bits[y * self.words..(y + 1) * self.words]
    }

    /// Marks the tile of pixel (x, y).
    #[inline]
    pub fn mark(&mut self, x: usize, y: usize) {
        let t = x / TILE_PIXELS as usize;
        self.bits[y * self.words + t / 64] |= 1 << (t % 64);
    }

    /// Marks the tiles of pixels x0..x1 of row y (inside the mask, x0 < x1).
    #[inline]
    pub fn mark_span(&mut self, x0: usize, x1: usize, y: usize) {
        // Bit by bit, not through `set_bits_in_rows`: a stamp's rows span one to three
        // tiles, and the word ranges' set-up made `trails-1000` 2 to 4% slower
        // (`builds-pairs`, 8 pairs: CPU 4.73 against 4.84 s).
        let tile = TILE_PIXELS as usize;
        let row = &mut self.bits[y * self.words..(y + 1) * self.words];
        for t in x0 / tile..=(x1 - 1) / tile {
            row[t / 64] |= 1 << (t % 64);
        }
    }

    /// Marks the tiles of pixels x0..x1 of row y (inside the mask, x0 < x1), as
    /// [`TileMask::mark_span`] does, and returns how many of them were not marked
    /// before.
    #[inline]
    pub fn mark_span_counting(&mut self, x0: usize, x1: usize, y: usize) -> usize {
        let tile = TILE_PIXELS as usize;
        let row = &mut self.bits[y * self.words..(y + 1) * self.words];
        let mut new = 0;
        for t in x0 / tile..=(x1 - 1) / tile {
            let (word, bit) = (&mut row[t / 64], 1 << (t % 64));
            new += usize::from(*word & bit == 0);
            *word |= bit;
        }
        new
    }

    /// Marks every tile that pixels of `r` fall in.
    pub fn add_rect(&mut self, r: PixelRect) {
        let x1 = r.x1.min(self.width);
        if r.x0 >= x1 {
            return;
        }
        let (t0, t1) = (
            (r.x0 / TILE_PIXELS) as usize,
            x1.div_ceil(TILE_PIXELS) as usize,
        );
        let rows = r.y0 as usize..(r.y1.min(self.height)) as usize;
        set_bits_in_rows(&mut self.bits, self.words, t0..t1, rows);
    }

    /// Marks every tile of `damage`: all of them when it is whole.
    pub fn add_damage(&mut self, damage: &Damage) {
        if damage.is_whole() {
            self.whole = true;
            return;
        }
        for r in damage.rects() {
            self.add_rect(*r);
        }
    }

    /// How many tiles the frame has.
    pub fn tiles(&self) -> usize {
        self.height as usize * self.width.div_ceil(TILE_PIXELS) as usize
    }

    /// How many tiles are marked (all of them when the mask is whole).
    pub fn count(&self) -> usize {
        if self.whole {
            return self.tiles();
        }
        self.bits.iter().map(|b| b.count_ones() as usize).sum()
    }

    /// Marks every tile `other` marks (a mask of the same size).
    pub fn add_mask(&mut self, other: &TileMask) {
        self.whole |= other.whole;
        for (a, b) in self.bits.iter_mut().zip(&other.bits) {
            *a |= b;
        }
    }
}

/// A mask marked while it holds at most `limit` tiles: past that it is made whole, and
/// marking it stops. A trail frame's passes that mark tile by tile (springs, arrows)
/// use it, since a frame that marks more than a third of its tiles is compressed
/// whole, and the marks past that are lost work.
pub struct Marking<'a> {
    mask: Option<&'a mut TileMask>,
    marked: usize,
    limit: usize,
}

impl<'a> Marking<'a> {
    /// Marks on `mask` (made whole at once if it already holds more than `limit`).
    pub fn new(mask: &'a mut TileMask, limit: usize) -> Self {
        let marked = mask.count();
        let mut marking = Marking {
            mask: Some(mask),
            marked,
            limit,
        };
        marking.check();
        marking
    }

    /// Marks the tiles of pixels x0..x1 of row y (inside the mask, x0 < x1), if the
    /// mask is still marked.
    #[inline]
    pub fn span(&mut self, x0: usize, x1: usize, y: usize) {
        if let Some(mask) = &mut self.mask {
            self.marked += mask.mark_span_counting(x0, x1, y);
        }
    }

    /// Makes the mask whole, and stops marking it, once it holds more than the limit.
    /// (Called between shapes, not between rows: a shape's rows are cheap to count.)
    pub fn check(&mut self) {
        if self.marked > self.limit {
            self.make_whole();
        }
    }

    /// How many more tiles may be marked before the mask is made whole.
    pub fn room(&self) -> usize {
        match self.mask {
            Some(_) => self.limit.saturating_sub(self.marked),
            None => 0,
        }
    }

    /// Makes the mask whole now, and stops marking it.
    pub fn make_whole(&mut self) {
        if let Some(mask) = self.mask.take() {
            mask.set_whole();
        }
    }

    /// Returns true once the mask is whole and no longer marked.
    pub fn is_done(&self) -> bool {
        self.mask.is_none()
    }
}

/// Copies the pixels of the tiles `mask` marks from `from` into `to`, two pixmaps of
/// the mask's size.
pub(super) fn copy_tiles(to: &mut Pixmap, from: &Pixmap, mask: &TileMask) {
    let stride = 4 * to.width() as usize;
    let tile = 4 * TILE_PIXELS as usize;
    let tiles = stride.div_ceil(tile);
    let (from, to) = (from.data(), to.data_mut());
    for y in 0..to.len() / stride.max(1) {
        let row = mask.row(y);
        let mut t = super::fastpng::next_bit(row, 0, true);
        while t < tiles {
            let end = super::fastpng::next_bit(row, t, false).min(tiles);
            let (a, b) = (y * stride + t * tile, y * stride + (end * tile).min(stride));
            // The same columns two rows down, most likely marked too (a body's tiles
            // are a column of runs): scattered runs are each a wait on memory, which
            // the processor does not foresee.
            for k in [a, b - 1] {
                super::raster::prefetch(from, k + 2 * stride);
                super::raster::prefetch(to, k + 2 * stride);
            }
            // Runs are a few tiles: copied in place a tile at a time rather than
            // through a call to `memcpy` each.
            let (src, dst) = (&from[a..b], &mut to[a..b]);
            let mut dst_tiles = dst.chunks_exact_mut(tile);
            let mut src_tiles = src.chunks_exact(tile);
            for (d, s) in (&mut dst_tiles).zip(&mut src_tiles) {
                d.copy_from_slice(s);
            }
            dst_tiles
                .into_remainder()
                .copy_from_slice(src_tiles.remainder());
            t = super::fastpng::next_bit(row, end, true);
        }
    }
}

/// Copies the pixels of the tiles `mask` marks that lie outside `inside` from `from`
/// into `to`, two pixmaps of the mask's size: a frame's margins around a plot, brought
/// back to the static layer where the frame may have drawn over them.
pub(super) fn copy_tiles_outside(
    to: &mut Pixmap,
    from: &Pixmap,
    mask: &TileMask,
    inside: PixelRect,
) {
    let width = to.width() as usize;
    let stride = 4 * width;
    let tile = TILE_PIXELS as usize;
    let (l, r) = (
        inside.x0 as usize,
        (inside.x1 as usize).max(inside.x0 as usize),
    );
    let (top, bottom) = (inside.y0 as usize, inside.y1 as usize);
    let (from, to) = (from.data(), to.data_mut());
    for y in 0..to.len() / stride.max(1) {
        let row = mask.row(y);
        let margins = if y < top || y >= bottom {
            [(0, width), (width, width)]
        } else {
            [(0, l), (r, width)]
        };
        for (x0, x1) in margins {
            let mut t = super::fastpng::next_bit(row, x0 / tile, true);
            while t * tile < x1 {
                let end = super::fastpng::next_bit(row, t, false);
                let (a, b) = ((t * tile).max(x0), (end * tile).min(x1));
                let line = y * stride;
                to[line + 4 * a..line + 4 * b].copy_from_slice(&from[line + 4 * a..line + 4 * b]);
                t = super::fastpng::next_bit(row, end, true);
            }
        }
    }
}

/// Sets bits `tiles` (not empty) of each row in `rows` of a bitmap of `words` 64-bit
/// words a row, bit t of a row in its word t / 64: a word's bits at once, not bit by
/// bit (a thousand bodies' rectangles marked a bit at a time cost a frame 0.05 ms).
pub(crate) fn set_bits_in_rows(
    bits: &mut [u64],
    words: usize,
    tiles: std::ops::Range<usize>,
    rows: std::ops::Range<usize>,
) {
    let (first, last) = (tiles.start, tiles.end - 1);
    for w in first / 64..=last / 64 {
        // Bits lo..=hi of word w.
        let lo = if w == first / 64 { first % 64 } else { 0 };
        let hi = if w == last / 64 { last % 64 } else { 63 };
        let mask = (u64::MAX >> (63 - hi)) & (u64::MAX << lo);
        for y in rows.clone() {
            bits[y * words + w] |= mask;
        }
    }
}

/// Copies the pixels of `r` from `from` into `to`, two pixmaps of the same size.
pub(super) fn copy_rect(to: &mut Pixmap, from: &Pixmap, r: PixelRect) {
    let stride = 4 * to.width() as usize;
    let (x0, x1) = (4 * r.x0 as usize, 4 * r.x1 as usize);
    let (from, to) = (from.data(), to.data_mut());
    for y in r.y0 as usize..r.y1 as usize {
        let row = y * stride;
        to[row + x0..row + x1].copy_from_slice(&from[row + x0..row + x1]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Setting a range of bits word by word sets exactly the bits one at a time would,
    /// for ranges inside one word, across one boundary and across several.
    #[test]
    fn bits_set_word_by_word_are_the_bits_set_one_by_one() {
        let words = 3;
        for start in 0..192 {
            for end in start + 1..=192 {
                let mut fast = vec![0u64; 2 * words];
                set_bits_in_rows(&mut fast, words, start..end, 1..2);
                let mut slow = vec![0u64; 2 * words];
                for t in start..end {
                    slow[words + t / 64] |= 1 << (t % 64);
                }
                assert_eq!(fast, slow, "bits {start}..{end}");
            }
        }
    }

    #[test]
    fn a_counted_span_counts_the_tiles_it_marks_first() {
        // 700 pixels: 88 tiles, two words a row, the last tile short.
        let mut counted = TileMask::new(700, 3);
        counted.clear();
        let mut plain = counted.clone();
        let spans = [(0, 1, 0), (5, 9, 0), (3, 17, 0), (500, 700, 0), (0, 700, 2)];
        let mut total = 0;
        for (x0, x1, y) in spans {
            total += counted.mark_span_counting(x0, x1, y);
            plain.mark_span(x0, x1, y);
            assert_eq!(total, counted.count(), "span {x0}..{x1} of row {y}");
        }
        assert_eq!(counted.bits, plain.bits);
        // Row 0: tiles 0, 1, 2 and 62 to 87; row 2: all 88.
        assert_eq!(total, 3 + 26 + 88);
    }

    #[test]
    fn rectangles_are_clamped_to_the_frame_and_empty_ones_dropped() {
        let mut d = Damage::default();
        d.add_around(1.5, 2.5, 3.0, 100, 50);
        d.add_around(99.0, 49.0, 4.0, 100, 50);
        d.add_around(-20.0, 10.0, 3.0, 100, 50);
        assert_eq!(
            d.rects(),
            &[
                PixelRect {
                    x0: 0,
                    y0: 0,
                    x1: 5,
                    y1: 6
                },
                PixelRect {
                    x0: 95,
                    y0: 45,
                    x1: 100,
                    y1: 50
                }
            ]
        );
        assert!(!d.is_whole());
        d.add_around(f32::NAN, 1.0, 1.0, 100, 50);
        assert!(d.is_whole());
        d.clear();
        // A quarter of the frame and more is whole.
        d.add_rect((0, 0, 50, 25), 100, 50);
        assert!(!d.is_whole());
        d.add_rect((60, 30, 61, 31), 100, 50);
        assert!(d.is_whole());
        d.clear();
        assert!(!d.is_whole() && d.rects().is_empty());
    }

    #[test]
    fn keeping_the_inside_restores_exactly_the_parts_outside() {
        let (w, h) = (40u32, 30u32);
        let inside = PixelRect {
            x0: 10,
            y0: 5,
            x1: 30,
            y1: 25,
        };
        let mut d = Damage::default();
        // Across the top-left corner, wholly inside, wholly outside (right margin).
        d.add_rect((6, 2, 14, 9), w, h);
        d.add_rect((12, 10, 16, 12), w, h);
        d.add_rect((32, 10, 36, 20), w, h);
        let before: Vec<PixelRect> = d.rects().to_vec();
        let mut restored = vec![0u32; (w * h) as usize];
        d.keep_inside(inside, |r| {
            for y in r.y0..r.y1 {
                for x in r.x0..r.x1 {
                    restored[(y * w + x) as usize] += 1;
                }
            }
        });
        let within = |r: &PixelRect, x: u32, y: u32| x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
        for y in 0..h {
            for x in 0..w {
                let damaged = before.iter().any(|r| within(r, x, y));
                let kept = d.rects().iter().any(|r| within(r, x, y));
                let outside = !within(&inside, x, y);
                // Each damaged pixel outside is restored once; the kept damage is
                // exactly the damaged pixels inside.
                let expected = u32::from(damaged && outside);
                assert_eq!(restored[(y * w + x) as usize], expected, "({x}, {y})");
                assert_eq!(kept, damaged && !outside, "({x}, {y})");
            }
        }
        assert_eq!(d.rects().len(), 2);
        assert_eq!(d.area, 4 * 4 + 4 * 2);
    }

    #[test]
    fn copying_tiles_copies_the_marked_tiles_and_nothing_else() {
        // An odd width, so that every row ends in a short tile; runs of one tile and
        // of many, at the start and the end of rows.
        let (w, h) = (203u32, 7u32);
        let mut from = Pixmap::new(w, h).expect("size");
        for (i, b) in from.data_mut().iter_mut().enumerate() {
            *b = (i * 7 % 251) as u8 + 1;
        }
        let mut to = Pixmap::new(w, h).expect("size");
        let mut mask = TileMask::new(w, h);
        mask.clear();
        let tiles = w.div_ceil(TILE_PIXELS) as usize;
        for y in 0..h as usize {
            for t in 0..tiles {
                if (t * 5 + y * 3) % 7 < 3 || t == tiles - 1 && y % 2 == 0 {
                    mask.mark(t * TILE_PIXELS as usize, y);
                }
            }
        }
        copy_tiles(&mut to, &from, &mask);
        for y in 0..h as usize {
            for x in 0..w as usize {
                let marked = (mask.row(y)[x / 8 / 64] >> (x / 8 % 64)) & 1 == 1;
                let k = 4 * (y * w as usize + x);
                let expected = if marked {
                    &from.data()[k..k + 4]
                } else {
                    &[0; 4][..]
                };
                assert_eq!(&to.data()[k..k + 4], expected, "({x}, {y})");
            }
        }
    }
}
