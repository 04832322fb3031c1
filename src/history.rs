//! Append-only histories shared between frames.
//!
//! Several things grow by one entry per frame and are drawn whole at every frame: the
//! positions behind trails, the points of trace curves, the comparison's error rows.
//! Copying such a history into each frame's snapshot costs time and memory that grow
//! with the frame index, so over a render they grow with the square of the frames.
//! Instead one [`HistoryWriter`] appends to storage that never moves, and each frame
//! keeps a [`History`]: the storage's `Arc` and the number of entries it sees. Taking a
//! snapshot costs the same at the last frame as at the first.
//!
//! Entries live in segments of 1, 2, 4, ... slots. A segment is allocated when the first
//! entry reaches it and never moves or grows, so appending never copies the entries
//! before, and a slot, once written, is never written again. Only the writer appends,
//! and there is one writer per storage (it cannot be cloned, and a snapshot cannot
//! append), so a slot is never written twice and the entries a snapshot sees never
//! change.

use std::fmt;
use std::sync::{Arc, OnceLock};

use glam::DVec2;

/// One set of points per frame so far: every body's position, for trails, or every
/// trace curve's point, for traces.
pub type PointHistory = History<Arc<[DVec2]>>;

/// The number of segments: segment s holds 2^s entries, so these hold more entries than
/// a `usize` can count.
const SEGMENTS: usize = usize::BITS as usize;

/// One segment: its slots, each written once.
type Segment<T> = Box<[OnceLock<T>]>;

/// The storage shared by a writer and its snapshots.
struct Storage<T> {
    segments: [OnceLock<Segment<T>>; SEGMENTS],
}

impl<T> Storage<T> {
    fn new() -> Self {
        Storage {
            segments: std::array::from_fn(|_| OnceLock::new()),
        }
    }

    /// Returns the segment and the slot in it of entry `i`.
    fn slot_of(i: usize) -> (usize, usize) {
        // Entry i is number i + 1 counted from 1; segment s holds numbers
        // 2^s ..= 2^(s+1) - 1.
        let n = i + 1;
        let s = n.ilog2() as usize;
        (s, n - (1 << s))
    }

    fn get(&self, i: usize) -> Option<&T> {
        let (s, slot) = Self::slot_of(i);
        self.segments[s].get()?.get(slot)?.get()
    }
}

/// A history as one frame sees it: the first `len` entries of storage shared with the
/// [`HistoryWriter`] that appends to it and with every other snapshot. Cloning one is an
/// `Arc` clone; the entries it sees never change.
pub struct History<T> {
    storage: Arc<Storage<T>>,
    len: usize,
}

impl<T> Clone for History<T> {
    fn clone(&self) -> Self {
        History {
            storage: Arc::clone(&self.storage),
            len: self.len,
        }
    }
}

impl<T> Default for History<T> {
    /// Returns a history that sees no entry.
    fn default() -> Self {
        History {
            storage: Arc::new(Storage::new()),
            len: 0,
        }
    }
}

impl<T> History<T> {
    /// Returns the number of entries this history sees.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Returns whether this history sees no entry.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Returns entry `i`, or `None` when this history does not see it.
    pub fn get(&self, i: usize) -> Option<&T> {
        if i < self.len {
            self.storage.get(i)
        } else {
            None
        }
    }

    /// Returns the last entry this history sees.
    pub fn last(&self) -> Option<&T> {
        self.len.checked_sub(1).and_then(|i| self.get(i))
    }

    /// Returns the entries this history sees, oldest first.
    pub fn iter(&self) -> Iter<'_, T> {
        self.iter_from(0)
    }

    /// Returns the entries from `start` on, oldest first (none when `start` is at or
    /// past the end). Finding `start` takes constant time: the entries before it are not
    /// walked, so the last few entries of a long history cost only themselves.
    pub fn iter_from(&self, start: usize) -> Iter<'_, T> {
        let start = start.min(self.len);
        let (s, slot) = Storage::<T>::slot_of(start);
        // The segment of `start` is unallocated only when `start` is the end.
        let slots = self.storage.segments[s]
            .get()
            .and_then(|segment| segment.get(slot..))
            .unwrap_or_default();
        Iter {
            segments: self.storage.segments.get(s + 1..).unwrap_or_default(),
            slots,
            remaining: self.len - start,
        }
    }
}

impl<'a, T> IntoIterator for &'a History<T> {
    type Item = &'a T;
    type IntoIter = Iter<'a, T>;

    fn into_iter(self) -> Iter<'a, T> {
        self.iter()
    }
}

impl<T: PartialEq> PartialEq for History<T> {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl<T: fmt::Debug> fmt::Debug for History<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// The entries of a [`History`], oldest first: a walk along each segment's slots in
/// turn.
pub struct Iter<'a, T> {
    /// The segments after the one `slots` is in.
    segments: &'a [OnceLock<Segment<T>>],
    /// The slots left in the current segment.
    slots: &'a [OnceLock<T>],
    /// The entries left to yield.
    remaining: usize,
}

impl<'a, T> Iter<'a, T> {
    /// Returns the next entry, or `None` at a slot that is not written, which cannot
    /// happen before `remaining` runs out: a history sees only written entries.
    fn step(&mut self) -> Option<&'a T> {
        if self.slots.is_empty() {
            let (segment, rest) = self.segments.split_first()?;
            self.slots = &**segment.get()?;
            self.segments = rest;
        }
        let (slot, rest) = self.slots.split_first()?;
        self.slots = rest;
        slot.get()
    }
}

impl<'a, T> Iterator for Iter<'a, T> {
    type Item = &'a T;

    fn next(&mut self) -> Option<&'a T> {
        if self.remaining == 0 {
            return None;
        }
        let entry = self.step();
        self.remaining = if entry.is_some() {
            self.remaining - 1
        } else {
            0
        };
        entry
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.remaining, Some(self.remaining))
    }
}

impl<T> ExactSizeIterator for Iter<'_, T> {}

impl<T> std::iter::FusedIterator for Iter<'_, T> {}

/// The one writer of a history: appends entries and hands out snapshots
/// ([`HistoryWriter::history`], cloned), each of which sees the entries appended before
/// it was taken.
pub struct HistoryWriter<T> {
    history: History<T>,
}

impl<T> Default for HistoryWriter<T> {
    fn default() -> Self {
        HistoryWriter {
            history: History::default(),
        }
    }
}

impl<T> HistoryWriter<T> {
    /// Returns a writer of an empty history.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends an entry after the last. Snapshots taken before do not see it.
    pub fn push(&mut self, entry: T) {
        let history = &mut self.history;
        let (s, slot) = Storage::<T>::slot_of(history.len);
        let segment = history.storage.segments[s]
            .get_or_init(|| std::iter::repeat_with(OnceLock::new).take(1 << s).collect());
        // This writer is the only one of its storage and has written slots 0 .. len
        // only, so the slot is empty.
        let written = segment[slot].set(entry);
        debug_assert!(written.is_ok(), "entry {} was written twice", history.len);
        history.len += 1;
    }

    /// Returns the history so far, every entry appended; clone it for a snapshot that
    /// outlives later appends.
    pub fn history(&self) -> &History<T> {
        &self.history
    }

    /// Returns the number of entries appended.
    pub fn len(&self) -> usize {
        self.history.len
    }

    /// Returns whether no entry has been appended.
    pub fn is_empty(&self) -> bool {
        self.history.is_empty()
    }
}

impl<T> Extend<T> for HistoryWriter<T> {
    fn extend<I: IntoIterator<Item = T>>(&mut self, entries: I) {
        for entry in entries {
            self.push(entry);
        }
    }
}

impl<T> FromIterator<T> for HistoryWriter<T> {
    fn from_iter<I: IntoIterator<Item = T>>(entries: I) -> Self {
        let mut writer = HistoryWriter::new();
        writer.extend(entries);
        writer
    }
}

impl<T: fmt::Debug> fmt::Debug for HistoryWriter<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.history.fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row like the comparison's: a time and some values.
    fn row(k: usize) -> (f64, Vec<f64>) {
        (k as f64 * 0.5, vec![k as f64, -(k as f64)])
    }

    #[test]
    fn each_snapshot_sees_the_entries_up_to_its_own_and_no_later_one() {
        let mut writer = HistoryWriter::new();
        assert!(writer.is_empty() && writer.history().last().is_none());
        let mut snapshots = Vec::new();
        // 100 entries fill segments 0 to 5 and part of segment 6, so entries on both
        // sides of every boundary are read back.
        for k in 0..100 {
            writer.push(row(k));
            snapshots.push(writer.history().clone());
        }
        for (k, snapshot) in snapshots.iter().enumerate() {
            assert_eq!(snapshot.len(), k + 1);
            let expected: Vec<(f64, Vec<f64>)> = (0..=k).map(row).collect();
            let seen: Vec<(f64, Vec<f64>)> = snapshot.iter().cloned().collect();
            assert_eq!(seen, expected, "snapshot {k}");
            assert_eq!(snapshot.iter().len(), k + 1);
            assert_eq!(snapshot.last(), Some(&row(k)));
            assert_eq!(snapshot.get(k), Some(&row(k)));
            // Entries appended after the snapshot are in the shared storage, yet unseen.
            assert_eq!(snapshot.get(k + 1), None);
        }
        assert_eq!(&snapshots[99], writer.history());
        assert_ne!(&snapshots[98], writer.history());
    }

    #[test]
    fn entries_map_to_segments_of_doubling_size() {
        let slots: Vec<(usize, usize)> = (0..8).map(Storage::<u8>::slot_of).collect();
        assert_eq!(
            slots,
            [
                (0, 0),
                (1, 0),
                (1, 1),
                (2, 0),
                (2, 1),
                (2, 2),
                (2, 3),
                (3, 0)
            ]
        );
    }

    #[test]
    fn iterating_from_any_start_yields_exactly_the_entries_from_there() {
        let writer: HistoryWriter<usize> = (0..70).collect();
        let history = writer.history();
        for start in 0..=72 {
            let expected: Vec<usize> = (start.min(70)..70).collect();
            let seen: Vec<usize> = history.iter_from(start).copied().collect();
            assert_eq!(seen, expected, "from {start}");
            assert_eq!(
                history.iter_from(start).len(),
                expected.len(),
                "from {start}"
            );
        }
        // A snapshot that ends on a segment boundary (7 entries fill segments 0 to 2)
        // stops there although the storage holds more.
        let mut writer = HistoryWriter::new();
        writer.extend(0..7u32);
        let seven = writer.history().clone();
        writer.extend(7..20);
        assert_eq!(
            seven.iter().copied().collect::<Vec<_>>(),
            (0..7).collect::<Vec<_>>()
        );
        assert_eq!(seven.iter_from(7).next(), None);
        assert_eq!(seven.iter_from(5).copied().collect::<Vec<_>>(), [5, 6]);
    }

    #[test]
    fn an_empty_history_has_nothing_to_walk() {
        let empty = History::<u8>::default();
        assert_eq!(empty.iter().next(), None);
        assert_eq!(empty.iter_from(3).next(), None);
        assert_eq!((empty.len(), empty.last(), empty.get(0)), (0, None, None));
        assert_eq!(empty, HistoryWriter::new().history().clone());
    }

    #[test]
    fn snapshots_cross_threads_and_outlive_their_writer() {
        let mut writer = HistoryWriter::new();
        let mut handles = Vec::new();
        for k in 0..40u64 {
            writer.push(Arc::<[u64]>::from(vec![k, k * k]));
            let snapshot = writer.history().clone();
            handles.push(std::thread::spawn(move || {
                snapshot.iter().map(|e| e[1]).sum::<u64>()
            }));
        }
        drop(writer);
        for (k, handle) in handles.into_iter().enumerate() {
            let k = k as u64;
            let expected: u64 = (0..=k).map(|j| j * j).sum();
            assert_eq!(handle.join().ok(), Some(expected), "snapshot {k}");
        }
    }
}
