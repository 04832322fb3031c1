//! The resting contacts' warm start: the impulses each contact point needed last step,
//! keyed by the two colliders' indices and the point's features.
//!
//! It is kept as a list sorted by key, each key once, rather than as a map: the solver
//! stores a step's points in the order of its manifolds, which are already in the
//! order of their pairs (i, j), so the list is built by appending, with no tree to
//! rebalance and nothing to allocate once it has grown; and it is read back through a
//! walk along the manifolds. The order is the one a sorted map would give, so what a checkpoint
//! writes does not depend on which of the two holds it.

/// A point's key: (collider i, collider j, the point's features).
pub type Key = (u32, u32, u64);

/// The impulses a contact point needed, kept for the next step: the normal and the
/// tangential accumulated impulses, keyed by the two colliders' indices and the point's
/// features. The keys are in increasing order, each once.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WarmStart {
    entries: Vec<(Key, (f64, f64))>,
}

impl WarmStart {
    /// Returns an empty warm start.
    pub fn new() -> Self {
        WarmStart::default()
    }

    /// Forgets every point, keeping the list's room.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Returns how many points are kept.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Returns whether no point is kept.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Returns a reader of the kept points, for looking them up in pair order.
    pub fn reader(&self) -> Reader<'_> {
        Reader {
            entries: &self.entries,
            at: 0,
        }
    }

    /// Keeps the impulses `value` for `key`, replacing what was kept for it, as a map's
    /// insert does. A key after every kept one (the points of manifolds in pair order)
    /// is appended; any other (the second point of a manifold whose features come
    /// first) is put in its place.
    #[inline]
    pub fn insert(&mut self, key: Key, value: (f64, f64)) {
        match self.entries.last() {
            Some((last, _)) if *last >= key => {
                match self.entries.binary_search_by(|(k, _)| k.cmp(&key)) {
                    Ok(at) => self.entries[at].1 = value,
                    Err(at) => self.entries.insert(at, (key, value)),
                }
            }
            _ => self.entries.push((key, value)),
        }
    }

    /// Returns the points in increasing order of their keys.
    pub fn iter(&self) -> impl Iterator<Item = (&Key, &(f64, f64))> {
        self.entries.iter().map(|(k, v)| (k, v))
    }
}

/// Looks up kept points by walking the list along with keys that come in increasing
/// order of their pairs (the manifolds' order), so that a step's lookups together cost
/// one pass over the list; a key whose pair comes before the last one asked for is
/// found by a binary search instead.
pub struct Reader<'a> {
    entries: &'a [(Key, (f64, f64))],
    /// Where the pair last asked for starts, or where it would.
    at: usize,
}

impl Reader<'_> {
    /// Returns the impulses kept for `key`, if any.
    #[inline]
    pub fn get(&mut self, key: &Key) -> Option<(f64, f64)> {
        let pair = (key.0, key.1);
        let of = |e: &(Key, (f64, f64))| (e.0 .0, e.0 .1);
        if self.at > 0 && of(&self.entries[self.at - 1]) >= pair {
            // Behind the walk: search the whole list.
            self.at = self.entries.partition_point(|e| of(e) < pair);
        } else {
            while self.at < self.entries.len() && of(&self.entries[self.at]) < pair {
                self.at += 1;
            }
        }
        self.entries[self.at..]
            .iter()
            .take_while(|e| of(e) == pair)
            .find(|e| e.0 .2 == key.2)
            .map(|e| e.1)
    }
}

impl FromIterator<(Key, (f64, f64))> for WarmStart {
    /// Returns the warm start holding these points, the last one for a key repeated.
    fn from_iter<I: IntoIterator<Item = (Key, (f64, f64))>>(points: I) -> Self {
        let mut warm = WarmStart::new();
        for (key, value) in points {
            warm.insert(key, value);
        }
        warm
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn holds_what_a_sorted_map_holds_in_the_same_order() {
        // Keys in pair order with the two points of a pair in either order, a key
        // repeated, and a few out of order altogether.
        let keys: Vec<Key> = vec![
            (0, 1, 5),
            (0, 1, 3),
            (0, 2, 7),
            (0, 2, 7),
            (1, 2, 1 << 33),
            (1, 2, 4),
            (0, 1, 4),
            (3, 9, 0),
            (2, 9, 0),
        ];
        let mut map = BTreeMap::new();
        let mut warm = WarmStart::new();
        for (n, &key) in keys.iter().enumerate() {
            let value = (n as f64, -(n as f64));
            map.insert(key, value);
            warm.insert(key, value);
        }
        let from_map: Vec<_> = map.iter().map(|(k, v)| (*k, *v)).collect();
        let from_warm: Vec<_> = warm.iter().map(|(k, v)| (*k, *v)).collect();
        assert_eq!(from_map, from_warm);
        // Looked up in any order, through one reader.
        let mut reader = warm.reader();
        for key in keys.iter().chain(&[(0, 1, 6), (9, 9, 9), (0, 0, 0)]) {
            assert_eq!(map.get(key).copied(), reader.get(key), "{key:?}");
        }
        let collected: WarmStart = keys.iter().map(|&k| (k, (1.0, 2.0))).collect();
        assert_eq!(collected.len(), map.len());
        warm.clear();
        assert!(warm.is_empty() && warm.reader().get(&(0, 1, 5)).is_none());
    }
}
