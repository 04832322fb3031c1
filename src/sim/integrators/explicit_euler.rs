//! Explicit (forward) Euler, exactly as the article writes it.

use glam::DVec2;

use super::{euler_advance, Slopes};
use crate::sim::chunks::{for_each_chunk_pair, sum_is_finite, wide_vectors};
use crate::sim::state::Coords;
use crate::sim::{State, System};

/// Advances one step of explicit Euler.
///
/// Euler's method for dy/dt = f(t, y) follows the slope at the start of the step:
/// y(t + h) = y(t) + h·f(t, y(t)). Applied to the coupled pair dr/dt = v and
/// dv/dt = F/m, with every force evaluated at the start of the step:
///
///   r(t + h) = r(t) + h·v(t)
///   v(t + h) = v(t) + h·F(t, r(t), v(t))/m
///
/// The position moves with the velocity at the start of the step, not the new one: that
/// is what makes it explicit (and what the symplectic variant changes). Its global error
/// is first order in h. On the drag equation dv/dt = -k·v/m it gives exactly
/// v_n = v0·(1 - h·k/m)^n, stable while h·k/m ≤ 2.
///
/// A spinning body's angle and angular velocity take the same step from the angular
/// acceleration α = τ/I at the start of the step:
///
///   θ(t + h) = θ(t) + h·ω(t)
///   ω(t + h) = ω(t) + h·τ(t, state)/I
pub fn step(system: &System, h: f64, state: &mut State, slopes: &mut Slopes) {
    let t = state.t;
    if system.spins() {
        system.derivatives(t, Coords::of(state), &mut slopes.acc, &mut slopes.alpha);
        system.record_finite_step(&state.pos, false);
        euler_advance(h, &mut state.pos, &mut state.vel, &slopes.acc);
        euler_advance(h, &mut state.angle, &mut state.omega, &slopes.alpha);
        return;
    }
    let (pos, vel) = (&mut state.pos[..], &mut state.vel[..]);
    if system.is_per_body() {
        // Without springs each body's acceleration depends on that body alone, so each
        // chunk computes its accelerations and is advanced at once, while its data is
        // still in cache; the arithmetic is the same, so the bits are too. Each chunk
        // also checks that what it wrote is finite while it is in cache, which spares
        // the simulation's check a pass over the whole state.
        let finite = for_each_chunk_pair(pos, vel, |start, pos, vel| {
            #[cfg(target_arch = "x86_64")]
            if wide_vectors() {
                #[target_feature(enable = "avx2")]
                unsafe fn wide(
                    s: &System,
                    t: f64,
                    h: f64,
                    i: usize,
                    r: &mut [DVec2],
                    v: &mut [DVec2],
                ) -> bool {
                    chunk(s, t, h, i, r, v)
                }
                // SAFETY: `wide_vectors` has checked that this processor has AVX2.
                return unsafe { wide(system, t, h, start, pos, vel) };
            }
            chunk(system, t, h, start, pos, vel)
        });
        system.record_finite_step(pos, finite);
        return;
    }
    system.record_finite_step(pos, false);
    system.accelerations(t, pos, vel, &mut slopes.acc);
    euler_advance(h, pos, vel, &slopes.acc);
}

/// Advances the chunk of bodies `start..start + pos.len()` by one step and returns
/// true when every position and velocity it wrote is finite (false may also mean that
/// their sum overflowed; the simulation's full check then decides).
#[inline(always)]
fn chunk(
    system: &System,
    t: f64,
    h: f64,
    start: usize,
    pos: &mut [DVec2],
    vel: &mut [DVec2],
) -> bool {
    // Gravity and a linear drag on bodies of one mass, the commonest swarm: the same
    // arithmetic as the general sum below, with its constants taken out of the loop.
    if let Some((g, k, inv)) = system.uniform_linear(start, pos.len()) {
        return match k {
            // a = (G - k·v)·(1/m), G = m·g.
            Some(k) => uniform_steps(pos, vel, |v| h * ((g - k * v) * inv), h),
            // a = G·(1/m), without drag, subtracting nothing (not even 0·v, which
            // could turn a zero's sign).
            None => uniform_steps(pos, vel, |_| h * (g * inv), h),
        };
    }
    system.for_each_acceleration(t, start, pos, vel, |r, v, a| {
        // r(t + h) = r(t) + h·v(t), with the velocity from the start of the step.
        *r += h * *v;
        // v(t + h) = v(t) + h·a(t), a = F(t, r(t), v(t))/m.
        *v += h * a;
    });
    sum_is_finite(pos, vel)
}

/// Steps every body of a chunk with r += h·v and v += dv(v), where `dv(v)` = h·a is
/// computed from the velocity at the start of the step, and returns true when every
/// position and velocity written is finite (false may also mean that their sum
/// overflowed). The check sums what each body wrote while it is in registers, in four
/// running sums, instead of reading the chunk again: a sum is finite only if every
/// term is.
#[inline(always)]
fn uniform_steps(
    pos: &mut [DVec2],
    vel: &mut [DVec2],
    dv: impl Fn(DVec2) -> DVec2,
    h: f64,
) -> bool {
    let mut sums = [DVec2::ZERO; 4];
    let mut r4 = pos.chunks_exact_mut(4);
    let mut v4 = vel.chunks_exact_mut(4);
    for (r, v) in (&mut r4).zip(&mut v4) {
        for j in 0..4 {
            let dv = dv(v[j]);
            // r(t + h) = r(t) + h·v(t), with the velocity from the start of the step.
            r[j] += h * v[j];
            // v(t + h) = v(t) + h·a(t).
            v[j] += dv;
            sums[j] += r[j] + v[j];
        }
    }
    for (r, v) in r4.into_remainder().iter_mut().zip(v4.into_remainder()) {
        let dv = dv(*v);
        *r += h * *v;
        *v += dv;
        sums[0] += *r + *v;
    }
    (sums[0] + sums[1] + sums[2] + sums[3]).is_finite()
}
