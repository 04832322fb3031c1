use super::data::clip_segment;
use super::*;

fn transparent_theme() -> Theme {
    Theme {
        background: None,
        ..Theme::default()
    }
}

fn chart(x: Axis, y: Axis, width: u32, height: u32) -> Chart {
    Chart::new(
        ChartSpec::new(x, y).theme(transparent_theme()),
        width,
        height,
    )
    .expect("a valid chart")
}

/// The bounding box `(x0, y0, x1, y1)`, inclusive, of pixels that are not transparent.
fn ink_box(pixmap: &Pixmap) -> Option<(u32, u32, u32, u32)> {
    let w = pixmap.width();
    pixmap
        .pixels()
        .iter()
        .enumerate()
        .filter(|(_, p)| p.alpha() != 0)
        .map(|(i, _)| (i as u32 % w, i as u32 / w))
        .fold(None, |acc, (x, y)| {
            Some(match acc {
                None => (x, y, x, y),
                Some((a, b, c, d)) => (a.min(x), b.min(y), c.max(x), d.max(y)),
            })
        })
}

fn blank(chart: &Chart) -> Pixmap {
    Pixmap::new(chart.canvas.0, chart.canvas.1).expect("a canvas")
}

#[test]
fn data_corners_map_to_the_frame_line_centres() {
    let c = chart(
        Axis::linear(-2.0, 2.0, "x"),
        Axis::log10(1e-6, 1e2, "y"),
        800,
        600,
    );
    let p = c.plot_area();
    let (l, t, r, b) = (
        p.left() as f32,
        p.top() as f32,
        p.right() as f32,
        p.bottom() as f32,
    );
    assert_eq!(c.to_px(-2.0, 1e-6), (l + 0.5, b - 0.5));
    assert_eq!(c.to_px(2.0, 1e2), (r - 0.5, t + 0.5));
    // The middle of the data is the middle of the frame; on a log axis, the middle
    // decade.
    let (mx, my) = c.to_px(0.0, 1e-2);
    assert!((mx - 0.5 * (l + r)).abs() < 1e-3 && (my - 0.5 * (t + b)).abs() < 1e-3);
    // Points a log axis cannot show map to NaN, not to a wild number.
    assert!(c.to_px(0.0, 0.0).1.is_nan() && c.to_px(0.0, -1.0).1.is_nan());
    let (x, y) = c.transform().invert(mx, my);
    assert!(
        x.abs() < 1e-9 && (y / 1e-2 - 1.0).abs() < 1e-9,
        "({x}, {y})"
    );
}

#[test]
fn a_data_direction_follows_the_axis_scales() {
    // x spans 100 units and y spans 1, so one y unit is far more pixels than one x unit.
    let c = chart(
        Axis::linear(0.0, 100.0, "x"),
        Axis::linear(0.0, 1.0, "y"),
        800,
        600,
    );
    let m = c.transform();
    let (ux, uy) = m.direction(50.0, 0.5, 0.0, 1.0).expect("a direction");
    assert!(
        ux.abs() < 1e-12 && (uy + 1.0).abs() < 1e-12,
        "+y is straight up"
    );
    let (ux, uy) = m.direction(50.0, 0.5, 1.0, 0.0).expect("a direction");
    assert!((ux - 1.0).abs() < 1e-12 && uy.abs() < 1e-12, "+x is right");
    // (1, 1) in data space: the pixel vector is (kx, -ky) with kx = width/100 and
    // ky = height/1.
    let p = c.plot_area();
    let kx = f64::from(p.width() - 1) / 100.0;
    let ky = f64::from(p.height() - 1);
    let (ux, uy) = m.direction(50.0, 0.5, 1.0, 1.0).expect("a direction");
    let n = kx.hypot(ky);
    assert!((ux - kx / n).abs() < 1e-9 && (uy + ky / n).abs() < 1e-9);
    assert_eq!(m.direction(50.0, 0.5, 0.0, 0.0), None);
    // On a log axis one decade is the same number of pixels anywhere, so the pixel
    // slope of y ∝ x (a line of slope 1 in log-log) is the same at every point.
    let c = chart(
        Axis::log10(1e-3, 1e3, "x"),
        Axis::log10(1e-3, 1e3, "y"),
        600,
        600,
    );
    let a = c
        .transform()
        .direction(1e-2, 1e-2, 1.0, 1.0)
        .expect("a direction");
    let b = c
        .transform()
        .direction(1e2, 1e2, 1.0, 1.0)
        .expect("a direction");
    assert!((a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9);
}

#[test]
fn an_arrow_along_plus_y_points_up_on_screen() {
    let c = chart(
        Axis::linear(0.0, 100.0, "x"),
        Axis::linear(0.0, 1.0, "y"),
        800,
        600,
    );
    let mut pixmap = blank(&c);
    let style = ArrowStyle::new(Color::BLACK, 2.0);
    c.arrow(&mut pixmap, (50.0, 0.2), (0.0, 0.5), &style);
    let (x0, y0, x1, y1) = ink_box(&pixmap).expect("the arrow has ink");
    let (base_x, base_y) = c.to_px(50.0, 0.2);
    let (_, tip_y) = c.to_px(50.0, 0.7);
    assert!(tip_y < base_y, "the tip is above the base on screen");
    assert!((y0 as f32 - tip_y).abs() <= 1.0 && ((y1 + 1) as f32 - base_y).abs() <= 1.0);
    assert!((x0 as f32) < base_x && (x1 as f32) > base_x && x1 - x0 <= 14);
    // The head, at the top, is wider than the shaft at the bottom.
    let row_width = |y: u32| {
        (0..800)
            .filter(|&x| pixmap.pixel(x, y).is_some_and(|p| p.alpha() > 0))
            .count()
    };
    assert!(row_width(y0 + 6) > 2 * row_width(y1 - 5));
    // The fixed-length form points the same way and is as long as asked.
    let mut pixmap = blank(&c);
    c.arrow_px(&mut pixmap, (50.0, 0.2), (0.0, 1e-3), 40.0, &style);
    let (_, y0, _, y1) = ink_box(&pixmap).expect("the arrow has ink");
    assert!((y1 - y0) as f32 >= 39.0 && (y1 - y0) as f32 <= 42.0);
    assert!(((y1 + 1) as f32 - base_y).abs() <= 1.0);
}

#[test]
fn slope_segments_have_the_slope_on_screen() {
    let c = chart(
        Axis::linear(-2.0, 2.0, "x"),
        Axis::linear(-1.0, 4.0, "y"),
        800,
        600,
    );
    let style = LineStyle::solid(Color::BLACK, 1.0);
    // Slope 0 is a horizontal segment of the requested length.
    let mut pixmap = blank(&c);
    c.slope_segments(&mut pixmap, [(0.0, 1.0, 0.0)], 20.0, &style);
    let (x0, y0, x1, y1) = ink_box(&pixmap).expect("the segment has ink");
    assert!((x1 - x0 + 1) >= 20 && (x1 - x0 + 1) <= 22 && y1 - y0 <= 2);
    // An infinite slope is vertical.
    let mut pixmap = blank(&c);
    c.slope_segments(&mut pixmap, [(0.0, 1.0, f64::INFINITY)], 20.0, &style);
    let (x0, _, x1, _) = ink_box(&pixmap).expect("the segment has ink");
    assert!(x1 - x0 <= 2);
    // A slope of (y pixels per unit) / (x pixels per unit)... inverted is 45° on screen.
    let m = c.transform();
    let (kx, ky) = (m.x.pixels_per_unit(), -m.y.pixels_per_unit());
    let (ux, uy) = m.direction(0.0, 1.0, 1.0, kx / ky).expect("a direction");
    assert!((ux - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12 && (ux + uy).abs() < 1e-12);
}

#[test]
fn data_never_paints_outside_the_frame() {
    let c = chart(
        Axis::linear(0.0, 1.0, "x"),
        Axis::linear(0.0, 1.0, "y"),
        400,
        300,
    );
    let mut pixmap = blank(&c);
    let thick = LineStyle::solid(Color::BLACK, 9.0);
    c.polyline(
        &mut pixmap,
        [(-1e9, -1e9), (0.5, 0.5), (1e12, -3.0)],
        &thick,
    );
    c.markers(
        &mut pixmap,
        [(0.0, 0.0), (1.0, 1.0), (1.0, 0.0)],
        &MarkerStyle::new(MarkerShape::Square, 30.0, Color::BLACK),
    );
    c.arrow(
        &mut pixmap,
        (0.9, 0.9),
        (0.5, 0.5),
        &ArrowStyle::new(Color::BLACK, 3.0),
    );
    c.fill_rect(&mut pixmap, (-5.0, -5.0), (0.1, 5.0), Color::BLACK);
    let (x0, y0, x1, y1) = ink_box(&pixmap).expect("something was drawn");
    let p = c.plot_area();
    // The frame is one pixel wide; the inside starts one pixel in.
    assert_eq!((x0 as i32, y0 as i32), (p.left() + 1, p.top() + 1));
    assert_eq!((x1 as i32, y1 as i32), (p.right() - 2, p.bottom() - 2));
}

#[test]
fn points_a_log_axis_cannot_show_break_the_line() {
    let c = chart(
        Axis::linear(0.0, 4.0, "t"),
        Axis::log10(1e-3, 1e1, "E"),
        400,
        300,
    );
    let mut pixmap = blank(&c);
    let style = LineStyle::solid(Color::BLACK, 1.5);
    c.polyline(
        &mut pixmap,
        [(0.0, 1.0), (1.0, 0.0), (2.0, -1.0), (3.0, f64::NAN)],
        &style,
    );
    assert_eq!(
        ink_box(&pixmap),
        None,
        "no two neighbouring points can be shown"
    );
    c.polyline(
        &mut pixmap,
        [(0.0, 1.0), (1.0, 0.0), (3.0, 1.0), (4.0, 1.0)],
        &style,
    );
    let (x0, _, _, _) = ink_box(&pixmap).expect("the last two points are joined");
    assert!(x0 as f32 >= c.to_px(3.0, 1.0).0 - 1.0);
}

#[test]
fn heatmap_cells_tile_without_gaps() {
    let c = chart(
        Axis::linear(0.0, 7.0, "x"),
        Axis::linear(0.0, 3.0, "y"),
        417,
        311,
    );
    let mut pixmap = blank(&c);
    let edges = |n: usize, max: f64| {
        (0..=n)
            .map(|i| max * i as f64 / n as f64)
            .collect::<Vec<_>>()
    };
    let color = |i: usize, j: usize| Color::from_rgba8((i * 30) as u8, (j * 80) as u8, 128, 255);
    c.fill_cells(&mut pixmap, &edges(7, 7.0), &edges(3, 3.0), color);
    let p = c.plot_area();
    for y in p.top() + 1..p.bottom() - 1 {
        for x in p.left() + 1..p.right() - 1 {
            let alpha = pixmap.pixel(x as u32, y as u32).map(|p| p.alpha());
            assert_eq!(alpha, Some(255), "pixel ({x}, {y})");
        }
    }
}

/// Lays out a chart and checks that its text boxes neither overlap each other nor
/// leave the region, and that the plot area lies inside the region.
fn check_layout(spec: ChartSpec, width: u32, height: u32) {
    let c = Chart::new(spec, width, height).expect("a valid chart");
    let theme = &c.spec.theme;
    let font = Font::dejavu_sans();
    let p = c.plot_area();
    assert!(p.left() > 0 && p.top() > 0);
    assert!(p.right() < width as i32 && p.bottom() < height as i32);
    assert!(c.x_ticks().major.len() >= 2 && c.y_ticks().major.len() >= 2);
    let mut previous_right = f32::NEG_INFINITY;
    for t in &c.x_ticks().major {
        let w = font.measure(&t.label, theme.tick_label_px).width;
        let x = c.to_px(t.value, c.spec.y.min).0;
        assert!(
            x - 0.5 * w >= 0.0 && x + 0.5 * w <= width as f32,
            "{:?}",
            t.label
        );
        assert!(
            x - 0.5 * w > previous_right + 4.0,
            "x labels overlap at {:?}",
            t.label
        );
        previous_right = x + 0.5 * w;
    }
    // Y labels are centred half a cap height below their ink's digit tops.
    let half_cap = 0.5 * font.cap_height(theme.tick_label_px);
    let mut previous_top = f32::INFINITY;
    let mut boxes = Vec::new();
    for t in &c.y_ticks().major {
        let w = font.measure(&t.label, theme.tick_label_px).width;
        let (up, down) = font.ink_extent(&t.label, theme.tick_label_px);
        let y = c.to_px(c.spec.x.min, t.value).1;
        let (top, bottom) = (y + half_cap - up, y + half_cap + down);
        assert!(
            p.left() as f32 - w > 0.0,
            "y label {:?} leaves the region",
            t.label
        );
        assert!(
            bottom < previous_top - 4.0,
            "y labels overlap at {:?}",
            t.label
        );
        assert!(top >= 0.0, "y label {:?} leaves the region", t.label);
        previous_top = top;
        boxes.push((
            p.left() as f32 - theme.label_gap - w,
            top,
            p.left() as f32,
            bottom,
        ));
    }
    // No x label touches a y label, which can happen in the bottom-left corner.
    let baseline = c.x_label_baseline();
    for t in &c.x_ticks().major {
        let w = font.measure(&t.label, theme.tick_label_px).width;
        let (up, down) = font.ink_extent(&t.label, theme.tick_label_px);
        let x = c.to_px(t.value, c.spec.y.min).0;
        let b = (x - 0.5 * w, baseline - up, x + 0.5 * w, baseline + down);
        for a in &boxes {
            let apart = b.0 >= a.2 || a.0 >= b.2 || b.1 >= a.3 + 1.0 || a.1 >= b.3 + 1.0;
            assert!(apart, "x label {:?} {b:?} touches a y label {a:?}", t.label);
        }
    }
}

#[test]
fn layouts_keep_labels_apart_and_inside() {
    let spec = |x: Axis, y: Axis| ChartSpec::new(x, y).title("A title");
    check_layout(
        spec(Axis::linear(-2.0, 2.0, "x"), Axis::linear(-1.0, 4.0, "y")),
        800,
        600,
    );
    check_layout(
        spec(Axis::linear(0.0, 1e7, "n"), Axis::linear(-3e-5, 3e-5, "e")),
        800,
        600,
    );
    check_layout(
        spec(
            Axis::linear(-1234.5, 98765.4, "x"),
            Axis::linear(0.0, 1.0, ""),
        ),
        400,
        300,
    );
    check_layout(
        spec(Axis::log10(1e-12, 1.0, "h"), Axis::log10(1e-9, 1e-2, "err")),
        400,
        300,
    );
    check_layout(
        spec(Axis::log10(2.0, 60.0, "n"), Axis::linear(0.0, 0.7, "")),
        320,
        240,
    );
    let big = ChartSpec::new(
        Axis::linear(0.0, 5.0, "t (s)"),
        Axis::linear(-0.5, 2.5, "v (m/s)"),
    )
    .theme(Theme::default().scaled(2.0));
    check_layout(big, 1600, 1200);
}

#[test]
fn bad_specs_are_errors() {
    let ok = Axis::linear(0.0, 1.0, "");
    let new = |x: Axis, y: Axis, w, h| Chart::new(ChartSpec::new(x, y), w, h).map(|_| ());
    assert!(matches!(
        new(Axis::linear(1.0, 1.0, ""), ok.clone(), 400, 300),
        Err(ChartError::BadRange { axis: "x", .. })
    ));
    assert!(matches!(
        new(ok.clone(), Axis::linear(0.0, f64::NAN, ""), 400, 300),
        Err(ChartError::BadRange { axis: "y", .. })
    ));
    assert!(matches!(
        new(ok.clone(), Axis::log10(0.0, 1.0, ""), 400, 300),
        Err(ChartError::LogRangeNotPositive { axis: "y", .. })
    ));
    assert!(matches!(
        new(ok.clone(), ok.clone(), 40, 30),
        Err(ChartError::TooSmall { .. })
    ));
    let region = IntRect::from_xywh(500, 0, 400, 300).expect("a rect");
    assert!(matches!(
        Chart::in_region(ChartSpec::new(ok.clone(), ok), 800, 300, region),
        Err(ChartError::RegionOutsideCanvas { .. })
    ));
}

#[test]
fn a_chart_in_a_region_stays_in_it() {
    let region = IntRect::from_xywh(400, 20, 380, 260).expect("a rect");
    let spec = ChartSpec::new(Axis::linear(0.0, 1.0, "x"), Axis::linear(0.0, 1.0, "y"))
        .title("right half")
        .legend_entry(LegendEntry::line(
            LineStyle::solid(Color::BLACK, 1.5),
            "a line",
        ));
    let c = Chart::in_region(spec, 800, 300, region).expect("a valid chart");
    let mut pixmap = Pixmap::new(800, 300).expect("a canvas");
    c.draw_static(&mut pixmap);
    c.polyline(
        &mut pixmap,
        [(0.0, 0.0), (1.0, 1.0)],
        &LineStyle::solid(Color::BLACK, 2.0),
    );
    c.draw_legend(&mut pixmap);
    assert_eq!(ink_box(&pixmap), Some((400, 20, 779, 279)));
}

#[test]
fn the_static_part_is_deterministic_and_reusable() {
    let spec = ChartSpec::new(Axis::linear(0.0, 5.0, "t"), Axis::log10(1e-3, 1e1, "E"))
        .title("Energy")
        .grid(true);
    let a = Chart::new(spec.clone(), 640, 480)
        .expect("a valid chart")
        .static_pixmap();
    let b = Chart::new(spec, 640, 480).expect("a valid chart");
    let mut frame = b.static_pixmap();
    assert_eq!(a.data(), frame.data());
    b.polyline(
        &mut frame,
        [(0.0, 1.0), (5.0, 2.0)],
        &LineStyle::solid(Color::BLACK, 1.5),
    );
    assert_ne!(a.data(), frame.data());
    // Copying the static pixmap resets a frame.
    frame.data_mut().copy_from_slice(a.data());
    assert_eq!(a.data(), frame.data());
}

#[test]
fn liang_barsky_clipping() {
    let bounds = (0.0, 0.0, 10.0, 10.0);
    assert_eq!(
        clip_segment((-5.0, 5.0), (15.0, 5.0), bounds),
        Some(((0.0, 5.0), (10.0, 5.0)))
    );
    assert_eq!(
        clip_segment((1.0, 1.0), (2.0, 2.0), bounds),
        Some(((1.0, 1.0), (2.0, 2.0)))
    );
    assert_eq!(clip_segment((-5.0, -5.0), (-1.0, 20.0), bounds), None);
    assert_eq!(clip_segment((11.0, 0.0), (20.0, 10.0), bounds), None);
}
