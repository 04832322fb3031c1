//! Reference problems: systems whose motion has a closed form, to measure integrators
//! against.
//!
//! Each problem is a [`System`] built through the public [`System::new`] and
//! [`System::rigid`] APIs, an initial [`State`] at t = 0, a suggested final time, and the
//! exact state at any time. The tests and the studies use them; nothing else in the
//! crate depends on them.
//!
//! Three of them turn: a spin-up under a constant torque, angular drag (with and
//! without a driving torque), and a box hanging from a fixed point by a spring at its
//! corner, which swings and turns at once. That last one has no closed form; its
//! reference is classical Runge–Kutta at a step so small that its truncation error is
//! below round-off (see [`ReferenceKind::HangingBox`]).

mod turning;

pub use turning::REFERENCE_STEP;
use turning::{angular_drag, hanging_box, reference_run, spin_up};

use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;
use std::sync::OnceLock;

use glam::DVec2;

use crate::sim::{Anchor, ForceSpec, Selection, State, System};

/// The reference problems, by the name the command line uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ReferenceKind {
    /// The article's constant acceleration of 5 (Equations 3 to 5), once along a line and
    /// once in the plane.
    ConstantAcceleration,
    /// Linear drag alone (Equation 12).
    Drag,
    /// Linear drag with uniform gravity: a fall towards terminal velocity.
    DragGravity,
    /// The article's force growing in time, F = 2t.
    TimeForce,
    /// An undamped harmonic oscillator: a spring of rest length 0 to a fixed point.
    Spring,
    /// An underdamped harmonic oscillator moving along a line through its anchor.
    DampedSpring,
    /// A circular orbit under an inverse-square central force.
    Orbit,
    /// A constant torque spinning up one body from rest and reversing another's spin:
    /// the rotational form of the constant acceleration.
    SpinUp,
    /// Angular drag, τ = -k·ω: one body's spin decays, another is driven by a constant
    /// torque towards its terminal spin rate τ/k.
    AngularDrag,
    /// A box hanging from a fixed point by a spring at its corner, under gravity: it
    /// swings and turns, the translation and rotation coupled through the spring.
    HangingBox,
}

impl ReferenceKind {
    /// Every reference problem, in the order tables list them.
    pub const ALL: &'static [ReferenceKind] = &[
        ReferenceKind::ConstantAcceleration,
        ReferenceKind::Drag,
        ReferenceKind::DragGravity,
        ReferenceKind::TimeForce,
        ReferenceKind::Spring,
        ReferenceKind::DampedSpring,
        ReferenceKind::Orbit,
        ReferenceKind::SpinUp,
        ReferenceKind::AngularDrag,
        ReferenceKind::HangingBox,
    ];

    /// Returns the problem's name.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceKind::ConstantAcceleration => "constant-acceleration",
            ReferenceKind::Drag => "drag",
            ReferenceKind::DragGravity => "drag-gravity",
            ReferenceKind::TimeForce => "time-force",
            ReferenceKind::Spring => "spring",
            ReferenceKind::DampedSpring => "damped-spring",
            ReferenceKind::Orbit => "orbit",
            ReferenceKind::SpinUp => "spin-up",
            ReferenceKind::AngularDrag => "angular-drag",
            ReferenceKind::HangingBox => "hanging-box",
        }
    }

    /// Returns the names of every problem, for error messages.
    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|k| k.name()).collect()
    }

    /// Returns true for the problems whose bodies turn, whose errors measure angles too.
    pub fn turns(self) -> bool {
        matches!(
            self,
            ReferenceKind::SpinUp | ReferenceKind::AngularDrag | ReferenceKind::HangingBox
        )
    }

    /// Returns what the studies' error measures on this problem, for their tables and
    /// axes: the position error, and for a problem that turns the angle error too.
    pub fn error_measure(self) -> &'static str {
        if self.turns() {
            "max over bodies of |r - r_exact| and |θ - θ_exact|"
        } else {
            "max over bodies of |r - r_exact|"
        }
    }

    /// Returns the label of the studies' error axis on this problem, at time `t`.
    pub fn error_axis(self, t: impl fmt::Display) -> String {
        if self.turns() {
            format!("error max(|r − r_exact|, |θ − θ_exact|) at t = {t} (m, rad)")
        } else {
            format!("position error |r − r_exact| at t = {t} (m)")
        }
    }

    /// Builds the problem.
    pub fn problem(self) -> ReferenceProblem {
        match self {
            ReferenceKind::ConstantAcceleration => constant_acceleration(),
            ReferenceKind::Drag => drag(),
            ReferenceKind::DragGravity => drag_gravity(),
            ReferenceKind::TimeForce => time_force(),
            ReferenceKind::Spring => spring(),
            ReferenceKind::DampedSpring => damped_spring(),
            ReferenceKind::Orbit => orbit(),
            ReferenceKind::SpinUp => spin_up(),
            ReferenceKind::AngularDrag => angular_drag(),
            ReferenceKind::HangingBox => hanging_box(),
        }
    }
}

impl fmt::Display for ReferenceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ReferenceKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                format!(
                    "unknown reference problem `{s}`; expected one of: {}",
                    Self::names().join(", ")
                )
            })
    }
}

/// A system, its initial state, and the exact state at any later time.
#[derive(Clone, Debug)]
pub struct ReferenceProblem {
    kind: ReferenceKind,
    system: System,
    initial: State,
    t_end: f64,
    solution: Solution,
}

impl ReferenceProblem {
    /// Returns which problem this is.
    pub fn kind(&self) -> ReferenceKind {
        self.kind
    }

    /// Returns the problem's name.
    pub fn name(&self) -> &'static str {
        self.kind.name()
    }

    /// Returns the masses and forces.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Returns the state at t = 0.
    pub fn initial(&self) -> &State {
        &self.initial
    }

    /// Returns the final time the studies integrate to.
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// Returns the same problem with another final time.
    pub fn with_t_end(mut self, t_end: f64) -> Self {
        self.t_end = t_end;
        self
    }

    /// Returns the exact state at time `t`.
    pub fn exact(&self, t: f64) -> State {
        let s0 = &self.initial;
        if let Solution::Numerical { at_end } = &self.solution {
            if t == self.t_end {
                return at_end
                    .get_or_init(|| reference_run(&self.system, s0, t))
                    .clone();
            }
            return reference_run(&self.system, s0, t);
        }
        let mut out = s0.clone();
        out.t = t;
        for i in 0..s0.len() {
            let (r, v) = self.solution.body(i, t - s0.t, s0.pos[i], s0.vel[i]);
            let (theta, omega) = self.solution.spin(i, t - s0.t, s0.angle[i], s0.omega[i]);
            (out.pos[i], out.vel[i]) = (r, v);
            (out.angle[i], out.omega[i]) = (theta, omega);
        }
        out
    }

    /// Returns the error of `state`'s positions and angles against the exact ones at
    /// `state.t`: the largest, over the bodies, of the Euclidean distance |r - r_exact|
    /// and of |θ - θ_exact| (in radians). Positions and orientations are what a frame
    /// shows, so the studies measure them; a body that does not turn has no angle error.
    pub fn position_error(&self, state: &State) -> f64 {
        let exact = self.exact(state.t);
        max_distance(&state.pos, &exact.pos).max(max_difference(&state.angle, &exact.angle))
    }

    /// Returns the angular frequency ω of an undamped oscillator (the `spring`
    /// problem), whose stepped energy has closed forms; `None` for any other problem.
    pub fn angular_frequency(&self) -> Option<f64> {
        match self.solution {
            Solution::Oscillator {
                omega, gamma: 0.0, ..
            } => Some(omega),
            _ => None,
        }
    }

    /// Returns the largest, over the bodies, of |v - v_exact| and |ω - ω_exact| at
    /// `state.t`.
    pub fn velocity_error(&self, state: &State) -> f64 {
        let exact = self.exact(state.t);
        max_distance(&state.vel, &exact.vel).max(max_difference(&state.omega, &exact.omega))
    }
}

/// Returns max_i |a_i - b_i| of two lists of angles or angular velocities; a
/// non-finite difference makes the result infinite.
fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |worst: f64, (x, y)| {
        let d = (x - y).abs();
        if d.is_finite() {
            worst.max(d)
        } else {
            f64::INFINITY
        }
    })
}

/// Returns max_i |a_i - b_i|; a non-finite distance makes the result infinite.
fn max_distance(a: &[DVec2], b: &[DVec2]) -> f64 {
    a.iter().zip(b).fold(0.0, |worst: f64, (x, y)| {
        let d = (*x - *y).length();
        if d.is_finite() {
            worst.max(d)
        } else {
            f64::INFINITY
        }
    })
}

/// The parameters of each closed form.
#[derive(Clone, Debug)]
enum Solution {
    /// r = r0 + v0·t + a·t²/2, v = v0 + a·t, with one acceleration per body.
    ConstantAcceleration { acc: Vec<DVec2> },
    /// Linear drag with gravity, rate λ = k/m and terminal velocity v_T = g/λ = m·g/k:
    /// v = v_T + (v0 - v_T)·e^(-λt), r = r0 + v_T·t + (v0 - v_T)·(1 - e^(-λt))/λ.
    /// With g = 0 this is Equation 12's v = v0·e^(-kt/m), r = r0 + v0·(m/k)(1 - e^(-kt/m)).
    Drag { rate: f64, g: DVec2 },
    /// F = f1·t on a body of mass m: v = v0 + (f1/m)·t²/2, r = r0 + v0·t + (f1/m)·t³/6.
    /// The article's F = 2t gives v = v0 + t²/m and r = r0 + v0·t + t³/(3m).
    TimeForce { f1_over_m: DVec2 },
    /// A linear oscillator about the centre c, x = r - c, with x'' + 2γx' + ω²x = 0 and
    /// ω_d = √(ω² - γ²) (γ = 0 is the undamped spring):
    /// x = e^(-γt)·(x0·cos ω_d t + (v0 + γ·x0)/ω_d · sin ω_d t),
    /// v = e^(-γt)·(v0·cos ω_d t - (ω²·x0 + γ·v0)/ω_d · sin ω_d t).
    Oscillator {
        centre: DVec2,
        omega: f64,
        gamma: f64,
    },
    /// A circular orbit about c with angular rate Ω = √(μ/R³): the initial offset and
    /// velocity turn by the angle Ω·t, r = c + Rot(Ωt)·(r0 - c), v = Rot(Ωt)·v0.
    Circle { centre: DVec2, rate: f64 },
    /// Bodies at rest whose spins obey ω' = α - λ·ω, one pair (α, λ) per body: with
    /// λ = 0 a constant angular acceleration, θ = θ0 + ω0·t + α·t²/2, ω = ω0 + α·t;
    /// with λ > 0, terminal spin ω_T = α/λ and ω = ω_T + (ω0 - ω_T)·e^(-λt),
    /// θ = θ0 + ω_T·t + (ω0 - ω_T)·(1 - e^(-λt))/λ.
    Spin { rates: Vec<(f64, f64)> },
    /// No closed form: the reference is a fine rk4 run ([`reference_run`]), the one at
    /// the final time computed once.
    Numerical { at_end: OnceLock<State> },
}

impl Solution {
    /// Returns the exact position and velocity of body `i` a time `t` after (r0, v0).
    fn body(&self, i: usize, t: f64, r0: DVec2, v0: DVec2) -> (DVec2, DVec2) {
        match self {
            Solution::ConstantAcceleration { acc } => {
                let a = acc[i];
                (r0 + v0 * t + 0.5 * a * t * t, v0 + a * t)
            }
            Solution::Drag { rate, g } => {
                let terminal = *g / *rate;
                let decay = (-rate * t).exp();
                // 1 - e^(-λt), computed without cancellation for small λt.
                let gone = -(-rate * t).exp_m1();
                let v = terminal + (v0 - terminal) * decay;
                let r = r0 + terminal * t + (v0 - terminal) * (gone / rate);
                (r, v)
            }
            Solution::TimeForce { f1_over_m } => {
                let r = r0 + v0 * t + *f1_over_m * (t * t * t / 6.0);
                let v = v0 + *f1_over_m * (t * t / 2.0);
                (r, v)
            }
            Solution::Oscillator {
                centre,
                omega,
                gamma,
            } => {
                let x0 = r0 - *centre;
                let wd = (omega * omega - gamma * gamma).sqrt();
                let (s, c) = (wd * t).sin_cos();
                let e = (-gamma * t).exp();
                let x = e * (x0 * c + (v0 + *gamma * x0) * (s / wd));
                let v = e * (v0 * c - (omega * omega * x0 + *gamma * v0) * (s / wd));
                (*centre + x, v)
            }
            Solution::Circle { centre, rate } => {
                let turn = DVec2::from_angle(rate * t);
                (*centre + turn.rotate(r0 - *centre), turn.rotate(v0))
            }
            // No force moves these centres of mass.
            Solution::Spin { .. } | Solution::Numerical { .. } => (r0 + v0 * t, v0),
        }
    }

    /// Returns the exact angle and angular velocity of body `i` a time `t` after
    /// (θ0, ω0): unchanged but for the problems that turn.
    fn spin(&self, i: usize, t: f64, theta0: f64, omega0: f64) -> (f64, f64) {
        let Solution::Spin { rates } = self else {
            return (theta0 + omega0 * t, omega0);
        };
        let (alpha, lambda) = rates[i];
        if lambda == 0.0 {
            // θ = θ0 + ω0·t + α·t²/2, ω = ω0 + α·t.
            return (
                theta0 + omega0 * t + 0.5 * alpha * t * t,
                omega0 + alpha * t,
            );
        }
        let terminal = alpha / lambda;
        // 1 - e^(-λt), computed without cancellation for small λt.
        let gone = -(-lambda * t).exp_m1();
        let omega = terminal + (omega0 - terminal) * (1.0 - gone);
        let theta = theta0 + terminal * t + (omega0 - terminal) * (gone / lambda);
        (theta, omega)
    }
}

/// Builds one body-selection list.
fn only(i: u32) -> Selection {
    Selection::Bodies(vec![i])
}

/// The article's a = 5: body 0 moves along the x axis (Equations 3 to 5, r = 5/2·t² +
/// v0·t + r0), body 1 in the plane with |a| = 5 at an angle to its initial velocity.
fn constant_acceleration() -> ReferenceProblem {
    let acc = vec![DVec2::new(5.0, 0.0), DVec2::new(3.0, -4.0)];
    // Uniform gravity gives every selected body the same acceleration g whatever its mass.
    let forces = [
        ForceSpec::Gravity {
            g: acc[0],
            bodies: only(0),
        },
        ForceSpec::Gravity {
            g: acc[1],
            bodies: only(1),
        },
    ];
    ReferenceProblem {
        kind: ReferenceKind::ConstantAcceleration,
        system: System::new(vec![1.0, 2.0], &forces),
        initial: State::new(
            0.0,
            vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 2.0)],
            vec![DVec2::new(2.0, 0.0), DVec2::new(-1.0, 3.0)],
        ),
        t_end: 2.0,
        solution: Solution::ConstantAcceleration { acc },
    }
}

/// Equation 12 with F = -k·v, k = 1 (the article's F = -v) and m = 2: two time
/// constants m/k over the run.
fn drag() -> ReferenceProblem {
    let (m, k) = (2.0, 1.0);
    ReferenceProblem {
        kind: ReferenceKind::Drag,
        system: System::new(
            vec![m],
            &[ForceSpec::Drag {
                k,
                bodies: Selection::All,
            }],
        ),
        initial: State::new(0.0, vec![DVec2::new(0.0, 1.0)], vec![DVec2::new(3.0, -1.0)]),
        t_end: 4.0,
        solution: Solution::Drag {
            rate: k / m,
            g: DVec2::ZERO,
        },
    }
}

/// A ball thrown up and sideways under gravity g = (0, -9.81) and linear drag k = 0.5 on
/// m = 1.5: its velocity tends to the terminal velocity m·g/k = (0, -29.43).
fn drag_gravity() -> ReferenceProblem {
    let (m, k, g) = (1.5, 0.5, DVec2::new(0.0, -9.81));
    ReferenceProblem {
        kind: ReferenceKind::DragGravity,
        system: System::new(
            vec![m],
            &[
                ForceSpec::Gravity {
                    g,
                    bodies: Selection::All,
                },
                ForceSpec::Drag {
                    k,
                    bodies: Selection::All,
                },
            ],
        ),
        initial: State::new(0.0, vec![DVec2::ZERO], vec![DVec2::new(10.0, 10.0)]),
        t_end: 3.0,
        solution: Solution::Drag { rate: k / m, g },
    }
}

/// The article's F = 2t along x, on m = 2, with some initial velocity across it.
fn time_force() -> ReferenceProblem {
    let m = 2.0;
    let f1 = DVec2::new(2.0, 0.0);
    ReferenceProblem {
        kind: ReferenceKind::TimeForce,
        system: System::new(
            vec![m],
            &[ForceSpec::TimeVarying {
                f0: DVec2::ZERO,
                f1,
                bodies: Selection::All,
                at: None,
            }],
        ),
        initial: State::new(0.0, vec![DVec2::new(0.0, 0.0)], vec![DVec2::new(1.0, 0.5)]),
        t_end: 2.0,
        solution: Solution::TimeForce { f1_over_m: f1 / m },
    }
}

/// A spring of stiffness 4π² and rest length 0 from a fixed point to a unit mass: period
/// 1, on an ellipse of semi-axes 1 and 1/2. The final time 1.25 is deliberately not a
/// whole number of periods: at a whole period, the phase error alone is measured, and
/// symplectic Euler (whose orbit is closed) looks second order there.
fn spring() -> ReferenceProblem {
    let m = 1.0;
    let omega = 2.0 * PI;
    let centre = DVec2::new(0.5, -0.25);
    ReferenceProblem {
        kind: ReferenceKind::Spring,
        system: System::new(
            vec![m],
            &[ForceSpec::Spring {
                a: 0,
                b: Anchor::Point(centre),
                stiffness: m * omega * omega,
                rest_length: 0.0,
                damping: 0.0,
                a_at: None,
                b_at: None,
            }],
        ),
        initial: State::new(
            0.0,
            vec![centre + DVec2::new(1.0, 0.0)],
            vec![DVec2::new(0.0, 0.5 * omega)],
        ),
        t_end: 1.25,
        solution: Solution::Oscillator {
            centre,
            omega,
            gamma: 0.0,
        },
    }
}

/// The spring above with damping 1 (γ = damping/(2m) = 1/2, well under ω = 2π). The
/// spring damps only along its axis, so the body moves along a line through the anchor,
/// where that is the isotropic damping F = -damping·v of the closed form; the line is
/// horizontal, so the motion stays on it exactly.
fn damped_spring() -> ReferenceProblem {
    let m = 1.0;
    let omega = 2.0 * PI;
    let damping = 1.0;
    let centre = DVec2::new(1.0, -0.5);
    ReferenceProblem {
        kind: ReferenceKind::DampedSpring,
        system: System::new(
            vec![m],
            &[ForceSpec::Spring {
                a: 0,
                b: Anchor::Point(centre),
                stiffness: m * omega * omega,
                rest_length: 0.0,
                damping,
                a_at: None,
                b_at: None,
            }],
        ),
        initial: State::new(
            0.0,
            vec![centre + DVec2::new(1.0, 0.0)],
            vec![DVec2::new(-2.0, 0.0)],
        ),
        t_end: 2.25,
        solution: Solution::Oscillator {
            centre,
            omega,
            gamma: damping / (2.0 * m),
        },
    }
}

/// A body of mass 3 on a circle of radius R = 1 about c under μ = 4π²: speed √(μ/R) = 2π
/// and period 2π·√(R³/μ) = 1, run for one and a quarter periods (not a whole number, for
/// the reason given at [`spring`]).
fn orbit() -> ReferenceProblem {
    let mu = 4.0 * PI * PI;
    let radius = 1.0;
    let centre = DVec2::new(0.5, 0.25);
    ReferenceProblem {
        kind: ReferenceKind::Orbit,
        system: System::new(
            vec![3.0],
            &[ForceSpec::Central {
                centre,
                strength: mu,
                bodies: Selection::All,
            }],
        ),
        initial: State::new(
            0.0,
            vec![centre + DVec2::new(radius, 0.0)],
            vec![DVec2::new(0.0, (mu / radius).sqrt())],
        ),
        t_end: 1.25,
        solution: Solution::Circle {
            centre,
            rate: (mu / (radius * radius * radius)).sqrt(),
        },
    }
}
