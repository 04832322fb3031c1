//! The names of two boxes' features in parry's box–box manifolds, by which the warm
//! start keys a contact's impulses from one step to the next. Its own file because it
//! works around one quirk of parry's boxes (see [`name_box_features`]), apart from the
//! narrow phase that asks for the manifolds. (A box against a disc needs no renaming:
//! parry names the box's sides and corners there by axis and sign.)

use parry2d_f64::query::ContactManifold;

/// Names the features of two boxes in a manifold of parry's box–box test: a vertex by
/// the signs of its coordinates (bit 0 for x < 0, bit 1 for y < 0, as parry means to),
/// a face by its outward normal (the manifold's normal in that box's frame: 0 for +x,
/// 1 for -x, 2 for +y, 3 for -y).
///
/// parry2d-f64 0.31 names a box's vertex by bits 31 and 30 of its coordinates' bit
/// patterns (`Cuboid::vertex_feature_id`), the sign bits of an `f32` but mantissa bits
/// of an `f64`; so the two vertices of a face often get the same id, and the two
/// points of a box resting on another then share one key in the warm start, each
/// starting from the other's impulses. The 20-row pyramid's solver then never
/// converged: each step's first sweep changed an impulse by a fifth of the largest.
/// Its face ids are built from those vertex ids, so a box's four faces could share
/// one, and a box tipping onto another face over another box's corners kept its keys.
/// The two points of a manifold are the ends of the overlap of two faces, each a
/// vertex of one box, so with vertices told apart no two share a key.
pub(super) fn name_box_features(m: &mut ContactManifold<(), ()>) {
    /// parry's `PackedFeatureId` headers of a vertex and a face, in the top two bits.
    const VERTEX: u32 = 0b01 << 30;
    const FACE: u32 = 0b11 << 30;
    const HEADER: u32 = 0b11 << 30;
    let face = |n: parry2d_f64::math::Vector| {
        if n.x.abs() >= n.y.abs() {
            FACE | u32::from(n.x < 0.0)
        } else {
            FACE | 2 | u32::from(n.y < 0.0)
        }
    };
    let (face1, face2) = (face(m.local_n1), face(m.local_n2));
    let name = |id: &mut u32, local: parry2d_f64::math::Vector, face: u32| match *id & HEADER {
        VERTEX => *id = VERTEX | u32::from(local.x < 0.0) | u32::from(local.y < 0.0) << 1,
        FACE => *id = face,
        _ => {}
    };
    for p in &mut m.points {
        name(&mut p.fid1.0, p.local_p1, face1);
        name(&mut p.fid2.0, p.local_p2, face2);
    }
}
