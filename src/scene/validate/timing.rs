//! The `[simulation]` and `[render]` tables: the integrator, the step, the tolerances and
//! the runs to compare; the image, the view, and the frame timing derived from dt and fps.

use std::ops::Range;

use toml::Spanned;

use super::run_length::{TimingSpans, MAX_STEPS};
use super::{Validator, MAX_IMAGE_SIDE};
use crate::numbers::Readable;
use crate::scene::raw::{RawRender, RawSimulation};
use crate::scene::{Body, CompareRun, Diagnostic, RenderSettings, Rgba, SimulationSettings, View};
use crate::sim::{ForceSpec, IntegratorKind, Tolerances};

/// How close 1/fps must be to a whole number of steps, relative.
pub(super) const WHOLE_STEPS_TOLERANCE: f64 = 1e-9;

impl Validator {
    pub(super) fn simulation(
        &mut self,
        raw: Option<&Spanned<RawSimulation>>,
        fps: Option<f64>,
        spans: &TimingSpans,
    ) -> Option<SimulationSettings> {
        let Some(raw) = raw else {
            // Without a [simulation] table: explicit Euler, 5 s, ten steps a frame.
            let dt = self.default_dt(fps?, spans)?;
            return Some(SimulationSettings {
                integrator: IntegratorKind::Euler,
                dt,
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
            (None, Some(fps)) => self.default_dt(fps, spans),
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
    pub(super) fn exact_exists(
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
    pub(super) fn compare(
        &mut self,
        list: &Spanned<Vec<Spanned<String>>>,
    ) -> Option<Vec<CompareRun>> {
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

    /// Checks that 1/fps is a whole number of steps.
    pub(super) fn whole_steps_per_frame(
        &mut self,
        dt: f64,
        fps: f64,
        span: Range<usize>,
    ) -> Option<()> {
        let interval = 1.0 / fps;
        let ratio = interval / dt;
        // A count too large to be exact has no fraction to check; `steps_per_frame`
        // refuses it, at the same place.
        if ratio > MAX_STEPS as f64 {
            return Some(());
        }
        let nearest = ratio.round();
        if nearest >= 1.0 && (ratio - nearest).abs() <= WHOLE_STEPS_TOLERANCE * ratio {
            return Some(());
        }
        let below = ratio.floor().max(1.0);
        let above = ratio.ceil().max(1.0);
        let option = |n: f64| {
            format!(
                "dt = {} ({} step{} a frame)",
                Readable(interval / n),
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
                    "the frame interval 1/fps = {} is not a whole number of steps of dt = {} ({ratio:.6} steps)",
                    Readable(interval),
                    Readable(dt)
                ),
            )
            .label("each frame must fall on a step")
            .hint(hint),
        );
        None
    }

    pub(super) fn render(
        &mut self,
        r: &RawRender,
        sim: Option<&SimulationSettings>,
        fps: Option<f64>,
        view: Option<View>,
        spans: &TimingSpans,
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
        let steps_per_frame = self.steps_per_frame(sim.dt, fps, spans);
        let frame_count = self.frame_count(sim.duration, fps, spans);
        let (steps_per_frame, frame_count) = (steps_per_frame?, frame_count?);
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
            frame_count,
        })
    }

    pub(super) fn view(&mut self, r: &Spanned<RawRender>) -> Option<View> {
        let Some(view) = &r.get_ref().view else {
            self.error(Diagnostic::at(r.span(), "[render] has no `view`").hint(
                "add `view = { min = [x0, y0], max = [x1, y1] }`: the world rectangle to show",
            ));
            return None;
        };
        let v = view.get_ref();
        let min = self.vec2(&v.min, "view.min")?;
        let max = self.vec2(&v.max, "view.max")?;
        let extent = max - min;
        // A side below the smallest normal f64 (found by the mutated-scene tests:
        // max = [5e-324, 9]) has no room for ticks or pixels: their steps underflow.
        if extent.x >= f64::MIN_POSITIVE && extent.y >= f64::MIN_POSITIVE {
            return Some(View { min, max });
        }
        if min.x < max.x && min.y < max.y {
            self.error(
                Diagnostic::at(view.span(), "the view is too small to draw")
                    .label(format!(
                        "{} × {}",
                        Readable(extent.x),
                        Readable(extent.y)
                    ))
                    .hint("each side must be at least 2.2e-308 (the smallest normal number); use other units"),
            );
            return None;
        }
        self.error(
            Diagnostic::at(view.span(), "the view is empty")
                .label("min must be below max on both axes")
                .hint(format!(
                    "min = [{}, {}] and max = [{}, {}] leave no area",
                    Readable(min.x),
                    Readable(min.y),
                    Readable(max.x),
                    Readable(max.y)
                )),
        );
        None
    }

    pub(super) fn image_side(
        &mut self,
        raw: Option<&Spanned<i64>>,
        key: &str,
        default: u32,
    ) -> Option<u32> {
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
}
