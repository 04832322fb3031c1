//! The narrow phase: where two shapes at given poses touch, how far apart they are, and
//! along which normal.
//!
//! Two discs are a closed form. Every pair with a polygon asks parry (the geometry
//! under Rapier) for its contact manifold, at most two points in 2-D: a box lying flat
//! on a floor touches it along an edge, and the impulse is then applied at the middle of
//! the points that touch (within the tolerance of the deepest), so that a flat landing
//! does not set the box spinning. Normals point from body b to body a, as in the
//! article's impulse equation.

use glam::DVec2;
use parry2d_f64::math::{Pose as ParryPose, Rot2};
use parry2d_f64::query::details::{
    contact_manifold_convex_ball, contact_manifold_cuboid_cuboid, contact_manifold_pfm_pfm,
};
use parry2d_f64::query::{self, ContactManifold};
use parry2d_f64::shape::{ConvexPolygon, Cuboid, Shape};

use super::box_features::name_box_features;
use super::collider::{from_parry, to_parry, Collider, ColliderShape};
use super::gjk_epa::support_maps_contact;
use crate::sim::rigid::rotate;

/// Where a body is: its centre of mass r and its angle θ, with (sin θ, cos θ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub r: DVec2,
    pub angle: f64,
    pub sin_cos: (f64, f64),
}

impl Pose {
    /// Returns the pose with its centre of mass at r, turned by θ.
    #[inline]
    pub fn new(r: DVec2, angle: f64) -> Self {
        Pose {
            r,
            angle,
            sin_cos: angle.sin_cos(),
        }
    }

    /// Returns the world position of the shape point q: r + R(θ)·q.
    #[inline]
    pub fn apply(&self, q: DVec2) -> DVec2 {
        self.r + rotate(self.sin_cos, q)
    }

    fn to_parry(self) -> ParryPose {
        let (s, c) = self.sin_cos;
        ParryPose::from_parts(to_parry(self.r), Rot2::from_cos_sin_unchecked(c, s))
    }
}

/// Each collider's latest rotation: the angle it was last posed at and that angle's
/// (sin θ, cos θ), so that posing it again at the same angle (a body that did not turn
/// since, met again by another pair or in another pass) costs no sine and cosine. The
/// values are `f64::sin_cos` of the very same angle, so the poses are the same to the
/// bit as [`Pose::new`]'s.
#[derive(Clone, Debug, Default)]
pub struct Rotations {
    latest: Vec<(f64, (f64, f64))>,
}

impl Rotations {
    /// Returns collider k's pose with its centre of mass at r, turned by θ.
    #[inline]
    pub fn pose(&mut self, k: usize, r: DVec2, angle: f64) -> Pose {
        if k >= self.latest.len() {
            // Every entry holds an angle and its own sine and cosine: 0 to start with.
            self.latest.resize(k + 1, (0.0, 0f64.sin_cos()));
        }
        let latest = &mut self.latest[k];
        if latest.0.to_bits() != angle.to_bits() {
            *latest = (angle, angle.sin_cos());
        }
        Pose {
            r,
            angle,
            sin_cos: latest.1,
        }
    }
}

/// Where two bodies touch or come closest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The signed distance between the shapes: positive apart, negative overlapping.
    pub gap: f64,
    /// The unit normal, pointing from body b to body a.
    pub normal: DVec2,
    /// The world point where the impulse acts: the middle of the closest points.
    pub point: DVec2,
    /// The closest points themselves (the middle of each pair of surface points): one,
    /// or two when an edge lies along an edge or a face (within the tolerance).
    pub points: [DVec2; 2],
    /// How many of `points` there are: 1 or 2.
    pub count: usize,
    /// Each point's own gap (signed distance along the normal).
    pub gaps: [f64; 2],
    /// Each point's features on the two shapes, packed: what a contact point is called
    /// from one step to the next, so that the resting-contact solver can start it from
    /// the impulse it needed last step.
    pub ids: [u64; 2],
}

impl Contact {
    /// Returns the closest points.
    pub fn points(&self) -> &[DVec2] {
        &self.points[..self.count]
    }
}

/// Returns the contact of a at `pa` and b at `pb` when their gap is at most
/// `prediction`, or `None` when they are farther apart.
///
/// `tol` is the contact tolerance: manifold points within `tol` of the closest one all
/// count, and the contact point is their middle.
pub fn contact(
    a: &Collider,
    pa: &Pose,
    b: &Collider,
    pb: &Pose,
    prediction: f64,
    tol: f64,
) -> Option<Contact> {
    match (&a.shape, &b.shape) {
        (ColliderShape::Disc { radius: ra }, ColliderShape::Disc { radius: rb }) => {
            discs(pa.r, *ra, pb.r, *rb, prediction)
        }
        (
            ColliderShape::Convex {
                shape: sa,
                cuboid: ca,
                ..
            },
            ColliderShape::Convex {
                shape: sb,
                cuboid: cb,
                ..
            },
        ) => {
            let mut m = ContactManifold::<(), ()>::new();
            let pos12 = pa.to_parry().inv_mul(&pb.to_parry());
            if let (Some(ca), Some(cb)) = (ca, cb) {
                // Two boxes: parry's separating-axis manifold, which is right even for
                // boxes that touch exactly side by side (the general polygon one takes
                // them for overlapping through their full height).
                contact_manifold_cuboid_cuboid(&pos12, ca, cb, prediction, &mut m);
                name_box_features(&mut m);
                return from_manifold(&m, pa, pb, tol);
            }
            contact_manifold_pfm_pfm(
                &pos12,
                sa.as_ref(),
                0.0,
                None,
                sb.as_ref(),
                0.0,
                None,
                prediction,
                &mut m,
            );
            let c = from_manifold(&m, pa, pb, tol)?;
            // The general manifold can take two polygons that touch exactly for deeply
            // overlapping; GJK's distance then tells, and the manifold is taken again
            // with b moved apart by a little, its gaps moved back by as much.
            let limit = tol.max(1e-12 * (a.reach + b.reach));
            if c.gap < -limit {
                let true_gap = separation(a, pa, b, pb)?.gap;
                if true_gap > c.gap + limit {
                    let away = (pb.r - pa.r).normalize_or(DVec2::Y) * (4.0 * limit);
                    let moved = Pose {
                        r: pb.r + away,
                        ..*pb
                    };
                    let mut m = ContactManifold::<(), ()>::new();
                    let pos12 = pa.to_parry().inv_mul(&moved.to_parry());
                    contact_manifold_pfm_pfm(
                        &pos12,
                        sa.as_ref(),
                        0.0,
                        None,
                        sb.as_ref(),
                        0.0,
                        None,
                        prediction + 4.0 * limit,
                        &mut m,
                    );
                    let mut c = from_manifold(&m, pa, &moved, tol)?;
                    // Moving b by `away` opened every gap along n by -away·n.
                    let opened = -away.dot(c.normal);
                    c.gap -= opened;
                    for g in &mut c.gaps {
                        *g -= opened;
                    }
                    return (c.gap <= prediction).then_some(c);
                }
            }
            Some(c)
        }
        (
            ColliderShape::Convex {
                shape: sa, cuboid, ..
            },
            ColliderShape::Disc { .. },
        ) => {
            let ball = b.ball()?;
            let mut m = ContactManifold::<(), ()>::new();
            let pos12 = pa.to_parry().inv_mul(&pb.to_parry());
            let shape = box_or_polygon(cuboid, sa);
            contact_manifold_convex_ball(
                &pos12, shape, &ball, None, None, prediction, &mut m, false,
            );
            from_manifold(&m, pa, pb, tol)
        }
        (ColliderShape::Disc { .. }, ColliderShape::Convex { .. }) => {
            // The same query with the roles swapped, and the normal turned back.
            // (Feature ids name b's feature first then; they only need to be stable.)
            contact(b, pb, a, pa, prediction, tol).map(|c| Contact {
                normal: -c.normal,
                ..c
            })
        }
    }
}

/// Returns the signed distance between a and b, with a normal from b to a and the
/// closest points' middle, however far apart they are: what conservative advancement
/// needs (parry's GJK and EPA for polygons).
pub fn separation(a: &Collider, pa: &Pose, b: &Collider, pb: &Pose) -> Option<Contact> {
    if let (ColliderShape::Disc { radius: ra }, ColliderShape::Disc { radius: rb }) =
        (&a.shape, &b.shape)
    {
        return discs(pa.r, *ra, pb.r, *rb, f64::INFINITY);
    }
    let (sa, cuboid_a): (&ConvexPolygon, _) = match &a.shape {
        ColliderShape::Convex { shape, cuboid, .. } => (shape.as_ref(), cuboid),
        ColliderShape::Disc { .. } => return separation_ball(a, pa, b, pb),
    };
    let (ppa, ppb) = (pa.to_parry(), pb.to_parry());
    let c = match &b.shape {
        // Two polygons: what `query::contact` does for them (GJK, then EPA when they
        // overlap), with this thread's EPA instead of a new one per call.
        ColliderShape::Convex { shape, .. } => {
            support_maps_contact(&ppa, sa, &ppb, shape.as_ref(), f64::MAX)?
        }
        ColliderShape::Disc { radius } => {
            let ball_b = parry2d_f64::shape::Ball::new(*radius);
            let shape = box_or_polygon(cuboid_a, sa);
            query::contact(&ppa, shape, &ppb, &ball_b, f64::MAX).ok()??
        }
    };
    // parry's normal1 points from a towards b, in world axes.
    let normal = -from_parry(c.normal1);
    let point = 0.5 * (from_parry(c.point1) + from_parry(c.point2));
    Some(Contact {
        gap: c.dist,
        normal,
        point,
        points: [point, point],
        count: 1,
        gaps: [c.dist, c.dist],
        ids: [0, 0],
    })
}

/// Returns the shape parry should project a disc's centre onto: a box's cuboid, whose
/// projection is a closed form (clamping to its half-extents), or the polygon, whose
/// projection is GJK's iterations. The two agree to round-off (`disc_box_tests.rs`).
fn box_or_polygon<'a>(cuboid: &'a Option<Cuboid>, polygon: &'a ConvexPolygon) -> &'a dyn Shape {
    match cuboid {
        Some(c) => c,
        None => polygon,
    }
}

/// The disc-first case of [`separation`], by symmetry.
fn separation_ball(a: &Collider, pa: &Pose, b: &Collider, pb: &Pose) -> Option<Contact> {
    separation(b, pb, a, pa).map(|c| Contact {
        normal: -c.normal,
        ..c
    })
}

/// Two discs: the gap is |r_a - r_b| - (ρ_a + ρ_b), the normal (r_a - r_b)/|r_a - r_b|,
/// and the point the middle of the two closest surface points.
#[inline]
fn discs(ra: DVec2, rad_a: f64, rb: DVec2, rad_b: f64, prediction: f64) -> Option<Contact> {
    let d = ra - rb;
    let dist = d.length();
    let gap = dist - (rad_a + rad_b);
    if gap > prediction {
        return None;
    }
    // Concentric discs have no normal; any unit vector is as good as another, and a
    // fixed one keeps the run deterministic.
    let normal = if dist > 0.0 { d / dist } else { DVec2::Y };
    // The surface points: r_a - ρ_a·n on a and r_b + ρ_b·n on b.
    let point = 0.5 * ((ra - rad_a * normal) + (rb + rad_b * normal));
    Some(Contact {
        gap,
        normal,
        point,
        points: [point, point],
        count: 1,
        gaps: [gap, gap],
        ids: [0, 0],
    })
}

/// Turns a parry manifold (points in a's frame, normal from a to b in a's frame) into
/// a contact: the closest distance, the normal from b to a in world axes, and the middle
/// of the points within `tol` of the closest.
fn from_manifold(m: &ContactManifold<(), ()>, pa: &Pose, pb: &Pose, tol: f64) -> Option<Contact> {
    let gap = m
        .points
        .iter()
        .map(|p| p.dist)
        .fold(f64::INFINITY, f64::min);
    if !gap.is_finite() {
        return None;
    }
    let mut points = [DVec2::ZERO; 2];
    let mut gaps = [gap; 2];
    let mut ids = [0u64; 2];
    let mut count = 0;
    for p in m.points.iter().filter(|p| p.dist <= gap + tol).take(2) {
        let on_a = pa.apply(from_parry(p.local_p1));
        let on_b = pb.apply(from_parry(p.local_p2));
        points[count] = 0.5 * (on_a + on_b);
        gaps[count] = p.dist;
        ids[count] = (u64::from(p.fid1.0) << 32) | u64::from(p.fid2.0);
        count += 1;
    }
    if count == 1 {
        points[1] = points[0];
        gaps[1] = gaps[0];
        ids[1] = ids[0];
    }
    let normal = -rotate(pa.sin_cos, from_parry(m.local_n1));
    Some(Contact {
        gap,
        normal,
        point: 0.5 * (points[0] + points[1]),
        points,
        count,
        gaps,
        ids,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, y: f64, angle: f64) -> Pose {
        Pose::new(DVec2::new(x, y), angle)
    }

    #[test]
    fn two_discs_touch_along_the_line_of_their_centres() {
        let a = Collider::disc(0, 1.0, 1.0);
        let b = Collider::disc(1, 0.5, 1.0);
        let c = contact(&a, &at(3.0, 0.0, 0.0), &b, &at(0.0, 0.0, 0.0), 10.0, 1e-9)
            .expect("within the prediction");
        assert_eq!(c.gap, 1.5);
        assert_eq!(c.normal, DVec2::X);
        // Closest points (2, 0) on a and (0.5, 0) on b: their middle is 1.25.
        assert_eq!(c.point, DVec2::new(1.25, 0.0));
        assert!(contact(&a, &at(3.0, 0.0, 0.0), &b, &at(0.0, 0.0, 0.0), 1.0, 1e-9).is_none());
    }

    #[test]
    fn a_box_flat_on_a_floor_touches_at_the_middle_of_its_bottom_edge() {
        // A 1 × 1 box 1e-3 above a 10 × 1 floor whose top is y = 0.
        let bx = Collider::rectangle(0, 1.0, 1.0, 1.0).expect("a box");
        let floor = Collider::rectangle(1, 10.0, 1.0, 1.0).expect("a box");
        let c = contact(
            &bx,
            &at(0.3, 0.501, 0.0),
            &floor,
            &at(0.0, -0.5, 0.0),
            0.1,
            1e-6,
        )
        .expect("close enough");
        assert!((c.gap - 1e-3).abs() < 1e-12, "gap {}", c.gap);
        assert!(
            (c.normal - DVec2::Y).length() < 1e-12,
            "normal {}",
            c.normal
        );
        assert!(
            (c.point - DVec2::new(0.3, 0.0005)).length() < 1e-12,
            "point {}",
            c.point
        );
        // Turned by 45°, it stands on its corner: the contact is that corner.
        let q = std::f64::consts::FRAC_PI_4;
        let h = 0.5 * 2f64.sqrt();
        let c = contact(
            &bx,
            &at(0.0, h + 1e-3, q),
            &floor,
            &at(0.0, -0.5, 0.0),
            0.1,
            1e-6,
        )
        .expect("close enough");
        assert!((c.gap - 1e-3).abs() < 1e-12, "gap {}", c.gap);
        assert!(c.point.x.abs() < 1e-12, "point {}", c.point);
    }

    #[test]
    fn a_disc_against_a_box_has_its_normal_from_the_box_face() {
        let disc = Collider::disc(0, 0.5, 1.0);
        let wall = Collider::rectangle(1, 1.0, 4.0, 1.0).expect("a box");
        // The disc right of the wall (wall face at x = 0.5), 0.25 away.
        let c = contact(
            &disc,
            &at(1.25, 0.7, 0.0),
            &wall,
            &at(0.0, 0.0, 0.0),
            1.0,
            1e-9,
        )
        .expect("close");
        assert!((c.gap - 0.25).abs() < 1e-12);
        assert!((c.normal - DVec2::X).length() < 1e-12);
        // Swapped, the normal still points from the second body to the first.
        let c = contact(
            &wall,
            &at(0.0, 0.0, 0.0),
            &disc,
            &at(1.25, 0.7, 0.0),
            1.0,
            1e-9,
        )
        .expect("close");
        assert!((c.normal + DVec2::X).length() < 1e-12);
        let s = separation(&disc, &at(5.0, 0.0, 0.0), &wall, &at(0.0, 0.0, 0.0))
            .expect("parry answers");
        assert!((s.gap - 4.0).abs() < 1e-12 && (s.normal - DVec2::X).length() < 1e-12);
        let s = separation(&wall, &at(0.0, 0.0, 0.0), &disc, &at(5.0, 0.0, 0.0))
            .expect("parry answers");
        assert!((s.gap - 4.0).abs() < 1e-12 && (s.normal + DVec2::X).length() < 1e-12);
    }
}

#[cfg(test)]
mod touching_tests {
    use super::*;

    #[test]
    fn boxes_and_polygons_side_by_side_touch_and_do_not_overlap() {
        // Two unit squares exactly side by side, as boxes and as polygons.
        let square = vec![
            DVec2::new(-0.5, -0.5),
            DVec2::new(0.5, -0.5),
            DVec2::new(0.5, 0.5),
            DVec2::new(-0.5, 0.5),
        ];
        let pairs = [
            (
                Collider::rectangle(0, 1.0, 1.0, 1.0).expect("a box"),
                Collider::rectangle(1, 1.0, 1.0, 1.0).expect("a box"),
            ),
            (
                Collider::polygon(0, square.clone(), 1.0).expect("convex"),
                Collider::polygon(1, square, 1.0).expect("convex"),
            ),
        ];
        for (a, b) in pairs {
            for dx in [1.0, 1.0 + 1e-9, 1.0 - 1e-9] {
                let pa = Pose::new(DVec2::new(0.0, 0.5), 0.0);
                let pb = Pose::new(DVec2::new(dx, 0.5), 0.0);
                let c = contact(&a, &pa, &b, &pb, 0.01, 0.01).expect("in contact");
                assert!((c.gap - (dx - 1.0)).abs() < 1e-12, "dx {dx}: gap {}", c.gap);
                assert!(
                    (c.normal + DVec2::X).length() < 1e-12,
                    "dx {dx}: {}",
                    c.normal
                );
            }
        }
    }
}

#[cfg(test)]
mod feature_tests {
    use super::*;

    /// The two points' keys of a box of size `w` × 1 resting at (x, 1e-3 above) on a
    /// box of size `floor` × 1, turned by `angle`.
    fn ids(w: f64, floor: f64, x: f64, angle: f64) -> [u64; 2] {
        let top = Collider::rectangle(0, w, 1.0, 1.0).expect("a box");
        let bottom = Collider::rectangle(1, floor, 1.0, 1.0).expect("a box");
        let pa = Pose::new(DVec2::new(x, 0.501), angle);
        let pb = Pose::new(DVec2::new(0.0, -0.5), 0.0);
        let c = contact(&top, &pa, &bottom, &pb, 0.1, 0.01).expect("touching");
        assert_eq!(c.count, 2, "a face on a face touches at two points");
        c.ids
    }

    #[test]
    fn the_two_points_of_a_box_on_a_box_have_keys_of_their_own_that_last() {
        // A narrow box on a wide floor (both ends the top box's corners), a wide box
        // on a narrow pillar (both the pillar's), and a box half over the edge of
        // another (one corner of each).
        for (w, floor, x) in [(1.0, 10.0, 0.3), (3.0, 1.0, 0.0), (1.0, 1.0, 0.6)] {
            let still = ids(w, floor, x, 0.0);
            assert_ne!(still[0], still[1], "{w} on {floor} at {x}: {still:x?}");
            // A box that settles by a little keeps its keys, so the warm start finds
            // them.
            let moved = ids(w, floor, x + 1e-3, 1e-4);
            assert_eq!(still, moved, "{w} on {floor} at {x}");
        }
    }

    #[test]
    fn a_box_on_another_face_has_other_keys() {
        // A 3 × 2 box on a pillar 1 wide touches at the pillar's two corners whichever
        // face it lies on; its face must tell the keys apart, so that a box tipped
        // onto another face does not start from the impulses of the one before.
        let top = Collider::rectangle(0, 3.0, 2.0, 1.0).expect("a box");
        let pillar = Collider::rectangle(1, 1.0, 1.0, 1.0).expect("a box");
        let pb = Pose::new(DVec2::new(0.0, -0.5), 0.0);
        let keys = |angle: f64, half: f64| {
            let pa = Pose::new(DVec2::new(0.0, half + 1e-3), angle);
            let c = contact(&top, &pa, &pillar, &pb, 0.1, 0.01).expect("touching");
            assert_eq!(c.count, 2);
            c.ids
        };
        let quarter = std::f64::consts::FRAC_PI_2;
        let all = [
            keys(0.0, 1.0),
            keys(quarter, 1.5),
            keys(2.0 * quarter, 1.0),
            keys(-quarter, 1.5),
        ];
        for (a, ka) in all.iter().enumerate() {
            for kb in &all[a + 1..] {
                assert!(ka.iter().all(|k| !kb.contains(k)), "{ka:x?} and {kb:x?}");
            }
        }
    }
}

#[cfg(test)]
pub(super) mod workspace_tests {
    use super::*;

    /// Returns the next of a fixed sequence of numbers in [0, 1), from the state s:
    /// s ← 6364136223846793005·s + 1442695040888963407 (mod 2⁶⁴), its top 53 bits / 2⁵³.
    pub(in crate::sim::contacts) fn next(s: &mut u64) -> f64 {
        *s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*s >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Returns parry's polygon of a collider.
    fn polygon(c: &Collider) -> &ConvexPolygon {
        match &c.shape {
            ColliderShape::Convex { shape, .. } => shape,
            ColliderShape::Disc { .. } => panic!("a polygon"),
        }
    }

    #[test]
    fn the_separation_answers_to_the_bit_as_parry_does() {
        // A triangle, a pentagon and a box (as a polygon), in every pair, at poses that
        // overlap (EPA), touch, or lie apart (GJK alone).
        let shapes = [
            Collider::polygon(
                0,
                vec![
                    DVec2::new(-0.5, -0.3),
                    DVec2::new(0.6, -0.2),
                    DVec2::new(0.0, 0.7),
                ],
                1.0,
            )
            .expect("convex"),
            Collider::polygon(
                1,
                (0..5)
                    .map(|k| {
                        let t = 2.0 * std::f64::consts::PI * f64::from(k) / 5.0;
                        DVec2::new(0.8 * t.cos(), 0.6 * t.sin())
                    })
                    .collect(),
                1.0,
            )
            .expect("convex"),
            Collider::polygon(
                2,
                vec![
                    DVec2::new(-1.0, -0.25),
                    DVec2::new(1.0, -0.25),
                    DVec2::new(1.0, 0.25),
                    DVec2::new(-1.0, 0.25),
                ],
                1.0,
            )
            .expect("convex"),
        ];
        let mut s = 7u64;
        let mut overlapping = 0;
        for _ in 0..4000 {
            let a = &shapes[(next(&mut s) * 3.0) as usize];
            let b = &shapes[(next(&mut s) * 3.0) as usize];
            let pa = Pose::new(DVec2::new(next(&mut s), next(&mut s)), 7.0 * next(&mut s));
            let pb = Pose::new(
                DVec2::new(3.0 * next(&mut s) - 1.0, 3.0 * next(&mut s) - 1.0),
                7.0 * next(&mut s),
            );
            // The separation, against parry's own query.
            let ours = separation(a, &pa, b, &pb).expect("two polygons");
            let theirs = query::contact(
                &pa.to_parry(),
                polygon(a),
                &pb.to_parry(),
                polygon(b),
                f64::MAX,
            )
            .expect("supported")
            .expect("within reach");
            assert_eq!(ours.gap.to_bits(), theirs.dist.to_bits());
            let point = 0.5 * (from_parry(theirs.point1) + from_parry(theirs.point2));
            let bits = |v: DVec2| [v.x.to_bits(), v.y.to_bits()];
            assert_eq!(bits(ours.point), bits(point));
            assert_eq!(bits(ours.normal), bits(-from_parry(theirs.normal1)));
            overlapping += usize::from(ours.gap < 0.0);
        }
        // Both GJK alone and EPA were asked.
        assert!(overlapping > 100 && overlapping < 3900, "{overlapping}");
    }
}

#[cfg(test)]
mod disc_box_tests;
