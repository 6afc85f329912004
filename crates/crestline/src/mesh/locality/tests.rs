use std::collections::HashSet;

use super::{is_scattered, Mesh, NEAR};
use crate::mesh::{ScalarProperty, TriangleSoup};
use crate::Point;

/// A bumpy `n × n` grid of vertices, two triangles per cell, in row order, with
/// the vertex's row-order index as the scalar `index`.
fn grid(n: usize) -> TriangleSoup {
    let positions = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f64, (i / n) as f64);
            Point::new(x, y, (0.3 * x).sin() * (0.2 * y).cos())
        })
        .collect();
    let mut triangles = Vec::new();
    for y in 0..n - 1 {
        for x in 0..n - 1 {
            let v = (y * n + x) as u32;
            let (right, up) = (v + 1, v + n as u32);
            triangles.push([v, right, up + 1]);
            triangles.push([v, up + 1, up]);
        }
    }
    TriangleSoup {
        positions,
        triangles,
        vertex_scalars: vec![ScalarProperty {
            name: "index".into(),
            values: (0..n * n).map(|i| i as f64).collect(),
        }],
        ..TriangleSoup::default()
    }
}

/// `soup` with its vertices listed in a scattered order: vertex i moves to
/// (i · stride) mod n, stride coprime to n; its scalars move with it.
fn scattered(mut soup: TriangleSoup, stride: usize) -> TriangleSoup {
    let n = soup.positions.len();
    let to = |i: usize| (i * stride) % n;
    fn moved<T: Copy>(values: &[T], to: impl Fn(usize) -> usize) -> Vec<T> {
        let mut out = values.to_vec();
        for (i, &x) in values.iter().enumerate() {
            out[to(i)] = x;
        }
        out
    }
    soup.positions = moved(&soup.positions, to);
    for property in &mut soup.vertex_scalars {
        property.values = moved(&property.values, to);
    }
    for t in &mut soup.triangles {
        *t = t.map(|v| to(v as usize) as u32);
    }
    soup
}

/// The faces as their corners' positions (bits) in cyclic order, rotated to start
/// at the least: the same set for the same oriented faces in any numbering.
fn oriented_faces(positions: &[Point], triangles: &[[u32; 3]]) -> HashSet<[[u64; 3]; 3]> {
    triangles
        .iter()
        .map(|t| {
            let corners = t.map(|v| {
                let p = positions[v as usize];
                [p.x, p.y, p.z].map(f64::to_bits)
            });
            let start = (0..3).min_by_key(|&k| corners[k]).unwrap_or(0);
            [0, 1, 2].map(|k| corners[(start + k) % 3])
        })
        .collect()
}

#[test]
fn a_scattered_soup_is_renumbered_and_its_inputs_still_name_the_files_vertices() {
    // 401² = 160,801 vertices; neighbours in a row end up 80,400 entries apart.
    let soup = scattered(grid(401), 80_400);
    assert!(is_scattered(&soup));
    let (mesh, report) = Mesh::from_file_soup(soup.clone(), false).unwrap();
    assert!(report.is_clean(), "{report}");
    let built = mesh.to_soup();
    assert!(!is_scattered(&built), "the mesh's order is still scattered");
    let far = built
        .triangles
        .iter()
        .filter(|t| t.iter().max().unwrap() - t.iter().min().unwrap() > NEAR)
        .count();
    assert!(far * 100 < built.triangles.len(), "{far} faces span far");
    assert_ne!(built.positions, soup.positions, "nothing was renumbered");
    // Every input vertex names the mesh vertex at its position, with its scalar.
    let index = mesh.vertex_scalar("index").unwrap();
    for (i, v) in mesh.input_vertices().iter().enumerate() {
        let v = v.expect("no vertex is dropped");
        assert_eq!(mesh.position(v), soup.positions[i], "vertex {i}");
        assert_eq!(
            index[v.idx()],
            soup.vertex_scalars[0].values[i],
            "vertex {i}"
        );
    }
    assert_eq!(
        mesh.to_input_order(index, f64::NAN),
        soup.vertex_scalars[0].values
    );
    // The same faces, each with its orientation.
    let faces = oriented_faces(&built.positions, &built.triangles);
    let expected = oriented_faces(&soup.positions, &soup.triangles);
    assert_eq!(faces.len(), soup.triangles.len());
    assert!(
        faces == expected,
        "{} faces differ",
        faces.difference(&expected).count()
    );
}

#[test]
fn a_soup_in_a_local_order_keeps_its_numbers() {
    let soup = grid(401);
    assert!(!is_scattered(&soup));
    let (mesh, _) = Mesh::from_file_soup(soup.clone(), false).unwrap();
    assert_eq!(mesh.positions(), &soup.positions[..]);
    assert_eq!(mesh.triangles(), soup.triangles);
    assert!(mesh
        .input_vertices()
        .iter()
        .enumerate()
        .all(|(i, v)| v.map(|v| v.idx()) == Some(i)));
}

#[test]
fn repairs_of_a_renumbered_soup_compose_with_the_new_numbers() {
    // A duplicate of vertex 7 (welded into it) and an unreferenced vertex.
    let mut soup = scattered(grid(401), 80_400);
    let n = soup.positions.len() as u32;
    soup.positions.push(soup.positions[7]);
    soup.positions.push(Point::new(1e3, 1e3, 1e3));
    soup.vertex_scalars[0].values.extend([-1.0, -2.0]);
    let face = soup.triangles.iter().position(|t| t.contains(&7)).unwrap();
    for v in &mut soup.triangles[face] {
        if *v == 7 {
            *v = n;
        }
    }
    let (mesh, report) = Mesh::from_file_soup(soup.clone(), false).unwrap();
    assert_eq!(report.welded_vertices, 1);
    assert_eq!(report.unreferenced_vertices, 1);
    let inputs = mesh.input_vertices();
    assert_eq!(inputs[n as usize], inputs[7]);
    assert_eq!(inputs[n as usize + 1], None);
    assert_eq!(mesh.position(inputs[7].unwrap()), soup.positions[7]);
    assert_eq!(mesh.vertex_count(), n as usize);
}

#[test]
fn strict_building_refuses_an_unorientable_soup_in_either_order() {
    // A Möbius strip of 70,000 columns of two vertices (2x at the top, 2x + 1 at
    // the bottom): its last quad joins the top of the last column to the bottom
    // of the first.
    let w = 70_000u32;
    let positions: Vec<Point> = (0..2 * w)
        .map(|i| {
            let u = f64::from(i / 2) / f64::from(w) * std::f64::consts::TAU;
            let s = f64::from(i % 2) - 0.5;
            let r = 1.0 + 0.3 * s * (u / 2.0).cos();
            Point::new(r * u.cos(), r * u.sin(), 0.3 * s * (u / 2.0).sin())
        })
        .collect();
    let mut triangles = Vec::new();
    for x in 0..w {
        let (a, c) = (2 * x, 2 * x + 1);
        let (b, d) = if x + 1 < w { (a + 2, a + 3) } else { (1, 0) };
        triangles.push([a, b, d]);
        triangles.push([a, d, c]);
    }
    let strip = TriangleSoup {
        positions,
        triangles,
        ..TriangleSoup::default()
    };
    let shuffled = scattered(strip.clone(), 70_001);
    assert!(!is_scattered(&strip) && is_scattered(&shuffled));
    for soup in [strip, shuffled] {
        let error = Mesh::from_file_soup(soup.clone(), true).unwrap_err();
        assert!(error.to_string().contains("orient"), "{error}");
        let (_, report) = Mesh::from_file_soup(soup, false).unwrap();
        assert!(!report.is_clean());
    }
}
