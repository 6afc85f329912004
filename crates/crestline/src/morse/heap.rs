//! A priority queue for the cancellation loop.

/// A max-heap like [`std::collections::BinaryHeap`] (push, pop), stored as a
/// 4-ary tree: half as many levels as a binary heap, and the four children of a
/// node side by side in memory. Popping from a large queue is bound by the memory
/// latency of each level, so fewer levels make it faster.
pub struct QuaternaryHeap<T> {
    items: Vec<T>,
}

impl<T: Ord + Copy> QuaternaryHeap<T> {
    /// An empty heap with room for `capacity` items.
    pub fn with_capacity(capacity: usize) -> QuaternaryHeap<T> {
        QuaternaryHeap {
            items: Vec::with_capacity(capacity),
        }
    }

    /// Add `item`.
    pub fn push(&mut self, item: T) {
        let mut hole = self.items.len();
        self.items.push(item);
        while hole > 0 {
            let parent = (hole - 1) / 4;
            if self.items[parent] >= item {
                break;
            }
            self.items[hole] = self.items[parent];
            hole = parent;
        }
        self.items[hole] = item;
    }

    /// Remove and return the greatest item.
    pub fn pop(&mut self) -> Option<T> {
        let last = self.items.pop()?;
        let Some(&top) = self.items.first() else {
            return Some(last);
        };
        self.sift_down(last);
        Some(top)
    }

    /// Put `item` in the hole left at the root, moving greater children up.
    fn sift_down(&mut self, item: T) {
        let n = self.items.len();
        let mut hole = 0;
        loop {
            let first = 4 * hole + 1;
            if first >= n {
                break;
            }
            let children = first..(first + 4).min(n);
            let greatest = children
                .reduce(|a, b| if self.items[b] > self.items[a] { b } else { a })
                .unwrap_or(first);
            if self.items[greatest] <= item {
                break;
            }
            self.items[hole] = self.items[greatest];
            hole = greatest;
        }
        self.items[hole] = item;
    }
}
