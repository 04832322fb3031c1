//! A hand-written explicit Euler loop for uniform gravity and linear drag on bodies of
//! equal mass: a measuring baseline, not part of the simulation.
//!
//! The general pipeline ([`super::Simulation`]) sums every force family by family,
//! divides by mass, checks that each step's state is finite and works on
//! `Vec<DVec2>`. [`HandWrittenEuler`] is the loop a programmer would write for this one
//! problem instead: the constants folded, positions and velocities in four flat `f64`
//! arrays, chunks of bodies on rayon's threads, and nothing else. It is timed beside the
//! pipeline, at the same moment on the same machine, by `cargo bench --bench simulate`
//! and `physframes bench --simulate-only`, so that the pipeline's cost is stated as a
//! ratio to this floor rather than as an absolute time, which moves with the machine.

use glam::DVec2;
use rayon::prelude::*;

use super::{IntegratorKind, State, System};

/// Bodies per rayon task: 16,384 bodies are 512 KiB of the four arrays and some tens of
/// microseconds of work, far more than scheduling a task costs, while 10^6 bodies still
/// make 62 tasks to share among the threads.
pub const BASELINE_CHUNK: usize = 16_384;

/// Explicit Euler for a = g - (k/m)·v on N bodies of mass m, over flat arrays.
///
/// It exists only for a system that it reproduces: explicit Euler, every force uniform
/// gravity or linear drag acting on every body, and every body of the same mass (see
/// [`HandWrittenEuler::new`]). With one gravity and one drag on bodies of mass 1 it
/// gives the pipeline's bits: m·g = g, k/m = k and F·(1/m) = F are then exact, and the
/// sums are taken in the same order. With other masses the two differ by rounding only.
#[derive(Clone, Debug)]
pub struct HandWrittenEuler {
    /// g = Σ g_i, the acceleration of every gravity force together.
    g: DVec2,
    /// k/m, with k = Σ k_i the drag coefficients together and m the common mass.
    k_over_m: f64,
    /// The step h.
    h: f64,
    x: Vec<f64>,
    y: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
}

impl HandWrittenEuler {
    /// Returns the baseline of a system stepped by `kind` with step `h` from `state`, or
    /// `None` when the baseline would not be the same physics: a method other than
    /// explicit Euler, a force other than gravity or linear drag, a force on only some
    /// bodies, unequal masses, or no body.
    pub fn new(system: &System, kind: IntegratorKind, h: f64, state: &State) -> Option<Self> {
        if kind != IntegratorKind::Euler || state.len() != system.len() {
            return None;
        }
        let m = system.uniform_mass()?;
        let (g, k) = system.force_set().gravity_and_linear_drag()?;
        let mut baseline = HandWrittenEuler {
            g,
            // The drag's share of a = g - (k/m)·v, folded once.
            k_over_m: k / m,
            h,
            x: Vec::new(),
            y: Vec::new(),
            vx: Vec::new(),
            vy: Vec::new(),
        };
        baseline.set_state(state);
        Some(baseline)
    }

    /// Starts again from `state`, which must hold as many bodies as the system.
    pub fn set_state(&mut self, state: &State) {
        self.x.clear();
        self.y.clear();
        self.vx.clear();
        self.vy.clear();
        self.x.extend(state.pos.iter().map(|r| r.x));
        self.y.extend(state.pos.iter().map(|r| r.y));
        self.vx.extend(state.vel.iter().map(|v| v.x));
        self.vy.extend(state.vel.iter().map(|v| v.y));
    }

    /// Returns the number of bodies.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Returns true when there is no body.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Returns every body's position.
    pub fn positions(&self) -> Vec<DVec2> {
        self.x
            .iter()
            .zip(&self.y)
            .map(|(x, y)| DVec2::new(*x, *y))
            .collect()
    }

    /// Returns every body's velocity.
    pub fn velocities(&self) -> Vec<DVec2> {
        self.vx
            .iter()
            .zip(&self.vy)
            .map(|(x, y)| DVec2::new(*x, *y))
            .collect()
    }

    /// Takes `n` steps, on the threads of the current rayon pool.
    pub fn run_steps(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Takes one step, in chunks of [`BASELINE_CHUNK`] bodies on the threads of the
    /// current rayon pool.
    pub fn step(&mut self) {
        let (g, k_over_m, h) = (self.g, self.k_over_m, self.h);
        self.x
            .par_chunks_mut(BASELINE_CHUNK)
            .zip(self.y.par_chunks_mut(BASELINE_CHUNK))
            .zip(self.vx.par_chunks_mut(BASELINE_CHUNK))
            .zip(self.vy.par_chunks_mut(BASELINE_CHUNK))
            .for_each(|(((x, y), vx), vy)| {
                let bodies = x.iter_mut().zip(y).zip(vx.iter_mut().zip(vy));
                for ((x, y), (vx, vy)) in bodies {
                    // x_{n+1} = x_n + h·v_n, with the velocity from the start of the step.
                    *x += h * *vx;
                    *y += h * *vy;
                    // v_{n+1} = v_n + h·a(x_n, v_n), with a = g - (k/m)·v_n.
                    *vx += h * (g.x - k_over_m * *vx);
                    *vy += h * (g.y - k_over_m * *vy);
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Anchor, ForceSpec, Selection, Simulation};

    fn gravity(g: DVec2) -> ForceSpec {
        ForceSpec::Gravity {
            g,
            bodies: Selection::All,
        }
    }

    fn drag(k: f64) -> ForceSpec {
        ForceSpec::Drag {
            k,
            bodies: Selection::All,
        }
    }

    /// A swarm of `n` bodies with positions and velocities spread over several
    /// magnitudes and both signs.
    fn swarm(n: usize) -> State {
        let (pos, vel) = (0..n)
            .map(|i| {
                let x = i as f64;
                (
                    DVec2::new(100.0 * (0.37 * x).sin(), 3.0 * x / n as f64),
                    DVec2::new((1.3 * x).cos(), 10.0 * (0.71 * x).sin() - 0.4),
                )
            })
            .unzip();
        State::new(0.0, pos, vel)
    }

    #[test]
    fn it_gives_the_pipelines_bits_on_bodies_of_mass_one() {
        // More bodies than one chunk, and not a whole number of chunks or of the
        // pipeline's lanes; the forces of scenes/bench/euler-1e6.toml, and each alone.
        let n = BASELINE_CHUNK + 1003;
        let state = swarm(n);
        let g = DVec2::new(0.0, -9.81);
        for forces in [
            vec![gravity(g), drag(0.1)],
            vec![gravity(g)],
            vec![drag(0.1)],
        ] {
            let system = System::new(vec![1.0; n], &forces);
            let h = 0.001;
            let mut baseline =
                HandWrittenEuler::new(&system, IntegratorKind::Euler, h, &state).expect("fits");
            let mut sim = Simulation::new(system, state.clone(), IntegratorKind::Euler, h);
            sim.run_steps(25).expect("finite");
            baseline.run_steps(25);
            let bits = |v: &[DVec2]| -> Vec<[u64; 2]> {
                v.iter().map(|v| [v.x.to_bits(), v.y.to_bits()]).collect()
            };
            assert!(
                bits(&baseline.positions()) == bits(&sim.state().pos),
                "{forces:?}"
            );
            assert!(
                bits(&baseline.velocities()) == bits(&sim.state().vel),
                "{forces:?}"
            );
        }
    }

    #[test]
    fn it_agrees_with_the_pipeline_to_rounding_on_other_masses() {
        // With m = 2.5 the pipeline computes ((m·g) - k·v)·(1/m) and the baseline
        // g - (k/m)·v: the same acceleration with different roundings. Each is within
        // 5ε·A of the exact a(v), with A = |g| + (k/m)·V and V the largest speed
        // component, and a(v) changes by (k/m)·|Δv| between the two velocities. Each
        // update rounds twice (h·a, then the sum), by at most ε·(h·A + V) on each side,
        // and 0 ≤ 1 - h·k/m ≤ 1 does not amplify an earlier difference. So after n steps
        //   |Δv| ≤ n·ε·(10·h·A + 2·(V + h·A)) ≤ n·16ε·(V + h·A) = E,
        //   |Δx| ≤ n·(h·E + 2ε·(X + h·V)),
        // with X the largest position component; the checks below keep a factor of two
        // on the second term for the terms in ε² left out.
        let n = 1000;
        let state = swarm(n);
        let (m, k, g, h) = (2.5, 0.7, DVec2::new(1.5, -9.81), 0.01);
        let system = System::new(vec![m; n], &[gravity(g), drag(k)]);
        let mut baseline =
            HandWrittenEuler::new(&system, IntegratorKind::Euler, h, &state).expect("fits");
        let mut sim = Simulation::new(system, state.clone(), IntegratorKind::Euler, h);
        let largest = |v: &[DVec2]| v.iter().fold(0.0_f64, |a, v| a.max(v.abs().max_element()));
        let (mut x_max, mut v_max) = (largest(&state.pos), largest(&state.vel));
        let steps = 300;
        for _ in 0..steps {
            sim.step().expect("finite");
            baseline.step();
            x_max = x_max.max(largest(&sim.state().pos));
            v_max = v_max.max(largest(&sim.state().vel));
        }
        let a_max = g.abs().max_element() + k / m * v_max;
        let n_eps = steps as f64 * f64::EPSILON;
        let dv_bound = n_eps * 16.0 * (v_max + h * a_max);
        let dx_bound = steps as f64 * h * dv_bound + n_eps * 4.0 * (x_max + h * v_max);
        let far = |a: &[DVec2], b: &[DVec2]| {
            largest(&a.iter().zip(b).map(|(a, b)| *a - *b).collect::<Vec<_>>())
        };
        let dv = far(&baseline.velocities(), &sim.state().vel);
        let dx = far(&baseline.positions(), &sim.state().pos);
        assert!(dv <= dv_bound, "|Δv| = {dv:e} > {dv_bound:e}");
        assert!(dx <= dx_bound, "|Δx| = {dx:e} > {dx_bound:e}");
    }

    #[test]
    fn it_exists_only_for_explicit_euler_under_gravity_and_drag_on_equal_masses() {
        let n = 4;
        let state = swarm(n);
        let g = DVec2::new(0.0, -9.81);
        let fits = |mass: Vec<f64>, forces: &[ForceSpec], kind| {
            HandWrittenEuler::new(&System::new(mass, forces), kind, 0.01, &state).is_some()
        };
        let euler = IntegratorKind::Euler;
        let both = [gravity(g), drag(0.1)];
        assert!(fits(vec![2.0; n], &both, euler));
        assert!(fits(
            vec![2.0; n],
            &[gravity(g), drag(0.1), gravity(g)],
            euler
        ));
        assert!(fits(vec![2.0; n], &[], euler));
        assert!(!fits(vec![2.0; n], &both, IntegratorKind::SymplecticEuler));
        assert!(!fits(vec![2.0, 2.0, 2.0, 3.0], &both, euler));
        let some_bodies = ForceSpec::Drag {
            k: 0.1,
            bodies: Selection::Range { start: 0, end: 3 },
        };
        assert!(!fits(vec![2.0; n], &[gravity(g), some_bodies], euler));
        let quadratic = ForceSpec::QuadraticDrag {
            c: 0.1,
            bodies: Selection::All,
        };
        assert!(!fits(vec![2.0; n], &[gravity(g), quadratic], euler));
        let spring = ForceSpec::Spring {
            a: 0,
            b: Anchor::Body(1),
            stiffness: 1.0,
            rest_length: 0.0,
            damping: 0.0,
            a_at: None,
            b_at: None,
        };
        assert!(!fits(vec![2.0; n], &[gravity(g), spring], euler));
    }
}
