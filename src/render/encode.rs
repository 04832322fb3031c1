//! PNG encoding with provenance: every file records what made it.

use std::str::FromStr;

use tiny_skia::Pixmap;

/// How hard the PNG encoder compresses. Every level is lossless.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Compression {
    /// The `png` crate's fastest mode: the Up filter and `fdeflate` over every frame.
    Fastest,
    /// The default. In a render whose frames are opaque, the same filter and code as
    /// `Fastest`, with the static layer compressed once and reused in every frame
    /// ([`super::fastpng`]): quicker when a static layer holds more than the
    /// background. Elsewhere, the `png` crate's fast mode (adaptive filtering).
    #[default]
    Fast,
    /// The smallest files (zlib level 9, adaptive filtering), at tens of times the
    /// encoding time.
    Best,
}

impl FromStr for Compression {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "fastest" => Ok(Compression::Fastest),
            "fast" => Ok(Compression::Fast),
            "best" => Ok(Compression::Best),
            _ => Err(format!(
                "unknown compression `{s}`; expected fastest, fast or best"
            )),
        }
    }
}

/// Text chunks written into every PNG: the scene, its hash, the integrator, dt, t and
/// the program version, so a frame can be traced back to what produced it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Provenance {
    pub entries: Vec<(String, String)>,
}

impl Provenance {
    /// Adds one keyword and its text.
    pub fn with(mut self, key: &str, value: impl ToString) -> Self {
        self.entries.push((key.to_string(), value.to_string()));
        self
    }
}

/// Encodes a pixmap as an 8-bit RGBA PNG with the given text chunks.
///
/// tiny-skia stores premultiplied colour; PNG wants straight colour. An opaque pixel is
/// the same in both, so the common case of an opaque image is written as it is.
pub fn encode_png(
    pixmap: &Pixmap,
    provenance: &Provenance,
    compression: Compression,
) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    encode_png_into(&mut out, pixmap, provenance, compression, false)?;
    Ok(out)
}

/// Encodes like [`encode_png`] into `out`, which is cleared first and keeps its
/// allocation, so that a worker encoding frame after frame allocates no output buffer.
/// `known_opaque` promises that every pixel is opaque (as when the frame was drawn over
/// an opaque static layer), which saves checking.
pub fn encode_png_into(
    out: &mut Vec<u8>,
    pixmap: &Pixmap,
    provenance: &Provenance,
    compression: Compression,
    known_opaque: bool,
) -> Result<(), png::EncodingError> {
    let data = pixmap.data();
    let opaque = known_opaque || data.chunks_exact(4).all(|p| p[3] == 255);
    debug_assert!(!known_opaque || data.chunks_exact(4).all(|p| p[3] == 255));
    let straight;
    let pixels: &[u8] = if opaque {
        data
    } else {
        straight = pixmap
            .pixels()
            .iter()
            .flat_map(|p| {
                let c = p.demultiply();
                [c.red(), c.green(), c.blue(), c.alpha()]
            })
            .collect::<Vec<u8>>();
        &straight
    };
    out.clear();
    out.reserve(data.len() / 8 + 1024);
    let mut encoder = png::Encoder::new(&mut *out, pixmap.width(), pixmap.height());
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(match compression {
        Compression::Fastest => png::Compression::Fastest,
        Compression::Fast => png::Compression::Fast,
        Compression::Best => png::Compression::High,
    });
    for (key, value) in &provenance.entries {
        encoder.add_itxt_chunk(key.clone(), value.clone())?;
    }
    let mut writer = encoder.write_header()?;
    writer.write_image_data(pixels)?;
    writer.finish()?;
    Ok(())
}
