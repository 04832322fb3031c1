//! A disc against a box, asked of parry's box (whose point projection is a closed form)
//! and of the same box as a polygon (GJK's): the narrow phase's two ways agree.

use glam::DVec2;

use super::workspace_tests::next;
use super::{contact, separation, Pose};
use crate::sim::contacts::collider::Collider;
use crate::sim::rigid::rotate;

#[test]
fn a_disc_meets_a_box_as_it_meets_the_same_box_as_a_polygon() {
    // A 0.6 × 0.2 box as parry's box (its projection a closed form) and as a
    // polygon of its four corners (GJK's, and EPA's inside it), and a disc of
    // radius 0.1 about it, apart, touching, overlapping, its centre inside: the
    // contacts and separations agree to round-off of the box's size, and where the
    // disc's centre is nearly as close to two sides (a corner's diagonal, the
    // middle inside), the sides' distances within 1e-9 of each other, either is
    // right and the normals are not compared.
    let (w, h) = (0.6, 0.2);
    let boxed = Collider::rectangle(0, w, h, 1.0).expect("a box");
    let corners = vec![
        DVec2::new(-0.5 * w, -0.5 * h),
        DVec2::new(0.5 * w, -0.5 * h),
        DVec2::new(0.5 * w, 0.5 * h),
        DVec2::new(-0.5 * w, 0.5 * h),
    ];
    let polygon = Collider::polygon(0, corners, 1.0).expect("convex");
    let disc = Collider::disc(1, 0.1, 1.0);
    let (mut s, mut compared, mut inside) = (7u64, 0, 0);
    let (mut worst_gap, mut worst_normal, mut worst_point) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..4000 {
        let pb = Pose::new(
            DVec2::new(4.0 * next(&mut s) - 2.0, 4.0 * next(&mut s) - 2.0),
            8.0 * next(&mut s),
        );
        // The disc's centre in the box's frame, within 0.5 of it.
        let local = DVec2::new(
            (w + 1.0) * (next(&mut s) - 0.5),
            (h + 1.0) * (next(&mut s) - 0.5),
        );
        let pd = Pose::new(pb.r + rotate(pb.sin_cos, local), 0.0);
        let sides = [
            0.5 * w - local.x,
            0.5 * w + local.x,
            0.5 * h - local.y,
            0.5 * h + local.y,
        ];
        let mut sorted = sides;
        sorted.sort_by(f64::total_cmp);
        let outside = sorted[0] < 0.0;
        let tie = if outside {
            // Beyond a corner's diagonal: both coordinates past the box.
            (local.x.abs() - 0.5 * w - (local.y.abs() - 0.5 * h)).abs() < 1e-9
        } else {
            sorted[1] - sorted[0] < 1e-9
        };
        inside += usize::from(!outside);
        let pairs = [
            (
                contact(&boxed, &pb, &disc, &pd, 0.2, 1e-6),
                contact(&polygon, &pb, &disc, &pd, 0.2, 1e-6),
            ),
            (
                contact(&disc, &pd, &boxed, &pb, 0.2, 1e-6),
                contact(&disc, &pd, &polygon, &pb, 0.2, 1e-6),
            ),
            (
                separation(&boxed, &pb, &disc, &pd),
                separation(&polygon, &pb, &disc, &pd),
            ),
            (
                separation(&disc, &pd, &boxed, &pb),
                separation(&disc, &pd, &polygon, &pb),
            ),
        ];
        for (by_box, by_polygon) in pairs {
            match (by_box, by_polygon) {
                (Some(b), Some(p)) => {
                    compared += 1;
                    worst_gap = worst_gap.max((b.gap - p.gap).abs());
                    worst_point = worst_point.max((b.point - p.point).length());
                    if !tie {
                        worst_normal = worst_normal.max((b.normal - p.normal).length());
                    }
                }
                (None, None) => {}
                (b, p) => assert!(
                    // Only at the prediction's edge may one answer and not the other.
                    b.or(p).is_some_and(|c| (c.gap - 0.2).abs() < 1e-12),
                    "{b:?} against {p:?} at {local}"
                ),
            }
        }
    }
    assert!(
        compared > 8000 && inside > 100,
        "{compared} compared, {inside} inside"
    );
    // Measured: gaps 1.1e-16 apart (one unit in the last place of 0.6), points
    // 3.0e-14 and normals 6.0e-13 (GJK's projection stops within its own epsilon).
    // The bounds are a hundred times that or more, and a millionth of the contact
    // tolerance (1e-6 of the box's size) or less.
    assert!(worst_gap <= 1e-14, "gaps differ by {worst_gap:e}");
    assert!(worst_point <= 1e-12, "points differ by {worst_point:e}");
    assert!(worst_normal <= 1e-10, "normals differ by {worst_normal:e}");
}

#[test]
fn a_disc_on_each_side_of_a_box_has_a_key_of_its_own_that_lasts() {
    // A disc resting 1e-4 into each of a turned 1 × 0.5 box's four sides: each side
    // gives the contact a key of its own, and a disc that rolls on by a little keeps
    // its key, so that the warm start finds it. (parry's box–box manifolds name a box's
    // sides from its corners' bit patterns, alike for all four corners of this box,
    // whose half sides' mantissas are zero; see `box_features.rs`. Its point
    // projection names them by axis and sign.)
    let (w, h) = (1.0, 0.5);
    let boxed = Collider::rectangle(0, w, h, 1.0).expect("a box");
    let disc = Collider::disc(1, 0.1, 1.0);
    let pb = Pose::new(DVec2::new(0.3, -0.2), 0.4);
    let key = |side: DVec2, along: f64| {
        let half = DVec2::new(0.5 * w, 0.5 * h);
        let local = side * (half.dot(side.abs()) + 0.1 - 1e-4) + side.perp() * along;
        let pd = Pose::new(pb.r + rotate(pb.sin_cos, local), 0.0);
        let c = contact(&boxed, &pb, &disc, &pd, 0.01, 1e-6).expect("touching");
        assert_eq!(c.count, 1);
        c.ids[0]
    };
    let sides = [DVec2::X, -DVec2::X, DVec2::Y, -DVec2::Y];
    let keys: Vec<u64> = sides.iter().map(|&n| key(n, 0.01)).collect();
    for (k, &n) in sides.iter().enumerate() {
        assert_eq!(keys[k], key(n, 0.02), "side {n}");
        assert!(!keys[k + 1..].contains(&keys[k]), "{keys:x?}");
    }
}
