//! Frames encoded against the frame before: a worker keeps the bits of the last frame
//! it encoded, tile by tile, and compresses afresh only the tiles where the new frame
//! may differ from it, copying the others' bits.
//!
//! This is for frames with no static layer worth the name, such as frames with trails:
//! their trails change only where this frame's new segments go and the bodies move, but
//! they are most of the frame's bytes, and compressing them whole every frame made a
//! late frame cost twice what an early one did.
//!
//! The bits do not depend on which tiles were copied: every row is the filter-type
//! literal followed by [`Deflate::bytes`] over the row's filtered bytes, 8-byte words
//! counted from the row's start, exactly as if the row were compressed whole. A tile
//! (32 bytes, four words) compressed on its own between runs of zeros gives the same
//! bits as inside its row, so a clean tile's bits, copied from the frame before, are
//! those the tile would have now. So the PNG is a function of the frame's pixels alone,
//! whatever frame the worker drew before, and whatever the marked tiles (a tile marked
//! that did not change costs time, not bits).

use tiny_skia::Pixmap;

use super::frame::{finish_png, next_bit, start_png};
use super::static_rows::Sums;
use super::*;
use crate::render::damage::TileMask;
use crate::render::raster::prefetch;

/// A worker's last frame as encoded: its PNG, where each nonzero tile's bits lie in
/// it, and the sums of every tile and row that give the next frame's Adler-32.
#[derive(Debug)]
pub struct FrameCoder {
    width: u32,
    height: u32,
    codes: &'static Codes,
    /// The last frame's PNG, whose bits clean tiles copy; `None` before the first
    /// frame.
    png: Option<Vec<u8>>,
    /// The buffer the next frame is encoded into.
    spare: Vec<u8>,
    /// Row by row, the last frame's tiles whose filtered bytes are not all zero, with
    /// their bits' positions in `png` (absolute, in bits), then a sentinel past the
    /// row's last tile, as [`Compressed`] keeps a static layer's (whose records also
    /// hold the sums, here in `own` and `row_sums`).
    items: Vec<Tile>,
    /// For each row, the index in `items` of its first item.
    row_items: Vec<u32>,
    /// The same for the frame being encoded.
    next_items: Vec<Tile>,
    next_row_items: Vec<u32>,
    /// Every tile's own sums in the last frame, row after row: Σ f_j over its
    /// filtered bytes f_0..f_31 in bits 0 to 12 (at most 32 · 255) and Σ j·f_j in bits
    /// 13 to 29 (at most 496 · 255), zero for a tile of zeros. A frame writes those of
    /// the tiles it compresses afresh; a clean tile's stay from the frame before, as
    /// its bytes do. They are kept apart from the records so that copying a clean
    /// span's records changes one field of each.
    own: Vec<u32>,
    /// Each row's Σ f_i and Σ i·f_i over its filtered bytes in the last frame: a
    /// frame takes from them the sums of the tiles it compresses afresh and adds their
    /// new ones, so that clean tiles are not read for Adler-32.
    row_sums: Vec<(u64, u64)>,
    /// One filtered row, and its tiles to compress afresh (bit t of word t / 64).
    filtered: Vec<u8>,
    dirty: Vec<u64>,
}

impl FrameCoder {
    /// A coder for frames `width` × `height` (every pixel opaque), or `None` when rows
    /// are too wide for 32-bit offsets.
    pub fn new(width: u32, height: u32) -> Option<Self> {
        let stride = 4 * width as usize;
        // The bit positions are 32-bit: frames whose PNG might pass 2^29 bytes (at most
        // about two bytes a filtered byte) are left to the other encoders.
        if stride > 1 << 20 || stride * height as usize > 1 << 27 {
            return None;
        }
        Some(FrameCoder {
            width,
            height,
            codes: codes(),
            png: None,
            spare: Vec::new(),
            items: Vec::new(),
            row_items: Vec::new(),
            next_items: Vec::new(),
            next_row_items: Vec::new(),
            own: vec![0; stride.div_ceil(TILE) * height as usize],
            row_sums: vec![(0, 0); height as usize],
            filtered: vec![0; stride],
            dirty: vec![0; stride.div_ceil(TILE).div_ceil(64)],
        })
    }

    /// Encodes `frame` as an 8-bit RGBA PNG with the given text chunks and returns it.
    /// `changed` marks the tiles of pixels where the frame may differ from the last
    /// frame this coder encoded (every tile, for the first frame, is taken as marked);
    /// a filtered tile is compressed afresh when its pixels or the pixels above them
    /// are marked, and copied otherwise.
    pub fn encode(&mut self, frame: &Pixmap, changed: &TileMask, provenance: &Provenance) -> &[u8] {
        assert_eq!((frame.width(), frame.height()), (self.width, self.height));
        assert_eq!(changed.size(), (self.width, self.height));
        let stride = 4 * self.width as usize;
        let tiles_per_row = stride.div_ceil(TILE);
        let data = frame.data();
        // The last frame's bits can be copied only when its tiles were recorded: a
        // frame marked changed everywhere is encoded whole and records none, and the
        // frame after it records them afresh.
        let previous = self
            .png
            .take()
            .filter(|_| !changed.is_whole() && !self.row_items.is_empty());
        let mut out = std::mem::take(&mut self.spare);
        let (mut w, idat_start) =
            start_png(self.codes, self.width, self.height, provenance, &mut out);
        let mut adler = Sums { a: 1, b: 0 };
        self.next_items.clear();
        self.next_row_items.clear();
        if changed.is_whole() {
            // Nothing to copy: every row is compressed whole, as the tiles would give
            // it bit for bit, without recording the tiles. A frame that differs
            // everywhere from the one before (arrows over trails, every frame) costs
            // what whole rows cost, not a tile's bookkeeping per tile.
            let mut filtered = std::mem::take(&mut self.filtered);
            for y in 0..self.height as usize {
                let row = &data[y * stride..(y + 1) * stride];
                match y.checked_sub(1) {
                    Some(a) => up_filter(row, &data[a * stride..y * stride], &mut filtered),
                    None => filtered.copy_from_slice(row),
                }
                w.flush_run();
                adler.add_byte(UP);
                w.literal(usize::from(UP));
                adler.add(&filtered);
                w.bytes(&filtered);
                adler.reduce();
            }
            self.filtered = filtered;
            self.items.clear();
            self.row_items.clear();
            let png = finish_png(w, adler, idat_start);
            self.spare = Vec::new();
            return self.png.insert(png).as_slice();
        }
        let mut dirty = std::mem::take(&mut self.dirty);
        for y in 0..self.height as usize {
            let row = &data[y * stride..(y + 1) * stride];
            let above = (y > 0).then(|| &data[(y - 1) * stride..y * stride]);
            // A filtered tile changes when its pixels or those above them do.
            match &previous {
                None => dirty.fill(u64::MAX),
                Some(_) => {
                    dirty.copy_from_slice(changed.row(y));
                    if y > 0 {
                        for (d, a) in dirty.iter_mut().zip(changed.row(y - 1)) {
                            *d |= a;
                        }
                    }
                }
            }
            // The pixels of the tiles to compress afresh AHEAD rows down, and of those
            // above them, asked for now: the tiles are scattered, so the processor does
            // not foresee them, and the filter's reads of them waited on memory (a
            // fifth of a trail frame's encoding, `trail_probe`).
            if previous.is_some() && y + AHEAD < self.height as usize {
                let ahead = y + AHEAD;
                let rows = (ahead * stride, (ahead - 1) * stride);
                let marks = changed.row(ahead).iter().zip(changed.row(ahead - 1));
                for (k, (&c, &a)) in marks.enumerate() {
                    let mut bits = c | a;
                    while bits != 0 {
                        let at = (64 * k + bits.trailing_zeros() as usize) * TILE;
                        bits &= bits - 1;
                        prefetch(data, rows.0 + at);
                        prefetch(data, rows.1 + at);
                    }
                }
            }
            w.flush_run();
            adler.add_byte(UP);
            w.literal(usize::from(UP));
            self.next_row_items.push(self.next_items.len() as u32);
            let own = &mut self.own[y * tiles_per_row..(y + 1) * tiles_per_row];
            // Σ f_i and Σ i·f_i over the row's filtered bytes: the last frame's, less
            // the old sums of each tile compressed afresh plus its new ones; from
            // nothing when every tile is.
            let (mut sum, mut weighted) = match previous {
                Some(_) => self.row_sums[y],
                None => (0, 0),
            };
            // The row's items of the frame before, its sentinel last.
            let old: &[Tile] = match previous {
                Some(_) => {
                    let end = self
                        .row_items
                        .get(y + 1)
                        .map_or(self.items.len(), |e| *e as usize);
                    &self.items[self.row_items[y] as usize..end]
                }
                None => &[],
            };
            let mut i = 0;
            let mut first = 0;
            while first < tiles_per_row {
                let d = next_bit(&dirty, first, true).min(tiles_per_row);
                if d > first {
                    // Clean tiles first..d: the last frame's bits, from its first
                    // nonzero tile's to its last's, with the runs of zeros around them.
                    let (p, q) = (first * TILE, (d * TILE).min(stride));
                    let stream = previous.as_deref().unwrap_or(&[]);
                    while (old[i].from as usize) < p {
                        i += 1;
                    }
                    let before = old[i];
                    let end = d * TILE;
                    let mut j = i;
                    if (before.from as usize) < end {
                        w.run += before.from as usize - p;
                        w.flush_run();
                        // Each copied tile's bits move by the same amount.
                        let at = w.bit_position() as u32;
                        // Written moved into room made for every item left in the
                        // row, in the pass that finds the span's last: not checked item by item
                        // (the check was most of copying a clean span), not through an
                        // iterator's fold, which counted the length a record at a
                        // time, nor copied by a call to `memcpy` and then moved (a frame
                        // with no tile marked 0.31 ms through the fold, 0.26 by
                        // `memcpy`, 0.24 so; with its marks 1.58, 1.55, 1.49 ms:
                        // `trail_probe`), nor after a pass of its own to find the last
                        // (own marks 1.30 ms against 1.23, `ONLY_OWN=1`).
                        let shift = at.wrapping_sub(before.start);
                        let n = self.next_items.len();
                        self.next_items.reserve(old.len() - i);
                        let room = self.next_items.spare_capacity_mut();
                        for (to, it) in room.iter_mut().zip(&old[i..]) {
                            if it.from as usize >= end {
                                break;
                            }
                            to.write(Tile {
                                start: it.start.wrapping_add(shift),
                                ..*it
                            });
                            j += 1;
                        }
                        // SAFETY: the j - i records past the length were written above.
                        unsafe { self.next_items.set_len(n + j - i) };
                        let last = old[j - 1];
                        w.put_bit_range(stream, before.start as usize, last.end() as usize);
                        w.run = q - last.to() as usize;
                    } else {
                        w.run += q - p;
                    }
                    i = j;
                }
                if d == tiles_per_row {
                    break;
                }
                // Dirty tiles d..t, filtered in one pass, then compressed.
                let t = next_bit(&dirty, d, false).min(tiles_per_row);
                let (a, b) = (d * TILE, (t * TILE).min(stride));
                match above {
                    Some(above) => up_filter(&row[a..b], &above[a..b], &mut self.filtered[a..b]),
                    None => self.filtered[a..b].copy_from_slice(&row[a..b]),
                }
                // Whole tiles in one stretch of the bit writer, each nonzero one
                // recorded, with its sums; a short last tile of the row on its own.
                // A tile of zeros is not recorded, and its sums are zero. Tile k's
                // bytes f_j are the row's f_i at i = TILE·k + j.
                if previous.is_some() {
                    for (k, o) in own.iter_mut().enumerate().take(t).skip(d) {
                        let s = u64::from(*o & 0x1fff);
                        sum = sum.wrapping_sub(s);
                        weighted =
                            weighted.wrapping_sub((TILE * k) as u64 * s + u64::from(*o >> 13));
                        *o = 0;
                    }
                } else {
                    own[d..t].fill(0);
                }
                let items = &mut self.next_items;
                let mut record =
                    |at: usize, (from, to, s, v): (usize, usize, u32, u32), start: usize, end| {
                        debug_assert!(end - start <= usize::from(u16::MAX), "a tile's bits");
                        items.push(Tile {
                            from: (at + from) as u32,
                            span: (to - from) as u8,
                            start: start as u32,
                            bits: (end - start) as u16,
                        });
                        own[at / TILE] = s | v << 13;
                        sum = sum.wrapping_add(u64::from(s));
                        weighted = weighted.wrapping_add(at as u64 * u64::from(s) + u64::from(v));
                    };
                let whole = (b - a) / TILE;
                w.bytes_tiles(
                    &self.filtered[a..a + whole * TILE],
                    |k, words, sums, start, end| {
                        record(a + k * TILE, tile_words(words, sums), start, end);
                    },
                );
                let at = a + whole * TILE;
                if at < b {
                    let f = &self.filtered[at..b];
                    match tile_bytes(f) {
                        None => w.run += b - at,
                        Some(bytes) => {
                            let start = w.bytes_marked::<true>(f);
                            record(at, bytes, start, w.bit_position());
                        }
                    }
                }
                first = t;
            }
            // The sentinel: past the last tile.
            let past = (tiles_per_row * TILE) as u32;
            self.next_items.push(Tile {
                from: past,
                ..Tile::default()
            });
            // The row's Adler-32 sums: s1 = Σ f_i and s2 = Σ (L - i)·f_i = L·s1 - Σ i·f_i.
            self.row_sums[y] = (sum, weighted);
            let len = stride as u64;
            adler.add_sums(len, sum, len * sum - weighted);
            adler.reduce();
        }
        self.dirty = dirty;
        let png = finish_png(w, adler, idat_start);
        std::mem::swap(&mut self.items, &mut self.next_items);
        std::mem::swap(&mut self.row_items, &mut self.next_row_items);
        self.spare = previous.unwrap_or_default();
        self.png.insert(png).as_slice()
    }
}

/// A nonzero tile of the last frame's row, or the row's sentinel (`from` past the
/// row's last tile, nothing else): 12 bytes, where the static layer's
/// [`super::static_rows::Item`] takes 32, so that the records a frame copies for its
/// clean tiles (one a tile, most of a late frame with trails) take a third of the
/// memory. Its sums are kept apart (`FrameCoder::own`), so a copied record changes
/// in one field.
#[derive(Clone, Copy, Debug, Default)]
struct Tile {
    /// The index in the row of its first nonzero byte, and how many bytes from it to
    /// one past its last.
    from: u32,
    span: u8,
    /// Where its bits start in the PNG, and how many there are: at most 32 bytes,
    /// none taking more than a 15-bit code (DEFLATE's longest; a run of zeros takes
    /// fewer a byte), so well under 2^16.
    start: u32,
    bits: u16,
}

const _: () = assert!(std::mem::size_of::<Tile>() == 12);

impl Tile {
    /// One past the index of its last nonzero byte.
    #[inline(always)]
    fn to(&self) -> u32 {
        self.from + u32::from(self.span)
    }

    /// Where its bits end in the PNG.
    #[inline(always)]
    fn end(&self) -> u32 {
        self.start.wrapping_add(u32::from(self.bits))
    }
}

/// How many rows ahead [`FrameCoder::encode`] asks for the pixels of the tiles it will
/// compress afresh: 2, 4 and 8 did alike in `trail_probe` (`ONLY_OWN=1`).
const AHEAD: usize = 4;

/// For a whole tile's filtered bytes f_j as four little-endian words, not all zero,
/// and each word's Σ f_i and Σ i·f_i over its own bytes, returns the index of the
/// first nonzero byte, one past the last, Σ f_j and Σ j·f_j.
#[inline(always)]
fn tile_words(words: [u64; 4], sums: [(u32, u32); 4]) -> (usize, usize, u32, u32) {
    // The nonzero words as bits, so that finding the first and the last does not
    // branch on where an edge falls in the tile.
    let busy = words
        .iter()
        .enumerate()
        .fold(0u32, |m, (k, w)| m | u32::from(*w != 0) << k);
    let first = (busy | 1 << 3).trailing_zeros() as usize;
    let last = (31 - (busy | 1).leading_zeros()) as usize;
    let from = 8 * first + (words[first].trailing_zeros() / 8) as usize;
    let to = 8 * last + 8 - (words[last].leading_zeros() / 8) as usize;
    let (mut s, mut v) = (0u32, 0u32);
    for (k, (ws, wv)) in sums.into_iter().enumerate() {
        // Byte j of word k is byte 8·k + j of the tile.
        s += ws;
        v += wv + 8 * k as u32 * ws;
    }
    (from, to, s, v)
}

/// For filtered bytes f_j, returns `None` when all are zero, else the index of the
/// first nonzero byte, one past the last, Σ f_j and Σ j·f_j, byte by byte: for a row's
/// short last tile (whole tiles go through [`tile_words`]).
fn tile_bytes(f: &[u8]) -> Option<(usize, usize, u32, u32)> {
    let from = f.iter().position(|x| *x != 0)?;
    let to = f.iter().rposition(|x| *x != 0).map_or(from, |l| l + 1);
    let (mut s, mut v) = (0u32, 0u32);
    for (j, &x) in f.iter().enumerate() {
        s += u32::from(x);
        v += j as u32 * u32::from(x);
    }
    Some((from, to, s, v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::fastpng::literals::word_sums;

    /// The sums by lanes equal the sums byte by byte, for every tile of a stream of
    /// pseudo-random bytes that includes the extremes (all 255, all 0, one byte).
    #[test]
    fn tile_sums_by_lanes_are_the_sums_byte_by_byte() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut tiles: Vec<[u8; TILE]> = vec![[255; TILE], [0; TILE], [0; TILE]];
        tiles[2][17] = 200;
        for _ in 0..10_000 {
            let mut tile = [0u8; TILE];
            for b in &mut tile {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let x = (state >> 56) as u8;
                // Half the bytes zero, as in filtered frames.
                *b = if state & (1 << 20) == 0 { 0 } else { x };
            }
            tiles.push(tile);
        }
        for tile in &tiles {
            let s: u32 = tile.iter().map(|&x| u32::from(x)).sum();
            let v: u32 = tile
                .iter()
                .enumerate()
                .map(|(j, &x)| j as u32 * u32::from(x))
                .sum();
            let from = tile.iter().position(|x| *x != 0);
            let to = tile.iter().rposition(|x| *x != 0).map(|l| l + 1);
            let expected = from.zip(to).map(|(f, t)| (f, t, s, v));
            let words: [u64; 4] = std::array::from_fn(|k| {
                u64::from_le_bytes(tile[8 * k..8 * k + 8].try_into().expect("eight bytes"))
            });
            let lanes = (words != [0; 4]).then(|| tile_words(words, words.map(word_sums)));
            assert_eq!(lanes, expected, "{tile:?}");
            assert_eq!(tile_bytes(tile), expected, "{tile:?}");
            // The short last tile of a row takes the byte path, with the same sums.
            let short = &tile[..TILE - 3];
            let s: u32 = short.iter().map(|&x| u32::from(x)).sum();
            let v: u32 = short
                .iter()
                .enumerate()
                .map(|(j, &x)| j as u32 * u32::from(x))
                .sum();
            if let Some((_, _, ss, vv)) = tile_bytes(short) {
                assert_eq!((ss, vv), (s, v));
            }
        }
    }
}
