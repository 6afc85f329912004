//! The surface as shown: the mesh itself, or above a number of triangles a coarser
//! copy by vertex clustering (Rossignac and Borrel 1993): the vertices in each cell
//! of a grid are merged at their mean, and the triangles whose corners fall in
//! three different cells are kept. The grid's cell is grown until few enough
//! triangles are left.

use std::collections::HashMap;

use crate::mesh::Mesh;

/// The mesh as the viewer shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct DisplayMesh {
    /// The shown vertices.
    pub positions: Vec<[f32; 3]>,
    /// The shown triangles.
    pub triangles: Vec<[u32; 3]>,
    /// The shown vertex of each vertex of the mesh.
    pub cluster: Vec<u32>,
}

impl DisplayMesh {
    /// The mean over each shown vertex's vertices of the finite `value(v)` (NaN where
    /// none is finite).
    pub fn per_vertex(&self, value: impl Fn(usize) -> f64) -> Vec<f64> {
        let mut sums = vec![(0.0, 0usize); self.positions.len()];
        for (v, &c) in self.cluster.iter().enumerate() {
            let x = value(v);
            if x.is_finite() {
                let sum = &mut sums[c as usize];
                *sum = (sum.0 + x, sum.1 + 1);
            }
        }
        sums.into_iter()
            .map(|(sum, n)| if n > 0 { sum / n as f64 } else { f64::NAN })
            .collect()
    }
}

/// `mesh` as it is when it has at most `max_faces` triangles, else clustered on a
/// grid whose cell doubles until at most `max_faces` are left.
pub fn display_mesh(mesh: &Mesh, max_faces: usize) -> DisplayMesh {
    let triangles = mesh.triangles();
    let positions = mesh.positions();
    if triangles.len() <= max_faces {
        return DisplayMesh {
            positions: positions
                .iter()
                .map(|p| [p.x, p.y, p.z].map(|x| x as f32))
                .collect(),
            triangles,
            cluster: (0..positions.len() as u32).collect(),
        };
    }
    let mut cell = mesh.mean_edge_length().max(f64::MIN_POSITIVE);
    loop {
        let display = clustered(mesh, &triangles, cell);
        if display.triangles.len() <= max_faces {
            return display;
        }
        cell *= 2.0;
    }
}

/// The mesh with its vertices merged per cube of side `cell`.
fn clustered(mesh: &Mesh, triangles: &[[u32; 3]], cell: f64) -> DisplayMesh {
    let mut cells: HashMap<[i64; 3], u32> = HashMap::new();
    let mut sums: Vec<([f64; 3], usize)> = Vec::new();
    let cluster: Vec<u32> = mesh
        .positions()
        .iter()
        .map(|p| {
            let key = [p.x, p.y, p.z].map(|x| (x / cell).floor() as i64);
            let id = *cells.entry(key).or_insert_with(|| {
                sums.push(([0.0; 3], 0));
                (sums.len() - 1) as u32
            });
            let sum = &mut sums[id as usize];
            sum.0 = [sum.0[0] + p.x, sum.0[1] + p.y, sum.0[2] + p.z];
            sum.1 += 1;
            id
        })
        .collect();
    let positions = sums
        .iter()
        .map(|(sum, n)| sum.map(|s| (s / *n as f64) as f32))
        .collect();
    let triangles = triangles
        .iter()
        .map(|t| t.map(|v| cluster[v as usize]))
        .filter(|[a, b, c]| a != b && b != c && a != c)
        .collect();
    DisplayMesh {
        positions,
        triangles,
        cluster,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{sphere, Sampling};

    #[test]
    fn a_large_mesh_is_shown_coarser_and_a_small_one_as_it_is() {
        let mesh = sphere(1.0, 20_000, Sampling::Regular).unwrap().mesh;
        let whole = display_mesh(&mesh, mesh.face_count());
        assert_eq!(whole.triangles, mesh.triangles());
        let coarse = display_mesh(&mesh, mesh.face_count() / 5);
        assert!(coarse.triangles.len() <= mesh.face_count() / 5);
        assert!(coarse.triangles.len() > mesh.face_count() / 40);
        // The shown vertices stay near the sphere, and each vertex's value is its
        // cluster's mean.
        for p in &coarse.positions {
            let r = p.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>().sqrt();
            assert!((0.9..=1.0 + 1e-6).contains(&r), "{r}");
        }
        let heights = coarse.per_vertex(|v| mesh.positions()[v].z);
        for (p, h) in coarse.positions.iter().zip(&heights) {
            assert!((f64::from(p[2]) - h).abs() < 1e-6);
        }
    }
}
