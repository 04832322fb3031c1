//! The explicit midpoint method (second-order Runge–Kutta, RK2).

use glam::DVec2;

use super::euler_substep;
use crate::sim::dof::Dof;
use crate::sim::state::Coords;
use crate::sim::{State, System};

/// Scratch buffers for the midpoint method: the state at the middle of the step and the
/// accelerations, for the linear pair and (for a system that spins) the angular pair.
#[derive(Clone, Debug)]
pub struct Midpoint {
    lin: Buffers<DVec2>,
    ang: Buffers<f64>,
}

/// The midpoint method's buffers for one kind of coordinate.
#[derive(Clone, Debug)]
struct Buffers<T> {
    acc: Vec<T>,
    mid_pos: Vec<T>,
    mid_vel: Vec<T>,
}

impl<T: Dof> Buffers<T> {
    fn new(n: usize) -> Self {
        Buffers {
            acc: vec![T::ZERO; n],
            mid_pos: vec![T::ZERO; n],
            mid_vel: vec![T::ZERO; n],
        }
    }

    /// r(t + h) = r + h·v_mid, v(t + h) = v + h·a(t + h/2, r_mid, v_mid).
    fn finish(&self, h: f64, pos: &mut [T], vel: &mut [T]) {
        for (((r, v), vm), a) in pos
            .iter_mut()
            .zip(vel.iter_mut())
            .zip(&self.mid_vel)
            .zip(&self.acc)
        {
            // r(t + h) = r + h·v_mid.
            *r += *vm * h;
            // v(t + h) = v + h·a(t + h/2, r_mid, v_mid).
            *v += *a * h;
        }
    }
}

impl Midpoint {
    /// Allocates the buffers for `n` bodies, once per run; angular ones when `spin`.
    pub fn new(n: usize, spin: bool) -> Self {
        Midpoint {
            lin: Buffers::new(n),
            ang: Buffers::new(if spin { n } else { 0 }),
        }
    }

    /// Advances one step and returns the number of force evaluations (2).
    ///
    /// For y' = f(t, y), the midpoint method takes a half Euler step to estimate the state
    /// at the middle of the step, and then a full step with the slope found there:
    ///
    ///   y_mid   = y + (h/2)·f(t, y)
    ///   y(t + h) = y + h·f(t + h/2, y_mid)
    ///
    /// With y = (r, v) and f = (v, a(t, r, v)):
    ///
    ///   r_mid = r + (h/2)·v,             v_mid = v + (h/2)·a(t, r, v)
    ///   r(t + h) = r + h·v_mid,          v(t + h) = v + h·a(t + h/2, r_mid, v_mid)
    ///
    /// and (θ, ω) with α = τ/I take the same two stages. The error of the half step is
    /// symmetric about the midpoint and cancels to first order, which makes the method
    /// second order.
    pub fn step(&mut self, system: &System, h: f64, state: &mut State) -> u32 {
        let (t, half, spin) = (state.t, 0.5 * h, system.spins());
        let (lin, ang) = (&mut self.lin, &mut self.ang);
        system.derivatives(t, Coords::of(state), &mut lin.acc, &mut ang.acc);
        // The state an Euler sub-step of h/2 reaches: r_mid, v_mid (and θ_mid, ω_mid).
        let start = (&state.pos[..], &state.vel[..], &lin.acc[..]);
        euler_substep(half, start, &mut lin.mid_pos, &mut lin.mid_vel);
        if spin {
            let start = (&state.angle[..], &state.omega[..], &ang.acc[..]);
            euler_substep(half, start, &mut ang.mid_pos, &mut ang.mid_vel);
        }
        let mid = Coords {
            pos: &lin.mid_pos,
            vel: &lin.mid_vel,
            angle: &ang.mid_pos,
            omega: &ang.mid_vel,
        };
        system.derivatives(t + half, mid, &mut lin.acc, &mut ang.acc);
        lin.finish(h, &mut state.pos, &mut state.vel);
        if spin {
            ang.finish(h, &mut state.angle, &mut state.omega);
        }
        2
    }
}
