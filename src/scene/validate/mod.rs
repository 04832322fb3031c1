//! Validation: from the raw file to a checked [`Scene`], reporting every problem at once.
//!
//! The [`Validator`] collects problems while it turns raw values into checked ones; each
//! check returns `None` after recording a problem, so validation goes on and reports
//! them all. Its checks live beside the part of the file they check: `timing.rs`
//! (`[simulation]`, `[render]`), `bodies.rs`, `swarms.rs`, `forces.rs`, `names.rs` (what
//! forces select) and `values.rs` (single numbers, vectors, colours).

mod bodies;
mod contacts;
mod forces;
mod names;
mod run_length;
mod swarms;
mod timing;
mod values;

use std::path::Path;

use sha2::{Digest, Sha256};
use toml::Spanned;

use super::raw::RawScene;
use super::{Diagnostic, Scene, Source};
use names::Names;

/// The largest image side accepted, in pixels.
pub const MAX_IMAGE_SIDE: i64 = 16384;
/// The largest number of frames a scene may ask for.
pub const MAX_FRAMES: u64 = 1_000_000;
/// The largest number of bodies a scene may declare, swarms included.
pub const MAX_BODIES: u64 = 10_000_000;
pub use run_length::{MAX_BODY_STEPS, MAX_STEPS};

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

impl Validator {
    pub(super) fn error(&mut self, d: Diagnostic) {
        self.diagnostics.push(d);
    }

    pub(super) fn scene(&mut self, path: &Path, text: &str, raw: RawScene) -> Option<Scene> {
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
        let timing = run_length::TimingSpans::new(raw.simulation.as_ref(), render_raw);
        let simulation = self.simulation(raw.simulation.as_ref(), fps, &timing);
        let view = render_raw.and_then(|r| self.view(r));
        let bodies = self.bodies(&raw.body, view);
        let render = render_raw
            .and_then(|r| self.render(r.get_ref(), simulation.as_ref(), fps, view, &timing));
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
        if let Some(bodies) = &bodies {
            self.forces_spare_static_bodies(&raw.force, &names, bodies);
        }
        let contact_keys = raw.contacts.as_ref().map(|c| (c, self.contact_keys(c)));
        if let (Some(sim), Some(bodies), Some(forces)) = (&simulation, &bodies, &forces) {
            if !self.no_exact_with_contacts(
                raw.simulation.as_ref(),
                sim,
                contact_keys.is_some(),
                bodies,
            ) {
                self.exact_exists(raw.simulation.as_ref(), sim, bodies, forces);
            }
        }
        let contacts = match (contact_keys, &bodies, &forces, &simulation) {
            (None, ..) => Some(None),
            (Some((table, Some(keys))), Some(bodies), Some(forces), Some(sim)) => self
                .contacts(
                    &raw,
                    table,
                    keys,
                    &names,
                    bodies,
                    (sim.dt, contacts::gravity_step(forces, sim.dt)),
                )
                .map(Some),
            _ => None,
        };
        let fits = match (&simulation, &render, &bodies) {
            (Some(sim), Some(r), Some(bodies)) => self.run_fits(
                sim,
                r.fps,
                (r.steps_per_frame, r.frame_count),
                bodies.len(),
                &timing,
            ),
            _ => Some(()),
        };
        let hash = hex(&Sha256::digest(text.as_bytes()));
        let (mut bodies, forces, contacts, ()) = (bodies?, forces?, contacts?, fits?);
        super::mark_turning(&mut bodies, &forces);
        if let Some(c) = &contacts {
            // An impulse off its centre of mass turns a colliding body that can move;
            // a disc's normal always passes through its centre.
            for &i in &c.bodies {
                let b = &mut bodies[i];
                let friction = b.friction.unwrap_or(c.friction) > 0.0;
                if !b.is_static && (friction || !matches!(b.shape, super::Shape::Circle { .. })) {
                    b.turns = true;
                }
            }
        }
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
            contacts,
        })
    }

    pub(super) fn name(&mut self, path: &Path, raw: Option<&Spanned<String>>) -> Option<String> {
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
}

/// Returns bytes as lowercase hexadecimal.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
