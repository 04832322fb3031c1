//! The resting-contact solver: contacts that touch without colliding (a box on a floor,
//! a tower of boxes, a pile of discs) are solved together at the end of each step, by
//! sequential impulses with accumulated, clamped impulses, warm started from the last
//! step, with Coulomb friction; then a few passes push apart what still overlaps by
//! more than the slop. This is Box2D's (v2.4) contact solver, stage by stage:
//!
//! 1. *prepare*: for each contact point, the arms r_A and r_B from the centres of mass
//!    (kept as the cross products r⊥·n and r⊥·t that every impulse uses), the normal
//!    and tangent masses 1/K_n and 1/K_t, and the velocity the point may
//!    close at: 0 when touching, gap/h when apart by `gap` (a speculative contact may
//!    close the gap in one step, but no more);
//! 2. *warm start*: each point starts from the impulses it needed last step (matched by
//!    the features that touch), applied at once;
//! 3. *solve*, `iterations` times: for each contact, friction at each point,
//!    λ_t = -v_t/K_t with the accumulated impulse clamped to ±μ·P_n; then the normal
//!    impulses, λ_n = -(v_n - bias)/K_n with the accumulated P_n ≥ 0 (two points
//!    together, as a 2 × 2 complementarity problem, like Box2D's block solver);
//! 4. *store impulses* for the next step's warm start;
//! 5. *relax positions*: a few passes in which each point deeper than the slop is
//!    pushed apart by β = 0.2 of its excess, along the normal, shared by inverse mass
//!    (non-linear Gauss–Seidel on positions). The bodies are moved, not turned: see
//!    [`relaxation`]. Positions change, velocities do not, so no energy is added.
//!
//! There is no restitution here: a contact that approaches faster than the resting
//! speed is a collision, answered before the solver by the exact impulse of
//! `response.rs`.

use glam::DVec2;

use super::response::Inverse;
use crate::sim::rigid::perp_dot;

/// The fraction of a point's overlap beyond the slop that one relaxation pass removes
/// (Box2D's Baumgarte factor).
const BAUMGARTE: f64 = 0.2;

/// Relaxation passes over the positions each step.
const POSITION_PASSES: usize = 3;

/// The sweeps stop early once a whole sweep changes no accumulated impulse by more than
/// this fraction of the largest normal impulse. A stack's unsolved remainder is what
/// it creeps by, step after step; warm started, a stack at rest converges in a few
/// sweeps.
const CONVERGED: f64 = 1e-9;

pub use super::warm::WarmStart;

/// One contact point being solved.
#[derive(Clone, Copy, Debug, Default)]
pub struct Point {
    /// The arms r_A, r_B from the centres of mass to the point, as the cross products
    /// the impulses use: r⊥·n (`rna`, `rnb`) and r⊥·t (`rta`, `rtb`), where
    /// r⊥·d = r × d is how far an impulse along d turns the body per unit of it.
    pub rna: f64,
    pub rnb: f64,
    pub rta: f64,
    pub rtb: f64,
    /// 1/K along the normal and along the tangent.
    pub normal_mass: f64,
    pub tangent_mass: f64,
    /// The normal velocity the point may not go below: 0, or -gap/h when apart.
    pub bias: f64,
    /// The accumulated impulses.
    pub pn: f64,
    pub pt: f64,
    /// The point's features, for the warm start.
    pub id: u64,
}

/// One contact between two bodies: one or two points along one normal.
#[derive(Clone, Copy, Debug)]
pub struct Manifold {
    /// The colliders' indices (i < j) and their bodies'.
    pub i: u32,
    pub j: u32,
    pub bi: usize,
    pub bj: usize,
    /// The unit normal, from body b (j) to body a (i).
    pub normal: DVec2,
    /// The pair's friction coefficient √(μ_a·μ_b).
    pub friction: f64,
    pub points: [Point; 2],
    pub count: usize,
}

/// The velocities the solver works on, borrowed from the end state.
pub struct Velocities<'a> {
    pub vel: &'a mut [DVec2],
    pub omega: &'a mut [f64],
    /// Whether the angular velocities are advanced at all (a system that spins).
    pub spins: bool,
}

impl Velocities<'_> {
    /// Returns the velocities of a manifold's two bodies, to be solved in registers.
    #[inline]
    fn load(&self, m: &Manifold) -> Local {
        let w = |b: usize| if self.spins { self.omega[b] } else { 0.0 };
        Local {
            va: self.vel[m.bi],
            wa: w(m.bi),
            vb: self.vel[m.bj],
            wb: w(m.bj),
        }
    }

    /// Writes a manifold's two bodies' velocities back.
    #[inline]
    fn store(&mut self, m: &Manifold, l: Local) {
        self.vel[m.bi] = l.va;
        self.vel[m.bj] = l.vb;
        if self.spins {
            self.omega[m.bi] = l.wa;
            self.omega[m.bj] = l.wb;
        }
    }
}

/// The velocities of the two bodies of the manifold being solved, held in registers
/// from its first impulse to its last rather than read back from memory after each:
/// a body's velocity depends on every impulse before it, so each round trip through
/// memory would lengthen the chain the sweep waits on. (The two bodies of a contact
/// are never the same body.) With `SPINS` false the angular velocities stay 0.
#[derive(Clone, Copy, Debug)]
struct Local {
    va: DVec2,
    wa: f64,
    vb: DVec2,
    wb: f64,
}

impl Local {
    /// Applies the impulse λ·d at arms whose cross products with d are (rda, rdb): +λ·d
    /// to body a, -λ·d to body b.
    #[inline(always)]
    fn apply<const SPINS: bool>(
        &mut self,
        inv: (Inverse, Inverse),
        d: DVec2,
        rda: f64,
        rdb: f64,
        lambda: f64,
    ) {
        let (ia, ib) = inv;
        // v_A += λ·d/M_A, ω_A += λ·(r_A⊥·d)/I_A; the opposite on B.
        let p = lambda * d;
        self.va += ia.mass * p;
        self.vb -= ib.mass * p;
        if SPINS {
            self.wa += ia.inertia * (lambda * rda);
            self.wb -= ib.inertia * (lambda * rdb);
        }
    }

    /// Returns the relative velocity of the touching points along d,
    /// (v_AP - v_BP)·d = (v_A - v_B)·d + ω_A·(r_A⊥·d) - ω_B·(r_B⊥·d), from the arms'
    /// cross products with d (rda, rdb).
    #[inline(always)]
    fn relative<const SPINS: bool>(&self, d: DVec2, rda: f64, rdb: f64) -> f64 {
        let linear = (self.va - self.vb).dot(d);
        if SPINS {
            linear + (self.wa * rda - self.wb * rdb)
        } else {
            linear
        }
    }
}

/// Returns 1/K for an impulse along the unit vector d at arms (ra, rb):
/// K = 1/M_A + 1/M_B + (r_A⊥·d)²/I_A + (r_B⊥·d)²/I_B.
pub fn effective_mass(inv: (Inverse, Inverse), ra: DVec2, rb: DVec2, d: DVec2) -> f64 {
    effective_mass_of(inv, perp_dot(ra, d), perp_dot(rb, d))
}

/// [`effective_mass`] from the arms' cross products with d, rad = r_A⊥·d and
/// rbd = r_B⊥·d.
pub fn effective_mass_of(inv: (Inverse, Inverse), rad: f64, rbd: f64) -> f64 {
    let (ia, ib) = inv;
    let k = ia.mass + ib.mass + rad * rad * ia.inertia + rbd * rbd * ib.inertia;
    if k > 0.0 {
        1.0 / k
    } else {
        0.0
    }
}

/// Runs stages 2 to 4 on the manifolds: warm start, `iterations` sweeps of friction and
/// normal impulses, and the impulses stored for the next step in `warm` (which then
/// holds only this step's points).
pub fn solve(
    manifolds: &mut [Manifold],
    inv: &[Inverse],
    v: &mut Velocities<'_>,
    iterations: usize,
    warm: &mut WarmStart,
) {
    // 2. Warm start.
    let mut kept = warm.reader();
    for m in manifolds.iter_mut() {
        let pair = (inv[m.i as usize], inv[m.j as usize]);
        let t = m.normal.perp();
        let mut l = v.load(m);
        for k in 0..m.count {
            if let Some((pn, pt)) = kept.get(&(m.i, m.j, m.points[k].id)) {
                m.points[k].pn = pn;
                m.points[k].pt = pt;
                let p = m.points[k];
                if v.spins {
                    l.apply::<true>(pair, m.normal, p.rna, p.rnb, pn);
                    l.apply::<true>(pair, t, p.rta, p.rtb, pt);
                } else {
                    l.apply::<false>(pair, m.normal, p.rna, p.rnb, pn);
                    l.apply::<false>(pair, t, p.rta, p.rtb, pt);
                }
            }
        }
        v.store(m, l);
    }
    // 3. Sweeps.
    for _ in 0..iterations {
        let (change, scale) = if v.spins {
            sweep::<true>(manifolds, inv, v)
        } else {
            sweep::<false>(manifolds, inv, v)
        };
        // Converged: no impulse changed by more than CONVERGED of the largest.
        if change <= CONVERGED * scale {
            break;
        }
    }
    // 4. Store.
    warm.clear();
    for m in manifolds.iter() {
        for p in &m.points[..m.count] {
            warm.insert((m.i, m.j, p.id), (p.pn, p.pt));
        }
    }
}

/// One sweep over every manifold: friction, then the normal impulses. Returns the
/// largest change of an accumulated impulse and the largest normal impulse.
fn sweep<const SPINS: bool>(
    manifolds: &mut [Manifold],
    inv: &[Inverse],
    v: &mut Velocities<'_>,
) -> (f64, f64) {
    let mut change: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for m in manifolds.iter_mut() {
        debug_assert_ne!(m.bi, m.bj, "a contact is between two bodies");
        let pair = (inv[m.i as usize], inv[m.j as usize]);
        let mut l = v.load(m);
        change = change.max(solve_friction::<SPINS>(m, pair, &mut l));
        change = change.max(solve_normal::<SPINS>(m, pair, &mut l));
        v.store(m, l);
        for p in &m.points[..m.count] {
            scale = scale.max(p.pn);
        }
    }
    (change, scale)
}

/// Friction at each point: λ_t = -v_t/K_t, the accumulated P_t clamped to ±μ·P_n.
/// Returns the largest change of an accumulated impulse.
fn solve_friction<const SPINS: bool>(
    m: &mut Manifold,
    inv: (Inverse, Inverse),
    v: &mut Local,
) -> f64 {
    let mut change: f64 = 0.0;
    if m.friction == 0.0 {
        return change;
    }
    let t = m.normal.perp();
    for k in 0..m.count {
        let p = m.points[k];
        let vt = v.relative::<SPINS>(t, p.rta, p.rtb);
        let lambda = -p.tangent_mass * vt;
        // (max and min rather than clamp: a state so large that its impulses
        // overflow must not panic, only blow up, which the step's check reports.)
        let limit = (m.friction * p.pn).max(0.0);
        let total = (p.pt + lambda).max(-limit).min(limit);
        let applied = total - p.pt;
        m.points[k].pt = total;
        change = change.max(applied.abs());
        v.apply::<SPINS>(inv, t, p.rta, p.rtb, applied);
    }
    change
}

/// The normal impulses: one point as λ_n = -(v_n - bias)/K_n with P_n ≥ 0; two points
/// together, by trying which of them push (Box2D's block solver). Returns the largest
/// change of an accumulated impulse.
fn solve_normal<const SPINS: bool>(
    m: &mut Manifold,
    inv: (Inverse, Inverse),
    v: &mut Local,
) -> f64 {
    let n = m.normal;
    if m.count == 2 {
        if let Some(change) = solve_block::<SPINS>(m, inv, v) {
            return change;
        }
    }
    let mut change: f64 = 0.0;
    for k in 0..m.count {
        let p = m.points[k];
        let vn = v.relative::<SPINS>(n, p.rna, p.rnb);
        let lambda = -p.normal_mass * (vn - p.bias);
        let total = (p.pn + lambda).max(0.0);
        let applied = total - p.pn;
        m.points[k].pn = total;
        change = change.max(applied.abs());
        v.apply::<SPINS>(inv, n, p.rna, p.rnb, applied);
    }
    change
}

/// The 2 × 2 normal problem: find P ≥ 0 with w = K·P + b ≥ 0 and P_k·w_k = 0, where
/// b_k = v_nk - bias_k - (K·P_old)_k, trying both pushing, then each alone, then
/// neither. Returns the largest change, or `None` when K is too badly conditioned to invert (the points nearly
/// coincide), for the points to be solved one by one.
fn solve_block<const SPINS: bool>(
    m: &mut Manifold,
    inv: (Inverse, Inverse),
    v: &mut Local,
) -> Option<f64> {
    let n = m.normal;
    let (ia, ib) = inv;
    let (p1, p2) = (m.points[0], m.points[1]);
    let (r1a, r1b) = (p1.rna, p1.rnb);
    let (r2a, r2b) = (p2.rna, p2.rnb);
    let k11 = ia.mass + ib.mass + ia.inertia * r1a * r1a + ib.inertia * r1b * r1b;
    let k22 = ia.mass + ib.mass + ia.inertia * r2a * r2a + ib.inertia * r2b * r2b;
    let k12 = ia.mass + ib.mass + ia.inertia * r1a * r2a + ib.inertia * r1b * r2b;
    let det = k11 * k22 - k12 * k12;
    // Box2D's test of the condition number: k11² < 1000·det.
    if k11 * k11 >= 1000.0 * det {
        return None;
    }
    let (a1, a2) = (p1.pn, p2.pn);
    let vn1 = v.relative::<SPINS>(n, r1a, r1b);
    let vn2 = v.relative::<SPINS>(n, r2a, r2b);
    // b = v_n - bias - K·a.
    let b1 = vn1 - p1.bias - (k11 * a1 + k12 * a2);
    let b2 = vn2 - p2.bias - (k12 * a1 + k22 * a2);
    // The candidates in turn, each computed only when the ones before it fail (in the
    // common case, the first).
    let both = || {
        // Both push: x = -K⁻¹·b.
        let x1 = -(k22 * b1 - k12 * b2) / det;
        let x2 = -(k11 * b2 - k12 * b1) / det;
        (x1 >= 0.0 && x2 >= 0.0).then_some((x1, x2))
    };
    // Only the first: x1 = -b1/K11, and the second does not close: K12·x1 + b2 ≥ 0.
    let first = || {
        let x1 = -b1 / k11;
        (x1 >= 0.0 && k12 * x1 + b2 >= 0.0).then_some((x1, 0.0))
    };
    let second = || {
        let x2 = -b2 / k22;
        (x2 >= 0.0 && k12 * x2 + b1 >= 0.0).then_some((0.0, x2))
    };
    // Neither: both already part.
    let neither = || (b1 >= 0.0 && b2 >= 0.0).then_some((0.0, 0.0));
    let (x1, x2) = both().or_else(first).or_else(second).or_else(neither)?;
    let (d1, d2) = (x1 - a1, x2 - a2);
    m.points[0].pn = x1;
    m.points[1].pn = x2;
    v.apply::<SPINS>(inv, n, r1a, r1b, d1);
    v.apply::<SPINS>(inv, n, r2a, r2b, d2);
    Some(d1.abs().max(d2.abs()))
}

/// Returns 1/K for a push that moves two bodies along a line without turning them:
/// K = 1/M_A + 1/M_B.
pub fn linear_mass(inv: (Inverse, Inverse)) -> f64 {
    let k = inv.0.mass + inv.1.mass;
    if k > 0.0 {
        1.0 / k
    } else {
        0.0
    }
}

/// Returns the position change of one relaxation pass for a point whose gap is `gap`
/// (negative: overlapping), with slop `slop`, at most `max` at once:
/// C = clamp(β·(gap + slop), -max, 0), and the push -C/K along the normal, with
/// K = 1/M_A + 1/M_B ([`linear_mass`]).
///
/// The push translates the bodies and does not turn them. Turning a box about an
/// overlapping corner also slides its centre sideways, a motion made on positions that
/// friction, which acts on velocities, never sees; in a stack those small slides add
/// up to creep. Measured on the 20-row pyramid, awake for 60 s at dt = 1/240 s, the
/// largest displacement of a box with the push turning bodies, then without, at 8,
/// 12, 16, 25 and 50 sweeps: 1.21 m, 2.6, 20.9, 12.9 and 5.4 mm, then 146, 2.6, 5.1,
/// 2.4 and 3.6 mm; and 1,000 discs poured at 16 sweeps overlapped past the limit
/// (exit 3) with the turning push. (Both series were measured while a box's two
/// points still shared a warm-start key, `narrow_phase::name_box_features`; without
/// that bug the pyramid moves 2.3 to 0.26 mm from 8 to 50 sweeps.) The velocity
/// sweeps still turn bodies into their contacts.
pub fn relaxation(gap: f64, slop: f64, max: f64, mass: f64) -> f64 {
    let c = (BAUMGARTE * (gap + slop)).max(-max).min(0.0);
    -c * mass
}

/// Relaxation passes per step.
pub const fn position_passes() -> usize {
    POSITION_PASSES
}
