//! The simulation: the flat state of every body, the forces and torques acting on
//! them, and the integrators that advance them in time.
//!
//! Data flows one way through this module: a validated [`crate::scene::Scene`] builds a
//! [`System`] (masses, moments of inertia and forces, fixed for the run) and a [`State`]
//! (time, positions, velocities, angles and angular velocities, advanced every step). An [`Integrator`] advances the state using only the
//! accelerations the system reports. Nothing here knows that frames or pixels exist.
//!
//! Hot data lives in flat arrays indexed by body: `State::pos`, `State::vel`, the force
//! buffers inside the integrators, and `System::inv_mass`. Cold data (names, colours,
//! shapes) stays in the scene.

pub mod baseline;
pub mod chunks;
pub mod contacts;
pub mod dof;
mod energy;
pub mod exact;
pub mod forces;
pub mod integrators;
pub mod rigid;
pub mod scalar_ode;
mod simulation;
pub mod state;
pub mod system;

pub use baseline::HandWrittenEuler;
pub use contacts::{ContactEvent, Contacts};
pub use forces::{Anchor, ForceSpec, Selection};
pub use integrators::{Integrator, IntegratorKind, Stepper, Tolerances};
pub use scalar_ode::ScalarMethod;
pub use simulation::{
    BlowUp, Simulation, MAX_ADAPTIVE_STEPS_PER_ADVANCE, OVERLAP, STIFF, UNANSWERABLE,
};
pub use state::{Coords, State};
pub use system::System;
