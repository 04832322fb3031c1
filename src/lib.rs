//! physframes: simulate 2-D bodies under forces and render every frame to PNG.
//!
//! Data flows one way: a scene file is parsed and validated into a [`scene::Scene`]; the
//! scene builds a [`sim::Simulation`]; the simulation yields the state at every frame
//! time; the renderer draws each state into a pixmap; the output stage encodes it to PNG
//! and writes it atomically. The simulation never imports the renderer, and the renderer
//! only reads simulation state.

pub mod blowup;
pub mod checkpoint;
pub mod cli;
pub mod compare;
pub mod diff;
pub mod error;
pub mod figures;
pub mod fuzzing;
pub mod history;
pub mod interrupt;
pub mod memory;
pub mod numbers;
pub mod output;
pub mod pipeline;
pub mod render;
pub mod scene;
pub mod sim;
pub mod study;
pub mod threads;
