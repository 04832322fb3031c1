//! Side-by-side comparison: the same scene run once per integrator in `compare`, and
//! the closed-form path where one exists, with the error of each run against time.
//!
//! The comparison runs beside the main simulation, on the simulation thread, and hands
//! the renderer a snapshot per frame: where each run's bodies are, and the error
//! history so far. A run that blows up stops and says when; the others go on.
//!
//! The error history is shared, not copied: the frames all hold one append-only
//! `ErrorHistory`, each seeing the rows up to its own, so a frame's snapshot costs the
//! same at the last frame as at the first.

use std::fmt;
use std::sync::{Arc, OnceLock};

use glam::DVec2;

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
    errors: ErrorHistory,
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
            errors: ErrorHistory::default(),
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
            errors: self.errors.clone(),
            error_labels,
        }
    }
}

/// One row of the error history: a frame's time and each integrator run's error.
pub type ErrorRow = (f64, Vec<f64>);

/// The number of segments of `Rows`: segment s holds 2^s rows, so these hold more rows
/// than a `usize` can count.
const SEGMENTS: usize = usize::BITS as usize;

/// Rows stored in segments of 1, 2, 4, ... slots. A segment is allocated when the first
/// row reaches it and never moves or grows, so appending never copies the rows before,
/// and a slot, once written, is never written again.
struct Rows {
    segments: [OnceLock<Box<[OnceLock<ErrorRow>]>>; SEGMENTS],
}

impl Rows {
    /// Returns the segment and the slot in it of row `i`.
    fn slot_of(i: usize) -> (usize, usize) {
        // Row i is number i + 1 counted from 1; segment s holds numbers 2^s ..= 2^(s+1) - 1.
        let n = i + 1;
        let s = n.ilog2() as usize;
        (s, n - (1 << s))
    }

    fn get(&self, i: usize) -> Option<&ErrorRow> {
        let (s, slot) = Self::slot_of(i);
        self.segments[s].get()?.get(slot)?.get()
    }
}

/// The error history as one frame sees it: the first `len` rows of storage shared with
/// the `Comparison` that appends to it and with every other frame. Cloning one is an
/// `Arc` clone; the rows it sees never change.
#[derive(Clone)]
pub struct ErrorHistory {
    rows: Arc<Rows>,
    len: usize,
}

impl Default for ErrorHistory {
    fn default() -> Self {
        ErrorHistory {
            rows: Arc::new(Rows {
                segments: std::array::from_fn(|_| OnceLock::new()),
            }),
            len: 0,
        }
    }
}

impl ErrorHistory {
    /// Appends a row after the last this history sees. Only the `Comparison` appends, to
    /// its own history, which always sees every row written so far; the frames' clones
    /// see only the rows before it.
    fn push(&mut self, row: ErrorRow) {
        let (s, slot) = Rows::slot_of(self.len);
        let segment = self.rows.segments[s]
            .get_or_init(|| std::iter::repeat_with(OnceLock::new).take(1 << s).collect());
        let written = segment[slot].set(row);
        debug_assert!(written.is_ok(), "row {} was written twice", self.len);
        self.len += 1;
    }

    /// Returns the number of rows this frame sees: one per frame up to and including it.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Returns whether this history has no row.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Returns row `i`, or `None` when this history does not see it.
    pub fn get(&self, i: usize) -> Option<&ErrorRow> {
        if i < self.len {
            self.rows.get(i)
        } else {
            None
        }
    }

    /// Returns the last row this history sees: its own frame's.
    pub fn last(&self) -> Option<&ErrorRow> {
        self.len.checked_sub(1).and_then(|i| self.get(i))
    }

    /// Returns the rows this history sees, oldest first.
    pub fn iter(&self) -> impl Iterator<Item = &ErrorRow> + '_ {
        // Rows are written in order, so the written slots come first in every segment.
        self.rows
            .segments
            .iter()
            .map_while(OnceLock::get)
            .flat_map(|segment| segment.iter().map_while(OnceLock::get))
            .take(self.len)
    }
}

impl PartialEq for ErrorHistory {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl fmt::Debug for ErrorHistory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// Orders integrators by expected accuracy at equal step: adaptive, then by order.
fn accuracy_rank(kind: IntegratorKind) -> (bool, u32) {
    (kind.is_adaptive(), kind.order())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(k: usize) -> ErrorRow {
        (k as f64 * 0.5, vec![k as f64, -(k as f64)])
    }

    #[test]
    fn each_snapshot_sees_the_rows_up_to_its_own_and_no_later_one() {
        let mut history = ErrorHistory::default();
        assert!(history.is_empty() && history.last().is_none());
        let mut snapshots = Vec::new();
        // 100 rows fill segments 0 to 5 and part of segment 6, so rows on both sides of
        // every boundary are read back.
        for k in 0..100 {
            history.push(row(k));
            snapshots.push(history.clone());
        }
        for (k, snapshot) in snapshots.iter().enumerate() {
            assert_eq!(snapshot.len(), k + 1);
            let expected: Vec<ErrorRow> = (0..=k).map(row).collect();
            let seen: Vec<ErrorRow> = snapshot.iter().cloned().collect();
            assert_eq!(seen, expected, "snapshot {k}");
            assert_eq!(snapshot.last(), Some(&row(k)));
            assert_eq!(snapshot.get(k), Some(&row(k)));
            // Rows appended after the snapshot are in the shared storage, yet unseen.
            assert_eq!(snapshot.get(k + 1), None);
        }
        assert_eq!(snapshots[99], history);
        assert_ne!(snapshots[98], history);
    }

    #[test]
    fn rows_map_to_segments_of_doubling_size() {
        let slots: Vec<(usize, usize)> = (0..8).map(Rows::slot_of).collect();
        assert_eq!(
            slots,
            [
                (0, 0),
                (1, 0),
                (1, 1),
                (2, 0),
                (2, 1),
                (2, 2),
                (2, 3),
                (3, 0)
            ]
        );
    }
}
