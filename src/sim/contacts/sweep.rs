//! The order of a step's contact stages: broad phase, times of impact, impacts taken
//! in time order, resting contacts at the step's end, and the overlap check (see the
//! module's notes in `mod.rs`).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec2;
use parry2d_f64::bounding_volume::Aabb;

use super::broad_phase::{swept_box, BroadPhase};
use super::narrow_phase::{contact, Contact, Rotations};
use super::relax::Relax;
use super::response::{closes, collide, normal_velocity, strike_point, Inverse, Side};
use super::sleep::{hold_all, hold_or_wake, settle, Islands};
use super::solver::{self, effective_mass_of, Manifold, Point, Velocities};
use super::toi::{time_of_impact, Path};
use super::{
    inverse, squeeze, Beyond, ContactEvent, Contacts, Overlap, Stop, Unanswerable, DEFAULT_SLOP,
    IMPACTS_PER_BODY, PAIRS_PER_BODY, PAIRS_PER_STEP,
};
use crate::sim::rigid::perp_dot;
use crate::sim::{State, System};

/// Sweeps over the contacts that collide at the step's end before the step leaves the
/// rest to the resting-contact solver.
const MAX_END_SWEEPS: usize = 100;

/// How deep resting bodies may overlap before the run stops: four slops, or a tenth of
/// the smaller body's size if that is more. The solver keeps a body resting on
/// another within about one slop and pushes back anything deeper by a fifth of its
/// excess per pass, but a pile being struck from above is squeezed further for a few
/// steps; a tenth of a body is far from passing through it.
const OVERLAP_SLOPS: f64 = 4.0;
const OVERLAP_SIZE: f64 = 0.1;

/// The buffers of a step's contact stages, kept between steps so that a step
/// allocates nothing once they have grown.
#[derive(Default)]
pub(super) struct Scratch {
    paths: Vec<Path>,
    inv: Vec<Inverse>,
    version: Vec<u32>,
    changed: Vec<bool>,
    changed_list: Vec<u32>,
    boxes: Vec<Aabb>,
    pairs: Vec<(u32, u32)>,
    found: Vec<(u32, u32)>,
    /// Candidate pairs the step may still meet (see `PAIRS_PER_BODY`).
    pairs_left: usize,
    heap: BinaryHeap<Reverse<Event>>,
    pub(super) broad: BroadPhase,
    query: Vec<u32>,
    touching: Vec<(u32, u32, Contact)>,
    manifolds: Vec<Manifold>,
    relax: Relax,
    islands: Islands,
    rotations: Rotations,
}

/// An impact of colliders i < j at step fraction λ, valid while neither has been
/// struck since it was found (their versions then are `vi` and `vj`). Ordered by λ,
/// then i, then j: the order impacts are taken in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Event {
    /// λ ≥ 0 as bits, which order as the numbers do.
    lambda: u64,
    i: u32,
    j: u32,
    vi: u32,
    vj: u32,
}

impl Contacts {
    /// Resolves the contacts of one step that took the bodies from `start` (at t0) to
    /// `end` (at t1), changing `end` where impulses act, and returns whether anything
    /// changed; or the deepest overlap left, or the body whose contacts cannot be
    /// answered.
    pub fn resolve(
        &mut self,
        system: &System,
        start: &State,
        end: &mut State,
        t0: f64,
        t1: f64,
    ) -> Result<bool, Stop> {
        if self.colliders.len() < 2 {
            return Ok(false);
        }
        let spins = system.spins();
        let inv_mass = system.inverse_masses();
        let inv_inertia = system.inverse_inertia();
        // A scene at rest, every body asleep or static: the sleeping bodies are held
        // and nothing else can happen, which is what the stages below would find, at
        // the cost of a pass over the bodies.
        if self.all_held(inv_mass, inv_inertia.filter(|_| spins)) {
            hold_all(&self.still, &self.colliders, start, end, spins);
            self.warm.clear();
            return Ok(true);
        }
        let Contacts {
            colliders,
            tolerance,
            resting,
            logging,
            log,
            warm,
            still,
            restless,
            scratch: s,
        } = self;
        let resting = *resting;
        let n = colliders.len();
        let h = t1 - t0;
        let tol = |i: usize, j: usize| {
            tolerance.unwrap_or(super::DEFAULT_TOLERANCE * colliders[i].size.min(colliders[j].size))
        };
        let margin = |i: usize| {
            let own = tolerance.unwrap_or(super::DEFAULT_TOLERANCE * colliders[i].size);
            // Resting contacts are found up to the slop apart, and as far as a resting
            // approach closes in a step (see the solver's reach below).
            if resting.speed > 0.0 {
                own + resting
                    .slop
                    .unwrap_or(super::DEFAULT_SLOP * colliders[i].size)
                    + resting.speed * h
            } else {
                own
            }
        };
        let slop = |i: usize, j: usize| {
            resting
                .slop
                .unwrap_or(super::DEFAULT_SLOP * colliders[i].size.min(colliders[j].size))
        };
        // The resting speed as a closing rate per unit of λ along the paths.
        let rest = resting.speed * h;

        // Each body's path through the step, from what the integrator did.
        s.paths.clear();
        s.inv.clear();
        for c in colliders.iter() {
            let b = c.body;
            let inertia = match (spins, inv_inertia) {
                (true, Some(ii)) => ii[b],
                _ => 0.0,
            };
            let inv = inverse(inv_mass[b], inertia);
            s.inv.push(inv);
            let (a0, a1, w0, w1) = if spins {
                (start.angle[b], end.angle[b], start.omega[b], end.omega[b])
            } else {
                (start.angle[b], start.angle[b], 0.0, 0.0)
            };
            let path = Path {
                lambda: 0.0,
                r: start.pos[b],
                angle: a0,
                dr: end.pos[b] - start.pos[b],
                dangle: a1 - a0,
                v: start.vel[b],
                omega: w0,
                dv: end.vel[b] - start.vel[b],
                domega: w1 - w0,
            };
            // A moving body so far out that f64 cannot place it to within its slop
            // has contacts no stage can answer (and the times of impact of paths
            // 10^16 m long would take seconds each): the run stops and names it.
            if !immovable(&inv) {
                if let Some(why) = beyond_precision(&path, c.size, spins) {
                    return Err(Stop::Unanswerable(Unanswerable { body: b, why }));
                }
            }
            s.paths.push(path);
        }
        let fixed = |inv: &[Inverse], i: usize| immovable(&inv[i]);
        s.version.clear();
        s.version.resize(n, 0);
        s.changed.clear();
        s.changed.resize(n, false);
        s.changed_list.clear();
        s.found.clear();
        s.heap.clear();

        // 1. The pairs whose swept boxes overlap.
        s.boxes.clear();
        for (k, c) in colliders.iter().enumerate() {
            s.boxes.push(swept_box(c, &s.paths[k], margin(k)));
        }
        let budget = PAIRS_PER_BODY * n + PAIRS_PER_STEP;
        if !s.broad.build(s.boxes.iter().copied(), &mut s.pairs, budget) {
            return Err(longest_path(colliders, start, end, budget));
        }
        s.pairs_left = budget - s.pairs.len();
        // Sleeping bodies that nothing awake and moving comes near are held where they
        // are, as static bodies for this step; the others wake (`sleep.rs`).
        let mut changed = false;
        if let Some(sleep) = resting.sleep {
            changed = hold_or_wake(
                still,
                &s.pairs,
                colliders,
                &mut s.inv,
                &mut s.paths,
                start,
                end,
                spins,
                sleep.speed,
                &mut s.islands,
            );
        }
        {
            let inv = &s.inv;
            s.pairs
                .retain(|&(i, j)| !(fixed(inv, i as usize) && fixed(inv, j as usize)));
        }

        // 2. The first impact of each pair.
        for &(i, j) in &s.pairs {
            let (iu, ju) = (i as usize, j as usize);
            if let Some(lambda) = time_of_impact(
                &colliders[iu],
                &s.paths[iu],
                &colliders[ju],
                &s.paths[ju],
                0.0,
                tol(iu, ju),
                rest,
            ) {
                s.heap.push(Reverse(Event {
                    lambda: lambda.to_bits(),
                    i,
                    j,
                    vi: 0,
                    vj: 0,
                }));
            }
        }

        // 3. Impacts in time order.
        let cap = IMPACTS_PER_BODY * n + 1_000;
        let mut impacts = 0usize;
        let mut exhausted = false;
        while let Some(Reverse(ev)) = s.heap.pop() {
            let (i, j) = (ev.i as usize, ev.j as usize);
            if ev.vi != s.version[i] || ev.vj != s.version[j] {
                continue;
            }
            let lambda = f64::from_bits(ev.lambda);
            let (pi, pj) = (s.paths[i].pose(lambda), s.paths[j].pose(lambda));
            let t = tol(i, j);
            let Some(ct) = contact(&colliders[i], &pi, &colliders[j], &pj, 2.0 * t, t) else {
                continue;
            };
            let (vi, wi) = s.paths[i].velocity(lambda);
            let (vj, wj) = s.paths[j].velocity(lambda);
            let mut a = Side {
                inv: s.inv[i],
                centre: pi.r,
                v: vi,
                omega: wi,
            };
            let mut b = Side {
                inv: s.inv[j],
                centre: pj.r,
                v: vj,
                omega: wj,
            };
            impacts += 1;
            if impacts > cap {
                exhausted = true;
                break;
            }
            let e = colliders[i].restitution.max(colliders[j].restitution);
            if let Some(point) = strike_point(&a, &b, ct.points(), ct.normal, e, resting.speed) {
                let mu = (colliders[i].friction * colliders[j].friction).sqrt();
                let imp = collide(&mut a, &mut b, point, ct.normal, e, mu);
                if *logging {
                    log.push(ContactEvent {
                        t: t0 + lambda * h,
                        a: colliders[i].body,
                        b: colliders[j].body,
                        point,
                        normal: ct.normal,
                        vn_before: imp.vn_before,
                        vn_after: imp.vn_after,
                        impulse: imp.j,
                        jt: imp.jt,
                    });
                }
                s.paths[i] = restart(&s.paths[i], lambda, a.v - vi, a.omega - wi, h, DVec2::ZERO);
                s.paths[j] = restart(&s.paths[j], lambda, b.v - vj, b.omega - wj, h, DVec2::ZERO);
            } else {
                // They touch and their velocities part, but their paths still close
                // (the path is the step's chord, the velocity its tangent): the rest
                // of both paths is moved apart along n, shared by inverse mass, so that
                // neither passes into the other. No velocity changes, so no energy or
                // momentum does, and nothing is logged.
                // The fastest closing of the contact's points along the paths.
                let (closing, scale) = ct
                    .points()
                    .iter()
                    .map(|p| {
                        let ua = s.paths[i].point_rate(pi.r, *p);
                        let ub = s.paths[j].point_rate(pj.r, *p);
                        ((ua - ub).dot(ct.normal), ua.length() + ub.length())
                    })
                    .fold((f64::INFINITY, 0.0), |m, x| if x.0 < m.0 { x } else { m });
                let total = s.inv[i].mass + s.inv[j].mass;
                if !closes(closing, scale, rest) || total == 0.0 {
                    continue;
                }
                let shift = -closing / total * ct.normal;
                s.paths[i] = restart(
                    &s.paths[i],
                    lambda,
                    DVec2::ZERO,
                    0.0,
                    h,
                    shift * s.inv[i].mass,
                );
                s.paths[j] = restart(
                    &s.paths[j],
                    lambda,
                    DVec2::ZERO,
                    0.0,
                    h,
                    -shift * s.inv[j].mass,
                );
            }
            // When both bodies move, j is requeried after i, with j's version raised
            // between the two: so i's requery need not search the pair (i, j), whose
            // event would carry j's old version and never be taken. j's requery
            // searches it.
            let then = (!fixed(&s.inv, j)).then_some(j);
            for (k, next) in [(i, then), (j, None)] {
                if fixed(&s.inv, k) {
                    continue;
                }
                s.version[k] += 1;
                if !requery(k, next, lambda, colliders, s, &margin, &tol, rest) {
                    return Err(longest_path(colliders, start, end, budget));
                }
            }
        }

        // The end of every struck body's path is where the step leaves it.
        for &k in &s.changed_list {
            let k = k as usize;
            let p = &s.paths[k];
            let b = colliders[k].body;
            let rest = 1.0 - p.lambda;
            end.pos[b] = p.r + rest * p.dr;
            end.vel[b] = p.v + rest * p.dv;
            if spins {
                end.angle[b] = p.angle + rest * p.dangle;
                end.omega[b] = p.omega + rest * p.domega;
            }
        }
        changed |= !s.changed_list.is_empty();

        // 4. Contacts at the step's end: none may overlap deeper than its allowance,
        // those that approach faster than the resting speed collide now, and the rest
        // go to the resting-contact solver.
        s.pairs.extend_from_slice(&s.found);
        s.pairs.sort_unstable();
        s.pairs.dedup();
        s.touching.clear();
        let mut deepest: Option<Overlap> = None;
        for &(i, j) in &s.pairs {
            let (iu, ju) = (i as usize, j as usize);
            let (bi, bj) = (colliders[iu].body, colliders[ju].body);
            let pi = s.rotations.pose(iu, end.pos[bi], end.angle[bi]);
            let pj = s.rotations.pose(ju, end.pos[bj], end.angle[bj]);
            let (t, sl) = (tol(iu, ju), slop(iu, ju));
            // With resting contact, points up to the slop apart are the solver's
            // (speculative: they may close that gap, no more); without, only touching
            // points matter.
            // Speculative contacts: a pair apart by less than the slop plus what a
            // resting approach closes in one step (resting speed × h) goes to the
            // solver, which lets it close its gap and no more; an impact would be
            // faster, and is found by the next step's time of impact.
            let reach = if resting.speed > 0.0 {
                sl + resting.speed * h
            } else {
                t
            };
            let Some(ct) = contact(&colliders[iu], &pi, &colliders[ju], &pj, reach, reach) else {
                continue;
            };
            let allowed = t + if resting.speed > 0.0 {
                (OVERLAP_SLOPS * sl).max(OVERLAP_SIZE * colliders[iu].size.min(colliders[ju].size))
            } else {
                0.0
            };
            if ct.gap < -allowed && deepest.is_none_or(|d| -ct.gap > d.depth) {
                deepest = Some(Overlap {
                    a: bi,
                    b: bj,
                    depth: -ct.gap,
                    crowded: exhausted,
                    squeezed: None,
                });
            }
            s.touching.push((i, j, ct));
        }
        if let Some(d) = deepest {
            let squeezed = squeeze::squeezed(d.a, d.b, colliders, &s.inv, &s.pairs);
            return Err(Stop::Overlap(Overlap { squeezed, ..d }));
        }
        // 4a. Collisions at the step's end, pair by pair in order, sweep after sweep.
        for _ in 0..MAX_END_SWEEPS {
            let mut any = false;
            for &(i, j, ct) in &s.touching {
                let (iu, ju) = (i as usize, j as usize);
                let (bi, bj) = (colliders[iu].body, colliders[ju].body);
                let t = tol(iu, ju);
                let mut a = Side {
                    inv: s.inv[iu],
                    centre: end.pos[bi],
                    v: end.vel[bi],
                    omega: if spins { end.omega[bi] } else { 0.0 },
                };
                let mut b = Side {
                    inv: s.inv[ju],
                    centre: end.pos[bj],
                    v: end.vel[bj],
                    omega: if spins { end.omega[bj] } else { 0.0 },
                };
                let e = colliders[iu].restitution.max(colliders[ju].restitution);
                // Only the points that touch collide.
                let mut touching = [DVec2::ZERO; 2];
                let mut count = 0;
                for (p, g) in ct.points().iter().zip(ct.gaps) {
                    if g <= t {
                        touching[count] = *p;
                        count += 1;
                    }
                }
                let Some(point) =
                    strike_point(&a, &b, &touching[..count], ct.normal, e, resting.speed)
                else {
                    continue;
                };
                let mu = (colliders[iu].friction * colliders[ju].friction).sqrt();
                let imp = collide(&mut a, &mut b, point, ct.normal, e, mu);
                if *logging {
                    log.push(ContactEvent {
                        t: t1,
                        a: bi,
                        b: bj,
                        point,
                        normal: ct.normal,
                        vn_before: imp.vn_before,
                        vn_after: imp.vn_after,
                        impulse: imp.j,
                        jt: imp.jt,
                    });
                }
                for (body, side, k) in [(bi, &a, iu), (bj, &b, ju)] {
                    if !fixed(&s.inv, k) {
                        end.vel[body] = side.v;
                        if spins {
                            end.omega[body] = side.omega;
                        }
                    }
                }
                any = true;
                changed = true;
            }
            if !any {
                break;
            }
        }
        // 4b. Resting contacts, solved together (`solver.rs`).
        if resting.speed > 0.0 {
            s.manifolds.clear();
            for &(i, j, ct) in &s.touching {
                let (iu, ju) = (i as usize, j as usize);
                let (bi, bj) = (colliders[iu].body, colliders[ju].body);
                // A contact still apart whose bodies close faster than the resting
                // speed is a collision to come, for the next step's impacts: the
                // solver must not brake it.
                if ct.gap > tol(iu, ju) {
                    let side = |k: usize, b: usize| Side {
                        inv: s.inv[k],
                        centre: end.pos[b],
                        v: end.vel[b],
                        omega: if spins { end.omega[b] } else { 0.0 },
                    };
                    let (sa, sb) = (side(iu, bi), side(ju, bj));
                    if ct
                        .points()
                        .iter()
                        .any(|p| normal_velocity(&sa, &sb, *p, ct.normal) < -resting.speed)
                    {
                        continue;
                    }
                }
                let pair = (s.inv[iu], s.inv[ju]);
                let t = ct.normal.perp();
                let mut m = Manifold {
                    i,
                    j,
                    bi,
                    bj,
                    normal: ct.normal,
                    friction: (colliders[iu].friction * colliders[ju].friction).sqrt(),
                    points: [Point::default(); 2],
                    count: ct.count,
                };
                for k in 0..ct.count {
                    let (ra, rb) = (ct.points[k] - end.pos[bi], ct.points[k] - end.pos[bj]);
                    let (rna, rnb) = (perp_dot(ra, ct.normal), perp_dot(rb, ct.normal));
                    let (rta, rtb) = (perp_dot(ra, t), perp_dot(rb, t));
                    m.points[k] = Point {
                        rna,
                        rnb,
                        rta,
                        rtb,
                        normal_mass: effective_mass_of(pair, rna, rnb),
                        tangent_mass: effective_mass_of(pair, rta, rtb),
                        // Apart by a gap, the point may close it within the step.
                        bias: -(ct.gaps[k].max(0.0)) / h,
                        pn: 0.0,
                        pt: 0.0,
                        id: ct.ids[k],
                    };
                }
                s.manifolds.push(m);
            }
            if !s.manifolds.is_empty() {
                let (vel, omega) = (&mut end.vel, &mut end.omega);
                let mut v = Velocities { vel, omega, spins };
                solver::solve(&mut s.manifolds, &s.inv, &mut v, resting.iterations, warm);
                changed = true;
                // 5. Relax positions: push apart what overlaps by more than the slop
                // (`relax.rs`).
                s.relax
                    .run(&s.manifolds, colliders, &s.inv, end, &mut s.rotations, slop);
            } else {
                warm.clear();
            }
        }
        // 6. Islands at rest fall asleep (`sleep.rs`).
        if let Some(sleep) = resting.sleep {
            changed |= settle(
                sleep,
                h,
                still,
                restless,
                &s.touching,
                colliders,
                &s.inv,
                end,
                spins,
                &mut s.islands,
            );
        }
        Ok(changed)
    }
}

/// Returns true for a collider that nothing moves: 1/M = 1/I = 0.
pub(super) fn immovable(inv: &Inverse) -> bool {
    inv.mass == 0.0 && inv.inertia == 0.0
}

/// Returns the path restarted at λ with its velocity and spin changed by Δv and Δω,
/// which also change the rest of its motion: Δr per unit λ gains h·Δv (and `shift`),
/// Δθ gains h·Δω, and the velocity at the end gains Δv.
fn restart(p: &Path, lambda: f64, dv: DVec2, dw: f64, h: f64, shift: DVec2) -> Path {
    let s = lambda - p.lambda;
    Path {
        lambda,
        r: p.r + s * p.dr,
        angle: p.angle + s * p.dangle,
        dr: p.dr + h * dv + shift,
        dangle: p.dangle + h * dw,
        v: p.v + s * p.dv + dv,
        omega: p.omega + s * p.domega + dw,
        dv: p.dv,
        domega: p.domega,
    }
}

/// Finds the later impacts of collider k, struck at λ: its new swept box is tested
/// against the boxes the step began with (for colliders not struck yet) and against
/// the current boxes of those struck already. The pair of k and `next`, the collider
/// requeried next, is left to that requery: `next`'s version rises before it, so an
/// event found here would be stale (it is still counted against the budget and
/// recorded as found, as its requery does).
#[allow(clippy::too_many_arguments)]
fn requery(
    k: usize,
    next: Option<usize>,
    lambda: f64,
    colliders: &[super::Collider],
    s: &mut Scratch,
    margin: &impl Fn(usize) -> f64,
    tol: &impl Fn(usize, usize) -> f64,
    rest: f64,
) -> bool {
    let bx = swept_box(&colliders[k], &s.paths[k], margin(k));
    if !s.changed[k] {
        s.changed[k] = true;
        s.changed_list.push(k as u32);
    }
    // The tree holds every collider's latest box (struck ones' too), so one query
    // finds all it may meet, at a cost that does not grow with how many were struck.
    s.broad.update(k, bx);
    s.broad.query(&bx, &mut s.query);
    let mut others = std::mem::take(&mut s.query);
    others.retain(|&m| m as usize != k);
    if others.len() > s.pairs_left {
        s.query = others;
        return false;
    }
    s.pairs_left -= others.len();
    for &m in &others {
        let m = m as usize;
        if immovable(&s.inv[k]) && immovable(&s.inv[m]) {
            continue;
        }
        let (i, j) = (k.min(m), k.max(m));
        s.found.push((i as u32, j as u32));
        if next == Some(m) {
            continue;
        }
        if let Some(at) = time_of_impact(
            &colliders[i],
            &s.paths[i],
            &colliders[j],
            &s.paths[j],
            lambda,
            tol(i, j),
            rest,
        ) {
            s.heap.push(Reverse(Event {
                lambda: at.to_bits(),
                i: i as u32,
                j: j as u32,
                vi: s.version[i],
                vj: s.version[j],
            }));
        }
    }
    s.query = others;
    true
}

/// Returns why a body on `path` is too far out for its contacts, if it is: where
/// neighbouring f64 values lie further apart than its slop (`DEFAULT_SLOP` of its
/// size), or its angle's further apart than `DEFAULT_SLOP` radians, contacts cannot be
/// kept to the slop. At 1 m that is 4.5·10^12 m from the origin.
fn beyond_precision(path: &Path, size: f64, spins: bool) -> Option<Beyond> {
    let end = path.r + path.dr;
    let coordinate = path.r.abs().max(end.abs()).max_element();
    // The spacing of f64 values at x is at most x·ε (ε = 2^-52).
    let spacing = coordinate * f64::EPSILON;
    if spacing > DEFAULT_SLOP * size {
        return Some(Beyond::Precision {
            coordinate,
            spacing,
            angle: false,
        });
    }
    if spins {
        let angle = path.angle.abs().max((path.angle + path.dangle).abs());
        if angle * f64::EPSILON > DEFAULT_SLOP {
            return Some(Beyond::Precision {
                coordinate: angle,
                spacing: angle * f64::EPSILON,
                angle: true,
            });
        }
    }
    None
}

/// The stop of a step that met more candidate pairs than `budget`, naming the body
/// that moved furthest in it: the one whose path crosses most others'.
fn longest_path(colliders: &[super::Collider], start: &State, end: &State, budget: usize) -> Stop {
    let (body, distance) = colliders
        .iter()
        .map(|c| (c.body, (end.pos[c.body] - start.pos[c.body]).length()))
        .fold(
            (colliders[0].body, -1.0),
            |m, x| if x.1 > m.1 { x } else { m },
        );
    Stop::Unanswerable(Unanswerable {
        body,
        why: Beyond::Pairs { distance, budget },
    })
}
