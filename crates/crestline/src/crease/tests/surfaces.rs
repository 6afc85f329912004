//! Crease surfaces (Schultz, Theisel and Seidel 2010): the crossings of the ridge
//! condition with the grid edges on fields whose ridges are known.

use crate::crease::{edge_crossings, CreaseField, CrossingOptions};
use crate::volume::{Derivatives, Volume};
use crate::Point;
use nalgebra::Matrix3;

/// f = exp(−(|x − c| − R)² / s²) on an n³ grid of unit voxels centred on c: its
/// ridge surface is the sphere of radius R, and outside it λ2 = λ3 < 0 with
/// g·e3 ≡ 0, the degenerate case that makes spurious sheets.
fn shell(n: usize, radius: f64, width: f64) -> (Volume, Point) {
    let c = (n - 1) as f64 / 2.0;
    let centre = Point::new(c, c, c);
    let samples = (0..n * n * n)
        .map(|i| {
            let p = Point::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64);
            let d = (p - centre).norm() - radius;
            (-(d * d) / (width * width)).exp() as f32
        })
        .collect();
    let volume = Volume::new([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap();
    (volume, centre)
}

/// The ridge field of `volume`, reconstructed by the cubic B-spline.
fn ridge_field(volume: &Volume) -> CreaseField {
    let derivatives = Derivatives::cubic_spline(volume, 2).unwrap();
    CreaseField::new(volume, &derivatives, true).unwrap()
}

#[test]
fn spherical_shell_edge_crossings_lie_on_the_sphere_and_nowhere_else() {
    let (radius, width) = (11.0, 3.0);
    let (volume, centre) = shell(34, radius, width);
    let field = ridge_field(&volume);
    let crossings = edge_crossings(&field, &field.default_options());
    let on_ridge: Vec<_> = crossings.iter().filter(|c| c.lambda3 < 0.0).collect();
    let distances: Vec<f64> = on_ridge
        .iter()
        .map(|c| ((c.position - centre).norm() - radius).abs())
        .collect();
    let mean = distances.iter().sum::<f64>() / distances.len() as f64;
    let far = distances.iter().filter(|&&d| d > 1.0).count();
    eprintln!(
        "{} crossings ({} with λ3 < 0): mean distance {mean:.4} voxel, {far} more than 1 voxel off",
        crossings.len(),
        on_ridge.len()
    );
    assert!(mean < 0.05, "mean distance {mean} voxel");
    assert_eq!(far, 0, "{far} of {} crossings far off", on_ridge.len());
    // Every grid edge that clearly straddles the sphere is crossed: the sheet has no
    // holes. (Smoothing moves the ridge inward by about 0.03 voxel, so ends closer
    // than 0.1 voxel to the sphere are left out.)
    let straddling = straddling_edges(volume.dims(), centre, radius);
    let crossed: std::collections::HashSet<u64> = on_ridge.iter().map(|c| c.edge).collect();
    let missed = straddling.iter().filter(|e| !crossed.contains(e)).count();
    assert_eq!(
        missed,
        0,
        "{missed} of {} straddling edges missed",
        straddling.len()
    );
}

/// Keys `3 · point + axis` of the grid edges whose ends lie on both sides of the
/// sphere, each more than 0.1 voxel from it.
fn straddling_edges(dims: [usize; 3], centre: Point, radius: f64) -> Vec<u64> {
    let [nx, ny, nz] = dims;
    let mut edges = Vec::new();
    // +1 outside, −1 inside, 0 within 0.1 voxel of the sphere.
    let side = |i: usize, j: usize, k: usize| {
        let d = (Point::new(i as f64, j as f64, k as f64) - centre).norm() - radius;
        if d.abs() < 0.1 {
            0
        } else {
            d.signum() as i32
        }
    };
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let here = side(i, j, k);
                let point = (i + nx * (j + ny * k)) as u64;
                for (axis, [a, b, c]) in [[i + 1, j, k], [i, j + 1, k], [i, j, k + 1]]
                    .into_iter()
                    .enumerate()
                {
                    if a < nx && b < ny && c < nz && here * side(a, b, c) < 0 {
                        edges.push(3 * point + axis as u64);
                    }
                }
            }
        }
    }
    edges
}

#[test]
fn without_the_degenerate_rule_the_shell_would_grow_spurious_sheets() {
    // With ε = 0 (no degenerate ends), the tiny random h outside the shell is
    // crossed all over: the rule of docs/design/crease.md is what keeps the result clean.
    let (radius, width) = (11.0, 3.0);
    let (volume, centre) = shell(34, radius, width);
    let field = ridge_field(&volume);
    let far = |epsilon: f64| {
        let options = CrossingOptions {
            epsilon,
            ..field.default_options()
        };
        edge_crossings(&field, &options)
            .iter()
            .filter(|c| c.lambda3 < 0.0 && ((c.position - centre).norm() - radius).abs() > 1.0)
            .count()
    };
    let with_rule = far(field.default_options().epsilon);
    let without = far(0.0);
    eprintln!("crossings more than 1 voxel off: {with_rule} with the rule, {without} without");
    assert!(without > 10 * with_rule.max(1), "{without} vs {with_rule}");
}

#[test]
fn spherical_shell_ridge_surface_is_the_sphere() {
    use crate::crease::crease_surface;
    let (radius, width) = (11.0, 3.0);
    let (volume, centre) = shell(34, radius, width);
    let field = ridge_field(&volume);
    let soup = &crease_surface(&field, &field.default_options(), 0).unwrap();
    let distances: Vec<f64> = soup
        .positions
        .iter()
        .map(|p| ((p - centre).norm() - radius).abs())
        .collect();
    let mean = distances.iter().sum::<f64>() / distances.len() as f64;
    let far = distances.iter().filter(|&&d| d > 1.0).count();
    let area: f64 = soup
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| soup.positions[v as usize]);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .sum();
    let sphere = 4.0 * std::f64::consts::PI * radius * radius;
    // Every edge of the triangulation is shared by exactly two triangles: closed.
    let mut edges = std::collections::HashMap::new();
    for t in &soup.triangles {
        for k in 0..3 {
            let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    let open = edges.values().filter(|&&n| n != 2).count();
    eprintln!(
        "{} vertices, {} triangles: mean distance {mean:.4} voxel, {far} beyond 1 voxel, area / sphere {:.4}, {open} edges not shared by two triangles",
        soup.positions.len(),
        soup.triangles.len(),
        area / sphere
    );
    assert!(mean < 0.05, "mean distance {mean}");
    assert_eq!(far, 0);
    assert!(
        (area / sphere - 1.0).abs() < 0.05,
        "area ratio {}",
        area / sphere
    );
    assert_eq!(open, 0, "the sphere is closed");
    let euler = soup.positions.len() as i64 - edges.len() as i64 + soup.triangles.len() as i64;
    assert_eq!(euler, 2, "a sphere");
}

/// A ridge that ends: f = p·u − k(u² + w²)/2 + q(u³ + u w²)/2 − m v²/2 in units of
/// ten voxels, (u, v, w) the offsets from `centre` along x, y and z. Across y its
/// Hessian is −k I + q [[3u, w], [w, u]] in (u, w): λ2 = λ3 on the line u = w = 0
/// (along y), a degenerate line of wedge type (Schultz et al. 2010, §3.2, Fig. 1a),
/// and the ridge surface g·e3 = 0 is the half-plane w = 0, u > 0, which ends on it.
fn ending_ridge(n: usize, centre: [f64; 3]) -> Volume {
    let (p, k, q, m) = (1.0, 20.0, 6.0, 1.0);
    let samples = (0..n * n * n)
        .map(|i| {
            let at = [i % n, (i / n) % n, i / (n * n)];
            let [u, v, w] = std::array::from_fn(|a| (at[a] as f64 - centre[a]) / 10.0);
            (p * u - k * (u * u + w * w) / 2.0 + q * (u * u * u + u * w * w) / 2.0
                - m * v * v / 2.0) as f32
        })
        .collect();
    Volume::new([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
}

/// f = (exp(−d₁²/s²) + exp(−d₂²/s²)) · exp(−y²/L²) on an n³ grid of unit voxels,
/// d₁ and d₂ the distances to two planes through the grid's central y axis at
/// `angle` (radians) to each other: two ridge sheets that cross along that axis,
/// where some of their ridge surfaces end rather than meet (the paper's Fig. 6
/// configuration); the factor along y keeps λ2 and λ3 from being exactly tied by
/// symmetry.
fn crossing_sheets(n: usize, angle: f64, width: f64, length: f64) -> Volume {
    let c = (n - 1) as f64 / 2.0;
    let half = angle / 2.0;
    let normals = [
        nalgebra::Vector3::new(half.sin(), 0.0, half.cos()),
        nalgebra::Vector3::new(half.sin(), 0.0, -half.cos()),
    ];
    let samples = (0..n * n * n)
        .map(|i| {
            let p = nalgebra::Vector3::new(
                (i % n) as f64 - c,
                ((i / n) % n) as f64 - c,
                (i / (n * n)) as f64 - c,
            );
            let sheets: f64 = normals
                .iter()
                .map(|m| (-(p.dot(m).powi(2)) / (width * width)).exp())
                .sum();
            (sheets * (-(p.y / length).powi(2)).exp()) as f32
        })
        .collect();
    Volume::new([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
}

/// Edge and boundary figures of a triangle soup (paper Table 3).
struct Topology {
    /// Edges in one triangle.
    boundary_edges: usize,
    /// Connected components of the boundary edges.
    boundary_components: usize,
    /// Edges in more than two triangles.
    non_manifold_edges: usize,
    /// Vertices where more than two boundary edges meet.
    crowded_vertices: usize,
}

fn edge_counts(soup: &crate::mesh::TriangleSoup) -> std::collections::HashMap<(u32, u32), usize> {
    let mut edges = std::collections::HashMap::new();
    for t in &soup.triangles {
        for k in 0..3 {
            let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    edges
}

fn topology(soup: &crate::mesh::TriangleSoup) -> Topology {
    let edges = edge_counts(soup);
    let boundary: Vec<(u32, u32)> = edges
        .iter()
        .filter(|(_, &n)| n == 1)
        .map(|(&e, _)| e)
        .collect();
    let mut degree = vec![0usize; soup.positions.len()];
    let mut pieces = petgraph::unionfind::UnionFind::<u32>::new(soup.positions.len());
    for &(a, b) in &boundary {
        degree[a as usize] += 1;
        degree[b as usize] += 1;
        pieces.union(a, b);
    }
    let mut roots: Vec<u32> = boundary.iter().map(|&(a, _)| pieces.find(a)).collect();
    roots.sort_unstable();
    roots.dedup();
    Topology {
        boundary_edges: boundary.len(),
        boundary_components: roots.len(),
        non_manifold_edges: edges.values().filter(|&&n| n > 2).count(),
        crowded_vertices: degree.iter().filter(|&&d| d > 2).count(),
    }
}

#[test]
fn a_ridge_surface_that_ends_is_bounded_by_its_degenerate_line() {
    use crate::crease::{crease_surface, DEGENERATE};
    let (n, centre) = (32, [15.3, 15.5, 15.7]);
    let volume = ending_ridge(n, centre);
    let field = ridge_field(&volume);
    // The polynomial's reconstruction at the volume's border inflates the range of
    // eigenvalues, and with it the default ε; take 0.5% of the range inside.
    let options = CrossingOptions {
        epsilon: 0.002,
        ..field.default_options()
    };
    let soup = crease_surface(&field, &options, 0).unwrap();
    let figures = topology(&soup);
    let degenerate = &soup
        .vertex_scalars
        .iter()
        .find(|s| s.name == DEGENERATE)
        .expect("the degenerate mark")
        .values;
    let inside = |p: &crate::Point| p.iter().all(|&x| x > 2.0 && x < (n - 1) as f64 - 2.0);
    let marked: Vec<&crate::Point> = soup
        .positions
        .iter()
        .zip(degenerate)
        .filter(|(_, &d)| d == 1.0)
        .map(|(p, _)| p)
        .collect();
    let off_line = marked
        .iter()
        .map(|p| ((p.x - centre[0]).powi(2) + (p.z - centre[2]).powi(2)).sqrt())
        .fold(0.0, f64::max);
    // The boundary edges away from the volume's border.
    let inner: Vec<(u32, u32)> = edge_counts(&soup)
        .into_iter()
        .filter(|&((a, b), count)| {
            count == 1 && inside(&soup.positions[a as usize]) && inside(&soup.positions[b as usize])
        })
        .map(|(e, _)| e)
        .collect();
    let on_line = inner
        .iter()
        .filter(|&&(a, b)| degenerate[a as usize] == 1.0 && degenerate[b as usize] == 1.0)
        .count();
    eprintln!(
        "{} vertices ({} degenerate, at most {off_line:.2e} voxel off the line), {} triangles: {} boundary edges in {} components, {} non-manifold edges, {} vertices with more than two boundary edges; {} boundary edges inside, {on_line} of them between degenerate points",
        soup.positions.len(),
        marked.len(),
        soup.triangles.len(),
        figures.boundary_edges,
        figures.boundary_components,
        figures.non_manifold_edges,
        figures.crowded_vertices,
        inner.len(),
    );
    assert_eq!(figures.non_manifold_edges, 0);
    assert_eq!(figures.crowded_vertices, 0);
    // One degenerate point per y-layer of faces, on the line.
    assert_eq!(marked.len(), n);
    assert!(off_line < 0.01, "{off_line}");
    // Inside the volume the surface ends only on the degenerate line.
    assert!(!inner.is_empty());
    assert_eq!(on_line, inner.len());
}

/// The samples per axis of [`sheets_field`].
const SHEETS: usize = 40;

/// The ridge field of two sheets crossing at 60° on a grid of `SHEETS`³ samples,
/// reconstructed by the cubic B-spline.
fn sheets_field() -> CreaseField {
    let volume = crossing_sheets(SHEETS, 60f64.to_radians(), 2.5, 15.0);
    ridge_field(&volume)
}

#[test]
fn crossing_sheets_give_a_manifold_surface_with_simple_boundaries() {
    use crate::crease::crease_surface;
    let (n, field) = (SHEETS, sheets_field());
    let soup = crease_surface(&field, &field.default_options(), 0).unwrap();
    let figures = topology(&soup);
    eprintln!(
        "crossing sheets: {} vertices, {} triangles: {} boundary edges in {} components, {} non-manifold edges, {} vertices with more than two boundary edges",
        soup.positions.len(),
        soup.triangles.len(),
        figures.boundary_edges,
        figures.boundary_components,
        figures.non_manifold_edges,
        figures.crowded_vertices,
    );
    // Both sheets are found (each alone crosses about n² cells, with two
    // triangles in most), and where they meet no edge is shared by more than two
    // triangles and no boundary vertex is pinched (paper Table 3).
    assert!(
        soup.triangles.len() > 2 * (n - 8) * (n - 8),
        "{}",
        soup.triangles.len()
    );
    assert_eq!(figures.non_manifold_edges, 0);
    assert_eq!(figures.crowded_vertices, 0);
}

#[test]
fn the_surface_is_trimmed_along_the_strength_level() {
    use crate::crease::{crease_surface, STRENGTH};
    let (n, field) = (SHEETS, sheets_field());
    // Strong enough that the sheets' fading ends (along y) are cut off.
    let mut options = field.default_options();
    options.strength *= 4.0;
    let soup = crease_surface(&field, &options, 0).unwrap();
    let strength = &soup
        .vertex_scalars
        .iter()
        .find(|s| s.name == STRENGTH)
        .unwrap()
        .values;
    let weakest = strength.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        weakest >= options.strength * (1.0 - 1e-9),
        "a vertex at {weakest}"
    );
    // The border runs along −λ3 = s, through the points cut on the triangles'
    // edges, not along the cells dropped where the sheet gets weak.
    let mut degree = vec![0usize; soup.positions.len()];
    for (&(a, b), &count) in &edge_counts(&soup) {
        if count == 1 {
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
    }
    let inner = |v: usize| {
        let p = soup.positions[v];
        [p.x, p.y, p.z]
            .iter()
            .all(|&x| x > 2.0 && x < (n - 3) as f64)
    };
    let border: Vec<usize> = (0..soup.positions.len())
        .filter(|&v| degree[v] > 0 && inner(v))
        .collect();
    let on_level = border
        .iter()
        .filter(|&&v| (strength[v] - options.strength).abs() <= 1e-9 * options.strength)
        .count();
    let figures = topology(&soup);
    eprintln!(
        "trimmed sheets: {} triangles, {} border vertices inside the volume, {on_level} on the level; {} non-manifold edges, {} crowded vertices",
        soup.triangles.len(),
        border.len(),
        figures.non_manifold_edges,
        figures.crowded_vertices
    );
    assert!(border.len() > 50, "{} border vertices", border.len());
    assert!(on_level as f64 >= 0.8 * border.len() as f64);
    assert_eq!(figures.non_manifold_edges, 0);
    assert_eq!(figures.crowded_vertices, 0);
}

#[test]
fn the_marching_cubes_baseline_finds_the_sphere_of_the_shell() {
    use crate::crease::oriented_marching_cubes;
    let (radius, width) = (11.0, 3.0);
    let (volume, centre) = shell(34, radius, width);
    let field = ridge_field(&volume);
    let soup = oriented_marching_cubes(&field, &field.default_options());
    let signed: Vec<f64> = soup
        .positions
        .iter()
        .map(|p| (p - centre).norm() - radius)
        .collect();
    // The vertices on the sphere, and those of the spurious sheets off it: outside,
    // where λ2 = λ3 < 0 and the sign of g·e3 is noise (the crease surface rejects
    // these edges, docs/design/crease.md; the baseline cannot), and inside, in cells whose corner
    // 0 lies where λ2 ≈ λ3 and orients the e3 of the others at random.
    let near: Vec<f64> = signed
        .iter()
        .map(|d| d.abs())
        .filter(|&d| d < 0.1)
        .collect();
    let far = signed.iter().filter(|&&d| d.abs() >= 0.5).count();
    let between = signed.len() - near.len() - far;
    let mean = near.iter().sum::<f64>() / near.len() as f64;
    let straddling = straddling_edges(volume.dims(), centre, radius).len();
    let edges = edge_counts(&soup);
    let near_vertex = |v: u32| signed[v as usize].abs() < 0.1;
    let open_on_sphere = edges
        .iter()
        .filter(|&(&(a, b), &n)| n == 1 && near_vertex(a) && near_vertex(b))
        .count();
    eprintln!(
        "{} vertices: {} within 0.1 voxel of the sphere (mean {mean:.4}), {far} at least 0.5 voxel off, {between} in between; {straddling} edges straddle the sphere; {} boundary edges, {open_on_sphere} of them on the sphere",
        signed.len(),
        near.len(),
        edges.values().filter(|&&n| n == 1).count(),
    );
    // Linear interpolation of g·e3 along the edges finds the sphere to a few
    // hundredths of a voxel (the smoothing moves it inward by about 0.03 voxel);
    // interpolating from the wrong end would spread the vertices over half a voxel.
    assert_eq!(between, 0, "{between} vertices 0.1 to 0.5 voxel off");
    assert!(mean < 0.05, "mean distance {mean}");
    // The sphere is found all around: at least as many vertices on it as grid edges
    // clearly straddle it.
    assert!(near.len() >= straddling, "{} of {straddling}", near.len());
    // Its cracks are all in the spurious sheets: on the sphere, e3 is radial at every
    // corner of the cells it crosses, and their orientations agree.
    assert_eq!(open_on_sphere, 0);
}

/// f = exp(−((x − c)·n)² / s²) on an n³ grid of unit voxels: a ridge sheet, the plane
/// through `c` normal to `normal`, tilted against the grid. Within s/√2 of it
/// λ1 = λ2 = 0 > λ3 and e3 = ±n: with s wide enough to cover the volume, e3 can be
/// oriented consistently everywhere.
fn tilted_sheet(n: usize, c: Point, normal: nalgebra::Vector3<f64>, width: f64) -> Volume {
    let samples = (0..n * n * n)
        .map(|i| {
            let p = Point::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64);
            let d = (p - c).dot(&normal);
            (-(d * d) / (width * width)).exp() as f32
        })
        .collect();
    Volume::new([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
}

#[test]
fn the_marching_cubes_baseline_of_a_planar_ridge_has_no_cracks() {
    use crate::crease::oriented_marching_cubes;
    let n = 24;
    let c = Point::new(11.3, 11.6, 11.45);
    let normal = nalgebra::Vector3::new(0.25, -0.2, 1.0).normalize();
    let volume = tilted_sheet(n, c, normal, 30.0);
    let field = ridge_field(&volume);
    let soup = oriented_marching_cubes(&field, &field.default_options());
    let off = soup
        .positions
        .iter()
        .map(|p| (p - c).dot(&normal).abs())
        .fold(0.0, f64::max);
    let last = (n - 1) as f64;
    let on_border = |v: u32| {
        let p = soup.positions[v as usize];
        [p.x, p.y].iter().any(|&x| x < 1e-9 || x > last - 1e-9)
    };
    let edges = edge_counts(&soup);
    let inner_open = edges
        .iter()
        .filter(|&(&(a, b), &count)| count == 1 && !(on_border(a) && on_border(b)))
        .count();
    let flipped = (0..n * n * n)
        .filter(|&i| {
            field
                .sample([i % n, (i / n) % n, i / (n * n)])
                .frame
                .e3
                .dot(&normal)
                < 0.0
        })
        .count();
    let figures = topology(&soup);
    eprintln!(
        "planar ridge: e3·n < 0 at {flipped} of {} samples; {} vertices, {} triangles, at most {off:.4} voxel off the plane; {} boundary edges in {} components, {inner_open} inside the volume, {} non-manifold edges",
        n * n * n,
        soup.positions.len(),
        soup.triangles.len(),
        figures.boundary_edges,
        figures.boundary_components,
        figures.non_manifold_edges,
    );
    // The eigenvectors come with either sign: the orientation per cell matters.
    assert!(flipped > 0 && flipped < n * n * n, "{flipped}");
    // The sheet crosses the whole volume: about (n − 1)² cells, most of them with a
    // polygon fanned into 4 to 6 triangles.
    assert!(soup.triangles.len() >= 3 * (n - 1) * (n - 1));
    assert!(off < 0.1, "{off}");
    // Every edge inside the volume is shared by exactly two triangles; the one
    // boundary runs around the volume's border.
    assert_eq!(figures.non_manifold_edges, 0);
    assert_eq!(inner_open, 0);
    assert_eq!(figures.boundary_components, 1);
    assert_eq!(figures.crowded_vertices, 0);
}

/// Warnings told to an observer.
#[derive(Default)]
struct Warnings(Vec<String>);

impl crate::progress::Observer for Warnings {
    fn warning(&mut self, message: &str) {
        self.0.push(message.to_string());
    }
}

#[test]
fn a_minimum_piece_size_that_empties_the_surface_is_named() {
    use crate::crease::{crease_surface, crease_surface_observed};
    let field = sheets_field();
    let options = field.default_options();
    let all = crease_surface(&field, &options, 0).unwrap().triangles.len();
    assert!(all > 100, "{all}");
    // Above every triangle there is: no value of the surface could pass.
    let err = crease_surface(&field, &options, usize::MAX).unwrap_err();
    let message = err.to_string();
    assert!(message.contains("`min_component`"), "{message}");
    assert!(
        message.contains(&format!("the {all} triangles")),
        "{message}"
    );
    // Above the largest piece but not above all: an empty surface and a warning
    // naming the option and the largest piece, not `strength`.
    let mut warnings = Warnings::default();
    let soup = crease_surface_observed(&field, &options, all, &mut warnings);
    // The sheets' surface has small pieces besides the large one.
    assert!(soup.unwrap().triangles.is_empty());
    assert_eq!(warnings.0.len(), 1, "{:?}", warnings.0);
    let warning = &warnings.0[0];
    assert!(warning.contains("try a lower `min_component`"), "{warning}");
    assert!(!warning.contains("`strength`"), "{warning}");
}

#[test]
fn a_field_kept_where_creases_are_strong_gives_the_same_surface_in_less_memory() {
    use crate::crease::{crease_surface, default_options, Survey};
    use crate::volume::Smoothing;
    let volume = crossing_sheets(SHEETS, 60f64.to_radians(), 2.5, 15.0);
    let whole = ridge_field(&volume);
    let survey = Survey::new(&volume, Smoothing::CubicSpline, true).unwrap();
    let options = default_options(survey.eigenvalue_range());
    assert_eq!(options, whole.default_options());
    // Twice the default strength: fewer samples are strong, the surface is smaller.
    let strong = CrossingOptions {
        strength: 2.0 * options.strength,
        ..options
    };
    let kept = survey.field(&volume, strong.strength).unwrap();
    assert!(
        kept.kept_len() < whole.kept_len() / 2,
        "{} of {}",
        kept.kept_len(),
        whole.kept_len()
    );
    assert_eq!(whole.kept_len(), volume.len());
    let expected = crease_surface(&whole, &strong, 0).unwrap();
    let got = crease_surface(&kept, &strong, 0).unwrap();
    assert!(!expected.triangles.is_empty());
    assert_eq!(got.positions, expected.positions);
    assert_eq!(got.triangles, expected.triangles);
    // Asked for weaker creases than it keeps, the field refuses.
    assert!(crease_surface(&kept, &options, 0).is_err());
}
