use super::codes::canonical;
use super::*;
use crate::render::encode::{encode_png_into, Compression};
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
    one.encode_damaged_tiles(&frame, &damage, &Provenance::default(), &mut expected);
    for threads in [2, 3, 7, 200] {
        let many = StaticPng::with_threads(&layer, threads).expect("readable");
        assert_eq!(many.layer.pool, one.layer.pool, "{threads} threads");
        let mut out = Vec::new();
        many.encode_damaged_tiles(&frame, &damage, &Provenance::default(), &mut out);
        assert_eq!(out, expected, "{threads} threads");
    }
}

#[test]
fn a_frame_is_the_same_bytes_whatever_its_damage() {
    // Tiles copied from the static layer, tiles compressed afresh and rows compressed
    // whole all give a row's bits as the row compressed whole would: the PNG is a
    // function of the pixels, however the encoder chose to get it.
    let layer = grey_discs(203, 61);
    let encoder = StaticPng::new(&layer).expect("readable");
    for k in [0, 1, 3] {
        let (frame, damage) = frame_with_discs(&layer, k);
        let none = Provenance::default();
        let (mut tiles, mut whole, mut chosen) = (Vec::new(), Vec::new(), Vec::new());
        encoder.encode_damaged_tiles(&frame, &damage, &none, &mut tiles);
        encoder.encode_damaged_tiles(&frame, &Damage::whole(), &none, &mut whole);
        encoder.encode(&frame, &none, &mut chosen);
        assert!(tiles == whole, "{k} discs: tiles and whole rows differ");
        assert!(chosen == whole, "{k} discs: the encoder's choice differs");
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
        encoder.encode_damaged_tiles(&frame, &damage, &Provenance::default(), &mut tiles);
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

#[test]
fn frames_encoded_against_the_frame_before_are_the_bits_of_a_fresh_encoding() {
    // Discs that move from frame to frame over a layer with detail, on an odd width (a
    // short tile ends every row): a coder that copies the unmarked tiles from the last
    // frame it encoded gives, bit for bit, what a fresh coder gives, whatever frames it
    // encoded before; marking a tile that did not change costs nothing in bits.
    use crate::render::damage::TileMask;
    let (width, height) = (203, 61);
    let layer = grey_discs(width, height);
    let provenance = Provenance::default().with("physframes:frame", 3);
    let mut coder = FrameCoder::new(width, height).expect("readable");
    let mut last: Option<Damage> = None;
    for (i, k) in [0, 1, 2, 5, 6, 3, 8, 8, 0, 7].into_iter().enumerate() {
        let (frame, damage) = frame_with_discs(&layer, k);
        let mut changed = TileMask::new(width, height);
        changed.clear();
        changed.add_damage(&damage);
        match &last {
            Some(before) => changed.add_damage(before),
            None => changed.set_whole(),
        }
        // A frame marked changed everywhere midway (compressed whole, its tiles not
        // recorded): the frame after it must record them afresh.
        if i == 5 {
            changed.set_whole();
        }
        // A spare tile marked where nothing changed.
        changed.add_rect(crate::render::PixelRect {
            x0: 150,
            y0: 3,
            x1: 151,
            y1: 4,
        });
        let ours = coder.encode(&frame, &changed, &provenance).to_vec();
        let fresh = FrameCoder::new(width, height)
            .expect("readable")
            .encode(&frame, &TileMask::new(width, height), &provenance)
            .to_vec();
        assert!(ours == fresh, "frame with {k} discs: the bits differ");
        let (pixels, text) = decode(&ours);
        assert_eq!(pixels, frame.data(), "frame with {k} discs");
        assert_eq!(
            text,
            vec![("physframes:frame".to_string(), "3".to_string())]
        );
        check_adler(&ours, frame.data(), 4 * width as usize);
        last = Some(damage);
    }
}

#[test]
fn a_row_compressed_tile_by_tile_is_the_row_compressed_whole() {
    // The frame coder's promise rests on this: Deflate::bytes over a row's aligned
    // tiles, one after the other, writes the bits it writes over the whole row.
    let codes = codes();
    let mut row = vec![0u8; 4 * 203];
    for (i, b) in row.iter_mut().enumerate() {
        // Runs of zeros of every length, single zeros inside words, and words
        // without zeros.
        *b = match (i * 7919) % 23 {
            0..=9 => 0,
            10..=12 => (i % 5) as u8,
            _ => (i % 251) as u8,
        };
    }
    let mut whole = Deflate::new(codes, Vec::new());
    whole.bytes(&row);
    whole.flush_run();
    let mut tiled = Deflate::new(codes, Vec::new());
    for tile in row.chunks(TILE) {
        tiled.bytes_marked::<true>(tile);
    }
    tiled.flush_run();
    assert_eq!(whole.into_bits(), tiled.into_bits());
}

#[test]
fn bit_ranges_are_copied_bit_for_bit_from_any_offset_to_any_offset() {
    // Long ranges take the word-at-a-time path, short ones the 56-bit one; both must
    // append exactly the bits asked for, after any number of bits pending, from every
    // offset within a byte, up to the last bit the source holds eight bytes past (as
    // it must).
    let codes = codes();
    let source: Vec<u8> = (0..400u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let bit = |bytes: &[u8], i: usize| bytes[i / 8] >> (i % 8) & 1;
    for pending in [0u32, 1, 2, 3, 4, 6, 7, 8, 13, 63] {
        for (from, to) in [
            (0, 3000),
            (5, 2900),
            (37, 3136),
            (1, 3135),
            (13, 530),
            (8, 1032),
            (3, 40),
            (100, 100),
        ] {
            let mut w = Deflate::new(codes, Vec::new());
            w.put((1 << pending) - 1, pending);
            w.put_bit_range(&source, from, to);
            let (out, bits) = w.into_bits();
            assert_eq!(bits, pending as usize + to - from);
            for i in 0..bits {
                let expected = if i < pending as usize {
                    1
                } else {
                    bit(&source, from + i - pending as usize)
                };
                assert_eq!(
                    bit(&out, i),
                    expected,
                    "bit {i} of {from}..{to} after {pending}"
                );
            }
        }
    }
}

/// What `Deflate::bytes_marked` writes, by its definition, word by word: a zero word
/// lengthens the run; otherwise the zeros before its first nonzero byte end the run,
/// the bytes from that one to its last nonzero byte are literals, and the zeros after
/// start the next run. Bytes past the last whole word go one by one.
fn bytes_by_definition(w: &mut Deflate<'_>, data: &[u8]) -> usize {
    let mut mark = usize::MAX;
    let mut chunks = data.chunks_exact(8);
    for chunk in &mut chunks {
        let Some(first) = chunk.iter().position(|b| *b != 0) else {
            w.run += 8;
            continue;
        };
        let last = chunk.iter().rposition(|b| *b != 0).unwrap_or(first);
        w.run += first;
        w.flush_run();
        mark = mark.min(w.bit_position());
        for &b in &chunk[first..=last] {
            w.literal(usize::from(b));
        }
        w.run = 7 - last;
    }
    for &b in chunks.remainder() {
        if b == 0 {
            w.run += 1;
        } else {
            w.flush_run();
            mark = mark.min(w.bit_position());
            w.literal(usize::from(b));
        }
    }
    mark
}

/// A xorshift generator from `seed` (not zero): each call gives a number below `n`.
fn xorshift(mut state: u64) -> impl FnMut(u64) -> u64 {
    move |n| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    }
}

#[test]
fn the_word_loop_writes_the_bits_of_its_definition() {
    // Busy stretches like anti-aliased edges (a zero alpha byte in every pixel),
    // words without zeros, single zeros, runs of zeros of every length up to past
    // the longest run one write takes (inside and across blocks of 64 words), and
    // slices of every length and alignment, after any run and bits pending.
    let codes = codes();
    let mut random = xorshift(0x2545_f491_4f6c_dd1d);
    for case in 0..400 {
        let len = random(3000) as usize;
        let mut data = Vec::with_capacity(len);
        while data.len() < len {
            match random(5) {
                0 => data.extend(std::iter::repeat_n(0, random(2500) as usize)),
                1 => data.extend(std::iter::repeat_n(0, random(12) as usize)),
                2 => {
                    for _ in 0..random(40) {
                        let rgb = [random(256), random(256), random(256)];
                        data.extend(rgb.map(|v| v as u8));
                        data.push(0);
                    }
                }
                _ => data.extend((0..random(30)).map(|_| random(256) as u8)),
            }
        }
        data.truncate(len);
        let (pending, run) = (random(8) as u32, random(300) as usize);
        let start = |w: &mut Deflate<'_>| {
            w.put((1 << pending) - 1, pending);
            w.run = run;
        };
        let mut reference = Deflate::new(codes, vec![0x5a; case % 13]);
        start(&mut reference);
        let expected_mark = bytes_by_definition(&mut reference, &data);
        let expected_run = reference.run;
        reference.flush_run();
        let expected = reference.into_bits();
        // Literal codes made ahead a block at a time (where the processor can), and
        // looked up word by word.
        for mut quick in [
            Deflate::new(codes, vec![0x5a; case % 13]),
            Deflate::new(codes, vec![0x5a; case % 13]).scalar(),
        ] {
            let way = if quick.is_vector() {
                "ahead"
            } else {
                "word by word"
            };
            start(&mut quick);
            let mark = quick.bytes_marked::<true>(&data);
            assert_eq!(
                mark, expected_mark,
                "case {case}, {way}: where the literals start"
            );
            assert_eq!(quick.run, expected_run, "case {case}, {way}: the run left");
            quick.flush_run();
            assert_eq!(quick.into_bits(), expected, "case {case}, {way}");
        }
    }
}

#[test]
fn a_words_one_write_is_its_bits_one_by_one() {
    // Every number of pending bits, run codes of 0 to 56 bits and literals of 0 to
    // 112, so that together they take from 0 bits to past 128 (the two-write path),
    // 127 and 128 among them.
    let codes = codes();
    let mut random = xorshift(0x1234_5678_9abc_def1);
    let mut bits_of = |count: u32| -> u128 {
        let value = u128::from(random(u64::MAX)) | u128::from(random(u64::MAX)) << 64;
        if count == 0 {
            0
        } else {
            value >> (128 - count)
        }
    };
    for pending in 0..8u32 {
        for run_count in [0, 1, 7, 8, 20, 33, 55, 56] {
            for count in (0..=112).step_by(1) {
                let run_bits = bits_of(run_count) as u64;
                let literals = bits_of(count);
                let mut quick = Deflate::new(codes, vec![0xa5; 3]);
                let mut reference = Deflate::new(codes, vec![0xa5; 3]);
                for w in [&mut quick, &mut reference] {
                    w.put((1 << pending) - 1, pending);
                }
                quick.word(run_bits, run_count, literals, count);
                reference.put(run_bits, run_count);
                for i in 0..count {
                    reference.put((literals >> i) as u64 & 1, 1);
                }
                let what = format!("{pending} pending, run of {run_count} bits, {count} bits");
                assert_eq!(quick.bit_position(), reference.bit_position(), "{what}");
                quick.put(1, 1);
                reference.put(1, 1);
                assert_eq!(quick.into_bits(), reference.into_bits(), "{what}");
            }
        }
    }
}

#[test]
fn literal_codes_are_made_ahead_wherever_the_processor_can() {
    // The word loop's test above compares the two ways only where both exist: on a
    // processor with AVX-512 VBMI (x86-64 v4 and Zen 4 on), the writer must use it.
    #[cfg(target_arch = "x86_64")]
    {
        let can = is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512bw")
            && is_x86_feature_detected!("avx512vbmi");
        assert_eq!(Deflate::new(codes(), Vec::new()).is_vector(), can);
    }
    assert!(!Deflate::new(codes(), Vec::new()).scalar().is_vector());
}

#[test]
fn tiles_in_one_stretch_are_the_tiles_one_by_one() {
    // The frame coder compresses a run of dirty tiles in one call: the bits, the run
    // left pending and each nonzero tile's start and end must be those of compressing
    // the tiles one call each, after any run (also one too long for a single write,
    // as after a clean span of zeros) and bits pending.
    let codes = codes();
    let mut random = xorshift(0x9e37_79b9_7f4a_7c15);
    for case in 0..400 {
        let tiles = 1 + random(40) as usize;
        let mut data = vec![0u8; tiles * TILE];
        for tile in data.chunks_exact_mut(TILE) {
            match random(4) {
                0 => {}
                1 => tile[random(TILE as u64) as usize] = 1 + random(255) as u8,
                2 => {
                    // An anti-aliased edge: RGB with a zero alpha byte.
                    for (i, b) in tile.iter_mut().enumerate() {
                        *b = if i % 4 == 3 { 0 } else { random(256) as u8 };
                    }
                }
                _ => {
                    for b in tile.iter_mut() {
                        *b = if random(3) == 0 { 0 } else { random(256) as u8 };
                    }
                }
            }
        }
        let pending = random(8) as u32;
        let run = [random(40), random(300), 2000 + random(8000)][case % 3] as usize;
        // Literal codes made ahead a block at a time (where the processor can), and
        // looked up word by word; the reference looks them up word by word.
        let quick = Deflate::new(codes, vec![0x5a; case % 13]);
        let scalar = Deflate::new(codes, vec![0x5a; case % 13]).scalar();
        for mut quick in [quick, scalar] {
            let mut reference = Deflate::new(codes, vec![0x5a; case % 13]).scalar();
            for w in [&mut quick, &mut reference] {
                w.put((1 << pending) - 1, pending);
                w.run = run;
            }
            let mut marks = Vec::new();
            quick.bytes_tiles(&data, |k, words, sums, start, end| {
                let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                assert_eq!(
                    bytes,
                    data[k * TILE..(k + 1) * TILE],
                    "case {case}, tile {k}"
                );
                // Each word's sums, byte by byte.
                let expected: [(u32, u32); 4] = std::array::from_fn(|w| {
                    let word = &bytes[8 * w..8 * w + 8];
                    let s = word.iter().map(|&x| u32::from(x)).sum();
                    let v = (0..8).map(|i| i as u32 * u32::from(word[i])).sum();
                    (s, v)
                });
                assert_eq!(sums, expected, "case {case}, tile {k}: sums");
                marks.push((k, start, end));
            });
            let mut expected = Vec::new();
            for (k, tile) in data.chunks_exact(TILE).enumerate() {
                let start = reference.bytes_marked::<true>(tile);
                if start != usize::MAX {
                    expected.push((k, start, reference.bit_position()));
                }
            }
            assert_eq!(marks, expected, "case {case}: the tiles' marks");
            assert_eq!(quick.run, reference.run, "case {case}: the run left");
            quick.flush_run();
            reference.flush_run();
            assert_eq!(quick.into_bits(), reference.into_bits(), "case {case}");
        }
    }
}

/// Reads bits least significant first.
struct BitReader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl BitReader<'_> {
    fn bits(&mut self, count: u32) -> u32 {
        let mut value = 0;
        for i in 0..count {
            let byte = self.data[self.pos / 8];
            value |= u32::from((byte >> (self.pos % 8)) & 1) << i;
            self.pos += 1;
        }
        value
    }

    /// Reads one Huffman-coded symbol, most significant code bit first.
    fn symbol(&mut self, lengths: &[u8], codes: &[u16]) -> usize {
        let mut code = 0u16;
        for length in 1..=15u8 {
            code = code << 1 | self.bits(1) as u16;
            if let Some(s) = (0..lengths.len()).find(|&s| lengths[s] == length && codes[s] == code)
            {
                return s;
            }
        }
        panic!("no symbol at bit {}", self.pos);
    }
}

#[test]
fn the_block_header_reads_back_as_the_fitted_code_lengths() {
    // Read as RFC 1951 (3.2.7) says a decoder reads it: the header is a last block of
    // dynamic codes whose lengths are the fitted ones, and it ends where it says.
    let codes = codes();
    let mut r = BitReader {
        data: &codes.header,
        pos: 0,
    };
    assert_eq!((r.bits(1), r.bits(2)), (1, 2), "BFINAL and BTYPE");
    let hlit = r.bits(5) as usize + 257;
    let hdist = r.bits(5) as usize + 1;
    let hclen = r.bits(4) as usize + 4;
    let mut cl_lengths = [0u8; 19];
    for &symbol in super::codes::ORDER.iter().take(hclen) {
        cl_lengths[symbol] = r.bits(3) as u8;
    }
    let cl_codes = canonical(&cl_lengths);
    let lengths: Vec<u8> = (0..hlit + hdist)
        .map(|_| r.symbol(&cl_lengths, &cl_codes) as u8)
        .collect();
    assert_eq!(&lengths[..hlit], &super::codes::LENGTHS[..]);
    assert_eq!(&lengths[hlit..], &super::codes::DISTANCE_LENGTHS[..]);
    assert_eq!(r.pos, codes.header_bits);
    // Both codes are complete (Kraft's sum is 1), as strict decoders demand.
    for l in [
        &super::codes::LENGTHS[..],
        &super::codes::DISTANCE_LENGTHS[..],
    ] {
        let kraft: f64 = l.iter().map(|&b| 0.5f64.powi(i32::from(b))).sum();
        assert_eq!(kraft, 1.0);
    }
    // The zlib header's check bits.
    assert_eq!(u16::from_be_bytes(codes.zlib) % 31, 0);
}
