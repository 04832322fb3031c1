//! `--apng FILE`: the rendered frames as one lossless animated PNG.
//!
//! The frames are read back from the folder in order after the render, so the
//! animation holds exactly the pixels of the frame files, including frames kept by
//! `--resume`. One frame is held in memory at a time.

use std::io::{BufReader, BufWriter};
use std::ops::Range;
use std::path::Path;

use crate::error::{Error, Result};

use super::frame_file_name;

/// Writes frames `frames` of `dir` to `out` as an APNG that shows each for 1/fps
/// seconds and loops forever. The file is written atomically.
pub fn write_apng(dir: &Path, frames: Range<u64>, fps: f64, out: &Path) -> Result<()> {
    let count = u32::try_from(frames.end - frames.start)
        .map_err(|_| Error::Usage("--apng: too many frames for one APNG".into()))?;
    let (num, den) = frame_delay(fps);
    let tmp = super::Output::create(out)?;
    let encode_error =
        |e: png::EncodingError| Error::Runtime(format!("cannot encode the APNG: {e}"));
    {
        let mut writer: Option<png::Writer<BufWriter<&std::fs::File>>> = None;
        let mut pixels = Vec::new();
        for k in frames {
            let path = dir.join(frame_file_name(k));
            let (width, height) = read_rgba(&path, &mut pixels)?;
            if writer.is_none() {
                let mut encoder = png::Encoder::new(BufWriter::new(tmp.as_file()), width, height);
                encoder.set_color(png::ColorType::Rgba);
                encoder.set_depth(png::BitDepth::Eight);
                encoder.set_compression(png::Compression::Fast);
                encoder.set_animated(count, 0).map_err(encode_error)?;
                encoder.set_frame_delay(num, den).map_err(encode_error)?;
                encoder
                    .set_blend_op(png::BlendOp::Source)
                    .map_err(encode_error)?;
                encoder
                    .add_itxt_chunk(
                        "Software".into(),
                        format!("physframes {}", env!("CARGO_PKG_VERSION")),
                    )
                    .map_err(encode_error)?;
                writer = Some(encoder.write_header().map_err(encode_error)?);
            }
            if let Some(w) = writer.as_mut() {
                w.write_image_data(&pixels).map_err(encode_error)?;
            }
        }
        if let Some(w) = writer {
            w.finish().map_err(encode_error)?;
        }
    }
    tmp.finish()
        .map_err(|e| Error::io("cannot move the finished file to", out, e))?;
    Ok(())
}

/// Returns the delay of one frame, 1/fps seconds, as the numerator and denominator
/// APNG stores: exact for whole fps, and to 1/60000 s otherwise (exact for 29.97).
pub fn frame_delay(fps: f64) -> (u16, u16) {
    if fps.fract() == 0.0 && (1.0..=65535.0).contains(&fps) {
        return (1, fps as u16);
    }
    let num = (60000.0 / fps).round().clamp(1.0, 65535.0);
    (num as u16, 60000)
}

/// Decodes an 8-bit RGBA frame file into `pixels`; returns its size.
fn read_rgba(path: &Path, pixels: &mut Vec<u8>) -> Result<(u32, u32)> {
    let file = std::fs::File::open(path).map_err(|e| Error::io("cannot read", path, e))?;
    let bad = |why: String| Error::Runtime(format!("cannot read frame {}: {why}", path.display()));
    let mut reader = png::Decoder::new(BufReader::new(file))
        .read_info()
        .map_err(|e| bad(e.to_string()))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| bad("the image is too large".into()))?;
    pixels.resize(size, 0);
    let info = reader.next_frame(pixels).map_err(|e| bad(e.to_string()))?;
    if info.color_type != png::ColorType::Rgba || info.bit_depth != png::BitDepth::Eight {
        return Err(bad("not an 8-bit RGBA PNG written by physframes".into()));
    }
    pixels.truncate(info.buffer_size());
    Ok((info.width, info.height))
}

#[cfg(test)]
mod tests {
    use super::frame_delay;

    #[test]
    fn frame_delays_are_exact_for_common_rates() {
        assert_eq!(frame_delay(25.0), (1, 25));
        assert_eq!(frame_delay(30.0), (1, 30));
        assert_eq!(frame_delay(29.97), (2002, 60000));
        assert_eq!(frame_delay(0.5), (65535, 60000));
    }
}
