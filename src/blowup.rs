//! Blow-ups: the watch that stops a run whose energy grows with nothing to feed it,
//! before its numbers overflow, and the message that tells a person which body blew up,
//! when, and what to change. The render pipeline, checkpoints, export, figures and
//! benchmarks all report a blow-up through [`blow_up_message`]; none of them owns it.

use crate::numbers::{about, Readable};
use crate::scene::Scene;
use crate::sim::contacts::{Beyond, DEFAULT_SLOP, IMPACTS_PER_BODY, PAIRS_PER_BODY};
use crate::sim::{BlowUp, Simulation, MAX_ADAPTIVE_STEPS_PER_ADVANCE, STIFF};
use crate::study::stability::stable_step_hint;

/// How many times its starting scale the mechanical energy of a scene without an energy
/// source may grow before the run is stopped as numerically unstable.
pub const ENERGY_GROWTH_LIMIT: f64 = 10.0;

/// Watches the mechanical energy of a scene that has no energy source: drag and damping
/// only remove energy and the other forces conserve it, so energy growing far past its
/// start is the integrator's instability, caught before it reaches infinity.
pub(crate) struct EnergyWatch {
    /// E0 and the scale S = KE0 + |U0| (plus the initial potential's own size).
    start: Option<(f64, f64)>,
}

impl EnergyWatch {
    pub(crate) fn new(sim: &Simulation) -> Self {
        let s = sim.state();
        let system = sim.system();
        let start = system.mechanical_energy(s).and_then(|e0| {
            let ke = system.kinetic_energy(s);
            let scale = ke + (e0 - ke).abs();
            (scale > 0.0 && scale.is_finite()).then_some((e0, scale))
        });
        EnergyWatch { start }
    }

    /// Returns a blow-up when E > E0 + (LIMIT - 1)·S, naming the body with the most
    /// kinetic energy.
    pub(crate) fn check(&self, sim: &Simulation) -> Result<(), BlowUp> {
        let Some((e0, scale)) = self.start else {
            return Ok(());
        };
        let s = sim.state();
        let system = sim.system();
        let Some(e) = system.mechanical_energy(s) else {
            return Ok(());
        };
        if e <= e0 + (ENERGY_GROWTH_LIMIT - 1.0) * scale {
            return Ok(());
        }
        let body = (0..s.len())
            .map(|i| system.kinetic_energy_of(s, i))
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(0, |(i, _)| i);
        Err(BlowUp {
            body,
            step: sim.steps(),
            t: s.t,
            quantity: ENERGY,
            overlap: None,
            unanswerable: None,
        })
    }
}

/// The `quantity` of a [`BlowUp`] raised by `EnergyWatch`.
pub const ENERGY: &str = "energy";

/// Describes a blow-up for a person: which body, which step, and what to change.
pub fn blow_up_message(scene: &Scene, b: &BlowUp) -> String {
    let integrator = scene.simulation.integrator;
    if b.quantity == STIFF {
        return format!(
            "the simulation stopped: {integrator} took {} steps without reaching the next frame (t = {}); the scene is too stiff for an explicit adaptive method at rtol = {}, atol = {}\nhint: loosen the tolerances, or use a fixed-step method with a dt that linear stability allows",
            MAX_ADAPTIVE_STEPS_PER_ADVANCE,
            Readable(b.t),
            Readable(scene.simulation.tolerances.rtol),
            Readable(scene.simulation.tolerances.atol)
        );
    }
    if let Some(u) = b.unanswerable {
        let name = &scene.bodies[u.body].name;
        let dt = Readable(scene.simulation.dt);
        return match u.why {
            Beyond::Precision {
                coordinate,
                spacing,
                angle,
            } => {
                let (what, unit, slop) = if angle {
                    ("an angle of", "rad", format!("{DEFAULT_SLOP} rad"))
                } else {
                    ("a coordinate of", "m", format!("{DEFAULT_SLOP} of its size"))
                };
                format!(
                    "the simulation stopped: body `{name}` reached {what} {} {unit} at step {} (t = {}), where f64 numbers lie {} {unit} apart, more than its contact slop ({slop}): its contacts can no longer be resolved; integrator {integrator}, dt = {dt}\nhint: a speed far larger than the scene's sent it there: check body `{name}`'s velocity and angular velocity, or leave it out of [contacts]",
                    about(coordinate),
                    b.step,
                    Readable(b.t),
                    about(spacing),
                )
            }
            Beyond::Pairs { distance, budget } => format!(
                "the simulation stopped: body `{name}` moved {} m in step {} (t = {}), and the paths of that step crossed more than {budget} pairs of bodies ({PAIRS_PER_BODY} per colliding body), past what a step answers; integrator {integrator}, dt = {dt}\nhint: give `{name}` (and any body as fast) a lower speed, or take a smaller dt, so that no body moves much more than its own size in a step",
                about(distance),
                b.step,
                Readable(b.t),
            ),
        };
    }
    if let Some((o, q)) = b.overlap.and_then(|o| o.squeezed.map(|q| (o, q))) {
        let (light, heavy) = (
            &scene.bodies[q.body as usize].name,
            &scene.bodies[q.by as usize].name,
        );
        // Left by the impacts, the step ran out of them, which more solver sweeps do
        // not change; left by the resting solver, more sweeps carry the push further.
        let (because, sweeps) = if o.crowded {
            (
                format!(", because the step met more impacts than it answers ({IMPACTS_PER_BODY} per colliding body)"),
                String::new(),
            )
        } else {
            let now = scene.contacts.as_ref().map_or(0, |c| c.resting.iterations);
            (
                String::new(),
                format!("raise [contacts] `iterations` (the resting solver's sweeps a step, {now} now) toward the ratio, "),
            )
        };
        return format!(
            "the simulation stopped: bodies `{}` and `{}` overlap by {:e} after step {} (t = {}), deeper than their contact tolerance{because}: body `{light}` is pressed by `{heavy}`, {} times its mass, and impulses one pair at a time hold a light body under a far heavier one only by passing the push between them about as many times as that ratio; integrator {integrator}, dt = {}\nhint: {sweeps}bring the masses of `{light}` and `{heavy}` closer (ratios of a few hundred or more are past what a step answers), or leave the light bodies out of [contacts] `bodies`",
            scene.bodies[o.a].name,
            scene.bodies[o.b].name,
            o.depth,
            b.step,
            Readable(b.t),
            about(f64::from(q.ratio)),
            scene.simulation.dt
        );
    }
    if let Some(o) = b.overlap.filter(|o| o.crowded) {
        return format!(
            "the simulation stopped: bodies `{}` and `{}` overlap by {:e} after step {} (t = {}), deeper than their contact tolerance, because the step met more impacts than it answers ({IMPACTS_PER_BODY} per colliding body): a crowd of bodies was struck faster than impulses one pair at a time can settle it; integrator {integrator}, dt = {}\nhint: start the bodies closer to where they come to rest (pour them from lower, or fewer at a time), or give them lower speeds",
            scene.bodies[o.a].name, scene.bodies[o.b].name, o.depth, b.step, Readable(b.t), scene.simulation.dt
        );
    }
    if let Some(o) = b.overlap {
        return format!(
            "the simulation stopped: bodies `{}` and `{}` overlap by {:e} after step {} (t = {}), deeper than their contact tolerance; integrator {integrator}, dt = {}\nhint: a smaller dt, or a larger [contacts] `tolerance`, lets the contacts keep them apart",
            scene.bodies[o.a].name, scene.bodies[o.b].name, o.depth, b.step, b.t, scene.simulation.dt
        );
    }
    let body = &scene.bodies[b.body];
    // What linear stability theory says of the scene's drags and springs, if anything.
    let masses: Vec<f64> = scene.bodies.iter().map(|b| b.mass).collect();
    let inertia: Vec<f64> = scene.bodies.iter().map(|b| b.inertia).collect();
    let theory = stable_step_hint(integrator, &masses, &inertia, &scene.forces)
        .map_or(String::new(), |h| format!("\n{h}"));
    if b.quantity == ENERGY {
        return format!(
            "the simulation blew up: its energy grew past {ENERGY_GROWTH_LIMIT} times its starting scale by step {} (t = {}) although nothing in the scene adds energy; body `{}` moves fastest; integrator {integrator}, dt = {}\nhint: a smaller dt, or a more stable integrator (symplectic-euler or verlet conserve a spring's energy){theory}",
            b.step,
            Readable(b.t),
            body.name,
            Readable(scene.simulation.dt)
        );
    }
    format!(
        "the simulation blew up: the {} of body `{}` became non-finite at step {} (t = {}) with integrator {integrator} and dt = {}\nhint: a smaller dt, or a more stable integrator, keeps it finite{theory}",
        b.quantity,
        body.name,
        b.step,
        Readable(b.t),
        Readable(scene.simulation.dt)
    )
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::sim::contacts::Overlap;

    const TWO_DISCS: &str = r#"
[simulation]
dt = 0.01
duration = 1.0
[render]
fps = 25
view = { min = [-2.0, -2.0], max = [2.0, 2.0] }
[contacts]
[[body]]
name = "upper"
mass = 1.0
position = [0.0, 1.0]
shape = { circle = { radius = 0.5 } }
[[body]]
name = "lower"
mass = 1.0
position = [0.0, 0.0]
shape = { circle = { radius = 0.5 } }
"#;

    fn squeezed(crowded: bool) -> BlowUp {
        let mut b = overlap(crowded);
        if let Some(o) = b.overlap.as_mut() {
            o.squeezed = Some(crate::sim::contacts::Squeezed {
                body: 1,
                by: 0,
                ratio: 4999.999999,
            });
        }
        b
    }

    /// An overlap of a light body beside a far heavier one names both and their ratio,
    /// and asks for closer masses, not a smaller dt or a gentler start.
    #[test]
    fn an_overlap_beside_a_far_heavier_body_asks_for_closer_masses() {
        let scene = crate::scene::parse(Path::new("two.toml"), TWO_DISCS).expect("a valid scene");
        for crowded in [false, true] {
            let m = blow_up_message(&scene, &squeezed(crowded));
            assert!(m.contains("bodies `upper` and `lower` overlap by 2.5e-1 after step 7"));
            assert!(
                m.contains("body `lower` is pressed by `upper`, 5000 times its mass"),
                "{m}"
            );
            assert!(
                m.contains("bring the masses of `lower` and `upper` closer"),
                "{m}"
            );
            assert_eq!(m.contains("per colliding body"), crowded, "{m}");
            // More sweeps help only an overlap the resting solver left.
            assert_eq!(
                m.contains(
                    "raise [contacts] `iterations` (the resting solver's sweeps a step, 25 now)"
                ),
                !crowded,
                "{m}"
            );
            assert!(!m.contains("a smaller dt"), "{m}");
            assert!(!m.contains("closer to where they come to rest"), "{m}");
        }
    }

    fn overlap(crowded: bool) -> BlowUp {
        BlowUp {
            body: 0,
            step: 7,
            t: 0.07,
            quantity: crate::sim::OVERLAP,
            overlap: Some(Overlap {
                a: 0,
                b: 1,
                depth: 0.25,
                crowded,
                squeezed: None,
            }),
            unanswerable: None,
        }
    }

    /// An overlap names both bodies, the step and the depth; one left because the
    /// step ran out of impacts says so and asks for a gentler start, not a smaller dt.
    #[test]
    fn an_overlap_says_whether_the_step_ran_out_of_impacts() {
        let scene = crate::scene::parse(Path::new("two.toml"), TWO_DISCS).expect("a valid scene");
        let plain = blow_up_message(&scene, &overlap(false));
        assert!(plain.contains("bodies `upper` and `lower` overlap by 2.5e-1 after step 7"));
        assert!(plain.contains("a smaller dt"), "{plain}");
        let crowded = blow_up_message(&scene, &overlap(true));
        assert!(crowded.contains("bodies `upper` and `lower` overlap by 2.5e-1 after step 7"));
        assert!(crowded.contains(&format!("({IMPACTS_PER_BODY} per colliding body)")));
        assert!(
            crowded.contains("closer to where they come to rest"),
            "{crowded}"
        );
        assert!(!crowded.contains("a smaller dt"), "{crowded}");
    }
}
