//! Explicit (forward) Euler, exactly as the article writes it.

use glam::DVec2;

use crate::sim::System;

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
pub fn step(
    system: &System,
    t: f64,
    h: f64,
    pos: &mut [DVec2],
    vel: &mut [DVec2],
    acc: &mut [DVec2],
) {
    system.accelerations(t, pos, vel, acc);
    for ((r, v), a) in pos.iter_mut().zip(vel.iter_mut()).zip(acc.iter()) {
        // r(t + h) = r(t) + h·v(t), with the velocity from the start of the step.
        *r += h * *v;
        // v(t + h) = v(t) + h·a(t), a = F(t, r(t), v(t))/m.
        *v += h * *a;
    }
}
