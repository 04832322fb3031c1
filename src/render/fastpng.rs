//! A PNG encoder for frames drawn over a static layer, which compresses the static
//! layer once per render instead of once per frame.
//!
//! Every frame repeats the static layer (background, axes, a field of arrows) wherever
//! nothing moves. The encoder Up-filters rows (each byte minus the byte above it) and
//! cuts every filtered row into tiles of 8 pixels. A tile of a frame whose pixels, and
//! the pixels above them, equal the static layer's has the static layer's filtered
//! bytes. So each row of the static layer is compressed once per render, as one stream
//! in which every nonzero tile's bits stand alone between runs of zeros; a frame's row
//! copies, for each clean span between dirty tiles, the stretch of that stream from the
//! span's first nonzero tile to its last in one piece, and compresses afresh only the
//! tiles that something moving touched. The Adler-32 of a clean span comes from prefix
//! sums of the static row, so clean tiles are neither filtered nor read.
//!
//! Which tiles are dirty comes from the renderer's [`Damage`] (the rectangles of the
//! bodies it drew: [`StaticPng::encode_damaged`]), or, when nothing is known, from
//! comparing the frame with the static layer ([`StaticPng::encode`]).
//!
//! The compressed stream is one DEFLATE block with the Huffman code that the `fdeflate`
//! crate tunes for filtered PNG data (read, once per process, from the header of an
//! empty `fdeflate` stream): literals, and runs of zeros as matches at distance 1. So a
//! frame is about the size `--compression fastest` gives. The pixels must be opaque
//! (premultiplied and straight colour then agree); the caller checks. Compressing a
//! dirty tile costs more than `fdeflate` spends on the same bytes inside a whole frame,
//! so a frame with much damage (by a cost model fitted to measurements:
//! `StaticPng::tiles_pay`) is handed to `fdeflate` whole. Either way the bytes depend
//! only on the frame and its damage, never on the worker, the frames before it or the
//! number of threads that compressed the static layer.

use std::sync::OnceLock;

use tiny_skia::Pixmap;

use super::damage::Damage;
use super::encode::{encode_png_into, Compression, Provenance};

/// Bytes per tile of a filtered row: 8 RGBA pixels.
const TILE: usize = 32;

/// The Up filter's type byte at the start of every row.
const UP: u8 = 2;

/// A static layer's compressed tiles, shared by the workers of one render.
#[derive(Debug)]
pub struct StaticPng {
    width: u32,
    height: u32,
    /// The static layer's pixels, RGBA, row after row.
    pixels: Vec<u8>,
    /// The compressed rows.
    layer: Compressed,
    codes: &'static Codes,
}

/// Compressed rows of a static layer, one after the other.
///
/// Each row is compressed once, as one stream of bits: its filter-type byte, then its
/// nonzero stretches (each tile's bytes from its first nonzero byte to its last,
/// compressed on their own) with the runs of zeros between them. Any stretch of that
/// stream from the start of one tile's bits to the end of a later tile's is a valid
/// DEFLATE encoding of the bytes between, so a clean span of a frame's row copies it
/// in one piece, whatever the number of tiles inside.
#[derive(Debug, Default)]
struct Compressed {
    /// Row by row, each tile whose filtered bytes are not all zero, left to right,
    /// then one sentinel (`from` = tiles per row · TILE) that holds the row's sums.
    /// Tiles of background are not stored: the gaps between these are runs of zeros.
    /// An encoder walks a row's items with a cursor, as it walks the row's spans.
    items: Vec<Item>,
    /// For each row, the index in `items` of its first item.
    row_items: Vec<u32>,
    /// For each row, the byte of the pool where its stream starts, and the stream's
    /// length in bits.
    row_pool: Vec<u32>,
    row_bits: Vec<u32>,
    /// For each row, whether its filtered bytes are all zero (the static layer is the
    /// background there): tiles would then save nothing.
    plain: Vec<bool>,
    /// How many 8-byte words of the static layer's filtered bytes are not zero.
    busy_words: usize,
    /// The rows' streams, each starting on a byte; eight spare zero bytes at the end
    /// let every stretch be read in whole 64-bit words.
    pool: Vec<u8>,
}

impl Compressed {
    /// Joins the compressed rows of consecutive parts of a layer, in order; `None`
    /// if an offset does not fit in 32 bits.
    fn join(parts: Vec<Compressed>) -> Option<Compressed> {
        let mut all = Compressed::default();
        for part in parts {
            let items = u32::try_from(all.items.len()).ok()?;
            let pool = u32::try_from(all.pool.len()).ok()?;
            all.row_items
                .extend(part.row_items.iter().map(|k| k + items));
            all.row_pool.extend(part.row_pool.iter().map(|k| k + pool));
            all.row_bits.extend_from_slice(&part.row_bits);
            all.items.extend_from_slice(&part.items);
            all.pool.extend_from_slice(&part.pool);
            all.plain.extend_from_slice(&part.plain);
            all.busy_words += part.busy_words;
        }
        Some(all)
    }
}

/// A nonzero tile of a static layer's row, or the row's sentinel.
#[derive(Clone, Copy, Debug, Default)]
struct Item {
    /// The index in the row of its first nonzero byte, and of the byte after its last.
    from: u32,
    to: u32,
    /// Where its bits start and end in the row's stream.
    start: u32,
    end: u32,
    /// Over the row's filtered bytes f_i before it: Σ f_i, and Σ i·f_i with i the
    /// byte's index in the row. The Adler-32 sums of any clean span follow from two
    /// differences of these, whatever its length.
    sum: u32,
    weighted: u64,
}

/// The Huffman code of the DEFLATE block, as bits ready to write least significant
/// first.
#[derive(Debug)]
struct Codes {
    /// The block header (BFINAL, BTYPE and the code lengths): bytes and bit count.
    header: Vec<u8>,
    header_bits: usize,
    /// The zlib stream header (CMF, FLG).
    zlib: [u8; 2],
    /// Literal bytes 0 to 255 and the end of block (256): (code, length).
    literal: [(u64, u32); 257],
    /// A match of length 3 to 258 at distance 1, length code, extra bits and distance
    /// code together: (bits, count), indexed by length.
    run: Vec<(u64, u32)>,
    /// A whole run of n zeros, as `Deflate::write_run` writes it, for every n below
    /// the length of this table: the shortest runs whose codes fit in 64 bits (about
    /// a thousand bytes), so that nearly every run is one lookup and one write.
    zeros: Vec<(u64, u32)>,
}

impl StaticPng {
    /// Compresses the tiles of a static layer, or returns `None` when the Huffman code
    /// cannot be read (then callers use the `png` crate).
    pub fn new(layer: &Pixmap) -> Option<Self> {
        Self::with_threads(layer, 1)
    }

    /// Compresses the tiles of a static layer like [`StaticPng::new`], its rows
    /// shared among `threads` threads. Each row is compressed on its own and the rows
    /// are joined in order, so the result does not depend on the number of threads.
    pub fn with_threads(layer: &Pixmap, threads: usize) -> Option<Self> {
        let codes = codes()?;
        let (width, height) = (layer.width(), layer.height());
        let stride = 4 * width as usize;
        // The prefix sums Σ f and the bit offsets within a row's stream are 32-bit:
        // rows of up to 2^20 bytes (262,144 pixels) fit both; wider frames go to the
        // `png` crate.
        if stride > 1 << 20 {
            return None;
        }
        let pixels = layer.data().to_vec();
        // Rows ys of the layer, compressed one after the other.
        let rows_of = |ys: std::ops::Range<usize>| -> Compressed {
            let mut part = Compressed::default();
            let mut filtered = vec![0; stride];
            for y in ys {
                let row = &pixels[y * stride..(y + 1) * stride];
                if y == 0 {
                    filtered.copy_from_slice(row);
                } else {
                    up_filter(row, &pixels[(y - 1) * stride..y * stride], &mut filtered);
                }
                compress_row(codes, &filtered, &mut part);
            }
            part
        };
        let h = height as usize;
        let threads = threads.clamp(1, h.max(1));
        let layer = if threads == 1 {
            rows_of(0..h)
        } else {
            let per = h.div_ceil(threads);
            let parts: Vec<Compressed> = std::thread::scope(|scope| {
                let handles: Vec<_> = (0..threads)
                    .map(|k| {
                        let ys = (k * per).min(h)..((k + 1) * per).min(h);
                        scope.spawn(move || rows_of(ys))
                    })
                    .collect();
                handles
                    .into_iter()
                    // A worker only compresses; it cannot panic short of a bug, and
                    // then the panic goes on.
                    .map(|t| t.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
                    .collect()
            });
            Compressed::join(parts)?
        };
        let mut png = StaticPng {
            width,
            height,
            pixels,
            layer,
            codes,
        };
        png.layer.pool.extend_from_slice(&[0; 8]);
        Some(png)
    }

    /// Encodes a frame drawn over this static layer (same size, every pixel opaque) as
    /// an 8-bit RGBA PNG with the given text chunks, into `out` (cleared first).
    ///
    /// When most rows differ from the static layer (a sample of every eighth row
    /// decides), reusing tiles saves little and `fdeflate` over the whole frame is
    /// quicker: the frame is then encoded as `--compression fastest` does.
    pub fn encode(
        &self,
        frame: &Pixmap,
        provenance: &Provenance,
        out: &mut Vec<u8>,
    ) -> Result<(), png::EncodingError> {
        assert_eq!((frame.width(), frame.height()), (self.width, self.height));
        let stride = 4 * self.width as usize;
        let (mut sampled, mut changed) = (0, 0);
        for (row, static_row) in frame
            .data()
            .chunks(stride)
            .zip(self.pixels.chunks(stride))
            .step_by(8)
        {
            sampled += 1;
            changed += usize::from(row != static_row);
        }
        if 2 * changed > sampled {
            return encode_png_into(out, frame, provenance, Compression::Fastest, true);
        }
        self.encode_tiles(frame, provenance, out);
        Ok(())
    }

    /// Encodes a frame drawn over this static layer, like [`StaticPng::encode`], given
    /// where it may differ from the static layer: the tiles outside the damage (and
    /// below none of it, since the Up filter reads the row above) are the static
    /// layer's, so their bits are copied without comparing any pixel. Whole damage
    /// falls back to [`StaticPng::encode`], and so does damage over so many tiles
    /// that `fdeflate` over the whole frame is quicker (`StaticPng::tiles_pay`).
    pub fn encode_damaged(
        &self,
        frame: &Pixmap,
        damage: &Damage,
        provenance: &Provenance,
        out: &mut Vec<u8>,
    ) -> Result<(), png::EncodingError> {
        if damage.is_whole() {
            return self.encode(frame, provenance, out);
        }
        self.encode_damaged_with(frame, damage, provenance, out, false)
    }

    /// Encodes a frame like [`StaticPng::encode_damaged`], always compressing the
    /// damaged tiles and copying the others (whole damage: every tile compressed), for
    /// measuring that path against `fdeflate`.
    pub fn encode_damaged_tiles(
        &self,
        frame: &Pixmap,
        damage: &Damage,
        provenance: &Provenance,
        out: &mut Vec<u8>,
    ) -> Result<(), png::EncodingError> {
        self.encode_damaged_with(frame, damage, provenance, out, true)
    }

    fn encode_damaged_with(
        &self,
        frame: &Pixmap,
        damage: &Damage,
        provenance: &Provenance,
        out: &mut Vec<u8>,
        always_tiles: bool,
    ) -> Result<(), png::EncodingError> {
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
            for y in rows {
                let row = &mut dirty[y * words..(y + 1) * words];
                for t in t0..t1 {
                    row[t / 64] |= 1 << (t % 64);
                }
            }
        }
        let dirty_tiles: u32 = dirty.iter().map(|w| w.count_ones()).sum();
        if !always_tiles && !self.tiles_pay(dirty_tiles as usize, height * tiles_per_row) {
            return encode_png_into(out, frame, provenance, Compression::Fastest, true);
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
        Ok(())
    }

    /// Whether compressing only the dirty tiles, and copying the others, is quicker
    /// than `fdeflate` over the whole frame, given the number of dirty tiles.
    ///
    /// A dirty tile costs more than `fdeflate` spends on the same bytes in a whole
    /// frame (its spans are found and filtered one by one); a clean tile costs next
    /// to nothing, and saves what `fdeflate` would spend on it: a little for a tile of
    /// background, much more for a tile of arrows or text, whose nonzero bytes it
    /// would code one by one. Fitted to encoding times at 1280 × 720 with 1000 to 2500
    /// circles over the background and over 500 arrows and axes (see the README's
    /// Performance section), per 8-byte word of the frame, with d the dirty fraction
    /// of the tiles: the tiles save 0.8 ns per word of the frame and 15 ns per nonzero
    /// word of the static layer outside the damage, and cost 2.6 ns per word of the
    /// frame per unit of d. Over the background they pay up to d ≈ 31%; over the
    /// arrows, beyond the quarter of the frame where damage becomes whole.
    fn tiles_pay(&self, dirty_tiles: usize, tiles: usize) -> bool {
        let words = (self.pixels.len() / 8).max(1) as f64;
        let d = dirty_tiles as f64 / tiles.max(1) as f64;
        let busy = self.layer.busy_words as f64 / words;
        2.6 * d < 0.8 + 15.0 * busy * (1.0 - d)
    }

    /// Encodes a frame reusing the static layer's compressed rows and tiles, finding
    /// them by comparing the frame's pixels with the static layer's.
    fn encode_tiles(&self, frame: &Pixmap, provenance: &Provenance, out: &mut Vec<u8>) {
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
    fn encode_rows(
        &self,
        data: &[u8],
        provenance: &Provenance,
        out: &mut Vec<u8>,
        mut plan: impl FnMut(usize, &mut [u64]) -> RowPlan,
    ) {
        let stride = 4 * self.width as usize;
        let tiles_per_row = stride.div_ceil(TILE);
        out.clear();
        out.extend_from_slice(b"\x89PNG\r\n\x1a\n");
        let mut ihdr = Vec::with_capacity(13);
        ihdr.extend_from_slice(&self.width.to_be_bytes());
        ihdr.extend_from_slice(&self.height.to_be_bytes());
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
        out.extend_from_slice(&self.codes.zlib);
        let mut w = Deflate::new(self.codes, std::mem::take(out));
        w.put_stored_bits(&self.codes.header, self.codes.header_bits);
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
        w.flush_run();
        w.literal(256);
        let (mut bytes, _) = w.into_bits();
        bytes.extend_from_slice(&adler.finish().to_be_bytes());
        *out = bytes;
        let length = (out.len() - idat_start - 8) as u32;
        out[idat_start..idat_start + 4].copy_from_slice(&length.to_be_bytes());
        let crc = crc32fast::hash(&out[idat_start + 4..]);
        out.extend_from_slice(&crc.to_be_bytes());
        chunk(out, b"IEND", &[]);
    }
}

/// Returns the index of the first bit at or after `from` that is set (when `set`) or
/// clear (otherwise) in the bitmap `words` (bit i is bit i % 64 of word i / 64), or
/// 64·words.len() when there is none.
#[inline]
fn next_bit(words: &[u64], from: usize, set: bool) -> usize {
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
enum RowPlan {
    /// The row and the row above are the static layer's: the row's bits are copied.
    Static,
    /// The row is filtered and compressed as a whole.
    Afresh,
    /// Clean tiles are copied and the others compressed.
    Tiles,
}

/// Compresses one filtered row of the static layer and appends it to `part`: its
/// stream (the filter-type byte, each nonzero tile's stretch from its first nonzero
/// byte to its last, and the runs of zeros between), where each tile's bits start and
/// end in it, and the sums Adler-32 needs.
fn compress_row(codes: &Codes, filtered: &[u8], part: &mut Compressed) {
    let stride = filtered.len();
    let tiles_per_row = stride.div_ceil(TILE);
    // How many 8-byte words of `bytes` are not zero, read a word at a time.
    let busy = |bytes: &[u8]| {
        let chunks = bytes.chunks_exact(8);
        let rest = chunks.remainder().iter().fold(0u8, |a, b| a | b);
        chunks
            .map(|w| u64::from_le_bytes(w.try_into().unwrap_or_default()))
            .filter(|w| *w != 0)
            .count()
            + usize::from(rest != 0)
    };
    part.row_items.push(part.items.len() as u32);
    part.row_pool.push(part.pool.len() as u32);
    let mut w = Deflate::new(codes, std::mem::take(&mut part.pool));
    let base = 8 * w.out.len();
    w.literal(usize::from(UP));
    let (mut sum, mut weighted) = (0u32, 0u64);
    let mut at = 0;
    let mut plain = true;
    for (k, tile) in filtered.chunks(TILE).enumerate() {
        if busy(tile) == 0 {
            continue;
        }
        let (Some(first), Some(last)) = (
            tile.iter().position(|b| *b != 0),
            tile.iter().rposition(|b| *b != 0),
        ) else {
            continue;
        };
        plain = false;
        let (from, to) = (k * TILE + first, k * TILE + last + 1);
        w.run += from - at;
        w.flush_run();
        let start = w.bit_position() - base;
        w.bytes(&filtered[from..to]);
        let end = w.bit_position() - base;
        at = to;
        part.items.push(Item {
            from: from as u32,
            to: to as u32,
            start: start as u32,
            end: end as u32,
            sum,
            weighted,
        });
        // Σ f_j and Σ j·f_j within the tile (small enough for 32 bits), then
        // Σ i·f_i = Σ (k·TILE + j)·f_j over the row.
        let (mut s, mut v) = (0u32, 0u32);
        for (j, &f) in tile.iter().enumerate() {
            s += u32::from(f);
            v += j as u32 * u32::from(f);
        }
        sum += s;
        weighted += (k * TILE) as u64 * u64::from(s) + u64::from(v);
    }
    w.run += stride - at;
    w.flush_run();
    part.row_bits.push((w.bit_position() - base) as u32);
    let (pool, _) = w.into_bits();
    part.pool = pool;
    part.plain.push(plain);
    if !plain {
        part.busy_words += busy(filtered);
    }
    // The sentinel: past the last tile, with the row's sums.
    let past = (tiles_per_row * TILE) as u32;
    part.items.push(Item {
        from: past,
        to: past,
        start: 0,
        end: 0,
        sum,
        weighted,
    });
}

/// The modulus of Adler-32.
const ADLER: u64 = 65521;

/// The two sums of an Adler-32 checksum, a = 1 + Σ x and b = Σ of a after each byte,
/// kept in 64 bits and reduced modulo 65521 only once per row.
///
/// After L more bytes x_0..x_{L-1}: a' = a + Σ x_j and b' = b + L·a + Σ (L - j)·x_j.
/// Within one row a stays below 2^32 and b below 2^48 for any width PNG allows, so the
/// 64-bit sums cannot overflow between reductions.
#[derive(Clone, Copy, Debug)]
struct Sums {
    a: u64,
    b: u64,
}

impl Sums {
    #[inline(always)]
    fn add_byte(&mut self, x: u8) {
        self.a += u64::from(x);
        self.b += self.a;
    }

    /// Adds L bytes given s1 = Σ x_j and s2 = Σ (L - j)·x_j.
    #[inline(always)]
    fn add_sums(&mut self, len: u64, s1: u64, s2: u64) {
        self.b += len * self.a + s2;
        self.a += s1;
    }

    /// Adds bytes: `simd-adler32` gives their own checksum, a' = 1 + s1 and
    /// b' = L + s2 modulo 65521, from which s1 and s2 follow (modulo 65521, which is
    /// all the checksum keeps).
    #[inline]
    fn add(&mut self, data: &[u8]) {
        let mut h = simd_adler32::Adler32::new();
        h.write(data);
        let own = u64::from(h.finish());
        let len = data.len() as u64;
        let s1 = ((own & 0xffff) + ADLER - 1) % ADLER;
        let s2 = ((own >> 16) + ADLER - len % ADLER) % ADLER;
        self.add_sums(len, s1, s2);
    }

    #[inline(always)]
    fn reduce(&mut self) {
        self.a %= ADLER;
        self.b %= ADLER;
    }

    /// The checksum: b in the high 16 bits, a in the low.
    fn finish(mut self) -> u32 {
        self.reduce();
        (self.b << 16 | self.a) as u32
    }
}

/// Writes a PNG chunk: length, type, data, CRC-32 of type and data.
fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32fast::hash(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// The Up filter: filtered = row - above, byte by byte, modulo 256.
#[inline]
fn up_filter(row: &[u8], above: &[u8], out: &mut [u8]) {
    for ((o, r), a) in out.iter_mut().zip(row).zip(above) {
        *o = r.wrapping_sub(*a);
    }
}

/// A DEFLATE bit writer with the run-of-zeros state of the encoder.
struct Deflate<'c> {
    codes: &'c Codes,
    out: Vec<u8>,
    /// Bits not yet written, least significant first, and how many.
    acc: u64,
    n: u32,
    /// Zero bytes seen and not yet written.
    run: usize,
}

impl<'c> Deflate<'c> {
    fn new(codes: &'c Codes, out: Vec<u8>) -> Self {
        Deflate {
            codes,
            out,
            acc: 0,
            n: 0,
            run: 0,
        }
    }

    /// Appends the low `count` bits of `bits` (count ≤ 64; no higher bit may be set).
    #[inline(always)]
    fn put(&mut self, bits: u64, count: u32) {
        if count == 0 {
            return;
        }
        self.acc |= bits << self.n;
        let total = self.n + count;
        if total >= 64 {
            self.out.extend_from_slice(&self.acc.to_le_bytes());
            // The bits that did not fit in the word just written.
            self.acc = if self.n == 0 {
                0
            } else {
                bits >> (64 - self.n)
            };
            self.n = total - 64;
        } else {
            self.n = total;
        }
    }

    #[inline(always)]
    fn literal(&mut self, symbol: usize) {
        let (code, length) = self.codes.literal[symbol];
        self.put(code, length);
    }

    /// The number of bits written so far.
    #[inline(always)]
    fn bit_position(&self) -> usize {
        8 * self.out.len() + self.n as usize
    }

    /// Appends bits `from..to` of `bytes` (bit i is bit i % 8 of byte i / 8), which
    /// must hold eight bytes past them: 56 at a time, from unaligned 64-bit reads.
    #[inline]
    fn put_bit_range(&mut self, bytes: &[u8], from: usize, to: usize) {
        let word_at = |bit: usize| {
            let at = bit / 8;
            let word = bytes
                .get(at..at + 8)
                .and_then(|b| b.try_into().ok())
                .map_or(0, u64::from_le_bytes);
            word >> (bit % 8)
        };
        const CHUNK: usize = 56;
        let mut bit = from;
        while to - bit >= CHUNK {
            self.put(word_at(bit) & ((1 << CHUNK) - 1), CHUNK as u32);
            bit += CHUNK;
        }
        let rest = to - bit;
        if rest > 0 {
            self.put(word_at(bit) & ((1 << rest) - 1), rest as u32);
        }
    }

    /// Appends `count` bits of a byte string, least significant bit of each byte first.
    fn put_stored_bits(&mut self, bytes: &[u8], count: usize) {
        let mut padded = bytes.to_vec();
        padded.extend_from_slice(&[0; 8]);
        self.put_bit_range(&padded, 0, count);
    }

    /// Compresses bytes: zero bytes lengthen the run, others are literals. Eight bytes
    /// are looked at at once: all zero, they lengthen the run; otherwise the zeros they
    /// start with end the run, the bytes from the first to the last nonzero one are
    /// literals, and the zeros they end with start the next run.
    #[inline]
    fn bytes(&mut self, data: &[u8]) {
        // The run is counted in a local, which stays in a register through the runs
        // of zero words that make up most of a filtered frame; it goes back into
        // `self.run` only to be written.
        let mut run = self.run;
        let mut chunks = data.chunks_exact(8);
        for chunk in &mut chunks {
            // One 8-byte load (a chunk of `chunks_exact(8)` always converts).
            let word = u64::from_le_bytes(chunk.try_into().unwrap_or_default());
            if word == 0 {
                run += 8;
                continue;
            }
            // No zero byte (the classic test: a byte is zero when subtracting one
            // borrows into its top bit and the byte had no top bit): eight literals.
            const ONES: u64 = 0x0101_0101_0101_0101;
            const TOPS: u64 = 0x8080_8080_8080_8080;
            if word.wrapping_sub(ONES) & !word & TOPS == 0 {
                self.run = run;
                self.flush_run();
                self.four(&chunk[..4]);
                self.four(&chunk[4..]);
                run = 0;
                continue;
            }
            let first = (word.trailing_zeros() / 8) as usize;
            let last = 7 - (word.leading_zeros() / 8) as usize;
            self.run = run + first;
            self.flush_run();
            self.literals(&chunk[first..=last]);
            run = 7 - last;
        }
        self.run = run;
        for &b in chunks.remainder() {
            if b == 0 {
                self.run += 1;
            } else {
                self.flush_run();
                self.literal(usize::from(b));
            }
        }
    }

    /// Writes four bytes as literals in one write (codes are at most 15 bits).
    #[inline(always)]
    fn four(&mut self, bytes: &[u8]) {
        let lit = &self.codes.literal;
        let (c0, l0) = lit[usize::from(bytes[0])];
        let (c1, l1) = lit[usize::from(bytes[1])];
        let (c2, l2) = lit[usize::from(bytes[2])];
        let (c3, l3) = lit[usize::from(bytes[3])];
        let bits = c0 | c1 << l0 | c2 << (l0 + l1) | c3 << (l0 + l1 + l2);
        self.put(bits, l0 + l1 + l2 + l3);
    }

    /// Writes bytes as literals, four codes (at most 15 bits each) at a time.
    #[inline(always)]
    fn literals(&mut self, bytes: &[u8]) {
        for four in bytes.chunks(4) {
            let (mut bits, mut count) = (0u64, 0u32);
            for &b in four {
                let (code, length) = self.codes.literal[usize::from(b)];
                bits |= code << count;
                count += length;
            }
            self.put(bits, count);
        }
    }

    /// Writes the pending run of zeros: one literal zero, then matches at distance 1 of
    /// up to 258 bytes, and at the end literal zeros for a rest shorter than 3.
    #[inline(always)]
    fn flush_run(&mut self) {
        // A run found in the table (an empty run is 0 bits) is one write; a longer
        // one is written piece by piece.
        match self.codes.zeros.get(self.run) {
            Some(&(bits, count)) => {
                self.run = 0;
                self.put(bits, count);
            }
            None => self.write_run(),
        }
    }

    fn write_run(&mut self) {
        self.literal(0);
        let mut rest = self.run - 1;
        self.run = 0;
        while rest >= 258 {
            let (bits, count) = self.codes.run[258];
            self.put(bits, count);
            rest -= 258;
        }
        if rest >= 3 {
            let (bits, count) = self.codes.run[rest];
            self.put(bits, count);
        } else {
            for _ in 0..rest {
                self.literal(0);
            }
        }
    }

    /// Pads to a whole byte and returns the bytes and the number of bits written.
    fn into_bits(mut self) -> (Vec<u8>, usize) {
        let bits = 8 * self.out.len() + self.n as usize;
        let bytes = self.n.div_ceil(8) as usize;
        self.out.extend_from_slice(&self.acc.to_le_bytes()[..bytes]);
        (self.out, bits)
    }
}

/// Returns the Huffman code, read once from the header of an empty `fdeflate` stream.
fn codes() -> Option<&'static Codes> {
    static CODES: OnceLock<Option<Codes>> = OnceLock::new();
    CODES.get_or_init(read_codes).as_ref()
}

/// Reads the dynamic Huffman header of an empty `fdeflate` stream (RFC 1951, 3.2.7).
fn read_codes() -> Option<Codes> {
    let stream = fdeflate::Compressor::new(Vec::new()).ok()?.finish().ok()?;
    let zlib = [*stream.first()?, *stream.get(1)?];
    let data = stream.get(2..)?;
    let mut r = BitReader { data, pos: 0 };
    let (_final, kind) = (r.bits(1)?, r.bits(2)?);
    if kind != 2 {
        return None;
    }
    let hlit = r.bits(5)? as usize + 257;
    let hdist = r.bits(5)? as usize + 1;
    let hclen = r.bits(4)? as usize + 4;
    const ORDER: [usize; 19] = [
        16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15,
    ];
    let mut cl_lengths = [0u8; 19];
    for &symbol in ORDER.iter().take(hclen) {
        cl_lengths[symbol] = r.bits(3)? as u8;
    }
    let cl_codes = canonical(&cl_lengths);
    let mut lengths: Vec<u8> = Vec::with_capacity(hlit + hdist);
    while lengths.len() < hlit + hdist {
        match r.symbol(&cl_lengths, &cl_codes)? {
            l @ 0..=15 => lengths.push(l as u8),
            16 => {
                let previous = *lengths.last()?;
                let n = 3 + r.bits(2)? as usize;
                lengths.extend(std::iter::repeat_n(previous, n));
            }
            17 => {
                let n = 3 + r.bits(3)? as usize;
                lengths.extend(std::iter::repeat_n(0, n));
            }
            18 => {
                let n = 11 + r.bits(7)? as usize;
                lengths.extend(std::iter::repeat_n(0, n));
            }
            _ => return None,
        }
    }
    let header_bits = r.pos;
    let header = data.get(..header_bits.div_ceil(8))?.to_vec();
    let (lit_lengths, dist_lengths) = lengths.split_at(hlit);
    if lit_lengths.len() < 286 || lit_lengths[..286].contains(&0) || dist_lengths[0] == 0 {
        return None;
    }
    let lit_codes = canonical(lit_lengths);
    let dist_codes = canonical(dist_lengths);
    let reversed = |code: u16, length: u8| {
        (
            u64::from(code.reverse_bits() >> (16 - u32::from(length))),
            u32::from(length),
        )
    };
    let mut literal = [(0, 0); 257];
    for (symbol, entry) in literal.iter_mut().enumerate() {
        *entry = reversed(lit_codes[symbol], lit_lengths[symbol]);
    }
    let distance_one = reversed(dist_codes[0], dist_lengths[0]);
    // Length symbols 257..=285: base lengths and extra bits (RFC 1951, 3.2.5).
    const BASE: [usize; 29] = [
        3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115,
        131, 163, 195, 227, 258,
    ];
    const EXTRA: [u32; 29] = [
        0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
    ];
    let mut run = vec![(0, 0); 259];
    for (length, entry) in run.iter_mut().enumerate().skip(3) {
        let k = if length == 258 {
            28
        } else {
            BASE.iter().rposition(|b| *b <= length)?
        };
        let (code, code_length) = reversed(lit_codes[257 + k], lit_lengths[257 + k]);
        let extra = (length - BASE[k]) as u64;
        let bits = code | extra << code_length | distance_one.0 << (code_length + EXTRA[k]);
        *entry = (bits, code_length + EXTRA[k] + distance_one.1);
    }
    let mut codes = Codes {
        header,
        header_bits,
        zlib,
        literal,
        run,
        zeros: Vec::new(),
    };
    codes.zeros = zero_runs(&codes);
    Some(codes)
}

/// The bits of every run of zeros that `Deflate::write_run` writes in at most 64 bits,
/// indexed by the run's length, up to the first that takes more.
fn zero_runs(codes: &Codes) -> Vec<(u64, u32)> {
    let mut zeros = vec![(0, 0)];
    loop {
        let mut w = Deflate::new(codes, Vec::new());
        w.run = zeros.len();
        w.write_run();
        let (out, count) = w.into_bits();
        if count > 64 {
            return zeros;
        }
        let mut word = [0u8; 8];
        word[..out.len()].copy_from_slice(&out);
        zeros.push((u64::from_le_bytes(word), count as u32));
    }
}

/// Assigns canonical Huffman codes to code lengths (RFC 1951, 3.2.2).
fn canonical(lengths: &[u8]) -> Vec<u16> {
    let mut count = [0u16; 16];
    for &l in lengths {
        count[usize::from(l)] += 1;
    }
    count[0] = 0;
    let mut next = [0u16; 16];
    let mut code = 0u16;
    for bits in 1..16 {
        code = (code + count[bits - 1]) << 1;
        next[bits] = code;
    }
    lengths
        .iter()
        .map(|&l| {
            if l == 0 {
                return 0;
            }
            let c = next[usize::from(l)];
            next[usize::from(l)] += 1;
            c
        })
        .collect()
}

/// Reads bits least significant first.
struct BitReader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl BitReader<'_> {
    fn bits(&mut self, count: u32) -> Option<u32> {
        let mut value = 0;
        for i in 0..count {
            let byte = *self.data.get(self.pos / 8)?;
            value |= u32::from((byte >> (self.pos % 8)) & 1) << i;
            self.pos += 1;
        }
        Some(value)
    }

    /// Reads one Huffman-coded symbol, most significant code bit first.
    fn symbol(&mut self, lengths: &[u8], codes: &[u16]) -> Option<usize> {
        let mut code = 0u16;
        for length in 1..=15u8 {
            code = code << 1 | self.bits(1)? as u16;
            if let Some(s) = (0..lengths.len()).find(|&s| lengths[s] == length && codes[s] == code)
            {
                return Some(s);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiny_skia::{Color, FillRule, Paint, PathBuilder, Transform};

    /// Checks the zlib stream's Adler-32 against the filtered bytes of `pixels`: the
    /// decoder does not.
    fn check_adler(png: &[u8], pixels: &[u8], stride: usize) {
        let at = png
            .windows(4)
            .position(|w| w == b"IDAT")
            .expect("an IDAT chunk");
        let length = u32::from_be_bytes(png[at - 4..at].try_into().expect("4 bytes")) as usize;
        let data = &png[at + 4..at + 4 + length];
        let stored = u32::from_be_bytes(data[data.len() - 4..].try_into().expect("4 bytes"));
        let mut h = simd_adler32::Adler32::new();
        let mut filtered = vec![0; stride];
        for (y, row) in pixels.chunks(stride).enumerate() {
            if y == 0 {
                filtered.copy_from_slice(row);
            } else {
                up_filter(row, &pixels[(y - 1) * stride..y * stride], &mut filtered);
            }
            h.write(&[UP]);
            h.write(&filtered);
        }
        assert_eq!(stored, h.finish(), "Adler-32");
    }

    fn decode(png: &[u8]) -> (Vec<u8>, Vec<(String, String)>) {
        let decoder = png::Decoder::new(std::io::Cursor::new(png));
        let mut reader = decoder.read_info().expect("a PNG header");
        let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
        reader.next_frame(&mut pixels).expect("pixels");
        let text = reader
            .info()
            .utf8_text
            .iter()
            .map(|c| (c.keyword.clone(), c.get_text().expect("text")))
            .collect();
        (pixels, text)
    }

    fn disc(pixmap: &mut Pixmap, x: f32, y: f32, r: f32, c: Color) {
        let mut paint = Paint::default();
        paint.set_color(c);
        paint.anti_alias = true;
        if let Some(path) = PathBuilder::from_circle(x, y, r) {
            pixmap.fill_path(
                &path,
                &paint,
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }

    #[test]
    fn frames_decode_to_their_pixels_and_text() {
        // A static layer with detail, and frames that change some tiles of it.
        let mut layer = Pixmap::new(203, 61).expect("pixmap");
        layer.fill(Color::from_rgba8(250, 250, 245, 255));
        for k in 0..12 {
            disc(
                &mut layer,
                17.0 * k as f32,
                30.0,
                6.5,
                Color::from_rgba8(90, 90, 90, 255),
            );
        }
        let encoder = StaticPng::new(&layer).expect("the fdeflate code is readable");
        let provenance = Provenance::default().with("physframes:t", 0.25);
        let mut out = Vec::new();
        for k in 0..6 {
            let mut frame = layer.clone();
            for j in 0..k * 7 {
                let c = Color::from_rgba8(30 * k as u8, 200, (j * 9) as u8, 255);
                disc(
                    &mut frame,
                    (j * 29 % 203) as f32,
                    (j * 13 % 61) as f32,
                    4.3,
                    c,
                );
            }
            encoder.encode_tiles(&frame, &provenance, &mut out);
            let (pixels, text) = decode(&out);
            assert_eq!(pixels, frame.data(), "frame {k}");
            check_adler(&out, frame.data(), 4 * 203);
            assert_eq!(text, [("physframes:t".to_string(), "0.25".to_string())]);
        }
    }

    #[test]
    fn long_runs_and_tiles_of_every_kind_round_trip() {
        let mut layer = Pixmap::new(700, 9).expect("pixmap");
        layer.fill(Color::WHITE);
        let encoder = StaticPng::new(&layer).expect("readable");
        let mut frame = layer.clone();
        frame.data_mut()[4 * 650 + 1] = 3;
        frame.data_mut()[4 * 700 * 5 + 7] = 0;
        let mut out = Vec::new();
        encoder.encode_tiles(&frame, &Provenance::default(), &mut out);
        assert_eq!(decode(&out).0, frame.data());
        check_adler(&out, frame.data(), 4 * 700);
        encoder.encode_tiles(&layer, &Provenance::default(), &mut out);
        assert_eq!(decode(&out).0, layer.data());
    }

    #[test]
    fn damaged_frames_decode_to_their_pixels() {
        // The frames of the test above, drawn over an odd width (a partial tile ends
        // every row), encoded from their damage, both by the tile path (forced) and
        // by the encoder's choice; the last is damaged whole.
        let (width, height) = (203, 61);
        let layer = grey_discs(width, height);
        let encoder = StaticPng::new(&layer).expect("the fdeflate code is readable");
        let mut out = Vec::new();
        for k in 0..9 {
            let (frame, damage) = frame_with_discs(&layer, k);
            let damage = if k == 8 { Damage::whole() } else { damage };
            for forced in [false, true] {
                if forced {
                    encoder.encode_damaged_tiles(&frame, &damage, &Provenance::default(), &mut out)
                } else {
                    encoder.encode_damaged(&frame, &damage, &Provenance::default(), &mut out)
                }
                .expect("encodes");
                assert_eq!(
                    decode(&out).0,
                    frame.data(),
                    "frame {k}, tiles forced: {forced}"
                );
                check_adler(&out, frame.data(), 4 * width as usize);
            }
        }
    }

    /// A static layer with detail: a row of grey discs over an off-white background.
    fn grey_discs(width: u32, height: u32) -> Pixmap {
        let mut layer = Pixmap::new(width, height).expect("pixmap");
        layer.fill(Color::from_rgba8(250, 250, 245, 255));
        for k in 0..12 {
            let grey = Color::from_rgba8(90, 90, 90, 255);
            disc(&mut layer, 17.0 * k as f32, 30.0, 6.5, grey);
        }
        layer
    }

    /// The layer with `k` coloured discs drawn over it, and their damage.
    fn frame_with_discs(layer: &Pixmap, k: usize) -> (Pixmap, Damage) {
        let (width, height) = (layer.width(), layer.height());
        let mut frame = layer.clone();
        let mut damage = Damage::default();
        for j in 0..k {
            let (x, y) = ((j * 71 % 211) as f32 - 3.0, (j * 23 % 67) as f32);
            let c = Color::from_rgba8(30 * k as u8, 200, (j * 9) as u8, 255);
            disc(&mut frame, x, y, 4.3, c);
            damage.add_around(x, y, 4.3 + 1.0, width, height);
        }
        (frame, damage)
    }

    #[test]
    fn the_layer_compresses_to_the_same_bits_on_any_number_of_threads() {
        let layer = grey_discs(203, 61);
        let one = StaticPng::new(&layer).expect("readable");
        let (frame, damage) = frame_with_discs(&layer, 5);
        let mut expected = Vec::new();
        one.encode_damaged_tiles(&frame, &damage, &Provenance::default(), &mut expected)
            .expect("encodes");
        for threads in [2, 3, 7, 200] {
            let many = StaticPng::with_threads(&layer, threads).expect("readable");
            assert_eq!(many.layer.pool, one.layer.pool, "{threads} threads");
            let mut out = Vec::new();
            many.encode_damaged_tiles(&frame, &damage, &Provenance::default(), &mut out)
                .expect("encodes");
            assert_eq!(out, expected, "{threads} threads");
        }
    }

    #[test]
    fn copied_tiles_cost_no_more_bytes_than_compressing_the_whole_frame() {
        // Runs of zeros cross from the static layer's tiles into the frame's and back
        // as in one stream: the tile path's frame is within a few bytes of fdeflate's
        // (same code, same runs; only where a run meets a dirty span may it split).
        let layer = grey_discs(203, 61);
        let encoder = StaticPng::new(&layer).expect("readable");
        for k in [0, 1, 3] {
            let (frame, damage) = frame_with_discs(&layer, k);
            let (mut tiles, mut whole) = (Vec::new(), Vec::new());
            encoder
                .encode_damaged_tiles(&frame, &damage, &Provenance::default(), &mut tiles)
                .expect("encodes");
            encode_png_into(
                &mut whole,
                &frame,
                &Provenance::default(),
                Compression::Fastest,
                true,
            )
            .expect("encodes");
            assert!(
                tiles.len() <= whole.len() + whole.len() / 100 + 16,
                "{k} discs: {} bytes by tiles, {} by fdeflate",
                tiles.len(),
                whole.len()
            );
        }
    }
}
