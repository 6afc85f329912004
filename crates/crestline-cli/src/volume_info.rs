//! `crestline info` on a 3D image: grid, placement in the world, and what its values
//! look like, to help choose an isosurface `--level`.

use std::path::Path;

use crate::report::Report;
use crestline::jobs::image_info;
use crestline::volume::{ValueSummary, Volume};
use crestline::{Result, Space};

use super::outputs::OutputSet;
use super::surface::SeriesArg;
use super::ReportArg;

/// Read the volume at `path`, print its summary and write the report if asked.
pub fn run(
    path: &Path,
    series: &SeriesArg,
    report_arg: &ReportArg,
    mut report: Report,
) -> Result<()> {
    let volume = report.stage("read", || series.options().read(path))?;
    let values = image_info(&volume, &mut report);
    let scale = values
        .otsu
        .is_finite()
        .then(|| volume.feature_scale(values.otsu, volume.voxel_size()));
    if let Some(scale) = scale {
        report.count("scale", scale);
    }
    super::print_stdout(&summary(path, &volume, &values, scale));
    if let Some(report_path) = &report_arg.report {
        let [nx, ny, nz] = volume.dims();
        report.count("nx", nx);
        report.count("ny", ny);
        report.count("nz", nz);
        report.count("voxels", volume.len());
        report.section("space", volume.space());
        report.section("spacing", volume.spacing());
        report.section("origin", volume.origin());
        report.section("direction", volume.direction().transpose().as_slice());
        report.section("values", &values);
        let mut files = OutputSet::default();
        files.write(report_path, |p| report.write(p))?;
        files.commit()?;
    }
    Ok(())
}

/// The human-readable summary, one fact per line.
fn summary(path: &Path, volume: &Volume, values: &ValueSummary, scale: Option<f64>) -> String {
    let [nx, ny, nz] = volume.dims();
    let [sx, sy, sz] = volume.spacing();
    let [ox, oy, oz] = volume.origin();
    let (low, high) = world_box(volume);
    let percentiles = values
        .percentiles
        .iter()
        .map(|(p, v)| format!("{p}%: {v:.4}"))
        .collect::<Vec<_>>()
        .join("  ");
    [
        format!("file              {}", path.display()),
        format!(
            "dimensions        {nx} × {ny} × {nz} ({} voxels)",
            volume.len()
        ),
        format!("world frame       {}", frame(volume)),
        format!("spacing           {sx:.6} × {sy:.6} × {sz:.6}"),
        format!("origin            [{ox:.4}, {oy:.4}, {oz:.4}]"),
        format!("index axes        {}", axis_directions(volume)),
        format!(
            "world box         [{:.4}, {:.4}, {:.4}] .. [{:.4}, {:.4}, {:.4}]",
            low[0], low[1], low[2], high[0], high[1], high[2]
        ),
        format!(
            "values            {:.6} .. {:.6}, mean {:.6}",
            values.min, values.max, values.mean
        ),
        format!("non-finite        {}", values.non_finite),
        format!("percentiles       {percentiles}"),
        format!("histogram (log)   {}", sparkline(&values.histogram)),
        otsu_line(values.otsu),
    ]
    .into_iter()
    .chain(scale.map(|scale| {
        format!(
            "feature scale     {scale:.4} at Otsu's level (2% of the cube root of the volume \
             inside; it follows --level, or give --scale)"
        )
    }))
    .collect::<Vec<_>>()
    .join("\n")
        + "\n"
}

/// Otsu's level, or why there is none (a constant image has no two classes).
fn otsu_line(otsu: f64) -> String {
    if otsu.is_finite() {
        format!("Otsu level        {otsu:.6} (separates object from background; a first --level to try)")
    } else {
        "Otsu level        none (the image has a single value: no object to separate)".to_string()
    }
}

/// The anatomical frame of the world coordinates, as the file declares it.
fn frame(volume: &Volume) -> String {
    match volume.space() {
        Some(space) => format!(
            "{space} (x to the {})",
            match space {
                Space::Ras => "right, y to the front, z up",
                Space::Lps => "left, y to the back, z up",
            }
        ),
        None => "none declared (not an anatomical frame)".to_string(),
    }
}

/// Where the index axes point, e.g. `i → +x, j → −y, k → +z` (the world axis each
/// index axis is closest to, with the cosine when it is oblique).
fn axis_directions(volume: &Volume) -> String {
    let direction = volume.direction();
    ["i", "j", "k"]
        .iter()
        .enumerate()
        .map(|(axis, name)| {
            let column = direction.column(axis);
            let (world, value) = (0..3)
                .map(|row| (row, column[row]))
                .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                .expect("three rows");
            let sign = if value < 0.0 { '−' } else { '+' };
            let letter = ['x', 'y', 'z'][world];
            let cosine = value.abs() / column.norm();
            if cosine > 1.0 - 1e-6 {
                format!("{name} → {sign}{letter}")
            } else {
                format!("{name} → {sign}{letter} (cos {cosine:.3})")
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The world bounding box of the voxel centres.
fn world_box(volume: &Volume) -> ([f64; 3], [f64; 3]) {
    let [nx, ny, nz] = volume.dims().map(|n| (n - 1) as f64);
    let mut low = [f64::INFINITY; 3];
    let mut high = [f64::NEG_INFINITY; 3];
    for corner in 0..8 {
        let index = [
            if corner & 1 == 0 { 0.0 } else { nx },
            if corner & 2 == 0 { 0.0 } else { ny },
            if corner & 4 == 0 { 0.0 } else { nz },
        ];
        let p = volume.index_to_world(index);
        for axis in 0..3 {
            low[axis] = low[axis].min(p[axis]);
            high[axis] = high[axis].max(p[axis]);
        }
    }
    (low, high)
}

/// The histogram as a row of block characters, heights by log(1 + count).
fn sparkline(histogram: &[usize]) -> String {
    const BLOCKS: [char; 9] = [' ', '▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    let height = |count: usize| (count as f64).ln_1p();
    let top = histogram.iter().map(|&c| height(c)).fold(0.0, f64::max);
    histogram
        .iter()
        .map(|&count| {
            let level = if top > 0.0 { height(count) / top } else { 0.0 };
            BLOCKS[(level * 8.0).round() as usize]
        })
        .collect()
}
