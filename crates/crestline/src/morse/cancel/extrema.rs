//! The extrema of one kind as disjoint sets that cancellations merge, each with
//! the state a cancellation reads: its region integral, its live links and its
//! heap of candidates (Sahner et al. 2008, §3.3–3.4); and the extrema at the ends
//! of every saddle's branches.

use std::collections::BinaryHeap;

use rayon::prelude::*;

use crate::mesh::Mesh;

use super::super::cells::{Integral, Saddle};
use super::super::disjoint::DisjointSets;
use super::super::gradient::Gradient;
use super::queue::{Candidate, Entry};

/// Extrema of one kind, merged by cancellations, numbered in id order (the initial
/// minima, or the initial maxima and then the boundary), so that the sets' arrays
/// are only as long as the extrema and set indices compare as element ids do
/// (queue ties are broken by set). Each set carries a [`SetState`].
pub(super) struct Extrema {
    pub(super) sets: DisjointSets,
    /// What each set carries, read together.
    pub(super) state: Vec<SetState>,
    /// The element (vertex or face id) of each index, increasing.
    pub(super) ids: Vec<u32>,
}

/// What an extremum set carries: the region integral, how many live saddle
/// branches end at it, its non-terminal cancellation candidates and its key in
/// the queue. Kept in one cache line, as a cancellation reads them together.
#[repr(align(64))]
pub(super) struct SetState {
    /// The candidates (s, e) whose branch ends at the set, keyed by the part of
    /// their score that does not depend on the extremum; see
    /// [`Scoring::offset`].
    pub(super) candidates: BinaryHeap<Candidate>,
    pub(super) region: Integral,
    pub(super) links: i64,
    /// The key of the set's entry in the queue, infinite if it has none: the
    /// only entry of the set that counts, others are outdated.
    pub(super) queued: f64,
    /// The surviving extremum (a vertex or face id) of the set.
    pub(super) survivor: u32,
}

impl Extrema {
    /// The extrema with the element ids `ids` and the regions `region` (indexed by
    /// element id).
    pub(super) fn new(ids: Vec<u32>, region: &[Integral]) -> Extrema {
        Extrema {
            sets: DisjointSets::new(ids.len()),
            state: ids
                .iter()
                .map(|&id| SetState {
                    candidates: BinaryHeap::new(),
                    region: region[id as usize],
                    links: 0,
                    queued: f64::INFINITY,
                    survivor: id,
                })
                .collect(),
            ids,
        }
    }

    pub(super) fn find(&self, x: u32) -> usize {
        self.sets.find(x) as usize
    }

    /// Merge the set of `gone` into that of `kept`; returns the new representative.
    pub(super) fn merge(&mut self, gone: usize, kept: usize) -> usize {
        let rep = self.sets.union(gone as u32, kept as u32) as usize;
        let other = if rep == kept { gone } else { kept };
        self.state[rep].region = self.state[rep].region.merged(self.state[other].region);
        self.state[rep].links += self.state[other].links;
        let mut moved = std::mem::take(&mut self.state[other].candidates);
        // `append` moves the smaller heap into the larger.
        self.state[rep].candidates.append(&mut moved);
        self.state[rep].survivor = self.state[kept].survivor;
        rep
    }

    /// Link the saddles to these extrema: `side(ends[s])` are the extrema at the
    /// ends of saddle s's two branches of this kind, `key(s)` its candidates' key.
    /// Counts each extremum's links and fills its heap of candidates, but at
    /// `skip` (the boundary).
    pub(super) fn link(
        &mut self,
        ends: &[Ends],
        side: impl Fn(&Ends) -> [u32; 2],
        key: impl Fn(usize) -> f64,
        skip: Option<u32>,
    ) {
        let kept = |end: &u32| Some(*end) != skip;
        // The links first, so that every heap is allocated once, at its size.
        for end in ends.iter().flat_map(&side).filter(kept) {
            self.state[end as usize].links += 1;
        }
        for state in &mut self.state {
            state.candidates.reserve_exact(state.links as usize);
        }
        for (s, pair) in ends.iter().map(&side).enumerate() {
            let key = key(s);
            for (branch, end) in pair.iter().enumerate().filter(|(_, end)| kept(end)) {
                let far = pair[1 - branch];
                self.state[*end as usize]
                    .candidates
                    .push(Candidate::new(key, s, branch, far));
            }
        }
    }

    /// The entry of set `m` (of `kind`) at `t`, now the one that counts, unless
    /// the set has a lower one.
    pub(super) fn claim_entry(&mut self, t: f64, kind: Kind, m: usize) -> Option<Entry> {
        let queued = &mut self.state[m].queued;
        (t < *queued).then(|| {
            *queued = t;
            Entry::new(t, kind, m as u32)
        })
    }

    /// The index of the tree of each set's surviving extremum.
    pub(super) fn survivor_trees(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.ids.len())
            .filter(|&m| self.find(m as u32) == m)
            .map(|m| {
                let survivor = self.state[m].survivor;
                self.ids.binary_search(&survivor).unwrap_or_else(|_| {
                    unreachable!("the survivor {survivor} is no initial extremum")
                })
            })
    }

    /// The best candidate of set `m` that is still a valid cancellation: its saddle
    /// is alive and its other branch ends at another set (see [`Hierarchy::valid`]).
    /// The candidates above it are dropped: they stay dead or invalid, as sets only
    /// merge.
    pub(super) fn best_valid(&mut self, m: usize, alive: &[bool]) -> Option<Candidate> {
        loop {
            let top = *self.state[m].candidates.peek()?;
            if alive[top.saddle()] && self.find(top.far) != m {
                return Some(top);
            }
            self.state[m].candidates.pop();
        }
    }
}

/// The two kinds of extrema.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Kind {
    Minimum,
    Maximum,
}

/// The extrema (set elements) at the ends of a saddle's branches: the minima at
/// the ends of its descending branches and the maxima at the ends of its ascending
/// ones, the boundary for a missing face. The current extremum of a branch is the
/// set its end lies in.
#[derive(Clone, Copy)]
pub(super) struct Ends {
    pub(super) minima: [u32; 2],
    pub(super) maxima: [u32; 2],
}

/// The extrema (set elements) at the ends of every saddle's branches: the minima
/// numbered in the order of `gradient.minima`, the maxima in that of
/// `gradient.maxima`, and the boundary after them.
pub(super) fn saddle_ends(mesh: &Mesh, gradient: &Gradient, saddles: &[Saddle]) -> Vec<Ends> {
    let numbering = |n: usize, ids: &mut dyn Iterator<Item = u32>| {
        let mut index = vec![u32::MAX; n];
        for (i, id) in ids.enumerate() {
            index[id as usize] = i as u32;
        }
        index
    };
    let minimum = numbering(
        mesh.vertex_count(),
        &mut gradient.minima.iter().map(|v| v.0),
    );
    let maximum = numbering(mesh.face_count(), &mut gradient.maxima.iter().map(|f| f.0));
    let boundary = gradient.maxima.len() as u32;
    saddles
        .par_iter()
        .map(|saddle| Ends {
            minima: saddle
                .vertices
                .map(|v| minimum[gradient.vertex_root[v.idx()].idx()]),
            maxima: saddle.faces.map(|f| {
                if f.is_valid() {
                    maximum[gradient.face_root[f.idx()].idx()]
                } else {
                    boundary
                }
            }),
        })
        .collect()
}
