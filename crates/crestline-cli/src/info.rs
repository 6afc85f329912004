//! `crestline info`: what a mesh or image file contains.

use std::path::{Path, PathBuf};

use crestline::io::is_volume_path;
use crestline::jobs::{mesh_info, MeshInfo};
use crestline::mesh::{ComponentInfo, RepairReport};
use crestline::Result;

use super::load::{load_mesh, report_with_progress, StrictArg};
use super::outputs::{check_paths, OutputSet};
use super::surface::SeriesArg;
use super::volume_info;
use super::ReportArg;

/// Arguments of `crestline info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// The mesh (.obj, .ply, .off, .stl, .gii, a FreeSurfer surface) or 3D image
    /// (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, or a DICOM folder, DICOMDIR or .dcm
    /// file).
    #[arg(value_name = "MESH|VOLUME")]
    pub input: PathBuf,
    #[command(flatten)]
    pub series: SeriesArg,
    #[command(flatten)]
    pub strict: StrictArg,
    #[command(flatten)]
    pub report: ReportArg,
}

/// Load the mesh or volume and print its summary to stdout.
pub fn run(args: &InfoArgs) -> Result<()> {
    let outputs: Vec<_> = args.report.output().into_iter().collect();
    check_paths(&[("the input", &args.input)], &outputs)?;
    let mut report = report_with_progress("info", &args.input);
    if is_volume_path(&args.input) {
        return volume_info::run(&args.input, &args.series, &args.report, report);
    }
    let (mesh, repairs) = load_mesh(&args.input, args.strict, &mut report)?;
    let info = mesh_info(&mesh, &mut report);
    super::print_stdout(&summary(&args.input, &info, &repairs));
    if let Some(path) = &args.report.report {
        report.count("euler_characteristic", info.euler_characteristic);
        report.section("repairs", &repairs);
        let mut files = OutputSet::default();
        files.write(path, |p| report.write(p))?;
        files.commit()?;
    }
    Ok(())
}

/// The human-readable summary, one fact per line.
fn summary(path: &Path, info: &MeshInfo, repairs: &RepairReport) -> String {
    let bbox = &info.bounding_box;
    let [vertices, faces, edges] = info.counts;
    let mut lines = vec![
        format!("file              {}", path.display()),
        format!("vertices          {vertices}"),
        format!("faces             {faces}"),
        format!("edges             {edges}"),
        format!("boundary loops    {}", info.boundary_loops),
        format!("components        {}", info.components.len()),
        format!("euler char.       {}", info.euler_characteristic),
        format!("genus             {}", genus_list(&info.components)),
        format!(
            "bounding box      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
            bbox.min.x, bbox.min.y, bbox.min.z, bbox.max.x, bbox.max.y, bbox.max.z
        ),
        format!("diagonal          {:.6}", bbox.diagonal()),
        format!("mean edge length  {:.6}", info.mean_edge_length),
        format!(
            "feature scale     {:.6} (1% of the square root of the area; --scale)",
            info.feature_scale
        ),
    ];
    let messages = repairs.messages();
    if messages.is_empty() {
        lines.push("repairs           none".into());
    } else {
        lines.push(format!(
            "repairs           {}",
            messages.join("\n                  ")
        ));
    }
    lines.join("\n") + "\n"
}

/// The genus of each component, largest components first (at most ten listed).
fn genus_list(components: &[ComponentInfo]) -> String {
    let mut sorted: Vec<&ComponentInfo> = components.iter().collect();
    sorted.sort_by_key(|c| std::cmp::Reverse(c.faces));
    let mut text = sorted
        .iter()
        .take(10)
        .map(|c| {
            let boundary = if c.boundary_loops > 0 {
                format!(" ({} boundary loops)", c.boundary_loops)
            } else {
                String::new()
            };
            format!("{}{boundary}", c.genus)
        })
        .collect::<Vec<_>>()
        .join(", ");
    if sorted.len() > 10 {
        text += &format!(", ... ({} more components)", sorted.len() - 10);
    }
    text
}
