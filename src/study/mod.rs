//! Accuracy studies: reference problems with closed forms, the convergence of each
//! integrator as the step shrinks, and the work each needs for a given precision.
//!
//! Every function here returns data (tables, rows) and leaves drawing and the command
//! line to their own modules. Nothing here runs threads, so results are deterministic
//! (the timings of the work-precision study excepted).

pub mod convergence;
pub mod reference;
pub mod work_precision;

pub use convergence::{
    convergence, ConvergenceOptions, ConvergenceRow, ConvergenceSeries, ConvergenceTable,
};
pub use reference::{ReferenceKind, ReferenceProblem};
pub use work_precision::{
    format_summary, work_precision, write_csv, WorkPrecisionOptions, WorkPrecisionRow, CSV_HEADER,
};
