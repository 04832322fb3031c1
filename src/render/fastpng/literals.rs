//! The literal codes of a busy word: the codes of its bytes from its first nonzero
//! byte to its last, one after the other, as the word loops of `deflate.rs` write them.
//!
//! Two ways give the same bits. [`Scalar`] looks up the word's eight codes when the
//! word loop reaches it. [`Vector`] (AVX-512 with VBMI) does it ahead of the loop for a
//! block of 64 words, eight words per 512-bit register: the codes and lengths of 64
//! bytes are three table lookups, the lengths outside each word's first..=last nonzero
//! byte are masked to zero, and the codes are put together in place, pairs of bytes in
//! 32-bit lanes, then fours in 64-bit lanes. The word loop then reads two halves and
//! their lengths per word. With AVX-512 the same pass finds the block's nonzero words
//! and, for tiles, the sums of their bytes for Adler-32. Looking up and shifting eight
//! codes one by one took most of the coder's time on frames full of anti-aliased edges:
//! made ahead, an `arrows-1000` frame encoded in 1.74 ms instead of 2.04 when this came
//! (see docs/performance-log.md, "Literal codes eight words a register").

use super::codes::Codes;

/// Words per block: the word loops find a block's nonzero words as one 64-bit mask.
pub(super) const BLOCK: usize = 64;

/// Where the word loops get a busy word's literal codes.
pub(super) trait Literals {
    /// Called before the word loop visits a block's words: `data` holds its whole
    /// words (at most [`BLOCK`]). Returns the block's nonzero words, bit j set when
    /// word j is not zero.
    fn block(&mut self, data: &[u8]) -> u64;

    /// The codes of bytes first..=last of word j of the block (`word`, nonzero, with
    /// first and last its first and last nonzero bytes), least significant first, and
    /// how many bits they take (at most 8 · 14 = 112).
    fn word(&self, j: usize, word: u64, first: u32, last: u32) -> (u128, u32);

    /// For word j of the block (`word`), Σ f_i and Σ i·f_i over its bytes f_0..f_7,
    /// for the Adler-32 of tiles (`Deflate::bytes_tiles`). Where a block was made with
    /// [`Vector`], only words of a chunk of eight with a nonzero word have them.
    fn sums(&self, j: usize, word: u64) -> (u32, u32);
}

/// Literal codes looked up one by one when the word loop reaches a word.
pub(super) struct Scalar<'c>(pub(super) &'c Codes);

impl Literals for Scalar<'_> {
    #[inline(always)]
    fn block(&mut self, data: &[u8]) -> u64 {
        let mut nonzero = 0u64;
        for (j, word) in data.chunks_exact(8).enumerate() {
            nonzero |= u64::from(word.iter().any(|b| *b != 0)) << j;
        }
        nonzero
    }

    /// The literal zero's code is all zero bits (`Codes::new` asserts it), so a zero
    /// byte adds nothing to the bits, only its length. So the word is shifted down to
    /// its first nonzero byte, all eight bytes' codes are put together unmasked, and
    /// the lengths of the zeros shifted in above the last nonzero byte are taken off.
    #[inline(always)]
    fn word(&self, _j: usize, word: u64, first: u32, last: u32) -> (u128, u32) {
        let shifted = word >> (8 * first);
        let (low, low_count) = half(&self.0.packed, shifted);
        let (high, high_count) = half(&self.0.packed, shifted >> 32);
        // The zeros after the last literal: bits of nothing, lengths to take off.
        let after = 7 - (last - first);
        // Low then high. When the last literal lies in the low half, `high` is all
        // zeros and its place does not matter.
        let bits = u128::from(low) | u128::from(high) << low_count;
        (bits, low_count + high_count - self.0.zero_length * after)
    }

    #[inline(always)]
    fn sums(&self, _j: usize, word: u64) -> (u32, u32) {
        word_sums(word)
    }
}

/// For the eight bytes f_j of a little-endian word, returns Σ f_j and Σ j·f_j, four
/// bytes at a time in 16-bit lanes of one multiply each (a scalar loop over the bytes
/// cost a fifth of the encoder's time).
///
/// With the even bytes e_i = f_{2i} and the odd ones o_i = f_{2i+1} in lanes i = 0..3,
/// multiplying by Σ_k c_k·2^(16k) leaves Σ_(i+k=3) x_i·c_k in the top lane: c = (1, 1,
/// 1, 1) gives Σ x_i, and c_k = 3 - k gives Σ i·x_i. No lane passes 6·255 < 2^16, so
/// none carries into the next. Then Σ j·f_j = 2·Σ i·e_i + 2·Σ i·o_i + Σ o_i.
#[inline(always)]
pub(super) fn word_sums(w: u64) -> (u32, u32) {
    const LANES: u64 = 0x00FF_00FF_00FF_00FF;
    const ONES: u64 = 0x0001_0001_0001_0001;
    const RAMP: u64 = 0x0000_0001_0002_0003;
    let (even, odd) = (w & LANES, (w >> 8) & LANES);
    let top = |x: u64| (x >> 48) as u32;
    let (se, so) = (top(even.wrapping_mul(ONES)), top(odd.wrapping_mul(ONES)));
    let (ve, vo) = (top(even.wrapping_mul(RAMP)), top(odd.wrapping_mul(RAMP)));
    (se + so, 2 * ve + 2 * vo + so)
}

/// The codes of the low four bytes of `word`, one after the other, and their length
/// (at most 4 · 14 = 56 bits), from `packed` (each code in the low 16 bits of its
/// entry, its length above).
#[inline(always)]
pub(super) fn half(packed: &[u32; 256], word: u64) -> (u64, u32) {
    let (mut bits, mut count) = (0u64, 0u32);
    for i in 0..4 {
        let entry = packed[((word >> (8 * i)) & 0xff) as usize];
        bits |= u64::from(entry & 0xffff) << count;
        count += entry >> 16;
    }
    (bits, count)
}

/// A block's literal codes, made ahead of the word loop: word j's low half (bytes 0
/// to 3, each byte before its first nonzero one or after its last taking no bits) in
/// `bits[2j]` with its length in `counts[2j]`, its high half at `2j + 1`. Entries of
/// zero words are left as they were.
pub(super) struct Halves {
    bits: [u64; 2 * BLOCK],
    counts: [u64; 2 * BLOCK],
    /// Word j's Σ f_i in the low 32 bits of `sums[j]` and Σ i·f_i above, when made.
    sums: [u64; BLOCK],
}

impl Halves {
    /// Room for a block's halves when this processor can make them (AVX-512 with
    /// VBMI), `None` otherwise.
    pub(super) fn new() -> Option<Box<Halves>> {
        #[cfg(target_arch = "x86_64")]
        if avx512::available() {
            return Some(Box::new(Halves {
                bits: [0; 2 * BLOCK],
                counts: [0; 2 * BLOCK],
                sums: [0; BLOCK],
            }));
        }
        None
    }
}

/// Literal codes made ahead of the word loop, a block at a time (see [`Halves`]), and
/// with `SUMS` the words' sums for Adler-32 too.
pub(super) struct Vector<'a, const SUMS: bool> {
    codes: &'a Codes,
    halves: &'a mut Halves,
}

impl<'a, const SUMS: bool> Vector<'a, SUMS> {
    /// `halves` comes from [`Halves::new`], so the processor has what
    /// [`Literals::block`] needs.
    pub(super) fn new(codes: &'a Codes, halves: &'a mut Halves) -> Self {
        Vector { codes, halves }
    }
}

impl<const SUMS: bool> Literals for Vector<'_, SUMS> {
    #[inline(always)]
    fn block(&mut self, data: &[u8]) -> u64 {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: a `Halves` is only made when `avx512::available()`.
        unsafe {
            avx512::fill::<SUMS>(&self.codes.lanes, data, self.halves)
        }
        #[cfg(not(target_arch = "x86_64"))]
        unreachable!("no `Halves` is made without AVX-512: {data:?}");
    }

    #[inline(always)]
    fn word(&self, j: usize, _word: u64, _first: u32, _last: u32) -> (u128, u32) {
        let (low, high) = (self.halves.bits[2 * j], self.halves.bits[2 * j + 1]);
        let (low_count, high_count) = (self.halves.counts[2 * j], self.halves.counts[2 * j + 1]);
        // low | high << low_count as two words; low_count ≤ 56, and
        // `high >> 1 >> (63 - low_count)` is high >> (64 - low_count), also for 0.
        let first = low | high << low_count;
        let second = high >> 1 >> (63 - low_count);
        (
            u128::from(first) | u128::from(second) << 64,
            (low_count + high_count) as u32,
        )
    }

    #[inline(always)]
    fn sums(&self, j: usize, _word: u64) -> (u32, u32) {
        debug_assert!(SUMS, "sums are made with the codes only when asked for");
        let both = self.halves.sums[j];
        (both as u32, (both >> 32) as u32)
    }
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use std::arch::x86_64::*;

    use super::{Halves, BLOCK};

    /// Returns true when the processor has what [`fill`] uses (checked once, then
    /// cached by the standard library).
    pub(super) fn available() -> bool {
        is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512bw")
            && is_x86_feature_detected!("avx512vbmi")
    }

    /// A 256-entry byte table in four registers.
    type Table = [__m512i; 4];

    /// Loads a 256-entry byte table.
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn table(bytes: &[u8; 256]) -> Table {
        // SAFETY: each load reads 64 of the table's 256 bytes.
        std::array::from_fn(|k| unsafe { _mm512_loadu_si512(bytes[64 * k..].as_ptr().cast()) })
    }

    /// `table[v]` in every byte: bits 0 to 6 of the index choose among 128 bytes of a
    /// pair of registers, bit 7 which pair.
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn lookup(t: &Table, v: __m512i) -> __m512i {
        let low = _mm512_permutex2var_epi8(t[0], v, t[1]);
        let high = _mm512_permutex2var_epi8(t[2], v, t[3]);
        _mm512_mask_blend_epi8(_mm512_movepi8_mask(v), low, high)
    }

    /// Bits from the lowest set bit of each byte of `x` to its highest.
    #[inline]
    fn between(x: u64) -> u64 {
        let (mut up, mut down) = (x, x);
        for (shift, mask) in [(1, 0xfe), (2, 0xfc), (4, 0xf0)] {
            let mask = 0x0101_0101_0101_0101u64 * mask;
            up |= (up << shift) & mask;
            down |= (down >> shift) & (mask >> shift);
        }
        up & down
    }

    /// Each 64-bit lane's two 32-bit codes `c0` (low) and `c1` (high), with their
    /// lengths `l0` and `l1` in the same places of `lengths`, put together:
    /// c0 | c1 << l0 in the lane, and l0 + l1 in the lengths' lane. The same a level
    /// down, for 16-bit codes in 32-bit lanes, is [`pairs`].
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn fours(codes: __m512i, lengths: __m512i) -> (__m512i, __m512i) {
        let low = _mm512_set1_epi64(0xffff_ffff);
        let l0 = _mm512_and_si512(lengths, low);
        let c1 = _mm512_srli_epi64::<32>(codes);
        let bits = _mm512_or_si512(_mm512_and_si512(codes, low), _mm512_sllv_epi64(c1, l0));
        (bits, _mm512_add_epi64(l0, _mm512_srli_epi64::<32>(lengths)))
    }

    /// Each 32-bit lane's two 16-bit codes put together as [`fours`] does a level up.
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn pairs(codes: __m512i, lengths: __m512i) -> (__m512i, __m512i) {
        let low = _mm512_set1_epi32(0xffff);
        let l0 = _mm512_and_si512(lengths, low);
        let c1 = _mm512_srli_epi32::<16>(codes);
        let bits = _mm512_or_si512(_mm512_and_si512(codes, low), _mm512_sllv_epi32(c1, l0));
        // l0 + l1 in every 32-bit lane.
        (bits, _mm512_madd_epi16(lengths, _mm512_set1_epi16(1)))
    }

    /// Makes the halves of the nonzero words of a block, eight words at a time (see
    /// [`Halves`]), and returns the block's nonzero words as a mask. `lanes` holds the
    /// literal codes' low bytes, high bytes and lengths.
    ///
    /// # Safety
    /// The processor must have AVX-512 F, BW and VBMI ([`available`]).
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    pub(super) unsafe fn fill<const SUMS: bool>(
        lanes: &[[u8; 256]; 3],
        data: &[u8],
        out: &mut Halves,
    ) -> u64 {
        let words = data.len() / 8;
        debug_assert!(words <= BLOCK);
        let [code_low, code_high, length] = lanes.each_ref().map(|t| table(t));
        // The halves of words 0, 2, 4, 6 come out in one register and those of 1, 3,
        // 5, 7 in the other; these take them into order.
        let first = _mm512_setr_epi64(0, 1, 8, 9, 2, 3, 10, 11);
        let second = _mm512_setr_epi64(4, 5, 12, 13, 6, 7, 14, 15);
        let mut nonzero = 0u64;
        for chunk in 0..words.div_ceil(8) {
            let bytes = &data[64 * chunk..data.len().min(64 * chunk + 64)];
            // The chunk's bytes, zeros past the data's end (a short last chunk).
            let within = u64::MAX >> (64 - bytes.len());
            // SAFETY: a masked load reads only the bytes its mask selects, which lie in
            // `bytes`; the others are neither read nor able to fault.
            let v = unsafe { _mm512_maskz_loadu_epi8(within, bytes.as_ptr().cast()) };
            let busy = _mm512_test_epi64_mask(v, v);
            if busy == 0 {
                continue;
            }
            nonzero |= u64::from(busy) << (8 * chunk);
            if SUMS {
                // Σ f_i by sums of absolute differences from zero; Σ i·f_i by
                // multiplying bytes by their places 0..7 (at most 255 · 13 in a 16-bit
                // pair) and adding pairs, then the word's two halves.
                let sum = _mm512_sad_epu8(v, _mm512_setzero_si512());
                let places = _mm512_set1_epi64(0x0706_0504_0302_0100);
                let pairs = _mm512_maddubs_epi16(v, places);
                let fours = _mm512_madd_epi16(pairs, _mm512_set1_epi16(1));
                let weighted = _mm512_add_epi64(
                    _mm512_and_si512(fours, _mm512_set1_epi64(0xffff_ffff)),
                    _mm512_srli_epi64::<32>(fours),
                );
                let both = _mm512_or_si512(sum, _mm512_slli_epi64::<32>(weighted));
                // SAFETY: the store writes the chunk's 8 of the block's sums.
                unsafe {
                    _mm512_storeu_si512(
                        out.sums[8 * chunk..8 * chunk + 8].as_mut_ptr().cast(),
                        both,
                    )
                };
            }
            // Each byte's code and length; a byte outside its word's first..=last
            // nonzero byte is a zero, whose code is all zero bits, and takes no bits.
            let keep = between(_mm512_test_epi8_mask(v, v));
            let (low, high) = (lookup(&code_low, v), lookup(&code_high, v));
            let lengths = _mm512_maskz_mov_epi8(keep, lookup(&length, v));
            // 16-bit codes and lengths: the even words' bytes (the low half of each
            // 128-bit lane) in one register, the odd words' in the other.
            let zero = _mm512_setzero_si512();
            let even = pairs(
                _mm512_unpacklo_epi8(low, high),
                _mm512_unpacklo_epi8(lengths, zero),
            );
            let odd = pairs(
                _mm512_unpackhi_epi8(low, high),
                _mm512_unpackhi_epi8(lengths, zero),
            );
            let (even, odd) = (fours(even.0, even.1), fours(odd.0, odd.1));
            let at = 16 * chunk;
            let (bits, counts) = (&mut out.bits[at..at + 16], &mut out.counts[at..at + 16]);
            // SAFETY: each store writes 8 of the 16 words just taken from the arrays.
            unsafe {
                _mm512_storeu_si512(
                    bits.as_mut_ptr().cast(),
                    _mm512_permutex2var_epi64(even.0, first, odd.0),
                );
                _mm512_storeu_si512(
                    bits[8..].as_mut_ptr().cast(),
                    _mm512_permutex2var_epi64(even.0, second, odd.0),
                );
                _mm512_storeu_si512(
                    counts.as_mut_ptr().cast(),
                    _mm512_permutex2var_epi64(even.1, first, odd.1),
                );
                _mm512_storeu_si512(
                    counts[8..].as_mut_ptr().cast(),
                    _mm512_permutex2var_epi64(even.1, second, odd.1),
                );
            }
        }
        nonzero
    }
}
