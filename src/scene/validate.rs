//! Validation: from the raw file to a checked [`Scene`], reporting every problem at once.

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;

use glam::DVec2;
use sha2::{Digest, Sha256};
use toml::Spanned;

use super::raw::{
    RawBody, RawForce, RawRange, RawRender, RawScalarRange, RawScene, RawShape, RawSimulation,
    RawSwarm, RawVec2,
};
use super::swarm::{member_spin, member_state, split_member_name, Uniform1, Uniform2};
use super::{
    Body, CompareRun, Diagnostic, PointMass, RenderSettings, Rgba, Scene, SceneError, Shape,
    SimulationSettings, Source, View,
};
use crate::sim::{Anchor, ForceSpec, IntegratorKind, Selection, Tolerances};

/// The largest image side accepted, in pixels.
pub const MAX_IMAGE_SIDE: i64 = 16384;
/// The largest number of frames a scene may ask for.
pub const MAX_FRAMES: u64 = 1_000_000;
/// The largest number of bodies a scene may declare, swarms included.
pub const MAX_BODIES: u64 = 10_000_000;
/// How close 1/fps must be to a whole number of steps, relative.
const WHOLE_STEPS_TOLERANCE: f64 = 1e-9;

/// Parses and validates the text of a scene file read from `path`.
pub fn parse(path: &Path, text: &str) -> Result<Scene, SceneError> {
    super::frontend::parse(path, text, &[])
}

/// Checks every rule on a raw scene that fits the schema. Returns the scene when every
/// rule holds, and every problem found.
pub(super) fn check(path: &Path, text: &str, raw: RawScene) -> (Option<Scene>, Vec<Diagnostic>) {
    let mut v = Validator::default();
    let scene = v.scene(path, text, raw);
    (scene, v.diagnostics)
}

/// Collects diagnostics while turning raw values into checked ones. Each check returns
/// `None` after recording a problem, so validation goes on and reports them all.
#[derive(Default)]
struct Validator {
    diagnostics: Vec<Diagnostic>,
}

/// The force keys other than `kind`, in the order the schema lists them.
const FORCE_KEYS: &[&str] = &[
    "bodies",
    "g",
    "k",
    "c",
    "f0",
    "f1",
    "a",
    "b",
    "stiffness",
    "rest_length",
    "damping",
    "centre",
    "strength",
    "tau",
    "at",
    "a_at",
    "b_at",
];

/// The force kinds and the keys each takes.
const FORCE_KINDS: &[(&str, &[&str])] = &[
    ("gravity", &["g", "bodies"]),
    ("drag", &["k", "bodies"]),
    ("quadratic-drag", &["c", "bodies"]),
    ("force", &["f0", "f1", "at", "bodies"]),
    (
        "spring",
        &[
            "a",
            "b",
            "stiffness",
            "rest_length",
            "damping",
            "a_at",
            "b_at",
        ],
    ),
    ("central", &["centre", "strength", "bodies"]),
    ("torque", &["tau", "bodies"]),
    ("angular-drag", &["k", "bodies"]),
];

impl Validator {
    fn error(&mut self, d: Diagnostic) {
        self.diagnostics.push(d);
    }

    fn scene(&mut self, path: &Path, text: &str, raw: RawScene) -> Option<Scene> {
        let name = self.name(path, raw.name.as_ref());
        let render_raw = raw.render.as_ref();
        if render_raw.is_none() {
            self.error(
                Diagnostic::whole_file("the scene has no [render] table")
                    .hint("add [render] with at least `view = { min = [x0, y0], max = [x1, y1] }`"),
            );
        }
        let fps = render_raw
            .and_then(|r| r.get_ref().fps.as_ref())
            .map_or(Some(30.0), |f| self.positive(f, "fps"));
        let simulation = self.simulation(raw.simulation.as_ref(), fps);
        let view = render_raw.and_then(|r| self.view(r));
        let bodies = self.bodies(&raw.body, view);
        let render =
            render_raw.and_then(|r| self.render(r.get_ref(), simulation.as_ref(), fps, view));
        // Forces are checked against every body's name, valid or not, so that one bad
        // body does not hide the problems of the forces.
        let body_names: Vec<String> = raw
            .body
            .iter()
            .enumerate()
            .map(|(i, b)| {
                b.get_ref()
                    .name
                    .as_ref()
                    .map_or_else(|| format!("body{i}"), |n| n.get_ref().clone())
            })
            .collect();
        let (swarms, members) = self.swarms(&raw.swarm, &raw.body, &body_names, view);
        let names = Names::new(&body_names, &swarms);
        let forces = self.forces(&raw.force, &names);
        let layers = super::layers::LayerCheck {
            text,
            diagnostics: &mut self.diagnostics,
            // Traces name the scene's own bodies, whose indices come before any swarm's.
            bodies: &body_names,
            bodies_drawn: names.len() > 0
                && render_raw
                    .and_then(|r| r.get_ref().show_bodies.as_ref())
                    .is_none_or(|s| *s.get_ref()),
            view,
        }
        .run(raw.axes.as_ref(), &raw.field, &raw.curve);
        if let (Some(bodies), Some(render)) = (&bodies, &render) {
            self.shapes_fit_the_rasteriser(&raw.body, bodies, render);
        }
        if let (Some(members), Some(render)) = (&members, &render) {
            self.swarm_shapes_fit_the_rasteriser(&raw.swarm, &swarms, members, render);
        }
        let bodies = match (bodies, members) {
            (Some(mut bodies), Some(members)) => {
                bodies.extend(members);
                Some(bodies)
            }
            _ => None,
        };
        if let (Some(sim), Some(bodies), Some(forces)) = (&simulation, &bodies, &forces) {
            self.exact_exists(raw.simulation.as_ref(), sim, bodies, forces);
        }
        let hash = hex(&Sha256::digest(text.as_bytes()));
        let (mut bodies, forces) = (bodies?, forces?);
        super::mark_turning(&mut bodies, &forces);
        self.turning_bodies_have_inertia(&raw.body, &bodies)?;
        Some(Scene {
            name: name?,
            source: Source {
                path: path.to_path_buf(),
                hash,
                overrides: Vec::new(),
            },
            simulation: simulation?,
            render: render?,
            bodies,
            forces,
            layers: layers?,
        })
    }

    /// Rejects a body that something turns but that has no moment of inertia: point
    /// masses that all sit at its centre of mass (a swarm's shapes always have one).
    fn turning_bodies_have_inertia(
        &mut self,
        raw: &[Spanned<RawBody>],
        bodies: &[Body],
    ) -> Option<()> {
        let mut ok = true;
        for (r, b) in raw.iter().zip(bodies) {
            if b.turns && b.inertia == 0.0 {
                self.error(
                    Diagnostic::at(
                        r.span(),
                        format!("body `{}` is turned but has no moment of inertia", b.name),
                    )
                    .label("its point masses all sit at its centre of mass, so I = 0")
                    .hint("give it `inertia = ...` (kg·m²), or spread its points out"),
                );
                ok = false;
            }
        }
        ok.then_some(())
    }

    /// Rejects bodies that would span more than a million pixels on screen.
    fn shapes_fit_the_rasteriser(
        &mut self,
        raw: &[Spanned<RawBody>],
        bodies: &[Body],
        render: &RenderSettings,
    ) {
        let scale = render.view.fit_scale(render.width, render.height);
        for (b, rb) in bodies.iter().zip(raw) {
            let pixels = b.shape.reach() * scale;
            if pixels > super::MAX_SHAPE_PIXELS {
                let span = rb.get_ref().shape.as_ref().map_or(rb.span(), |s| s.span());
                self.error(
                    Diagnostic::at(
                        span,
                        format!("body `{}` would span {pixels:.3e} pixels", b.name),
                    )
                    .label("far larger than the image")
                    .hint("check the units: the shape is measured in world units, like the view"),
                );
            }
        }
    }

    fn name(&mut self, path: &Path, raw: Option<&Spanned<String>>) -> Option<String> {
        let (name, span) = match raw {
            Some(s) => (s.get_ref().clone(), Some(s.span())),
            None => (
                path.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                None,
            ),
        };
        let ok = !name.is_empty()
            && !name.starts_with('.')
            && name
                .chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '.'));
        if ok {
            return Some(name);
        }
        let d = match span {
            Some(span) => Diagnostic::at(span, format!("scene name `{name}` cannot name a folder")),
            None => Diagnostic::whole_file(format!(
                "the file's stem `{name}` cannot name the output folder"
            )),
        };
        self.error(
            d.label("used as the output folder's name")
                .hint("use letters, digits, `-`, `_` and `.`, not starting with `.`"),
        );
        None
    }

    fn simulation(
        &mut self,
        raw: Option<&Spanned<RawSimulation>>,
        fps: Option<f64>,
    ) -> Option<SimulationSettings> {
        let Some(raw) = raw else {
            // Without a [simulation] table: explicit Euler, 5 s, ten steps a frame.
            return fps.map(|fps| SimulationSettings {
                integrator: IntegratorKind::Euler,
                dt: 1.0 / (10.0 * fps),
                duration: 5.0,
                tolerances: Tolerances::default(),
                compare: Vec::new(),
            });
        };
        let s = raw.get_ref();
        let integrator = match &s.integrator {
            None => Some(IntegratorKind::Euler),
            Some(name) => match name.get_ref().parse::<IntegratorKind>() {
                Ok(kind) => Some(kind),
                Err(message) => {
                    self.error(
                        Diagnostic::at(name.span(), message)
                            .label("not an integrator physframes knows"),
                    );
                    None
                }
            },
        };
        let duration = match &s.duration {
            Some(d) => self.positive(d, "duration"),
            None => Some(5.0),
        };
        let dt = match (&s.dt, fps) {
            (Some(dt), _) => self.positive(dt, "dt"),
            (None, Some(fps)) => Some(1.0 / (10.0 * fps)),
            (None, None) => None,
        };
        if let (Some(dt), Some(fps), Some(span)) = (dt, fps, s.dt.as_ref().map(|d| d.span())) {
            self.whole_steps_per_frame(dt, fps, span)?;
        }
        let defaults = Tolerances::default();
        let rtol = s
            .rtol
            .as_ref()
            .map_or(Some(defaults.rtol), |r| self.positive(r, "rtol"));
        let atol = s
            .atol
            .as_ref()
            .map_or(Some(defaults.atol), |a| self.positive(a, "atol"));
        let compare = match &s.compare {
            None => Some(Vec::new()),
            Some(list) => self.compare(list),
        };
        Some(SimulationSettings {
            integrator: integrator?,
            dt: dt?,
            duration: duration?,
            tolerances: Tolerances {
                rtol: rtol?,
                atol: atol?,
            },
            compare: compare?,
        })
    }

    /// Rejects `compare = [..., "exact"]` when the scene has no closed form.
    fn exact_exists(
        &mut self,
        raw: Option<&Spanned<RawSimulation>>,
        sim: &SimulationSettings,
        bodies: &[Body],
        forces: &[ForceSpec],
    ) {
        if !sim.compare.contains(&CompareRun::Exact) {
            return;
        }
        let masses: Vec<f64> = bodies.iter().map(|b| b.mass).collect();
        let initial = crate::sim::State::new(
            0.0,
            bodies.iter().map(|b| b.position).collect(),
            bodies.iter().map(|b| b.velocity).collect(),
        );
        if crate::sim::exact::ExactSolution::new(&masses, forces, &initial).is_some() {
            return;
        }
        let span = raw
            .and_then(|r| r.get_ref().compare.as_ref())
            .and_then(|c| c.get_ref().iter().find(|n| n.get_ref() == "exact"))
            .map(|n| n.span());
        let message = "this scene has no closed-form solution to compare with";
        let d = match span {
            Some(span) => Diagnostic::at(span, message),
            None => Diagnostic::whole_file(message),
        };
        self.error(d.hint(
            "the exact path exists when every force is gravity, linear drag, a time-varying force, or an undamped zero-length spring to a fixed point; remove \"exact\" or compare integrators only",
        ));
    }

    /// Checks `compare`: integrator names or "exact", each at most once.
    fn compare(&mut self, list: &Spanned<Vec<Spanned<String>>>) -> Option<Vec<CompareRun>> {
        let mut runs = Vec::new();
        let mut ok = true;
        for name in list.get_ref() {
            let run = if name.get_ref() == "exact" {
                CompareRun::Exact
            } else {
                match name.get_ref().parse::<IntegratorKind>() {
                    Ok(kind) => CompareRun::Integrator(kind),
                    Err(message) => {
                        self.error(
                            Diagnostic::at(name.span(), message)
                                .hint("`compare` takes integrator names and \"exact\""),
                        );
                        ok = false;
                        continue;
                    }
                }
            };
            if runs.contains(&run) {
                self.error(Diagnostic::at(
                    name.span(),
                    format!("`{}` is listed twice", name.get_ref()),
                ));
                ok = false;
            }
            runs.push(run);
        }
        ok.then_some(runs)
    }

    /// Checks that 1/fps is a whole number of steps; returns that number.
    fn whole_steps_per_frame(&mut self, dt: f64, fps: f64, span: Range<usize>) -> Option<u64> {
        let interval = 1.0 / fps;
        let ratio = interval / dt;
        let nearest = ratio.round();
        if nearest >= 1.0 && (ratio - nearest).abs() <= WHOLE_STEPS_TOLERANCE * ratio {
            return Some(nearest as u64);
        }
        let below = ratio.floor().max(1.0);
        let above = ratio.ceil().max(1.0);
        let option = |n: f64| {
            format!(
                "dt = {} ({} step{} a frame)",
                interval / n,
                n,
                if n == 1.0 { "" } else { "s" }
            )
        };
        let hint = if below == above {
            format!("the nearest valid value is {}", option(below))
        } else {
            format!(
                "the nearest valid values are {} and {}",
                option(below),
                option(above)
            )
        };
        self.error(
            Diagnostic::at(
                span,
                format!(
                    "the frame interval 1/fps = {interval} is not a whole number of steps of dt = {dt} ({ratio:.6} steps)"
                ),
            )
            .label("each frame must fall on a step")
            .hint(hint),
        );
        None
    }

    fn render(
        &mut self,
        r: &RawRender,
        sim: Option<&SimulationSettings>,
        fps: Option<f64>,
        view: Option<View>,
    ) -> Option<RenderSettings> {
        let width = self.image_side(r.width.as_ref(), "width", 800);
        let height = self.image_side(r.height.as_ref(), "height", 600);
        let background = match &r.background {
            Some(c) => self.color(c),
            None => Some(Rgba::WHITE),
        };
        let trails = r.trails.as_ref().is_some_and(|t| *t.get_ref());
        let hud = r.hud.as_ref().is_some_and(|h| *h.get_ref());
        let show_bodies = r.show_bodies.as_ref().is_none_or(|s| *s.get_ref());
        let show_springs = r.show_springs.as_ref().is_some_and(|s| *s.get_ref());
        let velocity_scale = r
            .velocity_scale
            .as_ref()
            .map(|s| self.positive(s, "velocity_scale"));
        let force_scale = r
            .force_scale
            .as_ref()
            .map(|s| self.positive(s, "force_scale"));
        let (sim, fps) = (sim?, fps?);
        let steps_per_frame = (1.0 / fps / sim.dt).round().max(1.0) as u64;
        // k = 0 ..= floor(duration·fps); the small relative allowance keeps 0.7·30 = 21
        // from flooring to 20 through rounding.
        let last = (sim.duration * fps * (1.0 + WHOLE_STEPS_TOLERANCE)).floor();
        if last + 1.0 > MAX_FRAMES as f64 {
            let d = Diagnostic::whole_file(format!(
                "duration × fps asks for {} frames, more than the limit of {MAX_FRAMES}",
                last + 1.0
            ))
            .hint("shorten `duration` or lower `fps`");
            self.error(d);
            return None;
        }
        Some(RenderSettings {
            width: width?,
            height: height?,
            fps,
            view: view?,
            background: background?,
            trails,
            hud,
            show_bodies,
            show_springs,
            velocity_scale: velocity_scale.map_or(Some(None), |s| s.map(Some))?,
            force_scale: force_scale.map_or(Some(None), |s| s.map(Some))?,
            steps_per_frame,
            frame_count: last as u64 + 1,
        })
    }

    fn view(&mut self, r: &Spanned<RawRender>) -> Option<View> {
        let Some(view) = &r.get_ref().view else {
            self.error(Diagnostic::at(r.span(), "[render] has no `view`").hint(
                "add `view = { min = [x0, y0], max = [x1, y1] }`: the world rectangle to show",
            ));
            return None;
        };
        let v = view.get_ref();
        let min = self.vec2(&v.min, "view.min")?;
        let max = self.vec2(&v.max, "view.max")?;
        if min.x < max.x && min.y < max.y {
            return Some(View { min, max });
        }
        self.error(
            Diagnostic::at(view.span(), "the view is empty")
                .label("min must be below max on both axes")
                .hint(format!(
                    "min = [{}, {}] and max = [{}, {}] leave no area",
                    min.x, min.y, max.x, max.y
                )),
        );
        None
    }

    fn image_side(&mut self, raw: Option<&Spanned<i64>>, key: &str, default: u32) -> Option<u32> {
        let Some(raw) = raw else {
            return Some(default);
        };
        let v = *raw.get_ref();
        if (1..=MAX_IMAGE_SIDE).contains(&v) {
            return Some(v as u32);
        }
        self.error(
            Diagnostic::at(
                raw.span(),
                format!("`{key}` must be from 1 to {MAX_IMAGE_SIDE} pixels"),
            )
            .label(format!("{v} pixels")),
        );
        None
    }

    fn bodies(&mut self, raw: &[Spanned<RawBody>], view: Option<View>) -> Option<Vec<Body>> {
        let mut seen: HashMap<String, Range<usize>> = HashMap::new();
        let mut bodies = Vec::with_capacity(raw.len());
        let mut ok = true;
        // The default radius: 1.5% of the view's smaller side, so a body is visible
        // whatever the scale of the world.
        let default_radius = view.map_or(0.1, |v| 0.015 * (v.max - v.min).min_element());
        for (i, rb) in raw.iter().enumerate() {
            match self.body(i, rb, default_radius) {
                Some(body) => {
                    let span = rb.get_ref().name.as_ref().map_or(rb.span(), |n| n.span());
                    if seen.contains_key(&body.name) {
                        self.error(
                            Diagnostic::at(span, format!("two bodies are named `{}`", body.name))
                                .label("a second body with this name")
                                .hint("forces name bodies, so each name must be unique"),
                        );
                        ok = false;
                    } else {
                        seen.insert(body.name.clone(), span);
                    }
                    bodies.push(body);
                }
                None => ok = false,
            }
        }
        ok.then_some(bodies)
    }

    /// Checks every `[[swarm]]` and builds its members, which follow the `[[body]]`
    /// bodies in file order. Returns the swarms' names and index ranges (for forces,
    /// even when a member is invalid) and the members.
    fn swarms(
        &mut self,
        raw: &[Spanned<RawSwarm>],
        raw_bodies: &[Spanned<RawBody>],
        body_names: &[String],
        view: Option<View>,
    ) -> (Vec<SwarmName>, Option<Vec<Body>>) {
        let mut names = Vec::new();
        let mut members = Vec::new();
        let mut ok = true;
        let mut first = raw_bodies.len() as u64;
        let default_radius = view.map_or(0.1, |v| 0.015 * (v.max - v.min).min_element());
        for rs in raw {
            let s = rs.get_ref();
            let name = self.swarm_name(&s.name, &names, raw_bodies, body_names);
            let count = *s.count.get_ref();
            let count = if count < 1 || first + count as u64 > MAX_BODIES {
                self.error(
                    Diagnostic::at(
                        s.count.span(),
                        format!("`count` must be from 1 to {}", MAX_BODIES - first),
                    )
                    .label(format!("{count} bodies"))
                    .hint(format!(
                        "a scene holds at most {MAX_BODIES} bodies, swarms included"
                    )),
                );
                None
            } else {
                Some(count as u64)
            };
            let seed = match &s.seed {
                None => Some(0),
                Some(seed) if *seed.get_ref() >= 0 => Some(*seed.get_ref() as u64),
                Some(seed) => {
                    self.error(
                        Diagnostic::at(seed.span(), "`seed` must be ≥ 0")
                            .label(format!("{} is negative", seed.get_ref())),
                    );
                    None
                }
            };
            let mass = self.positive(&s.mass, "mass");
            let angle = self.optional_scalar_range(s.angle.as_ref(), "angle");
            let spin = self.optional_scalar_range(s.angular_velocity.as_ref(), "angular_velocity");
            let position = self.range(&s.position, "position");
            let velocity = match &s.velocity {
                Some(v) => self.range(v, "velocity"),
                None => Some(Uniform2 {
                    min: DVec2::ZERO,
                    max: DVec2::ZERO,
                }),
            };
            let shape = match &s.shape {
                Some(shape) => self.shape(shape),
                None => Some((
                    Shape::Circle {
                        radius: default_radius,
                    },
                    DVec2::ZERO,
                )),
            };
            let color = match &s.color {
                Some(c) => self.color(c),
                None => Some(Rgba::palette(first as usize)),
            };
            if let (Some(name), Some(count)) = (&name, count) {
                names.push(SwarmName {
                    name: name.clone(),
                    first: first as u32,
                    count: count as u32,
                });
            }
            let (
                Some(name),
                Some(count),
                Some(seed),
                Some(mass),
                Some(position),
                Some(velocity),
                Some((shape, centroid)),
                Some(color),
            ) = (name, count, seed, mass, position, velocity, shape, color)
            else {
                ok = false;
                first += count.unwrap_or(0);
                continue;
            };
            let (Some(angle), Some(spin)) = (angle, spin) else {
                ok = false;
                first += count;
                continue;
            };
            members.reserve(count as usize);
            let inertia = shape.inertia(mass);
            for i in 0..count {
                let (r, v) = member_state(seed, i, position, velocity);
                // A swarm that gives no angle or angular velocity draws none: its
                // members are the bodies it always gave.
                let (theta, omega) = match (angle, spin) {
                    (None, None) => (0.0, 0.0),
                    (angle, spin) => member_spin(
                        seed,
                        i,
                        angle.unwrap_or(Uniform1 { min: 0.0, max: 0.0 }),
                        spin.unwrap_or(Uniform1 { min: 0.0, max: 0.0 }),
                    ),
                };
                members.push(Body {
                    name: format!("{name}{i}"),
                    mass,
                    // As for a body, the centre of mass is the drawn position plus the
                    // shape's centroid (nonzero only for polygons), turned with it.
                    position: r + turned(theta, centroid),
                    velocity: v,
                    angle: theta,
                    angular_velocity: omega,
                    inertia,
                    centre: centroid,
                    turns: false,
                    shape: shape.clone(),
                    color,
                    show_velocity: false,
                    show_force: false,
                });
            }
            first += count;
        }
        (names, ok.then_some(members))
    }

    /// Checks a swarm's name: unique, not ending in a digit (so that member names
    /// of different swarms cannot meet), and clashing with no body.
    fn swarm_name(
        &mut self,
        raw: &Spanned<String>,
        earlier: &[SwarmName],
        raw_bodies: &[Spanned<RawBody>],
        body_names: &[String],
    ) -> Option<String> {
        let name = raw.get_ref();
        let valid = !name.is_empty() && !name.ends_with(|c: char| c.is_ascii_digit());
        if !valid {
            self.error(
                Diagnostic::at(
                    raw.span(),
                    format!("swarm name `{name}` cannot name members"),
                )
                .label("members are named by appending 0, 1, 2, …")
                .hint("use a name that does not end in a digit, e.g. \"dust\""),
            );
            return None;
        }
        if earlier.iter().any(|s| s.name == *name) {
            self.error(
                Diagnostic::at(raw.span(), format!("two swarms are named `{name}`"))
                    .hint("forces select a swarm by its name, so each must be unique"),
            );
            return None;
        }
        let mut ok = true;
        for (rb, body) in raw_bodies.iter().zip(body_names) {
            let clash =
                body == name || split_member_name(body).is_some_and(|(prefix, _)| prefix == name);
            if clash {
                let span = rb.get_ref().name.as_ref().map_or(rb.span(), |n| n.span());
                self.error(
                    Diagnostic::at(
                        span,
                        format!("body `{body}` has a name that swarm `{name}` uses"),
                    )
                    .label("clashes with the swarm or one of its members")
                    .hint(format!(
                        "swarm `{name}` names its members {name}0, {name}1, …; rename the body or the swarm"
                    )),
                );
                ok = false;
            }
        }
        ok.then(|| name.clone())
    }

    /// Rejects swarms whose shape would span more than a million pixels on screen.
    fn swarm_shapes_fit_the_rasteriser(
        &mut self,
        raw: &[Spanned<RawSwarm>],
        swarms: &[SwarmName],
        members: &[Body],
        render: &RenderSettings,
    ) {
        let scale = render.view.fit_scale(render.width, render.height);
        let mut start = 0usize;
        for (rs, s) in raw.iter().zip(swarms) {
            let Some(first) = members.get(start) else {
                return;
            };
            let pixels = first.shape.reach() * scale;
            if pixels > super::MAX_SHAPE_PIXELS {
                let span = rs.get_ref().shape.as_ref().map_or(rs.span(), |s| s.span());
                self.error(
                    Diagnostic::at(
                        span,
                        format!(
                            "the members of swarm `{}` would span {pixels:.3e} pixels",
                            s.name
                        ),
                    )
                    .label("far larger than the image")
                    .hint("check the units: the shape is measured in world units, like the view"),
                );
            }
            start += s.count as usize;
        }
    }

    /// Checks a rectangle `{ min = [x0, y0], max = [x1, y1] }` with min ≤ max.
    /// Checks an optional interval `{ min, max }` of finite numbers with min ≤ max:
    /// `Some(None)` when absent, `None` after an error.
    fn optional_scalar_range(
        &mut self,
        raw: Option<&Spanned<RawScalarRange>>,
        key: &str,
    ) -> Option<Option<Uniform1>> {
        let Some(raw) = raw else {
            return Some(None);
        };
        let r = raw.get_ref();
        let min = self.finite(&r.min, &format!("{key}.min"));
        let max = self.finite(&r.max, &format!("{key}.max"));
        let (min, max) = (min?, max?);
        if min <= max && (max - min).is_finite() {
            return Some(Some(Uniform1 { min, max }));
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` has min above max"))
                .label(format!("min = {min}, max = {max}"))
                .hint("give min ≤ max"),
        );
        None
    }

    fn range(&mut self, raw: &Spanned<RawRange>, key: &str) -> Option<Uniform2> {
        let r = raw.get_ref();
        let min = self.vec2(&r.min, &format!("{key}.min"));
        let max = self.vec2(&r.max, &format!("{key}.max"));
        let (min, max) = (min?, max?);
        if min.x <= max.x && min.y <= max.y && (max - min).is_finite() {
            return Some(Uniform2 { min, max });
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` has min above max"))
                .label("min must not exceed max on either axis")
                .hint(format!(
                    "min = [{}, {}] and max = [{}, {}]",
                    min.x, min.y, max.x, max.y
                )),
        );
        None
    }

    fn body(&mut self, i: usize, raw: &Spanned<RawBody>, default_radius: f64) -> Option<Body> {
        let b = raw.get_ref();
        let name = b
            .name
            .as_ref()
            .map_or_else(|| format!("body{i}"), |n| n.get_ref().clone());
        let position = match &b.position {
            Some(p) => self.vec2(p, "position"),
            None => Some(DVec2::ZERO),
        };
        let velocity = match &b.velocity {
            Some(v) => self.vec2(v, "velocity"),
            None => Some(DVec2::ZERO),
        };
        let color = match &b.color {
            Some(c) => self.color(c),
            None => Some(Rgba::palette(i)),
        };
        // The mass and the shape come together: either `mass` with an optional `shape`,
        // or `points`, from which both follow (Equations 7-11).
        let mass_and_shape = match (&b.mass, &b.points) {
            (Some(m), Some(p)) => {
                self.error(
                    Diagnostic::at(
                        p.span(),
                        format!("body `{name}` has both `mass` and `points`"),
                    )
                    .label("the mass of a body of points is the sum of its points' masses")
                    .hint(format!("remove `mass = {}` or `points`", m.get_ref())),
                );
                None
            }
            (None, None) => {
                self.error(
                    Diagnostic::at(raw.span(), format!("body `{name}` has no mass"))
                        .hint("add `mass = 1.0` (or `points = [...]` for a body of point masses)"),
                );
                None
            }
            (Some(m), None) => {
                let mass = self.positive(m, "mass");
                let shape = match &b.shape {
                    Some(s) => self.shape(s),
                    None => Some((
                        Shape::Circle {
                            radius: default_radius,
                        },
                        DVec2::ZERO,
                    )),
                };
                mass.zip(shape)
            }
            (None, Some(points)) => {
                if let Some(s) = &b.shape {
                    self.error(
                        Diagnostic::at(
                            s.span(),
                            format!("body `{name}` has both `shape` and `points`"),
                        )
                        .hint("a body of point masses is drawn as its points; remove `shape`"),
                    );
                    None
                } else {
                    self.point_masses(points)
                }
            }
        };
        let angle = b
            .angle
            .as_ref()
            .map_or(Some(0.0), |a| self.finite(a, "angle"));
        let angular_velocity = b
            .angular_velocity
            .as_ref()
            .map_or(Some(0.0), |w| self.finite(w, "angular_velocity"));
        let inertia = b.inertia.as_ref().map(|i| self.positive(i, "inertia"));
        let (mass, (shape, centroid)) = mass_and_shape?;
        let angle = angle?;
        let inertia = match inertia {
            Some(given) => given?,
            None => self.shape_inertia(raw, &name, &shape, mass)?,
        };
        Some(Body {
            name,
            mass,
            // The centre of mass sits at `position` plus the centroid of the shape or of
            // the point masses (Equation 8), turned with the body: r = p + R(θ)·c.
            position: position? + turned(angle, centroid),
            velocity: velocity?,
            angle,
            angular_velocity: angular_velocity?,
            inertia,
            centre: centroid,
            turns: false,
            shape,
            color: color?,
            show_velocity: b.show_velocity.as_ref().is_some_and(|s| *s.get_ref()),
            show_force: b.show_force.as_ref().is_some_and(|s| *s.get_ref()),
        })
    }

    /// Returns the moment of inertia of a shape of mass `mass`, or reports one too large
    /// to be a number (a huge mass and size) at the body.
    fn shape_inertia(
        &mut self,
        raw: &Spanned<RawBody>,
        name: &str,
        shape: &Shape,
        mass: f64,
    ) -> Option<f64> {
        let inertia = shape.inertia(mass);
        if inertia.is_finite() {
            return Some(inertia);
        }
        self.error(
            Diagnostic::at(
                raw.span(),
                format!("the moment of inertia of body `{name}` is too large to compute"),
            )
            .label(format!("M·r² overflows: {inertia}"))
            .hint("use smaller units, or give `inertia` yourself"),
        );
        None
    }

    /// Returns the shape, with vertices relative to its centroid, and that centroid
    /// relative to the body's `position`.
    fn shape(&mut self, raw: &Spanned<RawShape>) -> Option<(Shape, DVec2)> {
        let s = raw.get_ref();
        let given = [s.circle.is_some(), s.rect.is_some(), s.polygon.is_some()];
        if given.iter().filter(|g| **g).count() != 1 {
            self.error(
                Diagnostic::at(
                    raw.span(),
                    "a shape must be exactly one of `circle`, `box` or `polygon`",
                )
                .hint("e.g. shape = { circle = { radius = 0.2 } }"),
            );
            return None;
        }
        if let Some(c) = &s.circle {
            let radius = self.positive(&c.get_ref().radius, "radius")?;
            return Some((Shape::Circle { radius }, DVec2::ZERO));
        }
        if let Some(b) = &s.rect {
            let width = self.positive(&b.get_ref().width, "width");
            let height = self.positive(&b.get_ref().height, "height");
            return Some((
                Shape::Box {
                    width: width?,
                    height: height?,
                },
                DVec2::ZERO,
            ));
        }
        let polygon = s.polygon.as_ref()?;
        let points_raw = &polygon.get_ref().points;
        let mut points = Vec::new();
        for p in points_raw.get_ref() {
            points.push(self.vec2(p, "polygon point")?);
        }
        let (area, centroid) = polygon_area_centroid(&points);
        if points.len() < 3 || area == 0.0 || !area.is_finite() || !centroid.is_finite() {
            self.error(
                Diagnostic::at(
                    points_raw.span(),
                    "a polygon needs at least 3 points enclosing some area",
                )
                .label(format!("{} points, area {}", points.len(), area.abs())),
            );
            return None;
        }
        let points = points.into_iter().map(|p| p - centroid).collect();
        Some((Shape::Polygon { points }, centroid))
    }

    /// Returns the total mass, the shape of point masses (offsets relative to the
    /// centre of mass), and the centre of mass relative to the body's `position`.
    fn point_masses(
        &mut self,
        raw: &Spanned<Vec<Spanned<crate::scene::raw::RawPointMass>>>,
    ) -> Option<(f64, (Shape, DVec2))> {
        if raw.get_ref().is_empty() {
            self.error(
                Diagnostic::at(raw.span(), "`points` is empty")
                    .hint("give at least one point mass"),
            );
            return None;
        }
        let mut points = Vec::new();
        let mut ok = true;
        for p in raw.get_ref() {
            let offset = self.vec2(&p.get_ref().offset, "offset");
            let mass = self.positive(&p.get_ref().mass, "mass");
            match (offset, mass) {
                (Some(offset), Some(mass)) => points.push(PointMass { offset, mass }),
                _ => ok = false,
            }
        }
        if !ok {
            return None;
        }
        // M = Σ m_i; r_CM = Σ m_i·r_i / M (Equation 8), here relative to `position`.
        let total: f64 = points.iter().map(|p| p.mass).sum();
        let centre = points
            .iter()
            .fold(DVec2::ZERO, |acc, p| acc + p.mass * p.offset)
            / total;
        if !total.is_finite() || !centre.is_finite() {
            self.error(Diagnostic::at(
                raw.span(),
                "the point masses' total or centre of mass overflows",
            ));
            return None;
        }
        let points = points
            .into_iter()
            .map(|p| PointMass {
                offset: p.offset - centre,
                mass: p.mass,
            })
            .collect();
        Some((total, (Shape::Points { points }, centre)))
    }

    fn forces(&mut self, raw: &[Spanned<RawForce>], names: &Names) -> Option<Vec<ForceSpec>> {
        let mut forces = Vec::new();
        let mut ok = true;
        for f in raw {
            match self.force(f, names) {
                Some(force) => forces.push(force),
                None => ok = false,
            }
        }
        ok.then_some(forces)
    }

    fn force(&mut self, raw: &Spanned<RawForce>, names: &Names) -> Option<ForceSpec> {
        let f = raw.get_ref();
        let kind = f.kind.get_ref().as_str();
        let Some((_, allowed)) = FORCE_KINDS.iter().find(|(k, _)| *k == kind) else {
            let kinds: Vec<&str> = FORCE_KINDS.iter().map(|(k, _)| *k).collect();
            self.error(
                Diagnostic::at(f.kind.span(), format!("unknown force kind `{kind}`"))
                    .label("not a force physframes knows")
                    .hint(format!("expected one of: {}", kinds.join(", "))),
            );
            return None;
        };
        // Keys that belong to other kinds are mistakes, not silently ignored values.
        let mut stray = false;
        for (key, span) in present_force_keys(f) {
            if !allowed.contains(&key) {
                self.error(
                    Diagnostic::at(span, format!("`{key}` does not apply to a `{kind}` force"))
                        .label("not used by this kind")
                        .hint(format!("a `{kind}` force takes: {}", allowed.join(", "))),
                );
                stray = true;
            }
        }
        let bodies = self.selection(f.bodies.as_ref(), names);
        let spec = match kind {
            "gravity" => {
                let g = match &f.g {
                    Some(g) => self.vec2(g, "g"),
                    None => Some(DVec2::new(0.0, -9.81)),
                };
                ForceSpec::Gravity {
                    g: g?,
                    bodies: bodies?,
                }
            }
            "drag" => {
                let k = match &f.k {
                    Some(k) => self.non_negative(k, "k"),
                    None => Some(1.0),
                };
                ForceSpec::Drag {
                    k: k?,
                    bodies: bodies?,
                }
            }
            "quadratic-drag" => {
                let c = self.required(raw, &f.c, "c", "c = 0.1")?;
                let c = self.non_negative(c, "c");
                ForceSpec::QuadraticDrag {
                    c: c?,
                    bodies: bodies?,
                }
            }
            "force" => {
                let f0 =
                    f.f0.as_ref()
                        .map_or(Some(DVec2::ZERO), |v| self.vec2(v, "f0"));
                let f1 =
                    f.f1.as_ref()
                        .map_or(Some(DVec2::ZERO), |v| self.vec2(v, "f1"));
                let at = self.optional_vec2(f.at.as_ref(), "at");
                ForceSpec::TimeVarying {
                    f0: f0?,
                    f1: f1?,
                    bodies: bodies?,
                    at: at?,
                }
            }
            "torque" => {
                let tau = self.required(raw, &f.tau, "tau", "tau = 1.0")?;
                let tau = self.finite(tau, "tau");
                ForceSpec::Torque {
                    tau: tau?,
                    bodies: bodies?,
                }
            }
            "angular-drag" => {
                let k = self.required(raw, &f.k, "k", "k = 0.1")?;
                let k = self.non_negative(k, "k");
                ForceSpec::AngularDrag {
                    k: k?,
                    bodies: bodies?,
                }
            }
            "spring" => self.spring(raw, names)?,
            "central" => {
                let centre = f
                    .centre
                    .as_ref()
                    .map_or(Some(DVec2::ZERO), |v| self.vec2(v, "centre"));
                let strength = self.required(raw, &f.strength, "strength", "strength = 1.0")?;
                let strength = self.finite(strength, "strength");
                ForceSpec::Central {
                    centre: centre?,
                    strength: strength?,
                    bodies: bodies?,
                }
            }
            _ => return None,
        };
        (!stray).then_some(spec)
    }

    fn spring(&mut self, raw: &Spanned<RawForce>, names: &Names) -> Option<ForceSpec> {
        let f = raw.get_ref();
        let a_raw = self.required(raw, &f.a, "a", "a = \"first-body\"");
        let b_raw = self.required(raw, &f.b, "b", "b = \"other-body\" or b = [0.0, 0.0]");
        let stiffness = self
            .required(raw, &f.stiffness, "stiffness", "stiffness = 10.0")
            .and_then(|s| self.non_negative(s, "stiffness"));
        let rest_length = f
            .rest_length
            .as_ref()
            .map_or(Some(0.0), |r| self.non_negative(r, "rest_length"));
        let damping = f
            .damping
            .as_ref()
            .map_or(Some(0.0), |d| self.non_negative(d, "damping"));
        let a = a_raw.and_then(|a| self.body_index(a, names));
        let b = b_raw.and_then(|b| match b.get_ref() {
            toml::Value::String(name) => self
                .body_index(&Spanned::new(b.span(), name.clone()), names)
                .map(Anchor::Body),
            toml::Value::Array(items) => {
                let xy: Vec<f64> = items
                    .iter()
                    .filter_map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
                    .collect();
                if items.len() == 2 && xy.len() == 2 && xy.iter().all(|x| x.is_finite()) {
                    Some(Anchor::Point(DVec2::new(xy[0], xy[1])))
                } else {
                    self.error(
                        Diagnostic::at(b.span(), "a fixed spring end must be two finite numbers")
                            .hint("e.g. b = [0.0, 0.0]"),
                    );
                    None
                }
            }
            _ => {
                self.error(
                    Diagnostic::at(b.span(), "`b` must be a body's name or a point [x, y]")
                        .hint("e.g. b = \"anchor\" or b = [0.0, 0.0]"),
                );
                None
            }
        });
        let a_at = self.optional_vec2(f.a_at.as_ref(), "a_at");
        let b_at = self.optional_vec2(f.b_at.as_ref(), "b_at");
        let (a, b) = (a?, b?);
        if b == Anchor::Body(a) {
            self.error(
                Diagnostic::at(raw.span(), "a spring joins a body to itself")
                    .hint("give `a` and `b` different bodies, or a fixed point for `b`"),
            );
            return None;
        }
        let (a_at, b_at) = (a_at?, b_at?);
        if let (Anchor::Point(p), Some(raw_b_at)) = (b, &f.b_at) {
            self.error(
                Diagnostic::at(
                    raw_b_at.span(),
                    "`b_at` places the spring's end on body `b`, but `b` is a fixed point",
                )
                .label("a fixed point has no body coordinates")
                .hint(format!(
                    "remove `b_at`: the spring's end is the point b = [{}, {}] itself",
                    p.x, p.y
                )),
            );
            return None;
        }
        Some(ForceSpec::Spring {
            a,
            b,
            stiffness: stiffness?,
            rest_length: rest_length?,
            damping: damping?,
            a_at,
            b_at,
        })
    }

    fn selection(
        &mut self,
        raw: Option<&Spanned<Vec<Spanned<String>>>>,
        names: &Names,
    ) -> Option<Selection> {
        let Some(raw) = raw else {
            return Some(Selection::All);
        };
        if raw.get_ref().is_empty() {
            self.error(
                Diagnostic::at(
                    raw.span(),
                    "`bodies` is empty, so the force acts on nothing",
                )
                .hint("leave `bodies` out to act on every body"),
            );
            return None;
        }
        // Each name selects one body or a whole swarm; the indices are gathered, then
        // sorted, so that a body named twice (itself, or through its swarm) is found.
        let mut picked: Vec<(u32, usize)> = Vec::new();
        let mut ok = true;
        for (k, name) in raw.get_ref().iter().enumerate() {
            match names.resolve(name.get_ref()) {
                Some(Target::Body(i)) => picked.push((i, k)),
                Some(Target::Swarm(range)) => picked.extend(range.map(|i| (i, k))),
                None => {
                    self.unknown_body(name, names);
                    ok = false;
                }
            }
        }
        picked.sort_unstable();
        for pair in picked.windows(2) {
            if pair[0].0 == pair[1].0 {
                let name = &raw.get_ref()[pair[1].1.max(pair[0].1)];
                self.error(
                    Diagnostic::at(
                        name.span(),
                        format!(
                            "`{}` selects body `{}` a second time",
                            name.get_ref(),
                            names.name_of(pair[0].0)
                        ),
                    )
                    .hint("a force acts once on each body it names (a swarm's name selects all its members)"),
                );
                ok = false;
                break;
            }
        }
        let list: Vec<u32> = picked.into_iter().map(|(i, _)| i).collect();
        ok.then(|| Selection::from_sorted(list, names.len()))
    }

    fn body_index(&mut self, name: &Spanned<String>, names: &Names) -> Option<u32> {
        match names.resolve(name.get_ref()) {
            Some(Target::Body(i)) => Some(i),
            Some(Target::Swarm(range)) => {
                self.error(
                    Diagnostic::at(
                        name.span(),
                        format!(
                            "`{}` is a swarm of {} bodies, not one body",
                            name.get_ref(),
                            range.len()
                        ),
                    )
                    .label("a swarm")
                    .hint(format!("name one member, e.g. `{}0`", name.get_ref())),
                );
                None
            }
            None => {
                self.unknown_body(name, names);
                None
            }
        }
    }

    fn unknown_body(&mut self, name: &Spanned<String>, names: &Names) {
        let mut known: Vec<String> = names.bodies.keys().map(|k| k.to_string()).collect();
        known.sort_unstable();
        for s in names.swarms {
            known.push(format!(
                "{} (a swarm: {}0 to {}{})",
                s.name,
                s.name,
                s.name,
                s.count - 1
            ));
        }
        let hint = if known.is_empty() {
            "the scene declares no body".to_string()
        } else {
            format!("bodies in this scene: {}", known.join(", "))
        };
        self.error(
            Diagnostic::at(
                name.span(),
                format!("no body is named `{}`", name.get_ref()),
            )
            .label("unknown body")
            .hint(hint),
        );
    }

    fn required<'a, T>(
        &mut self,
        table: &Spanned<RawForce>,
        value: &'a Option<Spanned<T>>,
        key: &str,
        example: &str,
    ) -> Option<&'a Spanned<T>> {
        if value.is_none() {
            let kind = table.get_ref().kind.get_ref();
            self.error(
                Diagnostic::at(table.span(), format!("a `{kind}` force needs `{key}`"))
                    .hint(format!("add `{example}`")),
            );
        }
        value.as_ref()
    }

    fn color(&mut self, raw: &Spanned<String>) -> Option<Rgba> {
        let c = Rgba::parse(raw.get_ref());
        if c.is_none() {
            self.error(
                Diagnostic::at(raw.span(), format!("`{}` is not a colour", raw.get_ref()))
                    .hint("write #rrggbb, #rrggbbaa or #rgb, e.g. \"#cc3333\""),
            );
        }
        c
    }

    fn finite(&mut self, raw: &Spanned<f64>, key: &str) -> Option<f64> {
        let v = *raw.get_ref();
        if v.is_finite() {
            return Some(v);
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be a finite number"))
                .label(format!("{v} is not finite")),
        );
        None
    }

    fn positive(&mut self, raw: &Spanned<f64>, key: &str) -> Option<f64> {
        let v = self.finite(raw, key)?;
        if v > 0.0 {
            return Some(v);
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be > 0"))
                .label(format!("{v} is not positive")),
        );
        None
    }

    fn non_negative(&mut self, raw: &Spanned<f64>, key: &str) -> Option<f64> {
        let v = self.finite(raw, key)?;
        if v >= 0.0 {
            return Some(v);
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be ≥ 0"))
                .label(format!("{v} is negative")),
        );
        None
    }

    /// Checks an optional vector: `Some(None)` when absent, `None` after an error.
    fn optional_vec2(
        &mut self,
        raw: Option<&Spanned<RawVec2>>,
        key: &str,
    ) -> Option<Option<DVec2>> {
        match raw {
            Some(v) => self.vec2(v, key).map(Some),
            None => Some(None),
        }
    }

    fn vec2(&mut self, raw: &Spanned<RawVec2>, key: &str) -> Option<DVec2> {
        let RawVec2([x, y]) = *raw.get_ref();
        if x.is_finite() && y.is_finite() {
            return Some(DVec2::new(x, y));
        }
        self.error(
            Diagnostic::at(raw.span(), format!("`{key}` must be two finite numbers"))
                .label(format!("[{x}, {y}] is not finite")),
        );
        None
    }
}

/// A swarm's name and the indices of its members: first ..first + count.
struct SwarmName {
    name: String,
    first: u32,
    count: u32,
}

/// What a name in a force selects.
enum Target {
    Body(u32),
    Swarm(std::ops::Range<u32>),
}

/// Resolves the names forces use: a body's, a swarm's, or a swarm member's
/// (`dust17`). Members are found by parsing their number, so a swarm of a million
/// bodies costs no table of a million names.
struct Names<'a> {
    bodies: HashMap<&'a str, u32>,
    swarms: &'a [SwarmName],
    len: usize,
}

impl<'a> Names<'a> {
    fn new(body_names: &'a [String], swarms: &'a [SwarmName]) -> Self {
        let bodies = body_names
            .iter()
            .enumerate()
            .map(|(i, name)| (name.as_str(), i as u32))
            .collect();
        let len = body_names.len() + swarms.iter().map(|s| s.count as usize).sum::<usize>();
        Names {
            bodies,
            swarms,
            len,
        }
    }

    /// Returns the number of bodies, swarm members included.
    fn len(&self) -> usize {
        self.len
    }

    fn resolve(&self, name: &str) -> Option<Target> {
        if let Some(i) = self.bodies.get(name) {
            return Some(Target::Body(*i));
        }
        if let Some(s) = self.swarms.iter().find(|s| s.name == name) {
            return Some(Target::Swarm(s.first..s.first + s.count));
        }
        let (prefix, k) = split_member_name(name)?;
        let s = self.swarms.iter().find(|s| s.name == prefix)?;
        (k < u64::from(s.count)).then(|| Target::Body(s.first + k as u32))
    }

    /// Returns the name of body `i`, for messages.
    fn name_of(&self, i: u32) -> String {
        if let Some((name, _)) = self.bodies.iter().find(|(_, j)| **j == i) {
            return name.to_string();
        }
        self.swarms
            .iter()
            .find(|s| (s.first..s.first + s.count).contains(&i))
            .map_or_else(|| format!("#{i}"), |s| format!("{}{}", s.name, i - s.first))
    }
}

/// Returns each key of a force table that is present, with its span.
fn present_force_keys(f: &RawForce) -> Vec<(&'static str, Range<usize>)> {
    let spans = [
        f.bodies.as_ref().map(|v| v.span()),
        f.g.as_ref().map(|v| v.span()),
        f.k.as_ref().map(|v| v.span()),
        f.c.as_ref().map(|v| v.span()),
        f.f0.as_ref().map(|v| v.span()),
        f.f1.as_ref().map(|v| v.span()),
        f.a.as_ref().map(|v| v.span()),
        f.b.as_ref().map(|v| v.span()),
        f.stiffness.as_ref().map(|v| v.span()),
        f.rest_length.as_ref().map(|v| v.span()),
        f.damping.as_ref().map(|v| v.span()),
        f.centre.as_ref().map(|v| v.span()),
        f.strength.as_ref().map(|v| v.span()),
        f.tau.as_ref().map(|v| v.span()),
        f.at.as_ref().map(|v| v.span()),
        f.a_at.as_ref().map(|v| v.span()),
        f.b_at.as_ref().map(|v| v.span()),
    ];
    FORCE_KEYS
        .iter()
        .zip(spans)
        .filter_map(|(k, s)| s.map(|s| (*k, s)))
        .collect()
}

/// Returns R(θ)·p, the offset p turned with a body at angle θ; exactly p at θ = 0, so
/// that a body that is not turned starts where it always did.
fn turned(theta: f64, p: DVec2) -> DVec2 {
    if theta == 0.0 {
        p
    } else {
        crate::sim::rigid::rotate(theta.sin_cos(), p)
    }
}

/// Returns the signed area of a polygon and its area centroid (the shoelace formula):
/// A = ½ Σ (x_i·y_{i+1} - x_{i+1}·y_i), C = Σ (p_i + p_{i+1})·cross_i / (6A).
fn polygon_area_centroid(points: &[DVec2]) -> (f64, DVec2) {
    let mut area2 = 0.0;
    let mut c = DVec2::ZERO;
    for (i, p) in points.iter().enumerate() {
        let q = points[(i + 1) % points.len()];
        let cross = p.x * q.y - q.x * p.y;
        area2 += cross;
        c += (*p + q) * cross;
    }
    if area2 == 0.0 {
        return (0.0, DVec2::ZERO);
    }
    (0.5 * area2, c / (3.0 * area2))
}

/// Returns bytes as lowercase hexadecimal.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
