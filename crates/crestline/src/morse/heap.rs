//! Priority queues for the cancellation loop.

use rayon::slice::ParallelSliceMut;

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

    /// The greatest item.
    pub fn peek(&self) -> Option<&T> {
        self.items.first()
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

/// A max-priority queue whose first items arrive together: they are sorted once
/// and read off in order, and only the items pushed later go into a
/// [`QuaternaryHeap`]. Popping one of the first items then reads memory in
/// sequence instead of missing the cache on each level of a large heap, and the
/// heap holds only the later items. Items come out in the order one heap of them
/// all would give.
pub struct SeededQueue<T> {
    /// The first items, increasing: the greatest is the last.
    initial: Vec<T>,
    heap: QuaternaryHeap<T>,
}

impl<T: Ord + Copy + Send> SeededQueue<T> {
    /// A queue of `initial`, with room for as many later items.
    pub fn new(mut initial: Vec<T>) -> SeededQueue<T> {
        initial.par_sort_unstable();
        let heap = QuaternaryHeap::with_capacity(initial.len());
        SeededQueue { initial, heap }
    }

    /// Add `item`.
    pub fn push(&mut self, item: T) {
        self.heap.push(item);
    }

    /// Remove and return the greatest item.
    pub fn pop(&mut self) -> Option<T> {
        match (self.initial.last(), self.heap.peek()) {
            (Some(first), Some(later)) if later > first => self.heap.pop(),
            (Some(_), _) => self.initial.pop(),
            (None, _) => self.heap.pop(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_the_initial_and_the_pushed_items_in_one_order() {
        // A pseudo-random mix of keys, with repeats, pushed between pops.
        let mut x: u64 = 0x9e37_79b9;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % 1000
        };
        let initial: Vec<u64> = (0..500).map(|_| next()).collect();
        let mut queue = SeededQueue::new(initial.clone());
        let mut reference = std::collections::BinaryHeap::from(initial);
        for step in 0..2000 {
            if step % 3 != 0 {
                let item = next();
                queue.push(item);
                reference.push(item);
            } else {
                assert_eq!(queue.pop(), reference.pop(), "pop {step}");
            }
        }
        while let Some(item) = reference.pop() {
            assert_eq!(queue.pop(), Some(item));
        }
        assert_eq!(queue.pop(), None);
    }
}
