//! Rays, hits and the triangles a height-field cell is split into.

use glam::{UVec2, Vec3};

/// The ray type every camera returns, shared with natura-core's cameras.
pub use natura_core::camera::Ray;

/// Which of the two triangles of a cell.
///
/// Musgrave splits each square cell along the diagonal that "runs from top
/// left to bottom right" (Musgrave 1993, §3.3.2). In cell-local coordinates
/// `(u, v) = (x/cell − i, y/cell − j) ∈ [0, 1]²` this is the anti-diagonal
/// `u + v = 1`, giving
///
/// * [`Triangle::Lower`]: corners `(0,0), (1,0), (0,1)`, where `u + v ≤ 1`;
/// * [`Triangle::Upper`]: corners `(1,1), (0,1), (1,0)`, where `u + v ≥ 1`.
///
/// The corners are listed in the order of [`Hit::barycentric`].
/// Erratum: the source's printed clip test `x + y ≤ cellxmax + cellymax`
/// (Musgrave 1993, §3.3.2) accepts the whole square; the triangle is `u + v ≤ 1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Triangle {
    /// The triangle holding corner `(i, j)`: `u + v ≤ 1`.
    Lower,
    /// The triangle holding corner `(i + 1, j + 1)`: `u + v ≥ 1`.
    Upper,
}

impl Triangle {
    /// The triangle's corners as sample offsets from the cell's `(i, j)`, in barycentric order.
    #[inline]
    #[must_use]
    pub const fn corners(self) -> [(u32, u32); 3] {
        match self {
            Triangle::Lower => [(0, 0), (1, 0), (0, 1)],
            Triangle::Upper => [(1, 1), (0, 1), (1, 0)],
        }
    }

    /// `0` for [`Triangle::Lower`], `1` for [`Triangle::Upper`].
    #[inline]
    #[must_use]
    pub const fn index(self) -> u32 {
        match self {
            Triangle::Lower => 0,
            Triangle::Upper => 1,
        }
    }
}

/// A ray's intersection with the height-field surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit: `point ≈ ray.origin + t·ray.dir`.
    pub t: f32,
    /// The hit point, world space: the barycentric combination of the triangle's corners.
    pub point: Vec3,
    /// Unit normal of the hit triangle's plane, always facing up (`z > 0`).
    pub geometric_normal: Vec3,
    /// Unit normal interpolated over the triangle from the corners' central-difference
    /// normals (Phong-style, as Musgrave 1993, Plate 8.1), facing up.
    pub smooth_normal: Vec3,
    /// The cell `(i, j)`: the square between samples `(i, j)` and `(i + 1, j + 1)`.
    pub cell: UVec2,
    /// Which triangle of the cell (see [`Triangle`] for the diagonal).
    pub triangle: Triangle,
    /// Barycentric weights of the triangle's corners, in the order of
    /// [`Triangle::corners`]; they sum to 1.
    pub barycentric: Vec3,
    /// Whether the ray arrived from above the surface (`dir · geometric_normal < 0`).
    pub from_above: bool,
}

/// Counters from one traced ray, for benchmarks and the source's
/// "about two tests per ray" claim (Musgrave 1993, §3.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraceStats {
    /// Hierarchy nodes (mipmap) examined, including cells.
    pub nodes_visited: u32,
    /// Cells whose z-span passed the cull and were tested against triangles.
    pub cells_tested: u32,
    /// Ray–triangle tests performed (two per tested cell).
    pub triangle_tests: u32,
}

impl std::ops::AddAssign for TraceStats {
    fn add_assign(&mut self, o: Self) {
        self.nodes_visited += o.nodes_visited;
        self.cells_tested += o.cells_tested;
        self.triangle_tests += o.triangle_tests;
    }
}
