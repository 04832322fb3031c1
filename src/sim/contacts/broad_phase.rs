//! The broad phase: which pairs of bodies can touch within a step, so that 10,000
//! bodies test their neighbours and not 5·10^7 pairs.
//!
//! Each colliding body's *swept box* bounds it over the part of the step still to come:
//! the bounding boxes of its shape where its path starts and where it ends (a body that
//! does not turn sweeps exactly their union; one that turns is bounded by its reach
//! about its centre of mass at both ends), widened by the contact tolerance. A
//! bounding-volume hierarchy over the boxes (parry's `Bvh`, the tree under Rapier)
//! gives every pair whose boxes overlap; a body struck within the step asks the tree
//! again with its new box.

use glam::DVec2;
use parry2d_f64::bounding_volume::Aabb;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

use super::collider::{to_parry, Collider};
use super::toi::Path;

/// The tree of one step's swept boxes.
#[derive(Default)]
pub struct BroadPhase {
    boxes: Vec<Aabb>,
    tree: Bvh,
    workspace: BvhWorkspace,
}

impl BroadPhase {
    /// Builds the tree over the given swept boxes, one per collider, and writes every
    /// pair (i, j), i < j, whose boxes overlap into `pairs`, sorted; or returns false,
    /// with `pairs` incomplete, when there are more than `budget` such pairs.
    ///
    /// The tree is built once and then kept: each step moves its leaves to their new
    /// boxes, refits the nodes above them and lets parry improve the tree a little
    /// (Rapier's way), which costs far less than building it afresh; a change in the
    /// number of boxes builds it again.
    pub fn build(
        &mut self,
        boxes: impl Iterator<Item = Aabb>,
        pairs: &mut Vec<(u32, u32)>,
        budget: usize,
    ) -> bool {
        self.boxes.clear();
        self.boxes.extend(boxes);
        if self.tree.leaf_count() as usize != self.boxes.len() {
            self.tree = Bvh::from_leaves(BvhBuildStrategy::Binned, &self.boxes);
        } else {
            for (i, b) in self.boxes.iter().enumerate() {
                self.tree.insert_or_update_partially(*b, i as u32, 0.0);
            }
            self.tree.refit(&mut self.workspace);
            self.tree.optimize_incremental(&mut self.workspace);
        }
        pairs.clear();
        // The traversal cannot be stopped, but past the budget it only counts.
        let mut over = false;
        self.tree
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |i, j| {
                if pairs.len() < budget {
                    pairs.push((i.min(j), i.max(j)));
                } else {
                    over = true;
                }
            });
        pairs.sort_unstable();
        !over
    }

    /// Builds the tree over the given boxes, one per collider, without listing its
    /// pairs: for callers that ask collider by collider and may stop early.
    pub fn rebuild(&mut self, boxes: impl Iterator<Item = Aabb>) {
        self.boxes.clear();
        self.boxes.extend(boxes);
        self.tree = Bvh::from_leaves(BvhBuildStrategy::Binned, &self.boxes);
    }

    /// Returns collider `k`'s box as last built or moved.
    pub fn box_of(&self, k: usize) -> Aabb {
        self.boxes[k]
    }

    /// Moves collider `k`'s leaf to the box `b` (a body struck within the step sweeps
    /// less, or elsewhere), growing the nodes above it as far as they must still hold
    /// it, so that a query sees every collider's latest box. The nodes may stay larger
    /// than they need; the next step's refit makes them tight again.
    pub fn update(&mut self, k: usize, b: Aabb) {
        self.boxes[k] = b;
        self.tree.insert(b, k as u32);
    }

    /// Writes into `out` every collider whose latest swept box overlaps `query`.
    pub fn query(&self, query: &Aabb, out: &mut Vec<u32>) {
        out.clear();
        out.extend(self.tree.intersect_aabb(query));
    }
}

/// Returns the box that holds collider `c` along `path` from its start to the step's
/// end (λ = 1), widened by `margin`.
pub fn swept_box(c: &Collider, path: &Path, margin: f64) -> Aabb {
    let rest = 1.0 - path.lambda;
    let end = path.r + rest * path.dr;
    let (lo, hi) = if path.dangle == 0.0 {
        let sc = path.angle.sin_cos();
        let (lo0, hi0) = c.aabb(path.r, sc);
        let (lo1, hi1) = c.aabb(end, sc);
        (lo0.min(lo1), hi0.max(hi1))
    } else {
        // A turning body stays within its reach of its centre of mass.
        (path.r.min(end) - c.reach, path.r.max(end) + c.reach)
    };
    let m = DVec2::splat(margin);
    Aabb::new(to_parry(lo - m), to_parry(hi + m))
}
