//! Ridge and valley lines as labels of the vertices of the surface they were
//! traced on, for neuroimaging tools that show per-vertex data: a GIfTI
//! `.label.gii` (Connectome Workbench, nilearn, FreeSurfer's freeview) or a
//! FreeSurfer ASCII `.label`.
//!
//! Every point of a line lies on the surface ([`SurfaceLocation`]): at a
//! vertex, on an edge or inside a face. It labels the corner of that element
//! nearest to it (the largest interpolation weight) with its line's family; a
//! vertex that points of both families reach takes the family of the point
//! nearest to it. The labels follow the vertices of the input file, in its
//! order ([`Mesh::to_input_order`]), so that they fit the surface file
//! whatever the repairs did; a vertex the repairs dropped is unlabelled.
//!
//! - `.label.gii`: one int32 value per vertex, [`UNLABELLED`] (`???`),
//!   [`RIDGE`] (red) or [`VALLEY`] (blue), with the `LabelTable`.
//! - `.label`: the labelled vertices only, with their tkr-RAS positions (the
//!   coordinates of the FreeSurfer surface file) and the value 1 for a ridge
//!   vertex and -1 for a valley vertex.

use std::path::Path;

use crate::io::freesurfer::{write_label, LabelledVertex};
use crate::io::gifti::{write_gifti_labels, GiftiLabel};
use crate::io::{choose_format, FileFormat, Structure};
use crate::mesh::{Mesh, VertexId};
use crate::{Error, Result};

use super::{FeatureLines, LineKind, SurfaceLocation};

/// The label of a vertex no line reaches.
pub const UNLABELLED: i32 = 0;
/// The label of a vertex on a ridge line.
pub const RIDGE: i32 = 1;
/// The label of a vertex on a valley line.
pub const VALLEY: i32 = 2;

/// The formats [`write_vertex_labels`] writes.
pub const LABEL_FORMATS: [FileFormat; 2] = [FileFormat::GiftiLabel, FileFormat::FreeSurferLabel];

/// [`vertex_labels`], its error a message.
fn labels_of(lines: &FeatureLines, mesh: &Mesh) -> std::result::Result<Vec<i32>, String> {
    let mut points = Vec::new();
    for line in lines.iter() {
        let label = family_label(line.kind).ok_or_else(|| {
            format!(
                "vertex labels hold ridge and valley lines, not {} lines",
                line.kind
            )
        })?;
        if line.locations.len() != line.points.len() {
            return Err(
                "the lines do not say where their points lie on the surface (faired \
                        lines leave it), so they cannot label its vertices"
                    .into(),
            );
        }
        for location in &line.locations {
            points.push((label, checked_weights(location, mesh)?));
        }
    }
    Ok(mesh.to_input_order(
        &label_nearest_corners(mesh.vertex_count(), points),
        UNLABELLED,
    ))
}

/// The label of the lines of `kind`: `RIDGE`, `VALLEY`, or `None` for the
/// kinds vertex labels do not hold.
pub fn family_label(kind: LineKind) -> Option<i32> {
    match kind {
        LineKind::Ridge => Some(RIDGE),
        LineKind::Valley => Some(VALLEY),
        _ => None,
    }
}

/// The label of each of `vertex_count` vertices from line points, each given as
/// its family's label and the vertices it interpolates with their weights: a
/// point labels its corner of largest weight, and of the points that label a
/// vertex the one of largest weight there wins. Vertices no point labels are
/// `UNLABELLED`.
pub fn label_nearest_corners(
    vertex_count: usize,
    points: impl IntoIterator<Item = (i32, Vec<(VertexId, f64)>)>,
) -> Vec<i32> {
    let mut labels = vec![UNLABELLED; vertex_count];
    let mut nearest = vec![0.0f64; vertex_count];
    for (label, corners) in points {
        let best = corners
            .into_iter()
            .filter(|(v, _)| v.idx() < vertex_count)
            .fold(None, |best: Option<(VertexId, f64)>, (v, w)| match best {
                Some((_, b)) if b >= w => best,
                _ => Some((v, w)),
            });
        if let Some((v, weight)) = best.filter(|&(v, w)| w > nearest[v.idx()]) {
            nearest[v.idx()] = weight;
            labels[v.idx()] = label;
        }
    }
    labels
}

/// The vertices `location` interpolates, with their weights, once its element
/// is known to be on `mesh`.
fn checked_weights(
    location: &SurfaceLocation,
    mesh: &Mesh,
) -> std::result::Result<Vec<(VertexId, f64)>, String> {
    if let Some(missing) = location.missing_on(mesh) {
        return Err(format!(
            "a line point lies on {missing} (lines of another mesh?)"
        ));
    }
    Ok(location.weights(mesh))
}

/// The GIfTI label table of the families, in their colours ([`LineKind::color`]).
fn label_table() -> Vec<GiftiLabel> {
    let family = |key: i32, kind: LineKind| {
        let [r, g, b] = kind.color_unit().map(|c| c as f32);
        GiftiLabel {
            key,
            name: kind.family().to_string(),
            rgba: [r, g, b, 1.0],
        }
    };
    vec![
        GiftiLabel {
            key: UNLABELLED,
            name: "???".to_string(),
            rgba: [0.0; 4],
        },
        family(RIDGE, LineKind::Ridge),
        family(VALLEY, LineKind::Valley),
    ]
}

/// Write the labels of the vertices `lines` (traced on `mesh`) pass near, in the
/// format of the extension of `path`: `.label.gii` or `.label` (see the module
/// documentation). Written atomically.
///
/// Errors: those of `vertex_labels`, as [`Error::File`] naming `path`, and an
/// unsupported extension.
pub(crate) fn write_vertex_labels(
    path: &Path,
    lines: &FeatureLines,
    mesh: &Mesh,
    structure: Structure,
) -> Result<()> {
    choose_format(path, "vertex labels", &LABEL_FORMATS)?;
    let labels = labels_of(lines, mesh).map_err(|message| Error::File {
        path: path.to_path_buf(),
        message,
    })?;
    write_labels(path, &labels, mesh, structure)
}

/// Write the labels of the vertices of `mesh` that line `points` pass near, as
/// [`write_on_surface`](super::write_on_surface) labels a mesh's own lines: each
/// point given as its line's kind (ridge or valley) and the vertices of `mesh` it
/// interpolates, with their weights; a point labels its corner of largest weight.
/// For lines found elsewhere, located on `mesh`. Written atomically, in the format
/// of the extension of `path`: `.label.gii` (naming `structure`) or `.label`.
///
/// Errors: a point of another kind than ridge or valley ([`Error::Argument`]),
/// and those of writing the labels ([`Error::File`] naming `path`).
pub fn write_point_labels(
    path: &Path,
    mesh: &Mesh,
    points: impl IntoIterator<Item = (LineKind, Vec<(VertexId, f64)>)>,
    structure: Structure,
) -> Result<()> {
    let labelled = points
        .into_iter()
        .map(|(kind, corners)| {
            let label = family_label(kind).ok_or_else(|| {
                Error::Argument(format!(
                    "vertex labels hold ridge and valley lines, not {kind} lines"
                ))
            })?;
            Ok((label, corners))
        })
        .collect::<Result<Vec<_>>>()?;
    let labels = label_nearest_corners(mesh.vertex_count(), labelled);
    write_labels(
        path,
        &mesh.to_input_order(&labels, UNLABELLED),
        mesh,
        structure,
    )
}

/// Write `labels`, one per vertex of the input surface of `mesh` in its order
/// (`UNLABELLED`, `RIDGE` or `VALLEY`, as `vertex_labels` gives them), in
/// the format of the extension of `path`: `.label.gii` or `.label` (see the
/// module documentation), a GIfTI file naming `structure` as Workbench reads it.
/// Written atomically.
///
/// Errors ([`Error::File`] naming `path`): an unsupported extension, not one
/// label per input vertex, or another label.
pub fn write_labels(path: &Path, labels: &[i32], mesh: &Mesh, structure: Structure) -> Result<()> {
    let format = choose_format(path, "vertex labels", &LABEL_FORMATS)?;
    let fail = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let count = mesh.input_vertices().len();
    if labels.len() != count {
        return Err(fail(format!(
            "{} labels for a surface of {count} vertices",
            labels.len()
        )));
    }
    if let Some(v) = labels
        .iter()
        .position(|l| ![UNLABELLED, RIDGE, VALLEY].contains(l))
    {
        return Err(fail(format!(
            "vertex {v} has the label {}, not {UNLABELLED}, {RIDGE} or {VALLEY}",
            labels[v]
        )));
    }
    match format {
        FileFormat::FreeSurferLabel => write_label(path, &labelled_vertices(labels, mesh)),
        _ => write_gifti_labels(
            path,
            labels,
            &label_table(),
            &[("Name", "crest lines")],
            &structure.gifti_metadata(),
        ),
    }
}

/// The labelled input vertices, with their tkr-RAS positions and the values of a
/// FreeSurfer label (1 ridge, -1 valley).
fn labelled_vertices(labels: &[i32], mesh: &Mesh) -> Vec<LabelledVertex> {
    let inputs = mesh.input_vertices();
    let labelled: Vec<(usize, VertexId)> = labels
        .iter()
        .enumerate()
        .filter(|(_, &label)| label != UNLABELLED)
        .filter_map(|(i, _)| Some((i, inputs[i]?)))
        .collect();
    let positions: Vec<_> = labelled.iter().map(|&(_, v)| mesh.position(v)).collect();
    let tkr = crate::space::to_tkr(&positions, mesh.volume_geometry());
    labelled
        .iter()
        .zip(tkr)
        .map(|(&(i, _), position)| LabelledVertex {
            vertex: i as u32,
            position,
            value: if labels[i] == RIDGE { 1.0 } else { -1.0 },
        })
        .collect()
}
