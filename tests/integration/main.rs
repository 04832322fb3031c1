//! physframes' integration tests, compiled into one binary (as tiny-skia and resvg do):
//! each module tests one capability, through the library or through the real binary.

mod bad_input;
mod cli_extras;
mod closed_forms;
mod collisions;
mod diagnostics;
mod docs;
mod every_scene;
mod figures;
mod golden;
mod integrators;
mod interrupt;
mod mutations;
mod perf;
mod properties;
mod render_cli;
mod resting;
mod resume;
mod rotation;
mod run_length;
mod runaway;
mod shards;
mod sleep;
mod studies;
mod trail_frames;
mod uniform_step;
mod util;
