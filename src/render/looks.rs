//! Looks: bodies that are drawn alike share one prepared look, whatever their order.
//!
//! A look is everything about how a body is drawn that does not change during the run:
//! its shape (turned once by its angle when it never turns), colour and arrows. Bodies
//! are grouped by that key, not by standing next to each other in the file, so the
//! default colour cycle, which gives neighbours different colours, still leaves ten
//! looks for a thousand bodies. Looks are numbered in the order of their first body, so
//! the grouping never depends on a hash map's order.
//!
//! A sprite's coverage depends only on the geometry (the shape and its fixed angle),
//! not on the colour, so it is keyed by geometry alone: looks that differ only in
//! colour stamp the same coverage in their own inks, and a geometry is stamped once
//! [`SPRITE_MIN_BODIES`] bodies share it, whatever their colours. The same holds for
//! the sprites of turning convex looks at angle bins ([`super::turning`]).

use std::collections::HashMap;
use std::sync::Arc;

use super::bodies::BodyLook;
use super::camera::Camera;
use super::sprite::{SpriteCoverage, SpriteSheet};
use super::turning::{TurningCoverage, TurningSheet};
use super::BodyDrawing;
use crate::scene::{Body, Shape};

/// How many bodies must share a small geometry before it is stamped from sprites
/// rather than drawn as a path: scenes of a few bodies are drawn exactly as their
/// paths.
pub const SPRITE_MIN_BODIES: usize = 16;

/// A look shared by one or more bodies, and its sprites when it is stamped.
pub struct Look {
    pub body: BodyLook,
    pub sprite: Option<SpriteSheet>,
    /// For a turning convex look, its sprites at angle bins.
    pub turning: Option<TurningSheet>,
}

/// The distinct looks of a scene's bodies, and the look of each body.
pub struct Looks {
    pub looks: Vec<Look>,
    /// The look of every body drawn, as an index into `looks`.
    pub look_of: Vec<u32>,
}

/// What makes two bodies' outlines the same in pixels: the shape's numbers, exactly,
/// and the angle it is prepared at (its own when it never turns, 0 when it turns).
#[derive(Clone, Debug, Hash, PartialEq, Eq)]
struct GeometryKey {
    shape: Vec<u64>,
    turns: bool,
    angle: u64,
}

/// What makes two bodies look the same: geometry, colour and arrows.
#[derive(Clone, Debug, Hash, PartialEq, Eq)]
struct LookKey {
    geometry: GeometryKey,
    color: [u8; 4],
    show_velocity: bool,
    show_force: bool,
}

impl GeometryKey {
    fn of(body: &Body) -> Self {
        let bits = |v: &mut Vec<u64>, x: f64| v.push(x.to_bits());
        let mut shape = Vec::new();
        match &body.shape {
            Shape::Circle { radius } => {
                shape.push(0);
                bits(&mut shape, *radius);
            }
            Shape::Box { width, height } => {
                shape.push(1);
                bits(&mut shape, *width);
                bits(&mut shape, *height);
            }
            Shape::Polygon { points } => {
                shape.push(2);
                for p in points {
                    bits(&mut shape, p.x);
                    bits(&mut shape, p.y);
                }
            }
            Shape::Points { points } => {
                shape.push(3);
                for p in points {
                    bits(&mut shape, p.mass);
                    bits(&mut shape, p.offset.x);
                    bits(&mut shape, p.offset.y);
                }
            }
        }
        GeometryKey {
            shape,
            turns: body.turns,
            angle: if body.turns { 0 } else { body.angle.to_bits() },
        }
    }
}

impl Looks {
    /// Groups the bodies shown into looks, and gives sprites to the small outline
    /// geometries that at least [`SPRITE_MIN_BODIES`] bodies share when `drawing`
    /// allows them.
    pub fn new(shown: &[Body], camera: &Camera, drawing: BodyDrawing) -> Self {
        let mut looks: Vec<Look> = Vec::new();
        let mut geometry_of: Vec<GeometryKey> = Vec::new();
        let mut index: HashMap<LookKey, u32> = HashMap::new();
        let mut users: HashMap<GeometryKey, usize> = HashMap::new();
        let mut look_of = Vec::with_capacity(shown.len());
        for b in shown {
            let geometry = GeometryKey::of(b);
            *users.entry(geometry.clone()).or_default() += 1;
            let key = LookKey {
                geometry,
                color: b.color.0,
                show_velocity: b.show_velocity,
                show_force: b.show_force,
            };
            let next = looks.len() as u32;
            let i = *index.entry(key.clone()).or_insert_with(|| {
                looks.push(Look {
                    body: BodyLook::new(b, camera),
                    sprite: None,
                    turning: None,
                });
                geometry_of.push(key.geometry);
                next
            });
            look_of.push(i);
        }
        if drawing == BodyDrawing::Sprites {
            // One coverage per geometry, rasterised for its first look and stamped in
            // each look's colours.
            let mut coverage: HashMap<&GeometryKey, Option<Arc<SpriteCoverage>>> = HashMap::new();
            let mut turning: HashMap<&GeometryKey, Option<Arc<TurningCoverage>>> = HashMap::new();
            for (look, geometry) in looks.iter_mut().zip(&geometry_of) {
                // A turning convex look that many bodies share is stamped at angle
                // bins.
                if look.body.turns_fast() && users[geometry] >= SPRITE_MIN_BODIES {
                    let sheet = turning
                        .entry(geometry)
                        .or_insert_with(|| TurningCoverage::new(&look.body));
                    look.turning = sheet
                        .as_ref()
                        .map(|c| TurningSheet::new(Arc::clone(c), &look.body));
                    continue;
                }
                // A turning look is stamped only when turning adds a line over the
                // same disc: a circle.
                let stamps = !look.body.turns() || look.body.turns_by_marker();
                if users[geometry] < SPRITE_MIN_BODIES || !look.body.is_outline() || !stamps {
                    continue;
                }
                let sheet = coverage
                    .entry(geometry)
                    .or_insert_with(|| SpriteSheet::coverage(&look.body));
                look.sprite = sheet
                    .as_ref()
                    .map(|c| SpriteSheet::with_coverage(Arc::clone(c), &look.body));
            }
        }
        Looks { looks, look_of }
    }
}
