//! A mesh built from its triangles for the jobs, its repairs told as warnings.

use crate::mesh::{Mesh, RepairReport, TriangleSoup};
use crate::progress::{try_stage, Observer};
use crate::Result;

/// The half-edge mesh of `soup`, read from a file, repaired as [`Mesh::from_soup`]
/// does (or, if `strict`, refusing a component that cannot be oriented
/// consistently, as [`Mesh::from_soup_strict`]) and renumbered if its vertex
/// order is scattered ([`Mesh::from_file_soup`]): the stage `build`, and each
/// repair as a warning.
///
/// # Examples
///
/// ```
/// use crestline::progress::Silent;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// let soup = crestline::io::read_mesh(path.as_ref())?;
/// let (mesh, repairs) = crestline::jobs::build_mesh(soup, false, &mut Silent)?;
/// assert!(mesh.face_count() > 0);
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn build_mesh(
    soup: TriangleSoup,
    strict: bool,
    observer: &mut dyn Observer,
) -> Result<(Mesh, RepairReport)> {
    let (mesh, repairs) = try_stage(observer, "build", || Mesh::from_file_soup(soup, strict))?;
    for message in repairs.messages() {
        observer.warning(&message);
    }
    Ok((mesh, repairs))
}
