//! Trails, drawn segment by segment into a layer that each worker keeps, so that a late
//! frame costs no more than an early one.
//!
//! A trail is the path of a body's centre of mass through every frame so far. Drawn
//! whole at every frame, as one stroke through all its points, frame k costs k
//! segments a body, and a render of n frames n²/2: 1000 trails over 1201 frames spent
//! 20 times longer on the last hundred frames than on the first. Instead each worker
//! keeps a [`TrailLayer`], the static layer with the trails so far over it, and brings
//! it up to each frame it draws by adding only the segments since the last one it drew.
//!
//! So that the frame does not depend on which worker drew it, nor on which frames that
//! worker drew before, the layer after frame k is a function of frames 0 ..= k alone:
//! segments are added in order (frame by frame, and within a frame body by body), and
//! each pixel keeps the trail coverage c of the strongest segment that covered it and
//! that segment's trail colour, a newer segment of another colour taking the pixel when
//! it covers it at least as much. The pixel shown is the static layer's with that colour
//! (the body's colour at 55% opacity) blended over it at coverage c, as tiny-skia blends
//! a path. A segment is a line 1.5 pixels wide with round ends from one frame's
//! position to the next, filled by [`raster`] (its round ends cut into chords).
//!
//! This is how trails look since issue #16: where a trail crosses itself or another,
//! the pixel shows one trail, not the two blended over each other as when each trail
//! was one translucent stroke drawn in body order, and a newer trail is drawn over an
//! older one.

use glam::DVec2;
use tiny_skia::Pixmap;

use super::camera::Camera;
use super::clip::ClipRect;
use super::damage::TileMask;
use super::raster;
use super::sprite::Ink;
use crate::history::PointHistory;

/// Half the width of a trail, in pixels.
const HALF_WIDTH: f64 = 0.75;

/// The trails' colours, shared by every worker of a render.
#[derive(Clone, Debug)]
pub struct TrailStyle {
    /// The distinct trail colours.
    inks: Vec<Ink>,
    /// Each body's trail colour, as an index into `inks`, for the bodies drawn.
    ink_of: Vec<u32>,
}

impl TrailStyle {
    /// Takes each drawn body's trail colour; equal colours share an index, numbered in
    /// the order of their first body.
    pub fn new(colors: impl IntoIterator<Item = tiny_skia::Color>) -> Self {
        let mut inks = Vec::new();
        let mut index = std::collections::HashMap::new();
        let ink_of = colors
            .into_iter()
            .map(|c| {
                let u = c.to_color_u8();
                let key = [u.red(), u.green(), u.blue(), u.alpha()];
                *index.entry(key).or_insert_with(|| {
                    inks.push(Ink::of(c));
                    (inks.len() - 1) as u32
                })
            })
            .collect();
        TrailStyle { inks, ink_of }
    }
}

/// What a worker keeps to draw frames with trails that it encodes against the frame
/// before ([`crate::render::fastpng::FrameCoder`]): its trail layer, the rectangles of
/// the bodies it last drew, and the tiles where its pixmap changed with the last frame
/// ([`crate::render::Renderer::draw_trail_frame`]).
pub struct TrailFrame {
    pub(super) layer: Option<TrailLayer>,
    /// The rectangles of the bodies drawn over the layer in the last frame (whole when
    /// something else was drawn, or nothing is known).
    pub(super) bodies: super::Damage,
    /// The tiles of pixels where the last frame drawn may differ from the one before.
    pub(super) changed: TileMask,
}

impl TrailFrame {
    /// A worker's state before its first frame of `width` × `height`: nothing is known
    /// of its pixmap.
    pub fn new(width: u32, height: u32) -> Self {
        let mut bodies = super::Damage::unbounded();
        bodies.set_whole();
        TrailFrame {
            layer: None,
            bodies,
            changed: TileMask::new(width, height),
        }
    }

    /// The tiles of pixels where the last frame drawn may differ from the frame drawn
    /// before it into the same pixmap (every tile after the first frame).
    pub fn changed(&self) -> &TileMask {
        &self.changed
    }
}

/// A worker's layer of trails: the static layer with every trail so far over it.
#[derive(Clone)]
pub struct TrailLayer {
    /// What frames start from: the static layer with the trails over it.
    base: Pixmap,
    /// Each pixel's trail coverage so far, and the trail colour that holds it.
    coverage: Vec<u8>,
    owner: Vec<u32>,
    /// How many frames of the history the layer holds.
    frames: usize,
    /// The points of one segment's outline, reused.
    outline: Vec<raster::Point>,
    /// The tiles where `base` changed since [`TrailLayer::take_changed`] last took them
    /// (every tile, for a new or restarted layer).
    changed: TileMask,
}

impl TrailLayer {
    /// Returns a layer without trails over `static_layer`.
    pub fn new(static_layer: &Pixmap) -> Self {
        let n = (static_layer.width() * static_layer.height()) as usize;
        TrailLayer {
            base: static_layer.clone(),
            coverage: vec![0; n],
            owner: vec![0; n],
            frames: 0,
            outline: Vec::new(),
            changed: TileMask::new(static_layer.width(), static_layer.height()),
        }
    }

    /// Adds to `mask` the tiles where the layer changed since this was last called
    /// (every tile, the first time and after the layer started again), and forgets
    /// them.
    pub fn take_changed(&mut self, mask: &mut TileMask) {
        mask.add_mask(&self.changed);
        self.changed.clear();
    }

    /// Returns the static layer with the trails so far over it.
    pub fn base(&self) -> &Pixmap {
        &self.base
    }

    /// Brings the layer to the frames `history` holds: adds the segments from the last
    /// frame it holds to the last in `history`, or, for a history shorter than what the
    /// layer holds (another render, say), starts again from the static layer. The
    /// result depends only on the history, not on the steps it came in.
    pub fn advance(
        &mut self,
        style: &TrailStyle,
        camera: &Camera,
        clip: &ClipRect,
        static_layer: &Pixmap,
        history: &PointHistory,
    ) {
        if history.len() < self.frames {
            self.base.data_mut().copy_from_slice(static_layer.data());
            self.coverage.fill(0);
            self.owner.fill(0);
            self.frames = 0;
            self.changed.set_whole();
        }
        let (width, height) = (self.base.width(), self.base.height());
        let mut previous: Option<&[DVec2]> = self
            .frames
            .checked_sub(1)
            .and_then(|k| history.get(k))
            .map(|p| &p[..]);
        for positions in history.iter_from(self.frames) {
            if let Some(before) = previous {
                for (i, &ink) in style.ink_of.iter().enumerate() {
                    let (Some(a), Some(b)) = (before.get(i), positions.get(i)) else {
                        continue;
                    };
                    let ends = clip.segment(camera.to_pixel_f64(*a), camera.to_pixel_f64(*b));
                    let Some((a, b)) = ends else {
                        continue;
                    };
                    raster::capsule(a, b, HALF_WIDTH, &mut self.outline);
                    let (coverage, owner) = (&mut self.coverage, &mut self.owner);
                    let changed = &mut self.changed;
                    // The row of the last pixel marked: pixels come row after row, so
                    // a row is found by division once, not once a pixel.
                    let w = width as usize;
                    let (mut row, mut row_start) = (0, 0);
                    let (base, layer) = (self.base.data_mut(), static_layer.data());
                    let trail = style.inks[ink as usize];
                    raster::cover_convex(width, height, &self.outline, |p, c| {
                        // The strongest segment holds the pixel; a newer one of
                        // another colour takes it when at least as strong.
                        let held = coverage[p];
                        if c > held || (c == held && owner[p] != ink) {
                            coverage[p] = c;
                            owner[p] = ink;
                            let k = 4 * p;
                            base[k..k + 4].copy_from_slice(&layer[k..k + 4]);
                            trail.blend(&mut base[k..k + 4], c);
                            if p < row_start || p >= row_start + w {
                                row = p / w;
                                row_start = row * w;
                            }
                            changed.mark(p - row_start, row);
                        }
                    });
                }
            }
            previous = Some(positions);
            self.frames += 1;
        }
    }
}
