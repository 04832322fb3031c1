//! Symplectic (semi-implicit) Euler: the velocity first, then the position with the new
//! velocity.

use super::Slopes;
use crate::sim::dof::Dof;
use crate::sim::state::Coords;
use crate::sim::{State, System};

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
/// spring spirals outwards; this one's stays on a slightly tilted ellipse). A spinning
/// body's angle and angular velocity take the same step:
/// ω(t + h) = ω(t) + h·τ/I, θ(t + h) = θ(t) + h·ω(t + h).
pub fn step(system: &System, h: f64, state: &mut State, slopes: &mut Slopes) -> u32 {
    system.derivatives(
        state.t,
        Coords::of(state),
        &mut slopes.acc,
        &mut slopes.alpha,
    );
    advance(h, &mut state.pos, &mut state.vel, &slopes.acc);
    if system.spins() {
        advance(h, &mut state.angle, &mut state.omega, &slopes.alpha);
    }
    1
}

/// The velocity, then the position with the new velocity, for (r, v) and (θ, ω) alike.
#[inline]
fn advance<T: Dof>(h: f64, pos: &mut [T], vel: &mut [T], acc: &[T]) {
    for ((r, v), a) in pos.iter_mut().zip(vel.iter_mut()).zip(acc.iter()) {
        // v(t + h) = v(t) + h·a(t), a = F(t, r(t), v(t))/m.
        *v += *a * h;
        // r(t + h) = r(t) + h·v(t + h), with the velocity just computed.
        *r += *v * h;
    }
}
