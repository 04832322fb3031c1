//! The static layer's rows compressed once per render: every nonzero tile's bits
//! standing alone between runs of zeros, with the prefix sums that give any clean
//! span's Adler-32.

use super::*;

/// Compressed rows of a static layer, one after the other.
///
/// Each row is compressed once, as one stream of bits: its filter-type byte, then its
/// nonzero stretches (each tile's bytes from its first nonzero byte to its last,
/// compressed on their own) with the runs of zeros between them. Any stretch of that
/// stream from the start of one tile's bits to the end of a later tile's is a valid
/// DEFLATE encoding of the bytes between, so a clean span of a frame's row copies it
/// in one piece, whatever the number of tiles inside.
#[derive(Debug, Default)]
pub(super) struct Compressed {
    /// Row by row, each tile whose filtered bytes are not all zero, left to right,
    /// then one sentinel (`from` = tiles per row · TILE) that holds the row's sums.
    /// Tiles of background are not stored: the gaps between these are runs of zeros.
    /// An encoder walks a row's items with a cursor, as it walks the row's spans.
    pub(super) items: Vec<Item>,
    /// For each row, the index in `items` of its first item.
    pub(super) row_items: Vec<u32>,
    /// For each row, the byte of the pool where its stream starts, and the stream's
    /// length in bits.
    pub(super) row_pool: Vec<u32>,
    pub(super) row_bits: Vec<u32>,
    /// For each row, whether its filtered bytes are all zero (the static layer is the
    /// background there): tiles would then save nothing.
    pub(super) plain: Vec<bool>,
    /// How many 8-byte words of the static layer's filtered bytes are not zero.
    pub(super) busy_words: usize,
    /// The rows' streams, each starting on a byte; eight spare zero bytes at the end
    /// let every stretch be read in whole 64-bit words.
    pub(super) pool: Vec<u8>,
}

impl Compressed {
    /// Joins the compressed rows of consecutive parts of a layer, in order; `None`
    /// if an offset does not fit in 32 bits.
    pub(super) fn join(parts: Vec<Compressed>) -> Option<Compressed> {
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
pub(super) struct Item {
    /// The index in the row of its first nonzero byte, and of the byte after its last.
    pub(super) from: u32,
    pub(super) to: u32,
    /// Where its bits start and end in the row's stream.
    pub(super) start: u32,
    pub(super) end: u32,
    /// Over the row's filtered bytes f_i before it: Σ f_i, and Σ i·f_i with i the
    /// byte's index in the row. The Adler-32 sums of any clean span follow from two
    /// differences of these, whatever its length.
    pub(super) sum: u32,
    pub(super) weighted: u64,
}

/// Compresses one filtered row of the static layer and appends it to `part`: its
/// stream (the filter-type byte, each nonzero tile's stretch from its first nonzero
/// byte to its last, and the runs of zeros between), where each tile's bits start and
/// end in it, and the sums Adler-32 needs.
pub(super) fn compress_row(codes: &Codes, filtered: &[u8], part: &mut Compressed) {
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
pub(super) const ADLER: u64 = 65521;

/// The two sums of an Adler-32 checksum, a = 1 + Σ x and b = Σ of a after each byte,
/// kept in 64 bits and reduced modulo 65521 only once per row.
///
/// After L more bytes x_0..x_{L-1}: a' = a + Σ x_j and b' = b + L·a + Σ (L - j)·x_j.
/// Within one row a stays below 2^32 and b below 2^48 for any width PNG allows, so the
/// 64-bit sums cannot overflow between reductions.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sums {
    pub(super) a: u64,
    pub(super) b: u64,
}

impl Sums {
    #[inline(always)]
    pub(super) fn add_byte(&mut self, x: u8) {
        self.a += u64::from(x);
        self.b += self.a;
    }

    /// Adds L bytes given s1 = Σ x_j and s2 = Σ (L - j)·x_j.
    #[inline(always)]
    pub(super) fn add_sums(&mut self, len: u64, s1: u64, s2: u64) {
        self.b += len * self.a + s2;
        self.a += s1;
    }

    /// Adds bytes: `simd-adler32` gives their own checksum, a' = 1 + s1 and
    /// b' = L + s2 modulo 65521, from which s1 and s2 follow (modulo 65521, which is
    /// all the checksum keeps).
    #[inline]
    pub(super) fn add(&mut self, data: &[u8]) {
        let mut h = simd_adler32::Adler32::new();
        h.write(data);
        let own = u64::from(h.finish());
        let len = data.len() as u64;
        let s1 = ((own & 0xffff) + ADLER - 1) % ADLER;
        let s2 = ((own >> 16) + ADLER - len % ADLER) % ADLER;
        self.add_sums(len, s1, s2);
    }

    #[inline(always)]
    pub(super) fn reduce(&mut self) {
        self.a %= ADLER;
        self.b %= ADLER;
    }

    /// The checksum: b in the high 16 bits, a in the low.
    pub(super) fn finish(mut self) -> u32 {
        self.reduce();
        (self.b << 16 | self.a) as u32
    }
}

/// The Up filter: filtered = row - above, byte by byte, modulo 256.
#[inline]
pub(super) fn up_filter(row: &[u8], above: &[u8], out: &mut [u8]) {
    for ((o, r), a) in out.iter_mut().zip(row).zip(above) {
        *o = r.wrapping_sub(*a);
    }
}
