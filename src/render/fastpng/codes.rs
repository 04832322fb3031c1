//! The Huffman code of the DEFLATE block, read once per process from the header of an
//! empty `fdeflate` stream, which tunes it for filtered PNG data.

use std::sync::OnceLock;

use super::*;

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
    /// in the low 16 bits and its length above them (at most 14 bits, checked when the
    /// code is read).
    pub(super) packed: [u32; 256],
    /// A match of length 3 to 258 at distance 1, length code, extra bits and distance
    /// code together: (bits, count), indexed by length.
    pub(super) run: Vec<(u64, u32)>,
    /// A whole run of n zeros, as `Deflate::write_run` writes it, for every n below
    /// the length of this table: the shortest runs whose codes fit in 64 bits (about
    /// a thousand bytes), so that nearly every run is one lookup and one write.
    pub(super) zeros: Vec<(u64, u32)>,
}

/// Returns the Huffman code, read once from the header of an empty `fdeflate` stream.
pub(super) fn codes() -> Option<&'static Codes> {
    static CODES: OnceLock<Option<Codes>> = OnceLock::new();
    CODES.get_or_init(read_codes).as_ref()
}

/// Reads the dynamic Huffman header of an empty `fdeflate` stream (RFC 1951, 3.2.7).
pub(super) fn read_codes() -> Option<Codes> {
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
    // The word loop writes four literals at a time in one write of at most 56 bits:
    // a code of the bytes longer than 14 bits (fdeflate's are at most 12) would not
    // fit, and the `png` crate is used instead.
    if literal[..256].iter().any(|&(_, length)| length > 14) {
        return None;
    }
    let packed = std::array::from_fn(|b| {
        let (code, length) = literal[b];
        code as u32 | length << 16
    });
    let mut codes = Codes {
        header,
        header_bits,
        zlib,
        literal,
        packed,
        run,
        zeros: Vec::new(),
    };
    codes.zeros = zero_runs(&codes);
    Some(codes)
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

/// Reads bits least significant first.
pub(super) struct BitReader<'a> {
    pub(super) data: &'a [u8],
    pub(super) pos: usize,
}

impl BitReader<'_> {
    pub(super) fn bits(&mut self, count: u32) -> Option<u32> {
        let mut value = 0;
        for i in 0..count {
            let byte = *self.data.get(self.pos / 8)?;
            value |= u32::from((byte >> (self.pos % 8)) & 1) << i;
            self.pos += 1;
        }
        Some(value)
    }

    /// Reads one Huffman-coded symbol, most significant code bit first.
    pub(super) fn symbol(&mut self, lengths: &[u8], codes: &[u16]) -> Option<usize> {
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
