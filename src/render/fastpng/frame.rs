//! A frame's PNG from the static layer's tiles: which tiles are dirty, whether
//! compressing them pays (the cost model), and the row streams assembled from copied
//! clean stretches and freshly compressed dirty tiles.

use tiny_skia::Pixmap;

use super::*;
use crate::render::damage::{set_bits_in_rows, Damage};
use crate::render::encode::Provenance;

impl StaticPng {
    pub(super) fn encode_damaged_with(
        &self,
        frame: &Pixmap,
        damage: &Damage,
        provenance: &Provenance,
        out: &mut Vec<u8>,
        always_tiles: bool,
    ) {
        assert_eq!((frame.width(), frame.height()), (self.width, self.height));
        let tiles_per_row = (4 * self.width as usize).div_ceil(TILE);
        let words = tiles_per_row.div_ceil(64);
        let height = self.height as usize;
        // One bit per tile, row by row: set when the tile, or the tile above it, may
        // differ from the static layer.
        let mut dirty = vec![0u64; height * words];
        if damage.is_whole() {
            dirty.fill(u64::MAX);
        }
        for r in damage.rects() {
            // Pixels x0..x1 are bytes 4·x0..4·x1, so tiles 4·x0/TILE to ⌈4·x1/TILE⌉.
            let (t0, t1) = (4 * r.x0 as usize / TILE, (4 * r.x1 as usize).div_ceil(TILE));
            let rows = r.y0 as usize..(r.y1 as usize + 1).min(height);
            if t0 < t1 {
                set_bits_in_rows(&mut dirty, words, t0..t1, rows);
            }
        }
        let dirty_tiles: u32 = dirty.iter().map(|w| w.count_ones()).sum();
        if !always_tiles && !self.tiles_pay(dirty_tiles as usize, height * tiles_per_row) {
            self.encode_whole(frame, provenance, out);
            return;
        }
        let data = frame.data();
        self.encode_rows(data, provenance, out, |y, dirty_row| {
            let row = &dirty[y * words..(y + 1) * words];
            if row.iter().all(|w| *w == 0) {
                return RowPlan::Static;
            }
            dirty_row.copy_from_slice(row);
            let count = row
                .iter()
                .map(|w| w.count_ones())
                .sum::<u32>()
                .min(tiles_per_row as u32);
            // Few clean tiles save less than switching between spans costs.
            if 4 * (tiles_per_row - count as usize) < tiles_per_row {
                RowPlan::Afresh
            } else {
                RowPlan::Tiles
            }
        });
    }

    /// Whether compressing only the dirty tiles, and copying the others, is quicker
    /// than compressing every row whole ([`StaticPng::encode_whole`]), given the
    /// number of dirty tiles.
    ///
    /// A dirty tile costs more than the same bytes cost in a whole row (its spans are
    /// found and filtered one by one); a clean tile costs next to nothing, and saves
    /// what the whole row would spend on it: a little for a tile of background, much
    /// more for a tile of arrows or text, whose nonzero bytes it would code one by
    /// one. Fitted to encoding times at 1280 × 720 with 500 to 2500 circles over the
    /// background and over 500 arrows and axes (`cargo run --release --example
    /// encode_probe -- N`), per 8-byte word of the frame, with d the dirty fraction of
    /// the tiles: the tiles save 0.55 ns per word of the frame and 12 ns per nonzero
    /// word of the static layer outside the damage, and cost 2.6 ns per word of the
    /// frame per unit of d. Over the background they pay up to d ≈ 21%; over the
    /// arrows, up to about 30%.
    pub(super) fn tiles_pay(&self, dirty_tiles: usize, tiles: usize) -> bool {
        let words = (self.pixels.len() / 8).max(1) as f64;
        let d = dirty_tiles as f64 / tiles.max(1) as f64;
        let busy = self.layer.busy_words as f64 / words;
        2.6 * d < 0.55 + 12.0 * busy * (1.0 - d)
    }

    /// Encodes a frame row by row, every row filtered and compressed whole: what a
    /// frame that differs from the static layer almost everywhere costs least as.
    /// Busy rows take a quarter less time than `fdeflate` spends on them (1000
    /// arrows: 2.1 against 2.7 ms), and the bits are those the tiles would give.
    pub(super) fn encode_whole(&self, frame: &Pixmap, provenance: &Provenance, out: &mut Vec<u8>) {
        self.encode_rows(frame.data(), provenance, out, |_, _| RowPlan::Afresh);
    }

    /// Encodes a frame reusing the static layer's compressed rows and tiles, finding
    /// them by comparing the frame's pixels with the static layer's.
    pub(super) fn encode_tiles(&self, frame: &Pixmap, provenance: &Provenance, out: &mut Vec<u8>) {
        let stride = 4 * self.width as usize;
        let tiles_per_row = stride.div_ceil(TILE);
        let data = frame.data();
        // Whether each tile of the row above, and of this row, equals the static layer.
        let mut above_same = vec![true; tiles_per_row];
        let mut same = vec![true; tiles_per_row];
        // Whether the whole row above equals the static layer's.
        let mut above_row_same = true;
        self.encode_rows(data, provenance, out, |y, dirty_row| {
            let row = &data[y * stride..(y + 1) * stride];
            let static_row = &self.pixels[y * stride..(y + 1) * stride];
            let row_same = row == static_row;
            let plan = if row_same && above_row_same {
                same.fill(true);
                RowPlan::Static
            } else if self.layer.plain[y] {
                // Tiles of a row that is the background save nothing.
                same.fill(row_same);
                RowPlan::Afresh
            } else {
                if row_same {
                    same.fill(true);
                } else {
                    for ((s, a), b) in same
                        .iter_mut()
                        .zip(row.chunks(TILE))
                        .zip(static_row.chunks(TILE))
                    {
                        // An OR of XORs compiles to a few vector instructions.
                        *s = a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0;
                    }
                }
                dirty_row.fill(0);
                let mut count = 0;
                for (t, (s, a)) in same.iter().zip(&above_same).enumerate() {
                    if *s && *a {
                        count += 1;
                    } else {
                        dirty_row[t / 64] |= 1 << (t % 64);
                    }
                }
                // Tiles pay when enough of the row is clean; otherwise the row is
                // compressed afresh, as a whole.
                if 4 * count < tiles_per_row {
                    RowPlan::Afresh
                } else {
                    RowPlan::Tiles
                }
            };
            above_row_same = row_same;
            std::mem::swap(&mut same, &mut above_same);
            plan
        });
    }

    /// Writes the PNG of a frame whose pixels are `data`, row by row as `plan` says:
    /// `plan(y, dirty)` returns how row y is encoded and, for [`RowPlan::Tiles`], sets
    /// bit t of `dirty` (bit t % 64 of word t / 64) for every tile t of the filtered
    /// row that is not the static layer's, and clears the others.
    pub(super) fn encode_rows(
        &self,
        data: &[u8],
        provenance: &Provenance,
        out: &mut Vec<u8>,
        mut plan: impl FnMut(usize, &mut [u64]) -> RowPlan,
    ) {
        let stride = 4 * self.width as usize;
        let tiles_per_row = stride.div_ceil(TILE);
        let (mut w, idat_start) = start_png(self.codes, self.width, self.height, provenance, out);
        // The Adler-32 of the filtered bytes so far, its two sums reduced once a row.
        let mut adler = Sums { a: 1, b: 0 };
        let mut row_filtered = vec![0u8; stride];
        let mut dirty = vec![0u64; tiles_per_row.div_ceil(64)];
        for y in 0..self.height as usize {
            let row = &data[y * stride..(y + 1) * stride];
            let how = plan(y, &mut dirty);
            w.flush_run();
            adler.add_byte(UP);
            if let RowPlan::Static = how {
                // The whole filtered row is the static layer's: copy its bits.
                let stream = &self.layer.pool[self.layer.row_pool[y] as usize..];
                w.put_bit_range(stream, 0, self.layer.row_bits[y] as usize);
                // The row's sentinel holds its sums; the first item's are zero.
                let end = self
                    .layer
                    .row_items
                    .get(y + 1)
                    .map_or(self.layer.items.len(), |e| *e as usize);
                let total = self.layer.items[end - 1];
                let s2 = stride as u64 * u64::from(total.sum) - total.weighted;
                adler.add_sums(stride as u64, u64::from(total.sum), s2);
                adler.reduce();
                continue;
            }
            w.literal(usize::from(UP));
            let above = (y > 0).then(|| &data[(y - 1) * stride..y * stride]);
            // Filters bytes a..b of the row into the same bytes of `out`.
            let filter = |a: usize, b: usize, out: &mut [u8]| match above {
                Some(above) => up_filter(&row[a..b], &above[a..b], &mut out[a..b]),
                None => out[a..b].copy_from_slice(&row[a..b]),
            };
            if let RowPlan::Afresh = how {
                filter(0, stride, &mut row_filtered);
                adler.add(&row_filtered);
                w.bytes(&row_filtered);
                adler.reduce();
                continue;
            }
            // Walk the row in spans: clean tiles first..d, then dirty tiles d..t. Only
            // the dirty tiles are filtered, summed and compressed; the clean ones are
            // the static layer's, compressed and summed once per render. A cursor
            // follows the walk through the row's nonzero static tiles.
            let items = &self.layer.items[self.layer.row_items[y] as usize..];
            let stream = &self.layer.pool[self.layer.row_pool[y] as usize..];
            let mut i = 0;
            let mut first = 0;
            while first < tiles_per_row {
                let d = next_bit(&dirty, first, true).min(tiles_per_row);
                let (p, q) = (first * TILE, (d * TILE).min(stride));
                // Static tiles in the dirty span before are passed over.
                while (items[i].from as usize) < p {
                    i += 1;
                }
                let mut j = i;
                while (items[j].from as usize) < d * TILE {
                    j += 1;
                }
                if j > i {
                    // The zeros up to the first nonzero tile, the stream from its bits
                    // to the end of the last one's, and the zeros after, pending.
                    w.run += items[i].from as usize - p;
                    w.flush_run();
                    w.put_bit_range(stream, items[i].start as usize, items[j - 1].end as usize);
                    w.run = q - items[j - 1].to as usize;
                } else {
                    w.run += q - p;
                }
                // The span's Adler-32 sums, from the prefix sums before its first
                // nonzero tile and before the first one after it: s1 = Σ f_i and
                // s2 = Σ (q - i)·f_i = q·s1 - Σ i·f_i over p ≤ i < q.
                let (before, after) = (items[i], items[j]);
                let s1 = u64::from(after.sum - before.sum);
                let s2 = q as u64 * s1 - (after.weighted - before.weighted);
                adler.add_sums((q - p) as u64, s1, s2);
                i = j;
                if d == tiles_per_row {
                    break;
                }
                let t = next_bit(&dirty, d, false).min(tiles_per_row);
                let (a, b) = (d * TILE, (t * TILE).min(stride));
                filter(a, b, &mut row_filtered);
                adler.add(&row_filtered[a..b]);
                w.bytes(&row_filtered[a..b]);
                first = t;
            }
            adler.reduce();
        }
        *out = finish_png(w, adler, idat_start);
    }
}

/// Starts a PNG of a frame `width` × `height` in `out` (cleared first): the
/// signature, the header, the provenance's text chunks, and the start of the IDAT
/// chunk up to the DEFLATE block's code. Returns the bit writer, which takes `out`,
/// and where the IDAT chunk starts.
pub(super) fn start_png<'c>(
    codes: &'c Codes,
    width: u32,
    height: u32,
    provenance: &Provenance,
    out: &mut Vec<u8>,
) -> (Deflate<'c>, usize) {
    out.clear();
    out.extend_from_slice(b"\x89PNG\r\n\x1a\n");
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    // 8 bits per channel, colour type 6 (RGBA), deflate, adaptive filtering, no
    // interlace.
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    chunk(out, b"IHDR", &ihdr);
    for (key, value) in &provenance.entries {
        // iTXt: keyword, NUL, uncompressed, method 0, no language, no translated
        // keyword, then the UTF-8 text.
        let mut text = Vec::with_capacity(key.len() + value.len() + 5);
        text.extend_from_slice(key.as_bytes());
        text.extend_from_slice(&[0, 0, 0, 0, 0]);
        text.extend_from_slice(value.as_bytes());
        chunk(out, b"iTXt", &text);
    }
    // IDAT: its length is known at the end, so the chunk is written in place.
    let idat_start = out.len();
    out.extend_from_slice(&[0, 0, 0, 0]);
    out.extend_from_slice(b"IDAT");
    out.extend_from_slice(&codes.zlib);
    let mut w = Deflate::new(codes, std::mem::take(out));
    w.put_stored_bits(&codes.header, codes.header_bits);
    (w, idat_start)
}

/// Ends the PNG that [`start_png`] started: the last run, the end of the block, the
/// Adler-32 of the filtered bytes, the IDAT chunk's length and CRC, and IEND.
pub(super) fn finish_png(mut w: Deflate<'_>, adler: Sums, idat_start: usize) -> Vec<u8> {
    w.flush_run();
    w.literal(256);
    let (mut out, _) = w.into_bits();
    out.extend_from_slice(&adler.finish().to_be_bytes());
    let length = (out.len() - idat_start - 8) as u32;
    out[idat_start..idat_start + 4].copy_from_slice(&length.to_be_bytes());
    let crc = crc32fast::hash(&out[idat_start + 4..]);
    out.extend_from_slice(&crc.to_be_bytes());
    chunk(&mut out, b"IEND", &[]);
    out
}

/// Returns the index of the first bit at or after `from` that is set (when `set`) or
/// clear (otherwise) in the bitmap `words` (bit i is bit i % 64 of word i / 64), or
/// 64·words.len() when there is none.
#[inline]
pub fn next_bit(words: &[u64], from: usize, set: bool) -> usize {
    let mut k = from / 64;
    if k >= words.len() {
        return 64 * words.len();
    }
    let flip = if set { 0 } else { u64::MAX };
    // The bits of word k from `from` on, flipped so that the sought ones are ones.
    let mut word = (words[k] ^ flip) & (u64::MAX << (from % 64));
    loop {
        if word != 0 {
            return 64 * k + word.trailing_zeros() as usize;
        }
        k += 1;
        if k == words.len() {
            return 64 * k;
        }
        word = words[k] ^ flip;
    }
}

/// How one row of a frame is encoded.
pub(super) enum RowPlan {
    /// The row and the row above are the static layer's: the row's bits are copied.
    Static,
    /// The row is filtered and compressed as a whole.
    Afresh,
    /// Clean tiles are copied and the others compressed.
    Tiles,
}
