//! Convex shapes scan-converted by walking their two chains of edges: the same bytes
//! as the general scan for the nonzero rule ([`super::fill_polygons`]), quicker.

use std::cell::RefCell;

use tiny_skia::Pixmap;

use super::clipper::ImageClip;
use super::eight::{blend8, prefetch, Span};
use super::shapes::Ring;
use super::{Edge, Point};
use crate::render::sprite::Ink;

/// Fills a convex polygon with `ink`, like [`super::fill_polygons`] with one polygon (the same
/// bytes) but quicker: a convex polygon crosses each sub-row at one edge going down and
/// one going up, so the two chains are walked instead of sorting edges.
pub fn fill_convex(pixmap: &mut Pixmap, points: &[Point], ink: Ink) {
    CONVEX.with(|c| {
        let c = &mut *c.borrow_mut();
        c.chains.set(points, &[], size(pixmap));
        blend_convex(pixmap, &mut c.chains, ink);
    });
}

/// Calls `put(i, c)` with the coverage c > 0 of every pixel i (counted row after row in
/// an image `width` × `height`) that a convex polygon covers, pixel by pixel within a
/// row and row after row: the coverage [`fill_convex`] blends.
pub fn cover_convex(width: u32, height: u32, points: &[Point], put: impl FnMut(usize, u8)) {
    CONVEX.with(|c| {
        let c = &mut *c.borrow_mut();
        let size = (width as usize, height as usize);
        c.chains.set(points, &[], size);
        scan_convex(size.0, size.1, &mut c.chains, put);
    });
}

/// Blends `ink` with the coverage of the convex polygon `outer` less the convex
/// `hole`, as the outlines' rings are blended (with AVX2 where there is some).
#[cfg(test)]
pub(super) fn fill_holed(pixmap: &mut Pixmap, outer: &[Point], hole: &[Point], ink: Ink) {
    CONVEX.with(|c| {
        let c = &mut *c.borrow_mut();
        c.chains.set(outer, hole, size(pixmap));
        blend_convex(pixmap, &mut c.chains, ink);
    });
}

/// The coverage of `outer` less `hole` pixel by pixel, as [`cover_convex`] gives a
/// polygon's: what [`fill_holed`] is tested against.
#[cfg(test)]
pub(super) fn cover_holed(
    (width, height): (usize, usize),
    outer: &[Point],
    hole: &[Point],
    put: impl FnMut(usize, u8),
) {
    CONVEX.with(|c| {
        let c = &mut *c.borrow_mut();
        c.chains.set(outer, hole, (width, height));
        scan_convex(width, height, &mut c.chains, put);
    });
}

/// The pixmap's width and height.
fn size(pixmap: &Pixmap) -> (usize, usize) {
    (pixmap.width() as usize, pixmap.height() as usize)
}

/// Blends `ink` into the pixmap with the coverage of the chains' shape.
fn blend_convex(pixmap: &mut Pixmap, chains: &mut Chains, ink: Ink) {
    let (width, height) = (pixmap.width() as usize, pixmap.height() as usize);
    let data = pixmap.data_mut();
    if chains.chains[2].is_empty() {
        blend_plain(data, width, height, chains, ink);
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if width <= super::avx2::MAX_WIDTH && super::avx2::available() {
        // SAFETY: the processor has AVX2, just checked, and the image is at most
        // MAX_WIDTH wide.
        unsafe { super::avx2::blend_holed(data, width, height, chains, ink) };
        return;
    }
    scan_convex(width, height, chains, |i, c| {
        ink.blend(&mut data[4 * i..4 * i + 4], c);
    });
}

/// Blends `ink` into the pixels `data` of an image `width` × `height` with the
/// coverage of a convex polygon without a hole: the bytes of [`scan_convex`]. Each
/// pixel row's (at most four) spans are covered and blended eight pixels at a time
/// without a branch on where they end (`eight.rs`, or `avx2.rs` where the processor
/// has AVX2 and the image is at most 4096 pixels wide: the same bytes), and one by one
/// only where eight pixels would pass the image's right edge.
fn blend_plain(data: &mut [u8], width: usize, height: usize, chains: &mut Chains, ink: Ink) {
    #[cfg(target_arch = "x86_64")]
    if width <= super::avx2::MAX_WIDTH && super::avx2::available() {
        // SAFETY: the processor has AVX2, just checked.
        unsafe { super::avx2::blend_plain(data, width, height, chains, ink) };
        return;
    }
    blend_plain_sse2(data, width, height, chains, ink);
}

/// [`blend_plain`] eight pixels at a time with SSE2 (or lane by lane where there is
/// none), on every processor: what the AVX2 version is tested against.
pub(super) fn blend_plain_sse2(
    data: &mut [u8],
    width: usize,
    height: usize,
    chains: &mut Chains,
    ink: Ink,
) {
    let (first, end) = chains.rows_within(height);
    let mut sy = first;
    while sy < end {
        let py = (sy >> 2) as usize;
        let row = chains.row_spans(sy, end, width);
        sy = row.next;
        let (lo, hi) = (row.lo, row.hi);
        let spans = row.spans();
        let base = py * width;
        if lo < hi {
            // The pixels two rows down, where the shape most likely goes on: an
            // arrow's few pixels a row are each a line of memory to wait for, which
            // the blend reaches sooner now that it does not branch.
            let ahead = 4 * (base + 2 * width);
            prefetch(data, ahead + 4 * lo as usize);
            prefetch(data, ahead + 4 * hi as usize);
        }
        let mut x = lo;
        while x < hi && x + 8 <= width as i64 {
            let k = 4 * (base + x as usize);
            let px: &mut [u8; 32] = (&mut data[k..k + 32])
                .try_into()
                .expect("eight pixels are 32 bytes");
            blend8(px, x, &spans, &ink);
            x += 8;
        }
        blend_tail(data, base, x, hi, &spans, &ink);
    }
}

/// Blends pixels x..hi of the row that starts at pixel `base`, one by one, with the
/// coverage of `spans`: where eight pixels at a time would pass the image's edge.
pub(super) fn blend_tail(
    data: &mut [u8],
    base: usize,
    x: i64,
    hi: i64,
    spans: &[Span; 4],
    ink: &Ink,
) {
    for x in x..hi {
        let mut c = 0u16;
        for &(a, b, full) in spans {
            let o = (b.min(4 * x + 4) - a.max(4 * x)).max(0);
            c += if o == 4 { full } else { 16 * o as u16 };
        }
        if c != 0 {
            let k = 4 * (base + x as usize);
            // Skia's runs cap a sum of 256 at 255: (a - (a >> 8)).
            ink.blend(&mut data[k..k + 4], (c - (c >> 8)).min(255) as u8);
        }
    }
}

/// One pixel row of a convex polygon without a hole, as quarter-pixel columns: the
/// span a[k]..b[k] of each sub-row k (a = b = 0 where it has none), the pixels lo..hi
/// the spans touch (clipped to the image's width; empty when lo >= hi), and the first
/// sub-row of the next pixel row.
pub(super) struct RowSpans {
    pub a: [i64; 4],
    pub b: [i64; 4],
    pub lo: i64,
    pub hi: i64,
    pub next: i64,
}

impl RowSpans {
    /// The spans with their sub-rows' full weights ([`weighed`]).
    pub fn spans(&self) -> [Span; 4] {
        weighed(self.a, self.b)
    }
}

/// A pixel row's spans a[k]..b[k] with each sub-row's full weight: 64, or 63 in the
/// last sub-row, so that a pixel all four cover whole sums to 255.
pub(super) fn weighed(a: [i64; 4], b: [i64; 4]) -> [Span; 4] {
    std::array::from_fn(|k| (a[k], b[k], 64 - u16::from(k == 3)))
}

/// A convex polygon, less a convex hole inside it, as chains of tiny-skia's edges: the
/// edges going down (winding +1) and those going up, each in order of their sub-rows,
/// which for a convex polygon follow one another without a gap.
#[derive(Default)]
pub(super) struct Chains {
    /// The polygon's two chains, then the hole's.
    chains: [Vec<Edge>; 4],
    /// Where each chain is: its current edge, the sub-row and x it was last asked for.
    cursors: [Cursor; 4],
}

/// A chain's current edge, and its crossing of the last sub-row asked for.
#[derive(Clone, Copy, Debug, Default)]
struct Cursor {
    edge: usize,
    sy: i64,
    x: i64,
    dx: i64,
    last: i64,
}

impl Chains {
    /// Takes the edges of `outer` less `hole`, to be filled into an image `width` ×
    /// `height`, cut to it as tiny-skia cuts a path that reaches outside it.
    pub(super) fn set(&mut self, outer: &[Point], hole: &[Point], (width, height): (usize, usize)) {
        for c in &mut self.chains {
            c.clear();
        }
        let finite = |ps: &[Point]| ps.iter().all(|p| p.0.is_finite() && p.1.is_finite());
        if outer.len() < 3 || !finite(outer) || !finite(hole) {
            return;
        }
        let clip = ImageClip::new(width, height, &[outer, hole]);
        for (k, points) in [outer, hole].into_iter().enumerate() {
            if points.len() < 3 {
                continue;
            }
            if clip.contained() {
                // Nothing to cut: each point taken into fixed point once.
                let mut previous = Edge::fixed(points[points.len() - 1]);
                for &p in points {
                    let p = Edge::fixed(p);
                    if let Some(e) = Edge::from_fixed(previous, p) {
                        self.chains[2 * k + usize::from(e.winding < 0)].push(e);
                    }
                    previous = p;
                }
                continue;
            }
            let mut previous = points[points.len() - 1];
            for &p in points {
                clip.cut(previous, p, |a, b| {
                    if let Some(e) = Edge::new(a, b) {
                        self.chains[2 * k + usize::from(e.winding < 0)].push(e);
                    }
                });
                previous = p;
            }
        }
        for c in &mut self.chains {
            c.sort_unstable_by_key(|e| e.first);
        }
        // No sub-row asked for yet.
        self.cursors = [Cursor {
            sy: i64::MIN,
            last: i64::MIN,
            ..Cursor::default()
        }; 4];
    }

    /// The sub-rows the polygon covers in an image `height` pixels high, first..end
    /// (empty when first >= end).
    pub(super) fn rows_within(&self, height: usize) -> (i64, i64) {
        let (first, end) = self.rows();
        (first.max(0), end.min(4 * height as i64))
    }

    /// The sub-rows the polygon covers, first..end.
    fn rows(&self) -> (i64, i64) {
        let [a, b, ..] = &self.chains;
        let first = a.iter().chain(b).map(|e| e.first).min().unwrap_or(0);
        let end = a.iter().chain(b).map(|e| e.last + 1).max().unwrap_or(0);
        (first, end)
    }

    /// The spans of the pixel row that holds sub-row `sy` (from `sy` to the row's end or
    /// `end`, whichever is first) in an image `width` pixels wide, from the crossings of
    /// the first two chains: what a polygon without a hole covers there.
    pub(super) fn row_spans(&mut self, mut sy: i64, end: i64, width: usize) -> RowSpans {
        let max_column = 4 * width as i64;
        let column = |v: i64| ((v + 0x8000) >> 16).clamp(0, max_column);
        let row_end = (((sy >> 2) + 1) * 4).min(end);
        let mut row = RowSpans {
            a: [0; 4],
            b: [0; 4],
            lo: i64::MAX,
            hi: 0,
            next: row_end,
        };
        while sy < row_end {
            if let (Some(up), Some(down)) = (self.crossing(0, sy), self.crossing(1, sy)) {
                let (a, b) = (column(up.min(down)), column(up.max(down)));
                if a < b {
                    row.lo = row.lo.min(a >> 2);
                    row.hi = row.hi.max((b + 3) >> 2);
                    let k = (sy & 3) as usize;
                    (row.a[k], row.b[k]) = (a, b);
                }
            }
            sy += 1;
        }
        row.hi = row.hi.min(width as i64);
        row
    }

    /// When the first two chains were last asked for sub-row `sy` - 1 and both go on
    /// with the same edge through sub-row `sy` + 3 (and `sy` starts a pixel row), the
    /// last sub-row before `end` through which both go on with their edges, and each
    /// chain's crossing of sub-row `sy` - 1 and step per sub-row.
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(super) fn straight(&self, sy: i64, end: i64) -> Option<(i64, [(i64, i64); 2])> {
        let [c0, c1, ..] = &self.cursors;
        let stop = c0.last.min(c1.last).min(end - 1);
        (sy & 3 == 0 && c0.sy == sy - 1 && c1.sy == sy - 1 && sy + 3 <= stop)
            .then_some((stop, [(c0.x, c0.dx), (c1.x, c1.dx)]))
    }

    /// Moves the first two chains' cursors on by `n` sub-rows of their current edges,
    /// as asking for each of them would.
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(super) fn advance(&mut self, n: i64) {
        for c in &mut self.cursors[..2] {
            c.sy += n;
            c.x += n * c.dx;
        }
    }

    /// Returns chain `k`'s fixed-point crossing of sub-row `sy`, or `None` when the
    /// chain does not reach it; calls come with `sy` increasing.
    #[inline]
    fn crossing(&mut self, k: usize, sy: i64) -> Option<i64> {
        let c = &mut self.cursors[k];
        if sy == c.sy + 1 && sy <= c.last {
            c.sy = sy;
            c.x += c.dx;
            return Some(c.x);
        }
        let chain = &self.chains[k];
        while c.edge < chain.len() && chain[c.edge].last < sy {
            c.edge += 1;
        }
        let e = chain.get(c.edge).filter(|e| e.first <= sy)?;
        *c = Cursor {
            edge: c.edge,
            sy,
            x: e.x + e.dx * (sy - e.first),
            dx: e.dx,
            last: e.last,
        };
        Some(c.x)
    }
}

/// What one thread reuses for convex shapes.
#[derive(Default)]
struct Convex {
    chains: Chains,
}

thread_local! {
    static CONVEX: RefCell<Convex> = RefCell::new(Convex::default());
}

/// Scan-converts a convex polygon less a convex hole sub-row by sub-row, in an image
/// `width` × `height`, and hands each pixel row's coverage to `put` (pixel index,
/// coverage) as it is finished. The spans are those tiny-skia
/// finds with the nonzero rule: from the polygon's left crossing to the hole's, and
/// from the hole's right crossing to the polygon's.
///
/// A pixel row's coverage is summed from its (at most eight) spans of quarter-pixel
/// columns pixel by pixel, as [`accumulate`] would sum them, except in the run of
/// pixels that all four sub-rows cover whole (255), which is blended in one go.
fn scan_convex(width: usize, height: usize, chains: &mut Chains, mut put: impl FnMut(usize, u8)) {
    let (first, end) = chains.rows_within(height);
    let mut sy = first;
    while sy < end {
        if let Some(row) = holed_row(chains, &mut sy, end, width) {
            put_row(&row, width, &mut put);
        }
    }
}

/// One pixel row of a convex polygon less a convex hole: its spans of quarter-pixel
/// columns a..b with each sub-row's full weight (at most two a sub-row, in sub-row
/// order and left to right within one), and the pixels every sub-row covers whole
/// (empty when core_lo >= core_hi, or when not every sub-row has one span).
pub(super) struct HoledRow {
    pub(super) py: usize,
    pub(super) spans: [Span; 8],
    pub(super) n: usize,
    core_lo: i64,
    core_hi: i64,
    holed: bool,
}

/// The spans of the pixel row holding sub-row `*sy`, from there to the row's end or
/// `end`, whichever is first, and moves `*sy` past them; `None` when they are empty.
#[inline(always)]
pub(super) fn holed_row(
    chains: &mut Chains,
    sy: &mut i64,
    end: i64,
    width: usize,
) -> Option<HoledRow> {
    let max_column = 4 * width as i64;
    let holed = !chains.chains[2].is_empty();
    let column = |v: i64| ((v + 0x8000) >> 16).clamp(0, max_column);
    let py = (*sy >> 2) as usize;
    let row_end = (((*sy >> 2) + 1) * 4).min(end);
    // The row's spans: quarter-pixel columns a..b and the sub-row's full weight.
    let mut spans = [(0i64, 0i64, 0u16); 8];
    let mut n = 0;
    // The pixels every sub-row covers whole, when each sub-row has one span.
    let (mut core_lo, mut core_hi) = (0i64, i64::MAX);
    let mut single = true;
    let mut rows = 0;
    while *sy < row_end {
        let full = 64 - u16::from(*sy & 3 == 3);
        let before = n;
        let mut add = |a: i64, b: i64| {
            if a < b {
                spans[n] = (a, b, full);
                n += 1;
            }
        };
        let (Some(up), Some(down)) = (chains.crossing(0, *sy), chains.crossing(1, *sy)) else {
            *sy += 1;
            single = false;
            continue;
        };
        let (l, r) = (up.min(down), up.max(down));
        let hole = if holed {
            chains.crossing(2, *sy).zip(chains.crossing(3, *sy))
        } else {
            None
        };
        match hole {
            None => add(column(l), column(r)),
            // The usual case, a hole wound against the polygon and inside it: the
            // nonzero rule covers from each of the polygon's crossings to the
            // hole's on its side.
            Some((a, b)) if (a <= b) != (up <= down) && l <= a.min(b) && a.max(b) <= r => {
                add(column(l), column(a.min(b)));
                add(column(a.max(b)), column(r));
            }
            // Otherwise the four crossings with their windings are sorted by x, as
            // tiny-skia sorts its active edges, and walked with the nonzero rule.
            Some((a, b)) => {
                let mut xs = [(up, 1i32), (down, -1), (a, 1), (b, -1)];
                xs.sort_by_key(|c| c.0);
                let (mut w, mut left) = (0, 0);
                for (x, winding) in xs {
                    let x = column(x);
                    if w == 0 {
                        left = x;
                    }
                    w += winding;
                    if w == 0 {
                        add(left, x);
                    }
                }
            }
        }
        if n == before + 1 {
            let (a, b, _) = spans[before];
            core_lo = core_lo.max((a + 3) >> 2);
            core_hi = core_hi.min(b >> 2);
        } else {
            single = false;
        }
        rows += 1;
        *sy += 1;
    }
    if n == 0 {
        return None;
    }
    if !(single && rows == 4) || core_lo >= core_hi {
        core_lo = i64::MAX;
        core_hi = i64::MAX;
    }
    Some(HoledRow {
        py,
        spans,
        n,
        core_lo,
        core_hi,
        holed,
    })
}

/// Hands a pixel row's coverage to `put` pixel by pixel, as [`scan_convex`] does.
#[inline(always)]
pub(super) fn put_row(row: &HoledRow, width: usize, put: &mut impl FnMut(usize, u8)) {
    let n = row.n;
    let (core_lo, core_hi) = (row.core_lo, row.core_hi);
    // The pixels the spans touch, as disjoint runs: a ring's row is two runs with the
    // hole between them, which is not visited.
    let mut spans = row.spans;
    let spans = &mut spans[..n];
    let holed = row.holed;
    // Without a hole a row's spans are one run (pixels between two of them, if any,
    // have no coverage and are skipped below); with one, they are sorted and merged
    // into runs, so that the hole is not visited.
    if holed {
        spans.sort_unstable_by_key(|s| s.0);
    }
    let base = row.py * width;
    let mut k = 0;
    while k < n {
        let mut lo = spans[k].0 >> 2;
        let mut hi = (spans[k].1 + 3) >> 2;
        let mut j = k + 1;
        while j < n && (!holed || spans[j].0 >> 2 <= hi) {
            lo = lo.min(spans[j].0 >> 2);
            hi = hi.max((spans[j].1 + 3) >> 2);
            j += 1;
        }
        let run = &spans[k..j];
        k = j;
        let hi = hi.min(width as i64);
        let mut x = lo;
        while x < hi {
            if x == core_lo {
                // Covered whole by all four sub-rows: 64·3 + 63 = 255.
                for i in base + x as usize..base + core_hi as usize {
                    put(i, 255);
                }
                x = core_hi;
                continue;
            }
            // Quarter-pixel columns 4x..4x + 4 against each span.
            let mut c = 0u16;
            for &(a, b, full) in run {
                let o = (b.min(4 * x + 4) - a.max(4 * x)).max(0);
                c += if o == 4 { full } else { 16 * o as u16 };
            }
            if c != 0 {
                // Skia's runs cap a sum of 256 at 255: (a - (a >> 8)).
                put(base + x as usize, (c - (c >> 8)).min(255) as u8);
            }
            x += 1;
        }
    }
}

thread_local! {
    /// Each thread's transformed points of a turned outline and of its ring's sides.
    static TURNED: RefCell<(Vec<tiny_skia::Point>, [Vec<Point>; 3])> =
        RefCell::new(Default::default());
}

/// Draws a convex outline turned and placed by `at` as tiny-skia draws the paths: the
/// polygon `fill` in `fill_ink`, then its stroke, `ring`, in `edge_ink`. The points are
/// taken through `at` by tiny-skia's own `Transform::map_points`, so the fill has the
/// bytes of tiny-skia's.
pub fn fill_turned(
    pixmap: &mut Pixmap,
    fill: &[Point],
    ring: &Ring,
    at: tiny_skia::Transform,
    fill_ink: Ink,
    edge_ink: Ink,
) {
    turned(pixmap, None, fill, ring, at, [fill_ink, edge_ink]);
}

/// Fills the convex polygon `under` in the first ink, then the convex polygon `over`
/// (its points in either order) in the second over it, both placed by `at` as
/// [`fill_turned`] places its points.
///
/// For an outline in opaque colours, with `under` its stroke's outer side and `over`
/// its inner side (a disc's curve moved a half-width out and in, [`super::disc`], or
/// a convex outline's [`super::Ring`]), this stands for the fill and then the
/// stroke, ring = outer - inner. With a pixel's coverages c_f by
/// the fill, c_o by the outer side and c_i by the inner one (c_i ≤ c_f ≤ c_o, and the
/// ring's c_o - c_i), the fill (F) then the stroke (E) over what lies under (B) give
/// E·(c_o - c_i) + (1 - c_o + c_i)·(F·c_f + B·(1 - c_f)), and the two fills
/// F·c_i + (1 - c_i)·(E·c_o + B·(1 - c_o)). The sides lie 1.5 pixels apart, more than
/// a pixel's diagonal, so a pixel has c_o = 1 or c_i = 0: the two differ by
/// c_i·(1 - c_f)·(B - F) or by (1 - c_o)·c_f·(F - B), at most c_f·(1 - c_f)·|F - B|,
/// a quarter of |F - B|, and only where the fill's edge crosses the pixel too.
pub fn fill_layers(
    pixmap: &mut Pixmap,
    under: &[Point],
    over: &[Point],
    at: tiny_skia::Transform,
    inks: [Ink; 2],
) {
    TURNED.with(|buffers| {
        let (scratch, [a, b, _]) = &mut *buffers.borrow_mut();
        super::place(at, under, scratch, a);
        super::place(at, over, scratch, b);
        CONVEX.with(|c| {
            let c = &mut *c.borrow_mut();
            for (points, ink) in [(&*a, inks[0]), (&*b, inks[1])] {
                c.chains.set(points, &[], size(pixmap));
                blend_convex(pixmap, &mut c.chains, ink);
            }
        });
    });
}

/// Draws a turned convex outline like [`fill_turned`], its fill into `fill_pixmap` and
/// its stroke into `edge_pixmap`, both in `ink`: with opaque white over transparent
/// pixmaps, the alpha of each is the coverage, as sprites keep it.
pub fn fill_turned_apart(
    fill_pixmap: &mut Pixmap,
    edge_pixmap: &mut Pixmap,
    fill: &[Point],
    ring: &Ring,
    at: tiny_skia::Transform,
    ink: Ink,
) {
    turned(fill_pixmap, Some(edge_pixmap), fill, ring, at, [ink, ink]);
}

/// The fill of [`fill_turned`] into `pixmap`, then the stroke into `edge_pixmap` or,
/// without one, over the fill.
fn turned(
    pixmap: &mut Pixmap,
    edge_pixmap: Option<&mut Pixmap>,
    fill: &[Point],
    ring: &Ring,
    at: tiny_skia::Transform,
    [fill_ink, edge_ink]: [Ink; 2],
) {
    TURNED.with(|buffers| {
        let (scratch, [f, o, i]) = &mut *buffers.borrow_mut();
        super::place(at, fill, scratch, f);
        super::place(at, &ring.outer, scratch, o);
        super::place(at, ring.inner.as_deref().unwrap_or(&[]), scratch, i);
        // The fill, then the stroke over it.
        CONVEX.with(|c| {
            let c = &mut *c.borrow_mut();
            c.chains.set(f, &[], size(pixmap));
            blend_convex(pixmap, &mut c.chains, fill_ink);
            let edge_pixmap = edge_pixmap.unwrap_or(pixmap);
            c.chains.set(o, i, size(edge_pixmap));
            blend_convex(edge_pixmap, &mut c.chains, edge_ink);
        });
    });
}
