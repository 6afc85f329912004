//! What the values of a volume look like: range, percentiles, a histogram and
//! Otsu's threshold, to help choose the isosurface level of an image.

use rayon::prelude::*;

use super::Volume;

/// Bins of [`ValueSummary::histogram`].
pub const HISTOGRAM_BINS: usize = 64;

/// The percentiles [`ValueSummary::percentiles`] lists.
pub const PERCENTILES: [f64; 7] = [1.0, 5.0, 25.0, 50.0, 75.0, 95.0, 99.0];

/// A summary of a volume's sample values.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ValueSummary {
    /// Samples that are not finite (NaN or infinite); they are left out of
    /// everything else.
    pub non_finite: usize,
    /// The smallest finite sample (NaN when there is none).
    pub min: f64,
    /// The largest finite sample (NaN when there is none).
    pub max: f64,
    /// The mean of the finite samples.
    pub mean: f64,
    /// `(p, value)` for each `p` of `PERCENTILES`: the exact percentile of the
    /// finite samples, with numpy's default (linear) definition — the value at
    /// rank `(n − 1)·p/100` of the sorted samples, interpolated linearly between
    /// the two samples around it (NaN when there is no finite sample).
    pub percentiles: Vec<(f64, f64)>,
    /// Counts of finite samples in `HISTOGRAM_BINS` equal bins from `min` to
    /// `max`.
    pub histogram: Vec<usize>,
    /// Otsu's threshold: the level between bins that best separates the
    /// histogram into two classes (largest between-class variance) — often a
    /// good first `--level` for an object against its background.
    pub otsu: f64,
}

impl ValueSummary {
    /// Summarises the samples of `volume` (in parallel).
    pub fn of(volume: &Volume) -> ValueSummary {
        let samples = volume.samples();
        let range = samples
            .par_iter()
            .filter(|v| v.is_finite())
            .fold(Range::default, |r, &v| r.with(f64::from(v)))
            .reduce(Range::default, Range::merge);
        let histogram = if range.count == 0 {
            vec![0; HISTOGRAM_BINS]
        } else {
            histogram(samples, range.min, range.max)
        };
        let width = (range.max - range.min) / HISTOGRAM_BINS as f64;
        let percentiles = PERCENTILES
            .iter()
            .zip(percentiles(samples, range.count, &PERCENTILES))
            .map(|(&p, value)| (p, value))
            .collect();
        let (min, max) = range.bounds();
        ValueSummary {
            non_finite: samples.len() - range.count,
            min,
            max,
            mean: range.sum / range.count as f64,
            percentiles,
            otsu: otsu(&histogram, range.min, width),
            histogram,
        }
    }

    /// The width of one histogram bin.
    pub fn bin_width(&self) -> f64 {
        (self.max - self.min) / HISTOGRAM_BINS as f64
    }
}

/// Running count, sum and range of finite samples.
#[derive(Clone, Copy, Debug)]
struct Range {
    count: usize,
    sum: f64,
    min: f64,
    max: f64,
}

impl Default for Range {
    fn default() -> Range {
        Range {
            count: 0,
            sum: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }
}

impl Range {
    fn with(self, v: f64) -> Range {
        Range {
            count: self.count + 1,
            sum: self.sum + v,
            min: self.min.min(v),
            max: self.max.max(v),
        }
    }

    fn merge(a: Range, b: Range) -> Range {
        Range {
            count: a.count + b.count,
            sum: a.sum + b.sum,
            min: a.min.min(b.min),
            max: a.max.max(b.max),
        }
    }

    /// `(min, max)`, or NaNs when no sample was counted.
    fn bounds(&self) -> (f64, f64) {
        if self.count == 0 {
            (f64::NAN, f64::NAN)
        } else {
            (self.min, self.max)
        }
    }
}

/// Counts of the finite samples in [`HISTOGRAM_BINS`] bins over `[min, max]`.
fn histogram(samples: &[f32], min: f64, max: f64) -> Vec<usize> {
    let scale = if max > min {
        HISTOGRAM_BINS as f64 / (max - min)
    } else {
        0.0
    };
    samples
        .par_iter()
        .filter(|v| v.is_finite())
        .fold(
            || vec![0usize; HISTOGRAM_BINS],
            |mut counts, &v| {
                let bin = ((f64::from(v) - min) * scale) as usize;
                counts[bin.min(HISTOGRAM_BINS - 1)] += 1;
                counts
            },
        )
        .reduce(
            || vec![0usize; HISTOGRAM_BINS],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
                a
            },
        )
}

/// The exact percentiles `ps` (in percent) of the `finite` finite samples, as
/// numpy's `np.percentile(samples, ps)` computes them by default ("linear"): for
/// `n` samples in increasing order x₀ ≤ … ≤ xₙ₋₁, the rank r = (n − 1)·p/100 and
/// the value x⌊r⌋ + (r − ⌊r⌋)·(x⌊r⌋₊₁ − x⌊r⌋). NaN for each when `finite` is 0.
fn percentiles(samples: &[f32], finite: usize, ps: &[f64]) -> Vec<f64> {
    if finite == 0 {
        return vec![f64::NAN; ps.len()];
    }
    let n = finite;
    // (rank below, rank above, fraction of the way between them)
    let ranks: Vec<(usize, usize, f64)> = ps
        .iter()
        .map(|&p| {
            let rank = (n - 1) as f64 * (p / 100.0);
            let below = (rank.floor().max(0.0) as usize).min(n - 1);
            (below, (below + 1).min(n - 1), rank - below as f64)
        })
        .collect();
    let mut wanted: Vec<usize> = ranks.iter().flat_map(|&(a, b, _)| [a, b]).collect();
    wanted.sort_unstable();
    wanted.dedup();
    let values = order_statistics(samples, &wanted);
    let value = |rank| f64::from(values[wanted.binary_search(&rank).expect("a wanted rank")]);
    ranks
        .iter()
        .map(|&(below, above, t)| lerp(value(below), value(above), t))
        .collect()
}

/// Values of one 16-bit digit of a [`key`].
const DIGITS: usize = 1 << 16;

/// A key of the finite sample `v` whose unsigned order is the order of the
/// values (that of [`f32::total_cmp`]: −0 just before +0).
fn key(v: f32) -> u32 {
    let bits = v.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 0x8000_0000
    }
}

/// The sample of a [`key`].
fn from_key(key: u32) -> f32 {
    f32::from_bits(if key >> 31 == 1 {
        key & 0x7fff_ffff
    } else {
        !key
    })
}

/// The `ranks`-th smallest finite samples (0 the smallest; each rank less than
/// the number of finite samples), in the order of `ranks`.
///
/// A radix selection on the [`key`]s, without a copy or a sort of the samples:
/// one parallel pass counts the high 16 bits of the keys, which tells the high
/// bits of each wanted sample and its rank among the samples sharing them; a
/// second pass counts the low 16 bits of those samples only, which tells the
/// rest.
fn order_statistics(samples: &[f32], ranks: &[usize]) -> Vec<f32> {
    // (bits of the key known so far, rank among the samples sharing them)
    let mut found: Vec<(u32, usize)> = ranks.iter().map(|&rank| (0, rank)).collect();
    for shift in [16, 0] {
        let mut prefixes: Vec<u32> = found.iter().map(|&(prefix, _)| prefix).collect();
        prefixes.sort_unstable();
        prefixes.dedup();
        let counts = digit_counts(samples, shift, &prefixes);
        for (prefix, rank) in &mut found {
            let slot = prefixes.binary_search(prefix).expect("a counted prefix");
            let mut below = 0;
            for (digit, &count) in counts[slot * DIGITS..][..DIGITS].iter().enumerate() {
                if *rank < below + count {
                    *prefix = (*prefix << 16) | digit as u32;
                    *rank -= below;
                    break;
                }
                below += count;
            }
        }
    }
    found.iter().map(|&(key, _)| from_key(key)).collect()
}

/// For each of `prefixes` (at most 2¹⁶), the counts of the digit
/// `key >> shift & 0xffff` of the finite samples whose key bits above it are the
/// prefix: 2¹⁶ counts a prefix, one table after the other. Counted over chunks
/// of the samples in parallel.
fn digit_counts(samples: &[f32], shift: u32, prefixes: &[u32]) -> Vec<usize> {
    let mut slots = vec![u16::MAX; DIGITS];
    for (slot, &prefix) in prefixes.iter().enumerate() {
        slots[prefix as usize] = u16::try_from(slot).expect("at most 2^16 - 1 prefixes");
    }
    let len = prefixes.len() * DIGITS;
    // A few chunks a thread, each with its own table.
    let chunk = (samples.len() / (4 * rayon::current_num_threads())).max(1 << 18);
    samples
        .par_chunks(chunk)
        .map(|chunk| {
            let mut counts = vec![0usize; len];
            for &v in chunk.iter().filter(|v| v.is_finite()) {
                let key = key(v);
                let slot = slots[key.checked_shr(shift + 16).unwrap_or(0) as usize];
                if slot != u16::MAX {
                    counts[usize::from(slot) * DIGITS + (key >> shift) as usize % DIGITS] += 1;
                }
            }
            counts
        })
        .reduce_with(|mut a, b| {
            a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
            a
        })
        .unwrap_or_else(|| vec![0; len])
}

/// `a + t·(b − a)` as numpy's percentile computes it: from `b` when `t ≥ ½`,
/// which keeps the result within `[a, b]` and exact at `t = 1`.
fn lerp(a: f64, b: f64, t: f64) -> f64 {
    let difference = b - a;
    if t >= 0.5 {
        b - difference * (1.0 - t)
    } else {
        a + difference * t
    }
}

/// Otsu's threshold: the bin edge that maximises the between-class variance
/// ω₀ω₁(μ₀ − μ₁)² of the two classes it separates (bins as their centres). Empty
/// bins between two populations give a plateau of equal maxima: its middle is
/// returned.
fn otsu(histogram: &[usize], min: f64, width: f64) -> f64 {
    let centre = |bin: usize| min + (bin as f64 + 0.5) * width;
    let total: f64 = histogram.iter().map(|&c| c as f64).sum();
    let total_sum: f64 = histogram
        .iter()
        .enumerate()
        .map(|(b, &c)| c as f64 * centre(b))
        .sum();
    let (mut count0, mut sum0) = (0.0, 0.0);
    // (variance, first and last edge reaching it)
    let mut best = (f64::NEG_INFINITY, f64::NAN, f64::NAN);
    for (bin, &count) in histogram.iter().enumerate().take(histogram.len() - 1) {
        count0 += count as f64;
        sum0 += count as f64 * centre(bin);
        let count1 = total - count0;
        if count0 == 0.0 || count1 == 0.0 {
            continue;
        }
        let gap = sum0 / count0 - (total_sum - sum0) / count1;
        let between = count0 * count1 * gap * gap;
        let edge = min + (bin + 1) as f64 * width;
        if between > best.0 * (1.0 + 1e-12) {
            best = (between, edge, edge);
        } else if between >= best.0 * (1.0 - 1e-12) {
            best.2 = edge;
        }
    }
    0.5 * (best.1 + best.2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    fn volume(samples: Vec<f32>) -> Volume {
        let n = samples.len();
        Volume::new([n, 1, 1], [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
    }

    #[test]
    fn range_mean_and_percentiles_of_a_ramp() {
        let summary = ValueSummary::of(&volume((0..=1000).map(|v| v as f32).collect()));
        assert_eq!(
            (summary.min, summary.max, summary.non_finite),
            (0.0, 1000.0, 0)
        );
        assert!((summary.mean - 500.0).abs() < 1e-9);
        assert_eq!(summary.histogram.iter().sum::<usize>(), 1001);
        // 1001 samples 0, 1, …, 1000: the rank (n − 1)·p/100 = 10p is the value.
        for (p, value) in &summary.percentiles {
            assert!((value - 10.0 * p).abs() < 1e-9, "{p}: {value}");
        }
    }

    /// The values of [`ValueSummary::percentiles`], in the order of [`PERCENTILES`].
    fn percentile_values(samples: Vec<f32>) -> Vec<f64> {
        let summary = ValueSummary::of(&volume(samples));
        let ps: Vec<f64> = summary.percentiles.iter().map(|&(p, _)| p).collect();
        assert_eq!(ps, PERCENTILES);
        summary.percentiles.iter().map(|&(_, v)| v).collect()
    }

    #[test]
    fn low_percentiles_of_a_mostly_zero_background_are_exactly_zero() {
        // 10000 samples, 78% of them 0 (like a brain-extracted head image) and the
        // others 1, 2, …, 2200, scattered over the grid by the permutation
        // i ↦ 7919·i mod 10000. Sorted, x₀ … x₇₇₉₉ are 0 and x₇₈₀₀₊ₖ = k + 1.
        let samples: Vec<f32> = (0..10_000)
            .map(|i| match (i * 7919) % 10_000 {
                j if j < 7800 => 0.0,
                j => (j - 7799) as f32,
            })
            .collect();
        assert_eq!(samples.iter().filter(|&&v| v == 0.0).count(), 7800);
        let values = percentile_values(samples);
        // 1% … 75%: ranks 99.99 … 7499.25, all among the zeros.
        assert_eq!(values[..5], [0.0; 5]);
        // 95%: rank 9999·0.95 = 9499.05, between x₉₄₉₉ = 1700 and x₉₅₀₀ = 1701;
        // 99%: rank 9899.01, between 2100 and 2101. numpy gives exactly these
        // (the fraction 9499.05 − 9499 is a little under 0.05 in binary).
        assert_eq!(values[5..], [1700.0499999999993, 2100.01]);
    }

    #[test]
    fn percentiles_interpolate_linearly_like_numpy() {
        // [1, 2, 3, 4] (given unsorted): rank r = 3·p/100 and value 1 + r:
        //   1% → r = 0.03 → 1.03     5% → 0.15 → 1.15     25% → 0.75 → 1.75
        //  50% → 1.5 → 2.5          75% → 2.25 → 3.25    95% → 2.85 → 3.85
        //  99% → 2.97 → 3.97
        // np.percentile([1, 2, 3, 4], [1, 5, 25, 50, 75, 95, 99]) prints these,
        // 3.85 and 3.97 as the nearest doubles 3.8499999999999996 and
        // 3.9699999999999998 (interpolated from 4 down: 4 − 0.15·1, 4 − 0.03·1).
        assert_eq!(
            percentile_values(vec![4.0, 1.0, 3.0, 2.0]),
            [
                1.03,
                1.15,
                1.75,
                2.5,
                3.25,
                3.8499999999999996,
                3.9699999999999998
            ]
        );
        // [0, 10, 30], uneven gaps: r = 2·p/100.
        //   1% → 0.02 → 0 + 0.02·10 = 0.2     5% → 0.1 → 1     25% → 0.5 → 5
        //  50% → 1 → 10    75% → 1.5 → 10 + 0.5·20 = 20    95% → 1.9 → 28
        //  99% → 1.98 → 29.6 (numpy: [0.2, 1.0, 5.0, 10.0, 20.0, 28.0, 29.6]).
        assert_eq!(
            percentile_values(vec![10.0, 30.0, 0.0]),
            [0.2, 1.0, 5.0, 10.0, 20.0, 28.0, 29.6]
        );
    }

    #[test]
    fn non_finite_samples_are_left_out_of_the_percentiles() {
        let samples = vec![
            f32::NAN,
            4.0,
            f32::NAN,
            1.0,
            f32::INFINITY,
            3.0,
            f32::NEG_INFINITY,
            2.0,
        ];
        assert_eq!(
            percentile_values(samples),
            percentile_values(vec![1.0, 2.0, 3.0, 4.0])
        );
        assert!(percentile_values(vec![f32::NAN; 4])
            .iter()
            .all(|v| v.is_nan()));
    }

    #[test]
    fn a_single_sample_is_every_percentile() {
        assert_eq!(percentile_values(vec![7.5]), [7.5; 7]);
        assert_eq!(percentile_values(vec![f32::NAN, -2.25]), [-2.25; 7]);
    }

    /// numpy's linear percentile of the finite samples in increasing order, for
    /// comparison.
    fn sorted_percentile(sorted: &[f32], p: f64) -> f64 {
        let rank = (sorted.len() - 1) as f64 * (p / 100.0);
        let below = rank.floor() as usize;
        let above = (below + 1).min(sorted.len() - 1);
        lerp(
            f64::from(sorted[below]),
            f64::from(sorted[above]),
            rank - below as f64,
        )
    }

    #[test]
    fn percentiles_equal_those_of_a_full_sort() {
        // Pseudo-random samples of sizes from 1 to a few chunks of the counting
        // passes: with many ties and zeros of both signs, or with any bits (all
        // exponents, subnormals, infinities and NaNs).
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 32) as u32
        };
        let ps = [
            0.0, 0.1, 1.0, 5.0, 25.0, 33.3, 50.0, 75.0, 95.0, 99.0, 99.9, 100.0,
        ];
        for n in (1..40).chain([1000, 4097, 300_000]) {
            for any_bits in [false, true] {
                let spread = 1 + next() % 500;
                let samples: Vec<f32> = (0..n)
                    .map(|_| match next() % 50 {
                        _ if any_bits => f32::from_bits(next()),
                        0 => f32::NAN,
                        1..=5 => 0.0,
                        6..=10 => -0.0,
                        _ => (next() % spread) as f32 * 0.37 - 40.0,
                    })
                    .collect();
                let mut sorted: Vec<f32> =
                    samples.iter().copied().filter(|v| v.is_finite()).collect();
                sorted.sort_by(f32::total_cmp);
                let exact = percentiles(&samples, sorted.len(), &ps);
                for (&p, &value) in ps.iter().zip(&exact) {
                    if sorted.is_empty() {
                        assert!(value.is_nan());
                    } else {
                        let by_sort = sorted_percentile(&sorted, p);
                        assert_eq!(value.to_bits(), by_sort.to_bits(), "n {n}, {p}%");
                    }
                }
            }
        }
    }

    #[test]
    fn keys_order_the_samples() {
        let samples = [
            f32::NEG_INFINITY,
            f32::MIN,
            -1.5,
            -f32::MIN_POSITIVE,
            -1e-45,
            -0.0,
            0.0,
            1e-45,
            f32::MIN_POSITIVE,
            1.5,
            f32::MAX,
            f32::INFINITY,
        ];
        for pair in samples.windows(2) {
            assert!(key(pair[0]) < key(pair[1]), "{pair:?}");
        }
        for v in samples {
            assert_eq!(from_key(key(v)).to_bits(), v.to_bits());
        }
    }

    #[test]
    fn otsu_splits_two_populations() {
        // 800 samples near 10 (background), 200 near 90 (object).
        let samples = (0..1000)
            .map(|i| {
                if i < 800 {
                    10.0 + (i % 7) as f32
                } else {
                    90.0 - (i % 5) as f32
                }
            })
            .collect();
        let summary = ValueSummary::of(&volume(samples));
        assert!(
            summary.otsu > 17.0 && summary.otsu < 86.0,
            "{}",
            summary.otsu
        );
    }

    #[test]
    fn non_finite_samples_are_counted_and_left_out() {
        let summary = ValueSummary::of(&volume(vec![f32::NAN, 1.0, f32::INFINITY, 3.0]));
        assert_eq!(summary.non_finite, 2);
        assert_eq!((summary.min, summary.max, summary.mean), (1.0, 3.0, 2.0));
        let empty = ValueSummary::of(&volume(vec![f32::NAN; 3]));
        assert_eq!(empty.non_finite, 3);
        assert!(empty.min.is_nan() && empty.otsu.is_nan());
        assert!(empty.percentiles.iter().all(|&(_, v)| v.is_nan()));
    }

    #[test]
    fn constant_volume_has_one_full_bin() {
        let summary = ValueSummary::of(&volume(vec![5.0; 10]));
        assert_eq!(summary.histogram[0], 10);
        assert_eq!((summary.min, summary.max), (5.0, 5.0));
        assert!(summary.percentiles.iter().all(|&(_, v)| v == 5.0));
    }
}
