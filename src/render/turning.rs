//! Sprites of turning outlines: a small look of straight edges (convex, or a polygon
//! that is not) that many bodies share, rasterised once per angle bin and sub-pixel
//! phase, and stamped at each frame's angle, or at a body's fixed angle.
//!
//! A turning box drawn by the scan converter ([`super::raster`]) still costs a few
//! microseconds a frame, most of it walking its outline and stroke sub-row by sub-row.
//! Like [`super::sprite`] for looks that do not turn, a look that at least
//! [`super::SPRITE_MIN_BODIES`] turning bodies share, and that reaches at most
//! [`MAX_TURNING_REACH`] pixels from its centre, is instead rasterised for `N` angles
//! around the circle and [`TURN_PHASES`] × [`TURN_PHASES`] sub-pixel offsets, each
//! angle's sprites when a frame first needs them, and stamped.
//!
//! A stamp is the look at its angle rounded to the nearest bin and its position rounded
//! to 1/[`TURN_PHASES`] pixel, rasterised as [`super::bodies::BodyLook::draw_turned_fast`]
//! draws it. Rounding the position moves every point by at most 1/16 pixel along each
//! axis, as for the sprites of looks that do not turn, and `N` is chosen so that
//! rounding the angle moves the look's farthest point by at most 1/8 pixel (a finer
//! angle hardly helped; the position's rounding is what shows: with 1/4 pixel instead
//! of 1/8 the mean difference grew by half). `tests/integration/every_scene.rs`
//! measures the difference against tiny-skia's paths at the exact angle and position. The sprites of an angle depend
//! on nothing but the look and the angle, so whichever worker makes them, every frame
//! gets the same bytes.

use std::sync::{Arc, OnceLock};

use tiny_skia::{Color, Pixmap, Transform};

use super::bodies::BodyLook;
use super::sprite::{snap_to, Ink, Sprite};

/// Sub-pixel phases per axis of a turning sprite: positions are rounded to 1/8 pixel.
pub const TURN_PHASES: u32 = 8;

/// The largest look, as a radius in pixels, whose turns are stamped: the bins grow with
/// the radius, and so does each sprite.
pub const MAX_TURNING_REACH: f32 = 16.0;

/// A turning look's coverage at every angle bin and phase, made an angle at a time.
#[derive(Debug)]
pub struct TurningCoverage {
    /// The look at angle 0, drawn through the scan converter at each bin.
    look: BodyLook,
    /// Room around the centre in the pixmaps the sprites are cut from.
    pad: i32,
    /// For each angle bin, its sprites, phase by phase (row of phases after row).
    bins: Vec<OnceLock<Box<[Sprite]>>>,
}

/// A turning look's coverage stamped in its colours.
#[derive(Clone, Debug)]
pub struct TurningSheet {
    coverage: Arc<TurningCoverage>,
    fill: Ink,
    edge: Ink,
}

impl TurningCoverage {
    /// Prepares the sprites of a turning look of straight edges, or returns `None` when the look is
    /// not one or reaches farther than [`MAX_TURNING_REACH`].
    pub fn new(look: &BodyLook) -> Option<Arc<Self>> {
        if !look.turns_fast() && !look.turns_general() {
            return None;
        }
        let reach = look.reach();
        if reach.is_nan() || reach > MAX_TURNING_REACH {
            return None;
        }
        // Half a bin, π/N, turns the farthest point by reach·π/N ≤ 1/8 pixel.
        let n = (8.0 * std::f64::consts::PI * f64::from(reach))
            .ceil()
            .max(8.0) as usize;
        Some(Arc::new(TurningCoverage {
            look: look.clone(),
            pad: (reach + 3.0).ceil() as i32,
            bins: (0..n).map(|_| OnceLock::new()).collect(),
        }))
    }

    /// Returns the bin of an angle: the nearest of the N angles 2π·k/N.
    fn bin(&self, theta: f64) -> usize {
        let n = self.bins.len() as f64;
        let k = (theta / std::f64::consts::TAU * n).round();
        k.rem_euclid(n) as usize
    }

    /// Returns the sprite for `theta` at the phases of (x, y), with the whole pixel its
    /// top-left sits on.
    fn sprite(&self, x: f32, y: f32, theta: f64) -> (&Sprite, i64, i64) {
        let (ix, i) = snap_to(x, TURN_PHASES);
        let (iy, j) = snap_to(y, TURN_PHASES);
        let bin = self.bin(theta);
        let sprites = self.bins[bin].get_or_init(|| self.rasterise(bin));
        let sprite = &sprites[(j * TURN_PHASES + i) as usize];
        (sprite, ix + i64::from(sprite.dx), iy + i64::from(sprite.dy))
    }

    /// Rasterises the look at the angle of `bin` at every phase, as
    /// [`BodyLook::draw_turned_fast`] draws it.
    fn rasterise(&self, bin: usize) -> Box<[Sprite]> {
        let theta = std::f64::consts::TAU * bin as f64 / self.bins.len() as f64;
        let (s, c) = theta.sin_cos();
        let (s, c) = (s as f32, c as f32);
        let side = (2 * self.pad + 2) as u32;
        let mut sprites = Vec::with_capacity((TURN_PHASES * TURN_PHASES) as usize);
        for j in 0..TURN_PHASES {
            for i in 0..TURN_PHASES {
                let x = self.pad as f32 + i as f32 / TURN_PHASES as f32;
                let y = self.pad as f32 + j as f32 / TURN_PHASES as f32;
                // Opaque white over transparent black leaves the coverage in alpha.
                let blank = || Pixmap::new(side, side).expect("a sprite of a few pixels");
                let (mut fill, mut edge) = (blank(), blank());
                self.look.draw_fast_apart(
                    &mut fill,
                    &mut edge,
                    Transform::from_row(c, -s, s, c, x, y),
                    Ink::of(Color::WHITE),
                );
                sprites.push(Sprite::trimmed(&fill, &edge, -self.pad, -self.pad));
            }
        }
        sprites.into_boxed_slice()
    }
}

impl TurningSheet {
    /// Stamps `coverage`, made for a look of the same geometry as `look`, in `look`'s
    /// colours.
    pub fn new(coverage: Arc<TurningCoverage>, look: &BodyLook) -> Self {
        let (fill, edge) = look.colors();
        TurningSheet {
            coverage,
            fill: Ink::of(fill),
            edge: Ink::of(edge),
        }
    }

    /// Returns the pixels that [`TurningSheet::stamp`] at (x, y) and `theta` may change,
    /// columns x0..x1 and rows y0..y1, which may reach outside the pixmap.
    pub fn footprint(&self, x: f32, y: f32, theta: f64) -> (i64, i64, i64, i64) {
        let (sprite, x0, y0) = self.coverage.sprite(x, y, theta);
        (x0, y0, x0 + sprite.width as i64, y0 + sprite.height as i64)
    }

    /// Marks in `mask` the tiles of the pixels that [`TurningSheet::stamp`] at (x, y)
    /// and `theta` may change, row by row.
    pub fn mark_tiles(
        &self,
        mask: &mut crate::render::damage::TileMask,
        x: f32,
        y: f32,
        theta: f64,
    ) {
        let (sprite, x0, y0) = self.coverage.sprite(x, y, theta);
        sprite.mark_tiles(mask, x0, y0);
    }

    /// Asks for the cache lines of the sprite that [`TurningSheet::stamp`] at (x, y)
    /// and `theta` reads, when its angle's sprites are made (nothing otherwise: making
    /// them is the stamp's). A frame's bodies each take a sprite of their own angle,
    /// spread over the bins' memory, and a stamp otherwise waits for its coverage.
    pub fn prefetch(&self, x: f32, y: f32, theta: f64) {
        let (_, i) = snap_to(x, TURN_PHASES);
        let (_, j) = snap_to(y, TURN_PHASES);
        let Some(sprites) = self.coverage.bins[self.coverage.bin(theta)].get() else {
            return;
        };
        if let Some(sprite) = sprites.get((j * TURN_PHASES + i) as usize) {
            sprite.prefetch();
        }
    }

    /// Returns which sprites a stamp at angle `theta` takes: its coverage (by address)
    /// and angle bin, so that looks at fixed angles can share the making of them.
    pub fn bin_of(&self, theta: f64) -> (usize, usize) {
        (
            Arc::as_ptr(&self.coverage) as usize,
            self.coverage.bin(theta),
        )
    }

    /// Makes the sprites of the angle bin of `theta` now, if they are not made yet,
    /// rather than at the first stamp that needs them.
    pub fn prepare(&self, theta: f64) {
        let bin = self.coverage.bin(theta);
        self.coverage.bins[bin].get_or_init(|| self.coverage.rasterise(bin));
    }

    /// Stamps the look with its centre at pixel (x, y) turned by `theta`, both rounded
    /// as the module explains. Parts outside the pixmap are skipped.
    pub fn stamp(&self, pixmap: &mut Pixmap, x: f32, y: f32, theta: f64) {
        let (sprite, x0, y0) = self.coverage.sprite(x, y, theta);
        sprite.stamp(pixmap, x0, y0, self.fill, self.edge);
    }
}
