//! What a mesh or an image holds (`crestline info`).

use super::scale::mesh_scale;
use crate::mesh::geometry::BoundingBox;
use crate::mesh::{ComponentInfo, Mesh};
use crate::progress::{stage, Observer};
use crate::volume::{ValueSummary, Volume};

/// The size, topology and geometry of a mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshInfo {
    /// Vertices, faces and edges.
    pub counts: [usize; 3],
    /// Closed boundary curves, over every component.
    pub boundary_loops: usize,
    /// χ = V − E + F of the whole mesh.
    pub euler_characteristic: i64,
    /// Each connected component's counts and genus.
    pub components: Vec<ComponentInfo>,
    /// The axis-aligned bounding box.
    pub bounding_box: BoundingBox,
    /// The mean edge length, each edge counted once: the unit of the mesh jobs'
    /// relative lengths.
    pub mean_edge_length: f64,
    /// The default feature scale (`super::scale::mesh_scale`).
    pub feature_scale: f64,
}

/// What `mesh` holds: the stage `topology`, and the counts `vertices`, `faces`,
/// `edges`, `boundary_loops` and `components`.
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// # let surface = Surface::of_mesh(mesh);
/// let info = jobs::mesh_info(&surface.mesh, &mut Silent);
/// assert_eq!(info.counts[0], surface.mesh.vertex_count());
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn mesh_info(mesh: &Mesh, observer: &mut dyn Observer) -> MeshInfo {
    let components = stage(observer, "topology", || mesh.components());
    let info = MeshInfo {
        counts: [mesh.vertex_count(), mesh.face_count(), mesh.edge_count()],
        boundary_loops: components.iter().map(|c| c.boundary_loops).sum(),
        euler_characteristic: mesh.euler_characteristic(),
        components,
        bounding_box: mesh.bounding_box(),
        mean_edge_length: mesh.mean_edge_length(),
        feature_scale: mesh_scale(mesh),
    };
    observer.measure("scale", info.feature_scale);
    for (key, value) in ["vertices", "faces", "edges"].into_iter().zip(info.counts) {
        observer.count(key, value);
    }
    observer.count("boundary_loops", info.boundary_loops);
    observer.count("components", info.components.len());
    info
}

/// The value statistics of `volume` (range, percentiles, histogram, Otsu's level:
/// a first isosurface level to try): the stage `statistics`.
///
/// # Examples
///
/// ```
/// # use crestline::progress::Silent;
/// # use crestline::jobs;
/// // A small image of an ellipsoid: values fall off from 100 at its centre.
/// let n = 24;
/// let samples = (0..n * n * n)
///     .map(|i| {
///         let [x, y, z] = [i % n, i / n % n, i / (n * n)].map(|c| c as f32 - 11.5);
///         100.0 - 10.0 * (x * x + 2.0 * y * y + 3.0 * z * z).sqrt()
///     })
///     .collect();
/// let identity = nalgebra::Matrix3::identity();
/// let volume = crestline::volume::Volume::new([n; 3], [1.0; 3], [0.0; 3], identity, samples)?;
/// let summary = jobs::image_info(&volume, &mut Silent);
/// assert!(summary.max <= 100.0);
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn image_info(volume: &Volume, observer: &mut dyn Observer) -> ValueSummary {
    stage(observer, "statistics", || ValueSummary::of(volume))
}
