pub mod diff;
pub mod render;
