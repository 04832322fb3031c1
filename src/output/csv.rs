//! Trajectories as CSV, simulated without drawing anything.

use std::io::Write;

use crate::scene::Scene;
use crate::sim::{BlowUp, Simulation};

/// Writes the trajectory of every body as CSV: a header
/// `t,body,x,y,vx,vy,angle,omega`, then one row per body at each frame time (or after
/// every step when `every_step`). Numbers are in Rust's shortest round-trip form, so
/// they parse back to the same f64. x and y are the centre of mass; `angle` is the
/// body's orientation θ in radians (counter-clockwise, not wrapped to a turn) and
/// `omega` its angular velocity ω = dθ/dt in rad/s, for every body, turning or not.
///
/// With `events`, every impulse of a scene with collisions is written there too, as the
/// collision log's rows (see [`super::events`]), in the order applied.
///
/// Returns the blow-up, if the state stopped being finite; the rows before it are
/// written.
pub fn write_trajectory(
    scene: &Scene,
    every_step: bool,
    out: &mut impl Write,
    mut events: Option<&mut dyn Write>,
) -> std::io::Result<Option<BlowUp>> {
    let names = scene.body_names();
    let mut sim = scene.simulation();
    sim.record_contacts(events.is_some());
    writeln!(out, "{HEADER}")?;
    write_rows(&sim, &names, out)?;
    // Writes the impulses of the steps just taken to the collision log.
    let mut log = |sim: &mut Simulation| -> std::io::Result<()> {
        match events.as_mut() {
            Some(w) => super::events::write_events(w, &sim.take_contact_events(), &names),
            None => Ok(()),
        }
    };
    let frames = scene.render.frame_count;
    if every_step {
        // Every step up to the last frame; an adaptive method's steps vary, and its last
        // one is shortened to land on the last frame's time.
        let t_end = scene.frame_time(frames - 1);
        if sim.integrator().is_adaptive() {
            while sim.state().t < t_end {
                let step = sim.step_towards(t_end);
                log(&mut sim)?;
                if let Err(b) = step {
                    return Ok(Some(b));
                }
                write_rows(&sim, &names, out)?;
            }
            return Ok(None);
        }
        for _ in 0..scene.total_steps() {
            let step = sim.step();
            log(&mut sim)?;
            if let Err(b) = step {
                return Ok(Some(b));
            }
            write_rows(&sim, &names, out)?;
        }
    } else {
        let energy = crate::blowup::EnergyWatch::new(&sim);
        for k in 1..frames {
            let step = sim
                .advance_to(scene.frame_time(k))
                .and_then(|()| energy.check(&sim));
            log(&mut sim)?;
            if let Err(b) = step {
                return Ok(Some(b));
            }
            write_rows(&sim, &names, out)?;
        }
    }
    Ok(None)
}

/// The header of a trajectory CSV.
pub const HEADER: &str = "t,body,x,y,vx,vy,angle,omega";

fn write_rows(sim: &Simulation, names: &[&str], out: &mut impl Write) -> std::io::Result<()> {
    let s = sim.state();
    for (i, name) in names.iter().enumerate() {
        let (p, v) = (s.pos[i], s.vel[i]);
        writeln!(
            out,
            "{},{},{},{},{},{},{},{}",
            s.t, name, p.x, p.y, v.x, v.y, s.angle[i], s.omega[i]
        )?;
    }
    Ok(())
}
