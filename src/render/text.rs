//! Text drawn from glyph outlines, with no system fonts.
//!
//! The only face is DejaVu Sans, compiled into the binary through the `dejavu` crate, so a
//! frame renders the same on every machine. A string becomes ONE `tiny_skia::Path`: each
//! glyph's TrueType outline (read by `ab_glyph`) is scaled, placed at its pen position with
//! kerning applied, and appended; the whole path is then filled anti-aliased with the
//! non-zero rule. All arithmetic is in `f32` in a fixed order, so the output is
//! byte-for-byte deterministic.
//!
//! Sizes are in pixels per em, like a CSS `font-size`: a 10 pt label at 100 dpi is
//! `10.0 * 100.0 / 72.0 ≈ 13.9` px. Positions are in pixmap pixels with y pointing down.
//! Rotation is counter-clockwise on screen in degrees, so `90.0` reads bottom to top, as a
//! y-axis title does.

use std::sync::OnceLock;

use ab_glyph::{Font as _, FontRef, GlyphId, OutlineCurve};
use tiny_skia::{Color, FillRule, Paint, Path, PathBuilder, Pixmap, Transform};

/// Horizontal placement of a string relative to its anchor point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum HAlign {
    /// The string starts at the anchor point.
    #[default]
    Left,
    /// The string is centred on the anchor point.
    Center,
    /// The string ends at the anchor point.
    Right,
}

/// Vertical placement of a string relative to its anchor point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum VAlign {
    /// The anchor point lies on the baseline.
    #[default]
    Baseline,
    /// The anchor point lies half a capital height above the baseline, so digits and
    /// capitals look centred on it (the right choice for y tick labels).
    Middle,
    /// The anchor point lies on the font's ascent line, above every glyph.
    Top,
    /// The anchor point lies on the font's descent line, below every glyph.
    Bottom,
}

/// Where a string sits relative to the point it is drawn at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Anchor {
    /// Horizontal placement.
    pub h: HAlign,
    /// Vertical placement.
    pub v: VAlign,
}

impl Anchor {
    /// Builds an anchor from its two parts.
    pub const fn new(h: HAlign, v: VAlign) -> Self {
        Self { h, v }
    }
}

/// The size of a string's layout box at one pixel size.
///
/// `ascent` and `descent` are the font's line metrics (both positive, measured up and down
/// from the baseline), not the ink of this particular string, so strings drawn on one
/// baseline share one box height. Every supported glyph's ink lies inside the box.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TextExtent {
    /// Advance width in pixels, kerning included.
    pub width: f32,
    /// Distance from the baseline up to the top of the box.
    pub ascent: f32,
    /// Distance from the baseline down to the bottom of the box.
    pub descent: f32,
}

impl TextExtent {
    /// Total height of the box, `ascent + descent`.
    pub fn height(&self) -> f32 {
        self.ascent + self.descent
    }
}

/// How to draw one string: size, colour, anchor and rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextStyle {
    /// Size in pixels per em.
    pub size_px: f32,
    /// Fill colour.
    pub color: Color,
    /// Where the string sits relative to the point it is drawn at.
    pub anchor: Anchor,
    /// Counter-clockwise rotation on screen, in degrees, about the anchor point.
    pub rotation_degrees: f32,
}

impl TextStyle {
    /// A left/baseline-anchored, unrotated style.
    pub fn new(size_px: f32, color: Color) -> Self {
        Self {
            size_px,
            color,
            anchor: Anchor::default(),
            rotation_degrees: 0.0,
        }
    }

    /// Returns this style with another anchor.
    pub fn anchor(mut self, h: HAlign, v: VAlign) -> Self {
        self.anchor = Anchor::new(h, v);
        self
    }

    /// Returns this style rotated counter-clockwise by `degrees`.
    pub fn rotated(mut self, degrees: f32) -> Self {
        self.rotation_degrees = degrees;
        self
    }
}

/// A scalable outline font with the metrics needed for layout.
pub struct Font {
    face: FontRef<'static>,
    units_per_em: f32,
    ascent: f32,
    descent: f32,
    cap_height: f32,
}

impl std::fmt::Debug for Font {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Font")
            .field("units_per_em", &self.units_per_em)
            .field("ascent", &self.ascent)
            .field("descent", &self.descent)
            .field("cap_height", &self.cap_height)
            .finish()
    }
}

/// The error returned when font bytes are not a usable TrueType/OpenType face.
#[derive(Debug, thiserror::Error)]
#[error("invalid font data: {0}")]
pub struct InvalidFont(String);

impl Font {
    /// DejaVu Sans, parsed once and shared by every thread.
    pub fn dejavu_sans() -> &'static Font {
        static FONT: OnceLock<Font> = OnceLock::new();
        FONT.get_or_init(|| {
            Font::from_static_bytes(dejavu::sans::regular())
                .expect("the DejaVu Sans bytes built into the binary are a valid font")
        })
    }

    /// Parses a font that lives for the whole program, such as one from `include_bytes!`.
    pub fn from_static_bytes(bytes: &'static [u8]) -> Result<Font, InvalidFont> {
        let face = FontRef::try_from_slice(bytes).map_err(|e| InvalidFont(e.to_string()))?;
        let units_per_em = face
            .units_per_em()
            .ok_or_else(|| InvalidFont("units per em out of range".to_owned()))?;
        let ascent = face.ascent_unscaled();
        let descent = -face.descent_unscaled();
        // The height of a flat capital stands in for the OS/2 cap height, which ab_glyph
        // does not expose.
        let cap_height = face
            .outline(face.glyph_id('H'))
            .map(|o| o.bounds.min.y.max(o.bounds.max.y))
            .unwrap_or(0.7 * units_per_em);
        Ok(Font {
            face,
            units_per_em,
            ascent,
            descent,
            cap_height,
        })
    }

    /// Returns true when the font has a glyph for `c` (rather than the "missing" box).
    pub fn has_glyph(&self, c: char) -> bool {
        self.face.glyph_id(c).0 != 0
    }

    /// Measures `text` at `size_px` pixels per em. The empty string is 0 wide.
    pub fn measure(&self, text: &str, size_px: f32) -> TextExtent {
        let scale = size_px / self.units_per_em;
        let mut width_units = 0.0f32;
        let mut previous: Option<GlyphId> = None;
        for c in text.chars() {
            let id = self.face.glyph_id(c);
            if let Some(p) = previous {
                width_units += self.face.kern_unscaled(p, id);
            }
            width_units += self.face.h_advance_unscaled(id);
            previous = Some(id);
        }
        TextExtent {
            width: width_units * scale,
            ascent: self.ascent * scale,
            descent: self.descent * scale,
        }
    }

    /// The ink of `text` above and below the baseline, in pixels: `(ascent, descent)`, both
    /// positive when the ink reaches that side, `(0, 0)` for a string with no ink. Tighter
    /// than [`Font::measure`], for layouts that pack labels closely.
    pub fn ink_extent(&self, text: &str, size_px: f32) -> (f32, f32) {
        let scale = size_px / self.units_per_em;
        let (mut top, mut bottom) = (0.0f32, 0.0f32);
        for c in text.chars() {
            if let Some(outline) = self.face.outline(self.face.glyph_id(c)) {
                // ab_glyph stores the unscaled box with `min.y` as the top (font y is up).
                let (y_top, y_bottom) = (outline.bounds.min.y, outline.bounds.max.y);
                top = top.max(y_top.max(y_bottom));
                bottom = bottom.max(-y_top.min(y_bottom));
            }
        }
        (top * scale, bottom * scale)
    }

    /// Height of a flat capital letter (and of the digits) above the baseline, in pixels.
    pub fn cap_height(&self, size_px: f32) -> f32 {
        self.cap_height * size_px / self.units_per_em
    }

    /// The outline of `text` as one path, in pixels, with the pen starting at the origin on
    /// the baseline and y pointing down. Returns `None` for a string with no ink (such as
    /// "" or " ").
    pub fn text_path(&self, text: &str, size_px: f32) -> Option<Path> {
        let scale = size_px / self.units_per_em;
        let mut builder = PathBuilder::new();
        let mut pen_units = 0.0f32;
        let mut previous: Option<GlyphId> = None;
        for c in text.chars() {
            let id = self.face.glyph_id(c);
            if let Some(p) = previous {
                pen_units += self.face.kern_unscaled(p, id);
            }
            if let Some(outline) = self.face.outline(id) {
                push_outline(&mut builder, &outline.curves, pen_units, scale);
            }
            pen_units += self.face.h_advance_unscaled(id);
            previous = Some(id);
        }
        builder.finish()
    }

    /// The transform that places a path from [`Font::text_path`] (or a box of `extent`) at
    /// `(x, y)` according to `style`'s anchor and rotation.
    pub fn placement(&self, extent: &TextExtent, x: f32, y: f32, style: &TextStyle) -> Transform {
        let dx = match style.anchor.h {
            HAlign::Left => 0.0,
            HAlign::Center => -0.5 * extent.width,
            HAlign::Right => -extent.width,
        };
        let dy = match style.anchor.v {
            VAlign::Baseline => 0.0,
            VAlign::Middle => 0.5 * self.cap_height(style.size_px),
            VAlign::Top => extent.ascent,
            VAlign::Bottom => -extent.descent,
        };
        Transform::from_translate(x, y)
            .pre_rotate(-style.rotation_degrees)
            .pre_translate(dx, dy)
    }

    /// Draws `text` at `(x, y)` into `pixmap`, anti-aliased.
    pub fn draw(&self, pixmap: &mut Pixmap, text: &str, x: f32, y: f32, style: &TextStyle) {
        let Some(path) = self.text_path(text, style.size_px) else {
            return;
        };
        let extent = self.measure(text, style.size_px);
        let transform = self.placement(&extent, x, y, style);
        let mut paint = Paint::default();
        paint.set_color(style.color);
        paint.anti_alias = true;
        pixmap.fill_path(&path, &paint, FillRule::Winding, transform, None);
    }
}

/// Appends one glyph's curves, in font units with y up, to `builder` in pixels with y down.
///
/// ab_glyph reports each curve with its start point and closes every contour with a line
/// back to its first point, so a new contour begins wherever a curve does not start at the
/// previous curve's end.
fn push_outline(builder: &mut PathBuilder, curves: &[OutlineCurve], pen_units: f32, scale: f32) {
    let map = |p: ab_glyph::Point| ((pen_units + p.x) * scale, -p.y * scale);
    let mut last: Option<ab_glyph::Point> = None;
    for curve in curves {
        let start = match curve {
            OutlineCurve::Line(a, _) | OutlineCurve::Quad(a, _, _) | OutlineCurve::Cubic(a, ..) => {
                *a
            }
        };
        if last != Some(start) {
            if last.is_some() {
                builder.close();
            }
            let (x, y) = map(start);
            builder.move_to(x, y);
        }
        let end = match curve {
            OutlineCurve::Line(_, b) => {
                let (x, y) = map(*b);
                builder.line_to(x, y);
                *b
            }
            OutlineCurve::Quad(_, c, b) => {
                let (cx, cy) = map(*c);
                let (x, y) = map(*b);
                builder.quad_to(cx, cy, x, y);
                *b
            }
            OutlineCurve::Cubic(_, c1, c2, b) => {
                let (c1x, c1y) = map(*c1);
                let (c2x, c2y) = map(*c2);
                let (x, y) = map(*b);
                builder.cubic_to(c1x, c1y, c2x, c2y, x, y);
                *b
            }
        };
        last = Some(end);
    }
    if last.is_some() {
        builder.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every character the figures and study plots print.
    const FIGURE_CHARS: &str = "AZaz09.,:;()[]+-=/ −²·ωΔ×≤⁰¹²³⁴⁵⁶⁷⁸⁹⁻";

    fn font() -> &'static Font {
        Font::dejavu_sans()
    }

    /// Returns the bounding box `(x0, y0, x1, y1)` of pixels that are not fully transparent.
    fn ink_box(pixmap: &Pixmap) -> Option<(u32, u32, u32, u32)> {
        let w = pixmap.width();
        let mut found: Option<(u32, u32, u32, u32)> = None;
        for (i, p) in pixmap.pixels().iter().enumerate() {
            if p.alpha() != 0 {
                let (x, y) = (i as u32 % w, i as u32 / w);
                found = Some(match found {
                    None => (x, y, x, y),
                    Some((a, b, c, d)) => (a.min(x), b.min(y), c.max(x), d.max(y)),
                });
            }
        }
        found
    }

    #[test]
    fn the_empty_string_is_zero_wide_and_draws_nothing() {
        let extent = font().measure("", 14.0);
        assert_eq!(extent.width, 0.0);
        assert!(extent.ascent > 0.0 && extent.descent > 0.0);
        let mut pixmap = Pixmap::new(20, 20).expect("a 20x20 pixmap");
        font().draw(
            &mut pixmap,
            "",
            5.0,
            15.0,
            &TextStyle::new(14.0, Color::BLACK),
        );
        assert_eq!(ink_box(&pixmap), None);
    }

    #[test]
    fn width_grows_in_proportion_to_size() {
        let small = font().measure("Energy E = ½mv²", 10.0).width;
        let large = font().measure("Energy E = ½mv²", 30.0).width;
        assert!(small > 0.0);
        assert!(
            (large / small - 3.0).abs() < 1e-5,
            "width ratio {} for a 3x size",
            large / small
        );
    }

    #[test]
    fn every_figure_character_has_a_glyph() {
        for c in FIGURE_CHARS.chars() {
            if c != ' ' {
                assert!(font().has_glyph(c), "DejaVu Sans lacks {c:?}");
            }
        }
    }

    #[test]
    fn kerning_narrows_a_kerned_pair() {
        // "AV" is kerned in DejaVu Sans, so the pair is narrower than its two letters apart.
        let pair = font().measure("AV", 100.0).width;
        let apart = font().measure("A", 100.0).width + font().measure("V", 100.0).width;
        assert!(pair < apart, "AV = {pair}, A + V = {apart}");
    }

    #[test]
    fn drawing_changes_pixels_only_inside_the_measured_box() {
        for (text, anchor) in [
            ("Δt = 0.01 s", Anchor::new(HAlign::Left, VAlign::Baseline)),
            (
                "ω² ≤ 10⁻⁶ × k·m",
                Anchor::new(HAlign::Center, VAlign::Middle),
            ),
            ("−2.5 (gjpqy)", Anchor::new(HAlign::Right, VAlign::Top)),
            ("ÅÉ|", Anchor::new(HAlign::Left, VAlign::Bottom)),
        ] {
            let size = 17.0;
            let (x, y) = (100.0, 50.0);
            let style = TextStyle {
                anchor,
                ..TextStyle::new(size, Color::BLACK)
            };
            let mut pixmap = Pixmap::new(200, 100).expect("a 200x100 pixmap");
            font().draw(&mut pixmap, text, x, y, &style);
            let extent = font().measure(text, size);
            let t = font().placement(&extent, x, y, &style);
            // The measured box, placed like the text, widened by one pixel of anti-aliasing.
            let (left, top) = (t.tx - 1.0, t.ty - extent.ascent - 1.0);
            let (right, bottom) = (t.tx + extent.width + 1.0, t.ty + extent.descent + 1.0);
            let (x0, y0, x1, y1) = ink_box(&pixmap).expect("the text has ink");
            assert!(
                x0 as f32 >= left
                    && y0 as f32 >= top
                    && (x1 + 1) as f32 <= right
                    && (y1 + 1) as f32 <= bottom,
                "{text:?}: ink ({x0},{y0})-({x1},{y1}) outside box ({left},{top})-({right},{bottom})"
            );
            // The ink should also fill most of the box's width, or the measure is too wide.
            assert!((x1 + 1 - x0) as f32 > 0.8 * extent.width, "{text:?}");
        }
    }

    #[test]
    fn a_quarter_turn_makes_text_read_upwards() {
        let mut pixmap = Pixmap::new(60, 200).expect("a 60x200 pixmap");
        let style = TextStyle::new(16.0, Color::BLACK)
            .anchor(HAlign::Center, VAlign::Middle)
            .rotated(90.0);
        font().draw(&mut pixmap, "velocity v (m/s)", 30.0, 100.0, &style);
        let (x0, y0, x1, y1) = ink_box(&pixmap).expect("the text has ink");
        let width = font().measure("velocity v (m/s)", 16.0).width;
        // Rotated, the string is tall and narrow and centred on the anchor point.
        assert!(
            (y1 - y0) as f32 > 0.9 * width && (x1 - x0) < 20,
            "{x0},{y0},{x1},{y1}"
        );
        assert!(((y0 + y1) as f32 / 2.0 - 100.0).abs() < 2.0);
        // Reading upwards, the pen moves towards the top of the screen: the heavy "WWW"
        // that starts "WWW..." must land below the light dots that end it.
        let mut pixmap = Pixmap::new(60, 200).expect("a 60x200 pixmap");
        font().draw(&mut pixmap, "WWW...", 30.0, 100.0, &style);
        let (mut sum, mut weighted) = (0.0f64, 0.0f64);
        for (i, p) in pixmap.pixels().iter().enumerate() {
            sum += f64::from(p.alpha());
            weighted += f64::from(p.alpha()) * (i / 60) as f64;
        }
        let centroid_y = weighted / sum;
        assert!(centroid_y > 102.0, "ink centroid at y = {centroid_y}");
    }

    #[test]
    fn ink_extent_is_tight_around_digits_and_descenders() {
        let cap = font().cap_height(20.0);
        let (up, down) = font().ink_extent("0123", 20.0);
        assert!(
            (up - cap).abs() < 0.1 * cap && down < 0.05 * cap,
            "{up} {down}"
        );
        let (_, down) = font().ink_extent("gy", 20.0);
        assert!(down > 0.15 * 20.0);
        assert_eq!(font().ink_extent("", 20.0), (0.0, 0.0));
        let (up, _) = font().ink_extent("10⁻⁶", 20.0);
        assert!(up > cap, "superscripts rise above the digits");
    }

    #[test]
    fn drawing_is_deterministic() {
        let render = || {
            let mut pixmap = Pixmap::new(120, 40).expect("a 120x40 pixmap");
            let style = TextStyle::new(15.3, Color::from_rgba8(20, 40, 200, 255))
                .anchor(HAlign::Center, VAlign::Middle)
                .rotated(17.0);
            font().draw(&mut pixmap, "dv/dt = −v/m", 60.3, 20.7, &style);
            pixmap.take()
        };
        assert_eq!(render(), render());
    }
}
