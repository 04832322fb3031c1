//! Accuracy and stability studies: reference problems with closed forms, the
//! convergence of each integrator as the step shrinks, the work each needs for a given
//! precision, the largest step each can take, and how each keeps energy.
//!
//! Every study function returns data (tables, rows) and leaves the command line to
//! `cli::study`; `plots` draws the data. Nothing here runs threads, so results are
//! deterministic (the timings of the work-precision study excepted).

pub mod convergence;
pub mod energy;
pub mod plots;
pub mod reference;
pub mod stability;
pub mod work_precision;

pub use convergence::{
    convergence, ConvergenceOptions, ConvergenceRow, ConvergenceSeries, ConvergenceTable,
};
pub use energy::{energy_study, EnergyOptions, EnergySeries, EnergyStudy};
pub use reference::{ReferenceKind, ReferenceProblem};
pub use stability::{
    stability, stability_grid, Boundary, StabilityGrid, StabilityOptions, StabilityProblem,
    StabilityRow, StabilityTable,
};
pub use work_precision::{
    format_summary, work_precision, write_csv, WorkPrecisionOptions, WorkPrecisionRow, CSV_HEADER,
};
