//! The curvature of the isosurfaces at the grid points where the Marching Lines
//! read it, computed slab by slab so that memory grows with the isosurface, not
//! with the image.
//!
//! A crest line can only pass through a cell the isosurface `f = I` meets, and
//! [`Extremality`](super::Extremality) reads the curvature at that cell's corners
//! only. So the derivatives of order 0 to 3 are taken over blocks of a few z slices
//! ([`Derivatives::at_voxels`]; blocks the isosurface misses are skipped), the
//! curvature of the isosurface through each such corner is computed from them
//! (Thirion & Gourdon 1993 §5; [`crate::differential::isosurface_curvature`]) and
//! the block is dropped. The frames live in one array numbered by a [`VoxelSet`]
//! of the corners: a few words per corner, against twenty derivative volumes for
//! the whole image.
//!
//! The frames are computed in the frame of the grid's index axes
//! ([`Derivatives::axis_jet`]), not in world coordinates: curvatures and
//! extremalities do not change under the rotation between the two, and every
//! decision of the Marching Lines (the sign of an extremality, a segment kept)
//! then depends on the samples and the spacing alone. A DICOM series (LPS) and its
//! NIfTI conversion (RAS), or an image and the same image declared rotated, give
//! the same lines, not lines that differ wherever rounding in the two world
//! frames falls on either side of a tie.

use rayon::prelude::*;

use crate::differential::IsoCurvature;
use crate::volume::grid::Grid;
use crate::volume::voxel_set::{VoxelSet, VoxelSetBuilder};
use crate::volume::{Derivatives, Partial, Volume};
use crate::{Result, Vector};

/// Curvature of the isosurface through one grid point, stored compactly.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    /// `k_max`, `k_min`.
    pub k: [f32; 2],
    /// `e_max`, `e_min`.
    pub e: [f32; 2],
    /// `t_max`, `t_min`, in the frame of the grid's axes.
    t: [[f32; 3]; 2],
}

impl Frame {
    /// The frame of `c`, or `None` unless its curvatures and extremalities are
    /// finite.
    fn new(c: &IsoCurvature) -> Option<Frame> {
        let p = &c.principal;
        let direction = |d: &Vector| [d.x as f32, d.y as f32, d.z as f32];
        let frame = Frame {
            k: [p.k_max as f32, p.k_min as f32],
            e: [c.e_max as f32, c.e_min as f32],
            t: [direction(&p.d_max), direction(&p.d_min)],
        };
        let finite = frame.k.iter().chain(&frame.e).all(|v| v.is_finite());
        finite.then_some(frame)
    }

    /// Direction `which` (0: `t_max`, 1: `t_min`), in the frame of the grid's axes.
    pub fn direction(&self, which: usize) -> Vector {
        Vector::from(self.t[which].map(f64::from))
    }
}

/// The curvature of the isosurface through each corner of the cells the
/// isosurface `f = I` meets, `None` where undefined (a vanishing gradient).
pub(super) struct Curvatures {
    pub grid: Grid,
    /// The corners that have a frame, numbering `frames`.
    corners: VoxelSet,
    frames: Vec<Option<Frame>>,
    /// `∂index/∂axis`, from lengths along the grid's axes in world units to
    /// indices: turns gradients along index axes into the frames' gradients.
    pub axis_to_grid: nalgebra::Matrix3<f64>,
}

impl Curvatures {
    /// The frames of `volume` smoothed by a Gaussian of standard deviation `sigma`
    /// (world units) at the corners of the cells where `smoothed` (the same
    /// smoothing's values) reaches `level`: every cell whose corner values have
    /// `min ≤ level ≤ max`. These hold every cell the isosurface crosses and every
    /// cell that holds one of its points, even one on a face, edge or corner of the
    /// cell.
    ///
    /// Errors as [`Derivatives::at_voxels`].
    pub fn at_isosurface(
        volume: &Volume,
        smoothed: &Volume,
        sigma: f64,
        level: f64,
    ) -> Result<Curvatures> {
        let corners = isosurface_corners(smoothed, level);
        let frames = Derivatives::at_voxels(volume, sigma, &Partial::ALL, &corners, |d, index| {
            Frame::new(&d.axis_jet(index)?.isosurface_curvature()?)
        })?;
        Ok(Curvatures {
            grid: volume.grid(),
            corners,
            frames,
            axis_to_grid: nalgebra::Matrix3::from_diagonal(&Vector::from(
                volume.spacing().map(|s| 1.0 / s),
            )),
        })
    }

    /// The frame at the grid point of linear index `at`, `None` where undefined or
    /// away from the isosurface.
    fn frame(&self, at: usize) -> Option<Frame> {
        self.frames[self.corners.number(at)?]
    }

    /// The frames at the 8 corners of `cell`, or `None` if one is undefined.
    pub fn corners(&self, cell: [usize; 3]) -> Option<[Frame; 8]> {
        let frames = self.grid.corners(cell).map(|at| self.frame(at));
        frames
            .iter()
            .all(Option::is_some)
            .then(|| frames.map(Option::unwrap))
    }
}

/// The corners of the cells of `smoothed` whose corner values have
/// `min ≤ level ≤ max`.
fn isosurface_corners(smoothed: &Volume, level: f64) -> VoxelSet {
    let grid = smoothed.grid();
    let samples = smoothed.samples();
    let reaches = |cell: &[usize; 3]| {
        let values = grid.corners(*cell).map(|at| f64::from(samples[at]));
        let low = values.iter().copied().fold(f64::INFINITY, f64::min);
        let high = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        low <= level && level <= high
    };
    let cells: Vec<Vec<usize>> = (0..grid.dims[2].saturating_sub(1))
        .into_par_iter()
        .map(|k| {
            let layer = grid.cells(k..k + 1).filter(reaches);
            layer.map(|cell| grid.index(cell)).collect()
        })
        .collect();
    let mut corners = VoxelSetBuilder::new(grid.sample_count());
    for cell in cells.iter().flatten() {
        for step in grid.corner_steps() {
            corners.insert(cell + step);
        }
    }
    corners.build()
}
