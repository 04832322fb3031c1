//! Times physframes' own DEFLATE coder against `fdeflate` on whole frames: each PNG
//! given is decoded, then encoded over and over both ways on one thread.
//!
//! ```sh
//! cargo run --release --example coder_probe -- output/figures/arrows-1000.png
//! ```
//!
//! For each frame it prints the best and median milliseconds of physframes' coder over
//! whole rows (`StaticPng::encode_damaged_tiles` with whole damage over a white static
//! layer) and of `fdeflate` (`--compression fastest`), and both PNGs' sizes, over
//! `RUNS` encodings (200 unless the environment variable says otherwise).

use std::time::Instant;

use physframes::render::fastpng::StaticPng;
use physframes::render::{encode_png_into, Compression, Damage, Provenance};
use tiny_skia::Pixmap;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let runs: usize = std::env::var("RUNS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(200);
    for path in std::env::args().skip(1) {
        let frame = decode(&std::fs::read(&path)?)?;
        let mut white = Pixmap::new(frame.width(), frame.height()).ok_or("empty frame")?;
        white.fill(tiny_skia::Color::WHITE);
        let coder = StaticPng::new(&white).ok_or("no fdeflate code")?;
        let none = Provenance::default();
        let time = |f: &mut dyn FnMut(&mut Vec<u8>)| {
            let mut out = Vec::new();
            let mut t: Vec<f64> = (0..runs)
                .map(|_| {
                    let start = Instant::now();
                    f(&mut out);
                    start.elapsed().as_secs_f64() * 1e3
                })
                .collect();
            t.sort_by(f64::total_cmp);
            (t[0], t[runs / 2], out)
        };
        let whole = Damage::whole();
        let ours = time(&mut |out| coder.encode_damaged_tiles(&frame, &whole, &none, out));
        let check = decode(&ours.2)?;
        assert!(
            check.data() == frame.data(),
            "{path}: our PNG decodes to other pixels"
        );
        let theirs = time(&mut |out| {
            encode_png_into(out, &frame, &none, Compression::Fastest, true).expect("encodes")
        });
        println!(
            "{path}: ours {:.3} / {:.3} ms ({} B), fdeflate {:.3} / {:.3} ms ({} B)",
            ours.0,
            ours.1,
            ours.2.len(),
            theirs.0,
            theirs.1,
            theirs.2.len()
        );
    }
    Ok(())
}

/// Decodes an opaque PNG into a pixmap (premultiplied and straight colour agree).
fn decode(png: &[u8]) -> Result<Pixmap, Box<dyn std::error::Error>> {
    let image = image::load_from_memory(png)?.to_rgba8();
    let size = tiny_skia::IntSize::from_wh(image.width(), image.height()).ok_or("empty")?;
    Ok(Pixmap::from_vec(image.into_raw(), size).ok_or("bad size")?)
}
