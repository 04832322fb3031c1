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
use super::picture::PictureSheet;
use super::points::{PointSprites, TurningPoints};
use super::sprite::{SpriteCoverage, SpriteSheet, MAX_SPRITE_REACH, PHASES};
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
    /// For a turning look of straight edges (a box, a polygon), its sprites at angle
    /// bins; also for such a look that never turns, when many bodies share its shape
    /// at other angles.
    pub turning: Option<TurningSheet>,
    /// For a look that never turns but is stamped from `turning`, its fixed angle.
    pub fixed_angle: Option<f64>,
    /// For a body of point masses that never turns and that many bodies share, its
    /// picture at every phase ([`super::picture`]).
    pub picture: Option<Arc<PictureSheet>>,
    /// For a body of point masses that turns and that many bodies share, or that few
    /// share in a scene of many bodies of point masses, its layers drawn by the scan
    /// converter and sprites ([`super::points`]).
    pub points: Option<TurningPoints>,
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

/// Snaps a disc's radius in pixels to the nearest 1/[`PHASES`] of a pixel (at least
/// 0.5, the smallest radius drawn): an edge moves by at most 1/16 pixel, as much as
/// snapping the position does.
pub fn snap_radius(r: f32) -> f32 {
    let step = PHASES as f32;
    ((r * step).round() / step).max(0.5)
}

/// Rasterises the sprite of every snapped radius that [`Looks::new`] stamps discs
/// from: those of looks whose geometry fewer than [`SPRITE_MIN_BODIES`] bodies share,
/// in a scene of at least that many discs. The sheets are shared among the available
/// threads; each is rasterised on its own, so they do not depend on the threads.
fn snapped_sheets(
    looks: &[Look],
    users: &HashMap<GeometryKey, usize>,
    geometry_of: &[GeometryKey],
    discs: usize,
    threads: usize,
) -> HashMap<u32, Option<Arc<SpriteCoverage>>> {
    let mut wanted: Vec<BodyLook> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    if discs >= SPRITE_MIN_BODIES {
        for (look, geometry) in looks.iter().zip(geometry_of) {
            let body = &look.body;
            let stamps = !body.turns() || body.turns_by_marker();
            if users[geometry] >= SPRITE_MIN_BODIES || !body.is_outline() || !stamps {
                continue;
            }
            let Some(r) = body.circle_radius().map(snap_radius) else {
                continue;
            };
            if seen.insert(r.to_bits()) {
                if let Some(l) = body.with_radius(r) {
                    wanted.push(l);
                }
            }
        }
    }
    let threads = crate::threads::or_cores(threads).clamp(1, wanted.len().max(1));
    let per = wanted.len().div_ceil(threads).max(1);
    let sheets: Vec<Option<Arc<SpriteCoverage>>> = std::thread::scope(|scope| {
        let handles: Vec<_> = wanted
            .chunks(per)
            .map(|part| {
                scope.spawn(move || part.iter().map(SpriteSheet::coverage).collect::<Vec<_>>())
            })
            .collect();
        handles
            .into_iter()
            // Rasterising cannot panic short of a bug, and then the panic goes on.
            .flat_map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    wanted
        .iter()
        .zip(sheets)
        .filter_map(|(l, sheet)| Some((l.circle_radius()?.to_bits(), sheet)))
        .collect()
}

impl Looks {
    /// Groups the bodies shown into looks, and gives sprites to the small outline
    /// geometries that at least [`SPRITE_MIN_BODIES`] bodies share when `drawing`
    /// allows them.
    pub fn new(shown: &[Body], camera: &Camera, drawing: BodyDrawing) -> Self {
        Self::with_threads(shown, camera, drawing, 0)
    }

    /// Like [`Looks::new`], rasterising the sprites made ahead of the first frame on
    /// `threads` threads (0: one per core). The sprites do not depend on it.
    pub fn with_threads(
        shown: &[Body],
        camera: &Camera,
        drawing: BodyDrawing,
        threads: usize,
    ) -> Self {
        let mut looks: Vec<Look> = Vec::new();
        let mut geometry_of: Vec<GeometryKey> = Vec::new();
        let mut index: HashMap<LookKey, u32> = HashMap::new();
        let mut users: HashMap<GeometryKey, usize> = HashMap::new();
        // For each look of a box or polygon that never turns: the key its shape has
        // when it turns (angle 0), its look prepared so, and its own angle; and how
        // many bodies have each such shape, turning or at any fixed angle.
        let mut fixed_of: Vec<Option<(GeometryKey, f64)>> = Vec::new();
        let mut turned_looks: HashMap<GeometryKey, BodyLook> = HashMap::new();
        let mut shape_users: HashMap<GeometryKey, usize> = HashMap::new();
        let mut look_of = Vec::with_capacity(shown.len());
        let discs = shown
            .iter()
            .filter(|b| matches!(b.shape, Shape::Circle { .. }))
            .count();
        let point_bodies = shown
            .iter()
            .filter(|b| matches!(b.shape, Shape::Points { .. }))
            .count();
        for b in shown {
            let geometry = GeometryKey::of(b);
            *users.entry(geometry.clone()).or_default() += 1;
            let straight = matches!(b.shape, Shape::Box { .. } | Shape::Polygon { .. });
            let turned_key = straight.then(|| GeometryKey {
                turns: true,
                angle: 0,
                ..geometry.clone()
            });
            if let Some(k) = &turned_key {
                *shape_users.entry(k.clone()).or_default() += 1;
            }
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
                    fixed_angle: None,
                    picture: None,
                    points: None,
                });
                geometry_of.push(key.geometry);
                let fixed = turned_key.filter(|_| !b.turns).map(|k| {
                    turned_looks.entry(k.clone()).or_insert_with(|| {
                        let turning = Body {
                            turns: true,
                            angle: 0.0,
                            ..b.clone()
                        };
                        BodyLook::new(&turning, camera)
                    });
                    (k, b.angle)
                });
                fixed_of.push(fixed);
                next
            });
            look_of.push(i);
        }
        if drawing == BodyDrawing::Sprites {
            // One coverage per geometry, rasterised for its first look and stamped in
            // each look's colours.
            let mut coverage: HashMap<&GeometryKey, Option<Arc<SpriteCoverage>>> = HashMap::new();
            let mut turning: HashMap<GeometryKey, Option<Arc<TurningCoverage>>> = HashMap::new();
            // Sprites of snapped radii, keyed by the radius's bits, rasterised on every
            // core at once: a scene of discs of many sizes has dozens.
            let mut snapped = snapped_sheets(&looks, &users, &geometry_of, discs, threads);
            let mut point_sprites = PointSprites::default();
            for ((look, geometry), fixed) in looks.iter_mut().zip(&geometry_of).zip(&fixed_of) {
                // A turning look of straight edges that many bodies share is stamped
                // at angle bins.
                let scanned = look.body.turns_fast() || look.body.turns_general();
                if scanned && users[geometry] >= SPRITE_MIN_BODIES {
                    let sheet = turning
                        .entry(geometry.clone())
                        .or_insert_with(|| TurningCoverage::new(&look.body));
                    look.turning = sheet
                        .as_ref()
                        .map(|c| TurningSheet::new(Arc::clone(c), &look.body));
                    continue;
                }
                // A box or polygon look that never turns and that too few bodies share
                // for a sprite of its own, but whose shape many bodies have at other angles
                // (crates scattered at angles of their own), is stamped from the
                // turning shape's sprites at its fixed angle.
                if let Some((key, angle)) = fixed {
                    let shared = shape_users.get(key).copied().unwrap_or(0);
                    if users[geometry] < SPRITE_MIN_BODIES && shared >= SPRITE_MIN_BODIES {
                        let sheet = turning.entry(key.clone()).or_insert_with(|| {
                            turned_looks.get(key).and_then(TurningCoverage::new)
                        });
                        if let Some(c) = sheet {
                            look.turning = Some(TurningSheet::new(Arc::clone(c), &look.body));
                            look.fixed_angle = Some(*angle);
                            continue;
                        }
                    }
                }
                // A body of point masses whose geometry many bodies share is laid over
                // the frame as a picture in its colours when it never turns, and drawn
                // layer by layer by the scan converter and sprites when it does.
                // One that too few bodies share, in a scene of many bodies of point
                // masses, is drawn by layers with its discs' radii snapped.
                if look.body.has_points() {
                    if users[geometry] >= SPRITE_MIN_BODIES {
                        if look.body.turns() {
                            look.points = point_sprites.layers(&look.body, false);
                        } else {
                            look.picture = PictureSheet::new(&look.body, MAX_SPRITE_REACH);
                        }
                    } else if point_bodies >= SPRITE_MIN_BODIES {
                        look.points = point_sprites.layers(&look.body, true);
                    }
                    continue;
                }
                // A turning look is stamped only when turning adds a line over the
                // same disc: a circle.
                let stamps = !look.body.turns() || look.body.turns_by_marker();
                if !look.body.is_outline() || !stamps {
                    continue;
                }
                if users[geometry] < SPRITE_MIN_BODIES {
                    // In a scene of many discs, a disc whose radius too few bodies
                    // share is stamped from the sprite of its radius snapped to
                    // 1/PHASES pixel, which other discs of nearby radii share.
                    let radius = look
                        .body
                        .circle_radius()
                        .filter(|_| discs >= SPRITE_MIN_BODIES);
                    if let Some(r) = radius {
                        let sheet = snapped.entry(snap_radius(r).to_bits()).or_default();
                        look.sprite = sheet
                            .as_ref()
                            .map(|c| SpriteSheet::with_coverage(Arc::clone(c), &look.body));
                    }
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
        prepare_fixed_bins(&looks, threads);
        Looks { looks, look_of }
    }
}

/// Makes, on `threads` threads at once (0: one per core), the angle bins that the looks at fixed angles stamp.
/// Made at their first stamps, as a turning look's are, they were made one after the
/// other by the worker drawing the first frame, the other waiting on them: crates at
/// angles of their own take most of their shapes' bins, 64 sprites each, and
/// `crates-1000`'s first frame took 0.23 s, a third of its 301 frames' render.
fn prepare_fixed_bins(looks: &[Look], threads: usize) {
    let mut wanted: Vec<((usize, usize), &TurningSheet, f64)> = looks
        .iter()
        .filter_map(|l| {
            let (sheet, theta) = (l.turning.as_ref()?, l.fixed_angle?);
            Some((sheet.bin_of(theta), sheet, theta))
        })
        .collect();
    wanted.sort_by_key(|w| w.0);
    wanted.dedup_by_key(|w| w.0);
    let threads = crate::threads::or_cores(threads).clamp(1, wanted.len().max(1));
    if wanted.len() < 2 || threads == 1 {
        for (_, sheet, theta) in &wanted {
            sheet.prepare(*theta);
        }
        return;
    }
    // Every thread takes every threads-th bin, so that each has bins of every shape.
    std::thread::scope(|scope| {
        for first in 0..threads {
            let wanted = &wanted;
            scope.spawn(move || {
                for (_, sheet, theta) in wanted.iter().skip(first).step_by(threads) {
                    sheet.prepare(*theta);
                }
            });
        }
    });
}
