//! A set of the samples of a grid, one bit per sample, that numbers its members in
//! linear order: data kept only at the members (the curvature at the corners of
//! the cells an isosurface crosses) lives in one dense array indexed by that number.

use std::ops::Range;

/// Bits per word of the set.
const WORD: usize = 64;

/// Grows a [`VoxelSet`] one member at a time.
#[derive(Clone, Debug)]
pub(crate) struct VoxelSetBuilder {
    words: Vec<u64>,
    len: usize,
}

impl VoxelSetBuilder {
    /// An empty set of the samples `0..len`.
    pub fn new(len: usize) -> VoxelSetBuilder {
        VoxelSetBuilder {
            words: vec![0; len.div_ceil(WORD)],
            len,
        }
    }

    /// The samples `at` of `0..len` where `member(at)`, decided in parallel, 64 at a
    /// time.
    pub fn from_fn(len: usize, member: impl Fn(usize) -> bool + Sync) -> VoxelSetBuilder {
        use rayon::prelude::*;
        let words = (0..len.div_ceil(WORD))
            .into_par_iter()
            .map(|w| {
                let samples = w * WORD..((w + 1) * WORD).min(len);
                samples.fold(0u64, |word, at| {
                    word | (u64::from(member(at)) << (at % WORD))
                })
            })
            .collect();
        VoxelSetBuilder { words, len }
    }

    /// Every sample of `0..len`.
    pub fn full(len: usize) -> VoxelSetBuilder {
        let mut words = vec![u64::MAX; len.div_ceil(WORD)];
        if let Some(last) = words.last_mut() {
            let used = len - (len.div_ceil(WORD) - 1) * WORD;
            if used < WORD {
                *last = (1 << used) - 1;
            }
        }
        VoxelSetBuilder { words, len }
    }

    /// Adds sample `at` (below the length given to [`VoxelSetBuilder::new`]).
    #[inline]
    pub fn insert(&mut self, at: usize) {
        debug_assert!(at < self.len);
        self.words[at / WORD] |= 1 << (at % WORD);
    }

    /// The set, its members numbered.
    pub fn build(self) -> VoxelSet {
        let mut before = Vec::with_capacity(self.words.len() + 1);
        let mut count = 0;
        for word in &self.words {
            before.push(count);
            count += word.count_ones() as usize;
        }
        before.push(count);
        VoxelSet {
            words: self.words,
            before,
        }
    }
}

/// A set of samples with each member's number: how many members come before it.
#[derive(Clone, Debug)]
pub(crate) struct VoxelSet {
    words: Vec<u64>,
    /// The number of members before each word, and the total last.
    before: Vec<usize>,
}

impl VoxelSet {
    /// The number of members.
    pub fn len(&self) -> usize {
        self.before[self.words.len()]
    }

    /// Whether `at` is a member.
    #[inline]
    pub fn contains(&self, at: usize) -> bool {
        self.words
            .get(at / WORD)
            .is_some_and(|word| word >> (at % WORD) & 1 == 1)
    }

    /// The number of member `at` (0 for the first), or `None` if `at` is not one.
    #[inline]
    pub fn number(&self, at: usize) -> Option<usize> {
        let word = *self.words.get(at / WORD)?;
        let bit = at % WORD;
        (word >> bit & 1 == 1)
            .then(|| self.before[at / WORD] + (word & ((1 << bit) - 1)).count_ones() as usize)
    }

    /// The members in `range`, in increasing order.
    pub fn members(&self, range: Range<usize>) -> impl Iterator<Item = usize> + '_ {
        let words = range.start / WORD..range.end.div_ceil(WORD).min(self.words.len());
        words
            .flat_map(move |w| {
                let mut bits = self.words[w];
                std::iter::from_fn(move || {
                    (bits != 0).then(|| {
                        let bit = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        w * WORD + bit
                    })
                })
            })
            .filter(move |at| range.contains(at))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn members_are_numbered_in_order_across_words() {
        let members = [0, 5, 63, 64, 65, 127, 128, 300, 999];
        let mut builder = VoxelSetBuilder::new(1000);
        for &at in members.iter().rev() {
            builder.insert(at);
        }
        builder.insert(64);
        let set = builder.build();
        assert_eq!(set.len(), members.len());
        for (n, &at) in members.iter().enumerate() {
            assert_eq!(set.number(at), Some(n), "sample {at}");
        }
        let others = (0..1000).filter(|at| !members.contains(at));
        assert!(others.clone().all(|at| set.number(at).is_none()));
        assert_eq!(set.number(1000), None);
        assert_eq!(set.members(0..1000).collect::<Vec<_>>(), members);
        assert_eq!(
            set.members(5..128).collect::<Vec<_>>(),
            [5, 63, 64, 65, 127]
        );
        assert_eq!(set.members(301..999).count(), 0);
        let odd = VoxelSetBuilder::from_fn(1000, |at| at % 2 == 1).build();
        assert_eq!(odd.len(), 500);
        assert!(odd.contains(999) && !odd.contains(998) && !odd.contains(1000));
        for len in [0, 1, 63, 64, 65, 130] {
            let full = VoxelSetBuilder::full(len).build();
            assert_eq!(full.len(), len);
            assert_eq!(full.members(0..len + 70).count(), len);
            assert_eq!(full.number(len.saturating_sub(1)), len.checked_sub(1));
        }
    }
}
