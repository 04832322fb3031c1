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
//! The compressed stream is one DEFLATE block with a Huffman code fitted to
//! physframes' frames (`codes.rs`): literals, and runs of zeros as matches at a
//! distance of one byte. So a frame is about 9% smaller than `--compression fastest`
//! makes it (which uses `fdeflate`'s code for filtered PNG data in general), in less
//! time on busy rows: the coder's loop does not branch on where nonzero bytes fall. The
//! pixels must be opaque (premultiplied and straight colour then agree); the caller
//! checks.
//! Compressing a dirty tile costs more than the same bytes cost inside a whole row, so
//! a frame with much damage (by a cost model fitted to measurements:
//! `StaticPng::tiles_pay`) is compressed row by row, every row whole. Either way the
//! bytes depend only on the frame, never on the worker, the frames before it, the
//! damage or the number of threads that compressed the static layer.
//!
//! The encoder lives in several files: `static_rows.rs` compresses the static layer's
//! rows into stand-alone tiles with prefix sums for Adler-32; `frame.rs` assembles a
//! frame's stream from copied stretches and freshly compressed dirty tiles, and holds
//! the cost model that decides between tiles and whole rows; `deflate.rs` is the bit
//! writer of the DEFLATE block; `codes.rs` holds the Huffman code and its header. This
//! file holds [`StaticPng`] and its entry points. `incremental.rs` holds
//! [`FrameCoder`], which encodes a frame against the last frame a worker encoded
//! instead of a static layer (frames with trails).

mod codes;
mod deflate;
mod frame;
mod incremental;
mod literals;
mod static_rows;

pub use frame::next_bit;
pub use incremental::FrameCoder;

use codes::{codes, Codes};
use deflate::{chunk, Deflate};
use static_rows::{compress_row, up_filter, Compressed, Sums};

use tiny_skia::Pixmap;

use super::damage::Damage;
use super::encode::Provenance;

/// Bytes per tile of a filtered row: 8 RGBA pixels.
pub(super) const TILE: usize = 32;

/// The Up filter's type byte at the start of every row.
pub(super) const UP: u8 = 2;

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

impl StaticPng {
    /// Compresses the tiles of a static layer, or returns `None` when its rows are too
    /// wide for 32-bit offsets (then callers use the `png` crate).
    pub fn new(layer: &Pixmap) -> Option<Self> {
        Self::with_threads(layer, 1)
    }

    /// Compresses the tiles of a static layer like [`StaticPng::new`], its rows
    /// shared among `threads` threads. Each row is compressed on its own and the rows
    /// are joined in order, so the result does not depend on the number of threads.
    pub fn with_threads(layer: &Pixmap, threads: usize) -> Option<Self> {
        let codes = codes();
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
    /// decides), reusing tiles saves little and compressing every row whole is
    /// quicker.
    pub fn encode(&self, frame: &Pixmap, provenance: &Provenance, out: &mut Vec<u8>) {
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
            self.encode_whole(frame, provenance, out);
            return;
        }
        self.encode_tiles(frame, provenance, out);
    }

    /// Encodes a frame drawn over this static layer, like [`StaticPng::encode`], given
    /// where it may differ from the static layer: the tiles outside the damage (and
    /// below none of it, since the Up filter reads the row above) are the static
    /// layer's, so their bits are copied without comparing any pixel. Whole damage
    /// falls back to [`StaticPng::encode`], and so does damage over so many tiles
    /// that compressing every row whole is quicker (`StaticPng::tiles_pay`).
    pub fn encode_damaged(
        &self,
        frame: &Pixmap,
        damage: &Damage,
        provenance: &Provenance,
        out: &mut Vec<u8>,
    ) {
        if damage.is_whole() {
            return self.encode(frame, provenance, out);
        }
        self.encode_damaged_with(frame, damage, provenance, out, false)
    }

    /// Encodes a frame like [`StaticPng::encode_damaged`], always compressing the
    /// damaged tiles and copying the others (whole damage: every tile compressed), for
    /// measuring that path against whole rows.
    pub fn encode_damaged_tiles(
        &self,
        frame: &Pixmap,
        damage: &Damage,
        provenance: &Provenance,
        out: &mut Vec<u8>,
    ) {
        self.encode_damaged_with(frame, damage, provenance, out, true)
    }
}

#[cfg(test)]
mod tests;
