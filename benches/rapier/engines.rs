//! The two engines behind one face: physframes' own `Simulation` of a scene, and a
//! Rapier world built from the same checked `Scene`, body for body.
//!
//! Rapier's world takes from the scene every body's shape, centre of mass, angle,
//! velocity and spin, its mass and moment of inertia (given to Rapier as they are, not
//! recomputed from a density), its friction and restitution, the scene's gravity and
//! its step. Our pair rules are Rapier's `GeometricMean` for friction (√(μ_a·μ_b)) and
//! `Max` for restitution, so the pairs are given those. What stays Rapier's own is
//! everything its integration parameters hold besides the step and the solver's
//! budget: its contact softness (30 Hz with a damping ratio of 10 between bodies,
//! 60 Hz against a fixed body), its allowed linear error, its prediction distance and
//! its contact recycling. Each engine is built twice: with bodies that never sleep
//! (ours with `sleep = false`, Rapier's with `can_sleep(false)`), which compares the
//! solvers, and with sleeping on in both, each with its own default thresholds, which
//! compares what a user of either gets by default.

use glam::DVec2;
use physframes::scene::{Scene, Shape};
use physframes::sim::{ForceSpec, Simulation};
use rapier2d_f64::prelude::{
    CoefficientCombineRule, ColliderBuilder, IntegrationParameters, MassProperties, PhysicsWorld,
    RigidBodyBuilder, RigidBodyHandle, Vector,
};

/// A body's centre of mass and angle.
pub type Pose = (DVec2, f64);

/// An engine that steps a scene and reports where its bodies are.
pub trait Engine {
    /// Advances the scene by one step of the scene's dt.
    fn step(&mut self);
    /// Returns each body's centre of mass and angle, in the scene's body order.
    fn poses(&self) -> Vec<Pose>;
}

/// physframes: the scene's own simulation, through the public path a render takes.
pub struct Physframes {
    sim: Simulation,
}

impl Physframes {
    /// Builds the scene's simulation, with its bodies sleeping as the scene says when
    /// `sleeping`, or never.
    pub fn new(scene: &Scene, sleeping: bool) -> Self {
        let mut scene = scene.clone();
        if !sleeping {
            if let Some(c) = scene.contacts.as_mut() {
                c.resting.sleep = None;
            }
        }
        Physframes {
            sim: scene.simulation(),
        }
    }
}

impl Engine for Physframes {
    fn step(&mut self) {
        self.sim
            .step()
            .expect("the bench's scenes neither blow up nor overlap past the limit");
    }

    fn poses(&self) -> Vec<Pose> {
        let s = self.sim.state();
        s.pos.iter().copied().zip(s.angle.iter().copied()).collect()
    }
}

/// Rapier: a `PhysicsWorld` of the scene's bodies, one rigid body and one collider
/// each.
pub struct Rapier {
    world: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
}

impl Rapier {
    /// Builds the scene in Rapier with `substeps` solver substeps a step
    /// (`num_solver_iterations`); every other integration parameter but the step keeps
    /// Rapier's default. Its bodies may sleep (Rapier's default) when `sleeping`.
    pub fn new(scene: &Scene, substeps: usize, sleeping: bool) -> Self {
        let contacts = scene
            .contacts
            .as_ref()
            .expect("the bench's scenes have [contacts]");
        let mut world = PhysicsWorld::new();
        world.gravity = to_rapier(gravity(scene));
        world.integration_parameters = IntegrationParameters {
            dt: scene.simulation.dt,
            num_solver_iterations: substeps,
            ..IntegrationParameters::default()
        };
        let mut handles = Vec::with_capacity(scene.bodies.len());
        for b in &scene.bodies {
            let collider = match b.shape {
                Shape::Circle { radius } => ColliderBuilder::ball(radius),
                Shape::Box { width, height } => ColliderBuilder::cuboid(0.5 * width, 0.5 * height),
                _ => panic!("the bench's scenes hold only circles and boxes"),
            }
            .friction(b.friction.unwrap_or(contacts.friction))
            .friction_combine_rule(CoefficientCombineRule::GeometricMean)
            .restitution(b.restitution.unwrap_or(contacts.restitution))
            .restitution_combine_rule(CoefficientCombineRule::Max);
            let body = if b.is_static {
                RigidBodyBuilder::fixed()
            } else {
                RigidBodyBuilder::dynamic()
                    .linvel(to_rapier(b.velocity))
                    .angvel(b.angular_velocity)
                    .can_sleep(sleeping)
            }
            .translation(to_rapier(b.position))
            .rotation(b.angle);
            let collider = if b.is_static {
                collider
            } else {
                collider.mass_properties(MassProperties::new(Vector::ZERO, b.mass, b.inertia))
            };
            let (handle, _) = world.insert(body, collider);
            handles.push(handle);
        }
        Rapier { world, handles }
    }
}

impl Engine for Rapier {
    fn step(&mut self) {
        self.world.step();
    }

    fn poses(&self) -> Vec<Pose> {
        self.handles
            .iter()
            .map(|&h| {
                let b = &self.world.bodies[h];
                let t = b.translation();
                (DVec2::new(t.x, t.y), b.rotation().angle())
            })
            .collect()
    }
}

/// Returns the scene's one force, uniform gravity, which the bench's scenes apply to
/// every body that moves.
fn gravity(scene: &Scene) -> DVec2 {
    match scene.forces.as_slice() {
        [ForceSpec::Gravity { g, .. }] => *g,
        _ => panic!("the bench's scenes have gravity as their only force"),
    }
}

fn to_rapier(v: DVec2) -> Vector {
    Vector::new(v.x, v.y)
}
