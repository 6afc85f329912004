//! A small chart of the cancellation hierarchy: significance (linear: the feature
//! criterion can be negative) against the number of saddles left (logarithmic), as
//! SVG rendered to PNG. Labels are drawn with a built-in
//! stroke font, so the PNG needs no system fonts.

use std::fmt::Write as _;
use std::path::Path;

use crestline::Result;

/// Canvas and plot area, in pixels.
const WIDTH: f64 = 480.0;
const HEIGHT: f64 = 320.0;
const LEFT: f64 = 78.0;
const RIGHT: f64 = 16.0;
const TOP: f64 = 28.0;
const BOTTOM: f64 = 52.0;

/// Write the chart of `points` (saddles left, significance), in the order of the
/// cancellations (significance non-decreasing), with a dashed mark at `kept`
/// saddles, to the PNG `path`.
pub fn write_hierarchy_png(path: &Path, points: &[(f64, f64)], kept: f64) -> Result<()> {
    crestline::draw::write_png(path, &hierarchy_svg(points, kept), None)
}

/// The chart as an SVG document.
fn hierarchy_svg(points: &[(f64, f64)], kept: f64) -> String {
    let usable: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|&(x, y)| x >= 1.0 && y.is_finite())
        .collect();
    let x_axis = LogAxis::spanning(usable.iter().map(|p| p.0).chain([kept.max(1.0)]));
    // The first cancellations can be far below the rest (the feature criterion
    // is negative there): the axis shows the last 99%, lower values sit on it.
    let y_axis = LinearAxis::spanning(usable.iter().skip(usable.len() / 100).map(|p| p.1));
    let to_x = |x: f64| LEFT + x_axis.fraction(x) * (WIDTH - LEFT - RIGHT);
    let to_y =
        |y: f64| HEIGHT - BOTTOM - y_axis.fraction(y).clamp(0.0, 1.0) * (HEIGHT - TOP - BOTTOM);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\">\
         <rect width=\"{WIDTH}\" height=\"{HEIGHT}\" fill=\"#ffffff\"/>\
         <g fill=\"none\" stroke=\"#333333\" stroke-width=\"1\" stroke-linecap=\"round\">"
    );
    let (x0, y0) = (LEFT, HEIGHT - BOTTOM);
    let _ = write!(svg, "<path d=\"M{x0} {TOP}V{y0}H{}\"/>", WIDTH - RIGHT);
    for (value, label) in x_axis.ticks() {
        let x = to_x(value);
        let _ = write!(svg, "<path d=\"M{x:.1} {y0}v5\"/>");
        text(&mut svg, &label, x - label_width(&label) / 2.0, y0 + 9.0);
    }
    for (value, label) in y_axis.ticks() {
        let y = to_y(value);
        let _ = write!(svg, "<path d=\"M{x0} {y:.1}h-5\"/>");
        text(&mut svg, &label, x0 - 9.0 - label_width(&label), y - 4.0);
    }
    let title = "saddles left";
    text(
        &mut svg,
        title,
        (LEFT + WIDTH - RIGHT - label_width(title)) / 2.0,
        HEIGHT - 20.0,
    );
    text(&mut svg, "significance", 4.0, 4.0);
    svg.push_str("</g>");
    if !usable.is_empty() {
        let curve: Vec<String> = usable
            .iter()
            .map(|&(x, y)| format!("{:.1} {:.1}", to_x(x), to_y(y)))
            .collect();
        let _ = write!(
            svg,
            "<path d=\"M{}\" fill=\"none\" stroke=\"#d35400\" stroke-width=\"1.5\"/>",
            curve.join("L")
        );
    }
    let x = to_x(kept.max(1.0));
    let _ = write!(
        svg,
        "<path d=\"M{x:.1} {TOP}V{y0}\" stroke=\"#2471a3\" stroke-dasharray=\"4 3\"/></svg>"
    );
    svg
}

/// A logarithmic axis over whole decades.
struct LogAxis {
    low: i32,
    high: i32,
}

impl LogAxis {
    /// The decades covering the positive `values` (one decade without any).
    fn spanning(values: impl Iterator<Item = f64>) -> LogAxis {
        let (mut low, mut high) = (i32::MAX, i32::MIN);
        for value in values.filter(|v| *v > 0.0 && v.is_finite()) {
            low = low.min(value.log10().floor() as i32);
            high = high.max(value.log10().ceil() as i32);
        }
        if low > high {
            return LogAxis { low: 0, high: 1 };
        }
        LogAxis {
            low,
            high: high.max(low + 1),
        }
    }

    /// Where `value` lies on the axis, from 0 to 1.
    fn fraction(&self, value: f64) -> f64 {
        (value.log10() - f64::from(self.low)) / f64::from(self.high - self.low)
    }

    /// A tick at every decade (every other one beyond six), with its label.
    fn ticks(&self) -> Vec<(f64, String)> {
        let step = if self.high - self.low > 6 { 2 } else { 1 };
        (self.low..=self.high)
            .step_by(step)
            .map(|e| (10f64.powi(e), decade_label(e)))
            .collect()
    }
}

/// A linear axis from and to multiples of a round step (1, 2 or 5 times a power
/// of ten), with about five steps.
struct LinearAxis {
    low: f64,
    high: f64,
    step: f64,
}

impl LinearAxis {
    /// The axis covering the finite `values` ([0, 1] without any).
    fn spanning(values: impl Iterator<Item = f64>) -> LinearAxis {
        let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
        for value in values.filter(|v| v.is_finite()) {
            (min, max) = (min.min(value), max.max(value));
        }
        if min > max {
            (min, max) = (0.0, 1.0);
        }
        if max - min <= f64::EPSILON * max.abs().max(1.0) {
            (min, max) = (min - 0.5, max + 0.5);
        }
        let rough = (max - min) / 5.0;
        let power = 10f64.powf(rough.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * power)
            .find(|&s| s >= rough)
            .unwrap_or(10.0 * power);
        LinearAxis {
            low: (min / step).floor() * step,
            high: (max / step).ceil() * step,
            step,
        }
    }

    /// Where `value` lies on the axis, from 0 to 1.
    fn fraction(&self, value: f64) -> f64 {
        (value - self.low) / (self.high - self.low)
    }

    /// A tick at every step, with its label.
    fn ticks(&self) -> Vec<(f64, String)> {
        let count = ((self.high - self.low) / self.step).round() as i64;
        let decimals = (-self.step.log10().floor()).max(0.0) as usize;
        (0..=count)
            .map(|k| {
                let value = self.low + k as f64 * self.step;
                let label = if value.abs() >= 1e5 {
                    format!("{value:.0e}")
                } else {
                    format!("{:.*}", decimals, value + 0.0)
                };
                (value, label)
            })
            .collect()
    }
}

/// "0.01", "1", "100", "1e5", "1e-4": short labels of 10^e.
fn decade_label(e: i32) -> String {
    match e {
        -2..=0 => format!("{}", 10f64.powi(e)),
        1..=3 => format!("{}", 10i64.pow(e as u32)),
        _ => format!("1e{e}"),
    }
}

/// Strokes of the characters the labels use, on a grid 4 wide and 6 high (y
/// down, lower-case letters from 3 to 6, descenders to 8).
fn glyph(c: char) -> &'static [&'static [(f64, f64)]] {
    match c {
        '0' => &[&[(0.0, 0.0), (4.0, 0.0), (4.0, 6.0), (0.0, 6.0), (0.0, 0.0)]],
        '1' => &[&[(1.0, 1.0), (2.0, 0.0), (2.0, 6.0)]],
        '2' => &[&[
            (0.0, 0.0),
            (4.0, 0.0),
            (4.0, 3.0),
            (0.0, 3.0),
            (0.0, 6.0),
            (4.0, 6.0),
        ]],
        '3' => &[
            &[(0.0, 0.0), (4.0, 0.0), (4.0, 6.0), (0.0, 6.0)],
            &[(1.0, 3.0), (4.0, 3.0)],
        ],
        '4' => &[
            &[(0.0, 0.0), (0.0, 3.0), (4.0, 3.0)],
            &[(4.0, 0.0), (4.0, 6.0)],
        ],
        '5' => &[&[
            (4.0, 0.0),
            (0.0, 0.0),
            (0.0, 3.0),
            (4.0, 3.0),
            (4.0, 6.0),
            (0.0, 6.0),
        ]],
        '6' => &[&[
            (4.0, 0.0),
            (0.0, 0.0),
            (0.0, 6.0),
            (4.0, 6.0),
            (4.0, 3.0),
            (0.0, 3.0),
        ]],
        '7' => &[&[(0.0, 0.0), (4.0, 0.0), (4.0, 6.0)]],
        '8' => &[
            &[(0.0, 0.0), (4.0, 0.0), (4.0, 6.0), (0.0, 6.0), (0.0, 0.0)],
            &[(0.0, 3.0), (4.0, 3.0)],
        ],
        '9' => &[&[
            (4.0, 3.0),
            (0.0, 3.0),
            (0.0, 0.0),
            (4.0, 0.0),
            (4.0, 6.0),
            (0.0, 6.0),
        ]],
        '.' => &[&[(2.0, 5.5), (2.0, 6.0)]],
        '-' => &[&[(0.5, 3.0), (3.5, 3.0)]],
        'a' => &[&[
            (0.0, 3.0),
            (4.0, 3.0),
            (4.0, 6.0),
            (0.0, 6.0),
            (0.0, 4.5),
            (4.0, 4.5),
        ]],
        'c' => &[&[(4.0, 3.0), (0.0, 3.0), (0.0, 6.0), (4.0, 6.0)]],
        'd' => &[&[(4.0, 0.0), (4.0, 6.0), (0.0, 6.0), (0.0, 3.0), (4.0, 3.0)]],
        'e' => &[&[
            (4.0, 6.0),
            (0.0, 6.0),
            (0.0, 3.0),
            (4.0, 3.0),
            (4.0, 4.5),
            (0.0, 4.5),
        ]],
        'f' => &[
            &[(4.0, 0.0), (2.0, 0.0), (2.0, 6.0)],
            &[(0.0, 3.0), (4.0, 3.0)],
        ],
        'g' => &[&[
            (4.0, 6.0),
            (0.0, 6.0),
            (0.0, 3.0),
            (4.0, 3.0),
            (4.0, 8.0),
            (0.0, 8.0),
        ]],
        'i' => &[&[(2.0, 3.0), (2.0, 6.0)], &[(2.0, 1.5), (2.0, 2.0)]],
        'k' => &[
            &[(0.0, 0.0), (0.0, 6.0)],
            &[(4.0, 3.0), (0.0, 4.5), (4.0, 6.0)],
        ],
        'l' => &[&[(2.0, 0.0), (2.0, 6.0)]],
        'n' => &[&[(0.0, 6.0), (0.0, 3.0), (4.0, 3.0), (4.0, 6.0)]],
        'p' => &[&[(0.0, 8.0), (0.0, 3.0), (4.0, 3.0), (4.0, 6.0), (0.0, 6.0)]],
        's' => &[&[
            (4.0, 3.0),
            (0.0, 3.0),
            (0.0, 4.5),
            (4.0, 4.5),
            (4.0, 6.0),
            (0.0, 6.0),
        ]],
        't' => &[
            &[(2.0, 1.0), (2.0, 6.0), (4.0, 6.0)],
            &[(0.0, 3.0), (4.0, 3.0)],
        ],
        _ => &[],
    }
}

/// Pixels per grid unit of the stroke font, and the advance of a character.
const SCALE: f64 = 1.6;
const ADVANCE: f64 = 6.0 * SCALE;

/// The width of `label` in pixels.
fn label_width(label: &str) -> f64 {
    label.chars().count() as f64 * ADVANCE - 2.0 * SCALE
}

/// `label` in the stroke font with its top left at (x, y).
fn text(svg: &mut String, label: &str, x: f64, y: f64) {
    for (i, c) in label.chars().enumerate() {
        let left = x + i as f64 * ADVANCE;
        for stroke in glyph(c) {
            let points: Vec<String> = stroke
                .iter()
                .map(|(gx, gy)| format!("{:.1} {:.1}", left + gx * SCALE, y + gy * SCALE))
                .collect();
            let _ = write!(svg, "<path d=\"M{}\"/>", points.join("L"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_label_character_has_strokes() {
        for label in ["saddles left", "significance", "0.01", "1e-45", "1000"] {
            for c in label.chars().filter(|c| *c != ' ') {
                assert!(!glyph(c).is_empty(), "{c}");
            }
        }
    }

    #[test]
    fn decades_cover_the_values() {
        let axis = LogAxis::spanning([0.03, 250.0].into_iter());
        assert_eq!((axis.low, axis.high), (-2, 3));
        assert!((axis.fraction(0.01) - 0.0).abs() < 1e-12);
        assert!((axis.fraction(1000.0) - 1.0).abs() < 1e-12);
        let labels: Vec<String> = axis.ticks().into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["0.01", "0.1", "1", "10", "100", "1000"]);
    }

    #[test]
    fn linear_ticks_are_round_and_cover_negative_values() {
        let axis = LinearAxis::spanning([-108.0, 10.7].into_iter());
        let labels: Vec<String> = axis.ticks().into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["-150", "-100", "-50", "0", "50"]);
        assert!(axis.fraction(-150.0).abs() < 1e-12);
        let small = LinearAxis::spanning([0.013, 0.061].into_iter());
        let labels: Vec<String> = small.ticks().into_iter().map(|t| t.1).collect();
        assert_eq!(
            labels,
            ["0.01", "0.02", "0.03", "0.04", "0.05", "0.06", "0.07"]
        );
    }
}
