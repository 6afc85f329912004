//! The scores of cancellations: the significance of the paper (Sahner et al.
//! 2008, eqs. 1–9, with the terminal-extremum terms Γ) or plain persistence.

use super::super::cells::Saddle;
use super::super::gradient::Keys;
use super::extrema::{Extrema, Kind};
use super::{Criterion, Partner};

/// What the scores of an extremum set's candidates read besides the sets of its
/// kind: the criterion, the keys, the saddles and which are alive. Apart from
/// [`Hierarchy`] so that the two kinds' sets can be scored side by side.
#[derive(Clone, Copy)]
pub(super) struct Scoring<'h> {
    pub(super) criterion: Criterion,
    pub(super) keys: &'h Keys,
    pub(super) saddles: &'h [Saddle],
    pub(super) alive: &'h [bool],
}

impl Scoring<'_> {
    /// The best valid cancellation with set `m` of `extrema` (of `kind`): its
    /// score, the saddle and the partner. Drops dead and invalid candidates from
    /// the set's heap on the way.
    pub(super) fn set_best(
        &self,
        extrema: &mut Extrema,
        kind: Kind,
        m: usize,
    ) -> Option<(f64, usize, Partner)> {
        let top = extrema.best_valid(m, self.alive)?;
        let (s, i) = (top.saddle(), top.branch());
        let saddle = &self.saddles[s];
        // A terminal extremum has a single live branch, the top one; its score
        // includes the Γ term (eqs. 5–8). Otherwise key + offset.
        let t = match (extrema.state[m].links == 1, kind) {
            (true, Kind::Minimum) => self.score_minimum(extrema, saddle, i, m),
            (true, Kind::Maximum) => self.score_maximum(extrema, saddle, i, m),
            (false, _) => top.key + self.offset(extrema, kind, m),
        };
        let partner = match kind {
            Kind::Minimum => Partner::Minimum(i),
            Kind::Maximum => Partner::Maximum(i),
        };
        Some((t, s, partner))
    }

    /// Set `m`'s (of `extrema`, of `kind`) part of its non-terminal candidates'
    /// scores.
    pub(super) fn offset(&self, extrema: &Extrema, kind: Kind, m: usize) -> f64 {
        let state = &extrema.state[m];
        match (self.criterion, kind) {
            (Criterion::Feature, Kind::Minimum) => -state.region.mean(),
            (Criterion::Feature, Kind::Maximum) => state.region.mean(),
            (Criterion::Persistence, Kind::Minimum) => -self.keys.vertex[state.survivor as usize],
            (Criterion::Persistence, Kind::Maximum) => self.keys.face[state.survivor as usize],
        }
    }

    /// Score of cancelling the saddle with the minimum `m` of `minima` at the end
    /// of branch `i`.
    pub(super) fn score_minimum(
        &self,
        minima: &Extrema,
        saddle: &Saddle,
        i: usize,
        m: usize,
    ) -> f64 {
        let state = &minima.state[m];
        match self.criterion {
            Criterion::Persistence => {
                self.keys.edge[saddle.edge.idx()] - self.keys.vertex[state.survivor as usize]
            }
            Criterion::Feature => {
                let region = state.region.mean();
                // σ_max(r, m): how much the ascending line rises above the valley.
                let sigma = saddle.ascending_mean() - region;
                if state.links == 1 {
                    // Γ_min(v_i, m_i) for a terminal minimum.
                    sigma.min(region - saddle.descending[i].mean())
                } else {
                    sigma
                }
            }
        }
    }

    /// Score of cancelling the saddle with the maximum `m` of `maxima` at the end
    /// of branch `i`.
    pub(super) fn score_maximum(
        &self,
        maxima: &Extrema,
        saddle: &Saddle,
        i: usize,
        m: usize,
    ) -> f64 {
        let state = &maxima.state[m];
        match self.criterion {
            Criterion::Persistence => {
                self.keys.face[state.survivor as usize] - self.keys.edge[saddle.edge.idx()]
            }
            Criterion::Feature => {
                let region = state.region.mean();
                // σ_min(v, M): how far the descending line sinks below the hill.
                let sigma = region - saddle.descending_mean();
                if state.links == 1 {
                    // Γ_max(r_i, M_i) for a terminal maximum.
                    sigma.min(saddle.ascending[i].mean() - region)
                } else {
                    sigma
                }
            }
        }
    }
}

/// The parts of a saddle's scores that do not depend on the extremum it is
/// cancelled with: (with a minimum, with a maximum). A non-terminal candidate
/// scores its key plus its extremum's [`offset`](Scoring::offset): σ_max(r, m) =
/// avg_r(I) − avg_U(m)(I) (eq. 1), σ_min(v, M) = avg_S(M)(I) − avg_v(I) (eq. 2),
/// or the persistence f(s) − f(m), f(M) − f(s).
pub(super) fn static_keys(criterion: Criterion, keys: &Keys, saddle: &Saddle) -> (f64, f64) {
    match criterion {
        Criterion::Feature => (saddle.ascending_mean(), -saddle.descending_mean()),
        Criterion::Persistence => {
            let f = keys.edge[saddle.edge.idx()];
            (f, -f)
        }
    }
}
