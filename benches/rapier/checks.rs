//! What the bench asks of each engine's result besides its speed: that the pyramid
//! stands, and that the pile stays in its bucket without discs passing into each other.

use glam::DVec2;
use physframes::scene::{Scene, Shape};

use crate::engines::Pose;

/// How far the moving bodies got from where they started.
#[derive(Clone, Copy, Debug, Default)]
pub struct Drift {
    /// The largest displacement of a centre of mass, in world units.
    pub moved: f64,
    /// The largest displacement as a fraction of that body's size (its shorter side).
    pub moved_of_size: f64,
    /// The largest turn, in radians.
    pub turned: f64,
}

impl Drift {
    /// Whether every body stayed within 1% of its size of its start and turned less
    /// than 0.01 rad: the test of `tests/integration/resting.rs` that a tower and a
    /// pyramid stand.
    pub fn stands(&self) -> bool {
        self.moved_of_size < 0.01 && self.turned < 0.01
    }
}

/// Returns how far the scene's moving bodies are at `poses` from where they were at
/// `from`.
pub fn drift(scene: &Scene, from: &[Pose], poses: &[Pose]) -> Drift {
    let mut d = Drift::default();
    for ((b, &(r0, angle0)), &(r, angle)) in scene.bodies.iter().zip(from).zip(poses) {
        if b.is_static {
            continue;
        }
        let size = match b.shape {
            Shape::Box { width, height } => width.min(height),
            Shape::Circle { radius } => 2.0 * radius,
            _ => panic!("the bench's scenes hold only circles and boxes"),
        };
        let moved = (r - r0).length();
        d.moved = d.moved.max(moved);
        d.moved_of_size = d.moved_of_size.max(moved / size);
        d.turned = d.turned.max((angle - angle0).abs());
    }
    d
}

/// The worst a pile of discs in a bucket was seen to do.
#[derive(Clone, Copy, Debug, Default)]
pub struct PileWorst {
    /// The most discs seen at one look with their centre outside the bucket (between
    /// the inner faces of its walls, above its bottom and below the walls' tops).
    pub escaped: usize,
    /// The deepest overlap of two discs, or of a disc and a wall, seen at any look.
    pub overlap: f64,
    /// The deepest overlap at the last look.
    pub last_overlap: f64,
    /// The highest disc centre at the last look: how deep the pile is.
    pub top: f64,
}

/// A bucket of three static boxes named `bottom`, `left` and `right`, and the discs in
/// it.
pub struct Bucket {
    walls: Vec<(DVec2, DVec2)>,
    inside: (DVec2, DVec2),
    discs: Vec<usize>,
    radius: f64,
}

impl Bucket {
    pub fn new(scene: &Scene) -> Self {
        let aabb = |name: &str| {
            let b = scene
                .bodies
                .iter()
                .find(|b| b.name == name)
                .expect("the bucket's walls are named bottom, left and right");
            let Shape::Box { width, height } = b.shape else {
                panic!("a wall is a box");
            };
            let half = 0.5 * DVec2::new(width, height);
            (b.position - half, b.position + half)
        };
        let (bottom, left, right) = (aabb("bottom"), aabb("left"), aabb("right"));
        let discs: Vec<usize> = (0..scene.bodies.len())
            .filter(|&i| !scene.bodies[i].is_static)
            .collect();
        let radius = match scene.bodies[discs[0]].shape {
            Shape::Circle { radius } => radius,
            _ => panic!("the pile is of discs"),
        };
        Bucket {
            walls: vec![bottom, left, right],
            inside: (
                DVec2::new(left.1.x, bottom.1.y),
                DVec2::new(right.0.x, left.1.y.min(right.1.y)),
            ),
            discs,
            radius,
        }
    }

    /// Looks at the pile at `poses` and folds what it sees into `worst`.
    pub fn look(&self, poses: &[Pose], worst: &mut PileWorst) {
        let r = self.radius;
        let (lo, hi) = self.inside;
        let mut centres: Vec<DVec2> = self.discs.iter().map(|&i| poses[i].0).collect();
        let escaped = centres
            .iter()
            .filter(|c| c.x < lo.x || c.x > hi.x || c.y < lo.y || c.y > hi.y)
            .count();
        worst.escaped = worst.escaped.max(escaped);
        worst.top = centres
            .iter()
            .map(|c| c.y)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut overlap = f64::NEG_INFINITY;
        // A disc against a wall: r minus the distance from its centre to the box, which
        // is negative inside the box.
        for c in &centres {
            for &(min, max) in &self.walls {
                let outside = (min - *c).max(*c - max);
                let distance = if outside.x > 0.0 || outside.y > 0.0 {
                    outside.max(DVec2::ZERO).length()
                } else {
                    outside.x.max(outside.y)
                };
                overlap = overlap.max(r - distance);
            }
        }
        // Two discs: sorted by x, each is compared with those less than 2r further on.
        centres.sort_unstable_by(|a, b| a.x.total_cmp(&b.x));
        for (k, a) in centres.iter().enumerate() {
            for b in &centres[k + 1..] {
                if b.x - a.x >= 2.0 * r {
                    break;
                }
                overlap = overlap.max(2.0 * r - (*b - *a).length());
            }
        }
        worst.overlap = worst.overlap.max(overlap);
        worst.last_overlap = overlap;
    }
}
