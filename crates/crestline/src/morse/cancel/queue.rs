//! The keys of the cancellation queue: a saddle's candidacy in an extremum's heap
//! and an extremum set's entry in the global queue, ordered so that ties break
//! the same way on every run.

use std::cmp::Ordering;

use super::extrema::Kind;

/// A cancellation candidate in an extremum's heap: saddle `id >> 1` with the
/// extremum at the end of its branch `id & 1`, smallest `key` first (then by saddle
/// and branch). `far` is the extremum (set element) at the end of the saddle's other
/// branch of the same kind, the boundary for a missing ascending branch.
#[derive(Clone, Copy)]
pub(super) struct Candidate {
    pub(super) key: f64,
    pub(super) id: u32,
    pub(super) far: u32,
}

impl Candidate {
    pub(super) fn new(key: f64, saddle: usize, branch: usize, far: u32) -> Candidate {
        debug_assert!(saddle < 1 << 31);
        Candidate {
            key,
            id: (saddle as u32) << 1 | branch as u32,
            far,
        }
    }

    pub(super) fn saddle(&self) -> usize {
        (self.id >> 1) as usize
    }

    pub(super) fn branch(&self) -> usize {
        (self.id & 1) as usize
    }
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Candidate {}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        other.key.total_cmp(&self.key).then(other.id.cmp(&self.id))
    }
}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A queue entry: the best score of an extremum set when queued. Never above the
/// set's current best: every change that can lower it queues a new entry, and an
/// entry whose set improved is re-queued when popped. A set has one entry that
/// counts, the lowest since it was last popped ([`SetState::queued`]): a higher
/// score is not queued, as the set is looked at anew at its lower entry anyway,
/// and the entries a lower one superseded are dropped when popped.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub(super) t: f64,
    /// The set, with the kind in the top bit (minima first), so that an entry
    /// takes 16 bytes.
    pub(super) slot: u32,
}

impl Entry {
    /// The entry of set `set` of `kind` at score `t`.
    pub(super) fn new(t: f64, kind: Kind, set: u32) -> Entry {
        debug_assert!(set < 1 << 31);
        Entry {
            t,
            slot: (kind as u32) << 31 | set,
        }
    }

    pub(super) fn kind(&self) -> Kind {
        if self.slot >> 31 == 0 {
            Kind::Minimum
        } else {
            Kind::Maximum
        }
    }

    pub(super) fn set(&self) -> usize {
        (self.slot & !(1 << 31)) as usize
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

impl Ord for Entry {
    /// By key (t, kind, set), smallest first (the queue is a max-heap).
    fn cmp(&self, other: &Self) -> Ordering {
        other.t.total_cmp(&self.t).then(other.slot.cmp(&self.slot))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
