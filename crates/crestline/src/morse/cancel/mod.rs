//! The cancellation hierarchy (Sahner et al. 2008, §2.1, §3.3–3.5): saddles are
//! cancelled against a neighbouring extremum in increasing order of a criterion,
//! either the feature-line-preserving significance of the paper or plain
//! persistence.

mod extrema;
mod queue;
mod scoring;
mod trees;

use std::cell::OnceCell;

use crate::mesh::{EdgeId, Mesh};

use super::cells::{Integral, Saddle};
use super::gradient::{EdgeRole, Gradient, Keys};
use super::heap::SeededQueue;
use extrema::{saddle_ends, Ends, Extrema, Kind};
use queue::Entry;
use scoring::{static_keys, Scoring};
use trees::{attach, Link};

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

/// The Morse-Smale complex under cancellation.
pub struct Hierarchy<'a> {
    mesh: &'a Mesh,
    keys: &'a Keys,
    /// The initial gradient, the roles of the cancelled saddle edges updated.
    initial: Gradient,
    /// The gradient after the cancellations so far, built on first use.
    current: OnceCell<Gradient>,
    /// Every saddle of the initial gradient, with its measured 1-cells.
    pub saddles: Vec<Saddle>,
    /// The extrema at the ends of each saddle's branches.
    ends: Vec<Ends>,
    /// Whether each saddle is still critical.
    pub alive: Vec<bool>,
    minima: Extrema,
    maxima: Extrema,
    /// The index of the boundary in `maxima` (one past the maxima).
    boundary: usize,
    criterion: Criterion,
    live_saddles: usize,
    /// Live saddles with no valid cancellation left: forced by topology.
    forced_saddles: usize,
    queue: SeededQueue<Entry>,
    /// The cancellations made, in order.
    pub cancelled: Vec<Cancellation>,
}

impl<'a> Hierarchy<'a> {
    /// The initial complex, every extremum queued under its best candidate.
    /// `regions` are the region integrals indexed by vertex and by face.
    pub fn new(
        mesh: &'a Mesh,
        keys: &'a Keys,
        gradient: Gradient,
        saddles: Vec<Saddle>,
        regions: (Vec<Integral>, Vec<Integral>),
        criterion: Criterion,
    ) -> Hierarchy<'a> {
        let (minimum_regions, mut maximum_regions) = regions;
        // The boundary: where maxima cancelled against boundary saddles drain.
        maximum_regions.push(Integral::default());
        let boundary = gradient.maxima.len();
        // The two kinds' sets, and the ends of the saddles' branches, side by side:
        // most of their cost is the first touch of fresh memory.
        let ((minima, maxima), ends) = rayon::join(
            || {
                rayon::join(
                    || {
                        Extrema::new(
                            gradient.minima.iter().map(|v| v.0).collect(),
                            &minimum_regions,
                        )
                    },
                    || {
                        let ids = gradient.maxima.iter().map(|f| f.0);
                        Extrema::new(
                            ids.chain([mesh.face_count() as u32]).collect(),
                            &maximum_regions,
                        )
                    },
                )
            },
            || saddle_ends(mesh, &gradient, &saddles),
        );
        let n = saddles.len();
        let mut hierarchy = Hierarchy {
            mesh,
            keys,
            initial: gradient,
            current: OnceCell::new(),
            saddles,
            ends,
            alive: vec![true; n],
            minima,
            maxima,
            boundary,
            criterion,
            live_saddles: n,
            forced_saddles: 0,
            queue: SeededQueue::new(Vec::new()),
            cancelled: Vec::new(),
        };
        hierarchy.add_candidates();
        hierarchy.queue = SeededQueue::new(hierarchy.initial_entries());
        hierarchy.forced_saddles = (0..n).filter(|&s| hierarchy.is_forced(s)).count();
        hierarchy
    }

    /// Link every saddle to the extrema at the ends of its branches, with its
    /// candidates in their heaps (minima and maxima side by side); the boundary
    /// is never a terminal maximum, nor cancelled.
    fn add_candidates(&mut self) {
        let (criterion, keys, saddles) = (self.criterion, self.keys, &self.saddles);
        let key = |s: usize| static_keys(criterion, keys, &saddles[s]);
        let ends = &self.ends;
        let boundary = self.boundary as u32;
        rayon::join(
            || self.minima.link(ends, |e| e.minima, |s| key(s).0, None),
            || {
                self.maxima
                    .link(ends, |e| e.maxima, |s| key(s).1, Some(boundary))
            },
        );
        self.maxima.state[self.boundary].links = i64::MAX / 2;
    }

    /// Every extremum set's entry under its best candidate, the minima's and the
    /// maxima's found side by side (the boundary is never queued).
    fn initial_entries(&mut self) -> Vec<Entry> {
        let (minimum_count, boundary) = (self.minima.state.len(), self.boundary);
        let (scoring, minima, maxima) = self.scoring_and_sets();
        let entries = |extrema: &mut Extrema, kind: Kind, count: usize| {
            (0..count)
                .filter_map(|m| {
                    let (t, _, _) = scoring.set_best(extrema, kind, m)?;
                    extrema.claim_entry(t, kind, m)
                })
                .collect::<Vec<_>>()
        };
        let (mut initial, later) = rayon::join(
            || entries(minima, Kind::Minimum, minimum_count),
            || entries(maxima, Kind::Maximum, boundary),
        );
        initial.extend(later);
        initial
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

    /// The discrete gradient after the cancellations so far. Each cancellation
    /// reverses the path from the saddle to the extremum it removes and hangs the
    /// saddle's end there on the saddle edge, which re-roots that tree at the
    /// surviving extremum. A tree has one orientation towards a given root, so
    /// the result is found once, here, from the initial forests: only the paths
    /// from where each initial tree is attached towards its surviving extremum to
    /// the tree's own root are reversed. The critical cells and root labels stay
    /// those of the initial gradient.
    pub fn gradient(&self) -> &Gradient {
        self.current.get_or_init(|| {
            let minima = self.attachments(Kind::Minimum);
            let maxima = self.attachments(Kind::Maximum);
            self.initial.rehung(self.mesh, &minima, &maxima)
        })
    }

    /// Where each initial tree of `kind` hangs on the tree of its surviving
    /// extremum (or the boundary): the node of the tree and the cancelled saddle
    /// edge it leaves by, for every tree that holds no surviving extremum.
    fn attachments(&self, kind: Kind) -> Vec<(u32, EdgeId)> {
        let (extrema, role) = match kind {
            Kind::Minimum => (&self.minima, EdgeRole::Primal),
            Kind::Maximum => (&self.maxima, EdgeRole::Dual),
        };
        let links: Vec<Link> = (0..self.saddles.len())
            .filter(|&s| self.initial.edge_role[self.saddles[s].edge.idx()] == role)
            .map(|s| {
                let saddle = &self.saddles[s];
                let (trees, nodes) = match kind {
                    Kind::Minimum => (self.ends[s].minima, saddle.vertices.map(|v| v.0)),
                    Kind::Maximum => (self.ends[s].maxima, saddle.faces.map(|f| f.0)),
                };
                Link {
                    trees,
                    nodes,
                    edge: saddle.edge,
                }
            })
            .collect();
        attach(extrema.state.len(), extrema.survivor_trees(), &links)
    }

    /// Whether saddle `s` has no valid cancellation, with a minimum or a maximum.
    fn is_forced(&self, s: usize) -> bool {
        !self.valid(s, Kind::Minimum) && !self.valid(s, Kind::Maximum)
    }

    /// The extrema of `kind`.
    fn extrema(&self, kind: Kind) -> &Extrema {
        match kind {
            Kind::Minimum => &self.minima,
            Kind::Maximum => &self.maxima,
        }
    }

    /// The extrema of `kind`, to change.
    fn extrema_mut(&mut self, kind: Kind) -> &mut Extrema {
        match kind {
            Kind::Minimum => &mut self.minima,
            Kind::Maximum => &mut self.maxima,
        }
    }

    /// The set of the boundary in `maxima`.
    fn boundary_set(&self) -> usize {
        self.maxima.find(self.boundary as u32)
    }

    /// How many live saddles become forced when the extremum sets `a` and `b` of
    /// `kind` (`a != b`) are merged: those linking `a` and `b`, which lose their
    /// cancellations of `kind`, and that have none of the other kind. Every such
    /// saddle has a candidate in the heap of each set it links (the boundary aside),
    /// so one heap is scanned: the smaller, or the one that is not the boundary.
    /// The scan also drops the candidates that no longer count, which the heap
    /// would drop when they came to its top: those of dead saddles, and those
    /// linking `a` and `b`, invalid once they are merged. The heap pops the others
    /// in the same order.
    fn newly_forced(&mut self, kind: Kind, a: usize, b: usize) -> usize {
        let other_kind = match kind {
            Kind::Minimum => Kind::Maximum,
            Kind::Maximum => Kind::Minimum,
        };
        let boundary = self.boundary_set();
        let state = &self.extrema(kind).state;
        let scan_a = match kind {
            Kind::Maximum if a == boundary || b == boundary => b == boundary,
            _ => state[a].candidates.len() <= state[b].candidates.len(),
        };
        let (scanned, other) = if scan_a { (a, b) } else { (b, a) };
        let mut candidates = std::mem::take(&mut self.extrema_mut(kind).state[scanned].candidates);
        let mut forced = 0;
        candidates.retain(|c| {
            let alive = self.alive[c.saddle()];
            let linking = alive && self.extrema(kind).find(c.far) == other;
            if linking && !self.valid(c.saddle(), other_kind) {
                forced += 1;
            }
            alive && !linking
        });
        self.extrema_mut(kind).state[scanned].candidates = candidates;
        forced
    }

    /// Number of live minima and maxima.
    pub fn extremum_counts(&self) -> (usize, usize) {
        let live = |extrema: &Extrema, count: usize| {
            (0..count).filter(|&m| extrema.find(m as u32) == m).count()
        };
        // The boundary's set is not a maximum.
        let maxima = live(&self.maxima, self.boundary + 1) - 1;
        (live(&self.minima, self.minima.state.len()), maxima)
    }

    /// The current minimum (set representative) at the end of each descending branch.
    fn minimum_ends(&self, s: usize) -> [usize; 2] {
        self.ends[s].minima.map(|m| self.minima.find(m))
    }

    /// The current maximum at the end of each ascending branch (none on the boundary).
    fn maximum_ends(&self, s: usize) -> [Option<usize>; 2] {
        self.ends[s]
            .maxima
            .map(|m| (m as usize != self.boundary).then(|| self.maxima.find(m)))
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
                let t = self.scoring().score_minimum(&self.minima, saddle, i, m);
                out.push((t, Partner::Minimum(i)));
            }
        }
        let boundary = self.boundary_set();
        if !valid_only || self.valid(s, Kind::Maximum) {
            for (i, m) in maxs.iter().enumerate() {
                if let Some(m) = m.filter(|&m| m != boundary) {
                    let t = self.scoring().score_maximum(&self.maxima, saddle, i, m);
                    out.push((t, Partner::Maximum(i)));
                }
            }
        }
        out
    }

    /// Whether cancelling saddle `s` with the extremum at the end of its branch of
    /// `kind` is valid: the saddle links two different extrema of that kind (a
    /// boundary saddle's single ascending branch may drain into the boundary).
    /// Once invalid, a candidate stays invalid, as sets only merge.
    fn valid(&self, s: usize, kind: Kind) -> bool {
        let ends = match kind {
            Kind::Minimum => self.ends[s].minima,
            Kind::Maximum => self.ends[s].maxima,
        };
        let extrema = self.extrema(kind);
        extrema.find(ends[0]) != extrema.find(ends[1])
    }

    /// What scoring reads besides the extremum sets.
    fn scoring(&self) -> Scoring<'_> {
        Scoring {
            criterion: self.criterion,
            keys: self.keys,
            saddles: &self.saddles,
            alive: &self.alive,
        }
    }

    /// The best valid cancellation with extremum set `m` of `kind`
    /// ([`Scoring::set_best`]).
    fn set_best(&mut self, kind: Kind, m: usize) -> Option<(f64, usize, Partner)> {
        let (scoring, minima, maxima) = self.scoring_and_sets();
        let extrema = match kind {
            Kind::Minimum => minima,
            Kind::Maximum => maxima,
        };
        scoring.set_best(extrema, kind, m)
    }

    /// What scoring reads, and the minima and maxima to change.
    fn scoring_and_sets(&mut self) -> (Scoring<'_>, &mut Extrema, &mut Extrema) {
        let scoring = Scoring {
            criterion: self.criterion,
            keys: self.keys,
            saddles: &self.saddles,
            alive: &self.alive,
        };
        (scoring, &mut self.minima, &mut self.maxima)
    }

    /// Queue extremum set `m` under its current best score, unless it has an
    /// entry at a lower one.
    fn queue_set(&mut self, kind: Kind, m: usize) {
        if let Some((t, _, _)) = self.set_best(kind, m) {
            self.push_entry(t, kind, m);
        }
    }

    /// Queue set `m` of `kind` at `t`, unless its entry is lower.
    fn push_entry(&mut self, t: f64, kind: Kind, m: usize) {
        if let Some(entry) = self.extrema_mut(kind).claim_entry(t, kind, m) {
            self.queue.push(entry);
        }
    }

    /// Cancel the next saddle in criterion order; `None` when no valid cancellation
    /// is left. The queue holds extremum sets, each under its best candidate: the
    /// smallest entry whose score is still current is the saddle of least t (eq. 9),
    /// cancelled with the extremum that attains it.
    pub fn cancel_next(&mut self) -> Option<Cancellation> {
        while let Some(entry) = self.queue.pop() {
            let (kind, m) = (entry.kind(), entry.set());
            let queued = &mut self.extrema_mut(kind).state[m].queued;
            if queued.to_bits() != entry.t.to_bits() {
                // A lower entry superseded this one.
                continue;
            }
            *queued = f64::INFINITY;
            let current = match kind {
                Kind::Minimum => self.minima.find(m as u32) == m,
                Kind::Maximum => self.maxima.find(m as u32) == m && m != self.boundary_set(),
            };
            if !current {
                continue;
            }
            let Some((t, s, partner)) = self.set_best(kind, m) else {
                continue;
            };
            // Lazy queue: a set whose best score grew since it was queued (its top
            // saddle was cancelled elsewhere, a region merged) goes back in.
            if t > entry.t + 1e-12 * entry.t.abs().max(1e-300) {
                self.push_entry(t, kind, m);
                continue;
            }
            return Some(self.cancel(s, partner, t));
        }
        None
    }

    /// Cancel saddle `s` with `partner`: make the saddle edge part of the forest of
    /// the extremum (its tree is re-hung when the [`gradient`](Self::gradient) is
    /// next asked for), merge the extremum into the other branch's, and re-score
    /// the saddles of extrema that became terminal.
    fn cancel(&mut self, s: usize, partner: Partner, t: f64) -> Cancellation {
        self.alive[s] = false;
        self.live_saddles -= 1;
        self.current.take();
        let edge = self.saddles[s].edge;
        let mins = self.minimum_ends(s);
        let maxs = self.maximum_ends(s);
        // The merged set, and the sets of the other kind whose link counts drop.
        let (record, merged, others) = match partner {
            Partner::Minimum(i) => {
                self.initial.edge_role[edge.idx()] = EdgeRole::Primal;
                let gone_vertex = self.minima.state[mins[i]].survivor;
                self.forced_saddles += self.newly_forced(Kind::Minimum, mins[i], mins[1 - i]);
                self.minima.state[mins[i]].links -= 1;
                self.minima.state[mins[1 - i]].links -= 1;
                let merged = self.minima.merge(mins[i], mins[1 - i]);
                for m in maxs.into_iter().flatten() {
                    self.maxima.state[m].links -= 1;
                }
                let others = maxs.map(|m| m.map(|m| (Kind::Maximum, m)));
                (("minimum", gone_vertex), (Kind::Minimum, merged), others)
            }
            Partner::Maximum(i) => {
                self.initial.edge_role[edge.idx()] = EdgeRole::Dual;
                let boundary = self.boundary_set();
                let (gone, kept) = (maxs[i].unwrap_or(boundary), maxs[1 - i].unwrap_or(boundary));
                let gone_face = self.maxima.state[gone].survivor;
                self.forced_saddles += self.newly_forced(Kind::Maximum, gone, kept);
                self.maxima.state[gone].links -= 1;
                self.maxima.state[kept].links -= 1;
                let merged = self.maxima.merge(gone, kept);
                for m in mins {
                    self.minima.state[m].links -= 1;
                }
                let others = mins.map(|m| Some((Kind::Minimum, m)));
                (("maximum", gone_face), (Kind::Maximum, merged), others)
            }
        };
        // A cancellation can lower other scores (§3.7): the merged extremum's region
        // and candidates changed, and extrema whose link counts dropped to one became
        // terminal (the Γ terms of eqs. 7–8). Queue them afresh, once each. The
        // scores of the others whose counts dropped stay or grow (a candidate of
        // theirs died), which their pending entries answer when popped.
        let [a, b] =
            others.map(|set| set.filter(|&(kind, m)| self.extrema(kind).state[m].links == 1));
        self.requeue(merged);
        match (a, b) {
            (Some(a), Some(b)) if a == b => self.requeue(a),
            (a, b) => a.into_iter().chain(b).for_each(|set| self.requeue(set)),
        }
        let cancellation = Cancellation {
            saddle: edge.0,
            extremum_kind: record.0,
            extremum: record.1,
            t,
        };
        self.cancelled.push(cancellation);
        cancellation
    }

    /// Queue the set (kind, index) afresh, unless it is the boundary's.
    fn requeue(&mut self, (kind, m): (Kind, usize)) {
        if kind == Kind::Minimum || m != self.boundary_set() {
            self.queue_set(kind, m);
        }
    }
}
