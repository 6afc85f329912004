//! The entries of one vector or of several vectors interleaved, for the iteration
//! that solves several right-hand sides of one matrix at once: every pass over
//! the matrix (the product, the smoother's sweeps, the transfers between levels)
//! then serves all of them. A pass is bound by the latency of its chains of
//! dependent reads and sums more than by the bytes it moves, so a second vector
//! rides along almost free: on the dragon ×4's extremality system a solve of one
//! vector took 2.2–2.8 s, of two ([`Pair`]) 2.0–2.7 s (9–11 iterations either
//! way), of four (measured with a four-lane type, not kept) 3.3–4.0 s.

use std::ops::{Add, AddAssign, Mul, Sub, SubAssign};

/// A vector entry: one `f64`, or one entry of each of several vectors
/// ([`Pair`]). Arithmetic is lane by lane; scalars of the iteration (step
/// lengths, inner products) are lanes too, one per vector.
pub trait Lanes:
    Copy
    + Default
    + Send
    + Sync
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + AddAssign
    + SubAssign
    + Mul<f64, Output = Self>
{
    /// How many vectors.
    const COUNT: usize;

    /// Lane by lane product.
    fn times(self, other: Self) -> Self;

    /// Lane by lane quotient.
    fn over(self, other: Self) -> Self;

    /// Lane `k`.
    fn lane(self, k: usize) -> f64;

    /// Sets lane `k`.
    fn set_lane(&mut self, k: usize, value: f64);
}

impl Lanes for f64 {
    const COUNT: usize = 1;

    fn times(self, other: f64) -> f64 {
        self * other
    }

    fn over(self, other: f64) -> f64 {
        self / other
    }

    fn lane(self, _: usize) -> f64 {
        self
    }

    fn set_lane(&mut self, _: usize, value: f64) {
        *self = value;
    }
}

/// One entry of each of two vectors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pair(pub [f64; 2]);

impl Add for Pair {
    type Output = Pair;

    fn add(self, o: Pair) -> Pair {
        Pair([self.0[0] + o.0[0], self.0[1] + o.0[1]])
    }
}

impl Sub for Pair {
    type Output = Pair;

    fn sub(self, o: Pair) -> Pair {
        Pair([self.0[0] - o.0[0], self.0[1] - o.0[1]])
    }
}

impl AddAssign for Pair {
    fn add_assign(&mut self, o: Pair) {
        *self = *self + o;
    }
}

impl SubAssign for Pair {
    fn sub_assign(&mut self, o: Pair) {
        *self = *self - o;
    }
}

impl Mul<f64> for Pair {
    type Output = Pair;

    fn mul(self, s: f64) -> Pair {
        Pair([self.0[0] * s, self.0[1] * s])
    }
}

impl Lanes for Pair {
    const COUNT: usize = 2;

    fn times(self, o: Pair) -> Pair {
        Pair([self.0[0] * o.0[0], self.0[1] * o.0[1]])
    }

    fn over(self, o: Pair) -> Pair {
        Pair([self.0[0] / o.0[0], self.0[1] / o.0[1]])
    }

    fn lane(self, k: usize) -> f64 {
        self.0[k]
    }

    fn set_lane(&mut self, k: usize, value: f64) {
        self.0[k] = value;
    }
}

/// Lane `k` of every entry.
pub fn lane<V: Lanes>(v: &[V], k: usize) -> Vec<f64> {
    v.iter().map(|x| x.lane(k)).collect()
}

/// Sets lane `k` of every entry from `values`.
pub fn set_lane<V: Lanes>(v: &mut [V], k: usize, values: &[f64]) {
    for (x, &value) in v.iter_mut().zip(values) {
        x.set_lane(k, value);
    }
}
