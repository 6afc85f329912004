//! Grouping items by a small integer key in linear time (a counting sort).

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

    /// The non-empty buckets, in key order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.start
            .windows(2)
            .filter(|w| w[1] > w[0])
            .map(|w| &self.items[w[0] as usize..w[1] as usize])
    }
}
