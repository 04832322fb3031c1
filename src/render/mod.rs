//! Rendering primitives for figures and study plots: outline text, tick placement and a
//! reusable 2-D chart.

pub mod plot;
pub mod text;
pub mod ticks;
