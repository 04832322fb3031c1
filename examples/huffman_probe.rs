//! Fits the Huffman code of physframes' PNG coder (`render/fastpng/codes.rs`) to frames:
//! counts the symbols the coder writes for each PNG given (literal bytes of the Up-
//! filtered rows, and runs of zeros as a literal zero and matches at distance 1, by the
//! coder's own rule), weighs every frame alike, makes the code the same for a byte
//! and its negative (so that light marks on dark backgrounds fare as dark on light),
//! and prints the code lengths, limited to 14 bits, as the table `LENGTHS` of
//! `codes.rs`, with what each frame would take in bytes.
//!
//! ```sh
//! for s in scenes/*.toml scenes/bench/*.toml; do
//!   physframes figure "$s" --out "frames/$(basename "$s" .toml).png"
//! done
//! cargo run --release --example huffman_probe -- frames/*.png
//! ```

use std::path::Path;

/// Matches of lengths 3 to 258: the base length of each length code and its extra bits
/// (RFC 1951, 3.2.5).
const BASE: [usize; 29] = [
    3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131,
    163, 195, 227, 258,
];
const EXTRA: [u32; 29] = [
    0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
];

/// Literals 0 to 255, the end of the block (256) and the length codes 257 to 285.
const SYMBOLS: usize = 286;
const MAX_LENGTH: usize = 14;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    let mut frames = Vec::new();
    for path in &paths {
        let image = image::open(Path::new(path))?.to_rgba8();
        frames.push(count(image.as_raw(), 4 * image.width() as usize));
    }
    // Each frame weighs alike, whatever its size.
    let mut weight = [0f64; SYMBOLS];
    for (counts, _) in &frames {
        let total: u64 = counts.iter().sum();
        for (w, c) in weight.iter_mut().zip(counts) {
            *w += *c as f64 / total as f64;
        }
    }
    // A byte and its negative alike; every symbol possible.
    for b in 1..128 {
        let mean = (weight[b] + weight[256 - b]) / 2.0;
        (weight[b], weight[256 - b]) = (mean, mean);
    }
    let floor = weight.iter().sum::<f64>() * 1e-9;
    for w in &mut weight {
        *w += floor;
    }
    let lengths = package_merge(&weight, MAX_LENGTH);
    let kraft: f64 = lengths.iter().map(|&l| 0.5f64.powi(i32::from(l))).sum();
    assert!(
        (kraft - 1.0).abs() < 1e-12,
        "the code is not complete: {kraft}"
    );
    for (path, (counts, extra)) in paths.iter().zip(&frames) {
        let bits: u64 = counts
            .iter()
            .zip(&lengths)
            .map(|(c, l)| c * u64::from(*l))
            .sum::<u64>()
            + extra;
        println!("{path}: {} bytes of compressed data", bits.div_ceil(8));
    }
    println!("const LENGTHS: [u8; {SYMBOLS}] = {lengths:?};");
    Ok(())
}

/// The symbols the coder writes for an opaque RGBA image of rows `stride` bytes long,
/// and the extra bits of its matches (each with its one-bit distance code).
fn count(pixels: &[u8], stride: usize) -> ([u64; SYMBOLS], u64) {
    let mut counts = [0u64; SYMBOLS];
    let mut extra = 0u64;
    let mut flush = |run: &mut usize, counts: &mut [u64; SYMBOLS]| {
        if *run == 0 {
            return;
        }
        counts[0] += 1;
        let mut rest = *run - 1;
        *run = 0;
        while rest >= 3 {
            let length = rest.min(258);
            let k = BASE.iter().rposition(|b| *b <= length).unwrap_or(0);
            counts[257 + k] += 1;
            extra += u64::from(EXTRA[k]) + 1;
            rest -= BASE[k];
        }
        counts[0] += rest as u64;
    };
    let mut filtered = vec![0u8; stride];
    for (y, row) in pixels.chunks(stride).enumerate() {
        for (x, f) in filtered.iter_mut().enumerate() {
            *f = if y == 0 {
                row[x]
            } else {
                row[x].wrapping_sub(pixels[(y - 1) * stride + x])
            };
        }
        let mut run = 0;
        counts[2] += 1;
        // Word by word: the zeros before a word's first nonzero byte end the run, the
        // bytes from it to the last nonzero one are literals, the zeros after start
        // the next run; the bytes past the last whole word go one by one.
        let mut words = filtered.chunks_exact(8);
        for word in &mut words {
            let Some(first) = word.iter().position(|b| *b != 0) else {
                run += 8;
                continue;
            };
            let last = word.iter().rposition(|b| *b != 0).unwrap_or(first);
            run += first;
            flush(&mut run, &mut counts);
            for &b in &word[first..=last] {
                counts[usize::from(b)] += 1;
            }
            run = 7 - last;
        }
        for &b in words.remainder() {
            if b == 0 {
                run += 1;
            } else {
                flush(&mut run, &mut counts);
                counts[usize::from(b)] += 1;
            }
        }
        flush(&mut run, &mut counts);
    }
    counts[256] += 1;
    (counts, extra)
}

/// Code lengths of at most `limit` bits minimising Σ weight·length (the package-merge
/// algorithm of Larmore and Hirschberg).
fn package_merge(weight: &[f64], limit: usize) -> Vec<u8> {
    let n = weight.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|a, b| weight[*a].total_cmp(&weight[*b]));
    // A package: its weight and how often each symbol is in it.
    type Package = (f64, Vec<u8>);
    let leaves: Vec<Package> = order
        .iter()
        .map(|&s| {
            let mut members = vec![0u8; n];
            members[s] = 1;
            (weight[s], members)
        })
        .collect();
    let mut list = leaves.clone();
    for _ in 1..limit {
        let packages: Vec<Package> = list
            .chunks_exact(2)
            .map(|pair| {
                let members = pair[0]
                    .1
                    .iter()
                    .zip(&pair[1].1)
                    .map(|(a, b)| a + b)
                    .collect();
                (pair[0].0 + pair[1].0, members)
            })
            .collect();
        let mut merged = Vec::with_capacity(leaves.len() + packages.len());
        let (mut i, mut j) = (0, 0);
        while i < leaves.len() || j < packages.len() {
            if j == packages.len() || (i < leaves.len() && leaves[i].0 <= packages[j].0) {
                merged.push(leaves[i].clone());
                i += 1;
            } else {
                merged.push(packages[j].clone());
                j += 1;
            }
        }
        list = merged;
    }
    let mut lengths = vec![0u8; n];
    for (_, members) in &list[..2 * n - 2] {
        for (l, m) in lengths.iter_mut().zip(members) {
            *l += m;
        }
    }
    lengths
}
