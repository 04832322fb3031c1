//! Side-by-side comparison: the same scene run once per integrator in `compare`, and
//! the closed-form path where one exists, with the error of each run against time.
//!
//! The comparison runs beside the main simulation, on the simulation thread, and hands
//! the renderer a snapshot per frame: where each run's bodies are, and the error
//! history so far. A run that blows up stops and says when; the others go on.
//!
//! The error history is shared, not copied: the frames all hold one append-only
//! `ErrorHistory` ([`crate::history`]), each seeing the rows up to its own, so a frame's
//! snapshot costs the same at the last frame as at the first.

use glam::DVec2;

use crate::history::{History, HistoryWriter};
use crate::scene::{CompareRun, Scene};
use crate::sim::exact::ExactSolution;
use crate::sim::{IntegratorKind, Simulation};

/// One compared run at one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Ghost {
    /// "exact" or the integrator's name.
    pub label: String,
    /// The bodies' centres of mass, or `None` after the run blew up.
    pub pos: Option<Vec<DVec2>>,
    /// The time at which the run blew up, if it did.
    pub blew_up_at: Option<f64>,
}

/// Everything the renderer needs to draw a comparison at one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareFrame {
    /// The compared runs, in the order `compare` lists them.
    pub ghosts: Vec<Ghost>,
    /// What errors are measured against: "exact", or the most accurate integrator.
    pub reference: String,
    /// For each frame so far, its time and each integrator run's error: the largest,
    /// over the bodies, of |r - r_reference| (NaN once a run has blown up).
    pub errors: ErrorHistory,
    /// The labels of the integrator runs whose errors `errors` holds, in order.
    pub error_labels: Vec<String>,
}

/// The compared runs of a scene, advanced frame by frame.
pub struct Comparison {
    runs: Vec<(CompareRun, Option<Simulation>, Option<f64>)>,
    exact: Option<ExactSolution>,
    /// The index in `runs` of the reference when there is no closed form.
    reference: Option<usize>,
    errors: HistoryWriter<ErrorRow>,
}

impl Comparison {
    /// Returns the comparison a scene asks for, or `None` when `compare` is empty.
    pub fn new(scene: &Scene) -> Option<Self> {
        let list = &scene.simulation.compare;
        if list.is_empty() {
            return None;
        }
        let exact = ExactSolution::new(
            &scene.bodies.iter().map(|b| b.mass).collect::<Vec<_>>(),
            &scene.forces,
            &scene.initial_state(),
        );
        let runs: Vec<(CompareRun, Option<Simulation>, Option<f64>)> = list
            .iter()
            .map(|run| match run {
                CompareRun::Integrator(kind) => (*run, Some(scene.simulation_with(*kind)), None),
                CompareRun::Exact => (*run, None, None),
            })
            .collect();
        // Without a closed form, errors are measured against the most accurate run:
        // the highest order, adaptive dopri5 first.
        let reference = match exact {
            Some(_) => None,
            None => runs
                .iter()
                .enumerate()
                .filter_map(|(i, (run, _, _))| match run {
                    CompareRun::Integrator(k) => Some((i, accuracy_rank(*k))),
                    CompareRun::Exact => None,
                })
                .max_by_key(|(_, rank)| *rank)
                .map(|(i, _)| i),
        };
        Some(Comparison {
            runs,
            exact,
            reference,
            errors: HistoryWriter::new(),
        })
    }

    /// Advances every run to time `t` and returns the frame's snapshot.
    pub fn advance_to(&mut self, t: f64) -> CompareFrame {
        for (_, sim, blew_up) in &mut self.runs {
            if let (Some(s), None) = (sim.as_mut(), *blew_up) {
                if let Err(b) = s.advance_to(t) {
                    *blew_up = Some(b.t);
                }
            }
        }
        let exact = self.exact.as_ref().map(|e| e.state_at(t).pos);
        let reference_pos: Option<Vec<DVec2>> = match (&exact, self.reference) {
            (Some(pos), _) => Some(pos.clone()),
            (None, Some(i)) => match &self.runs[i] {
                (_, Some(sim), None) => Some(sim.state().pos.clone()),
                _ => None,
            },
            (None, None) => None,
        };
        let mut ghosts = Vec::with_capacity(self.runs.len());
        let mut row = Vec::new();
        let mut error_labels = Vec::new();
        for (i, (run, sim, blew_up)) in self.runs.iter().enumerate() {
            let (label, pos) = match (run, sim) {
                (CompareRun::Exact, _) => ("exact".to_string(), exact.clone()),
                (CompareRun::Integrator(k), Some(s)) => (
                    k.name().to_string(),
                    blew_up.is_none().then(|| s.state().pos.clone()),
                ),
                (CompareRun::Integrator(k), None) => (k.name().to_string(), None),
            };
            if matches!(run, CompareRun::Integrator(_)) && Some(i) != self.reference {
                // e = max over bodies of |r - r_reference|.
                let e = match (&pos, &reference_pos) {
                    (Some(p), Some(r)) => p
                        .iter()
                        .zip(r)
                        .map(|(a, b)| (*a - *b).length())
                        .fold(0.0, f64::max),
                    _ => f64::NAN,
                };
                row.push(e);
                error_labels.push(label.clone());
            }
            ghosts.push(Ghost {
                label,
                pos,
                blew_up_at: *blew_up,
            });
        }
        self.errors.push((t, row));
        let reference = match (self.exact.is_some(), self.reference) {
            (true, _) => "exact".to_string(),
            (false, Some(i)) => ghosts[i].label.clone(),
            (false, None) => String::new(),
        };
        CompareFrame {
            ghosts,
            reference,
            errors: self.errors.history().clone(),
            error_labels,
        }
    }
}

/// One row of the error history: a frame's time and each integrator run's error.
pub type ErrorRow = (f64, Vec<f64>);

/// The error history as one frame sees it: the rows up to and including its own, in
/// storage shared with every other frame (see [`crate::history`]).
pub type ErrorHistory = History<ErrorRow>;

/// Orders integrators by expected accuracy at equal step: adaptive, then by order.
fn accuracy_rank(kind: IntegratorKind) -> (bool, u32) {
    (kind.is_adaptive(), kind.order())
}
