//! Reading a large scene file's `[[body]]` tables in slices, on every core, straight
//! into the schema's bodies.
//!
//! [`DeTable::parse`] lexes its whole input into one vector of tokens, builds one of
//! events, then the document; for the 1.16 MB of `scenes/bench/bodies-10000.toml` that
//! is about 60 MB, all of it memory that the process touches for the first time (one
//! page fault per 4 KB, some 15,000, which cost as much as the parsing itself). Here
//! the file is cut at column-0 lines `[[body]]` into slices of about [`SLICE_BYTES`];
//! each slice is parsed alone and its bodies deserialized at once, so that no slice's
//! tokens, events or document outlive it, and the next slice reuses their memory.
//!
//! This is only a quicker way to the same [`RawScene`]: every span in it counts from the
//! start of the whole text, as the whole parse's do (the tests compare the two `Debug`
//! texts, spans included). `--set` overrides that leave the bodies alone are applied to
//! the document of everything but the bodies, which is the whole document's but for the
//! key `body`. Whenever anything is not as the reasoning below assumes (a slice that
//! does not parse, a body that does not fit the schema, a root key met in two places, an
//! override that does not apply), [`raw_scene`] gives up and the front end takes the
//! whole-document path, which reports every problem with its place as it always has.
//!
//! **Why a slice boundary is a real `[[body]]` header.** A slice starts at a line whose
//! first bytes are `[[body]]`. If the text before it parses, every string, array and
//! inline table opened in it is closed in it, and the parser is between two expressions
//! at its end: were the line inside a multi-line string or array of the whole text, the
//! text before it would end inside that string or array and fail to parse. The text
//! before ends with a line break, which ends every token whatever follows it, so the
//! whole parse reads the line as the header `[[body]]`, as the slice's parse does.
//!
//! **Why the bodies are the whole parse's.** The text before the first slice (the
//! prefix) must not hold the key `body`, so the first `[[body]]` begins the array of
//! tables, in the whole parse as in the first slice. Each later slice's `[[body]]`
//! appends to it in the whole parse; a header `[body.x]` or `[[body.x]]` reaches the last
//! table of `body`, which is in the same slice, since slices start only at `[[body]]`.
//! So the whole parse's array is the slices' arrays one after the other. Any other root
//! key of a slice (a `[[force]]` after the bodies, say) is moved into the prefix's
//! document with its spans shifted; if the prefix or an earlier slice already has that
//! key, the whole parse must decide what it means, and it does.

use std::borrow::Cow;
use std::ops::Range;

use rayon::prelude::*;
use serde::Deserialize;
use toml::de::{DeTable, DeValue, Deserializer};
use toml::Spanned;

use super::raw::{
    RawBody, RawBox, RawCircle, RawPointMass, RawPolygon, RawScene, RawShape, RawVec2,
};

/// Files shorter than this are parsed whole: their vectors stay small anyway.
pub(super) const WHOLE_BELOW: usize = 64 * 1024;

/// The least length of a slice, in bytes: about 280 bodies of the benchmark's.
pub(super) const SLICE_BYTES: usize = 32 * 1024;

/// Returns the raw scene of a text of at least [`WHOLE_BELOW`] bytes read in slices, or
/// `None` when it is shorter or the whole-document path must read it. `prepare` is given
/// the document of everything but the bodies before the schema is tried on it (to apply
/// `--set` overrides that leave the bodies alone), and gives up by returning false.
pub(super) fn raw_scene<'i>(
    text: &'i str,
    prepare: impl FnOnce(&mut DeTable<'i>) -> bool,
) -> Option<RawScene> {
    if text.len() < WHOLE_BELOW {
        return None;
    }
    raw_scene_in_slices(text, SLICE_BYTES, prepare)
}

/// Returns the raw scene of `text` read in slices of at least `slice_bytes` bytes,
/// whatever its length (the tests cut small files with it), or `None` when the
/// whole-document path must read it; `prepare` as for [`raw_scene`].
pub(super) fn raw_scene_in_slices<'i>(
    text: &'i str,
    slice_bytes: usize,
    prepare: impl FnOnce(&mut DeTable<'i>) -> bool,
) -> Option<RawScene> {
    let (starts, headers) = slice_starts(text, slice_bytes);
    let first = *starts.first()?;
    let mut root = DeTable::parse(&text[..first]).ok()?;
    if root.get_ref().contains_key("body") {
        return None;
    }
    let ends: Vec<usize> = starts[1..].iter().copied().chain([text.len()]).collect();
    let slices: Vec<Option<Slice<'_>>> = starts
        .par_iter()
        .zip(ends.par_iter())
        .map(|(&start, &end)| Slice::read(text, start..end))
        .collect();
    let mut body = Vec::with_capacity(headers);
    for slice in slices {
        let slice = slice?;
        body.extend(slice.bodies);
        for (key, value) in slice.rest {
            if root.get_ref().contains_key(key.get_ref().as_ref()) {
                return None;
            }
            root.get_mut().insert(key, value);
        }
    }
    if !prepare(root.get_mut()) {
        return None;
    }
    let mut raw = RawScene::deserialize(Deserializer::from(root)).ok()?;
    raw.body = body;
    Some(raw)
}

/// Returns where the slices start, each at a column-0 line `[[body]]`: at the first such
/// line, then at the first such line at least `slice_bytes` past the last start; and
/// how many such lines there are.
fn slice_starts(text: &str, slice_bytes: usize) -> (Vec<usize>, usize) {
    let mut starts: Vec<usize> = Vec::new();
    let mut headers = 0;
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        if is_body_header(line) {
            headers += 1;
            if starts
                .last()
                .is_none_or(|&last| offset - last >= slice_bytes)
            {
                starts.push(offset);
            }
        }
        offset += line.len();
    }
    (starts, headers)
}

/// Returns true when a line is `[[body]]` from its first byte, followed by nothing but
/// blanks and a comment.
fn is_body_header(line: &str) -> bool {
    let Some(rest) = line.strip_prefix("[[body]]") else {
        return false;
    };
    let rest = rest.trim_start_matches([' ', '\t']);
    rest.is_empty() || rest.starts_with(['#', '\n']) || rest.starts_with("\r\n")
}

/// The key of a table entry, with its span.
type Key<'i> = Spanned<Cow<'i, str>>;

/// What one slice holds: its bodies, and its other root entries, spans shifted to count
/// from the start of the whole text.
struct Slice<'i> {
    bodies: Vec<Spanned<RawBody>>,
    rest: Vec<(Key<'i>, Spanned<DeValue<'i>>)>,
}

/// The part of the schema a slice's bodies are read with.
#[derive(Deserialize)]
struct Bodies {
    body: Vec<Spanned<RawBody>>,
}

impl<'i> Slice<'i> {
    /// Parses the slice of `text` at `range` and reads its bodies, or returns `None`.
    fn read(text: &'i str, range: Range<usize>) -> Option<Slice<'i>> {
        let offset = range.start;
        let mut table = DeTable::parse(&text[range]).ok()?.into_inner();
        let (key, bodies) = table.remove_entry("body")?;
        let mut only = DeTable::default();
        only.insert(key, bodies);
        let mut bodies = Bodies::deserialize(Deserializer::from(Spanned::new(0..0, only)))
            .ok()?
            .body;
        for body in &mut bodies {
            shift_body(body, offset);
        }
        let mut rest = Vec::with_capacity(table.len());
        let mut scratch = Vec::new();
        for (key, mut value) in table {
            shift_value(&mut value, offset, &mut scratch);
            rest.push((
                Spanned::new(moved(key.span(), offset), key.into_inner()),
                value,
            ));
        }
        Some(Slice { bodies, rest })
    }
}

/// Returns a span moved `offset` bytes on.
fn moved(span: Range<usize>, offset: usize) -> Range<usize> {
    span.start + offset..span.end + offset
}

/// Moves a `Spanned`'s span `offset` bytes on, keeping its value.
fn shift<T>(spanned: Spanned<T>, offset: usize) -> Spanned<T> {
    let span = moved(spanned.span(), offset);
    Spanned::new(span, spanned.into_inner())
}

/// Returns a copy of a `Spanned` number or vector with its span moved `offset` bytes on.
fn shift_copy<T: Copy>(spanned: &Spanned<T>, offset: usize) -> Spanned<T> {
    Spanned::new(moved(spanned.span(), offset), *spanned.get_ref())
}

/// Moves the span of an optional `Spanned` `offset` bytes on.
fn shift_option<T>(field: &mut Option<Spanned<T>>, offset: usize) {
    if let Some(spanned) = field.take() {
        *field = Some(shift(spanned, offset));
    }
}

/// Moves every span of a body, and of everything in it, `offset` bytes on.
fn shift_body(body: &mut Spanned<RawBody>, offset: usize) {
    // Named in full, so that a new key of the schema cannot be forgotten here.
    let RawBody {
        name,
        mass,
        position,
        velocity,
        shape,
        points,
        color,
        show_velocity,
        show_force,
        angle,
        angular_velocity,
        inertia,
        fixed,
        restitution,
        friction,
    } = body.get_mut();
    shift_option(name, offset);
    shift_option(mass, offset);
    shift_option(position, offset);
    shift_option(velocity, offset);
    if let Some(shape) = shape {
        shift_shape(shape.get_mut(), offset);
    }
    shift_option(shape, offset);
    if let Some(points) = points {
        for point in points.get_mut().iter_mut() {
            let RawPointMass { offset: at, mass } = point.get_mut();
            *at = shift_copy(at, offset);
            *mass = shift_copy(mass, offset);
            *point = shift(take_point(point), offset);
        }
    }
    shift_option(points, offset);
    shift_option(color, offset);
    shift_option(show_velocity, offset);
    shift_option(show_force, offset);
    shift_option(angle, offset);
    shift_option(angular_velocity, offset);
    shift_option(inertia, offset);
    shift_option(fixed, offset);
    shift_option(restitution, offset);
    shift_option(friction, offset);
    let span = moved(body.span(), offset);
    let inner = std::mem::replace(body.get_mut(), empty_body());
    *body = Spanned::new(span, inner);
}

/// Takes a point mass out of its place, leaving a placeholder to be overwritten.
fn take_point(point: &mut Spanned<RawPointMass>) -> Spanned<RawPointMass> {
    let zero = Spanned::new(0..0, RawVec2([0.0, 0.0]));
    let placeholder = RawPointMass {
        offset: zero,
        mass: Spanned::new(0..0, 0.0),
    };
    std::mem::replace(point, Spanned::new(0..0, placeholder))
}

/// Moves every span inside a shape `offset` bytes on.
fn shift_shape(shape: &mut RawShape, offset: usize) {
    let RawShape {
        circle,
        rect,
        polygon,
    } = shape;
    if let Some(circle) = circle {
        let RawCircle { radius } = circle.get_mut();
        *radius = shift_copy(radius, offset);
    }
    shift_option(circle, offset);
    if let Some(rect) = rect {
        let RawBox { width, height } = rect.get_mut();
        *width = shift_copy(width, offset);
        *height = shift_copy(height, offset);
    }
    shift_option(rect, offset);
    if let Some(polygon) = polygon {
        let RawPolygon { points } = polygon.get_mut();
        for point in points.get_mut().iter_mut() {
            *point = shift_copy(point, offset);
        }
        let list = std::mem::take(points.get_mut());
        *points = Spanned::new(moved(points.span(), offset), list);
    }
    shift_option(polygon, offset);
}

/// A body with no keys, a placeholder while a body is moved.
fn empty_body() -> RawBody {
    RawBody {
        name: None,
        mass: None,
        position: None,
        velocity: None,
        shape: None,
        points: None,
        color: None,
        show_velocity: None,
        show_force: None,
        angle: None,
        angular_velocity: None,
        inertia: None,
        fixed: None,
        restitution: None,
        friction: None,
    }
}

/// Moves every span in a value, and in the keys and values it holds, `offset` bytes on.
fn shift_value<'i>(
    value: &mut Spanned<DeValue<'i>>,
    offset: usize,
    scratch: &mut Vec<(Key<'i>, Spanned<DeValue<'i>>)>,
) {
    match value.get_mut() {
        DeValue::Table(table) => shift_table(table, offset, scratch),
        DeValue::Array(items) => {
            for item in items.iter_mut() {
                shift_value(item, offset, scratch);
            }
        }
        _ => {}
    }
    let span = moved(value.span(), offset);
    let inner = std::mem::replace(value.get_mut(), DeValue::Boolean(false));
    *value = Spanned::new(span, inner);
}

/// Moves every span in a table `offset` bytes on, keeping the table itself (and so the
/// flags `toml` keeps on it) and the order of its keys.
fn shift_table<'i>(
    table: &mut DeTable<'i>,
    offset: usize,
    scratch: &mut Vec<(Key<'i>, Spanned<DeValue<'i>>)>,
) {
    for (_, value) in table.iter_mut() {
        shift_value(value, offset, scratch);
    }
    // A key cannot be changed in place, so the entries are taken out from the last
    // (which moves no other entry) and put back from the first.
    let base = scratch.len();
    while let Some(last) = table.keys().next_back().map(|k| k.get_ref().clone()) {
        match table.remove_entry(last.as_ref()) {
            Some(entry) => scratch.push(entry),
            None => break,
        }
    }
    while scratch.len() > base {
        let Some((key, value)) = scratch.pop() else {
            break;
        };
        table.insert(
            Spanned::new(moved(key.span(), offset), key.into_inner()),
            value,
        );
    }
}

#[cfg(test)]
mod tests;
