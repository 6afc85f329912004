//! Grouping items by a small integer key in linear time (a counting sort).

use std::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;

/// How many pieces [`Buckets::new`] sorts in parallel: one per thread, at most four
/// (every piece holds a count per key), and one for small inputs.
fn sort_pieces(items: usize) -> usize {
    if items < 1 << 16 {
        1
    } else {
        rayon::current_num_threads().clamp(1, 4)
    }
}

/// Items `0..n` grouped by a key in `0..key_count`: the items with key `k` are
/// [`Buckets::get`]`(k)`, in increasing item order.
pub(crate) struct Buckets {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Buckets {
    /// Group the items by `keys[item]`; every key must be below `key_count`.
    ///
    /// A counting sort in parallel: each of a few pieces of the items counts its
    /// keys, and places its items after those of the pieces before it, so the
    /// items of a bucket stay in increasing order.
    pub(crate) fn new(key_count: usize, keys: &[u32]) -> Buckets {
        let piece = keys.len().div_ceil(sort_pieces(keys.len())).max(1);
        // Per piece, the count of every key, then where its next item of that key goes.
        let mut next: Vec<Vec<u32>> = keys
            .par_chunks(piece)
            .map(|keys| {
                let mut count = vec![0u32; key_count];
                for &k in keys {
                    count[k as usize] += 1;
                }
                count
            })
            .collect();
        let mut start = Vec::with_capacity(key_count + 1);
        let mut total = 0u32;
        for k in 0..key_count {
            start.push(total);
            for counts in &mut next {
                let count = counts[k];
                counts[k] = total;
                total += count;
            }
        }
        start.push(total);
        let items: Vec<AtomicU32> = (0..keys.len())
            .into_par_iter()
            .map(|_| AtomicU32::new(0))
            .collect();
        keys.par_chunks(piece)
            .zip(next.par_iter_mut())
            .enumerate()
            .for_each(|(p, (keys, next))| {
                for (item, &k) in (p * piece..).zip(keys) {
                    // Each piece writes its own slots: no two writes meet.
                    items[next[k as usize] as usize].store(item as u32, Ordering::Relaxed);
                    next[k as usize] += 1;
                }
            });
        let items = items.into_iter().map(AtomicU32::into_inner).collect();
        Buckets { start, items }
    }

    /// The items with key `k`.
    pub(crate) fn get(&self, k: usize) -> &[u32] {
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }

    /// The groups of two or more items that share their bucket and `key(item)`,
    /// found in parallel over ranges of buckets: in bucket order, then key order,
    /// the items of a group in increasing order. Every other item is alone on its
    /// key (an edge with one face, a face with no twin).
    pub(crate) fn shared<K, F>(&self, key: F) -> Groups
    where
        K: Ord + Copy + Send,
        F: Fn(u32) -> K + Sync,
    {
        let buckets = self.start.len() - 1;
        let chunk = buckets.div_ceil(rayon::current_num_threads() * 16).max(1);
        let parts: Vec<Part> = (0..buckets.div_ceil(chunk))
            .into_par_iter()
            .map(|part| {
                let range = part * chunk..((part + 1) * chunk).min(buckets);
                // At most every item of the range is in a group.
                let most = (self.start[range.end] - self.start[range.start]) as usize;
                let mut groups = Part {
                    items: Vec::with_capacity(most),
                    ends: Vec::with_capacity(most / 2),
                };
                let mut keyed: Vec<(K, u32)> = Vec::new();
                for k in range {
                    keyed.clear();
                    keyed.extend(self.get(k).iter().map(|&item| (key(item), item)));
                    keyed.sort_unstable();
                    for same in keyed.chunk_by(|x, y| x.0 == y.0) {
                        if same.len() > 1 {
                            groups.items.extend(same.iter().map(|&(_, item)| item));
                            groups.ends.push(groups.items.len() as u32);
                        }
                    }
                }
                groups
            })
            .collect();
        Groups { parts }
    }

    /// The non-empty buckets, in key order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.start
            .windows(2)
            .filter(|w| w[1] > w[0])
            .map(|w| &self.items[w[0] as usize..w[1] as usize])
    }
}

/// Groups of items, in the pieces [`Buckets::shared`] found them in (kept apart
/// rather than copied into one array).
pub(crate) struct Groups {
    parts: Vec<Part>,
}

/// Groups stored flat: group `g` is `items[ends[g - 1]..ends[g]]`.
struct Part {
    items: Vec<u32>,
    ends: Vec<u32>,
}

impl Groups {
    /// The groups, in order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.parts.iter().flat_map(Part::groups)
    }

    /// The groups, in parallel (collected in order).
    pub(crate) fn par_iter(&self) -> impl ParallelIterator<Item = &[u32]> + '_ {
        self.parts.par_iter().flat_map_iter(Part::groups)
    }
}

impl Part {
    fn groups(&self) -> impl Iterator<Item = &[u32]> + '_ {
        std::iter::once(0)
            .chain(self.ends.iter().copied())
            .zip(&self.ends)
            .map(|(start, &end)| &self.items[start as usize..end as usize])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buckets_sorted_in_pieces_keep_every_item_in_order() {
        // Enough items for several pieces, on a pool of three threads.
        let n = 300_000u32;
        let keys: Vec<u32> = (0..n)
            .map(|i| i.wrapping_mul(2_654_435_761) % 997)
            .collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let buckets = pool.install(|| Buckets::new(1000, &keys));
        assert_eq!(pool.install(|| sort_pieces(keys.len())), 3);
        for k in 0..1000 {
            let expected: Vec<u32> = (0..n).filter(|&i| keys[i as usize] == k as u32).collect();
            assert_eq!(buckets.get(k), expected, "bucket {k}");
        }
    }

    #[test]
    fn shared_keys_are_grouped_in_bucket_then_key_order() {
        // Item i lies in bucket i % 7 with key i % 5: items share both when they
        // are equal modulo 35.
        let n = 2000u32;
        let buckets: Vec<u32> = (0..n).map(|i| i % 7).collect();
        let groups = Buckets::new(7, &buckets).shared(|i| i % 5);
        let found: Vec<Vec<u32>> = groups.iter().map(<[u32]>::to_vec).collect();
        let mut expected: Vec<(u32, u32, Vec<u32>)> = (0..35)
            .map(|r| (r % 7, r % 5, (r..n).step_by(35).collect()))
            .collect();
        expected.sort();
        let expected: Vec<Vec<u32>> = expected.into_iter().map(|(_, _, g)| g).collect();
        assert_eq!(found, expected);
        // Keys seen once make no group.
        assert_eq!(Buckets::new(7, &buckets).shared(|i| i).iter().count(), 0);
    }
}
