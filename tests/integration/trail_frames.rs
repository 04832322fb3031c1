//! Frames with trails drawn and encoded against the last frame a worker drew
//! (`Renderer::draw_trail_frame`, `FrameCoder`): the pixels are those of a whole
//! redraw, the tiles marked as changed hold every pixel that changed, and the PNG is
//! the bits of a fresh encoding, whichever frames the worker drew before.

use glam::DVec2;
use physframes::render::damage::TileMask;
use physframes::render::fastpng::FrameCoder;
use physframes::render::trails::TrailFrame;
use physframes::render::{ArrowScales, FrameView, Provenance, Renderer};

use crate::every_scene::{trail_history, user_scene};

/// Draws the frames `order` of a scene as one worker would (into one pixmap, with one
/// trail state and one coder), checking each against a whole redraw and a fresh
/// encoding. Turning bodies get an angle that changes with the frame. The frames
/// `whole_at` must mark every tile, the others tiles only (`None`: every frame whole).
fn check_worker(name: &str, text: &str, order: &[usize], whole_at: Option<&[usize]>) {
    let velocity = |k: usize, i: usize| DVec2::new(1.0 + i as f64 * 0.1, -0.5 * k as f64);
    check_worker_with(name, text, order, whole_at, &velocity);
}

/// [`check_worker`], with body i's velocity in frame k `velocity(k, i)`.
fn check_worker_with(
    name: &str,
    text: &str,
    order: &[usize],
    whole_at: Option<&[usize]>,
    velocity: &dyn Fn(usize, usize) -> DVec2,
) {
    let s = crate::util::scene(text);
    let renderer = Renderer::new(
        &s,
        ArrowScales {
            velocity: 0.3,
            force: 1.0,
        },
    );
    let frames = order.iter().max().expect("frames") + 1;
    let history = trail_history(&s, frames as u64);
    let (width, height) = (s.render.width, s.render.height);
    let mut pixmap = renderer.new_frame();
    let mut state = TrailFrame::new(width, height);
    let mut coder = FrameCoder::new(width, height).expect("readable");
    let mut before = pixmap.clone();
    for &k in order {
        let pos = history[k].last().expect("a frame").clone();
        let vel: Vec<DVec2> = (0..pos.len()).map(|i| velocity(k, i)).collect();
        let angle: Vec<f64> = (0..pos.len())
            .map(|i| 0.37 * (k * (i + 1)) as f64)
            .collect();
        let view = FrameView {
            index: k as u64,
            t: s.frame_time(k as u64),
            pos: &pos,
            vel: &vel,
            angle: Some(&angle),
            force: None,
            trail: Some(&history[k]),
            traces: None,
            compare: None,
        };
        renderer.draw_trail_frame(&view, &mut pixmap, &mut state);
        let whole = renderer.draw(&view);
        // And those are the pixels of every pass drawn over the whole frame (the
        // path shared by redraws could hide a mistake from the comparison above).
        assert!(
            whole.data() == renderer.draw_every_pass(&view).data(),
            "{name}, frame {k}: differs from every pass drawn whole"
        );
        assert!(
            pixmap.data() == whole.data(),
            "{name}, frame {k}: differs from a whole redraw"
        );
        // Every pixel that changed since the last frame lies in a marked tile.
        let changed = state.changed();
        assert_eq!(
            changed.is_whole(),
            whole_at.is_none_or(|w| w.contains(&k)),
            "{name}, frame {k}: whole or tiles"
        );
        if !changed.is_whole() {
            let outside = crate::util::change_outside(changed, &pixmap, &before);
            assert!(
                outside.is_none(),
                "{name}, frame {k}: pixel {outside:?} changed outside the marked tiles"
            );
        }
        let provenance = Provenance::default().with("physframes:frame", k);
        let ours = coder.encode(&pixmap, changed, &provenance).to_vec();
        let fresh = FrameCoder::new(width, height)
            .expect("readable")
            .encode(&pixmap, &TileMask::new(width, height), &provenance)
            .to_vec();
        assert!(ours == fresh, "{name}, frame {k}: the PNG differs");
        let decoder = png::Decoder::new(std::io::Cursor::new(&ours));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
        reader.next_frame(&mut pixels).expect("pixels");
        assert!(
            pixels == pixmap.data(),
            "{name}, frame {k}: the PNG decodes to other pixels"
        );
        before = pixmap.clone();
    }
}

#[test]
fn trail_frames_drawn_against_the_frame_before_are_those_of_a_whole_redraw() {
    // Bodies in the default colours, circles, boxes and triangles mixed, some leaving
    // the image; a worker that draws every frame, one that jumps over frames another
    // drew, and one that goes back to an earlier frame (its layer starts again).
    let mixed = user_scene(60, 0, true, false);
    check_worker("mixed", &mixed, &(0..24).collect::<Vec<_>>(), Some(&[0]));
    check_worker("jumping", &mixed, &[0, 2, 3, 7, 8, 15, 23, 39], Some(&[0]));
    check_worker("back", &mixed, &[10, 11, 4, 5, 6], Some(&[10, 4]));
    // Turning boxes and triangles.
    let turning = user_scene(60, 0, true, true);
    check_worker("turning", &turning, &[0, 1, 3, 5, 6, 9, 30], Some(&[0]));
    // Boxes and triangles of their own sizes, all turning, enough to be drawn by the
    // scan converter (a turned box marks the box of its corners); and the same never
    // turning, each at an angle of its own (the box of its outline).
    let mut scanned = String::from(
        "[simulation]\nduration = 2.0\n[render]\nwidth = 320\nheight = 180\nfps = 20\ntrails = true\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    for i in 0..24 {
        let (w, h) = (0.2 + 0.006 * i as f64, 0.12 + 0.007 * (i % 7) as f64);
        let shape = if i % 2 == 0 {
            format!("{{ box = {{ width = {w:.3}, height = {h:.3} }} }}")
        } else {
            format!(
                "{{ polygon = {{ points = [[{:.3}, {:.3}], [{w:.3}, 0.0], [0.0, {h:.3}]] }} }}",
                -w, -h
            )
        };
        scanned.push_str(&format!(
            "[[body]]\nmass = 1.0\nposition = [{:.2}, {:.2}]\nvelocity = [{:.2}, {:.2}]\nangle = {:.2}\nangular_velocity = 1.5\nshape = {shape}\n",
            0.6 + (i % 8) as f64 * 1.9,
            0.8 + (i / 8) as f64 * 2.6,
            ((i % 5) as f64 - 2.0) * 0.5,
            ((i % 3) as f64 - 1.0) * 0.6,
            0.3 * i as f64,
        ));
    }
    check_worker("scanned", &scanned, &[0, 1, 2, 5, 6, 9, 17], Some(&[0]));
    let fixed = scanned.replace("angular_velocity = 1.5\n", "");
    assert!(!fixed.contains("angular_velocity"), "none turns");
    check_worker(
        "scanned, fixed",
        &fixed,
        &[0, 1, 2, 5, 6, 9, 17],
        Some(&[0]),
    );
    // Arrows over the trails mark the tiles they may change, row by row (pixels
    // changed outside them fail above), on every third body; on every body the marks
    // pass a third of the frame's tiles, and every tile is marked instead (60 bodies:
    // 40 marked less once bodies that never turn marked the boxes of their outlines).
    let arrows = user_scene(40, 3, true, false);
    check_worker("arrows", &arrows, &[0, 1, 2, 5, 6, 7], Some(&[0]));
    let every = user_scene(60, 1, true, true);
    check_worker("every arrow", &every, &[0, 1, 4, 5, 9, 10], None);
    // Long arrows in frames 2 and 5, short ones in the others: a frame whose arrows
    // mark more than a third of the tiles is coded whole, and so is the frame after
    // it, which restores them, but the frame after that is coded by tiles again. (So
    // arrows drawn over a whole frame still mark what the next frame must restore.)
    let long = |k: usize, i: usize| match k {
        2 | 5 => DVec2::new(0.2 * (i % 5) as f64, -30.0),
        _ => DVec2::new(0.5, 0.1 * (i % 3) as f64),
    };
    let some = user_scene(40, 1, true, false);
    check_worker_with(
        "long arrows",
        &some,
        &(0..8).collect::<Vec<_>>(),
        Some(&[0, 2, 3, 5, 6]),
        &long,
    );
    // Springs' coils over the trails mark their tiles, as arrows do: covered by
    // distance for 16 springs or more, tiny-skia's strokes for fewer; between a body
    // and the one that starts nearest it, and from a body to a fixed point near where
    // it starts. Springs across the frame, whose coils would mark more than an eighth
    // of its tiles, leave every frame whole instead.
    let start = |i: usize| {
        // Body i's starting position, as user_scene places it.
        let k = (i * 7919) % 97;
        DVec2::new(
            0.3 + (k as f64 * 0.161) % 15.4,
            0.3 + (i as f64 * 0.377) % 8.4,
        )
    };
    let springs_over = |bodies: String, n: usize, partner: &dyn Fn(usize) -> Option<usize>| {
        let mut text = bodies.replacen(
            "width = 320\nheight = 180\n",
            "width = 640\nheight = 360\nshow_springs = true\n",
            1,
        );
        assert!(text.contains("show_springs"), "springs shown");
        for i in 0..n {
            let b = match partner(i) {
                Some(j) => format!("\"body{j}\""),
                None => format!("[{:.3}, {:.3}]", start(i).x + 1.0, start(i).y - 0.5),
            };
            text.push_str(&format!(
                "[[force]]\nkind = \"spring\"\na = \"body{i}\"\nb = {b}\nstiffness = 0.5\n"
            ));
        }
        text
    };
    let springs = |n: usize, partner: &dyn Fn(usize) -> Option<usize>| {
        springs_over(user_scene(40, 0, true, false), n, partner)
    };
    let nearest = |i: usize| {
        i.is_multiple_of(4).then(|| {
            (0..40)
                .filter(|&j| j != i)
                .min_by(|&a, &b| {
                    let (da, db) = (start(a) - start(i), start(b) - start(i));
                    da.length().total_cmp(&db.length())
                })
                .expect("another body")
        })
    };
    let order = [0, 1, 2, 5, 6, 9, 10, 13];
    check_worker("springs", &springs(20, &nearest), &order, Some(&[0]));
    check_worker("few springs", &springs(6, &nearest), &order, Some(&[0]));
    let across = |i: usize| Some((i + 20) % 40);
    check_worker("springs across", &springs(20, &across), &order, None);
    // The HUD over the trails: its box is marked with the bodies, not every tile,
    // and its text, which changes every frame, is right in every frame.
    let hud = mixed.replacen("[render]\n", "[render]\nhud = true\n", 1);
    assert!(hud.contains("hud = true"), "the HUD is on");
    check_worker("hud", &hud, &[0, 1, 2, 3, 7, 8, 15], Some(&[0]));
    // With axes, the plot's margins go back to the static layer where bodies, arrows,
    // springs or trails drew over them, tile by tile: bodies leaving the plot, with
    // arrows on some, springs to fixed points and the HUD; and a frame made whole by
    // long arrows, whose margins are restored whole, and the frames after it.
    let axes = |text: &str| {
        let text = text.replacen(
            "width = 320\nheight = 180\n",
            "width = 640\nheight = 360\n",
            1,
        );
        format!("{text}\n[axes]\ntitle = \"Trails\"\nx_label = \"x (m)\"\ny_label = \"y (m)\"\n")
    };
    check_worker(
        "axes",
        &axes(&mixed),
        &(0..12).collect::<Vec<_>>(),
        Some(&[0]),
    );
    let hud_arrows =
        user_scene(40, 3, true, true).replacen("[render]\n", "[render]\nhud = true\n", 1);
    check_worker("axes, arrows, hud", &axes(&hud_arrows), &order, Some(&[0]));
    check_worker(
        "axes, springs",
        &axes(&springs(20, &nearest)),
        &order,
        Some(&[0]),
    );
    // A legend over the trails, redrawn in its box every frame as the HUD is.
    let legend = format!(
        "{}legend = \"bottom-right\"\n[[curve]]\nkind = \"exact\"\ny = \"0.5*x\"\nlabel = \"y = x/2\"\n",
        axes(&hud_arrows)
    );
    check_worker("axes, legend", &legend, &order, Some(&[0]));
    // Everything at once: axes with a grid, a legend at the bottom left and the HUD,
    // turning shapes with arrows on some, springs; and axes on an image too small to
    // leave them a plot area, drawn without them.
    let all = format!(
        "{}grid = true\nlegend = \"bottom-left\"\n[[curve]]\nkind = \"exact\"\ny = \"9 - 0.5*x\"\nlabel = \"a line\"\n",
        axes(
            &springs_over(user_scene(40, 3, true, true), 20, &nearest).replacen(
                "[render]\n",
                "[render]\nhud = true\n",
                1
            )
        )
    );
    check_worker("everything", &all, &order, Some(&[0]));
    let tiny = format!(
        "{}\n[axes]\ntitle = \"Trails\"\n",
        mixed.replacen(
            "width = 320\nheight = 180\n",
            "width = 96\nheight = 54\n",
            1,
        )
    );
    assert!(tiny.contains("width = 96"), "a tiny image");
    check_worker("tiny axes", &tiny, &order, None);
    // (At 320 × 180, where the long arrows mark more than a third of the tiles.)
    let small_axes = format!("{some}\n[axes]\ntitle = \"Trails\"\n");
    check_worker_with(
        "axes, long arrows",
        &small_axes,
        &(0..8).collect::<Vec<_>>(),
        Some(&[0, 2, 3, 5, 6]),
        &long,
    );
}
