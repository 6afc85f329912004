//! Grouping items by a small integer key in linear time (a counting sort).

use rayon::prelude::*;

/// Items `0..n` grouped by a key in `0..key_count`: the items with key `k` are
/// [`Buckets::get`]`(k)`, in increasing item order.
pub(crate) struct Buckets {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Buckets {
    /// Group the items by `keys[item]`; every key must be below `key_count`.
    pub(crate) fn new(key_count: usize, keys: &[u32]) -> Buckets {
        let mut start = vec![0u32; key_count + 1];
        for &k in keys {
            start[k as usize + 1] += 1;
        }
        for k in 0..key_count {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; keys.len()];
        for (item, &k) in keys.iter().enumerate() {
            items[fill[k as usize] as usize] = item as u32;
            fill[k as usize] += 1;
        }
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
        let parts: Vec<Groups> = (0..buckets.div_ceil(chunk))
            .into_par_iter()
            .map(|part| {
                let mut groups = Groups::default();
                let mut keyed: Vec<(K, u32)> = Vec::new();
                for k in part * chunk..((part + 1) * chunk).min(buckets) {
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
        Groups::concatenated(parts)
    }

    /// The non-empty buckets, in key order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.start
            .windows(2)
            .filter(|w| w[1] > w[0])
            .map(|w| &self.items[w[0] as usize..w[1] as usize])
    }
}

/// Groups of items, stored flat: group `g` is `items[ends[g - 1]..ends[g]]`.
#[derive(Default)]
pub(crate) struct Groups {
    items: Vec<u32>,
    ends: Vec<u32>,
}

impl Groups {
    /// The groups of `parts`, one after the other.
    fn concatenated(parts: Vec<Groups>) -> Groups {
        let mut all = Groups::default();
        for part in parts {
            let offset = all.items.len() as u32;
            all.items.extend(part.items);
            all.ends.extend(part.ends.iter().map(|e| e + offset));
        }
        all
    }

    /// The groups, in order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
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
