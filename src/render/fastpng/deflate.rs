//! Writing the one DEFLATE block of a frame: literals and runs of zeros with the
//! Huffman code from `codes.rs`, bit-exact stretches copied from the static rows, and
//! the PNG chunks around the stream.

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
}

impl<'c> Deflate<'c> {
    pub(super) fn new(codes: &'c Codes, out: Vec<u8>) -> Self {
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
    pub(super) fn put(&mut self, bits: u64, count: u32) {
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
    #[inline]
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
    /// from / 8 + 8·i and s = from % 8, which reads one word past the last (the eight
    /// bytes past the range that callers keep).
    fn put_bytes_shifted(&mut self, bytes: &[u8], from: usize, count: usize) {
        let (at, s) = (from / 8, (from % 8) as u32);
        let start = self.out.len();
        self.out.resize(start + 8 * count, 0);
        let out = &mut self.out[start..];
        if s == 0 {
            out.copy_from_slice(&bytes[at..at + 8 * count]);
            return;
        }
        let src = &bytes[at..];
        let word = |i: usize| {
            let b: [u8; 8] = src[8 * i..8 * i + 8].try_into().unwrap_or_default();
            u64::from_le_bytes(b)
        };
        // One byte past the words: enough for the last word's high bits.
        let past = |i: usize| u64::from(src.get(8 * i).copied().unwrap_or(0));
        for (i, o) in out.chunks_exact_mut(8).enumerate() {
            let high = if i + 1 < count {
                word(i + 1)
            } else {
                past(i + 1)
            };
            o.copy_from_slice(&((word(i) >> s) | (high << (64 - s))).to_le_bytes());
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
    #[inline]
    pub(super) fn bytes_marked<const MARK: bool>(&mut self, data: &[u8]) -> usize {
        let mut mark = usize::MAX;
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
                if MARK && mark == usize::MAX {
                    mark = self.bit_position();
                }
                self.four(&chunk[..4]);
                self.four(&chunk[4..]);
                run = 0;
                continue;
            }
            let first = (word.trailing_zeros() / 8) as usize;
            let last = 7 - (word.leading_zeros() / 8) as usize;
            self.run = run + first;
            self.flush_run();
            if MARK && mark == usize::MAX {
                mark = self.bit_position();
            }
            self.literals(&chunk[first..=last]);
            run = 7 - last;
        }
        self.run = run;
        for &b in chunks.remainder() {
            if b == 0 {
                self.run += 1;
            } else {
                self.flush_run();
                if MARK && mark == usize::MAX {
                    mark = self.bit_position();
                }
                self.literal(usize::from(b));
            }
        }
        mark
    }

    /// Writes four bytes as literals in one write (codes are at most 15 bits).
    #[inline(always)]
    pub(super) fn four(&mut self, bytes: &[u8]) {
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
    pub(super) fn literals(&mut self, bytes: &[u8]) {
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
