//! Ramps against their definition: AVX2 against pixel by pixel, exact areas along the
//! rows, and the stated bound along a slanted side.

use super::*;
use tiny_skia::Color;

/// A pixmap `w` × `h` of one colour.
fn canvas(w: u32, h: u32) -> Pixmap {
    let mut p = Pixmap::new(w, h).expect("pixmap");
    p.fill(Color::from_rgba8(250, 248, 240, 255));
    p
}

/// A small deterministic generator (Park–Miller), in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0 * 48_271 % 0x7fff_ffff;
        self.0 as f64 / f64::from(0x7fff_ffffu32)
    }
}

#[test]
fn registers_and_pixels_give_the_same_bytes() {
    // Shafts and heads of every direction, size and place, inside the image and
    // across each of its edges, in opaque and translucent inks, over pixels
    // already drawn: AVX2 and pixel by pixel leave the same bytes. (On a
    // processor without AVX2, the paths are one and the test says nothing.)
    let inks = [
        Ink::of(Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff)),
        Ink::of(Color::from_rgba8(0xc0, 0x39, 0x2b, 0x99)),
    ];
    let mut rng = Rng(7);
    for (w, h) in [(97u32, 61u32), (8, 40), (200, 9), (7, 30)] {
        let mut canvases = [canvas(w, h), canvas(w, h)];
        let paths = [Path::Avx2, Path::Pixels];
        for k in 0..900 {
            let ink = inks[k % 2];
            let at = (
                rng.next() * f64::from(w + 20) - 10.0,
                rng.next() * f64::from(h + 20) - 10.0,
            );
            let a = rng.next() * std::f64::consts::TAU;
            let len = 0.3 + rng.next() * [4.0, 30.0, 150.0][k % 3];
            let (u, v) = (a.cos(), a.sin());
            let end = (at.0 + len * u, at.1 + len * v);
            let half = 0.3 + rng.next() * 2.0;
            for (canvas, path) in canvases.iter_mut().zip(paths) {
                if k % 2 == 0 {
                    if let Some(r) = Ramps::shaft(at, end, half) {
                        fill_with(canvas, &r, ink, path);
                    }
                } else if let Some(r) = Ramps::head(end, (u, v), len.min(14.0)) {
                    fill_with(canvas, &r, ink, path);
                }
            }
        }
        let [avx2, pixels] = &canvases;
        assert!(avx2.data() == pixels.data(), "{w} × {h}");
    }
}

#[test]
fn a_rectangle_along_the_rows_covers_each_pixel_by_its_area() {
    // A shaft along a row or a column is a rectangle of pixels' exact areas: each
    // ramp is the overlap of a pixel with the slab along one axis, and their
    // product the overlap's area. White ink over black leaves 255 × area, rounded,
    // in every channel. The corners are chosen so that no 255 × area falls within
    // 0.01 of a half (f32's error in the ramps is far below that).
    for (a, b, half) in [
        ((2.27, 4.61), (11.83, 4.61), 1.19),
        ((5.7, 1.13), (5.7, 9.35), 0.9),
        ((11.77, 6.45), (2.21, 6.45), 2.07),
    ] {
        let mut p = Pixmap::new(16, 12).expect("pixmap");
        p.fill(Color::BLACK);
        let r = Ramps::shaft(a, b, half).expect("a shaft");
        fill_ramps(&mut p, &r, Ink::of(Color::WHITE));
        let (x0, x1) = (a.0.min(b.0), a.0.max(b.0));
        let (y0, y1) = (a.1.min(b.1), a.1.max(b.1));
        let (x0, x1, y0, y1) = if a.1 == b.1 {
            (x0, x1, y0 - half, y1 + half)
        } else {
            (x0 - half, x1 + half, y0, y1)
        };
        for y in 0..12 {
            for x in 0..16 {
                let over = |p: f64, lo: f64, hi: f64| (hi.min(p + 1.0) - lo.max(p)).max(0.0);
                let area = over(f64::from(x), x0, x1) * over(f64::from(y), y0, y1);
                let want = (255.0 * area).round();
                assert!(
                    ((255.0 * area).fract() - 0.5).abs() > 0.01,
                    "({x}, {y}) too near a half"
                );
                let got = p.data()[4 * (y * 16 + x) as usize];
                assert_eq!(f64::from(got), want, "pixel ({x}, {y}) of {a:?}..{b:?}");
            }
        }
    }
}

#[test]
fn a_slanted_side_is_within_its_stated_bound_of_the_exact_area() {
    // A side at an angle θ: the exact area of a pixel inside it is a trapezoid's
    // integral in the distance d of the pixel's centre, the ramp clamp(d + 1/2, 0,
    // 1) its straight-line stand-in; they differ most at 45°, by (√2/2 - 1/2)^2 =
    // 0.0429 of a pixel. Here a long shaft at many angles, its far side inside
    // the image only: each pixel far from the shaft's ends is compared with its
    // exact area inside the near side (computed by cutting the pixel's square,
    // in f64), within 0.0429 and a level's rounding.
    for step in 0..24 {
        let angle = 0.05 + f64::from(step) * std::f64::consts::FRAC_PI_2 / 24.0;
        let (u, v) = (angle.cos(), angle.sin());
        let mut p = Pixmap::new(64, 64).expect("pixmap");
        p.fill(Color::BLACK);
        // Half-width 200 about a line through (32, 32) + 200·n: the near side
        // passes through (32, 32), along (u, v), the inside towards +n.
        let n = (-v, u);
        let c = (32.0 + 200.0 * n.0, 32.0 + 200.0 * n.1);
        let a = (c.0 - 400.0 * u, c.1 - 400.0 * v);
        let b = (c.0 + 400.0 * u, c.1 + 400.0 * v);
        let r = Ramps::shaft(a, b, 200.0).expect("a shaft");
        fill_ramps(&mut p, &r, Ink::of(Color::WHITE));
        for y in 0..64 {
            for x in 0..64 {
                let exact = area_inside((f64::from(x), f64::from(y)), (32.0, 32.0), n);
                let got = f64::from(p.data()[4 * (y * 64 + x) as usize]) / 255.0;
                assert!(
                    (got - exact).abs() <= 0.0429 + 0.5 / 255.0 + 1e-6,
                    "angle {angle}: pixel ({x}, {y}) {got} against {exact}"
                );
            }
        }
    }
}

/// The area of the unit pixel with top-left corner `p` on the side n·(q - o) >= 0
/// of the line through `o` with unit normal `n`: the pixel's square cut by the
/// line (Sutherland–Hodgman), then the shoelace formula.
fn area_inside(p: (f64, f64), o: (f64, f64), n: (f64, f64)) -> f64 {
    let square = [
        (p.0, p.1),
        (p.0 + 1.0, p.1),
        (p.0 + 1.0, p.1 + 1.0),
        (p.0, p.1 + 1.0),
    ];
    let side = |q: (f64, f64)| n.0 * (q.0 - o.0) + n.1 * (q.1 - o.1);
    let mut cut = Vec::new();
    for i in 0..4 {
        let (a, b) = (square[i], square[(i + 1) % 4]);
        let (sa, sb) = (side(a), side(b));
        if sa >= 0.0 {
            cut.push(a);
        }
        if (sa >= 0.0) != (sb >= 0.0) {
            let t = sa / (sa - sb);
            cut.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    let m = cut.len();
    (0..m)
        .map(|i| {
            let (a, b) = (cut[i], cut[(i + 1) % m]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum::<f64>()
        .abs()
        / 2.0
}
