//! The heads-up display: one line with the frame's time and number, top left.

use tiny_skia::{Color, IntRect, Pixmap, Rect};

use super::super::text::{Font, HAlign, TextStyle, VAlign};

/// Draws "t = 1.24   frame 31 / 125" in the top-left corner of `area`, on a pale box so
/// it reads over anything.
pub fn draw(
    pixmap: &mut Pixmap,
    area: IntRect,
    t: f64,
    index: u64,
    frame_count: u64,
    fps: f64,
    scale: f32,
) {
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
    if let Some(rect) = Rect::from_xywh(
        left,
        top,
        (extent.width + 2.0 * pad).ceil(),
        (extent.height() + 2.0 * pad).ceil(),
    ) {
        let mut paint = tiny_skia::Paint::default();
        paint.set_color(Color::from_rgba8(255, 255, 255, 0xcc));
        pixmap.fill_rect(rect, &paint, tiny_skia::Transform::identity(), None);
    }
    let style = TextStyle::new(size, Color::BLACK).anchor(HAlign::Left, VAlign::Top);
    font.draw(pixmap, &text, left + pad, (top + pad).round(), &style);
}
