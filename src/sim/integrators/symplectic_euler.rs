//! Symplectic (semi-implicit) Euler: the velocity first, then the position with the new
//! velocity.

use glam::DVec2;

use crate::sim::System;

/// Advances one step of symplectic Euler and returns the number of force evaluations (1).
///
/// The only change from explicit Euler is the order of the two updates: the velocity is
/// advanced first, and the position then moves with the velocity at the end of the step:
///
///   v(t + h) = v(t) + h·F(t, r(t), v(t))/m
///   r(t + h) = r(t) + h·v(t + h)
///
/// It is still first order, but for forces that derive from a potential it is a
/// symplectic map: it exactly conserves a modified energy H̃ = H + O(h), so the energy
/// error stays bounded over any number of steps instead of growing (explicit Euler's
/// spring spirals outwards; this one's stays on a slightly tilted ellipse).
pub fn step(
    system: &System,
    t: f64,
    h: f64,
    pos: &mut [DVec2],
    vel: &mut [DVec2],
    acc: &mut [DVec2],
) -> u32 {
    system.accelerations(t, pos, vel, acc);
    for ((r, v), a) in pos.iter_mut().zip(vel.iter_mut()).zip(acc.iter()) {
        // v(t + h) = v(t) + h·a(t), a = F(t, r(t), v(t))/m.
        *v += h * *a;
        // r(t + h) = r(t) + h·v(t + h), with the velocity just computed.
        *r += h * *v;
    }
    1
}
