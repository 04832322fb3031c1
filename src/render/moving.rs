//! What moves each frame: the bodies, in index order, each the fastest way its look
//! allows (a sprite, turning sprites, a picture, layers, the scan converter or
//! tiny-skia's paths), and their velocity and force arrows; each recording, when asked,
//! where it drew (rectangles, or tiles row by row) for the frame's damage.
//!
//! These are [`Renderer`]'s, in a file of their own: `mod.rs` holds the renderer and
//! the frame's passes in order (restore, trails, bodies, arrows, overlay).

use tiny_skia::{Color, Pixmap};

use super::arrows::{arrow_spans, draw_arrow, draw_arrow_path};
use super::damage::{Marking, TileMask};
use super::{raster, BodyDrawing, Damage, FrameView, Renderer, DAMAGE_MARGIN};

/// The width in pixels of the bodies' velocity and force arrows.
const ARROW_WIDTH: f32 = 2.0;

/// Where a trail frame's arrows mark the tiles of the pixels they may change: `frame`,
/// the tiles where the frame may differ from the worker's last (all else the frame drew
/// already marked), and `next`, the tiles the next frame must restore (the bodies'
/// already marked).
///
/// A mask with more than `limit` tiles marked stands for every tile: a frame that
/// marks more than a third of its tiles is compressed whole, its rows' bookkeeping
/// costing more than its tiles save (see [`Renderer::draw_trail_frame`]), and the next
/// frame, whose own mask holds `next`, will be too. So once either passes the limit it
/// is made whole and no longer marked, and once both have, the arrows left are drawn
/// unmarked: marking them would be lost work. (Marking every one of a thousand arrows
/// over trails, at the default scale, was a tenth of such a render: `perf`.) `next`
/// is marked on when `frame` is whole for other reasons, a new layer's first frame or
/// the last frame's arrows, so that a frame whose own arrows mark few tiles lets the
/// frame after it be coded by tiles.
pub(super) struct ArrowMarks<'a> {
    pub frame: &'a mut TileMask,
    pub next: &'a mut TileMask,
    pub limit: usize,
}

/// The colour of velocity arrows.
fn velocity_color() -> Color {
    Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff)
}

/// The colour of force arrows.
fn force_color() -> Color {
    Color::from_rgba8(0xc0, 0x39, 0x2b, 0xff)
}

impl Renderer {
    /// Draws the velocity and force arrows of the bodies that show them, marking, when
    /// `marks` are given, the tiles of the pixels each may change in both its masks
    /// (row by row, [`arrow_spans`]), until the frame's passes its limit.
    pub(super) fn draw_arrows(
        &self,
        frame: &FrameView<'_>,
        pixmap: &mut Pixmap,
        marks: Option<ArrowMarks<'_>>,
    ) {
        let size = (self.width, self.height);
        let mut marks = marks.map(|m| {
            (
                Marking::new(m.frame, m.limit),
                Marking::new(m.next, m.limit),
            )
        });
        for &i in &self.arrow_bodies {
            let i = i as usize;
            let look = &self.looks[self.look_of[i] as usize].body;
            let at = self.camera.to_pixel_f64(frame.pos[i]);
            let mut arrow = |d: (f64, f64), c: Color| {
                if let Some((this, next)) = &mut marks {
                    arrow_spans(size, at, d, ARROW_WIDTH, |y, x0, x1| {
                        this.span(x0, x1, y);
                        next.span(x0, x1, y);
                    });
                    this.check();
                    next.check();
                    if this.is_done() && next.is_done() {
                        marks = None;
                    }
                }
                self.arrow(pixmap, at, d, c);
            };
            if look.show_velocity {
                let d = self
                    .camera
                    .to_pixel_vector_f64(self.arrows.velocity * frame.vel[i]);
                arrow(d, velocity_color());
            }
            if let (true, Some(force)) = (look.show_force, frame.force) {
                let d = self
                    .camera
                    .to_pixel_vector_f64(self.arrows.force * force[i]);
                arrow(d, force_color());
            }
        }
    }

    /// Draws a body's arrow from pixel `at` along the pixel vector `d`, 2 pixels wide.
    fn arrow(&self, pixmap: &mut Pixmap, at: (f64, f64), d: (f64, f64), c: Color) {
        match self.drawing {
            BodyDrawing::Sprites => draw_arrow(pixmap, &self.clip, at, d, c, ARROW_WIDTH),
            BodyDrawing::Paths => draw_arrow_path(pixmap, &self.clip, at, d, c, ARROW_WIDTH),
        }
    }

    /// Draws the bodies in index order, adding to `damage`, when given, a rectangle
    /// around each body drawn; with `tiles` as well, a stamp marks its tiles there row
    /// by row instead of adding its rectangle.
    pub(super) fn draw_bodies(
        &self,
        frame: &FrameView<'_>,
        pixmap: &mut Pixmap,
        mut damage: Option<&mut Damage>,
        mut tiles: Option<&mut TileMask>,
    ) {
        for (i, (p, &look)) in frame.pos.iter().zip(&self.look_of).enumerate() {
            // The pixels of a body a few ahead, asked for now: the frame is larger
            // than the cache, and a stamp otherwise waits for each row it blends.
            // (Large bodies cost their drawing, not the wait: they are left alone.)
            if let (Some(q), Some(&ahead)) = (
                frame.pos.get(i + raster::AHEAD),
                self.look_of.get(i + raster::AHEAD),
            ) {
                let look = &self.looks[ahead as usize];
                let reach = look.body.reach() + 3.0;
                if reach <= raster::PREFETCH_REACH {
                    let (x, y) = self.camera.to_pixel(*q);
                    raster::prefetch_around(pixmap.data(), self.width, self.height, x, y, reach);
                    // And a turning stamp's sprite, one of many.
                    let angle = frame
                        .angle
                        .filter(|_| look.body.turns())
                        .map(|a| a[i + raster::AHEAD])
                        .or(look.fixed_angle);
                    if let (Some(sheet), Some(theta)) = (&look.turning, angle) {
                        sheet.prefetch(x, y, theta);
                    }
                }
            }
            if self.still.get(i) == Some(&true) {
                continue;
            }
            let look = &self.looks[look as usize];
            let (x, y) = self.camera.to_pixel(*p);
            // Bodies entirely outside the image are skipped, and so are positions
            // that are not finite.
            if look.body.is_outside(x, y, self.width, self.height) {
                continue;
            }
            // A body that turns is drawn at this frame's angle.
            let angle = frame
                .angle
                .filter(|_| look.body.turns())
                .map(|a| a[i])
                .or(look.fixed_angle);
            if let Some(damage) = damage.as_deref_mut().filter(|d| !d.is_whole()) {
                // A turning stamp changes exactly its sprite's rectangle.
                // With `tiles`, a stamp's tiles are marked row by row instead.
                if let (Some(sheet), Some(theta)) = (&look.turning, angle) {
                    match tiles.as_deref_mut() {
                        Some(tiles) => sheet.mark_tiles(tiles, x, y, theta),
                        None => {
                            damage.add_rect(sheet.footprint(x, y, theta), self.width, self.height)
                        }
                    }
                    sheet.stamp(pixmap, x, y, theta);
                    continue;
                }
                // So does a picture's.
                if let (Some(picture), None) = (&look.picture, angle) {
                    damage.add_rect(picture.footprint(x, y), self.width, self.height);
                    picture.stamp(pixmap, x, y);
                    continue;
                }
                match &look.sprite {
                    // A stamp changes exactly its sprite's rectangle.
                    Some(sprite) if angle.is_none() => match tiles.as_deref_mut() {
                        Some(tiles) => sprite.mark_tiles(tiles, x, y),
                        None => damage.add_rect(sprite.footprint(x, y), self.width, self.height),
                    },
                    // A turning circle's stamp, then its orientation line from the
                    // centre to the rim, in the box of its ends: row by row and that
                    // box, or the rectangle around both.
                    Some(sprite) if look.body.turns_by_marker() => {
                        let theta = angle.unwrap_or(0.0);
                        let line = look.body.orientation_box(x, y, theta);
                        let line = line.unwrap_or_else(|| sprite.footprint(x, y));
                        match tiles.as_deref_mut() {
                            Some(tiles) => {
                                sprite.mark_tiles(tiles, x, y);
                                damage.add_rect(line, self.width, self.height);
                            }
                            None => {
                                let s = sprite.footprint(x, y);
                                let both = (
                                    s.0.min(line.0),
                                    s.1.min(line.1),
                                    s.2.max(line.2),
                                    s.3.max(line.3),
                                );
                                damage.add_rect(both, self.width, self.height);
                            }
                        }
                    }
                    // A turning convex outline drawn by the scan converter lies in
                    // the box of its turned points, grown for its stroke and
                    // anti-aliasing; a pixel more is spare.
                    _ if angle.is_some() && self.turning_fast && look.body.turns_fast() => {
                        let theta = angle.unwrap_or(0.0);
                        let (ex, ey) = look.body.turned_extent(theta).unwrap_or((0.0, 0.0));
                        let (ex, ey) = (ex + 1.0, ey + 1.0);
                        damage.add_rect(
                            (
                                (x - ex).floor() as i64,
                                (y - ey).floor() as i64,
                                (x + ex).ceil() as i64 + 1,
                                (y + ey).ceil() as i64 + 1,
                            ),
                            self.width,
                            self.height,
                        )
                    }
                    // A look that never turns lies in its own box, grown for its
                    // stroke and rounded out to whole pixels (tiny-skia touches no
                    // pixel the shape misses), with a pixel to spare; a body of
                    // point masses in the box of its discs and marker. Everything
                    // drawn for another lies within its reach of (x, y), at any angle;
                    // the margin covers the outline's half-width and anti-aliasing (a
                    // sprite pads by 3 pixels) with a pixel to spare.
                    _ => match look
                        .body
                        .fixed_box()
                        .filter(|_| angle.is_none())
                        .or_else(|| look.body.points_box(angle))
                    {
                        Some([x0, y0, x1, y1]) => damage.add_rect(
                            (
                                (x + x0).floor() as i64,
                                (y + y0).floor() as i64,
                                (x + x1).ceil() as i64,
                                (y + y1).ceil() as i64,
                            ),
                            self.width,
                            self.height,
                        ),
                        None => damage.add_around(
                            x,
                            y,
                            look.body.reach() + DAMAGE_MARGIN,
                            self.width,
                            self.height,
                        ),
                    },
                }
            }
            if let (Some(sheet), Some(theta)) = (&look.turning, angle) {
                sheet.stamp(pixmap, x, y, theta);
                continue;
            }
            if let (Some(picture), None) = (&look.picture, angle) {
                picture.stamp(pixmap, x, y);
                continue;
            }
            if let Some(points) = &look.points {
                if points.draw(pixmap, x, y, angle) {
                    continue;
                }
            }
            match (&look.sprite, angle) {
                (Some(sprite), None) => sprite.stamp(pixmap, x, y),
                // Only a circle's look turns and keeps its sprite: the disc, then its
                // orientation line.
                (Some(sprite), Some(theta)) => {
                    sprite.stamp(pixmap, x, y);
                    look.body.draw_orientation_fast(pixmap, x, y, theta);
                }
                // A turning convex outline goes through the scan converter, when many
                // bodies do.
                (None, Some(theta)) if self.turning_fast => {
                    look.body.draw_turned_fast(pixmap, x, y, theta)
                }
                (None, Some(theta)) => look.body.draw_turned(pixmap, x, y, theta),
                (None, None) if self.fixed_fast => look.body.draw_fast(pixmap, x, y),
                (None, None) => look.body.draw(pixmap, x, y),
            }
        }
    }
}
