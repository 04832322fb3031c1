//! Renders sample charts to PNG files, to look at and to time the renderer.
//!
//! Usage: `cargo run --example plot_demo [OUTPUT_DIR]` (default: the system temp folder).

use std::path::PathBuf;
use std::time::Instant;

use physframes::render::plot::{
    palette, ArrowStyle, Axis, Chart, ChartSpec, Corner, Dash, LegendEntry, LineStyle, MarkerShape,
    MarkerStyle,
};
use tiny_skia::Color;

fn main() -> anyhow::Result<()> {
    let dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(std::env::temp_dir);
    std::fs::create_dir_all(&dir)?;

    // Figure 2: the slope field of dy/dx = 2x and the parabola y = x² through it.
    let field = LineStyle::solid(Color::from_rgba8(0x55, 0x55, 0x55, 255), 1.2);
    let curve = LineStyle::solid(palette(0), 1.5);
    let shifted = LineStyle::solid(palette(1), 1.5).dashed(Dash::Dashed);
    let spec = ChartSpec::new(Axis::linear(-2.0, 2.0, "x"), Axis::linear(-1.0, 4.0, "y"))
        .title("Slope field of dy/dx = 2x")
        .legend_entry(LegendEntry::line(curve, "y = x²"))
        .legend_entry(LegendEntry::line(shifted, "y = x² − 1"));
    let chart = Chart::new(spec, 800, 600)?;
    let background = chart.static_pixmap();
    let start = Instant::now();
    let mut pixmap = background.clone();
    let segments: Vec<(f64, f64, f64)> = (0..25)
        .flat_map(|i| (0..21).map(move |j| (i, j)))
        .map(|(i, j)| {
            let x = -2.0 + 4.0 * f64::from(i) / 24.0;
            let y = -1.0 + 5.0 * f64::from(j) / 20.0;
            (x, y, 2.0 * x)
        })
        .collect();
    chart.slope_segments(&mut pixmap, segments.iter().copied(), 16.0, &field);
    let parabola = |c: f64| {
        (0..=200).map(move |i| {
            let x = -2.0 + 4.0 * f64::from(i) / 200.0;
            (x, x * x + c)
        })
    };
    chart.polyline(&mut pixmap, parabola(0.0), &curve);
    chart.polyline(&mut pixmap, parabola(-1.0), &shifted);
    chart.draw_legend(&mut pixmap);
    let elapsed = start.elapsed();
    let path = dir.join("plot_demo_slope_field.png");
    save_png(&pixmap, &path)?;
    println!(
        "{} ({} segments, data layer {:?})",
        path.display(),
        segments.len(),
        elapsed
    );

    // Figure 3: dv/dt = −v/m with arrows, one decaying solution, markers at whole seconds.
    let spec = ChartSpec::new(
        Axis::linear(0.0, 5.0, "time t (s)"),
        Axis::linear(-0.5, 2.5, "velocity v (m/s)"),
    )
    .title("dv/dt = −v/m, m = 1 kg")
    .grid(true)
    .legend_entry(LegendEntry::line(curve, "v(t) = v₀·exp(−t/m)"))
    .legend_entry(LegendEntry::marker(
        MarkerStyle::new(MarkerShape::Circle, 7.0, palette(3)),
        "whole seconds",
    ));
    let chart = Chart::new(spec, 800, 600)?;
    let mut pixmap = chart.static_pixmap();
    let arrow = ArrowStyle::new(Color::from_rgba8(0x60, 0x60, 0x60, 255), 1.0);
    for i in 0..=10 {
        for j in 0..=9 {
            let t = 0.25 + 0.45 * f64::from(i);
            let v = -0.35 + 0.3 * f64::from(j);
            chart.arrow_px(&mut pixmap, (t, v), (1.0, -v), 18.0, &arrow);
        }
    }
    let solution = (0..=250).map(|i| {
        let t = 5.0 * f64::from(i) / 250.0;
        (t, 2.0 * (-t).exp())
    });
    chart.polyline(&mut pixmap, solution, &curve);
    let seconds = (0..=5).map(|t| (f64::from(t), 2.0 * (-f64::from(t)).exp()));
    chart.markers(
        &mut pixmap,
        seconds,
        &MarkerStyle::new(MarkerShape::Circle, 7.0, palette(3)),
    );
    chart.draw_legend(&mut pixmap);
    let path = dir.join("plot_demo_decay.png");
    save_png(&pixmap, &path)?;
    println!("{}", path.display());

    // A work-precision plot: log-log, one line per method, legend bottom left.
    let mut spec = ChartSpec::new(
        Axis::log10(1e-9, 1e-1, "global error |Δx| (m)"),
        Axis::log10(1e-4, 1e0, "cost per run (s)"),
    )
    .title("Work–precision")
    .grid(true);
    spec.theme.legend_corner = Corner::BottomLeft;
    let methods = [
        ("explicit Euler", 1.0),
        ("symplectic Euler", 1.0),
        ("RK4", 4.0),
    ];
    for (k, (name, _)) in methods.iter().enumerate() {
        spec.legend
            .push(LegendEntry::line(LineStyle::solid(palette(k), 1.5), *name));
    }
    let chart = Chart::new(spec, 800, 600)?;
    let mut pixmap = chart.static_pixmap();
    for (k, (_, order)) in methods.iter().enumerate() {
        let points: Vec<(f64, f64)> = (0..8)
            .map(|n| {
                let h = 0.1 / 2f64.powi(n);
                let error = (0.3 + 0.2 * k as f64) * h.powf(*order);
                let cost = 1e-4 * 0.1 / h * (1.0 + k as f64);
                (error, cost)
            })
            .collect();
        let style = LineStyle::solid(palette(k), 1.5);
        chart.polyline(&mut pixmap, points.iter().copied(), &style);
        chart.markers(
            &mut pixmap,
            points.iter().copied(),
            &MarkerStyle::new(MarkerShape::Square, 6.0, palette(k)),
        );
    }
    chart.draw_legend(&mut pixmap);
    let path = dir.join("plot_demo_work_precision.png");
    save_png(&pixmap, &path)?;
    println!("{}", path.display());
    // A 4x enlargement of the bottom-left corner, to check ticks and labels pixel by pixel.
    let corner = zoom(&pixmap, 0, 400, 200, 200, 4)?;
    let path = dir.join("plot_demo_work_precision_corner.png");
    save_png(&corner, &path)?;
    println!("{}", path.display());

    // Two panels in one image: energy on a log axis beside a phase portrait, 1200×450.
    let mut canvas = tiny_skia::Pixmap::new(1200, 450).ok_or_else(|| anyhow::anyhow!("canvas"))?;
    let left =
        tiny_skia::IntRect::from_xywh(0, 0, 600, 450).ok_or_else(|| anyhow::anyhow!("rect"))?;
    let right =
        tiny_skia::IntRect::from_xywh(600, 0, 600, 450).ok_or_else(|| anyhow::anyhow!("rect"))?;
    let energy = Chart::in_region(
        ChartSpec::new(
            Axis::linear(0.0, 100.0, "time t (s)"),
            Axis::log10(1e-12, 1e-2, "relative energy error |ΔE/E₀|"),
        )
        .title("Energy drift")
        .grid(true)
        .legend_entry(LegendEntry::line(
            LineStyle::solid(palette(0), 1.5),
            "explicit Euler",
        ))
        .legend_entry(LegendEntry::line(LineStyle::solid(palette(2), 1.5), "RK4")),
        1200,
        450,
        left,
    )?;
    energy.draw_static(&mut canvas);
    let drift = |scale: f64, power: f64| {
        (1..=400).map(move |i| {
            let t = f64::from(i) * 0.25;
            (t, scale * t.powf(power) * (1.0 + 0.5 * (t * 1.3).sin()))
        })
    };
    energy.polyline(
        &mut canvas,
        drift(1e-4, 1.0),
        &LineStyle::solid(palette(0), 1.5),
    );
    energy.polyline(
        &mut canvas,
        drift(1e-11, 0.5),
        &LineStyle::solid(palette(2), 1.5),
    );
    energy.draw_legend(&mut canvas);
    let phase = Chart::in_region(
        ChartSpec::new(
            Axis::linear(-1.5, 1.5, "position x (m)"),
            Axis::linear(-3.0, 3.0, "velocity v (m/s)"),
        )
        .title("Phase portrait, ω = 2 rad/s"),
        1200,
        450,
        right,
    )?;
    phase.draw_static(&mut canvas);
    let arrow = ArrowStyle::new(Color::from_rgba8(0x70, 0x70, 0x70, 255), 1.0);
    for i in 0..=12 {
        for j in 0..=12 {
            let x = -1.5 + 0.25 * f64::from(i);
            let v = -3.0 + 0.5 * f64::from(j);
            phase.arrow_px(&mut canvas, (x, v), (v, -4.0 * x), 14.0, &arrow);
        }
    }
    let ellipse = (0..=360).map(|k| {
        let a = f64::from(k).to_radians();
        (a.cos(), -2.0 * a.sin())
    });
    phase.polyline(&mut canvas, ellipse, &LineStyle::solid(palette(3), 2.0));
    let path = dir.join("plot_demo_two_panels.png");
    save_png(&canvas, &path)?;
    println!("{}", path.display());

    // A small 400×300 chart with heatmap cells and outward ticks.
    let mut spec = ChartSpec::new(
        Axis::linear(0.0, 10.0, "step size h (ms)"),
        Axis::linear(0.0, 1.0, "damping ζ"),
    )
    .title("Stable region");
    spec.theme.tick_direction = physframes::render::plot::TickDirection::Out;
    let small = Chart::new(spec, 400, 300)?;
    let mut pixmap = small.static_pixmap();
    let xs: Vec<f64> = (0..=20).map(|i| 0.5 * f64::from(i)).collect();
    let ys: Vec<f64> = (0..=10).map(|j| 0.1 * f64::from(j)).collect();
    small.fill_cells(&mut pixmap, &xs, &ys, |i, j| {
        if (i as f64) * 0.5 < 2.0 + 6.0 * (j as f64) * 0.1 {
            Color::from_rgba8(0x9e, 0xd6, 0x9e, 255)
        } else {
            Color::from_rgba8(0xf4, 0xa6, 0xa6, 255)
        }
    });
    let path = dir.join("plot_demo_small.png");
    save_png(&pixmap, &path)?;
    println!("{}", path.display());
    let path = dir.join("plot_demo_small_corner.png");
    save_png(&zoom(&pixmap, 0, 200, 100, 100, 6)?, &path)?;

    // Timing: a whole figure, static part included, many times over.
    let start = Instant::now();
    let runs = 50;
    for _ in 0..runs {
        let chart = Chart::new(
            ChartSpec::new(Axis::linear(-2.0, 2.0, "x"), Axis::linear(-1.0, 4.0, "y"))
                .title("Slope field of dy/dx = 2x")
                .legend_entry(LegendEntry::line(curve, "y = x²")),
            800,
            600,
        )?;
        let mut pixmap = chart.static_pixmap();
        chart.slope_segments(&mut pixmap, segments.iter().copied(), 16.0, &field);
        chart.polyline(&mut pixmap, parabola(0.0), &curve);
        chart.polyline(&mut pixmap, parabola(-1.0), &shifted);
        chart.draw_legend(&mut pixmap);
        std::hint::black_box(&pixmap);
    }
    println!("whole figure: {:?} per run", start.elapsed() / runs);
    let mut times = [std::time::Duration::ZERO; 5];
    for _ in 0..runs {
        let t = Instant::now();
        let chart = Chart::new(
            ChartSpec::new(Axis::linear(-2.0, 2.0, "x"), Axis::linear(-1.0, 4.0, "y"))
                .title("Slope field of dy/dx = 2x")
                .legend_entry(LegendEntry::line(curve, "y = x²")),
            800,
            600,
        )?;
        times[0] += t.elapsed();
        let t = Instant::now();
        let mut pixmap = chart.static_pixmap();
        times[1] += t.elapsed();
        let t = Instant::now();
        chart.slope_segments(&mut pixmap, segments.iter().copied(), 16.0, &field);
        times[2] += t.elapsed();
        let t = Instant::now();
        chart.polyline(&mut pixmap, parabola(0.0), &curve);
        chart.polyline(&mut pixmap, parabola(-1.0), &shifted);
        times[3] += t.elapsed();
        let t = Instant::now();
        chart.draw_legend(&mut pixmap);
        times[4] += t.elapsed();
    }
    for (name, time) in ["layout", "static", "segments", "curves", "legend"]
        .iter()
        .zip(times)
    {
        println!("{name}: {:?}", time / runs);
    }
    Ok(())
}

/// Writes `pixmap` as an RGBA PNG (tiny-skia is built without its own PNG support).
fn save_png(pixmap: &tiny_skia::Pixmap, path: &std::path::Path) -> anyhow::Result<()> {
    let image = image::RgbaImage::from_raw(
        pixmap.width(),
        pixmap.height(),
        pixmap.clone().take_demultiplied(),
    )
    .ok_or_else(|| anyhow::anyhow!("pixmap buffer has the wrong length"))?;
    image.save(path)?;
    Ok(())
}

/// Copies the `w × h` block at `(x, y)` enlarged `factor` times with nearest-neighbour
/// sampling.
fn zoom(
    pixmap: &tiny_skia::Pixmap,
    x: u32,
    y: u32,
    w: u32,
    h: u32,
    factor: u32,
) -> anyhow::Result<tiny_skia::Pixmap> {
    let mut out = tiny_skia::Pixmap::new(w * factor, h * factor)
        .ok_or_else(|| anyhow::anyhow!("zoomed size is zero"))?;
    let width = out.width();
    for (i, p) in out.pixels_mut().iter_mut().enumerate() {
        let (ox, oy) = (i as u32 % width, i as u32 / width);
        if let Some(src) = pixmap.pixel(x + ox / factor, y + oy / factor) {
            *p = src;
        }
    }
    Ok(out)
}
