//! Sleeping: bodies that have come to rest stop being simulated until something
//! awake comes near them, as in Box2D and Rapier. A settled pile, a standing tower or
//! a box that slid to a stop then costs almost nothing, and stays exactly where it
//! came to rest instead of creeping by round-off.
//!
//! # The rules
//!
//! - *At rest*: at the end of each step, a body whose every point moves no faster than
//!   the sleep speed, |v| + |ω|·reach ≤ v_sleep, adds h to its time at rest; any faster
//!   and its time at rest returns to 0. A body under a force that changes with time,
//!   or tied by a spring to another body, never counts as at rest.
//! - *Islands*: the bodies that touch (the pairs the step's end found within reach of
//!   each other, both awake and movable) form islands. An island falls asleep when
//!   every body in it has been at rest for the sleep time and it rests on something
//!   that does not move (a static body or a sleeping one): a body that floats free,
//!   however slowly, never sleeps. Its bodies' velocities and spins become exactly 0.
//! - *Asleep*: at the start of each step a sleeping body is put back where it was and
//!   held still (whatever the integrator did with gravity), and the contact stages
//!   treat it as static: its pairs with static or sleeping bodies are skipped, which is
//!   what makes sleeping cheap.
//! - *Waking*: when an awake body that moves (faster than the sleep speed at the
//!   step's start) may touch a sleeping one within the
//!   step (their swept boxes, widened by the contact margin, meet), the sleeping body
//!   and every sleeping body connected to it through such boxes wake before the step's
//!   contacts are solved, and move this step as the integrator moved them. A body
//!   struck onto a sleeping one within the step (its path changed by an impulse after
//!   the boxes were compared) meets it as a static body for the rest of that step, and
//!   wakes it for the next.
//!
//! Every decision is taken in collider order from the state alone, so the outcome is
//! the same on every run and for any number of threads; each collider's time at rest
//! (or `ASLEEP`) is part of the state that checkpoints carry.

use glam::DVec2;

use super::narrow_phase::Contact;
use super::response::Inverse;
use super::sweep::immovable;
use super::toi::Path;
use super::{Collider, Sleep};
use crate::sim::State;

/// The time at rest that marks a collider asleep.
pub const ASLEEP: f64 = f64::INFINITY;

/// Disjoint sets of colliders (union by size, path halving), reused step after step.
#[derive(Default)]
pub(super) struct Islands {
    parent: Vec<u32>,
    size: Vec<u32>,
    /// Per root: the least time at rest of the island's bodies.
    least: Vec<f64>,
    /// Per root: whether the island rests on something that does not move.
    grounded: Vec<bool>,
    /// Per collider: whether it was touched this step (waking).
    touched: Vec<bool>,
}

impl Islands {
    fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
        self.size.clear();
        self.size.resize(n, 1);
    }

    fn find(&mut self, mut k: usize) -> usize {
        while self.parent[k] as usize != k {
            let up = self.parent[self.parent[k] as usize];
            self.parent[k] = up;
            k = up as usize;
        }
        k
    }

    fn union(&mut self, a: usize, b: usize) {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return;
        }
        if self.size[ra] < self.size[rb] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb] = ra as u32;
        self.size[ra] += self.size[rb];
    }
}

/// Holds body b where the step began, at rest: its pose at the start, and no velocity
/// or spin (whatever the integrator made of them).
fn hold(b: usize, start: &State, end: &mut State, spins: bool) {
    end.pos[b] = start.pos[b];
    end.vel[b] = DVec2::ZERO;
    if spins {
        end.angle[b] = start.angle[b];
        end.omega[b] = 0.0;
    }
}

/// The start of a step: wakes every sleeping collider that an awake, movable one that
/// is moving (faster than the sleep speed `speed` at the step's start) may touch
/// within the step (`pairs` are the broad phase's, whose swept boxes meet), with the
/// sleeping colliders joined to it through such pairs; and holds every other
/// sleeping collider where the step began, at rest, with a zero inverse mass and
/// inertia so that the contact stages treat it as static. Returns whether any collider
/// sleeps through this step.
#[allow(clippy::too_many_arguments)]
pub(super) fn hold_or_wake(
    still: &mut [f64],
    pairs: &[(u32, u32)],
    colliders: &[Collider],
    inv: &mut [Inverse],
    paths: &mut [Path],
    start: &State,
    end: &mut State,
    spins: bool,
    speed: f64,
    islands: &mut Islands,
) -> bool {
    if !still.contains(&ASLEEP) {
        return false;
    }
    let n = still.len();
    // Only a body that moves wakes its sleeping neighbours here. One at rest beside a
    // sleeping island, near enough for their boxes to meet but not within reach of it
    // (so not of its island), would otherwise wake it the step it fell asleep, and be
    // woken by it in turn when its own island slept: two islands at rest side by side
    // never both slept (a 2,000-disc pile and a disc on the floor beside it, seen
    // taking turns every 0.5 s). A body at rest that comes within reach of a sleeping
    // one wakes it at the step's end (`settle`). A speed that is not a number counts as
    // moving.
    let moving = |k: usize| {
        let b = colliders[k].body;
        let w = if spins { start.omega[b].abs() } else { 0.0 };
        let fastest = start.vel[b].length() + w * colliders[k].reach;
        fastest > speed || fastest.is_nan()
    };
    islands.reset(n);
    islands.touched.clear();
    islands.touched.resize(n, false);
    for &(i, j) in pairs {
        let (i, j) = (i as usize, j as usize);
        match (still[i] == ASLEEP, still[j] == ASLEEP) {
            (true, true) => islands.union(i, j),
            (true, false) if !immovable(&inv[j]) && moving(j) => islands.touched[i] = true,
            (false, true) if !immovable(&inv[i]) && moving(i) => islands.touched[j] = true,
            _ => {}
        }
    }
    // An island is woken by any of its bodies being touched.
    for k in 0..n {
        if islands.touched[k] {
            let root = islands.find(k);
            islands.touched[root] = true;
        }
    }
    let mut holding = false;
    for k in 0..n {
        if still[k] != ASLEEP {
            continue;
        }
        let root = islands.find(k);
        if islands.touched[root] {
            // Awake again: it moves this step as the integrator moved it.
            still[k] = 0.0;
            continue;
        }
        holding = true;
        let b = colliders[k].body;
        hold(b, start, end, spins);
        let p = &mut paths[k];
        p.r = start.pos[b];
        p.angle = end.angle[b];
        (p.dr, p.dangle, p.v, p.omega, p.dv, p.domega) =
            (DVec2::ZERO, 0.0, DVec2::ZERO, 0.0, DVec2::ZERO, 0.0);
        inv[k] = Inverse {
            mass: 0.0,
            inertia: 0.0,
        };
    }
    holding
}

/// Holds every sleeping collider where the step began, at rest: what
/// [`hold_or_wake`] does when nothing awake can move.
pub(super) fn hold_all(
    still: &[f64],
    colliders: &[Collider],
    start: &State,
    end: &mut State,
    spins: bool,
) {
    for (c, &s) in colliders.iter().zip(still) {
        if s == ASLEEP {
            hold(c.body, start, end, spins);
        }
    }
}

/// The end of a step: adds h to the time at rest of every awake, movable collider that
/// moved no faster than the sleep speed (and sets it to 0 for one that moved faster or
/// never sleeps), joins the colliders of the step's contacts (`touching`) into islands,
/// wakes a sleeping collider that an awake one touches, and puts to sleep every island
/// that has been at rest for the sleep time and rests on something that does not move.
/// Returns whether any body fell asleep (its velocity and spin set to 0).
#[allow(clippy::too_many_arguments)]
pub(super) fn settle(
    sleep: Sleep,
    h: f64,
    still: &mut [f64],
    restless: &[bool],
    touching: &[(u32, u32, Contact)],
    colliders: &[Collider],
    inv: &[Inverse],
    end: &mut State,
    spins: bool,
    islands: &mut Islands,
) -> bool {
    let n = still.len();
    let awake = |still: &[f64], k: usize| still[k] != ASLEEP && !immovable(&inv[k]);
    // At rest this step: |v| + |ω|·reach ≤ v_sleep.
    for k in 0..n {
        if !awake(still, k) {
            continue;
        }
        let b = colliders[k].body;
        let w = if spins { end.omega[b].abs() } else { 0.0 };
        let speed = end.vel[b].length() + w * colliders[k].reach;
        // (Written so that a speed that is not a number counts as moving.)
        still[k] = if !restless[k] && speed <= sleep.speed {
            still[k] + h
        } else {
            0.0
        };
    }
    islands.reset(n);
    islands.grounded.clear();
    islands.grounded.resize(n, false);
    islands.touched.clear();
    islands.touched.resize(n, false);
    for &(i, j, _) in touching {
        let (i, j) = (i as usize, j as usize);
        match (awake(still, i), awake(still, j)) {
            (true, true) => islands.union(i, j),
            (true, false) => {
                islands.touched[i] = true;
                // A sleeping body touched by an awake one wakes for the next step.
                if still[j] == ASLEEP {
                    still[j] = 0.0;
                }
            }
            (false, true) => {
                islands.touched[j] = true;
                if still[i] == ASLEEP {
                    still[i] = 0.0;
                }
            }
            (false, false) => {}
        }
    }
    // Each island's least time at rest, and whether it rests on something.
    islands.least.clear();
    islands.least.resize(n, ASLEEP);
    for k in 0..n {
        if !awake(still, k) {
            continue;
        }
        let root = islands.find(k);
        islands.least[root] = islands.least[root].min(still[k]);
        if islands.touched[k] {
            islands.grounded[root] = true;
        }
    }
    let mut slept = false;
    for k in 0..n {
        if !awake(still, k) {
            continue;
        }
        let root = islands.find(k);
        if !(islands.grounded[root] && islands.least[root] >= sleep.time) {
            continue;
        }
        still[k] = ASLEEP;
        let b = colliders[k].body;
        end.vel[b] = DVec2::ZERO;
        if spins {
            end.omega[b] = 0.0;
        }
        slept = true;
    }
    slept
}
