//! physframes' integration tests, compiled into one binary (as tiny-skia and resvg do):
//! each module tests one capability, through the library or through the real binary.

mod bad_input;
mod closed_forms;
mod perf;
mod render_cli;
mod util;
