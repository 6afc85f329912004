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
    /// `(p, value)` for each `p` of [`PERCENTILES`], read off the histogram (to
    /// within one bin width).
    pub percentiles: Vec<(f64, f64)>,
    /// Counts of finite samples in [`HISTOGRAM_BINS`] equal bins from `min` to
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
            .map(|&p| (p, percentile(&histogram, p, range.min, width)))
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

/// The value below which `p` percent of the counted samples lie, interpolated
/// linearly inside its bin.
fn percentile(histogram: &[usize], p: f64, min: f64, width: f64) -> f64 {
    let total: usize = histogram.iter().sum();
    if total == 0 {
        return f64::NAN;
    }
    let target = p / 100.0 * total as f64;
    let mut below = 0.0;
    for (bin, &count) in histogram.iter().enumerate() {
        let next = below + count as f64;
        if next >= target && count > 0 {
            let inside = (target - below) / count as f64;
            return min + (bin as f64 + inside) * width;
        }
        below = next;
    }
    min + histogram.len() as f64 * width
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
        for (p, value) in &summary.percentiles {
            assert!(
                (value - 10.0 * p).abs() <= summary.bin_width(),
                "{p}: {value}"
            );
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
    }

    #[test]
    fn constant_volume_has_one_full_bin() {
        let summary = ValueSummary::of(&volume(vec![5.0; 10]));
        assert_eq!(summary.histogram[0], 10);
        assert_eq!((summary.min, summary.max), (5.0, 5.0));
        assert!(summary.percentiles.iter().all(|&(_, v)| v == 5.0));
    }
}
