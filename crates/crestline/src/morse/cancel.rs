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

crate::named::named!(Criterion, "criterion", {
    Feature => "feature",
    Persistence => "persistence",
});

/// Which extremum a cancellation removes: the minimum or maximum at the end of
/// branch `0` or `1` of the saddle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    /// The minimum at the end of this descending branch.
    Minimum(usize),
    /// The maximum at the end of this ascending branch.
    Maximum(usize),
}

/// One cancellation, as recorded in the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Cancellation {
    /// The saddle edge.
    pub saddle: u32,
    /// `"minimum"` (a vertex id) or `"maximum"` (a face id).
    pub extremum_kind: &'static str,
    /// The vertex (minimum) or face (maximum) id of the extremum removed.
    pub extremum: u32,
    /// The criterion's value when cancelled.
    pub t: f64,
}

/// Extrema of one kind, merged by cancellations: each set carries the region
/// integral, how many live saddle branches end at it, and its non-terminal
/// cancellation candidates.
struct Extrema {
    sets: UnionFind<u32>,
    region: Vec<Integral>,
    links: Vec<i64>,
    /// Per set, the candidates (s, e) whose branch ends at it, keyed by the part of
    /// their score that does not depend on the extremum; see [`Hierarchy::offset`].
    candidates: Vec<BinaryHeap<Candidate>>,
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
            candidates: (0..n).map(|_| BinaryHeap::new()).collect(),
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
        let mut moved = std::mem::take(&mut self.candidates[other]);
        // `append` moves the smaller heap into the larger.
        self.candidates[rep].append(&mut moved);
        self.survivor[rep] = self.survivor[kept];
        rep
    }
}

/// The two kinds of extrema.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    Minimum,
    Maximum,
}

/// A cancellation candidate in an extremum's heap: saddle `saddle` with the
/// extremum at the end of its branch `branch`, smallest `key` first.
#[derive(Clone, Copy, PartialEq)]
struct Candidate {
    key: f64,
    saddle: u32,
    branch: u8,
}

impl Eq for Candidate {}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .key
            .total_cmp(&self.key)
            .then(other.saddle.cmp(&self.saddle))
            .then(other.branch.cmp(&self.branch))
    }
}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A queue entry: the best score of an extremum set when queued, held `copies`
/// times. Never above the set's current best: every change that can lower it queues
/// a new entry, and an entry whose set improved is re-queued when popped. Entries
/// with equal keys are interchangeable, so the queue keeps them as one with a count
/// instead of as separate elements: re-queueing would otherwise multiply the
/// entries of sets that are touched often.
#[derive(Clone, Copy)]
struct Entry {
    t: f64,
    kind: Kind,
    set: u32,
    copies: u32,
}

impl Entry {
    /// One copy of the entry of set `set` of `kind` at score `t`.
    fn new(t: f64, kind: Kind, set: u32) -> Entry {
        Entry {
            t,
            kind,
            set,
            copies: 1,
        }
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

impl Ord for Entry {
    /// By key (t, kind, set), smallest first (BinaryHeap is a max-heap); the count
    /// is not part of the key.
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .t
            .total_cmp(&self.t)
            .then(other.kind.cmp(&self.kind))
            .then(other.set.cmp(&self.set))
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
    /// The discrete gradient, updated by every cancellation.
    pub gradient: Gradient,
    /// Every saddle of the initial gradient, with its measured 1-cells.
    pub saddles: Vec<Saddle>,
    /// Whether each saddle is still critical.
    pub alive: Vec<bool>,
    minima: Extrema,
    maxima: Extrema,
    /// The index of the boundary in `maxima` (one past the faces).
    boundary: usize,
    criterion: Criterion,
    live_saddles: usize,
    /// Live saddles with no valid cancellation left: forced by topology.
    forced_saddles: usize,
    queue: BinaryHeap<Entry>,
    /// The cancellations made, in order.
    pub cancelled: Vec<Cancellation>,
}

impl<'a> Hierarchy<'a> {
    /// The initial complex, every extremum queued under its best candidate.
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
            live_saddles: n,
            forced_saddles: 0,
            queue: BinaryHeap::with_capacity(n),
            cancelled: Vec::new(),
        };
        let boundary_set = boundary;
        for s in 0..n {
            let saddle = &hierarchy.saddles[s];
            let (low, high) = hierarchy.static_keys(saddle);
            for (branch, end) in hierarchy.minimum_ends(s).into_iter().enumerate() {
                hierarchy.minima.links[end] += 1;
                hierarchy.minima.candidates[end].push(Candidate {
                    key: low,
                    saddle: s as u32,
                    branch: branch as u8,
                });
            }
            for (branch, end) in hierarchy.maximum_ends(s).into_iter().enumerate() {
                if let Some(end) = end {
                    hierarchy.maxima.links[end] += 1;
                    hierarchy.maxima.candidates[end].push(Candidate {
                        key: high,
                        saddle: s as u32,
                        branch: branch as u8,
                    });
                }
            }
        }
        // The boundary is never a terminal maximum, nor cancelled.
        hierarchy.maxima.links[boundary_set] = i64::MAX / 2;
        hierarchy.maxima.candidates[boundary_set].clear();
        for m in 0..hierarchy.minima.region.len() {
            hierarchy.queue_set(Kind::Minimum, m);
        }
        for m in 0..boundary_set {
            hierarchy.queue_set(Kind::Maximum, m);
        }
        hierarchy.forced_saddles = (0..n).filter(|&s| hierarchy.is_forced(s)).count();
        hierarchy
    }

    /// Number of live saddles.
    pub fn saddle_count(&self) -> usize {
        self.live_saddles
    }

    /// Number of live saddles that a valid cancellation could still remove: the
    /// [`saddle_count`](Self::saddle_count) less the saddles forced by topology
    /// (those whose [`best`](Self::best) is `None`).
    pub fn cancellable_count(&self) -> usize {
        self.live_saddles - self.forced_saddles
    }

    /// Whether saddle `s` has no valid cancellation, with a minimum or a maximum.
    fn is_forced(&self, s: usize) -> bool {
        !self.valid(s, Kind::Minimum) && !self.valid(s, Kind::Maximum)
    }

    /// How many live saddles become forced when the extremum sets `a` and `b` of
    /// `kind` (`a != b`) are merged: those linking `a` and `b`, which lose their
    /// cancellations of `kind`, and that have none of the other kind. Every such
    /// saddle has a candidate in the heap of each set it links (the boundary aside),
    /// so one heap is scanned: the smaller, or the one that is not the boundary.
    fn newly_forced(&self, kind: Kind, a: usize, b: usize) -> usize {
        let (extrema, other_kind) = match kind {
            Kind::Minimum => (&self.minima, Kind::Maximum),
            Kind::Maximum => (&self.maxima, Kind::Minimum),
        };
        let boundary = self.maxima.find(self.boundary as u32);
        let scan_a = match kind {
            Kind::Maximum if a == boundary || b == boundary => b == boundary,
            _ => extrema.candidates[a].len() <= extrema.candidates[b].len(),
        };
        let (scanned, other) = if scan_a { (a, b) } else { (b, a) };
        extrema.candidates[scanned]
            .iter()
            .map(|c| (c.saddle as usize, 1 - c.branch as usize))
            .filter(|&(s, far)| self.alive[s] && self.branch_end(kind, s, far) == other)
            .filter(|&(s, _)| !self.valid(s, other_kind))
            .count()
    }

    /// The extremum set at the end of `branch` of saddle `s` (the boundary for a
    /// missing ascending branch).
    fn branch_end(&self, kind: Kind, s: usize, branch: usize) -> usize {
        match kind {
            Kind::Minimum => self.minimum_ends(s)[branch],
            Kind::Maximum => self.maximum_ends(s)[branch]
                .unwrap_or_else(|| self.maxima.find(self.boundary as u32)),
        }
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
        if !valid_only || self.valid(s, Kind::Minimum) {
            for (i, &m) in mins.iter().enumerate() {
                out.push((self.score_minimum(saddle, i, m), Partner::Minimum(i)));
            }
        }
        let boundary = self.maxima.find(self.boundary as u32);
        if !valid_only || self.valid(s, Kind::Maximum) {
            for (i, m) in maxs.iter().enumerate() {
                if let Some(m) = m.filter(|&m| m != boundary) {
                    out.push((self.score_maximum(saddle, i, m), Partner::Maximum(i)));
                }
            }
        }
        out
    }

    /// The parts of a saddle's scores that do not depend on the extremum it is
    /// cancelled with: (with a minimum, with a maximum). A non-terminal candidate
    /// scores its key plus its extremum's [`offset`](Self::offset): σ_max(r, m) =
    /// avg_r(I) − avg_U(m)(I) (eq. 1), σ_min(v, M) = avg_S(M)(I) − avg_v(I) (eq. 2),
    /// or the persistence f(s) − f(m), f(M) − f(s).
    fn static_keys(&self, saddle: &Saddle) -> (f64, f64) {
        match self.criterion {
            Criterion::Feature => (saddle.ascending_mean(), -saddle.descending_mean()),
            Criterion::Persistence => {
                let f = self.keys.edge[saddle.edge.idx()];
                (f, -f)
            }
        }
    }

    /// The extremum's part of its non-terminal candidates' scores.
    fn offset(&self, kind: Kind, m: usize) -> f64 {
        match (self.criterion, kind) {
            (Criterion::Feature, Kind::Minimum) => -self.minima.region[m].mean(),
            (Criterion::Feature, Kind::Maximum) => self.maxima.region[m].mean(),
            (Criterion::Persistence, Kind::Minimum) => {
                -self.keys.vertex[self.minima.survivor[m] as usize]
            }
            (Criterion::Persistence, Kind::Maximum) => {
                self.keys.face[self.maxima.survivor[m] as usize]
            }
        }
    }

    /// Whether cancelling saddle `s` with the extremum at the end of its branch of
    /// `kind` is valid: the saddle links two different extrema of that kind (a
    /// boundary saddle's single ascending branch may drain into the boundary).
    /// Once invalid, a candidate stays invalid, as sets only merge.
    fn valid(&self, s: usize, kind: Kind) -> bool {
        match kind {
            Kind::Minimum => {
                let [a, b] = self.minimum_ends(s);
                a != b
            }
            Kind::Maximum => {
                let boundary = self.maxima.find(self.boundary as u32);
                match self.maximum_ends(s) {
                    [Some(a), Some(b)] => a != b,
                    [Some(m), None] | [None, Some(m)] => m != boundary,
                    [None, None] => false,
                }
            }
        }
    }

    /// The best valid cancellation with extremum set `m` of `kind`: its score, the
    /// saddle and the partner. Drops dead and invalid candidates from the set's
    /// heap on the way.
    fn set_best(&mut self, kind: Kind, m: usize) -> Option<(f64, usize, Partner)> {
        loop {
            let top = *match kind {
                Kind::Minimum => &self.minima.candidates[m],
                Kind::Maximum => &self.maxima.candidates[m],
            }
            .peek()?;
            let s = top.saddle as usize;
            if !self.alive[s] || !self.valid(s, kind) {
                match kind {
                    Kind::Minimum => self.minima.candidates[m].pop(),
                    Kind::Maximum => self.maxima.candidates[m].pop(),
                };
                continue;
            }
            let i = top.branch as usize;
            let saddle = &self.saddles[s];
            // A terminal extremum has a single live branch, the top one; its score
            // includes the Γ term (eqs. 5–8). Otherwise key + offset.
            return Some(match kind {
                Kind::Minimum => (
                    if self.minima.links[m] == 1 {
                        self.score_minimum(saddle, i, m)
                    } else {
                        top.key + self.offset(kind, m)
                    },
                    s,
                    Partner::Minimum(i),
                ),
                Kind::Maximum => (
                    if self.maxima.links[m] == 1 {
                        self.score_maximum(saddle, i, m)
                    } else {
                        top.key + self.offset(kind, m)
                    },
                    s,
                    Partner::Maximum(i),
                ),
            });
        }
    }

    /// Queue extremum set `m` under its current best score.
    fn queue_set(&mut self, kind: Kind, m: usize) {
        if let Some((t, _, _)) = self.set_best(kind, m) {
            self.queue.push(Entry::new(t, kind, m as u32));
        }
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

    /// Cancel the next saddle in criterion order; `None` when no valid cancellation
    /// is left. The queue holds extremum sets, each under its best candidate: the
    /// smallest entry whose score is still current is the saddle of least t (eq. 9),
    /// cancelled with the extremum that attains it.
    pub fn cancel_next(&mut self) -> Option<Cancellation> {
        while let Some(entry) = self.pop_entry() {
            let m = entry.set as usize;
            let current = match entry.kind {
                Kind::Minimum => self.minima.find(entry.set) == m,
                Kind::Maximum => {
                    self.maxima.find(entry.set) == m && m != self.maxima.find(self.boundary as u32)
                }
            };
            if !current {
                continue;
            }
            let Some((t, s, partner)) = self.set_best(entry.kind, m) else {
                continue;
            };
            // Lazy queue: a set whose best score grew since it was queued (its top
            // saddle was cancelled elsewhere, a region merged) goes back in, every
            // copy alike, as nothing changes between them.
            if t > entry.t + 1e-12 * entry.t.abs().max(1e-300) {
                self.queue.push(Entry { t, ..entry });
                continue;
            }
            // One copy is used; the others wait in the queue as before.
            if entry.copies > 1 {
                self.queue.push(Entry {
                    copies: entry.copies - 1,
                    ..entry
                });
            }
            return Some(self.cancel(s, partner, t));
        }
        None
    }

    /// Pop the smallest entry together with every other entry of the same key.
    fn pop_entry(&mut self) -> Option<Entry> {
        let mut entry = self.queue.pop()?;
        while self.queue.peek() == Some(&entry) {
            entry.copies += self.queue.pop().map_or(0, |e| e.copies);
        }
        Some(entry)
    }

    /// Cancel saddle `s` with `partner`: reverse the gradient along the branch to
    /// the extremum, make the saddle edge part of that forest, merge the extremum
    /// into the other branch's, and re-score the saddles of extrema that became
    /// terminal.
    fn cancel(&mut self, s: usize, partner: Partner, t: f64) -> Cancellation {
        self.alive[s] = false;
        self.live_saddles -= 1;
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
                self.forced_saddles += self.newly_forced(Kind::Minimum, mins[i], mins[1 - i]);
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
                self.forced_saddles += self.newly_forced(Kind::Maximum, gone, kept);
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
        // A cancellation can lower other scores (§3.7): the merged extremum's region
        // and candidates changed, and extrema whose link counts dropped may have
        // become terminal (the Γ terms of eqs. 7–8). Queue them afresh.
        let mut touched: Vec<(Kind, usize)> = touched_minima
            .into_iter()
            .map(|m| (Kind::Minimum, self.minima.find(m as u32)))
            .chain(
                touched_maxima
                    .into_iter()
                    .map(|m| (Kind::Maximum, self.maxima.find(m as u32))),
            )
            .collect();
        touched.sort_unstable();
        touched.dedup();
        for (kind, m) in touched {
            if kind == Kind::Minimum || m != self.maxima.find(self.boundary as u32) {
                self.queue_set(kind, m);
            }
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
