//! A map from Gmsh tags (node or element numbers) to dense indices.
//!
//! Gmsh numbers nodes and elements contiguously in practice, and announces the tag range in the
//! section header, so the map is a plain vector over that range (one load per lookup) with a
//! hash map for tags outside it. The announced range is only a hint: a file that lies about it
//! still reads correctly, just slower. The vector's length is capped (by the caller, from the
//! file size) so a garbled header cannot make it allocate without bound.

use std::collections::HashMap;

const NONE: usize = usize::MAX;

/// Tag -> index.
#[derive(Default)]
pub(super) struct TagMap {
    lo: u64,
    dense: Vec<usize>,
    sparse: HashMap<u64, usize>,
}

impl TagMap {
    /// A map expecting `count` tags in `[lo, hi]`, whose dense part holds at most `cap` entries.
    pub fn with_range(lo: u64, hi: u64, count: usize, cap: usize) -> Self {
        let span = hi.checked_sub(lo).and_then(|s| s.checked_add(1));
        let dense_len = match span.and_then(|s| usize::try_from(s).ok()) {
            // Dense only when the range is not much sparser than the count it holds.
            Some(s) if s <= cap && s <= count.saturating_mul(4).saturating_add(1024) => s,
            _ => 0,
        };
        TagMap { lo, dense: vec![NONE; dense_len], sparse: HashMap::new() }
    }

    fn slot(&self, tag: u64) -> Option<usize> {
        let off = usize::try_from(tag.checked_sub(self.lo)?).ok()?;
        (off < self.dense.len()).then_some(off)
    }

    /// Inserts `tag -> index`; `false` (and no change) if `tag` is already present.
    pub fn insert(&mut self, tag: u64, index: usize) -> bool {
        match self.slot(tag) {
            Some(s) if self.dense[s] == NONE => {
                self.dense[s] = index;
                true
            }
            Some(_) => false,
            None => match self.sparse.entry(tag) {
                std::collections::hash_map::Entry::Occupied(_) => false,
                std::collections::hash_map::Entry::Vacant(v) => {
                    v.insert(index);
                    true
                }
            },
        }
    }

    /// The index of `tag`.
    #[inline]
    pub fn get(&self, tag: u64) -> Option<usize> {
        match self.slot(tag) {
            Some(s) => (self.dense[s] != NONE).then_some(self.dense[s]),
            None => self.sparse.get(&tag).copied(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_and_sparse_tags_map_and_detect_duplicates() {
        let mut m = TagMap::with_range(10, 12, 3, 100);
        assert!(m.insert(10, 0));
        assert!(m.insert(12, 1));
        assert!(m.insert(1_000_000, 2)); // outside the announced range: the hash part
        assert!(m.insert(3, 3)); // below it
        assert!(!m.insert(12, 9));
        assert!(!m.insert(1_000_000, 9));
        assert_eq!(m.get(10), Some(0));
        assert_eq!(m.get(11), None);
        assert_eq!(m.get(12), Some(1));
        assert_eq!(m.get(1_000_000), Some(2));
        assert_eq!(m.get(3), Some(3));
        assert_eq!(m.get(u64::MAX), None);
    }

    #[test]
    fn absurd_ranges_stay_sparse() {
        let m = TagMap::with_range(0, u64::MAX, 5, 1 << 20);
        assert!(m.dense.is_empty());
        let m = TagMap::with_range(9, 1, 5, 1 << 20);
        assert!(m.dense.is_empty());
    }
}
