//! Signed distance fields baked from a triangle mesh onto a regular grid:
//! each grid node holds the mesh collider's signed distance (the magnitude
//! from the hierarchy's closest point, the sign from the pseudonormals of a
//! closed mesh or the winding number of an open one).
//! A query interpolates the eight nodes of its cell trilinearly, and the
//! normal is the analytic gradient of that interpolant, normalised.
//!
//! The grid covers the mesh's box padded by [`PADDING_CELLS`] cells. A query
//! outside the grid's box is clamped to it: its distance is the distance to
//! the box plus the interpolated value at the clamped point (an upper bound
//! of the true distance, up to interpolation error, and the relative error
//! shrinks far away), and its normal is the gradient of that sum. Baking costs one mesh query per node, spread over threads.

use super::mesh_collider::MeshCollider;
use crate::math::Aabb;
use glam::Vec3;
use rayon::prelude::*;
use std::fmt;
use std::sync::Arc;

/// Empty cells around the mesh's box on every side.
pub const PADDING_CELLS: f32 = 2.0;
/// Most grid nodes a field may have (64 MiB of distances).
pub const MAX_NODES: usize = 1 << 24;

/// Why a distance field cannot be baked.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SdfError {
    /// The cell size is zero, negative or not a number.
    #[error("must be a positive number, got {cell_size}")]
    CellSize {
        /// The cell size asked for.
        cell_size: f32,
    },
    /// The mesh has no triangles to measure the distance to.
    #[error("the mesh has no triangles")]
    EmptyMesh,
    /// The cell size is so small for the mesh that the grid would pass
    /// [`MAX_NODES`].
    #[error(
        "a cell size of {cell_size} needs a grid of {} x {} x {} nodes, more than {max}; use a larger cell size",
        .dims[0], .dims[1], .dims[2], max = MAX_NODES
    )]
    TooManyNodes {
        /// The cell size asked for.
        cell_size: f32,
        /// Nodes the grid would have along x, y and z.
        dims: [usize; 3],
    },
}

/// Distances on the nodes of a regular grid.
#[derive(Clone, PartialEq)]
pub struct SdfGrid {
    /// Position of node `(0, 0, 0)`.
    origin: Vec3,
    cell_size: f32,
    /// Nodes along x, y and z (at least two each).
    dims: [usize; 3],
    /// Node `(i, j, k)` at `i + dims[0] * (j + dims[1] * k)`.
    values: Vec<f32>,
    /// The triangles of the mesh the field was baked from, kept for drawing.
    surface: Arc<[[Vec3; 3]]>,
}

impl fmt::Debug for SdfGrid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SdfGrid")
            .field("origin", &self.origin)
            .field("cell_size", &self.cell_size)
            .field("dims", &self.dims)
            .finish()
    }
}

impl SdfGrid {
    /// Samples `mesh`'s signed distance on a grid of `cell_size` around it.
    /// Refuses a cell size that is not positive, or so small that the grid
    /// would pass [`MAX_NODES`].
    pub fn bake(mesh: &MeshCollider, cell_size: f32) -> Result<Self, SdfError> {
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(SdfError::CellSize { cell_size });
        }
        let Aabb { min, max } = mesh.bounds();
        if !min.cmple(max).all() {
            return Err(SdfError::EmptyMesh);
        }
        let padding = Vec3::splat(PADDING_CELLS * cell_size);
        let cells = ((max - min + 2.0 * padding) / cell_size).ceil();
        let dims = (cells + Vec3::ONE).to_array().map(|n| n as usize);
        let count = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
        match count {
            Some(n) if n <= MAX_NODES => {}
            _ => return Err(SdfError::TooManyNodes { cell_size, dims }),
        }
        let mut grid = SdfGrid {
            origin: min - padding,
            cell_size,
            dims,
            values: Vec::new(),
            surface: mesh.triangles().collect(),
        };
        grid.values = (0..dims.iter().product())
            .into_par_iter()
            .map(|i| mesh.signed_distance(grid.node_position(i)).0)
            .collect();
        Ok(grid)
    }

    /// Position of node `(0, 0, 0)`.
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// Distances at the nodes, node `(i, j, k)` at `i + dims[0] * (j + dims[1] * k)`.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The triangles of the mesh the field was baked from (to draw it).
    pub fn surface(&self) -> &[[Vec3; 3]] {
        &self.surface
    }

    /// Edge length of the grid's cells (m).
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Nodes along x, y and z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    fn node_position(&self, index: usize) -> Vec3 {
        let [nx, ny, _] = self.dims;
        let (i, j, k) = (index % nx, (index / nx) % ny, index / (nx * ny));
        self.origin + Vec3::new(i as f32, j as f32, k as f32) * self.cell_size
    }

    fn value(&self, i: usize, j: usize, k: usize) -> f32 {
        self.values[i + self.dims[0] * (j + self.dims[1] * k)]
    }

    /// The grid's box: from the first node to the last.
    fn far_corner(&self) -> Vec3 {
        let [nx, ny, nz] = self.dims;
        self.origin + Vec3::new((nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32) * self.cell_size
    }

    /// The box the grid's nodes span.
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: self.origin,
            max: self.far_corner(),
        }
    }

    /// Signed distance (negative inside) and outward unit normal at `p`.
    /// Outside the grid's box, the distance to the box plus the value at the
    /// nearest point of the box, and the gradient of that sum: the direction
    /// away from the box plus the interpolant's gradient along the axes on
    /// which `p` is within the box.
    pub fn signed_distance(&self, p: Vec3) -> (f32, Vec3) {
        let q = p.clamp(self.origin, self.far_corner());
        let (value, gradient) = self.trilinear(q);
        let outside = p - q;
        let gap = outside.length();
        if gap > 0.0 {
            let free = Vec3::select(outside.cmpeq(Vec3::ZERO), gradient, Vec3::ZERO);
            (
                gap + value,
                (outside / gap + free).normalize_or(outside / gap),
            )
        } else {
            (value, gradient.normalize_or(Vec3::Y))
        }
    }

    /// The trilinear interpolant at `q` (inside the grid's box) and its gradient.
    fn trilinear(&self, q: Vec3) -> (f32, Vec3) {
        let g = (q - self.origin) / self.cell_size;
        let cell = |axis: usize| (g[axis].floor().max(0.0) as usize).min(self.dims[axis] - 2);
        let (i, j, k) = (cell(0), cell(1), cell(2));
        let f = g - Vec3::new(i as f32, j as f32, k as f32);
        let c = |di, dj, dk| self.value(i + di, j + dj, k + dk);
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        // Along x first, on the four x-edges of the cell.
        let edges = [
            [c(0, 0, 0), c(1, 0, 0)],
            [c(0, 1, 0), c(1, 1, 0)],
            [c(0, 0, 1), c(1, 0, 1)],
            [c(0, 1, 1), c(1, 1, 1)],
        ];
        let x = edges.map(|[a, b]| lerp(a, b, f.x));
        let dx = edges.map(|[a, b]| b - a);
        let (y0, y1) = (lerp(x[0], x[1], f.y), lerp(x[2], x[3], f.y));
        let value = lerp(y0, y1, f.z);
        let gradient = Vec3::new(
            lerp(lerp(dx[0], dx[1], f.y), lerp(dx[2], dx[3], f.y), f.z),
            lerp(x[1] - x[0], x[3] - x[2], f.z),
            y1 - y0,
        ) / self.cell_size;
        (value, gradient)
    }
}
