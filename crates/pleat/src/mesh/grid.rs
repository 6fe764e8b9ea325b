//! Rectangular grid cloth: `cols x rows` vertices over a `width x height` sheet.
//!
//! Vertex `(row, col)` has index `row * cols + col`; row 0 is the top edge
//! (the highest for a vertical sheet, the farthest along -z for a horizontal
//! one) and column 0 the left edge (-x).

use super::Mesh;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Plane the sheet lies in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GridOrientation {
    /// In the x-z plane, facing +y.
    #[default]
    Horizontal,
    /// In the x-y plane, facing +z.
    Vertical,
}

/// Parameters of a grid mesh.
#[derive(Clone, Debug)]
pub struct GridSpec {
    /// Vertices along x (columns), at least 2.
    pub cols: usize,
    /// Vertices along the other side (rows), at least 2.
    pub rows: usize,
    /// Width and height of the sheet (m).
    pub size: [f32; 2],
    /// The plane the sheet lies in.
    pub orientation: GridOrientation,
    /// Centre of the sheet.
    pub center: Vec3,
    /// Alternate the diagonal direction from quad to quad (a less biased mesh).
    pub alternate_diagonals: bool,
}

impl GridSpec {
    /// A horizontal grid centred at the origin with alternating diagonals.
    pub fn new(cols: usize, rows: usize, size: [f32; 2]) -> Self {
        GridSpec {
            cols,
            rows,
            size,
            orientation: GridOrientation::Horizontal,
            center: Vec3::ZERO,
            alternate_diagonals: true,
        }
    }

    /// Index of the vertex at `row`, `col`.
    pub fn index(&self, row: usize, col: usize) -> u32 {
        (row * self.cols + col) as u32
    }

    /// Builds the mesh. `cols` and `rows` must be at least 2.
    pub fn build(&self) -> Mesh {
        let (cols, rows) = (self.cols, self.rows);
        let mut positions = Vec::with_capacity(cols * rows);
        for r in 0..rows {
            for c in 0..cols {
                let u = c as f32 / (cols - 1) as f32 - 0.5;
                let v = r as f32 / (rows - 1) as f32 - 0.5;
                let (x, down) = (u * self.size[0], v * self.size[1]);
                let local = match self.orientation {
                    GridOrientation::Horizontal => Vec3::new(x, 0.0, down),
                    GridOrientation::Vertical => Vec3::new(x, -down, 0.0),
                };
                positions.push(self.center + local);
            }
        }
        let mut triangles = Vec::with_capacity(2 * (cols - 1) * (rows - 1));
        for r in 0..rows - 1 {
            for c in 0..cols - 1 {
                let [a, b] = [self.index(r, c), self.index(r, c + 1)];
                let [d, e] = [self.index(r + 1, c), self.index(r + 1, c + 1)];
                let flip = self.alternate_diagonals && (r + c) % 2 == 1;
                // Counter-clockwise seen from +y (horizontal) or +z (vertical).
                let quad = if flip {
                    [[a, d, b], [b, d, e]]
                } else {
                    [[a, d, e], [a, e, b]]
                };
                triangles.extend(quad);
            }
        }
        Mesh {
            positions,
            triangles,
            grid: Some([cols, rows]),
        }
    }

    /// Vertices of a named corner: `top_left`, `top_right`, `bottom_left`, `bottom_right`.
    pub fn corner(&self, name: &str) -> Option<u32> {
        let (last_r, last_c) = (self.rows - 1, self.cols - 1);
        Some(match name {
            "top_left" => self.index(0, 0),
            "top_right" => self.index(0, last_c),
            "bottom_left" => self.index(last_r, 0),
            "bottom_right" => self.index(last_r, last_c),
            _ => return None,
        })
    }

    /// Vertices of a named edge: `top`, `bottom`, `left`, `right`.
    pub fn edge(&self, name: &str) -> Option<Vec<u32>> {
        let (last_r, last_c) = (self.rows - 1, self.cols - 1);
        Some(match name {
            "top" => (0..self.cols).map(|c| self.index(0, c)).collect(),
            "bottom" => (0..self.cols).map(|c| self.index(last_r, c)).collect(),
            "left" => (0..self.rows).map(|r| self.index(r, 0)).collect(),
            "right" => (0..self.rows).map(|r| self.index(r, last_c)).collect(),
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normal(mesh: &Mesh, t: usize) -> Vec3 {
        let [a, b, c] = mesh.triangles[t].map(|i| mesh.positions[i as usize]);
        (b - a).cross(c - a).normalize()
    }

    #[test]
    fn grid_counts_and_winding() {
        for orientation in [GridOrientation::Horizontal, GridOrientation::Vertical] {
            let spec = GridSpec {
                orientation,
                ..GridSpec::new(5, 4, [1.0, 1.0])
            };
            let mesh = spec.build();
            assert_eq!(mesh.positions.len(), 20);
            assert_eq!(mesh.triangles.len(), 2 * 4 * 3);
            let facing = match orientation {
                GridOrientation::Horizontal => Vec3::Y,
                GridOrientation::Vertical => Vec3::Z,
            };
            for t in 0..mesh.triangles.len() {
                assert!(normal(&mesh, t).dot(facing) > 0.999, "triangle {t}");
            }
        }
    }

    #[test]
    fn named_corners_and_edges() {
        let spec = GridSpec {
            orientation: GridOrientation::Vertical,
            ..GridSpec::new(3, 3, [1.0, 1.0])
        };
        let mesh = spec.build();
        let top_left = mesh.positions[spec.corner("top_left").unwrap() as usize];
        assert_eq!(top_left, Vec3::new(-0.5, 0.5, 0.0));
        assert_eq!(spec.edge("right").unwrap(), vec![2, 5, 8]);
        assert!(spec.corner("middle").is_none());
    }
}
