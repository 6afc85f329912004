//! Trimming a crease surface to the strength: the part of each triangle where the
//! strength −λ3, interpolated linearly from its corners, is at least s (docs/design/crease.md,
//! "Crease surfaces": skip weak cells, then trim). Triangles are cut along the
//! iso-line −λ3 = s, each cut point computed once per edge and shared by the two
//! triangles of the edge, so the trimmed surface keeps its connectivity and ends in
//! a smooth border instead of the staircase of dropped cells.

use std::collections::HashMap;

use super::surface::Mesh;

/// The part of `mesh` where its per-vertex strength is at least `strength`; cut
/// points have the strength `strength` and are not degenerate points.
pub(super) fn trimmed(mut mesh: Mesh, strength: f64) -> Mesh {
    let mut cuts: HashMap<[u32; 2], u32> = HashMap::new();
    let mut kept = Vec::with_capacity(mesh.triangles.len());
    for triangle in std::mem::take(&mut mesh.triangles) {
        let inside = triangle.map(|v| mesh.strength[v as usize] >= strength);
        let count = inside.iter().filter(|&&i| i).count();
        match count {
            3 => kept.push(triangle),
            0 => {}
            _ => {
                // The corner alone on its side first, the order (and so the
                // orientation) kept.
                let lone = inside.iter().position(|&i| i == (count == 1)).unwrap_or(0);
                let [a, b, c] = [0, 1, 2].map(|k| triangle[(lone + k) % 3]);
                let ab = cut(&mut mesh, &mut cuts, [a, b], strength);
                let ac = cut(&mut mesh, &mut cuts, [a, c], strength);
                if count == 1 {
                    kept.push([a, ab, ac]);
                } else {
                    kept.extend([[ab, b, c], [ab, c, ac]]);
                }
            }
        }
    }
    mesh.triangles = kept;
    mesh
}

/// The vertex where the strength crosses `strength` on the edge `[a, b]`, added to
/// `mesh` on first use.
fn cut(mesh: &mut Mesh, cuts: &mut HashMap<[u32; 2], u32>, [a, b]: [u32; 2], strength: f64) -> u32 {
    let key = [a.min(b), a.max(b)];
    if let Some(&v) = cuts.get(&key) {
        return v;
    }
    let [p, q] = key.map(|v| v as usize);
    let (sp, sq) = (mesh.strength[p], mesh.strength[q]);
    let t = ((strength - sp) / (sq - sp)).clamp(0.0, 1.0);
    let t = if t.is_finite() { t } else { 0.5 };
    let position = mesh.positions[p] + (mesh.positions[q] - mesh.positions[p]) * t;
    let v = mesh.positions.len() as u32;
    mesh.positions.push(position);
    mesh.strength.push(strength);
    mesh.degenerate.push(0.0);
    cuts.insert(key, v);
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Point;

    /// A strip of two triangles over the unit square, strength rising with x from
    /// 0 to 2.
    fn strip() -> Mesh {
        Mesh {
            positions: vec![
                Point::new(0.0, 0.0, 0.0),
                Point::new(1.0, 0.0, 0.0),
                Point::new(1.0, 1.0, 0.0),
                Point::new(0.0, 1.0, 0.0),
            ],
            strength: vec![0.0, 2.0, 2.0, 0.0],
            degenerate: vec![0.0; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    fn area(mesh: &Mesh) -> f64 {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum()
    }

    #[test]
    fn the_square_is_cut_along_the_iso_line_and_cut_points_are_shared() {
        let trimmed = trimmed(strip(), 1.0);
        // Where x ≥ 1/2: half the square.
        assert!((area(&trimmed) - 0.5).abs() < 1e-12);
        // The diagonal's cut point serves both triangles: 4 + 3 cut points.
        assert_eq!(trimmed.positions.len(), 7);
        let cut_points = &trimmed.positions[4..];
        assert!(cut_points.iter().all(|p| (p.x - 0.5).abs() < 1e-12));
        assert!(trimmed.strength[4..].iter().all(|&s| s == 1.0));
        // Orientation kept: every normal still points along +z.
        for t in &trimmed.triangles {
            let [a, b, c] = t.map(|v| trimmed.positions[v as usize]);
            assert!((b - a).cross(&(c - a)).z > 0.0);
        }
    }

    #[test]
    fn all_in_or_all_out_is_kept_or_dropped_whole() {
        assert_eq!(trimmed(strip(), 0.0).triangles.len(), 2);
        assert!(trimmed(strip(), 3.0).triangles.is_empty());
    }
}
