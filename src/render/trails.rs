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
//! position to the next, each pixel covered by the distance d of its centre to the
//! segment, c = clamp(1.25 − d, 0, 1) ([`raster::cover_capsule`]); since a pixel keeps
//! its strongest segment, a trail of one colour is the stroke of its whole path by that
//! ramp, as springs' coils are drawn: a straight stretch gets the exact area a row or
//! a column crossed by it has inside it, and within a few hundredths of a pixel at
//! other angles. Until the eighteenth session of issue #16 each segment was a polygon
//! with chords for its round ends, filled by tiny-skia's sixteen samples a pixel: four
//! times the producer's cost for pixels a few levels apart (measured in
//! `tests/integration/every_scene.rs`).
//!
//! This is how trails look since issue #16: where a trail crosses itself or another,
//! the pixel shows one trail, not the two blended over each other as when each trail
//! was one translucent stroke drawn in body order, and a newer trail is drawn over an
//! older one.

use std::sync::{Arc, Mutex};

use glam::DVec2;
use tiny_skia::Pixmap;

use super::camera::Camera;
use super::clip::ClipRect;
use super::damage::TileMask;
use super::raster;
use super::raster::prefetch;
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
        // Each pixel holds its colour's index in 24 bits ([`pack`]).
        debug_assert!(inks.len() <= 1 << 24, "{} trail colours", inks.len());
        TrailStyle { inks, ink_of }
    }
}

/// What a worker keeps to draw frames with trails that it encodes against the frame
/// before ([`crate::render::fastpng::FrameCoder`]): its trail layer, the rectangles of
/// the bodies it last drew (its stamps' tiles, row by row), and the tiles where its
/// pixmap changed with the last frame ([`crate::render::Renderer::draw_trail_frame`]).
pub struct TrailFrame {
    pub(super) layer: Option<TrailLayer>,
    /// The rectangles of the bodies drawn over the layer in the last frame (whole when
    /// something else was drawn, or nothing is known).
    pub(super) bodies: super::Damage,
    /// The tiles of the stamps among them, marked row by row; meaningful only when
    /// `bodies` is not whole.
    pub(super) body_tiles: TileMask,
    /// The tiles of pixels where the last frame drawn may differ from the one before.
    pub(super) changed: TileMask,
    /// The render's shared rasterisation of the segments and this worker's number in
    /// it, for the layer.
    pub(super) shared: Option<(Arc<SharedTrails>, usize)>,
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
            body_tiles: TileMask::new(width, height),
            changed: TileMask::new(width, height),
            shared: None,
        }
    }

    /// Like [`TrailFrame::new`], for worker number `worker` of a render, whose layer
    /// takes its segments from `shared`, rasterised once for all the render's workers.
    pub fn sharing(width: u32, height: u32, shared: Arc<SharedTrails>, worker: usize) -> Self {
        TrailFrame {
            shared: Some((shared, worker)),
            ..Self::new(width, height)
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
    /// Each pixel's trail coverage so far and the trail colour that holds it
    /// ([`pack`]).
    held: Vec<u32>,
    /// How many frames of the history the layer holds.
    frames: usize,
    /// The tiles where `base` changed since [`TrailLayer::take_changed`] last took them
    /// (every tile, for a new or restarted layer).
    changed: TileMask,
    /// The render's shared rasterisation of the segments and this layer's worker
    /// number in it, when the layer takes its segments from there.
    shared: Option<(Arc<SharedTrails>, usize)>,
}

impl TrailLayer {
    /// Returns a layer without trails over `static_layer`.
    pub fn new(static_layer: &Pixmap) -> Self {
        let n = (static_layer.width() * static_layer.height()) as usize;
        TrailLayer {
            base: static_layer.clone(),
            held: vec![0; n],
            frames: 0,
            changed: TileMask::new(static_layer.width(), static_layer.height()),
            shared: None,
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
            self.held.fill(0);
            self.frames = 0;
            self.changed.set_whole();
        }
        let (width, height) = (self.base.width(), self.base.height());
        let target = history.len();
        if target == self.frames {
            return;
        }
        // The render's producer, or another worker, may have rasterised these frames
        // already: their pixels are copied, not rasterised again.
        if let Some((shared, worker)) = &self.shared {
            let frames =
                shared.pixels_for(self.frames, history, (style, camera, clip, static_layer));
            if let Some(frames) = frames {
                let base = self.base.data_mut();
                let mut rows = Rows::new(width);
                for pixels in &frames {
                    for &(p, rgba) in pixels.iter() {
                        let p = p as usize;
                        base[4 * p..4 * p + 4].copy_from_slice(&rgba);
                        let (x, y) = rows.of(p);
                        self.changed.mark(x, y);
                    }
                }
                self.frames = target;
                shared.reached(*worker, target);
                return;
            }
            // What this layer needs was forgotten (it started again, say): it goes on
            // on its own, from the static layer.
            self.shared = None;
            self.base.data_mut().copy_from_slice(static_layer.data());
            self.held.fill(0);
            self.frames = 0;
            self.changed.set_whole();
        }
        let mut previous: Option<&[DVec2]> = self
            .frames
            .checked_sub(1)
            .and_then(|k| history.get(k))
            .map(|p| &p[..]);
        for positions in history.iter_from(self.frames) {
            if let Some(before) = previous {
                let base = self.base.data_mut();
                let changed = &mut self.changed;
                let mut rows = Rows::new(width);
                rasterise_frame(
                    (style, camera, clip, static_layer),
                    (width, height),
                    (before, positions),
                    &mut self.held,
                    |p, rgba| {
                        base[4 * p..4 * p + 4].copy_from_slice(&rgba);
                        let (x, y) = rows.of(p);
                        changed.mark(x, y);
                    },
                );
            }
            previous = Some(positions);
            self.frames += 1;
        }
    }

    /// Takes this layer's segments from `shared`, rasterised once for all the workers
    /// of a render, as worker number `worker`; the layer stays the function of the
    /// history it is on its own.
    pub fn share(&mut self, shared: Arc<SharedTrails>, worker: usize) {
        self.shared = Some((shared, worker));
    }
}

/// The column and row of pixel indices in an image `width` pixels wide that mostly
/// come row after row, as a segment's do: the row of the last one is kept, so that a
/// row is found by a division once a row, not once a pixel.
struct Rows {
    width: usize,
    row: usize,
    start: usize,
}

impl Rows {
    fn new(width: u32) -> Self {
        Rows {
            width: (width as usize).max(1),
            row: 0,
            start: 0,
        }
    }

    /// Pixel `p`'s column and row.
    #[inline]
    fn of(&mut self, p: usize) -> (usize, usize) {
        if p < self.start || p >= self.start + self.width {
            self.row = p / self.width;
            self.start = self.row * self.width;
        }
        (p - self.start, self.row)
    }
}

/// What a frame's segments are drawn with: the trails' colours, the camera, the clip
/// and the static layer they blend over.
pub(super) type Drawing<'a> = (&'a TrailStyle, &'a Camera, &'a ClipRect, &'a Pixmap);

/// Rasterises the segments of one frame, from the positions `before` to `positions`,
/// body by body, into the coverage and owner of each pixel, and calls `put(p, rgba)`
/// for each pixel p whose trail changes, with its new colour: the static layer's with
/// the strongest segment's trail colour blended over it at its coverage. The strongest
/// segment holds a pixel; a newer one of another colour takes it when at least as
/// strong.
fn rasterise_frame(
    (style, camera, clip, static_layer): Drawing<'_>,
    (width, height): (u32, u32),
    (before, positions): (&[DVec2], &[DVec2]),
    held: &mut [u32],
    mut put: impl FnMut(usize, [u8; 4]),
) {
    let layer = static_layer.data();
    let (w, h) = (width as usize, height as usize);
    for (i, &ink) in style.ink_of.iter().enumerate() {
        // The pixels a segment reads are wherever its body is: cache misses, one for
        // the coverage and owner held and one for the static layer, each of a few
        // rows (a third of rasterising `trails-1000` waited on them). They are asked
        // for a few bodies ahead, around where the body is now.
        if let Some(ahead) = positions.get(i + PREFETCH_AHEAD) {
            let (x, y) = camera.to_pixel_f64(*ahead);
            if x >= 0.0 && y >= 1.0 && x < w as f64 && y < (h - 1) as f64 {
                let (x, y) = (x as usize, y as usize);
                for row in y - 1..=y + 1 {
                    let p = row * w + x;
                    prefetch(held, p);
                    prefetch(layer, 4 * p);
                }
            }
        }
        let (Some(a), Some(b)) = (before.get(i), positions.get(i)) else {
            continue;
        };
        let ends = clip.segment(camera.to_pixel_f64(*a), camera.to_pixel_f64(*b));
        let Some((a, b)) = ends else {
            continue;
        };
        let trail = style.inks[ink as usize];
        raster::cover_capsule((width, height), a, b, HALF_WIDTH, |p, c| {
            // The coverage held in the low byte, its colour above: a newer segment
            // takes the pixel when stronger, or as strong and of another colour.
            let now = held[p];
            let (coverage, owner) = ((now & 0xff) as u8, now >> 8);
            if c > coverage || (c == coverage && owner != ink) {
                held[p] = pack(c, ink);
                let k = 4 * p;
                let mut rgba = [layer[k], layer[k + 1], layer[k + 2], layer[k + 3]];
                trail.blend(&mut rgba, c);
                put(p, rgba);
            }
        });
    }
}

/// A pixel's trail as the rasterisation holds it: the strongest segment's coverage in
/// the low byte and its trail colour's index above, in one word so that a segment
/// reads one array where it was two (a colour index is below 2^24: a scene has at most
/// 10,000,000 bodies, and so as many trail colours at most).
#[inline]
fn pack(coverage: u8, owner: u32) -> u32 {
    owner << 8 | u32::from(coverage)
}

/// How many bodies ahead [`rasterise_frame`] asks for the pixels a segment will read.
const PREFETCH_AHEAD: usize = 4;

/// A frame's changed trail pixels: (pixel index, colour), in the order they changed.
type FramePixels = Arc<[(u32, [u8; 4])]>;

/// The trails of one render, rasterised once and shared by its workers.
///
/// Each worker keeps its own [`TrailLayer`], because each draws a different frame; on
/// its own, each rasterised every frame's segments, so that `n` workers did the work
/// `n` times over. Instead each frame's segments are rasterised here, once (by the
/// render's producer as it records the frame's positions, or else by the first worker
/// to need them), into one coverage and owner by the same rule as a layer on its own,
/// and the pixels they changed are kept; each worker copies those pixels into its
/// layer. A frame's pixels are kept until every worker has passed it.
///
/// Two locks: one over the rasterisation (the coverage and owner), held while a frame
/// is rasterised, and one over the frames' pixels, held only to add a frame or take
/// some. A worker whose frames are rasterised takes them without waiting for the
/// producer to finish the frame it is on (waiting on one lock for both cost the
/// workers of `trails-1000` a twentieth of their time).
pub struct SharedTrails {
    raster: Mutex<Raster>,
    kept: Mutex<Kept>,
}

/// The rasterisation: each pixel's strongest coverage so far and its owner ([`pack`]).
#[derive(Default)]
struct Raster {
    held: Vec<u32>,
    /// How many frames of the history are rasterised.
    frames: usize,
    /// How many pixels the last frame changed: the next frame's first guess.
    last_len: usize,
}

/// The changed pixels of the frames rasterised and not yet forgotten.
#[derive(Default)]
struct Kept {
    /// The changed pixels of frames `first..first + pixels.len()`.
    first: usize,
    pixels: std::collections::VecDeque<FramePixels>,
    /// How many frames each worker's layer holds.
    reached: Vec<usize>,
    /// The bytes of the kept pixels, and the most that are kept.
    bytes: usize,
    limit: usize,
}

/// The most bytes of frames' changed pixels [`SharedTrails`] keeps: 64 MiB, about 1600
/// frames of 1000 trails' segments at 1280 × 720.
pub const MAX_KEPT_BYTES: usize = 64 << 20;

/// Takes a lock whether or not another thread panicked while holding it: the data
/// behind these locks is whole after every step.
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl SharedTrails {
    /// Shared trails for a render of `workers` workers, numbered from 0: a frame's
    /// pixels are kept until each of them has passed it.
    pub fn new(workers: usize) -> Self {
        Self::keeping(workers, MAX_KEPT_BYTES)
    }

    /// Like [`SharedTrails::new`], keeping at most `bytes` of frames' pixels: past
    /// that the oldest are forgotten, and a worker that still needed them (one that
    /// has not drawn yet while the producer rasterised many frames ahead, as in a
    /// render resumed or sharded late) rasterises its layer on its own, as before
    /// sharing. The bytes of the frames do not depend on it.
    pub fn keeping(workers: usize, bytes: usize) -> Self {
        SharedTrails {
            raster: Mutex::new(Raster::default()),
            kept: Mutex::new(Kept {
                reached: vec![0; workers.max(1)],
                limit: bytes,
                ..Kept::default()
            }),
        }
    }

    /// Notes that `worker`'s layer holds `frames` frames, and forgets the pixels of
    /// the frames every worker has passed.
    fn reached(&self, worker: usize, frames: usize) {
        let mut k = lock(&self.kept);
        if let Some(r) = k.reached.get_mut(worker) {
            *r = frames;
        }
        let passed = k.reached.iter().copied().min().unwrap_or(0);
        while k.first < passed && !k.pixels.is_empty() {
            k.forget_oldest();
        }
    }

    /// Returns the changed pixels of frames `from..history.len()`, rasterising those
    /// not yet rasterised, or `None` when some were forgotten.
    fn pixels_for(
        &self,
        from: usize,
        history: &PointHistory,
        drawing: Drawing<'_>,
    ) -> Option<Vec<FramePixels>> {
        let end = history.len();
        {
            let k = lock(&self.kept);
            if from < k.first {
                return None;
            }
            if k.first + k.pixels.len() >= end {
                return Some(k.range(from, end));
            }
        }
        // Some frames are not rasterised yet: the producer may be on them, and this
        // waits for it (or does them).
        self.advance(history, drawing);
        let k = lock(&self.kept);
        // Rasterising may have forgotten the oldest frames to keep within the limit.
        (from >= k.first).then(|| k.range(from, end))
    }

    /// Rasterises the segments of the frames of `history` not yet rasterised, so that
    /// the workers find them done: the render's producer calls this as it records each
    /// frame's positions, off the workers' way.
    pub(super) fn advance(&self, history: &PointHistory, drawing: Drawing<'_>) {
        let mut r = lock(&self.raster);
        let (width, height) = (drawing.3.width(), drawing.3.height());
        let n = (width * height) as usize;
        if r.held.len() != n {
            r.held = vec![0; n];
        }
        while r.frames < history.len() {
            let frame = r.frames;
            let mut changed = Vec::with_capacity(r.last_len + r.last_len / 4);
            if let (Some(before), Some(positions)) = (
                frame.checked_sub(1).and_then(|j| history.get(j)),
                history.get(frame),
            ) {
                let held = &mut r.held;
                rasterise_frame(
                    drawing,
                    (width, height),
                    (before, positions),
                    held,
                    |p, rgba| changed.push((p as u32, rgba)),
                );
            }
            r.last_len = changed.len();
            r.frames += 1;
            // The kept frames' lock is taken for the push alone.
            lock(&self.kept).push(Arc::from(changed));
        }
    }
}

impl Kept {
    /// Keeps the next frame's pixels, forgetting the oldest past the limit.
    fn push(&mut self, pixels: FramePixels) {
        self.bytes += std::mem::size_of_val(&pixels[..]);
        self.pixels.push_back(pixels);
        while self.bytes > self.limit && !self.pixels.is_empty() {
            self.forget_oldest();
        }
    }

    /// The pixels of frames `from..end`, all kept.
    fn range(&self, from: usize, end: usize) -> Vec<FramePixels> {
        self.pixels
            .range(from - self.first..end - self.first)
            .cloned()
            .collect()
    }

    /// Forgets the pixels of the oldest frame kept.
    fn forget_oldest(&mut self) {
        if let Some(pixels) = self.pixels.pop_front() {
            self.bytes -= std::mem::size_of_val(&pixels[..]);
            self.first += 1;
        }
    }
}
