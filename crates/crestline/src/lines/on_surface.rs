//! Files of lines that refer to the vertices of the surface file the lines were
//! traced on, rather than to positions: vertex labels (`.label.gii`, `.label`) and
//! Workbench border files (`.border`). They fit that file vertex for vertex, in its
//! order, whatever the repairs made of it on reading.

use std::collections::HashMap;
use std::path::Path;

use super::{write_border, write_vertex_labels, BorderSurface, FeatureLines, LABEL_FORMATS};
use crate::io::{choose_format, FileFormat, Structure};
use crate::mesh::Mesh;
use crate::Result;

/// The formats [`write_on_surface`] writes: the vertex labels and `.border`.
pub const SURFACE_FORMATS: [FileFormat; 3] =
    [LABEL_FORMATS[0], LABEL_FORMATS[1], FileFormat::Border];

/// Write `lines`, traced on `mesh`, in the format of the extension of `path`
/// ([`SURFACE_FORMATS`]): labels of the vertices they pass near
/// (`write_vertex_labels`) or a border file (`write_border`) whose triangles
/// are numbered as in the file the mesh was read from. `structure` is the border
/// file's and a GIfTI label file's.
pub fn write_on_surface(
    path: &Path,
    lines: &FeatureLines,
    mesh: &Mesh,
    structure: Structure,
) -> Result<()> {
    if choose_format(path, "lines on a surface", &SURFACE_FORMATS)? != FileFormat::Border {
        return write_vertex_labels(path, lines, mesh, structure);
    }
    let numbers = FileNumbers::of(mesh);
    let surface = BorderSurface {
        file_vertex: Some(&numbers.of_mesh_vertex),
        file_vertex_count: numbers.file_vertex_count,
        ..BorderSurface::of_mesh(mesh, structure)
    };
    write_border(path, lines, &surface).map_err(|e| e.in_file(path))
}

/// The numbering of the vertices of the file a mesh was read from.
struct FileNumbers {
    /// The number in the file of each mesh vertex.
    of_mesh_vertex: Vec<u32>,
    /// How many vertices the file holds.
    file_vertex_count: usize,
}

impl FileNumbers {
    /// The numbers of the vertices of `mesh` in its input ([`Mesh::input_vertices`]);
    /// a mesh not built from a soup keeps its own.
    fn of(mesh: &Mesh) -> FileNumbers {
        let inputs = mesh.input_vertices();
        if inputs.is_empty() {
            return FileNumbers {
                of_mesh_vertex: (0..mesh.vertex_count() as u32).collect(),
                file_vertex_count: mesh.vertex_count(),
            };
        }
        FileNumbers {
            of_mesh_vertex: input_numbers(mesh),
            file_vertex_count: inputs.len(),
        }
    }
}

/// The number in the input file of each mesh vertex: the input vertex it came
/// from ([`Mesh::input_vertices`]). A copy made where several fans of faces met at
/// one input vertex takes the number of the input vertex at its position, which is
/// that vertex or a duplicate of it the repairs welded: a triangle of the file with
/// that corner has the same point there. (Every copy has one; were one missing,
/// its own number would stand, and the border writer refuses a number beyond the
/// file's.)
fn input_numbers(mesh: &Mesh) -> Vec<u32> {
    let inputs = mesh.input_vertices();
    let mut numbers = vec![None; mesh.vertex_count()];
    for (input, vertex) in inputs.iter().enumerate() {
        if let Some(v) = vertex {
            numbers[v.idx()].get_or_insert(input as u32);
        }
    }
    let key = |v: usize| mesh.positions()[v].coords.map(f64::to_bits);
    let by_position: HashMap<_, u32> = numbers
        .iter()
        .enumerate()
        .filter_map(|(v, n)| Some((key(v), (*n)?)))
        .collect();
    numbers
        .iter()
        .enumerate()
        .map(|(v, n)| {
            n.or_else(|| by_position.get(&key(v)).copied())
                .unwrap_or(v as u32)
        })
        .collect()
}
