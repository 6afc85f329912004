//! The cancellation hierarchy (Sahner et al. 2008, §2.1, §3.3–3.5): saddles are
//! cancelled against a neighbouring extremum in increasing order of a criterion,
//! either the feature-line-preserving significance of the paper or plain
//! persistence.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use petgraph::unionfind::UnionFind;

use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};

use super::cells::{Integral, Saddle};
use super::gradient::{EdgeRole, Gradient, Keys};

/// How saddles are ranked for cancellation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Criterion {
    /// The paper's significance: how much a line stands out from the regions it
    /// separates, with the terminal-extremum adjustments (eqs. 1–9).
    #[default]
    Feature,
    /// Persistence: the function difference between saddle and extremum.
    Persistence,
}

/// Which extremum a cancellation removes: the minimum or maximum at the end of
/// branch `0` or `1` of the saddle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    Minimum(usize),
    Maximum(usize),
}

/// One cancellation, as recorded in the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Cancellation {
    /// The saddle edge.
    pub saddle: u32,
    /// `"minimum"` (a vertex id) or `"maximum"` (a face id).
    pub extremum_kind: &'static str,
    pub extremum: u32,
    /// The criterion's value when cancelled.
    pub t: f64,
}

/// Extrema of one kind, merged by cancellations: each set carries the region
/// integral, how many live saddle branches end at it, and the saddles linked to it.
struct Extrema {
    sets: UnionFind<u32>,
    region: Vec<Integral>,
    links: Vec<i64>,
    linked: Vec<Vec<u32>>,
    /// The surviving extremum (a vertex or face id) of each set.
    survivor: Vec<u32>,
}

impl Extrema {
    fn new(mut region: Vec<Integral>, with_boundary: bool) -> Extrema {
        if with_boundary {
            // The boundary: where maxima cancelled against boundary saddles drain.
            region.push(Integral::default());
        }
        let n = region.len();
        Extrema {
            sets: UnionFind::new(n),
            region,
            links: vec![0; n],
            linked: vec![Vec::new(); n],
            survivor: (0..n as u32).collect(),
        }
    }

    fn find(&self, x: u32) -> usize {
        self.sets.find(x) as usize
    }

    /// Merge the set of `gone` into that of `kept`; returns the new representative.
    fn merge(&mut self, gone: usize, kept: usize) -> usize {
        self.sets.union(gone as u32, kept as u32);
        let rep = self.find(kept as u32);
        let other = if rep == kept { gone } else { kept };
        self.region[rep] = self.region[rep].merged(self.region[other]);
        self.links[rep] += self.links[other];
        let moved = std::mem::take(&mut self.linked[other]);
        self.linked[rep].extend(moved);
        self.survivor[rep] = self.survivor[kept];
        rep
    }
}

/// The two kinds of extrema.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Minimum,
    Maximum,
}

/// A queue entry: a saddle's score, valid while its version is current.
#[derive(Clone, Copy, PartialEq)]
struct Entry {
    t: f64,
    saddle: usize,
    version: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Smallest t first (BinaryHeap is a max-heap).
        other
            .t
            .total_cmp(&self.t)
            .then(other.saddle.cmp(&self.saddle))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The Morse-Smale complex under cancellation.
pub struct Hierarchy<'a> {
    mesh: &'a Mesh,
    keys: &'a Keys,
    pub gradient: Gradient,
    pub saddles: Vec<Saddle>,
    pub alive: Vec<bool>,
    minima: Extrema,
    maxima: Extrema,
    /// The index of the boundary in `maxima` (one past the faces).
    boundary: usize,
    criterion: Criterion,
    version: Vec<u32>,
    /// The score each saddle is queued under (+∞ if none).
    queued: Vec<f64>,
    queue: BinaryHeap<Entry>,
    /// The cancellations made, in order.
    pub cancelled: Vec<Cancellation>,
}

impl<'a> Hierarchy<'a> {
    /// The initial complex, every saddle scored and queued.
    pub fn new(
        mesh: &'a Mesh,
        keys: &'a Keys,
        gradient: Gradient,
        saddles: Vec<Saddle>,
        regions: (Vec<Integral>, Vec<Integral>),
        criterion: Criterion,
    ) -> Hierarchy<'a> {
        let (minimum_regions, maximum_regions) = regions;
        let n = saddles.len();
        let boundary = maximum_regions.len();
        let mut hierarchy = Hierarchy {
            mesh,
            keys,
            gradient,
            saddles,
            alive: vec![true; n],
            minima: Extrema::new(minimum_regions, false),
            maxima: Extrema::new(maximum_regions, true),
            boundary,
            criterion,
            version: vec![0; n],
            queued: vec![f64::INFINITY; n],
            queue: BinaryHeap::with_capacity(n),
            cancelled: Vec::new(),
        };
        for s in 0..n {
            for end in hierarchy.minimum_ends(s) {
                hierarchy.minima.links[end] += 1;
                hierarchy.minima.linked[end].push(s as u32);
            }
            for end in hierarchy.maximum_ends(s).into_iter().flatten() {
                hierarchy.maxima.links[end] += 1;
                hierarchy.maxima.linked[end].push(s as u32);
            }
        }
        // The boundary is never a terminal maximum.
        hierarchy.maxima.links[boundary] = i64::MAX / 2;
        for s in 0..n {
            hierarchy.requeue(s);
        }
        hierarchy
    }

    /// Number of live saddles.
    pub fn saddle_count(&self) -> usize {
        self.alive.iter().filter(|&&a| a).count()
    }

    /// Number of live minima and maxima.
    pub fn extremum_counts(&self) -> (usize, usize) {
        let boundary = self.maxima.find(self.boundary as u32);
        let live = |ex: &Extrema, roots: &[u32]| {
            let mut reps: Vec<usize> = roots
                .iter()
                .map(|&r| ex.find(r))
                .filter(|&r| r != boundary)
                .collect();
            reps.sort_unstable();
            reps.dedup();
            reps.len()
        };
        let minima: Vec<u32> = self.gradient.minima.iter().map(|v| v.0).collect();
        let maxima: Vec<u32> = self.gradient.maxima.iter().map(|f| f.0).collect();
        (live(&self.minima, &minima), live(&self.maxima, &maxima))
    }

    /// The current minimum (set representative) at the end of each descending branch.
    fn minimum_ends(&self, s: usize) -> [usize; 2] {
        self.saddles[s]
            .vertices
            .map(|v| self.minima.find(self.gradient.vertex_root[v.idx()].0))
    }

    /// The current maximum at the end of each ascending branch (none on the boundary).
    fn maximum_ends(&self, s: usize) -> [Option<usize>; 2] {
        self.saddles[s].faces.map(|f| {
            f.is_valid()
                .then(|| self.maxima.find(self.gradient.face_root[f.idx()].0))
        })
    }

    /// The lowest-scoring valid cancellation of saddle `s`, if any.
    pub fn best(&self, s: usize) -> Option<(f64, Partner)> {
        self.candidates(s, true)
            .into_iter()
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// The saddle's significance regardless of validity: its lowest score.
    pub fn significance(&self, s: usize) -> f64 {
        self.candidates(s, false)
            .into_iter()
            .map(|c| c.0)
            .fold(f64::INFINITY, f64::min)
    }

    /// Scored candidates of saddle `s` (only valid ones if `valid_only`).
    fn candidates(&self, s: usize, valid_only: bool) -> Vec<(f64, Partner)> {
        let saddle = &self.saddles[s];
        let mins = self.minimum_ends(s);
        let maxs = self.maximum_ends(s);
        let mut out = Vec::with_capacity(4);
        if !valid_only || mins[0] != mins[1] {
            for (i, &m) in mins.iter().enumerate() {
                out.push((self.score_minimum(saddle, i, m), Partner::Minimum(i)));
            }
        }
        // Two ascending branches must end at different maxima; a boundary saddle's
        // single branch may drain its maximum through the boundary.
        let boundary = self.maxima.find(self.boundary as u32);
        let valid = match maxs {
            [Some(a), Some(b)] => a != b,
            [Some(m), None] | [None, Some(m)] => m != boundary,
            [None, None] => false,
        };
        if !valid_only || valid {
            for (i, m) in maxs.iter().enumerate() {
                if let Some(m) = m.filter(|&m| m != boundary) {
                    out.push((self.score_maximum(saddle, i, m), Partner::Maximum(i)));
                }
            }
        }
        out
    }

    /// Score of cancelling the saddle with the minimum `m` at the end of branch `i`.
    fn score_minimum(&self, saddle: &Saddle, i: usize, m: usize) -> f64 {
        match self.criterion {
            Criterion::Persistence => {
                self.keys.edge[saddle.edge.idx()]
                    - self.keys.vertex[self.minima.survivor[m] as usize]
            }
            Criterion::Feature => {
                let region = self.minima.region[m].mean();
                // σ_max(r, m): how much the ascending line rises above the valley.
                let sigma = saddle.ascending_mean() - region;
                if self.minima.links[m] == 1 {
                    // Γ_min(v_i, m_i) for a terminal minimum.
                    sigma.min(region - saddle.descending[i].mean())
                } else {
                    sigma
                }
            }
        }
    }

    /// Score of cancelling the saddle with the maximum `m` at the end of branch `i`.
    fn score_maximum(&self, saddle: &Saddle, i: usize, m: usize) -> f64 {
        match self.criterion {
            Criterion::Persistence => {
                self.keys.face[self.maxima.survivor[m] as usize] - self.keys.edge[saddle.edge.idx()]
            }
            Criterion::Feature => {
                let region = self.maxima.region[m].mean();
                // σ_min(v, M): how far the descending line sinks below the hill.
                let sigma = region - saddle.descending_mean();
                if self.maxima.links[m] == 1 {
                    // Γ_max(r_i, M_i) for a terminal maximum.
                    sigma.min(saddle.ascending[i].mean() - region)
                } else {
                    sigma
                }
            }
        }
    }

    /// Re-score saddle `s` and queue it under a new version.
    fn requeue(&mut self, s: usize) {
        self.version[s] += 1;
        self.queued[s] = f64::INFINITY;
        if let Some((t, _)) = self.best(s) {
            self.queued[s] = t;
            self.queue.push(Entry {
                t,
                saddle: s,
                version: self.version[s],
            });
        }
    }

    /// Re-score the live saddles linked to extremum set `rep` and move those whose
    /// score dropped forward in the queue; raised scores are caught lazily when
    /// popped.
    fn rescore_linked(&mut self, kind: Kind, rep: usize) {
        let extrema = match kind {
            Kind::Minimum => &mut self.minima,
            Kind::Maximum => &mut self.maxima,
        };
        let alive = &self.alive;
        extrema.linked[rep].retain(|&x| alive[x as usize]);
        let linked = std::mem::take(&mut extrema.linked[rep]);
        for &x in &linked {
            let s = x as usize;
            let dropped = self
                .best(s)
                .is_some_and(|(t, _)| t < self.queued[s] - 1e-12 * t.abs());
            if dropped {
                self.requeue(s);
            }
        }
        match kind {
            Kind::Minimum => self.minima.linked[rep] = linked,
            Kind::Maximum => self.maxima.linked[rep] = linked,
        }
    }

    /// Cancel the next saddle in criterion order; `None` when no valid cancellation
    /// is left.
    pub fn cancel_next(&mut self) -> Option<Cancellation> {
        while let Some(entry) = self.queue.pop() {
            let s = entry.saddle;
            if !self.alive[s] || entry.version != self.version[s] {
                continue;
            }
            let Some((t, partner)) = self.best(s) else {
                continue;
            };
            // Lazy queue: a score that grew since it was queued (a region merged,
            // a candidate became invalid) goes back in the queue.
            if t > entry.t + 1e-12 * entry.t.abs().max(1e-300) {
                self.requeue(s);
                continue;
            }
            return Some(self.cancel(s, partner, t));
        }
        None
    }

    /// Cancel saddle `s` with `partner`: reverse the gradient along the branch to
    /// the extremum, make the saddle edge part of that forest, merge the extremum
    /// into the other branch's, and re-score the saddles of extrema that became
    /// terminal.
    fn cancel(&mut self, s: usize, partner: Partner, t: f64) -> Cancellation {
        self.alive[s] = false;
        let saddle = self.saddles[s].clone();
        let mins = self.minimum_ends(s);
        let maxs = self.maximum_ends(s);
        let mut touched_minima = Vec::new();
        let mut touched_maxima = Vec::new();
        let record = match partner {
            Partner::Minimum(i) => {
                self.reverse_vertex_path(saddle.vertices[i], saddle.edge);
                self.gradient.edge_role[saddle.edge.idx()] = EdgeRole::Primal;
                let gone_vertex = self.minima.survivor[mins[i]];
                self.minima.links[mins[i]] -= 1;
                self.minima.links[mins[1 - i]] -= 1;
                touched_minima.push(self.minima.merge(mins[i], mins[1 - i]));
                for m in maxs.into_iter().flatten() {
                    self.maxima.links[m] -= 1;
                    touched_maxima.push(m);
                }
                ("minimum", gone_vertex)
            }
            Partner::Maximum(i) => {
                self.reverse_face_path(saddle.faces[i], saddle.edge);
                self.gradient.edge_role[saddle.edge.idx()] = EdgeRole::Dual;
                let boundary = self.maxima.find(self.boundary as u32);
                let (gone, kept) = (maxs[i].unwrap_or(boundary), maxs[1 - i].unwrap_or(boundary));
                let gone_face = self.maxima.survivor[gone];
                self.maxima.links[gone] -= 1;
                self.maxima.links[kept] -= 1;
                touched_maxima.push(self.maxima.merge(gone, kept));
                for m in mins {
                    self.minima.links[m] -= 1;
                    touched_minima.push(m);
                }
                ("maximum", gone_face)
            }
        };
        // A cancellation can lower other saddles' scores (paper §3.7): the merged
        // extremum's region mean changed, and extrema whose link counts dropped may
        // have become terminal (the Γ terms of eqs. 7–8). Re-score their saddles.
        let mut touched: Vec<(Kind, usize)> = touched_minima
            .into_iter()
            .map(|m| (Kind::Minimum, self.minima.find(m as u32)))
            .chain(
                touched_maxima
                    .into_iter()
                    .map(|m| (Kind::Maximum, self.maxima.find(m as u32))),
            )
            .collect();
        touched.sort_unstable_by_key(|&(kind, rep)| (kind == Kind::Maximum, rep));
        touched.dedup();
        for (kind, rep) in touched {
            self.rescore_linked(kind, rep);
        }
        let cancellation = Cancellation {
            saddle: saddle.edge.0,
            extremum_kind: record.0,
            extremum: record.1,
            t,
        };
        self.cancelled.push(cancellation);
        cancellation
    }

    /// Reverse the primal path from `start` to its minimum and hang `start` on the
    /// saddle edge (whose other end leads to the surviving minimum).
    fn reverse_vertex_path(&mut self, start: VertexId, saddle: EdgeId) {
        let mut current = start;
        let mut incoming = saddle;
        while let Some((e, next)) = self.gradient.vertex_step(self.mesh, current) {
            self.gradient.vertex_parent[current.idx()] = incoming;
            incoming = e;
            current = next;
        }
        self.gradient.vertex_parent[current.idx()] = incoming;
    }

    /// Reverse the dual path from `start` to its maximum and hang `start` on the
    /// saddle edge.
    fn reverse_face_path(&mut self, start: FaceId, saddle: EdgeId) {
        let mut current = start;
        let mut incoming = saddle;
        while let Some((e, next)) = self.gradient.face_step(self.mesh, current) {
            self.gradient.face_parent[current.idx()] = incoming;
            incoming = e;
            current = next;
        }
        self.gradient.face_parent[current.idx()] = incoming;
    }
}
