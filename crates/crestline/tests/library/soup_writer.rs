//! Writing triangle soups that no half-edge mesh can hold: a Möbius strip, with a
//! vertex scalar, saved as PLY, OBJ and VTK and read back unchanged.

use crestline::io::{read_mesh, write_soup};
use crestline::mesh::{ScalarProperty, TriangleSoup};
use crestline::Point;

/// A Möbius strip of `n` quads (2n triangles) with the parameter u as a scalar.
fn mobius(n: u32) -> TriangleSoup {
    let mut positions = Vec::new();
    let mut u_values = Vec::new();
    for i in 0..n {
        let u = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        for s in [-0.3, 0.3] {
            let r = 1.0 + s * (u / 2.0).cos();
            positions.push(Point::new(r * u.cos(), r * u.sin(), s * (u / 2.0).sin()));
            u_values.push(u);
        }
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        let (a, b) = (2 * i, 2 * i + 1);
        // The last quad joins the first with its sides swapped: the twist.
        let (c, d) = if i + 1 == n {
            (1, 0)
        } else {
            (2 * i + 2, 2 * i + 3)
        };
        triangles.push([a, c, b]);
        triangles.push([b, c, d]);
    }
    TriangleSoup {
        positions,
        triangles,
        vertex_scalars: vec![ScalarProperty {
            name: "u".into(),
            values: u_values,
        }],
        space: None,
        volume_geometry: None,
    }
}

#[test]
fn a_non_orientable_soup_is_written_as_it_is() {
    let soup = mobius(24);
    let dir = tempfile::tempdir().unwrap();
    for extension in ["ply", "obj"] {
        let path = dir.path().join(format!("strip.{extension}"));
        write_soup(&path, &soup).unwrap();
        let back = read_mesh(&path).unwrap();
        assert_eq!(back.positions, soup.positions, "{extension}");
        assert_eq!(back.triangles, soup.triangles, "{extension}");
        if extension == "ply" {
            let u = &back.vertex_scalars[0];
            assert_eq!(u.name, "u");
            let close = u.values.iter().zip(&soup.vertex_scalars[0].values);
            assert!(close.into_iter().all(|(a, b)| (a - b).abs() < 1e-6));
        }
    }
    let path = dir.path().join("strip.vtk");
    write_soup(&path, &soup).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("POINTS 48 double\n"));
    assert!(text.contains("POLYGONS 48 192\n"));
    assert!(text.contains("POINT_DATA 48\nSCALARS u double 1\n"));
    assert_eq!(text.lines().filter(|l| l.starts_with("3 ")).count(), 48);
}

#[test]
fn a_bad_soup_is_refused_naming_the_file_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let mut out_of_range = mobius(8);
    out_of_range.triangles[3][1] = 99;
    let mut nan = mobius(8);
    nan.positions[2].y = f64::NAN;
    let mut short = mobius(8);
    short.vertex_scalars[0].values.pop();
    let cases = [
        (out_of_range, "strip.ply", "triangle 3"),
        (nan, "strip.obj", "vertex 2"),
        (short, "strip.vtk", "15 values for 16 vertices"),
        (mobius(8), "strip.stl", "supported extensions"),
    ];
    for (soup, name, words) in cases {
        let path = dir.path().join(name);
        let err = write_soup(&path, &soup).unwrap_err().to_string();
        assert!(err.contains(name) && err.contains(words), "{err}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
