//! Parry's contact of two convex shapes by GJK, then EPA where they overlap, with one
//! EPA workspace a thread.
//!
//! `query::contact` makes a new EPA (its vertices, faces and heap) every time two shapes
//! overlap, and resting contacts overlap by their slop, so the impact searches'
//! separations spent 6% of a scene of resting polygons in the allocator
//! (`mixed-contacts-300`). The same steps, from parry's public functions, with a
//! workspace that parry clears at the start of each query, give the same bits
//! (`narrow_phase`'s tests hold [`support_maps_contact`] to `query::contact`).

use std::cell::RefCell;

use parry2d_f64::math::{Pose as ParryPose, Vector as ParryVector};
use parry2d_f64::query;
use parry2d_f64::query::epa::EPA;
use parry2d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry2d_f64::shape::SupportMap;

thread_local! {
    /// Each thread's expanding-polytope workspace, which parry clears at the start of
    /// every query: the same answers as a new one, without its allocations.
    static EPA_WORKSPACE: RefCell<EPA> = RefCell::new(EPA::new());
}

/// Returns what parry's `contact_support_map_support_map_with_params` returns for g2 at
/// `pos12` in g1's frame (GJK from the direction of g2's centre, then EPA when the
/// shapes overlap), but with this thread's EPA workspace instead of a new one.
fn gjk_epa(
    pos12: &ParryPose,
    g1: &dyn SupportMap,
    g2: &dyn SupportMap,
    prediction: f64,
) -> GJKResult {
    // GJK starts from the direction of g2's centre, or +x when the centres coincide.
    let dir = pos12.translation.try_normalize().unwrap_or(ParryVector::X);
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(pos12, g1, g2, dir));
    match gjk::closest_points(pos12, g1, g2, prediction, true, &mut simplex) {
        // Overlapping: the origin is inside the Minkowski difference, and EPA finds its
        // nearest boundary point; parry reports no contact when EPA fails.
        GJKResult::Intersection => EPA_WORKSPACE
            .with(|epa| epa.borrow_mut().closest_points(pos12, g1, g2, &simplex))
            .map(|(p1, p2_1, n1)| GJKResult::ClosestPoints(p1, p2_1, n1))
            .unwrap_or(GJKResult::NoIntersection(ParryVector::X)),
        other => other,
    }
}

/// Returns parry's contact between two support-mapped shapes g1 at `pos1` and g2 at
/// `pos2` when their distance is at most `prediction`, in world axes: to the bit what
/// `query::contact` returns for two polygons (parry's
/// `contact_support_map_support_map`), but with this thread's EPA workspace.
pub(super) fn support_maps_contact(
    pos1: &ParryPose,
    g1: &dyn SupportMap,
    pos2: &ParryPose,
    g2: &dyn SupportMap,
    prediction: f64,
) -> Option<query::Contact> {
    // The pose of g2 in g1's frame: pos12 = pos1⁻¹·pos2.
    let pos12 = pos1.inv_mul(pos2);
    let GJKResult::ClosestPoints(p1, p2_1, n1) = gjk_epa(&pos12, g1, g2, prediction) else {
        return None;
    };
    // The distance along the normal, d = (p2 - p1)·n1, in g1's frame; p2 in g2's own
    // frame is pos12⁻¹·p2, and the normal on g2 is R12⁻¹·(-n1).
    let dist = (p2_1 - p1).dot(n1);
    let p2 = pos12.inverse_transform_point(p2_1);
    let n2 = pos12.rotation.inverse() * -n1;
    let mut c = query::Contact::new(p1, p2, n1, n2, dist);
    // Back to world axes: each point and normal by its own shape's pose.
    c.transform_by_mut(pos1, pos2);
    Some(c)
}
