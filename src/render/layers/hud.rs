//! The heads-up display: one line with the frame's time and number, top left.

use tiny_skia::{Color, IntRect, Pixmap, Rect};

use super::super::text::{Font, HAlign, TextStyle, VAlign};

/// Draws "t = 1.24   frame 31 / 125" in the top-left corner of `area`, on a pale box so
/// it reads over anything, and returns the pixels it may have touched, x0..x1 by
/// y0..y1: the box and a margin of two pixels around it, for glyphs whose edges reach
/// past their measured extent.
pub fn draw(
    pixmap: &mut Pixmap,
    area: IntRect,
    t: f64,
    index: u64,
    frame_count: u64,
    fps: f64,
    scale: f32,
) -> (i64, i64, i64, i64) {
    // Enough decimals to tell frames apart: ceil(-log10(1/fps)), at least one.
    let decimals = (fps.log10().ceil().max(1.0) as usize).min(6);
    let text = format!(
        "t = {t:.decimals$}   frame {index} / {}",
        frame_count.saturating_sub(1)
    );
    let font = Font::dejavu_sans();
    let size = 14.0 * scale;
    let extent = font.measure(&text, size);
    let pad = (4.0 * scale).round();
    let left = area.left() as f32 + (6.0 * scale).round();
    let top = area.top() as f32 + (6.0 * scale).round();
    let (w, h) = (
        (extent.width + 2.0 * pad).ceil(),
        (extent.height() + 2.0 * pad).ceil(),
    );
    if let Some(rect) = Rect::from_xywh(left, top, w, h) {
        let mut paint = tiny_skia::Paint::default();
        paint.set_color(Color::from_rgba8(255, 255, 255, 0xcc));
        pixmap.fill_rect(rect, &paint, tiny_skia::Transform::identity(), None);
    }
    let style = TextStyle::new(size, Color::BLACK).anchor(HAlign::Left, VAlign::Top);
    font.draw(pixmap, &text, left + pad, (top + pad).round(), &style);
    let whole = |v: f32| if v.is_finite() { v as i64 } else { 0 };
    (
        whole(left.floor()) - 2,
        whole(top.floor()) - 2,
        whole((left + w).ceil()) + 2,
        whole((top + h).ceil()) + 2,
    )
}
