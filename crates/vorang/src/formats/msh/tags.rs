//! Gmsh tags → positions in file order. Tags may be sparse, but Gmsh numbers nodes and elements
//! 1…n as a rule, and every element names its nodes by tag: a hash lookup per node of every
//! element was a fifth of reading a large file. So tags up to about twice the count so far are
//! kept in a vector indexed by tag, and only tags far beyond go to a hash map. Which of the two
//! holds a tag changes nothing but speed: a lookup asks both.

use std::collections::HashMap;

/// Marks a tag the vector does not hold.
const NONE: u32 = u32::MAX;

/// Vector slots allowed beyond twice the entries, so that a small file's tags always fit.
const SLACK: usize = 1 << 12;

#[derive(Debug, Default)]
pub(super) struct TagIndex {
    dense: Vec<u32>,
    sparse: HashMap<u64, usize>,
    len: usize,
}

impl TagIndex {
    /// The position of `tag`, if it was inserted.
    pub(super) fn get(&self, tag: u64) -> Option<usize> {
        match usize::try_from(tag).ok().and_then(|t| self.dense.get(t)) {
            Some(&k) if k != NONE => Some(k as usize),
            _ => self.sparse.get(&tag).copied(),
        }
    }

    /// Records `tag` at `index`; false (and nothing changes) if the tag is there already.
    pub(super) fn insert(&mut self, tag: u64, index: usize) -> bool {
        if self.get(tag).is_some() {
            return false;
        }
        let bound = self.len.saturating_mul(2).saturating_add(SLACK);
        match usize::try_from(tag) {
            Ok(t) if t < bound && index < NONE as usize => {
                if t >= self.dense.len() {
                    // Grow by doubling at least, so that tags 1…n cost amortised O(1).
                    let want = (t + 1).max(self.dense.len() * 2).min(bound);
                    self.dense.resize(want, NONE);
                }
                self.dense[t] = index as u32;
            }
            _ => {
                self.sparse.insert(tag, index);
            }
        }
        self.len += 1;
        true
    }

    /// An index of `tags` by their position; a tag that repeats is found at its last.
    pub(super) fn of(tags: &[u64]) -> TagIndex {
        let mut index = TagIndex::default();
        for (i, &t) in tags.iter().enumerate() {
            if !index.insert(t, i) {
                match usize::try_from(t).ok().and_then(|t| index.dense.get_mut(t)) {
                    Some(k) if *k != NONE => *k = i as u32,
                    _ => {
                        index.sparse.insert(t, i);
                    }
                }
            }
        }
        index
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::SplitMix64;

    /// Against a hash map alone, on dense, shuffled, sparse and huge tags with repeats.
    #[test]
    fn finds_what_a_hash_map_finds() {
        let mut rng = SplitMix64(5);
        for case in 0..4 {
            let mut index = TagIndex::default();
            let mut reference = HashMap::new();
            for i in 0..20_000usize {
                let tag = match case {
                    0 => i as u64 + 1,
                    1 => rng.next_u64() % 25_000,
                    2 => rng.next_u64() % 1_000_000,
                    _ => rng.next_u64() >> (rng.next_u64() % 64),
                };
                let new = !reference.contains_key(&tag);
                if new {
                    reference.insert(tag, i);
                }
                assert_eq!(index.insert(tag, i), new, "case {case}, tag {tag}");
            }
            for t in 0..30_000u64 {
                assert_eq!(index.get(t), reference.get(&t).copied(), "case {case}");
            }
            for (&t, &k) in &reference {
                assert_eq!(index.get(t), Some(k));
            }
            assert!(index.dense.len() <= 2 * reference.len() + SLACK);
            let tags: Vec<u64> = (0..5000).map(|_| rng.next_u64() % 3000).collect();
            let last = TagIndex::of(&tags);
            for (i, &t) in tags.iter().enumerate() {
                assert_eq!(last.get(t), tags.iter().rposition(|&u| u == t), "{i}");
            }
        }
    }
}
