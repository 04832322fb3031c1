//! physframes' integration tests, compiled into one binary (as tiny-skia and resvg do):
//! each module tests one capability, through the library or through the real binary.

mod bad_input;
mod cli_extras;
mod closed_forms;
mod diagnostics;
mod docs;
mod every_scene;
mod figures;
mod golden;
mod integrators;
mod perf;
mod properties;
mod render_cli;
mod resume;
mod rotation;
mod shards;
mod studies;
mod uniform_step;
mod util;
