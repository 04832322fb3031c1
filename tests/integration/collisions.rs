//! Collisions against closed forms: the restitution law at every impulse, the
//! conservation laws of an impulse, an elastic gas that keeps its energy, rebound
//! heights in the ratio e², the spin of an off-centre hit, and a disc far too fast for
//! its step that still bounces off a thin wall.
//!
//! Tolerances: an impulse is a handful of multiplications and additions, so the
//! restitution law, momentum and energy hold to a few ulps of the quantities involved:
//! 1e-12 relative allows for that with room. Over a whole run the errors of thousands
//! of impulses add up; where a test allows more it says why.

use glam::DVec2;
use physframes::scene::Scene;
use physframes::sim::rigid::perp_dot;
use physframes::sim::{ContactEvent, IntegratorKind, Simulation};

use crate::util::{scene, stderr, Sandbox};

fn assert_close(actual: f64, expected: f64, relative: f64, what: &str) {
    let scale = expected.abs().max(1e-300);
    assert!(
        (actual - expected).abs() <= relative * scale,
        "{what}: got {actual}, expected {expected} (relative error {:e}, allowed {relative:e})",
        (actual - expected).abs() / scale
    );
}

/// Runs a scene's simulation to its end, recording every impulse, and calls `each`
/// after every step with the simulation and the impulses of that step.
fn run(
    scene: &Scene,
    integrator: IntegratorKind,
    mut each: impl FnMut(&Simulation, &[ContactEvent]),
) -> Vec<ContactEvent> {
    let mut sim = scene.simulation_with(integrator);
    sim.record_contacts(true);
    let mut all = Vec::new();
    for _ in 0..scene.total_steps() {
        sim.step().expect("no blow-up and no overlap");
        let events = sim.take_contact_events();
        each(&sim, &events);
        all.extend(events);
    }
    all
}

/// The restitution each row's pair uses: the larger of its two bodies' values.
fn pair_restitution(scene: &Scene, e: &ContactEvent) -> f64 {
    let c = scene.contacts.as_ref().expect("the scene collides");
    let of = |i: usize| scene.bodies[i].restitution.unwrap_or(c.restitution);
    of(e.a).max(of(e.b))
}

fn assert_restitution_law(scene: &Scene, events: &[ContactEvent]) {
    for e in events {
        let law = -pair_restitution(scene, e) * e.vn_before;
        assert!(
            e.vn_before < 0.0,
            "an impulse only where the bodies approach: {e:?}"
        );
        assert!(
            (e.vn_after - law).abs() <= 1e-12 * e.vn_before.abs(),
            "vn_after = {} but -e·vn_before = {law} at t = {}",
            e.vn_after,
            e.t
        );
    }
}

#[test]
fn equal_discs_head_on_with_e_1_swap_velocities() {
    let s = scene(
        r#"
        [simulation]
        dt = 0.01
        duration = 1.0
        [render]
        view = { min = [-3.0, -2.0], max = [3.0, 2.0] }
        fps = 10
        [contacts]
        [[body]]
        name = "left"
        mass = 2.0
        position = [-1.0, 0.0]
        velocity = [1.5, 0.0]
        shape = { circle = { radius = 0.25 } }
        [[body]]
        name = "right"
        mass = 2.0
        position = [1.0, 0.0]
        velocity = [-0.5, 0.0]
        shape = { circle = { radius = 0.25 } }
        "#,
    );
    let events = run(&s, IntegratorKind::Euler, |_, _| {});
    assert_eq!(events.len(), 1, "one collision: {events:?}");
    let mut sim = s.simulation();
    sim.advance_to(1.0).expect("finite");
    let v = &sim.state().vel;
    assert_close(v[0].x, -0.5, 1e-12, "left after");
    assert_close(v[1].x, 1.5, 1e-12, "right after");
    assert_eq!((v[0].y, v[1].y), (0.0, 0.0));
    // They met when 1.5 apart (centres) minus the radii: 1.5/2 = 0.75 s... at
    // t = (2 - 0.5)/(1.5 + 0.5) = 0.75.
    assert_close(events[0].t, 0.75, 1e-12, "time of impact");
    assert_restitution_law(&s, &events);
}

/// Free bodies of every shape, spinning and not, colliding with each other and nothing
/// else: no force acts, so momentum and angular momentum about the origin may change
/// only by round-off, impulse after impulse.
fn free_mixture(e: f64) -> Scene {
    let mut text = format!(
        r#"
        [simulation]
        dt = 0.004
        duration = 4.0
        [render]
        view = {{ min = [-6.0, -6.0], max = [6.0, 6.0] }}
        fps = 25
        [contacts]
        restitution = {e}
        "#
    );
    let shapes = [
        "{ circle = { radius = 0.3 } }",
        "{ box = { width = 0.7, height = 0.35 } }",
        "{ polygon = { points = [[0.0, 0.0], [0.6, 0.1], [0.2, 0.5]] } }",
        "{ circle = { radius = 0.2 } }",
    ];
    for i in 0..16 {
        let (x, y) = ((i % 4) as f64 * 1.6 - 2.4, (i / 4) as f64 * 1.6 - 2.4);
        // Everyone heads roughly for the middle, at different speeds and spins.
        let (vx, vy) = (-x * (0.6 + 0.05 * i as f64), -y * (0.5 + 0.03 * i as f64));
        text.push_str(&format!(
            "[[body]]\nmass = {}\nposition = [{x}, {y}]\nvelocity = [{vx}, {vy}]\nangle = {}\nangular_velocity = {}\nshape = {}\n",
            1.0 + 0.3 * (i % 3) as f64,
            0.2 * i as f64,
            if i % 2 == 0 { 1.5 } else { -0.7 },
            shapes[i % 4],
        ));
    }
    scene(&text)
}

#[test]
fn every_impulse_keeps_momentum_and_angular_momentum_and_the_restitution_law() {
    // Inelastic impulses between turning polygons can end in sustained contact (a box
    // rocking against another), which impulses alone answer only by ever shorter
    // bounces: that is resting contact, the next issue's. Plastic impulses are tested
    // on discs below, whose contacts cannot trap a spin.
    for e in [1.0, 0.6] {
        let s = free_mixture(e);
        let system = s.system();
        let sim0 = s.simulation();
        let p0 = system.momentum(&sim0.state().vel);
        let l0 = sim0.system().angular_momentum(sim0.state(), DVec2::ZERO);
        // The scales the round-off is measured against: Σ m|v| and Σ (|r|·m|v| + I|ω|).
        let st = sim0.state();
        let p_scale: f64 = s
            .bodies
            .iter()
            .zip(&st.vel)
            .map(|(b, v)| b.mass * v.length())
            .sum();
        let l_scale: f64 = s
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                b.mass * st.pos[i].length() * st.vel[i].length() + b.inertia * st.omega[i].abs()
            })
            .sum();
        let mut impulses = 0;
        let events = run(&s, IntegratorKind::Euler, |sim, step| {
            impulses += step.len();
            let p = sim.system().momentum(&sim.state().vel);
            let l = sim.system().angular_momentum(sim.state(), DVec2::ZERO);
            assert!(
                (p - p0).length() <= 1e-12 * p_scale,
                "e = {e}: momentum {p} from {p0}"
            );
            // Positions grow by up to |v|·t over the run, which the scale at t = 0
            // does not include: allow the scale at the end (|r| at most 6 + 4·|v|).
            assert!(
                (l - l0).abs() <= 1e-12 * 4.0 * l_scale,
                "e = {e}: angular momentum {l} from {l0} at t = {}",
                sim.state().t
            );
        });
        assert!(impulses >= 10, "e = {e}: only {impulses} impulses");
        assert_restitution_law(&s, &events);
    }
}

/// A row of touching discs struck at one end, as Newton's cradle.
fn cradle(e: f64) -> Scene {
    let mut text = format!(
        r#"
        [simulation]
        dt = 0.01
        duration = 1.0
        [render]
        view = {{ min = [-2.0, -1.0], max = [4.0, 1.0] }}
        fps = 10
        [contacts]
        restitution = {e}
        [[body]]
        name = "striker"
        mass = 1.0
        position = [-1.0, 0.0]
        velocity = [2.0, 0.0]
        shape = {{ circle = {{ radius = 0.1 }} }}
        "#
    );
    for k in 0..4 {
        text.push_str(&format!(
            "[[body]]\nmass = 1.0\nposition = [{}, 0.0]\nshape = {{ circle = {{ radius = 0.1 }} }}\n",
            0.2 * k as f64
        ));
    }
    scene(&text)
}

#[test]
fn newtons_cradle_passes_the_strike_down_the_row_within_one_step() {
    // Elastic: the striker stops, the touching discs pass its momentum on impact by
    // impact at one instant (in body order), and the last leaves at its speed.
    let s = cradle(1.0);
    let events = run(&s, IntegratorKind::Euler, |_, _| {});
    assert_eq!(events.len(), 4, "{events:?}");
    // At one instant, but for the round-off in where the discs were placed.
    assert!(
        events.iter().all(|e| (e.t - events[0].t).abs() < 1e-12),
        "one instant: {events:?}"
    );
    assert_restitution_law(&s, &events);
    let mut sim = s.simulation();
    sim.advance_to(1.0).expect("finite");
    let v: Vec<f64> = sim.state().vel.iter().map(|v| v.x).collect();
    for (k, vk) in v.iter().enumerate().take(4) {
        assert!(vk.abs() <= 1e-12, "disc {k} moves at {vk}");
    }
    assert_close(v[4], 2.0, 1e-12, "the last disc");
    // Plastic: the row moves on together at a fifth of the speed (momentum 2 shared by
    // mass 5), every impulse leaving its pair at v_n' = 0.
    let s = cradle(0.0);
    let events = run(&s, IntegratorKind::Euler, |_, _| {});
    assert_restitution_law(&s, &events);
    let mut sim = s.simulation();
    sim.advance_to(1.0).expect("finite");
    // Impulse by impulse the discs' speeds approach 0.4 geometrically, and the
    // impacts stop once the pairs close at less than APPROACH_EPSILON = 1e-9 of their
    // speeds (about 1e-9 m/s here): each disc is within a few of those of 0.4.
    let vel = &sim.state().vel;
    for v in vel {
        assert!((v.x - 0.4).abs() <= 1e-8, "{v}");
    }
    let p: f64 = vel.iter().map(|v| v.x).sum();
    assert_close(p, 2.0, 1e-12, "momentum");
}

#[test]
fn elastic_impulses_keep_the_kinetic_energy() {
    let s = free_mixture(1.0);
    let sim0 = s.simulation();
    let e0 = sim0.system().kinetic_energy(sim0.state());
    let events = run(&s, IntegratorKind::Euler, |sim, step| {
        if !step.is_empty() {
            let e = sim.system().kinetic_energy(sim.state());
            assert_close(e, e0, 1e-12, "kinetic energy after an impulse");
        }
    });
    assert!(!events.is_empty());
}

#[test]
fn an_elastic_gas_keeps_its_energy_and_no_two_discs_overlap() {
    // 200 discs, e = 1, no forces, in a box of four static walls, for 10 s.
    let s = scene(
        r#"
        [simulation]
        dt = 0.005
        duration = 10.0
        [render]
        view = { min = [-0.5, -0.5], max = [10.5, 10.5] }
        fps = 20
        [contacts]
        [[swarm]]
        name = "gas"
        count = 200
        seed = 3
        mass = 1.0
        layout = "grid"
        position = { min = [0.0, 0.0], max = [10.0, 10.0] }
        velocity = { min = [-3.0, -3.0], max = [3.0, 3.0] }
        shape = { circle = { radius = 0.15 } }
        [[body]]
        name = "floor"
        static = true
        position = [5.0, -0.25]
        shape = { box = { width = 11.0, height = 0.5 } }
        [[body]]
        name = "ceiling"
        static = true
        position = [5.0, 10.25]
        shape = { box = { width = 11.0, height = 0.5 } }
        [[body]]
        name = "left"
        static = true
        position = [-0.25, 5.0]
        shape = { box = { width = 0.5, height = 10.0 } }
        [[body]]
        name = "right"
        static = true
        position = [10.25, 5.0]
        shape = { box = { width = 0.5, height = 10.0 } }
        "#,
    );
    let sim0 = s.simulation();
    let e0 = sim0.system().kinetic_energy(sim0.state());
    let tol = 1e-6 * 0.3;
    let mut frames = 0;
    let mut steps = 0u64;
    let events = run(&s, IntegratorKind::Euler, |sim, _| {
        steps += 1;
        if !steps.is_multiple_of(s.render.steps_per_frame) {
            return;
        }
        frames += 1;
        // No two discs overlap by more than the tolerance, and none leaves the box.
        // The four walls are bodies 0 to 3 ([[body]] tables come before swarms).
        let pos = &sim.state().pos[4..];
        for (i, p) in pos.iter().enumerate() {
            assert!(
                p.x >= 0.15 - tol && p.x <= 9.85 + tol && p.y >= 0.15 - tol && p.y <= 9.85 + tol,
                "disc {i} left the box: {p}"
            );
            for (j, q) in pos.iter().enumerate().take(i) {
                let gap = (*p - *q).length() - 0.3;
                assert!(gap >= -tol, "discs {j} and {i} overlap by {}", -gap);
            }
        }
    });
    assert_eq!(frames, 200);
    assert!(
        events.len() > 2000,
        "thousands of collisions: {}",
        events.len()
    );
    let mut sim = s.simulation();
    sim.advance_to(10.0).expect("finite");
    let e = sim.system().kinetic_energy(sim.state());
    // Each impulse keeps the energy to a few ulps; thousands of them stay far below
    // 1e-9 of it.
    assert_close(e, e0, 1e-9, "kinetic energy after 10 s");
    assert_restitution_law(&s, &events);
}

/// A ball dropped from 1 m above a static floor, with restitution e.
fn dropped_ball(e: f64, integrator: &str, dt: f64) -> Scene {
    scene(&format!(
        r#"
        [simulation]
        integrator = "{integrator}"
        dt = {dt}
        duration = 2.0
        [render]
        view = {{ min = [-1.0, -0.5], max = [1.0, 1.5] }}
        fps = 10
        [contacts]
        restitution = {e}
        [[body]]
        name = "floor"
        static = true
        position = [0.0, -0.5]
        shape = {{ box = {{ width = 2.0, height = 1.0 }} }}
        [[body]]
        name = "ball"
        mass = 0.5
        position = [0.0, 1.1]
        shape = {{ circle = {{ radius = 0.1 }} }}
        [[force]]
        kind = "gravity"
        bodies = ["ball"]
        "#
    ))
}

/// Returns the heights above the floor of the ball's bottom at each apex after the
/// first bounce: from the last state that rises (vy > 0) before it falls, as the top
/// of the parabola through it, y + vy²/(2g).
fn apexes(s: &Scene, integrator: IntegratorKind) -> Vec<f64> {
    let mut out = Vec::new();
    let mut last = (0.0, 0.0);
    run(s, integrator, |sim, _| {
        let st = sim.state();
        let (y, vy) = (st.pos[1].y, st.vel[1].y);
        if last.1 > 0.0 && vy <= 0.0 {
            out.push(last.0 + last.1 * last.1 / (2.0 * 9.81) - 0.1);
        }
        last = (y, vy);
    });
    out
}

#[test]
fn rebound_heights_fall_in_the_ratio_e_squared() {
    for e in [0.9, 0.7, 0.5] {
        // rk4 is exact for a constant force, so within a step the path departs from
        // the true parabola only by being its chord: after an impact at λ the state is
        // off the parabola by (1 - λ)·λ·g·h²/2 ≤ g·h²/8 = 1.2e-6 m at h = 1e-3 (the
        // velocity, linear in t, is exact). The apex is read off the exact parabola
        // through a state, so each rebound height is within a few g·h²/8 of e² times
        // the one before; g·h² = 9.8e-6 m allows eight. Heights of a few
        // centimetres, where this is 1e-4 relative, are as low as the test goes.
        let s = dropped_ball(e, "rk4", 0.001);
        let h = apexes(&s, IntegratorKind::Rk4);
        assert!(h.len() >= 2, "e = {e}: apexes {h:?}");
        let allowed = 9.81 * 1e-6;
        assert!(
            (h[0] - e * e).abs() <= allowed,
            "e = {e}: first rebound {}",
            h[0]
        );
        for w in h.windows(2).filter(|w| w[0] > 0.02) {
            assert!(
                (w[1] - e * e * w[0]).abs() <= allowed,
                "e = {e}: rebound {} after {}: ratio {} for e² = {}",
                w[1],
                w[0],
                w[1] / w[0],
                e * e
            );
        }
    }
    // Explicit Euler is first order: its rebounds approach e² as h halves.
    let err = |dt: f64| {
        let s = dropped_ball(0.8, "euler", dt);
        let h = apexes(&s, IntegratorKind::Euler);
        (h[1] / h[0] - 0.64).abs()
    };
    let (coarse, fine) = (err(0.002), err(0.001));
    assert!(fine < 0.01, "Euler at h = 1e-3: ratio off by {fine}");
    assert!(fine < 0.75 * coarse, "first order: {coarse} then {fine}");
}

#[test]
fn a_box_hit_off_centre_starts_to_spin_by_the_lever_of_the_impulse() {
    // A box flying left at a static wall, turned so that one corner strikes first.
    let s = scene(
        r#"
        [simulation]
        dt = 0.001
        duration = 1.0
        [render]
        view = { min = [-3.0, -2.0], max = [3.0, 2.0] }
        fps = 10
        [contacts]
        restitution = 0.5
        [[body]]
        name = "wall"
        static = true
        position = [-2.0, 0.0]
        shape = { box = { width = 0.2, height = 4.0 } }
        [[body]]
        name = "box"
        mass = 2.0
        position = [0.0, 0.1]
        velocity = [-3.0, 0.0]
        angle = 0.3
        shape = { box = { width = 1.0, height = 0.5 } }
        "#,
    );
    let inertia = s.bodies[1].inertia;
    assert_close(inertia, 2.0 * (1.0 + 0.25) / 12.0, 1e-15, "I of the box");
    let mut sim = s.simulation();
    sim.record_contacts(true);
    let mut first: Option<(ContactEvent, f64, DVec2)> = None;
    while first.is_none() {
        let before = (sim.state().omega[1], sim.state().pos[1]);
        sim.step().expect("finite");
        if let Some(e) = sim.take_contact_events().first() {
            let _ = before;
            first = Some((*e, sim.state().omega[1], sim.state().pos[1]));
        }
    }
    let (e, omega, _) = first.expect("it hits");
    // The wall is body a (index 0); the box is b, and takes -j along n at P.
    assert_eq!((e.a, e.b), (0, 1));
    // No torque acts, so the spin at the step's end is the impulse's:
    // ω = r_BP⊥·(-j·n)/I, with r_BP from the box's centre at the instant of impact.
    // That centre is where the box was at t_impact: it moved at (-3, 0) until then.
    let centre = DVec2::new(0.0 - 3.0 * e.t, 0.1);
    let expected = perp_dot(e.point - centre, -e.impulse * e.normal) / inertia;
    assert!(expected.abs() > 0.1, "a real spin: {expected}");
    assert_close(omega, expected, 1e-9, "ω after the hit");
}

#[test]
fn a_disc_at_1000_metres_a_second_bounces_off_a_one_centimetre_wall() {
    // dt = 0.01: the disc moves 10 m a step, a thousand times the wall's thickness.
    let s = scene(
        r#"
        [simulation]
        dt = 0.01
        duration = 1.0
        [render]
        view = { min = [-20.0, -5.0], max = [20.0, 5.0] }
        fps = 10
        [contacts]
        [[body]]
        name = "wall"
        static = true
        position = [5.0, 0.0]
        shape = { box = { width = 0.01, height = 2.0 } }
        [[body]]
        name = "bullet"
        mass = 0.01
        position = [0.0, 0.0]
        velocity = [1000.0, 0.0]
        shape = { circle = { radius = 0.05 } }
        "#,
    );
    let events = run(&s, IntegratorKind::Euler, |sim, _| {
        assert!(sim.state().pos[1].x < 5.0, "the bullet passed the wall");
    });
    assert_eq!(events.len(), 1);
    let mut sim = s.simulation();
    sim.advance_to(1.0).expect("finite");
    assert_close(sim.state().vel[1].x, -1000.0, 1e-12, "bounced back");
    // It touched the wall's face at x = 4.995 with its edge: at t = 4.945/1000.
    assert_close(events[0].t, 4.945 / 1000.0, 1e-9, "time of impact");
}

#[test]
fn every_integrator_bounces_a_ball_and_keeps_it_out_of_the_floor() {
    for kind in IntegratorKind::ALL {
        let s = dropped_ball(0.8, kind.name(), 0.002);
        let events = run(&s, *kind, |sim, _| {
            let bottom = sim.state().pos[1].y - 0.1;
            assert!(
                bottom >= -1e-6 * 0.2,
                "{kind}: the ball is {bottom} into the floor"
            );
        });
        assert!(events.len() >= 3, "{kind}: {} impulses", events.len());
        assert_restitution_law(&s, &events);
        let h = apexes(&s, *kind);
        // Every method rebounds to about e² = 0.64 of the drop: within its own error.
        assert!((h[0] - 0.64).abs() < 0.02, "{kind}: first rebound {}", h[0]);
    }
}

#[test]
fn the_collision_log_is_written_by_export_and_render_and_obeys_the_law() {
    let dir = Sandbox::new();
    let path = std::path::PathBuf::from(crate::util::example("bounce.toml"));
    let s = Scene::load(&path).expect("the example is valid");
    let out = dir.run(&[
        "export",
        path.to_str().expect("utf-8"),
        "--out",
        dir.path("t.csv").to_str().expect("utf-8"),
        "--events",
        dir.path("export-events.csv").to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = dir.run(&[
        "render",
        path.to_str().expect("utf-8"),
        "--out",
        dir.path("frames").to_str().expect("utf-8"),
        "--events",
        dir.path("render-events.csv").to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let a = std::fs::read_to_string(dir.path("export-events.csv")).expect("written");
    let b = std::fs::read_to_string(dir.path("render-events.csv")).expect("written");
    assert_eq!(a, b, "export and render log the same impulses");
    let mut lines = a.lines();
    assert_eq!(
        lines.next(),
        Some("t,a,b,px,py,nx,ny,vn_before,vn_after,impulse,jt")
    );
    let names = s.body_names();
    let mut rows = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 11, "{line}");
        let num = |k: usize| f[k].parse::<f64>().expect("a number");
        let (ia, ib) = (
            names.iter().position(|n| *n == f[1]).expect("a body name"),
            names.iter().position(|n| *n == f[2]).expect("a body name"),
        );
        let c = s.contacts.as_ref().expect("collides");
        let e = [ia, ib]
            .iter()
            .map(|&i| s.bodies[i].restitution.unwrap_or(c.restitution))
            .fold(0.0, f64::max);
        assert!(
            (num(5).hypot(num(6)) - 1.0).abs() < 1e-12,
            "unit normal: {line}"
        );
        assert!(
            (num(8) + e * num(7)).abs() <= 1e-12 * num(7).abs(),
            "vn_after = -e·vn_before: {line}"
        );
        rows += 1;
    }
    assert!(rows >= 5, "{rows} rows");
}

#[test]
fn bad_contact_keys_are_located_errors_and_nothing_is_written() {
    let base = r#"
        [simulation]
        dt = 0.01
        duration = 1.0
        [render]
        view = { min = [-3.0, -3.0], max = [3.0, 3.0] }
        fps = 10
    "#;
    let cases: &[(&str, &str)] = &[
        ("[contacts]\nrestitution = 1.5\n[[body]]\nmass = 1.0\n", "`restitution` must be between 0 and 1"),
        ("[contacts]\ntolerance = 0.0\n[[body]]\nmass = 1.0\n", "`tolerance` must be > 0"),
        ("[contacts]\nbodies = []\n[[body]]\nmass = 1.0\n", "nothing collides"),
        ("[contacts]\n[[body]]\nmass = 1.0\nrestitution = -0.1\n", "`restitution` must be between 0 and 1"),
        ("[[body]]\nstatic = true\nmass = 1.0\n", "static body `body0` cannot have `mass`"),
        ("[[body]]\nstatic = true\nvelocity = [1.0, 0.0]\n", "cannot have `velocity`"),
        ("[[body]]\nstatic = true\nangular_velocity = 1.0\n", "cannot have `angular_velocity`"),
        (
            "[[body]]\nname = \"floor\"\nstatic = true\n[[force]]\nkind = \"gravity\"\nbodies = [\"floor\"]\n",
            "body `floor` is static, so no force acts on it",
        ),
        (
            "[contacts]\n[[body]]\nname = \"arrow\"\nmass = 1.0\nshape = { polygon = { points = [[0.0, 0.0], [2.0, 1.0], [0.0, 2.0], [0.5, 1.0]] } }\n",
            "its polygon is not convex",
        ),
        (
            "[contacts]\nbodies = [\"dumbbell\"]\n[[body]]\nname = \"dumbbell\"\npoints = [{ offset = [0.0, 0.0], mass = 1.0 }, { offset = [1.0, 0.0], mass = 1.0 }]\n",
            "made of point masses, which do not collide",
        ),
        (
            "[contacts]\n[[body]]\nname = \"a\"\nmass = 1.0\nshape = { circle = { radius = 0.5 } }\n[[body]]\nname = \"b\"\nmass = 1.0\nposition = [0.8, 0.0]\nshape = { circle = { radius = 0.5 } }\n",
            "bodies `a` and `b` overlap by 2.000e-1 at t = 0",
        ),
        // 10^5 discs on one spot: about 5·10^9 overlapping pairs, which the check
        // neither lists (it once ran out of memory doing so) nor counts.
        (
            "[contacts]\n[[swarm]]\nname = \"heap\"\ncount = 100000\nmass = 1.0\nposition = { min = [0.0, 0.0], max = [0.001, 0.001] }\nshape = { circle = { radius = 0.1 } }\n",
            "at least 99994 more pairs of colliding bodies overlap at t = 0",
        ),
        (
            "[contacts]\n[[body]]\nmass = 1.0\n[[swarm]]\nname = \"s\"\ncount = 2\nmass = 1.0\nlayout = \"spiral\"\nposition = { min = [0.0, 0.0], max = [1.0, 1.0] }\n",
            "unknown layout `spiral`",
        ),
    ];
    let dir = Sandbox::new();
    for (k, (tail, message)) in cases.iter().enumerate() {
        let name = format!("bad{k}.toml");
        let path = dir.write(&name, &format!("{base}{tail}"));
        let out_dir = dir.path(&format!("out{k}"));
        let out = dir.run(&[
            "render",
            path.to_str().expect("utf-8"),
            "--out",
            out_dir.to_str().expect("utf-8"),
        ]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "case {k}: {err}");
        assert!(
            err.contains(message),
            "case {k}: expected {message:?} in\n{err}"
        );
        assert!(
            err.contains(&format!("{name}:")),
            "case {k}: located: {err}"
        );
        assert!(!out_dir.exists(), "case {k}: nothing written");
    }
}

/// Static bodies may overlap (a floor of several boxes), so 20,000 of them piled on one
/// spot are a valid scene, which the check at t = 0 passes without looking at their
/// 2·10^8 pairs; one disc dropped into the pile overlaps them all, and the check names
/// five of its pairs and counts the rest from where it stopped.
#[test]
fn a_pile_of_static_bodies_is_checked_without_its_pairs() {
    let mut text = String::from(
        "[simulation]\ndt = 0.01\nduration = 0.1\n[render]\nfps = 25\nview = { min = [-1.0, -1.0], max = [1.0, 1.0] }\n[contacts]\n",
    );
    for _ in 0..20_000 {
        text.push_str("[[body]]\nstatic = true\nshape = { circle = { radius = 0.1 } }\n");
    }
    let dir = Sandbox::new();
    let valid = dir.write("statics.toml", &text);
    let out = dir.run(&["check", valid.to_str().expect("utf-8")]);
    assert!(out.status.success(), "{}", stderr(&out));
    text.push_str(
        "[[body]]\nname = \"dropped\"\nmass = 1.0\nshape = { circle = { radius = 0.1 } }\n",
    );
    let bad = dir.write("dropped.toml", &text);
    let out = dir.run(&["check", bad.to_str().expect("utf-8")]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("and `dropped` overlap by 2.000e-1 at t = 0"),
        "{err}"
    );
    assert!(err.contains("at least 19995 more pairs"), "{err}");
    // The count of the pairs left unlisted comes after the five it follows, though it
    // points at no line of the file (which would sort it first).
    let (listed, more) = (
        err.rfind("overlap by").expect("the pairs listed"),
        err.find("more pairs").expect("the count"),
    );
    assert!(listed < more, "the count after the pairs listed: {err}");
}

#[test]
fn a_sharded_render_of_a_colliding_scene_equals_a_single_run_byte_for_byte() {
    let path = crate::util::example("billiards.toml");
    crate::util::assert_shards_equal_a_single_run(
        &path,
        "5",
        &["--threads", "1"],
        [&["--threads", "2"], &["--threads", "1"]],
    );
}
