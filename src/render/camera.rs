//! The camera: world coordinates (f64, y up) to pixel coordinates (f32, y down).

use glam::DVec2;

use crate::scene::View;

/// Maps the world onto the image: p = anchor + (s_x·(x - o_x), -s_y·(y - o_y)), where o
/// is a world point that lands on the pixel `anchor`.
///
/// [`Camera::fit`] uses one scale for both axes, so world units are square on screen and
/// circles stay round. The whole requested view is always visible: the scale is the
/// largest that fits the view inside the image, s = min(W / view width, H / view height),
/// and the view's centre maps to the image's centre. When the view's aspect ratio differs
/// from the image's, the image shows more of the world along the axis with room to
/// spare, equally on both sides (like CSS `object-fit: contain`, without bars).
///
/// [`Camera::affine`] takes the transform of a chart's plot area, so that bodies, fields
/// and curves share one transform with the axes' ticks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Pixels per world unit along x and along y (both positive).
    scale: DVec2,
    /// The world point that maps to `anchor`.
    centre: DVec2,
    /// The pixel that `centre` maps to.
    anchor: DVec2,
    /// The image's size in pixels.
    size: DVec2,
}

impl Camera {
    /// Creates the camera that fits `view` into a `width` × `height` image.
    pub fn fit(view: View, width: u32, height: u32) -> Self {
        let size = DVec2::new(f64::from(width), f64::from(height));
        let s = view.fit_scale(width, height);
        Camera {
            scale: DVec2::splat(s),
            centre: 0.5 * (view.min + view.max),
            anchor: 0.5 * size,
            size,
        }
    }

    /// Creates the camera p_x = p0_x + (x - x0)·ppu_x, p_y = p0_y + (y - y0)·ppu_y from
    /// the coefficients `(v0, p0, ppu)` of each axis (ppu_y < 0: y points up), as
    /// [`super::plot::DataToPixel::linear_coefficients`] gives them.
    pub fn affine(x: (f64, f64, f64), y: (f64, f64, f64), width: u32, height: u32) -> Self {
        Camera {
            scale: DVec2::new(x.2, -y.2),
            centre: DVec2::new(x.0, y.0),
            anchor: DVec2::new(x.1, y.1),
            size: DVec2::new(f64::from(width), f64::from(height)),
        }
    }

    /// Returns the coefficients `(v0, p0, ppu)` of x and y, the inverse of
    /// [`Camera::affine`].
    pub fn coefficients(&self) -> ((f64, f64, f64), (f64, f64, f64)) {
        (
            (self.centre.x, self.anchor.x, self.scale.x),
            (self.centre.y, self.anchor.y, -self.scale.y),
        )
    }

    /// Returns pixels per world unit along x (the scale of both axes when units are
    /// square, as they are for world scenes).
    pub fn scale(&self) -> f64 {
        self.scale.x
    }

    /// Returns pixels per world unit along x and along y.
    pub fn scale_xy(&self) -> DVec2 {
        self.scale
    }

    /// Maps a world point to pixels: p = anchor + (s_x·(x - cx), -s_y·(y - cy)).
    #[inline]
    pub fn to_pixel(&self, world: DVec2) -> (f32, f32) {
        let (x, y) = self.to_pixel_f64(world);
        (x as f32, y as f32)
    }

    /// Maps a world point to pixels in f64, for geometry that is clipped before it is
    /// drawn.
    #[inline]
    pub fn to_pixel_f64(&self, world: DVec2) -> (f64, f64) {
        let d = world - self.centre;
        (
            self.anchor.x + self.scale.x * d.x,
            self.anchor.y - self.scale.y * d.y,
        )
    }

    /// Maps a world displacement in f64 pixels.
    #[inline]
    pub fn to_pixel_vector_f64(&self, world: DVec2) -> (f64, f64) {
        (self.scale.x * world.x, -self.scale.y * world.y)
    }

    /// Maps a world displacement (a vector, not a point) to pixels; y flips.
    #[inline]
    pub fn to_pixel_vector(&self, world: DVec2) -> (f32, f32) {
        let (x, y) = self.to_pixel_vector_f64(world);
        (x as f32, y as f32)
    }

    /// Maps a pixel back to the world.
    pub fn to_world(&self, x: f64, y: f64) -> DVec2 {
        DVec2::new(
            self.centre.x + (x - self.anchor.x) / self.scale.x,
            self.centre.y - (y - self.anchor.y) / self.scale.y,
        )
    }

    /// Returns the world rectangle the whole image shows (at least the view).
    pub fn visible(&self) -> View {
        View {
            min: self.to_world(0.0, self.size.y),
            max: self.to_world(self.size.x, 0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(x0: f64, y0: f64, x1: f64, y1: f64) -> View {
        View {
            min: DVec2::new(x0, y0),
            max: DVec2::new(x1, y1),
        }
    }

    #[test]
    fn a_view_of_the_image_aspect_fills_it_exactly() {
        let c = Camera::fit(view(-1.0, -3.0, 7.0, 3.0), 800, 600);
        assert_eq!(c.to_pixel(DVec2::new(-1.0, 3.0)), (0.0, 0.0));
        assert_eq!(c.to_pixel(DVec2::new(7.0, -3.0)), (800.0, 600.0));
        assert_eq!(c.scale(), 100.0);
    }

    #[test]
    fn a_wider_view_is_fitted_by_width_and_centred_vertically() {
        // 11 × 6 world units into 800 × 600: width limits, s = 800/11.
        let c = Camera::fit(view(-1.0, -3.0, 10.0, 3.0), 800, 600);
        let s = 800.0 / 11.0;
        assert!((c.scale() - s).abs() < 1e-12);
        let (x0, y_top) = c.to_pixel(DVec2::new(-1.0, 3.0));
        let (x1, y_bottom) = c.to_pixel(DVec2::new(10.0, -3.0));
        assert!((x0 - 0.0).abs() < 1e-4 && (x1 - 800.0).abs() < 1e-3);
        // The 6 units of height take 6·s pixels, centred in 600.
        let margin = (600.0 - 6.0 * s) / 2.0;
        assert!((y_top as f64 - margin).abs() < 1e-3);
        assert!((y_bottom as f64 - (600.0 - margin)).abs() < 1e-3);
        let visible = c.visible();
        assert!(visible.min.y < -3.0 && visible.max.y > 3.0);
    }

    #[test]
    fn world_units_are_square_on_screen() {
        let c = Camera::fit(view(0.0, 0.0, 100.0, 1.0), 640, 480);
        let (dx, dy) = c.to_pixel_vector(DVec2::new(1.0, 1.0));
        assert_eq!(dx, -dy);
    }

    #[test]
    fn an_affine_camera_round_trips_its_coefficients() {
        let x = (0.0, 60.0, 140.0);
        let y = (-0.5, 540.0, -150.0);
        let c = Camera::affine(x, y, 800, 600);
        assert_eq!(c.coefficients(), (x, y));
        assert_eq!(c.to_pixel_f64(DVec2::new(1.0, 0.5)), (200.0, 390.0));
        assert_eq!(c.scale_xy(), DVec2::new(140.0, 150.0));
    }
}
