//! The Huffman code of the DEFLATE block: code lengths fitted to physframes' frames by
//! `examples/huffman_probe.rs`, and the dynamic block header that carries them.
//!
//! Until the tenth session the code was read from the header of an empty `fdeflate`
//! stream, which `fdeflate` tunes for filtered PNG data in general. Fitted to the
//! symbols this coder writes for 33 frames of the example and bench scenes and the
//! figures (anti-aliased edges over plain backgrounds, trails, arrows, text and axes),
//! the same frames take 9% fewer bytes (busy frames 8 to 10%, frames of a few bodies
//! 15 to 28%), at the same speed.

use std::sync::OnceLock;

use super::*;

/// The code lengths of the literal/length alphabet: literal bytes 0 to 255, the end of
/// the block (256) and the length codes 257 to 285, at most 14 bits each (the word
/// loop writes four literals in one write of at most 56 bits). Fitted by
/// `cargo run --release --example huffman_probe -- FRAMES.png` (see its header for
/// the frames) with every frame weighed alike and a byte's code as long as its
/// negative's, so that light marks over dark backgrounds fare as dark ones over light.
pub(super) const LENGTHS: [u8; 286] = [
    2, 5, 7, 8, 8, 7, 8, 8, 7, 8, 7, 8, 8, 8, 8, 8, 8, 9, 8, 8, 8, 8, 9, 8, 8, 7, 8, 9, 9, 9, 9, 8,
    8, 9, 9, 9, 9, 9, 9, 9, 9, 9, 8, 10, 9, 9, 9, 8, 9, 10, 10, 8, 9, 10, 10, 10, 9, 9, 9, 10, 10,
    9, 9, 9, 9, 10, 10, 10, 11, 10, 10, 9, 9, 10, 10, 10, 10, 9, 10, 10, 10, 11, 10, 10, 9, 10, 11,
    9, 10, 10, 10, 11, 10, 11, 11, 10, 10, 10, 10, 10, 10, 10, 9, 8, 11, 11, 11, 11, 11, 10, 11,
    10, 9, 11, 11, 10, 10, 11, 11, 11, 11, 11, 11, 10, 11, 12, 11, 10, 9, 10, 10, 11, 11, 10, 11,
    11, 11, 11, 11, 11, 10, 10, 11, 11, 9, 10, 11, 10, 11, 11, 11, 11, 11, 8, 9, 10, 10, 10, 10,
    10, 10, 10, 11, 11, 10, 11, 10, 10, 10, 9, 11, 10, 9, 10, 10, 11, 10, 10, 10, 9, 10, 10, 10,
    10, 9, 9, 10, 10, 11, 10, 10, 10, 9, 9, 9, 9, 10, 10, 9, 9, 9, 10, 10, 10, 9, 8, 10, 10, 9, 8,
    9, 9, 9, 10, 8, 9, 9, 9, 9, 9, 9, 9, 9, 9, 8, 8, 9, 9, 9, 9, 8, 7, 8, 8, 9, 8, 8, 8, 8, 9, 8,
    8, 8, 8, 8, 8, 7, 8, 7, 8, 8, 7, 8, 8, 7, 5, 13, 9, 7, 8, 11, 10, 9, 9, 13, 9, 8, 9, 10, 9, 9,
    9, 10, 9, 10, 10, 10, 9, 10, 7, 9, 8, 9, 9, 10, 3,
];

/// The distance alphabet: distance 1 (runs of zeros) and one unused code, so that the
/// code is complete, as every decoder accepts.
pub(super) const DISTANCE_LENGTHS: [u8; 2] = [1, 1];

/// The Huffman code of the DEFLATE block, as bits ready to write least significant
/// first.
#[derive(Debug)]
pub(super) struct Codes {
    /// The block header (BFINAL, BTYPE and the code lengths): bytes and bit count.
    pub(super) header: Vec<u8>,
    pub(super) header_bits: usize,
    /// The zlib stream header (CMF, FLG).
    pub(super) zlib: [u8; 2],
    /// Literal bytes 0 to 255 and the end of block (256): (code, length).
    pub(super) literal: [(u64, u32); 257],
    /// Literal bytes 0 to 255 packed for the word loop of `Deflate::bytes`: the code
    /// in the low 16 bits and its length above them.
    pub(super) packed: [u32; 256],
    /// The length of the literal zero's code, whose bits are all zero.
    pub(super) zero_length: u32,
    /// The literal bytes' codes' low bytes, high bytes and lengths, as tables of bytes
    /// for `literals::Vector`.
    pub(super) lanes: [[u8; 256]; 3],
    /// A match of length 3 to 258 at distance 1, length code, extra bits and distance
    /// code together: (bits, count), indexed by length.
    pub(super) run: Vec<(u64, u32)>,
    /// A whole run of n zeros, as `Deflate::write_run` writes it, for every n below
    /// the length of this table: the shortest runs whose codes fit in 64 bits (about
    /// a thousand bytes), so that nearly every run is one lookup and one write.
    pub(super) zeros: Vec<(u64, u32)>,
}

/// Returns the Huffman code, built once per process.
pub(super) fn codes() -> &'static Codes {
    static CODES: OnceLock<Codes> = OnceLock::new();
    CODES.get_or_init(|| Codes::new(&LENGTHS, &DISTANCE_LENGTHS))
}

/// Length symbols 257..=285: base lengths and extra bits (RFC 1951, 3.2.5).
const BASE: [usize; 29] = [
    3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131,
    163, 195, 227, 258,
];
const EXTRA: [u32; 29] = [
    0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
];

/// The order in which the header gives the code-length alphabet's lengths.
pub(super) const ORDER: [usize; 19] = [
    16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15,
];

impl Codes {
    /// The code of these literal/length and distance code lengths (every literal and
    /// length symbol coded, literals in at most 14 bits, distance 1 the first
    /// distance symbol).
    fn new(lengths: &[u8; 286], distances: &[u8]) -> Codes {
        assert!(lengths.iter().all(|l| (1..=14).contains(l)));
        let (header, header_bits) = header(lengths, distances);
        let lit_codes = canonical(lengths);
        let dist_codes = canonical(distances);
        let reversed = |code: u16, length: u8| {
            (
                u64::from(code.reverse_bits() >> (16 - u32::from(length))),
                u32::from(length),
            )
        };
        let literal: [(u64, u32); 257] =
            std::array::from_fn(|s| reversed(lit_codes[s], lengths[s]));
        let distance_one = reversed(dist_codes[0], distances[0]);
        let mut run = vec![(0, 0); 259];
        for (length, entry) in run.iter_mut().enumerate().skip(3) {
            let k = BASE.iter().rposition(|b| *b <= length).unwrap_or(0);
            let (code, code_length) = reversed(lit_codes[257 + k], lengths[257 + k]);
            let extra = (length - BASE[k]) as u64;
            let bits = code | extra << code_length | distance_one.0 << (code_length + EXTRA[k]);
            *entry = (bits, code_length + EXTRA[k] + distance_one.1);
        }
        // The word loop leaves zero bytes' codes out of the bits and counts only their
        // lengths: the literal zero must be the first code of the shortest length.
        assert_eq!(literal[0].0, 0, "the literal zero's code is all zero bits");
        let packed: [u32; 256] = std::array::from_fn(|b| {
            let (code, length) = literal[b];
            code as u32 | length << 16
        });
        let mut codes = Codes {
            header,
            header_bits,
            // Deflate with a 32 KiB window, no dictionary, the fastest level; the
            // check bits make the 16-bit header a multiple of 31.
            zlib: [0x78, 0x01],
            literal,
            packed,
            zero_length: literal[0].1,
            lanes: [0, 8, 16].map(|shift| packed.map(|p: u32| (p >> shift) as u8)),
            run,
            zeros: Vec::new(),
        };
        codes.zeros = zero_runs(&codes);
        codes
    }
}

/// The dynamic block header of a last block with these code lengths (RFC 1951, 3.2.7):
/// BFINAL, BTYPE = 2, the counts of codes, then every length coded with a code-length
/// code that gives each of the lengths 0 to 15 four bits (a complete code; the run
/// symbols 16 to 18 are not used). Returns its bytes and its length in bits.
fn header(lengths: &[u8], distances: &[u8]) -> (Vec<u8>, usize) {
    let mut bits: Vec<bool> = Vec::new();
    let mut put = |value: u32, count: u32| {
        bits.extend((0..count).map(|i| value >> i & 1 == 1));
    };
    put(1, 1);
    put(2, 2);
    put(lengths.len() as u32 - 257, 5);
    put(distances.len() as u32 - 1, 5);
    put(19 - 4, 4);
    let mut cl_lengths = [4u8; 19];
    cl_lengths[16..].fill(0);
    for symbol in ORDER {
        put(u32::from(cl_lengths[symbol]), 3);
    }
    let cl_codes = canonical(&cl_lengths);
    for &l in lengths.iter().chain(distances) {
        // Huffman codes go most significant bit first.
        let code = u32::from(cl_codes[usize::from(l)]);
        let length = u32::from(cl_lengths[usize::from(l)]);
        put(code.reverse_bits() >> (32 - length), length);
    }
    let mut bytes = vec![0u8; bits.len().div_ceil(8)];
    for (i, _) in bits.iter().enumerate().filter(|(_, b)| **b) {
        bytes[i / 8] |= 1 << (i % 8);
    }
    (bytes, bits.len())
}

/// The bits of every run of zeros that `Deflate::write_run` writes in at most 64 bits,
/// indexed by the run's length, up to the first that takes more.
pub(super) fn zero_runs(codes: &Codes) -> Vec<(u64, u32)> {
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
pub(super) fn canonical(lengths: &[u8]) -> Vec<u16> {
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
