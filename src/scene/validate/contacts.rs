//! `[contacts]`: which bodies collide and how, and the checks that need the bodies:
//! shapes that can collide, no overlap at the start, no force on a static body, and no
//! closed form to compare with.

use std::ops::Range;

use toml::Spanned;

use super::names::{Names, Target};
use super::Validator;
use crate::scene::raw::{RawContacts, RawForce, RawScene, RawSimulation};
use crate::scene::{Body, CompareRun, ContactSettings, Diagnostic, Shape, SimulationSettings};
use crate::sim::contacts::{
    Contacts, PolygonProblem, Resting, Sleep, DEFAULT_ITERATIONS, DEFAULT_SLEEP_FRACTION,
    DEFAULT_SLEEP_TIME, DEFAULT_SLOP, DEFAULT_TOLERANCE,
};
use crate::sim::ForceSpec;

/// How many of its own widths a body's contacts may reach (see
/// `Validator::contacts_reach_within_bodies`).
const REACH_SIZES: f64 = 10.0;

/// Returns |g|·dt for the scene's strongest gravity (0 without gravity): the speed
/// gravity adds in one step, from which the default resting speed is taken.
pub(super) fn gravity_step(forces: &[ForceSpec], dt: f64) -> f64 {
    let g = forces
        .iter()
        .filter_map(|f| match f {
            ForceSpec::Gravity { g, .. } => Some(g.length()),
            _ => None,
        })
        .fold(0.0, f64::max);
    g * dt
}

/// What `[contacts]` says before the bodies are known.
pub(super) struct ContactKeys {
    restitution: f64,
    tolerance: Option<f64>,
    friction: f64,
    rest_speed: Option<f64>,
    slop: Option<f64>,
    iterations: usize,
    /// `sleep` (default true), `sleep_speed` and `sleep_time` when given.
    sleep: bool,
    sleep_speed: Option<f64>,
    sleep_time: f64,
}

/// How many steps' worth of the scene's strongest gravity make the default resting
/// speed: a contact approaching slower than 3·|g|·dt rests. Gravity adds |g|·dt to a
/// body resting on the floor every step, so its contact is always below this, while a
/// ball dropped from a height of a few dt²·|g| already bounces.
pub const REST_SPEED_STEPS: f64 = 3.0;

impl Validator {
    /// Checks the values of `[contacts]`.
    pub(super) fn contact_keys(&mut self, raw: &Spanned<RawContacts>) -> Option<ContactKeys> {
        let c = raw.get_ref();
        let restitution = c
            .restitution
            .as_ref()
            .map_or(Some(1.0), |e| self.restitution(e));
        let tolerance = match &c.tolerance {
            Some(t) => self.positive(t, "tolerance").map(Some),
            None => Some(None),
        };
        let friction = c
            .friction
            .as_ref()
            .map_or(Some(0.0), |m| self.non_negative(m, "friction"));
        let rest_speed = match &c.rest_speed {
            Some(v) => self.non_negative(v, "rest_speed").map(Some),
            None => Some(None),
        };
        let slop = match &c.slop {
            Some(v) => self.positive(v, "slop").map(Some),
            None => Some(None),
        };
        let iterations = match &c.iterations {
            None => Some(DEFAULT_ITERATIONS),
            Some(n) if (1..=1000).contains(n.get_ref()) => Some(*n.get_ref() as usize),
            Some(n) => {
                self.error(
                    Diagnostic::at(n.span(), "`iterations` must be between 1 and 1000")
                        .label(format!("{} sweeps", n.get_ref()))
                        .hint(format!(
                            "the resting-contact solver's sweeps per step; {DEFAULT_ITERATIONS} is the default"
                        )),
                );
                None
            }
        };
        let sleep = c.sleep.as_ref().is_none_or(|s| *s.get_ref());
        let sleep_speed = match &c.sleep_speed {
            Some(v) => self.non_negative(v, "sleep_speed").map(Some),
            None => Some(None),
        };
        let sleep_time = c
            .sleep_time
            .as_ref()
            .map_or(Some(DEFAULT_SLEEP_TIME), |t| self.positive(t, "sleep_time"));
        Some(ContactKeys {
            restitution: restitution?,
            tolerance: tolerance?,
            friction: friction?,
            rest_speed: rest_speed?,
            slop: slop?,
            iterations: iterations?,
            sleep,
            sleep_speed: sleep_speed?,
            sleep_time: sleep_time?,
        })
    }

    /// Resolves which bodies collide and checks that each can: a circle, a box or a
    /// convex polygon, and none overlapping another at t = 0.
    pub(super) fn contacts(
        &mut self,
        raw: &RawScene,
        table: &Spanned<RawContacts>,
        keys: ContactKeys,
        names: &Names,
        bodies: &[Body],
        (dt, gravity_step): (f64, f64),
    ) -> Option<ContactSettings> {
        let spans = BodySpans::new(raw, names);
        let mut ok = true;
        let chosen: Vec<usize> = match &table.get_ref().bodies {
            None => (0..bodies.len())
                .filter(|&i| !matches!(bodies[i].shape, Shape::Points { .. }))
                .collect(),
            Some(list) => {
                if list.get_ref().is_empty() {
                    self.error(
                        Diagnostic::at(list.span(), "`bodies` is empty, so nothing collides")
                            .hint("leave `bodies` out to make every body with a shape collide"),
                    );
                    return None;
                }
                let mut chosen = Vec::new();
                for name in list.get_ref() {
                    let range = match names.resolve(name.get_ref()) {
                        Some(Target::Body(i)) => i as usize..i as usize + 1,
                        Some(Target::Swarm(r)) => r.start as usize..r.end as usize,
                        None => {
                            self.unknown_body(name, names);
                            ok = false;
                            continue;
                        }
                    };
                    for i in range {
                        if let Shape::Points { .. } = bodies[i].shape {
                            self.error(
                                Diagnostic::at(
                                    name.span(),
                                    format!(
                                        "body `{}` is made of point masses, which do not collide",
                                        bodies[i].name
                                    ),
                                )
                                .label("only circles, boxes and convex polygons collide")
                                .hint("give the body a `shape`, or leave it out of `bodies`"),
                            );
                            ok = false;
                            break;
                        }
                        chosen.push(i);
                    }
                }
                chosen.sort_unstable();
                chosen.dedup();
                chosen
            }
        };
        if !ok {
            return None;
        }
        let rest_speed = keys.rest_speed.unwrap_or(REST_SPEED_STEPS * gravity_step);
        // Bodies sleep only where contacts rest (a resting speed above 0).
        let sleep = (keys.sleep && rest_speed > 0.0).then(|| Sleep {
            speed: keys
                .sleep_speed
                .unwrap_or(DEFAULT_SLEEP_FRACTION * rest_speed),
            time: keys.sleep_time,
        });
        let settings = ContactSettings {
            restitution: keys.restitution,
            tolerance: keys.tolerance,
            friction: keys.friction,
            resting: Resting {
                speed: rest_speed,
                slop: keys.slop,
                iterations: keys.iterations,
                sleep,
            },
            bodies: chosen,
        };
        let mut refused = 0;
        for &i in &settings.bodies {
            let Err(problem) = crate::scene::collider_of(i, &bodies[i], &settings) else {
                continue;
            };
            refused += 1;
            if refused > 5 {
                continue;
            }
            let name = &bodies[i].name;
            let d = match problem {
                PolygonProblem::NotConvex => Diagnostic::at(
                    spans.shape(i),
                    format!("body `{name}` collides but its polygon is not convex"),
                )
                .hint("split it into convex bodies, or leave it out of [contacts] `bodies`"),
                PolygonProblem::Degenerate => Diagnostic::at(
                    spans.shape(i),
                    format!("body `{name}` collides but its shape has no area to collide with"),
                )
                .label("its sides are too small, or too unequal, for their area to be a number")
                .hint("use other units, or leave it out of [contacts] `bodies`"),
            };
            self.error(d);
        }
        if refused > 5 {
            self.error(Diagnostic::whole_file(format!(
                "{} more colliding bodies cannot collide",
                refused - 5
            )));
        }
        if refused > 0 {
            return None;
        }
        let mut contacts = crate::scene::contacts_of(bodies, &settings);
        if !self.contacts_reach_within_bodies(table, &contacts, &settings, dt, bodies) {
            return None;
        }
        let pos: Vec<_> = bodies.iter().map(|b| b.position).collect();
        let angle: Vec<_> = bodies.iter().map(|b| b.angle).collect();
        let overlaps = overlaps_at_start(&mut contacts, &pos, &angle, bodies);
        for o in overlaps.iter().take(5) {
            self.error(
                Diagnostic::at(
                    spans.body(o.b),
                    format!(
                        "bodies `{}` and `{}` overlap by {:.3e} at t = 0",
                        bodies[o.a].name, bodies[o.b].name, o.depth
                    ),
                )
                .label("colliding bodies may touch at the start, but not overlap")
                .hint("move them apart, or leave one out of [contacts] `bodies`"),
            );
        }
        if overlaps.len() > 5 {
            // The search stops once OVERLAPS_LISTED are found: past that, a count.
            let more = if overlaps.len() >= OVERLAPS_LISTED {
                format!("at least {}", overlaps.len() - 5)
            } else {
                (overlaps.len() - 5).to_string()
            };
            self.error(Diagnostic::whole_file(format!(
                "{more} more pairs of colliding bodies overlap at t = 0"
            )));
        }
        overlaps.is_empty().then_some(settings)
    }

    /// Refuses contacts that reach farther from a body than ten times its width. A
    /// body's contacts are sought within tolerance + slop + rest_speed × dt of it; with
    /// absurd values (a resting speed of 10³⁰⁸ m/s, say) every pair of bodies in the
    /// scene is a contact, which a scene of thousands cannot hold in memory. Within ten
    /// widths a body has at most a few hundred neighbours however densely packed, and a
    /// coarse but honest scene passes: 1 cm marbles at dt = 1/30 s reach 3.3 cm by the
    /// default resting speed, 3·|g|·dt. Returns whether every body's reach fits.
    fn contacts_reach_within_bodies(
        &mut self,
        table: &Spanned<RawContacts>,
        contacts: &Contacts,
        settings: &ContactSettings,
        dt: f64,
        bodies: &[Body],
    ) -> bool {
        let resting = settings.resting;
        let rest = resting.speed * dt;
        let widest = contacts.colliders().iter().find_map(|c| {
            let tolerance = settings.tolerance.unwrap_or(DEFAULT_TOLERANCE * c.size);
            let slop = if resting.speed > 0.0 {
                resting.slop.unwrap_or(DEFAULT_SLOP * c.size)
            } else {
                0.0
            };
            let reach = tolerance + slop + rest;
            // A reach that is not a number is refused too.
            (reach > REACH_SIZES * c.size || reach.is_nan())
                .then_some((c.body, reach, tolerance, slop, c.size))
        });
        let Some((b, reach, tolerance, slop, size)) = widest else {
            return true;
        };
        self.error(
            Diagnostic::at(
                table.span(),
                format!(
                    "contacts would reach {reach:.3e} m from body `{}`, more than {REACH_SIZES} times its size, {size:.3e} m",
                    bodies[b].name
                ),
            )
            .label(format!(
                "tolerance + slop + rest_speed × dt = {tolerance:.3e} + {slop:.3e} + {:.3e} × {dt:.3e}",
                resting.speed
            ))
            .hint("lower `rest_speed`, `slop` or `tolerance` in [contacts], or the step dt"),
        );
        false
    }

    /// Refuses a force whose `bodies` names a static body, which no force moves.
    pub(super) fn forces_spare_static_bodies(
        &mut self,
        forces: &[Spanned<RawForce>],
        names: &Names,
        bodies: &[Body],
    ) {
        for f in forces {
            let Some(list) = &f.get_ref().bodies else {
                continue;
            };
            for name in list.get_ref() {
                if let Some(Target::Body(i)) = names.resolve(name.get_ref()) {
                    if bodies.get(i as usize).is_some_and(|b| b.is_static) {
                        self.error(
                            Diagnostic::at(
                                name.span(),
                                format!(
                                    "body `{}` is static, so no force acts on it",
                                    name.get_ref()
                                ),
                            )
                            .hint("remove it from `bodies`, or remove `static = true`"),
                        );
                    }
                }
            }
        }
    }

    /// Refuses `compare = ["exact"]` in a scene with collisions or static bodies, which
    /// has no closed form; returns true when it did.
    pub(super) fn no_exact_with_contacts(
        &mut self,
        raw: Option<&Spanned<RawSimulation>>,
        sim: &SimulationSettings,
        has_contacts: bool,
        bodies: &[Body],
    ) -> bool {
        if !sim.compare.contains(&CompareRun::Exact)
            || !(has_contacts || bodies.iter().any(|b| b.is_static))
        {
            return false;
        }
        let span = raw
            .and_then(|r| r.get_ref().compare.as_ref())
            .and_then(|c| c.get_ref().iter().find(|n| n.get_ref() == "exact"))
            .map(|n| n.span());
        let message =
            "a scene with collisions or static bodies has no closed-form solution to compare with";
        let d = match span {
            Some(span) => Diagnostic::at(span, message),
            None => Diagnostic::whole_file(message),
        };
        self.error(d.hint("remove \"exact\", or compare integrators only"));
        true
    }
}

/// How many overlapping pairs the check at t = 0 looks for before it stops.
const OVERLAPS_LISTED: usize = 100;

/// Returns the pairs of colliding bodies that overlap at t = 0 deeper than their
/// tolerance (two static bodies may: a floor built of several boxes), in body order,
/// up to about [`OVERLAPS_LISTED`].
fn overlaps_at_start(
    contacts: &mut Contacts,
    pos: &[glam::DVec2],
    angle: &[f64],
    bodies: &[Body],
) -> Vec<crate::sim::contacts::Overlap> {
    contacts.overlaps(pos, angle, |i| !bodies[i].is_static, OVERLAPS_LISTED)
}

/// Where each body is written in the file: its own `[[body]]` table, or its swarm's.
struct BodySpans<'a> {
    raw: &'a RawScene,
    swarms: Vec<(Range<usize>, usize)>,
}

impl<'a> BodySpans<'a> {
    fn new(raw: &'a RawScene, names: &Names) -> Self {
        let swarms = raw
            .swarm
            .iter()
            .enumerate()
            .filter_map(|(k, s)| match names.resolve(s.get_ref().name.get_ref()) {
                Some(Target::Swarm(r)) => Some((r.start as usize..r.end as usize, k)),
                _ => None,
            })
            .collect();
        BodySpans { raw, swarms }
    }

    /// The span of body i's table (or its swarm's).
    fn body(&self, i: usize) -> Range<usize> {
        if let Some(b) = self.raw.body.get(i) {
            return b.span();
        }
        self.swarm(i).map_or(0..0, |s| s.span())
    }

    /// The span of body i's shape, or of its table when it has none written.
    fn shape(&self, i: usize) -> Range<usize> {
        if let Some(b) = self.raw.body.get(i) {
            return b.get_ref().shape.as_ref().map_or(b.span(), |s| s.span());
        }
        self.swarm(i).map_or(0..0, |s| {
            s.get_ref().shape.as_ref().map_or(s.span(), |sh| sh.span())
        })
    }

    fn swarm(&self, i: usize) -> Option<&'a Spanned<crate::scene::raw::RawSwarm>> {
        self.swarms
            .iter()
            .find(|(r, _)| r.contains(&i))
            .map(|(_, k)| &self.raw.swarm[*k])
    }
}
