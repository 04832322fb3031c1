//! Writing the one DEFLATE block of a frame: literals and runs of zeros with the
//! Huffman code from `codes.rs`, bit-exact stretches copied from the static rows, and
//! the PNG chunks around the stream.

use super::literals::{Halves, Literals, Scalar, Vector, BLOCK};
use super::*;

/// Writes a PNG chunk: length, type, data, CRC-32 of type and data.
pub(super) fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32fast::hash(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// A DEFLATE bit writer with the run-of-zeros state of the encoder.
pub(super) struct Deflate<'c> {
    pub(super) codes: &'c Codes,
    pub(super) out: Vec<u8>,
    /// Bits not yet written, least significant first, and how many.
    pub(super) acc: u64,
    pub(super) n: u32,
    /// Zero bytes seen and not yet written.
    pub(super) run: usize,
    /// Room for a block's literal codes made ahead of the word loop, when the
    /// processor can make them (`literals::Vector`); `None` otherwise.
    halves: Option<Box<Halves>>,
}

impl<'c> Deflate<'c> {
    pub(super) fn new(codes: &'c Codes, out: Vec<u8>) -> Self {
        Deflate {
            codes,
            out,
            acc: 0,
            n: 0,
            run: 0,
            halves: Halves::new(),
        }
    }
    /// This writer with busy words' literal codes looked up word by word, as on a
    /// processor without AVX-512: tests compare both ways.
    #[cfg(test)]
    pub(super) fn scalar(mut self) -> Self {
        self.halves = None;
        self
    }

    /// Appends a run's code and a word's literal codes as the word loops do.
    #[cfg(test)]
    pub(super) fn word(&mut self, run_bits: u64, run_count: u32, bits: u128, count: u32) {
        let mut sink = Sink::take(self, SINK_BYTES_PER_WORD);
        sink.word(run_bits, run_count, bits, count);
        sink.give(self);
    }

    /// Whether busy words' literal codes are made ahead, a block at a time.
    #[cfg(test)]
    pub(super) fn is_vector(&self) -> bool {
        self.halves.is_some()
    }

    /// Appends the low `count` bits of `bits` (count ≤ 64; no higher bit may be set).
    #[inline(always)]
    pub(super) fn put(&mut self, bits: u64, count: u32) {
        if count > 56 {
            self.emit(bits & 0xffff_ffff, 32);
            self.emit(bits >> 32, count - 32);
        } else {
            self.emit(bits, count);
        }
    }

    /// Appends the low `count` bits of `bits` (count ≤ 56; no higher bit may be set),
    /// through a [`Sink`] with room for them.
    #[inline(always)]
    pub(super) fn emit(&mut self, bits: u64, count: u32) {
        let mut sink = Sink::take(self, 8);
        sink.emit(bits, count);
        sink.give(self);
    }

    #[inline(always)]
    pub(super) fn literal(&mut self, symbol: usize) {
        let (code, length) = self.codes.literal[symbol];
        self.put(code, length);
    }

    /// The number of bits written so far.
    #[inline(always)]
    pub(super) fn bit_position(&self) -> usize {
        8 * self.out.len() + self.n as usize
    }

    /// Appends bits `from..to` of `bytes` (bit i is bit i % 8 of byte i / 8), which
    /// must hold eight bytes past them. A long range is copied a word at a time once
    /// the output is on a byte (see [`Deflate::put_bytes_shifted`]); what is left, 56
    /// bits at a time from unaligned 64-bit reads.
    #[inline(always)]
    pub(super) fn put_bit_range(&mut self, bytes: &[u8], from: usize, to: usize) {
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
        // Worth the set-up from a few hundred bits on.
        if to - bit >= 512 {
            // Bits up to the output's next byte, then the pending whole bytes out.
            let k = ((8 - self.n % 8) % 8) as usize;
            self.put(word_at(bit) & ((1 << k) - 1), k as u32);
            bit += k;
            self.out
                .extend_from_slice(&self.acc.to_le_bytes()[..(self.n / 8) as usize]);
            (self.acc, self.n) = (0, 0);
            let count = (to - bit) / 64;
            self.put_bytes_shifted(bytes, bit, count);
            bit += 64 * count;
        }
        while to - bit >= CHUNK {
            self.put(word_at(bit) & ((1 << CHUNK) - 1), CHUNK as u32);
            bit += CHUNK;
        }
        let rest = to - bit;
        if rest > 0 {
            self.put(word_at(bit) & ((1 << rest) - 1), rest as u32);
        }
    }

    /// Appends `count` 64-bit words of `bytes` starting at bit `from`, to an output
    /// that is on a whole byte with no bits pending: word i is
    /// w_i = (x_i >> s) | (x_{i+1} << (64 - s)), x_i the little-endian word at byte
    /// from / 8 + 8·i and s = from % 8, of which only the first byte of x_{i+1} counts:
    /// for the last word, the byte past the words.
    fn put_bytes_shifted(&mut self, bytes: &[u8], from: usize, count: usize) {
        let (at, s) = (from / 8, (from % 8) as u32);
        let start = self.out.len();
        self.out.resize(start + 8 * count, 0);
        let out = &mut self.out[start..];
        if s == 0 {
            out.copy_from_slice(&bytes[at..at + 8 * count]);
            return;
        }
        // Word i's high bits are the low s bits of the next word: its first byte (for
        // the last word, the byte past the words, read as zero if it is not there).
        let src = &bytes[at..at + 8 * count];
        for (i, (o, x)) in out.chunks_exact_mut(8).zip(src.chunks_exact(8)).enumerate() {
            let low = u64::from_le_bytes([x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]]);
            let next = bytes.get(at + 8 * i + 8).copied().unwrap_or(0);
            o.copy_from_slice(&((low >> s) | (u64::from(next) << (64 - s))).to_le_bytes());
        }
    }

    /// Appends `count` bits of a byte string, least significant bit of each byte first.
    pub(super) fn put_stored_bits(&mut self, bytes: &[u8], count: usize) {
        let mut padded = bytes.to_vec();
        padded.extend_from_slice(&[0; 8]);
        self.put_bit_range(&padded, 0, count);
    }

    /// Compresses bytes: zero bytes lengthen the run, others are literals. Eight bytes
    /// are looked at at once: all zero, they lengthen the run; otherwise the zeros they
    /// start with end the run, the bytes from the first to the last nonzero one are
    /// literals, and the zeros they end with start the next run.
    #[inline]
    pub(super) fn bytes(&mut self, data: &[u8]) {
        self.bytes_marked::<false>(data);
    }

    /// Compresses bytes as [`Deflate::bytes`] does (the same bits), and, when `MARK`,
    /// returns the bit position of the first literal, after the run before it: where
    /// the bits that stand for `data` alone begin (`usize::MAX` when every byte is
    /// zero). Trailing zeros stay in the run, so afterwards the bit position is the end
    /// of the last literal.
    ///
    /// Nothing in the loop branches on the bytes. The words are taken 64 at a time: a
    /// bit for each nonzero word, then the nonzero words one after the other, the zero
    /// words between them only counted. A nonzero word's first and last nonzero bytes
    /// come from counting zero bits; its literal codes (first..=last, a zero between
    /// them staying a literal) come from [`Literals`]: made ahead for the block with
    /// AVX-512 where the processor has it, looked up word by word otherwise. Branches on
    /// where an anti-aliased edge's words and bytes begin and end, which the processor
    /// mispredicted, took a third of the time of busy rows. The bits are written
    /// through a [`Sink`] held in registers, with room for the most the bytes can take
    /// reserved up front.
    #[inline]
    pub(super) fn bytes_marked<const MARK: bool>(&mut self, data: &[u8]) -> usize {
        match self.halves.take() {
            Some(mut halves) => {
                let literals = Vector::<false>::new(self.codes, &mut halves);
                let mark = self.marked_with::<MARK>(data, literals);
                self.halves = Some(halves);
                mark
            }
            None => self.marked_with::<MARK>(data, Scalar(self.codes)),
        }
    }

    /// [`Deflate::bytes_marked`] with busy words' literal codes from `literals`.
    #[inline(always)]
    fn marked_with<const MARK: bool>(&mut self, data: &[u8], mut literals: impl Literals) -> usize {
        let mut mark = usize::MAX;
        let mut run = self.run;
        let words = data.len() / 8;
        let word_at = |j: usize| {
            let b = &data[8 * j..8 * j + 8];
            u64::from_le_bytes(b.try_into().unwrap_or_default())
        };
        // A local slice: through `self.codes` the table's address and length were
        // loaded again after every write, which might have changed them for all the
        // compiler knew.
        let zeros: &[(u64, u32)] = &self.codes.zeros;
        let mut sink = Sink::take(self, SINK_BYTES_PER_WORD * words);
        for block in (0..words).step_by(BLOCK) {
            let n = (words - block).min(BLOCK);
            let mut nonzero = literals.block(&data[8 * block..8 * (block + n)]);
            let mut next = 0;
            while nonzero != 0 {
                let j = nonzero.trailing_zeros() as usize;
                nonzero &= nonzero - 1;
                run += 8 * (j - next);
                next = j + 1;
                let word = word_at(block + j);
                let first = word.trailing_zeros() / 8;
                let last = 7 - word.leading_zeros() / 8;
                run += first as usize;
                let (run_bits, run_count) = match zeros.get(run) {
                    Some(&(bits, count)) if count <= 56 => (bits, count),
                    // A run too long for one write, rarely met among busy words.
                    _ => {
                        sink.give(self);
                        self.run = run;
                        self.flush_run();
                        sink = Sink::take(self, SINK_BYTES_PER_WORD * (words - block));
                        (0, 0)
                    }
                };
                if MARK {
                    mark = mark.min(sink.bit_position() + run_count as usize);
                }
                let (bits, count) = literals.word(j, word, first, last);
                sink.word(run_bits, run_count, bits, count);
                run = (7 - last) as usize;
            }
            run += 8 * (n - next);
        }
        sink.give(self);
        self.run = run;
        // The bytes past the last whole word, one by one.
        for &b in &data[8 * words..] {
            if b == 0 {
                self.run += 1;
            } else {
                self.flush_run();
                if MARK {
                    mark = mark.min(self.bit_position());
                }
                self.literal(usize::from(b));
            }
        }
        mark
    }

    /// Compresses whole tiles of [`TILE`] bytes as [`Deflate::bytes`] does (the same
    /// bits), and calls `tile(k, words, sums, start, end)` for each tile k with a nonzero
    /// byte: its four little-endian words, each word's Σ f_i and Σ i·f_i over its bytes
    /// (as `literals::word_sums` gives them), the bit position of its first literal
    /// (after the run before it) and the bit position past its last literal, which
    /// [`Deflate::bytes_marked`] gives a tile compressed alone. `data.len()` must be a
    /// multiple of [`TILE`].
    ///
    /// This is the loop of `bytes_marked` over a tile's four words, with the sink taken
    /// once for a stretch of tiles instead of once a tile (a few per cent of a trail
    /// frame's encoding; see docs/performance-log.md). The word's code is written out again
    /// here rather than shared: a shared function, inlined, made whole rows about 4%
    /// slower (`trail_probe`'s last line, three alternated runs).
    #[inline]
    pub(super) fn bytes_tiles(
        &mut self,
        data: &[u8],
        tile: impl FnMut(usize, [u64; 4], [(u32, u32); 4], usize, usize),
    ) {
        match self.halves.take() {
            Some(mut halves) => {
                self.tiles_with(data, tile, Vector::<true>::new(self.codes, &mut halves));
                self.halves = Some(halves);
            }
            None => self.tiles_with(data, tile, Scalar(self.codes)),
        }
    }

    /// [`Deflate::bytes_tiles`] with busy words' literal codes from `literals`.
    #[inline(always)]
    fn tiles_with(
        &mut self,
        data: &[u8],
        mut tile: impl FnMut(usize, [u64; 4], [(u32, u32); 4], usize, usize),
        mut literals: impl Literals,
    ) {
        debug_assert_eq!(data.len() % TILE, 0);
        let tiles = data.len() / TILE;
        // A local slice: through `self.codes` the table's address and length were
        // loaded again after every write, which might have changed them for all the
        // compiler knew.
        let zeros: &[(u64, u32)] = &self.codes.zeros;
        let mut run = self.run;
        let mut sink = Sink::take(self, SINK_BYTES_PER_WORD * 4 * tiles);
        let word_at = |j: usize| {
            let b = &data[8 * j..8 * j + 8];
            u64::from_le_bytes(b.try_into().unwrap_or_default())
        };
        // Tiles a block of words at a time, for the literal codes.
        const PER_BLOCK: usize = BLOCK / 4;
        for group in (0..tiles).step_by(PER_BLOCK) {
            let m = (tiles - group).min(PER_BLOCK);
            let nonzero = literals.block(&data[group * TILE..(group + m) * TILE]);
            if nonzero == 0 {
                run += m * TILE;
                continue;
            }
            for t in 0..m {
                let k = group + t;
                let words = std::array::from_fn(|j| word_at(4 * k + j));
                let mut nonzero = (nonzero >> (4 * t)) & 0xf;
                if nonzero == 0 {
                    run += TILE;
                    continue;
                }
                let mut start = usize::MAX;
                let mut next = 0;
                while nonzero != 0 {
                    let j = nonzero.trailing_zeros() as usize;
                    nonzero &= nonzero - 1;
                    run += 8 * (j - next);
                    next = j + 1;
                    let word = words[j];
                    let first = word.trailing_zeros() / 8;
                    let last = 7 - word.leading_zeros() / 8;
                    run += first as usize;
                    let (run_bits, run_count) = match zeros.get(run) {
                        Some(&(bits, count)) if count <= 56 => (bits, count),
                        // A run too long for one write (the zeros of a clean span before).
                        _ => {
                            sink.give(self);
                            self.run = run;
                            self.flush_run();
                            sink = Sink::take(self, SINK_BYTES_PER_WORD * 4 * (tiles - k));
                            (0, 0)
                        }
                    };
                    start = start.min(sink.bit_position() + run_count as usize);
                    let (bits, count) = literals.word(4 * t + j, word, first, last);
                    sink.word(run_bits, run_count, bits, count);
                    run = (7 - last) as usize;
                }
                run += 8 * (4 - next);
                let sums = std::array::from_fn(|j| literals.sums(4 * t + j, words[j]));
                tile(k, words, sums, start, sink.bit_position());
            }
        }
        sink.give(self);
        self.run = run;
    }

    /// Writes the pending run of zeros: one literal zero, then matches at distance 1 of
    /// up to 258 bytes, and at the end literal zeros for a rest shorter than 3.
    #[inline(always)]
    pub(super) fn flush_run(&mut self) {
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

    pub(super) fn write_run(&mut self) {
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
    pub(super) fn into_bits(mut self) -> (Vec<u8>, usize) {
        let bits = 8 * self.out.len() + self.n as usize;
        let bytes = self.n.div_ceil(8) as usize;
        self.out.extend_from_slice(&self.acc.to_le_bytes()[..bytes]);
        (self.out, bits)
    }
}

/// The most bytes one word of [`Deflate::bytes_marked`] writes: a run's code (at most
/// 56 bits; longer ones go through [`Deflate::flush_run`]) and eight literals of at
/// most 14 bits (21 bytes), with room for the unaligned 16-byte store past them.
const SINK_BYTES_PER_WORD: usize = 32;

/// A [`Deflate`]'s output taken into locals for a loop, so that its length and pending
/// bits stay in registers (through `&mut self` the compiler loaded and stored them at
/// every write, since the bytes written might alias them), with room reserved up
/// front.
struct Sink {
    /// The output's start and the whole bytes written.
    ptr: *mut u8,
    len: usize,
    /// The output's capacity: `len + 8` never passes it.
    room: usize,
    /// Pending bits (fewer than eight between writes), least significant first.
    acc: u64,
    n: u32,
}

impl Sink {
    /// Takes `w`'s output with room for `bytes` more bytes, and eight spare.
    #[inline(always)]
    fn take(w: &mut Deflate<'_>, bytes: usize) -> Sink {
        w.out.reserve(bytes + 8);
        Sink {
            ptr: w.out.as_mut_ptr(),
            len: w.out.len(),
            room: w.out.capacity(),
            acc: w.acc,
            n: w.n,
        }
    }

    /// Gives the output back to `w`, which it was taken from.
    #[inline(always)]
    fn give(self, w: &mut Deflate<'_>) {
        assert!(self.len <= w.out.capacity() && self.ptr == w.out.as_mut_ptr());
        // SAFETY: every byte below `len` was there before or written by `emit`.
        unsafe { w.out.set_len(self.len) };
        (w.acc, w.n) = (self.acc, self.n);
    }

    /// The number of bits written so far.
    #[inline(always)]
    fn bit_position(&self) -> usize {
        8 * self.len + self.n as usize
    }

    /// Appends the low `count` bits of `bits` (count ≤ 56; no higher bit may be set)
    /// without a branch on the data: the pending bits and the new ones, at most 63,
    /// are stored as one unaligned 64-bit word past the bytes written, and the whole
    /// bytes among them are taken into the output, leaving fewer than eight pending.
    #[inline(always)]
    fn emit(&mut self, bits: u64, count: u32) {
        debug_assert!(count <= 56 && self.n < 8 && bits >> count == 0);
        self.acc |= bits << self.n;
        self.n += count;
        assert!(self.len + 8 <= self.room, "the sink's room was reserved");
        // SAFETY: the eight bytes at `len` lie within the capacity (asserted).
        unsafe {
            self.ptr
                .add(self.len)
                .cast::<[u8; 8]>()
                .write_unaligned(self.acc.to_le_bytes());
        }
        let whole = self.n / 8;
        self.len += whole as usize;
        // At most 56 bits are shifted out: the shift is defined.
        self.acc >>= 8 * whole;
        self.n -= 8 * whole;
    }

    /// Appends the low `count` bits of `bits` (count ≤ 120; no higher bit may be set)
    /// as [`Sink::emit`] does, through one unaligned 128-bit store: the pending bits
    /// and the new ones are at most 127.
    #[inline(always)]
    fn emit_wide(&mut self, bits: u128, count: u32) {
        debug_assert!(count <= 120 && self.n < 8 && bits >> count == 0);
        let all = u128::from(self.acc) | bits << self.n;
        let n = self.n + count;
        assert!(self.len + 16 <= self.room, "the sink's room was reserved");
        // SAFETY: the sixteen bytes at `len` lie within the capacity (asserted).
        unsafe {
            self.ptr
                .add(self.len)
                .cast::<[u8; 16]>()
                .write_unaligned(all.to_le_bytes());
        }
        let whole = n / 8;
        self.len += whole as usize;
        // At most 120 bits are shifted out: the shift is defined.
        self.acc = (all >> (8 * whole)) as u64;
        self.n = n - 8 * whole;
    }

    /// Appends a run's code (`run_count` ≤ 56 bits) and then a word's literal codes
    /// (`count` ≤ 112 bits), in one write of two 64-bit words when the pending bits,
    /// the run's and the literals' take at most 127 bits (nearly always: seven
    /// literals of 9 bits and a run of a thousand zeros), in two writes otherwise.
    ///
    /// The pending bits and the run's code make one head of m ≤ 63 bits; the literals
    /// go above it, shifted by m. A run written through [`Deflate::flush_run`] comes as
    /// an empty code.
    #[inline(always)]
    fn word(&mut self, run_bits: u64, run_count: u32, bits: u128, count: u32) {
        debug_assert!(run_count <= 56 && count <= 112 && bits >> count == 0);
        let m = self.n + run_count;
        let total = m + count;
        // Up to 127 bits: byte `total / 8` of the two words is then within them.
        if total >= 128 {
            self.emit(run_bits, run_count);
            self.emit_wide(bits, count);
            return;
        }
        let head = self.acc | run_bits << self.n;
        let (low, high) = (bits as u64, (bits >> 64) as u64);
        // (head, low, high) as a 192-bit number, m bits of head, its low 128 bits: the
        // rest is zero, as total < 128. `low >> 1 >> (63 - m)` is low >> (64 - m),
        // defined for m = 0 as well.
        let first = head | low << m;
        let second = (low >> 1 >> (63 - m)) | high << m;
        assert!(self.len + 16 <= self.room, "the sink's room was reserved");
        // SAFETY: the sixteen bytes at `len` lie within the capacity (asserted).
        unsafe {
            let at = self.ptr.add(self.len);
            at.cast::<[u8; 8]>().write_unaligned(first.to_le_bytes());
            at.add(8)
                .cast::<[u8; 8]>()
                .write_unaligned(second.to_le_bytes());
        }
        let whole = total / 8;
        self.len += whole as usize;
        // The pending bits are byte `whole` of the two words, with nothing above. The
        // word is chosen by masks: as an `if`, the compiler once made it a branch, which
        // the processor mispredicted about every other word (a quarter slower).
        let in_second = u64::from(whole >= 8).wrapping_neg();
        self.acc = ((first & !in_second) | (second & in_second)) >> (8 * (whole % 8));
        self.n = total % 8;
    }
}
