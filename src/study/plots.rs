//! The studies' diagrams, drawn with the [`Chart`] of `render::plot`: the convergence
//! plot, the work-precision diagram, the energy-error plot and the stability heatmaps.
//!
//! Every function takes a study's data and returns a pixmap; [`encode`] turns it into
//! PNG bytes with provenance. Each integrator keeps one colour and one marker shape in
//! every diagram (its position in [`IntegratorKind::ALL`]), so plots compare at a glance.

use tiny_skia::{Color, IntRect, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

use crate::error::{Error, Result};
use crate::render::plot::{
    palette, Axis, Chart, ChartError, ChartSpec, Corner, Dash, LegendEntry, LegendSample,
    LineStyle, MarkerShape, MarkerStyle,
};
use crate::render::text::{Font, HAlign, TextStyle, VAlign};
use crate::render::{encode_png, Compression, Provenance};
use crate::sim::IntegratorKind;

use super::convergence::ConvergenceTable;
use super::energy::{spring_energy_theory, EnergyStudy, EnergyTheory};
use super::reference::ReferenceKind;
use super::stability::{Boundary, StabilityGrid, StabilityProblem, StabilityTable};
use super::work_precision::WorkPrecisionRow;

/// The size of the single-chart diagrams, in pixels.
pub const CHART_SIZE: (u32, u32) = (900, 640);

/// Returns the provenance every study PNG carries: the program version, the study, the
/// problem and the integrators, then any `extra` settings.
pub fn provenance(
    study: &str,
    problem: &str,
    integrators: &[IntegratorKind],
    extra: &[(&str, String)],
) -> Provenance {
    let names: Vec<&str> = integrators.iter().map(|k| k.name()).collect();
    let mut p = Provenance::default()
        .with(
            "Software",
            format!("physframes {}", env!("CARGO_PKG_VERSION")),
        )
        .with("physframes:study", study)
        .with("physframes:problem", problem)
        .with("physframes:integrators", names.join(","));
    for (key, value) in extra {
        p = p.with(&format!("physframes:{key}"), value);
    }
    p
}

/// Encodes a diagram as PNG with its provenance.
pub fn encode(pixmap: &Pixmap, provenance: &Provenance) -> Result<Vec<u8>> {
    encode_png(pixmap, provenance, Compression::Fast)
        .map_err(|e| Error::Runtime(format!("cannot encode the diagram: {e}")))
}

/// Returns the colour and marker of an integrator, the same in every diagram.
fn series_style(kind: IntegratorKind) -> (LineStyle, MarkerStyle) {
    const SHAPES: [MarkerShape; 4] = [
        MarkerShape::Circle,
        MarkerShape::Square,
        MarkerShape::Diamond,
        MarkerShape::Triangle,
    ];
    let index = IntegratorKind::ALL
        .iter()
        .position(|&k| k == kind)
        .unwrap_or(0);
    let color = palette(index);
    (
        LineStyle::solid(color, 1.5),
        MarkerStyle::new(SHAPES[index % SHAPES.len()], 7.0, color),
    )
}

/// Returns the whole decades that enclose every positive finite value, or `None` when
/// there is none. A single decade is widened to two.
fn decade_range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return None;
    }
    let a = lo.log10().floor();
    let mut b = hi.log10().ceil();
    if b <= a {
        b = a + 1.0;
    }
    Some((10f64.powf(a), 10f64.powf(b)))
}

/// Turns a layout failure into an error of the command.
fn chart_error(e: ChartError) -> Error {
    Error::Runtime(format!("cannot lay out the diagram: {e}"))
}

/// Draws the convergence plot: the error at the final time against h, log-log, one
/// line per integrator. A method of order p is a straight line of slope p.
pub fn convergence_chart(table: &ConvergenceTable) -> Result<Pixmap> {
    let (w, h) = CHART_SIZE;
    let hs = table.series.iter().flat_map(|s| s.rows.iter().map(|r| r.h));
    let errors = table
        .series
        .iter()
        .flat_map(|s| s.rows.iter().map(|r| r.error));
    let x = decade_range(hs).unwrap_or((1e-3, 1.0));
    let y = decade_range(errors).unwrap_or((1e-16, 1.0));
    let mut spec = ChartSpec::new(
        Axis::log10(x.0, x.1, "step h (s)"),
        Axis::log10(y.0, y.1, table.kind.error_axis(table.t_end)),
    )
    .title(format!(
        "Convergence on {}: halving h divides the error by 2^order",
        table.problem
    ))
    .grid(true);
    spec.theme.legend_corner = Corner::BottomRight;
    for s in &table.series {
        let (line, marker) = series_style(s.integrator);
        let observed = s
            .final_order()
            .map_or_else(|| "-".to_string(), |p| format!("{p:.2}"));
        spec.legend.push(LegendEntry::line_marker(
            line,
            marker,
            format!(
                "{} (order {}, observed {observed})",
                s.integrator, s.nominal_order
            ),
        ));
    }
    let chart = Chart::new(spec, w, h).map_err(chart_error)?;
    let mut pixmap = chart.static_pixmap();
    for s in &table.series {
        let (line, marker) = series_style(s.integrator);
        let points: Vec<(f64, f64)> = s.rows.iter().map(|r| (r.h, r.error)).collect();
        chart.polyline(&mut pixmap, points.iter().copied(), &line);
        chart.markers(&mut pixmap, points.iter().copied(), &marker);
    }
    chart.draw_legend(&mut pixmap);
    Ok(pixmap)
}

/// Draws the work-precision diagram: the error at the final time against the run time,
/// log-log, one line with markers per integrator (one marker per h, or per tolerance for
/// dopri5). Lower left is better; a line's slope is minus its order per unit of cost.
pub fn work_precision_chart(
    problem: ReferenceKind,
    t_end: f64,
    rows: &[WorkPrecisionRow],
) -> Result<Pixmap> {
    let (w, h) = CHART_SIZE;
    let finite = |r: &&WorkPrecisionRow| r.error.is_finite() && r.error > 0.0;
    let x = decade_range(rows.iter().filter(finite).map(|r| r.seconds)).unwrap_or((1e-7, 1.0));
    let y = decade_range(rows.iter().filter(finite).map(|r| r.error)).unwrap_or((1e-16, 1.0));
    let mut kinds: Vec<IntegratorKind> = Vec::new();
    for r in rows {
        if !kinds.contains(&r.integrator) {
            kinds.push(r.integrator);
        }
    }
    let mut spec = ChartSpec::new(
        Axis::log10(x.0, x.1, "run time of one solve (s), median"),
        Axis::log10(y.0, y.1, problem.error_axis(t_end)),
    )
    .title(format!("Work–precision on {problem}: lower left is better"))
    .grid(true);
    // Cheap and accurate at once is where no method reaches: the legend's corner.
    spec.theme.legend_corner = Corner::BottomLeft;
    for &kind in &kinds {
        let (line, marker) = series_style(kind);
        let label = if kind.is_adaptive() {
            format!("{kind} (one point per tolerance)")
        } else {
            format!("{kind} (order {})", kind.order())
        };
        spec.legend
            .push(LegendEntry::line_marker(line, marker, label));
    }
    let chart = Chart::new(spec, w, h).map_err(chart_error)?;
    let mut pixmap = chart.static_pixmap();
    for &kind in &kinds {
        let (line, marker) = series_style(kind);
        let points: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.integrator == kind)
            .filter(finite)
            .map(|r| (r.seconds, r.error))
            .collect();
        chart.polyline(&mut pixmap, points.iter().copied(), &line);
        chart.markers(&mut pixmap, points.iter().copied(), &marker);
    }
    chart.draw_legend(&mut pixmap);
    Ok(pixmap)
}

/// The smallest relative energy error the energy plot shows: a few ε, below which
/// differences are round-off.
const ENERGY_FLOOR: f64 = 1e-16;

/// Draws the energy plot: |E - E0|/E0 against time on a log axis, one line per
/// integrator (the largest value over each sampled block of steps, so no oscillation is
/// lost between samples). On the undamped spring, theory's exact curve for each
/// Runge–Kutta method is drawn over it as dots, and the proven bound of each symplectic
/// method as a dotted line in its colour.
///
/// The axis is logarithmic because the errors span twenty decades and more at once:
/// explicit Euler's grows geometrically, RK4's stays near 10⁻⁸; on a linear axis,
/// symmetric or not, every line but the largest would lie flat on zero. The sign is
/// lost, but it is in the CSV, and theory gives it (only RK4 loses energy).
pub fn energy_chart(study: &EnergyStudy) -> Result<Pixmap> {
    let (w, h) = CHART_SIZE;
    let o = &study.options;
    let t_end = o.steps as f64 * o.dt;
    let values = study.series.iter().flat_map(|s| {
        s.rows
            .iter()
            .map(|r| r.max_abs_relative_error.max(ENERGY_FLOOR))
    });
    let y = decade_range(values).unwrap_or((ENERGY_FLOOR, 1.0));
    let title = match study.omega {
        Some(omega) => format!(
            "Energy error on {}: h = {} s, h·ω = {:.4}, {} steps",
            study.problem,
            o.dt,
            o.dt * omega,
            o.steps
        ),
        None => format!(
            "Energy error on {}: h = {} s, {} steps",
            study.problem, o.dt, o.steps
        ),
    };
    let mut spec = ChartSpec::new(
        Axis::linear(0.0, t_end, "time t (s)"),
        Axis::log10(y.0, y.1, "relative energy error |E − E₀| / E₀"),
    )
    .title(title)
    .grid(true);
    spec.theme.legend_corner = Corner::TopLeft;
    spec.theme.legend_px = 12.5;
    let grey = Color::from_rgba8(0x30, 0x30, 0x30, 255);
    let theory_marker = MarkerStyle::new(MarkerShape::Circle, 4.5, grey);
    let mut any_exact = false;
    let mut any_bound = false;
    let theories: Vec<Option<(f64, EnergyTheory)>> = study
        .series
        .iter()
        .map(|s| {
            let omega = study.omega?;
            let theory = spring_energy_theory(s.integrator, o.dt * omega, 1)?;
            Some((o.dt * omega, theory))
        })
        .collect();
    // A series that repeats an earlier one (midpoint and Heun share R(z) = 1 + z + z²/2,
    // so on a linear problem they agree to round-off) is dashed, so both show.
    let twins: Vec<Option<IntegratorKind>> = study
        .series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            study.series[..i]
                .iter()
                .find(|earlier| same_values(earlier, s))
                .map(|earlier| earlier.integrator)
        })
        .collect();
    for ((s, theory), twin) in study.series.iter().zip(&theories).zip(&twins) {
        let (line, _) = series_style(s.integrator);
        let entry = match twin {
            Some(earlier) => LegendEntry::line(
                line.dashed(Dash::Dashed),
                format!("{} (same as {earlier})", s.integrator),
            ),
            None => LegendEntry::line(line, s.integrator.name()),
        };
        spec.legend.push(entry);
        match theory {
            Some((_, EnergyTheory::Exact(_))) => any_exact = true,
            Some((_, EnergyTheory::Bound(_))) => any_bound = true,
            None => {}
        }
    }
    if any_exact {
        spec.legend.push(LegendEntry::marker(
            theory_marker,
            "theory: |R(ihω)|²ⁿ − 1 (Runge–Kutta)",
        ));
    }
    if any_bound {
        spec.legend.push(LegendEntry::line(
            LineStyle::solid(grey, 1.0).dashed(Dash::Dotted),
            "proven bound (symplectic)",
        ));
    }
    let chart = Chart::new(spec, w, h).map_err(chart_error)?;
    let mut pixmap = chart.static_pixmap();
    for (s, twin) in study.series.iter().zip(&twins) {
        let (line, _) = series_style(s.integrator);
        let line = if twin.is_some() {
            line.dashed(Dash::Dashed)
        } else {
            line
        };
        let points = s
            .rows
            .iter()
            .map(|r| (r.t, r.max_abs_relative_error.max(y.0)));
        chart.polyline(&mut pixmap, points, &line);
    }
    // Theory goes on top as small dark dots, about 30 along the run, so that where it
    // matches the data it shows as dots on the coloured line without hiding its colour.
    for (s, theory) in study.series.iter().zip(&theories) {
        let (line, _) = series_style(s.integrator);
        match theory {
            Some((sw, EnergyTheory::Exact(_))) => {
                // |(1 + δ)^n - 1| at every k-th sampled step.
                let every = s.rows.len().div_ceil(30).max(1);
                let dots = s
                    .rows
                    .iter()
                    .skip(every - 1)
                    .step_by(every)
                    .filter_map(|r| match spring_energy_theory(s.integrator, *sw, r.step) {
                        Some(EnergyTheory::Exact(v)) => Some((r.t, v.abs().max(y.0))),
                        _ => None,
                    });
                chart.markers(&mut pixmap, dots, &theory_marker);
            }
            Some((_, EnergyTheory::Bound(b))) => {
                // The bound in the method's colour: it belongs to that line alone.
                chart.polyline(
                    &mut pixmap,
                    [(0.0, *b), (t_end, *b)],
                    &LineStyle::solid(line.color, 1.2).dashed(Dash::Dotted),
                );
            }
            None => {}
        }
    }
    chart.draw_legend(&mut pixmap);
    Ok(pixmap)
}

/// Returns true when two energy series have the same rows to within 10⁻⁹ relative.
fn same_values(a: &super::energy::EnergySeries, b: &super::energy::EnergySeries) -> bool {
    a.rows.len() == b.rows.len()
        && a.rows.iter().zip(&b.rows).all(|(x, y)| {
            let (p, q) = (x.max_abs_relative_error, y.max_abs_relative_error);
            x.t == y.t && (p - q).abs() <= 1e-9 * p.abs().max(q.abs())
        })
}

/// The width and height of one heatmap panel, in pixels.
const PANEL: (u32, u32) = (400, 380);
/// The height of the band above the panels that holds the figure's title.
const HEADER: u32 = 64;
/// The width of the strip right of the panels that holds the colour bar.
const COLORBAR_STRIP: u32 = 190;
/// |ln g| at or below 10^LOG_FLOOR is drawn white: neutral to within round-off.
const LOG_FLOOR: f64 = -10.0;
/// |ln g| at or above 10^LOG_CEIL takes the darkest colour.
const LOG_CEIL: f64 = 1.0;

/// Draws the stability heatmaps: one panel per integrator with step h across and the
/// stiffness up (both log), each cell coloured by the measured growth per step g, and
/// theory's boundary h = s*·m/k (or s*/ω) drawn over it as a black line; on drag, the
/// dashed line h = m/k is where explicit and symplectic Euler start to flip the sign of
/// v. A colour bar on the right reads the colours.
///
/// The colour is ln g on a symmetric log scale: white for |ln g| ≤ 10⁻¹⁰ (neutral to
/// within round-off), red for growth and blue for decay, deepening with each decade of
/// |ln g| up to 10. A log scale shows the tiny growth of midpoint on the spring
/// (ln g ≈ s⁴/8) as clearly as the explosive growth past RK4's limit, so the stability
/// boundary is a sharp change of hue wherever it lies.
pub fn stability_chart(grid: &StabilityGrid, table: &StabilityTable) -> Result<Pixmap> {
    let n = grid.growth.len().max(1);
    let cols = n.min(4) as u32;
    let rows = (n as u32).div_ceil(cols);
    let font = Font::dejavu_sans();
    let problem = grid.problem;
    let (header1, header2) = match problem {
        StabilityProblem::Drag => (
            "Linear stability on drag, m·dv/dt = −k·v, m = 1 kg",
            "colour: growth per step g = |v(t + h)| / |v(t)|; black line: theory's boundary h·k/m = s*",
        ),
        StabilityProblem::Spring => (
            "Linear stability on an undamped spring, x″ = −ω²·x, m = 1 kg",
            "colour: growth per step g = spectral radius of the one-step map of (x, v); black line: theory's boundary h·ω = s*",
        ),
    };
    // The panels and the colour bar, widened if need be so the header fits.
    let header_width = font.measure(header2, 14.0).width.ceil() as u32 + 32;
    let width = (cols * PANEL.0 + COLORBAR_STRIP).max(header_width);
    let height = HEADER + rows * PANEL.1;
    let mut pixmap = Pixmap::new(width, height)
        .ok_or_else(|| Error::Runtime("cannot allocate the heatmap".to_string()))?;
    pixmap.fill(Color::WHITE);
    let centre_x = 0.5 * width as f32;
    font.draw(
        &mut pixmap,
        header1,
        centre_x,
        26.0,
        &TextStyle::new(19.0, Color::BLACK).anchor(HAlign::Center, VAlign::Baseline),
    );
    font.draw(
        &mut pixmap,
        header2,
        centre_x,
        50.0,
        &TextStyle::new(14.0, Color::BLACK).anchor(HAlign::Center, VAlign::Baseline),
    );
    let (h_min, h_max) = (
        grid.h_edges.first().copied().unwrap_or(1e-3),
        grid.h_edges.last().copied().unwrap_or(1.0),
    );
    let (k_min, k_max) = (
        grid.stiffness_edges.first().copied().unwrap_or(0.1),
        grid.stiffness_edges.last().copied().unwrap_or(1.0),
    );
    let y_title = match problem {
        StabilityProblem::Drag => "drag coefficient k (kg/s)",
        StabilityProblem::Spring => "angular frequency ω (rad/s)",
    };
    let symbol = problem.step_symbol();
    let boundary_line = LineStyle::solid(Color::BLACK, 2.0);
    // Gold, so that it shows on the deep blue where R(-s) = 1 - s passes through 0.
    let flip_line =
        LineStyle::solid(Color::from_rgba8(0xff, 0xc4, 0x00, 255), 2.0).dashed(Dash::Dashed);
    for (index, (kind, values)) in grid.growth.iter().enumerate() {
        let (col, row) = (index as u32 % cols, index as u32 / cols);
        let region = IntRect::from_xywh(
            (col * PANEL.0) as i32,
            (HEADER + row * PANEL.1) as i32,
            PANEL.0,
            PANEL.1,
        )
        .ok_or_else(|| Error::Runtime("a heatmap panel has no area".to_string()))?;
        let row_of_table = table.rows.iter().find(|r| r.integrator == *kind);
        let theory = row_of_table.map(|r| r.theory.clone());
        let mut spec = ChartSpec::new(
            Axis::log10(h_min, h_max, "step h (s)"),
            Axis::log10(k_min, k_max, y_title),
        )
        .title(kind.name());
        spec.theme.background = None;
        spec.theme.legend_corner = Corner::BottomLeft;
        spec.theme.legend_px = 12.0;
        let found = row_of_table.map(|r| r.found);
        match &theory {
            Some(t) if t.boundary > 0.0 => {
                let found = match found {
                    Some(Boundary::At(s)) => format!(", found {s:.4}"),
                    _ => String::new(),
                };
                spec.legend.push(LegendEntry::line(
                    boundary_line,
                    format!("theory {symbol} = {:.4}{found}", t.boundary),
                ));
                if let Some(flip) = t.sign_flip {
                    spec.legend.push(LegendEntry::line(
                        flip_line,
                        format!("v flips sign past {symbol} = {flip}"),
                    ));
                }
            }
            Some(_) => spec.legend.push(LegendEntry {
                sample: LegendSample::Patch(diverging(0.6)),
                label: "theory: unstable for every h > 0".to_string(),
            }),
            None => {}
        }
        let chart = Chart::in_region(spec, width, height, region).map_err(chart_error)?;
        chart.draw_static(&mut pixmap);
        chart.fill_cells(&mut pixmap, &grid.h_edges, &grid.stiffness_edges, |i, j| {
            diverging(colour_position(values[j][i]))
        });
        if let Some(t) = &theory {
            // h = s*/k is a straight line on log-log axes: two points draw it.
            if t.boundary > 0.0 {
                let line = [(t.boundary / k_min, k_min), (t.boundary / k_max, k_max)];
                chart.polyline(&mut pixmap, line, &boundary_line);
            }
            if let Some(flip) = t.sign_flip {
                let line = [(flip / k_min, k_min), (flip / k_max, k_max)];
                chart.polyline(&mut pixmap, line, &flip_line);
            }
        }
        // The cells cover the frame's inner edge; draw the frame and ticks again on top.
        redraw_frame(&mut pixmap, &chart);
        chart.draw_legend(&mut pixmap);
    }
    draw_colorbar(&mut pixmap, cols * PANEL.0, HEADER, height);
    Ok(pixmap)
}

/// Returns where the growth factor g sits on the colour scale, from -1 (strongest
/// decay) through 0 (neutral, white) to 1 (strongest growth): the sign of ln g times
/// the position of log10|ln g| between `LOG_FLOOR` and `LOG_CEIL`.
pub fn colour_position(g: f64) -> f64 {
    if g.is_nan() {
        return 0.0;
    }
    if g <= 0.0 {
        // A step that wipes the state out in one go (Euler on drag at s = 1).
        return -1.0;
    }
    let r = g.ln();
    if r == 0.0 {
        return 0.0;
    }
    let u = ((r.abs().log10() - LOG_FLOOR) / (LOG_CEIL - LOG_FLOOR)).clamp(0.0, 1.0);
    u.copysign(r)
}

/// A diverging blue–white–red colour map (ColorBrewer's RdBu, reversed) with exact
/// white at 0: `u` in [-1, 1], blue for decay, red for growth.
pub fn diverging(u: f64) -> Color {
    const RED: [(u8, u8, u8); 6] = [
        (0xff, 0xff, 0xff),
        (0xfd, 0xdb, 0xc7),
        (0xf4, 0xa5, 0x82),
        (0xd6, 0x60, 0x4d),
        (0xb2, 0x18, 0x2b),
        (0x67, 0x00, 0x1f),
    ];
    const BLUE: [(u8, u8, u8); 6] = [
        (0xff, 0xff, 0xff),
        (0xd1, 0xe5, 0xf0),
        (0x92, 0xc5, 0xde),
        (0x43, 0x93, 0xc3),
        (0x21, 0x66, 0xac),
        (0x05, 0x30, 0x61),
    ];
    let stops = if u >= 0.0 { &RED } else { &BLUE };
    let x = u.abs().clamp(0.0, 1.0) * (stops.len() - 1) as f64;
    let i = (x.floor() as usize).min(stops.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (f64::from(a) + (f64::from(b) - f64::from(a)) * f).round() as u8;
    let (a, b) = (stops[i], stops[i + 1]);
    Color::from_rgba8(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2), 255)
}

/// Strokes the chart's frame again, over data that was filled up to it.
fn redraw_frame(pixmap: &mut Pixmap, chart: &Chart) {
    let plot = chart.plot_area();
    let width = chart.spec().theme.frame_width;
    let half = 0.5 * width;
    if let Some(rect) = Rect::from_ltrb(
        plot.left() as f32 + half,
        plot.top() as f32 + half,
        plot.right() as f32 - half,
        plot.bottom() as f32 - half,
    ) {
        let path = PathBuilder::from_rect(rect);
        let mut paint = Paint::default();
        paint.set_color(chart.spec().theme.frame_color);
        let stroke = Stroke {
            width,
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
    }
}

/// Draws the colour bar in the strip that starts at `left`: a vertical bar of the
/// diverging map with ln g labelled at every third decade.
fn draw_colorbar(pixmap: &mut Pixmap, left: u32, top: u32, bottom: u32) {
    let font = Font::dejavu_sans();
    let text = TextStyle::new(13.0, Color::BLACK);
    let x0 = left as f32 + 24.0;
    let bar_w = 22.0;
    let y0 = top as f32 + 56.0;
    let y1 = (bottom as f32 - 56.0).max(y0 + 100.0);
    font.draw(
        pixmap,
        "ln g per step",
        x0 - 6.0,
        y0 - 30.0,
        &TextStyle::new(14.0, Color::BLACK),
    );
    font.draw(pixmap, "grows (red)", x0 - 6.0, y0 - 12.0, &text);
    font.draw(pixmap, "decays (blue)", x0 - 6.0, y1 + 22.0, &text);
    // One row of pixels per colour, top (u = 1) to bottom (u = -1).
    let rows = (y1 - y0).round() as i32;
    for k in 0..rows {
        let u = 1.0 - 2.0 * (f64::from(k) + 0.5) / f64::from(rows);
        if let Some(rect) = Rect::from_xywh(x0, y0 + k as f32, bar_w, 1.0) {
            let mut paint = Paint::default();
            paint.set_color(diverging(u));
            paint.anti_alias = false;
            pixmap.fill_rect(rect, &paint, Transform::identity(), None);
        }
    }
    let mut frame = Paint::default();
    frame.set_color(Color::BLACK);
    if let Some(rect) = Rect::from_ltrb(x0 - 0.5, y0 - 0.5, x0 + bar_w + 0.5, y1 + 0.5) {
        let path = PathBuilder::from_rect(rect);
        pixmap.stroke_path(
            &path,
            &frame,
            &Stroke::default(),
            Transform::identity(),
            None,
        );
    }
    // Ticks at ln g = ±10¹, ±10⁻², ±10⁻⁵, ±10⁻⁸, and 0.
    let y_of = |u: f64| y0 + ((1.0 - u) / 2.0) as f32 * (y1 - y0);
    let mut ticks: Vec<(f64, String)> = vec![(0.0, "0 (g = 1)".to_string())];
    for e in [1, -2, -5, -8] {
        let u = (f64::from(e) - LOG_FLOOR) / (LOG_CEIL - LOG_FLOOR);
        let power = crate::render::ticks::format_decade(e, Default::default());
        ticks.push((u, format!("+{power}")));
        ticks.push((-u, format!("−{power}")));
    }
    let label = text.anchor(HAlign::Left, VAlign::Middle);
    let mut marks = PathBuilder::new();
    for (u, name) in &ticks {
        let y = y_of(*u).round() + 0.5;
        marks.move_to(x0 + bar_w, y);
        marks.line_to(x0 + bar_w + 5.0, y);
        font.draw(pixmap, name, x0 + bar_w + 9.0, y, &label);
    }
    if let Some(path) = marks.finish() {
        pixmap.stroke_path(
            &path,
            &frame,
            &Stroke::default(),
            Transform::identity(),
            None,
        );
    }
    font.draw(pixmap, "white: |ln g| ≤ 10⁻¹⁰", x0 - 6.0, y1 + 40.0, &text);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neutral_growth_is_white_and_the_map_is_symmetric() {
        assert_eq!(colour_position(1.0), 0.0);
        assert_eq!(diverging(0.0), Color::WHITE);
        assert_eq!(colour_position(1.0 + 1e-12), colour_position(1.0 + 1e-12));
        assert!(colour_position(2.0) > 0.0 && colour_position(0.5) < 0.0);
        assert!((colour_position(2.0) + colour_position(0.5)).abs() < 1e-12);
        assert_eq!(colour_position(0.0), -1.0);
        assert_eq!(colour_position(1e9), 1.0);
    }

    #[test]
    fn decades_enclose_the_values() {
        assert_eq!(decade_range([3e-5, 0.2, 0.0, f64::NAN]), Some((1e-5, 1.0)));
        assert_eq!(decade_range([0.5]), Some((0.1, 1.0)));
        assert_eq!(decade_range([f64::INFINITY]), None);
    }
}
