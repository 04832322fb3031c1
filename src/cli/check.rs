//! `physframes check`.

use clap::Args;

use super::{SceneArgs, Verbosity};
use crate::error::Result;
use crate::numbers::Readable as R;
use crate::scene::Shape;

#[derive(Debug, Args)]
pub struct CheckArgs {
    #[command(flatten)]
    scene: SceneArgs,
}

pub fn run(args: CheckArgs, verbosity: Verbosity) -> Result<()> {
    let scene = args.scene.load()?;
    if verbosity.quiet {
        return Ok(());
    }
    let mut out = String::new();
    macro_rules! outln {
        ($out:ident, $($arg:tt)*) => {{
            use std::fmt::Write as _;
            let _ = writeln!($out, $($arg)*);
        }};
    }
    let s = &scene.simulation;
    let r = &scene.render;
    outln!(
        out,
        "scene `{}` ({}) is valid",
        scene.name,
        scene.source.path.display()
    );
    outln!(
        out,
        "  simulation: {} with dt = {}, duration {} s, {} steps",
        s.integrator,
        R(s.dt),
        R(s.duration),
        scene.total_steps()
    );
    outln!(
        out,
        "  frames: {} at {} fps ({} steps a frame), {}×{} pixels",
        r.frame_count,
        R(r.fps),
        r.steps_per_frame,
        r.width,
        r.height
    );
    outln!(out, "  bodies: {}", scene.bodies.len());
    // A swarm can hold a million bodies: list the first ones, then say how many more.
    const LISTED: usize = 20;
    for b in scene.bodies.iter().take(LISTED) {
        let shape = match &b.shape {
            Shape::Circle { radius } => format!("circle r = {}", R(*radius)),
            Shape::Box { width, height } => format!("box {} × {}", R(*width), R(*height)),
            Shape::Polygon { points } => format!("polygon of {} points", points.len()),
            Shape::Points { points } => format!("{} point masses", points.len()),
        };
        // Rotation is shown for a body that is turned or turns, and only then, so that
        // the summary of a scene without rotation reads as it always did.
        let spin = if b.turns || b.angle != 0.0 {
            format!(
                ", angle {} rad, angular velocity {} rad/s, I = {}{}",
                R(b.angle),
                R(b.angular_velocity),
                R(b.inertia),
                if b.turns { ", turns" } else { "" }
            )
        } else {
            String::new()
        };
        if b.is_static {
            outln!(
                out,
                "    {}: static, at ({}, {}), {shape}{}",
                b.name,
                b.position.x,
                b.position.y,
                if b.angle != 0.0 {
                    format!(", angle {} rad", b.angle)
                } else {
                    String::new()
                }
            );
            continue;
        }
        outln!(
            out,
            "    {}: mass {}, centre of mass ({}, {}), velocity ({}, {}), {shape}{spin}",
            b.name,
            R(b.mass),
            R(b.position.x),
            R(b.position.y),
            R(b.velocity.x),
            R(b.velocity.y)
        );
    }
    if scene.bodies.len() > LISTED {
        outln!(out, "    … and {} more", scene.bodies.len() - LISTED);
    }
    if let Some(c) = &scene.contacts {
        outln!(
            out,
            "  contacts: {} colliding bodies, restitution {}, tolerance {}",
            c.bodies.len(),
            c.restitution,
            match c.tolerance {
                Some(t) => format!("{}", crate::numbers::Readable(t)),
                None => format!(
                    "{:e} of the smaller body's size",
                    crate::sim::contacts::DEFAULT_TOLERANCE
                ),
            }
        );
        let r = &c.resting;
        if r.speed > 0.0 {
            let slop = match r.slop {
                Some(s) => format!("{}", crate::numbers::Readable(s)),
                None => format!(
                    "{:e} of the smaller body's size",
                    crate::sim::contacts::DEFAULT_SLOP
                ),
            };
            outln!(
                out,
                "    friction {}; contacts approaching at most {} m/s rest, overlapping up to {slop}, {} sweeps a step",
                crate::numbers::Readable(c.friction),
                crate::numbers::about(r.speed),
                r.iterations
            );
            match r.sleep {
                Some(sl) => outln!(
                    out,
                    "    bodies at rest (at most {} m/s) for {} s fall asleep",
                    crate::numbers::about(sl.speed),
                    crate::numbers::Readable(sl.time)
                ),
                None => outln!(out, "    bodies never sleep"),
            }
        } else {
            outln!(
                out,
                "    friction {}; no resting contact (no gravity and no rest_speed): every approach is a collision",
                crate::numbers::Readable(c.friction)
            );
        }
    }
    outln!(out, "  forces: {}", scene.forces.len());
    for f in &scene.forces {
        outln!(out, "    {}", f.kind_name());
    }
    let layers = &scene.layers;
    if layers.axes.is_some() || !layers.fields.is_empty() || !layers.curves.is_empty() {
        outln!(
            out,
            "  figure: {}, {} field{}, {} curve{}",
            if layers.axes.is_some() {
                "axes"
            } else {
                "no axes"
            },
            layers.fields.len(),
            if layers.fields.len() == 1 { "" } else { "s" },
            layers.curves.len(),
            if layers.curves.len() == 1 { "" } else { "s" }
        );
    }
    if verbosity.verbose {
        for o in &scene.source.overrides {
            outln!(out, "  override: --set {o}");
        }
        outln!(out, "  scene hash: {}", scene.source.hash);
    }
    super::say(&out)
}
