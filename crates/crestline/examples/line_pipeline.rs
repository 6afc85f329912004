//! Every stage of the line pipeline replaced by the caller's own: an extractor
//! (iso-lines of a scalar field), a filter (by the length of a line) and an
//! exporter (CSV), next to the crate's own ([`crestline::lines::MinStrength`],
//! [`crestline::lines::LineFormat`]). The fourth stage, curvature, is shown in
//! `custom_estimator.rs`.
//!
//! The extractor is built from the crate's shared line tools: [`ZeroSet`] traces the
//! zero set of any per-vertex function (the same tracer draws ridges and
//! silhouettes), [`chain`] joins the segments into polylines, and each point keeps
//! its [`SurfaceLocation`].
//!
//! `cargo run --release --example line_pipeline [-- --output OUT.csv]`
//! (an option rather than a bare path: `cargo test FILTER` runs this example
//! with the filter as its argument)

use std::io::Write;
use std::path::{Path, PathBuf};

use crestline::io::read_mesh;
use crestline::io::write_atomically;
use crestline::lines::{
    chain, FeatureLines, LineExporter, LineExtractor, LineFilter, LineFormat, LineKind, LinePoint,
    Polyline, SurfaceWithValues, ZeroSet,
};
use crestline::mesh::Mesh;
use crestline::progress::{Observer, Silent};

/// Iso-lines of a per-vertex scalar at the given levels.
struct IsoLines {
    levels: Vec<f64>,
}

impl LineExtractor<SurfaceWithValues<'_>> for IsoLines {
    fn extract(
        &self,
        surface: &SurfaceWithValues<'_>,
        _: &mut dyn Observer,
    ) -> crestline::Result<FeatureLines> {
        let mesh = surface.mesh;
        let mut lines = FeatureLines::new("iso-lines");
        for &level in &self.levels {
            let shifted = surface.values.iter().map(|v| v - level).collect();
            let zero_set = ZeroSet::new(shifted);
            let segments = zero_set.segments(mesh);
            // Strength ∫ 1 ds: the length of each connected piece.
            let locate = |p: LinePoint| (zero_set.location(mesh, p).position(mesh), 1.0);
            for piece in chain(&segments, locate, 0.0) {
                let locations: Vec<_> = piece
                    .points
                    .iter()
                    .map(|&p| zero_set.location(mesh, p))
                    .collect();
                let points = locations.iter().map(|at| at.position(mesh)).collect();
                let line = Polyline::new(LineKind::Contour, piece.closed, piece.strength, points)
                    .with_values("level", vec![level; locations.len()])
                    .with_locations(locations);
                lines.push(line);
            }
        }
        Ok(lines)
    }
}

/// Keeps lines with at least this many points.
struct MinPoints(usize);

impl LineFilter for MinPoints {
    fn keep(&self, line: &Polyline) -> bool {
        line.points.len() >= self.0
    }
}

/// One CSV row per point: line, point, x, y, z, level.
struct Csv;

impl LineExporter for Csv {
    fn export(&self, path: &Path, lines: &FeatureLines) -> crestline::Result<()> {
        lines.validate()?;
        write_atomically(path, |w| {
            writeln!(w, "line,point,x,y,z,level")?;
            for (l, line) in lines.iter().enumerate() {
                let levels = &line.values["level"];
                for (i, (p, level)) in line.points.iter().zip(levels).enumerate() {
                    writeln!(w, "{l},{i},{},{},{},{level}", p.x, p.y, p.z)?;
                }
            }
            Ok(())
        })
    }
}

fn main() -> crestline::Result<()> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny_small.obj");
    let (mesh, _repairs) = Mesh::from_soup(read_mesh(&path)?).map_err(|e| e.in_file(&path))?;
    let height: Vec<f64> = mesh.positions().iter().map(|p| p.y).collect();
    let (low, high) = height
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let levels = (1..10)
        .map(|i| low + (high - low) * f64::from(i) / 10.0)
        .collect();
    let surface = SurfaceWithValues {
        mesh: &mesh,
        values: &height,
    };
    let mut lines = IsoLines { levels }.extract(&surface, &mut Silent)?;
    let found = lines.len();
    lines.filter(&MinPoints(8));
    lines.filter(&crestline::lines::MinStrength(0.02 * (high - low)));
    println!(
        "bunny: {found} iso-lines of the height at 9 levels, {} kept ({} closed)",
        lines.len(),
        lines.iter().filter(|l| l.closed).count()
    );
    let out = std::env::args()
        .skip_while(|a| a != "--output")
        .nth(1)
        .map_or_else(
            || std::env::temp_dir().join("crestline-iso-lines.csv"),
            PathBuf::from,
        );
    let exporters: [(&dyn LineExporter, PathBuf); 2] = [
        (&Csv, out.clone()),
        (&LineFormat::Vtk, out.with_extension("vtk")),
    ];
    for (exporter, file) in exporters {
        exporter.export(&file, &lines)?;
        println!("wrote {}", file.display());
    }
    // Every iso-line point lies at its level.
    for line in &lines {
        for at in &line.locations {
            let value = at.interpolate(&mesh, &height);
            assert!((value - line.values["level"][0]).abs() < 1e-9 * (high - low));
        }
    }
    assert!(lines.iter().any(|l| l.closed));
    Ok(())
}
