//! A PNG encoder for frames drawn over a static layer, which compresses the static
//! layer once per render instead of once per frame.
//!
//! Every frame repeats the static layer (background, axes, a field of arrows) wherever
//! nothing moves. The encoder Up-filters rows (each byte minus the byte above it) and
//! cuts every filtered row into tiles of 8 pixels. A tile of a frame whose pixels, and
//! the pixels above them, equal the static layer's has the static layer's filtered
//! bytes, so its compressed bits are computed once per render and copied into every
//! frame; only tiles that something moving touched are compressed afresh.
//!
//! Which tiles those are comes from the renderer's [`Damage`] (the rectangles of the
//! bodies it drew: [`StaticPng::encode_damaged`]), or, when nothing is known, from
//! comparing the frame with the static layer ([`StaticPng::encode`]).
//!
//! The compressed stream is one DEFLATE block with the Huffman code that the `fdeflate`
//! crate tunes for filtered PNG data (read, once per process, from the header of an
//! empty `fdeflate` stream): literals, and runs of zeros as matches at distance 1. So a
//! frame is about the size `--compression fastest` gives. The pixels must be opaque
//! (premultiplied and straight colour then agree); the caller checks. Compressing a
//! dirty tile costs more than `fdeflate` spends on the same bytes inside a whole frame,
//! so a frame with much damage (more than a tenth of its tiles, or most rows changed)
//! is handed to `fdeflate` whole. Either way the bytes depend only on the frame and its
//! damage, never on the worker or the frames before it.

use std::sync::OnceLock;

use simd_adler32::Adler32;
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
    /// For each tile, row by row: what its filtered bytes compress to.
    tiles: Vec<TileBits>,
    /// For each tile, row by row: the index in its row of the first tile at or after
    /// it that is not all zeros (tiles per row when none is), so that a clean span of
    /// zero tiles is skipped at once.
    next_bits: Vec<u16>,
    /// For each tile that begins a run of two or more consecutive tiles that are not
    /// all zero, row by row: the index in its row of the run's end, and what the whole
    /// run compresses to; (0, unused) for every other tile.
    joined: Vec<(u16, TileBits)>,
    /// For each row, the filter-type byte and the whole filtered row compressed at
    /// once (runs of zeros cross tiles), as bits of the pool, and its Adler-32: used
    /// when the row and the row above equal the static layer's.
    rows: Vec<(TileBits, u32)>,
    /// For each row, whether its filtered bytes are all zero (the static layer is the
    /// background there): tiles would then save nothing.
    plain: Vec<bool>,
    /// The compressed bits of the tiles, each starting on a byte; eight spare zero bytes
    /// at the end let every tile be read in whole 64-bit words.
    pool: Vec<u8>,
    codes: &'static Codes,
}

/// What a tile of the static layer compresses to.
#[derive(Clone, Copy, Debug)]
enum TileBits {
    /// All `len` filtered bytes are zero: the tile only lengthens the run of zeros.
    Zeros { len: u32 },
    /// `bits` bits starting at byte `start` of the pool.
    Bits { start: u32, bits: u32 },
    /// At most 64 bits, held here: most tiles of a sparse layer (a few pixels of an
    /// arrow among background) compress to that, and are then written with one
    /// store and no read of the pool.
    Short { bits: u64, count: u32 },
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
}

impl StaticPng {
    /// Compresses the tiles of a static layer, or returns `None` when the Huffman code
    /// cannot be read (then callers use the `png` crate).
    pub fn new(layer: &Pixmap) -> Option<Self> {
        let codes = codes()?;
        let (width, height) = (layer.width(), layer.height());
        let stride = 4 * width as usize;
        let pixels = layer.data().to_vec();
        let mut filtered = vec![0; pixels.len()];
        for y in 0..height as usize {
            let row = &pixels[y * stride..(y + 1) * stride];
            let out = &mut filtered[y * stride..(y + 1) * stride];
            if y == 0 {
                out.copy_from_slice(row);
            } else {
                let above = &pixels[(y - 1) * stride..y * stride];
                up_filter(row, above, out);
            }
        }
        let tiles_per_row = stride.div_ceil(TILE);
        let mut tiles = Vec::with_capacity(height as usize * tiles_per_row);
        let mut pool = Vec::new();
        for y in 0..height as usize {
            let row = &filtered[y * stride..(y + 1) * stride];
            for tile in row.chunks(TILE) {
                if tile.iter().all(|b| *b == 0) {
                    tiles.push(TileBits::Zeros {
                        len: tile.len() as u32,
                    });
                    continue;
                }
                tiles.push(compress_alone(codes, tile, &mut pool));
            }
        }
        // Each run of consecutive tiles that are not all zero, compressed as one: a
        // clean span that holds it whole copies it in one go.
        let mut joined = vec![(0u16, TileBits::Zeros { len: 0 }); tiles.len()];
        for y in 0..height as usize {
            let row = &tiles[y * tiles_per_row..(y + 1) * tiles_per_row];
            let mut t = 0;
            while t < tiles_per_row {
                if matches!(row[t], TileBits::Zeros { .. }) {
                    t += 1;
                    continue;
                }
                let start = t;
                while t < tiles_per_row && !matches!(row[t], TileBits::Zeros { .. }) {
                    t += 1;
                }
                if t - start > 1 {
                    let bytes =
                        &filtered[y * stride + start * TILE..y * stride + (t * TILE).min(stride)];
                    joined[y * tiles_per_row + start] =
                        (t as u16, compress_alone(codes, bytes, &mut pool));
                }
            }
        }
        let mut next_bits = vec![0u16; tiles.len()];
        for (row, next) in tiles
            .chunks(tiles_per_row)
            .zip(next_bits.chunks_mut(tiles_per_row))
        {
            let mut after = tiles_per_row as u16;
            for t in (0..tiles_per_row).rev() {
                if !matches!(row[t], TileBits::Zeros { .. }) {
                    after = t as u16;
                }
                next[t] = after;
            }
        }
        let plain = filtered
            .chunks(stride)
            .map(|row| row.iter().all(|b| *b == 0))
            .collect();
        let mut rows = Vec::with_capacity(height as usize);
        for row in filtered.chunks(stride) {
            let mut w = Deflate::new(codes, Vec::new());
            w.literal(usize::from(UP));
            w.bytes(row);
            w.flush_run();
            let (bytes, bits) = w.into_bits();
            let mut h = Adler32::new();
            h.write(&[UP]);
            h.write(row);
            rows.push((
                TileBits::Bits {
                    start: pool.len() as u32,
                    bits: bits as u32,
                },
                h.finish(),
            ));
            pool.extend_from_slice(&bytes);
        }
        pool.extend_from_slice(&[0; 8]);
        Some(StaticPng {
            joined,
            next_bits,
            rows,
            plain,
            width,
            height,
            pixels,
            tiles,
            pool,
            codes,
        })
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
    /// falls back to [`StaticPng::encode`].
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
        assert_eq!((frame.width(), frame.height()), (self.width, self.height));
        let tiles_per_row = (4 * self.width as usize).div_ceil(TILE);
        let words = tiles_per_row.div_ceil(64);
        let height = self.height as usize;
        // One bit per tile, row by row: set when the tile, or the tile above it, may
        // differ from the static layer.
        let mut dirty = vec![0u64; height * words];
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
        // Compressing a dirty tile costs several times what fdeflate spends on the
        // same bytes within a whole frame (measured: at 22% of tiles dirty the tiles
        // take 1.3 times fdeflate's time over the whole frame), so beyond a tenth of
        // the tiles the whole frame goes to fdeflate, as `--compression fastest`.
        let dirty_tiles: u32 = dirty.iter().map(|w| w.count_ones()).sum();
        if 10 * dirty_tiles as usize > height * tiles_per_row {
            return encode_png_into(out, frame, provenance, Compression::Fastest, true);
        }
        let data = frame.data();
        self.encode_rows(data, provenance, out, |y, dirty_row| {
            let row = &dirty[y * words..(y + 1) * words];
            if row.iter().all(|w| *w == 0) {
                return RowPlan::Static;
            }
            dirty_row.copy_from_slice(row);
            let count: u32 = row.iter().map(|w| w.count_ones()).sum();
            // Few clean tiles save less than switching between spans costs.
            if 4 * (tiles_per_row - count as usize) < tiles_per_row {
                RowPlan::Afresh
            } else {
                RowPlan::Tiles
            }
        });
        Ok(())
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
            } else if self.plain[y] {
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
        // The Adler-32 of the filtered bytes so far.
        let mut adler = 1u32;
        let mut row_filtered = vec![0u8; stride];
        let mut dirty = vec![0u64; tiles_per_row.div_ceil(64)];
        for y in 0..self.height as usize {
            let row = &data[y * stride..(y + 1) * stride];
            let how = plan(y, &mut dirty);
            if let RowPlan::Static = how {
                // The whole filtered row is the static layer's: copy its bits.
                if let (TileBits::Bits { start, bits }, row_adler) = self.rows[y] {
                    w.flush_run();
                    w.put_pool_bits(&self.pool[start as usize..], bits as usize);
                    adler = adler_combine(adler, row_adler, stride + 1);
                }
                continue;
            }
            w.flush_run();
            w.literal(usize::from(UP));
            // The whole row is filtered and summed at once: one pass each, faster than
            // a pass per span for rows cut into many spans.
            if y == 0 {
                row_filtered.copy_from_slice(row);
            } else {
                up_filter(row, &data[(y - 1) * stride..y * stride], &mut row_filtered);
            }
            adler = adler_update(adler, &[UP]);
            adler = adler_update(adler, &row_filtered);
            if let RowPlan::Afresh = how {
                w.bytes(&row_filtered);
                continue;
            }
            // Walk the row in spans: clean tiles first..d, then dirty tiles d..t.
            let base = y * tiles_per_row;
            let mut first = 0;
            while first < tiles_per_row {
                let d = next_bit(&dirty, first, true).min(tiles_per_row);
                // The static layer's filtered bytes, compressed once per render: runs of
                // zero tiles are skipped whole, the others copied.
                let mut k = first;
                while k < d {
                    let next = (self.next_bits[base + k] as usize).min(d);
                    w.run += (next * TILE).min(stride) - k * TILE;
                    if next == d {
                        break;
                    }
                    // A run of non-zero tiles wholly in the span goes in one copy.
                    let (end, run_bits) = self.joined[base + next];
                    let (bits, end) = if end as usize > next && end as usize <= d {
                        (run_bits, end as usize)
                    } else {
                        (self.tiles[base + next], next + 1)
                    };
                    match bits {
                        TileBits::Zeros { len } => w.run += len as usize,
                        TileBits::Short { bits, count } => {
                            w.flush_run();
                            w.put(bits, count);
                        }
                        TileBits::Bits { start, bits } => {
                            w.flush_run();
                            w.put_pool_bits(&self.pool[start as usize..], bits as usize);
                        }
                    }
                    k = end;
                }
                if d == tiles_per_row {
                    break;
                }
                let t = next_bit(&dirty, d, false).min(tiles_per_row);
                w.bytes(&row_filtered[d * TILE..(t * TILE).min(stride)]);
                first = t;
            }
        }
        w.flush_run();
        w.literal(256);
        let (mut bytes, _) = w.into_bits();
        bytes.extend_from_slice(&adler.to_be_bytes());
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

/// Compresses `bytes` (not all zero) on their own: as bits held in place when they
/// fit in 64, or appended to the pool.
fn compress_alone(codes: &'static Codes, bytes: &[u8], pool: &mut Vec<u8>) -> TileBits {
    let mut w = Deflate::new(codes, Vec::new());
    w.bytes(bytes);
    w.flush_run();
    let (out, bits) = w.into_bits();
    if bits <= 64 {
        let mut word = [0u8; 8];
        word[..out.len()].copy_from_slice(&out);
        return TileBits::Short {
            bits: u64::from_le_bytes(word),
            count: bits as u32,
        };
    }
    let start = pool.len() as u32;
    pool.extend_from_slice(&out);
    TileBits::Bits {
        start,
        bits: bits as u32,
    }
}

/// The modulus of Adler-32.
const ADLER: u64 = 65521;

/// Continues an Adler-32 checksum over `data`.
fn adler_update(adler: u32, data: &[u8]) -> u32 {
    let mut h = Adler32::from_checksum(adler);
    h.write(data);
    h.finish()
}

/// Combines the Adler-32 of two strings into that of their concatenation, given the
/// second's length (as zlib's adler32_combine): a = a1 + a2 - 1 and
/// b = b1 + b2 + len2·(a1 - 1), modulo 65521.
fn adler_combine(first: u32, second: u32, len2: usize) -> u32 {
    let m = ADLER;
    let (a1, b1) = (u64::from(first & 0xffff), u64::from(first >> 16));
    let (a2, b2) = (u64::from(second & 0xffff), u64::from(second >> 16));
    let len = len2 as u64 % m;
    let a = (a1 + a2 + m - 1) % m;
    let b = (b1 + b2 + len * ((a1 + m - 1) % m)) % m;
    (b << 16 | a) as u32
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
struct Deflate {
    codes: &'static Codes,
    out: Vec<u8>,
    /// Bits not yet written, least significant first, and how many.
    acc: u64,
    n: u32,
    /// Zero bytes seen and not yet written.
    run: usize,
}

impl Deflate {
    fn new(codes: &'static Codes, out: Vec<u8>) -> Self {
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

    /// Appends `count` bits stored least significant first from the start of `bytes`,
    /// which must hold eight bytes past them.
    fn put_pool_bits(&mut self, bytes: &[u8], count: usize) {
        let words = count / 64;
        for k in 0..words {
            let word = u64::from_le_bytes(bytes[8 * k..8 * k + 8].try_into().unwrap_or([0; 8]));
            self.put(word, 64);
        }
        let rest = (count % 64) as u32;
        if rest > 0 {
            let word =
                u64::from_le_bytes(bytes[8 * words..8 * words + 8].try_into().unwrap_or([0; 8]));
            self.put(word & ((1u64 << rest) - 1), rest);
        }
    }

    /// Appends `count` bits of a byte string, least significant bit of each byte first.
    fn put_stored_bits(&mut self, bytes: &[u8], count: usize) {
        let mut padded = bytes.to_vec();
        padded.extend_from_slice(&[0; 8]);
        self.put_pool_bits(&padded, count);
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
        match self.run {
            0 => {}
            // One or two zeros are literals (a match is at least 3 bytes long), written
            // in one go: the common case of an alpha byte between colour bytes.
            1 | 2 => {
                let (code, length) = self.codes.literal[0];
                let (bits, count) = if self.run == 1 {
                    (code, length)
                } else {
                    (code | code << length, 2 * length)
                };
                self.run = 0;
                self.put(bits, count);
            }
            _ => self.write_run(),
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
    Some(Codes {
        header,
        header_bits,
        zlib,
        literal,
        run,
    })
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
        let mut h = Adler32::new();
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
        // every row), encoded from their damage: a few discs take the tile path, more
        // damage than a tenth of the tiles goes to fdeflate whole.
        let (width, height) = (203, 61);
        let mut layer = Pixmap::new(width, height).expect("pixmap");
        layer.fill(Color::from_rgba8(250, 250, 245, 255));
        for k in 0..12 {
            let grey = Color::from_rgba8(90, 90, 90, 255);
            disc(&mut layer, 17.0 * k as f32, 30.0, 6.5, grey);
        }
        let encoder = StaticPng::new(&layer).expect("the fdeflate code is readable");
        let mut out = Vec::new();
        for k in 0..8 {
            let mut frame = layer.clone();
            let mut damage = Damage::default();
            for j in 0..k {
                let (x, y) = ((j * 71 % 211) as f32 - 3.0, (j * 23 % 67) as f32);
                let c = Color::from_rgba8(30 * k as u8, 200, (j * 9) as u8, 255);
                disc(&mut frame, x, y, 4.3, c);
                damage.add_around(x, y, 4.3 + 1.0, width, height);
            }
            encoder
                .encode_damaged(&frame, &damage, &Provenance::default(), &mut out)
                .expect("encodes");
            assert_eq!(decode(&out).0, frame.data(), "frame {k}");
            check_adler(&out, frame.data(), 4 * width as usize);
        }
    }
}
