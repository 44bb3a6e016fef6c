//! Grid geometry shared by the solvers: sizes, boundary sides, cell kinds and
//! the staggered (MAC) velocity field.
//!
//! Every solver works on `nx × ny × nz` cubic cells of side `h` metres, the
//! domain's minimum corner at the world origin (shift positions yourself if
//! you need another origin). A **2-D** simulation is a grid with `ny = 1`: it
//! lives in the vertical x–z plane, so that "up" is +z in 2-D and 3-D alike
//! (natura's z-up convention). Any axis with a single cell is *flat*: no flow
//! crosses it and its velocity component stays zero.

use natura_core::Grid3;

use crate::error::{FluidError, Result};

/// Grid sizes in cells along x, y and z; every size `>= 1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Dims {
    /// Cells along x.
    pub nx: usize,
    /// Cells along y (1 for a 2-D simulation in the x–z plane).
    pub ny: usize,
    /// Cells along z (up).
    pub nz: usize,
}

/// The largest number of cells a solver accepts (2³⁰, about 4 GiB per scalar field).
pub const MAX_CELLS: usize = 1 << 30;

impl Dims {
    /// Returns `nx × ny × nz` cells, refusing zero sizes and more than [`MAX_CELLS`].
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidSize`] if a side is zero or the cell count
    /// (or the face count, one more per axis) exceeds the cap; sizes near
    /// `usize::MAX` are refused without overflow.
    pub fn new(nx: usize, ny: usize, nz: usize) -> Result<Self> {
        let dims = format!("{nx} × {ny} × {nz}");
        if nx == 0 || ny == 0 || nz == 0 {
            return Err(FluidError::InvalidSize {
                dims,
                reason: "every dimension must be at least 1",
            });
        }
        // Face grids have one more sample per axis; keep those within the cap too.
        // Any side above the cap fails before a product could overflow.
        let within = |cap: usize, extra: usize| {
            [nx, ny, nz].iter().try_fold(1usize, |acc, &n| {
                n.checked_add(extra)
                    .and_then(|m| acc.checked_mul(m))
                    .filter(|&p| p <= cap)
            })
        };
        if within(MAX_CELLS, 0).is_none() || within(4 * MAX_CELLS, 1).is_none() {
            return Err(FluidError::InvalidSize {
                dims,
                reason: "more than 2^30 cells",
            });
        }
        Ok(Self { nx, ny, nz })
    }

    /// A 2-D grid of `nx × nz` cells in the vertical x–z plane (`ny = 1`).
    ///
    /// # Errors
    ///
    /// As [`Dims::new`].
    pub fn plane(nx: usize, nz: usize) -> Result<Self> {
        Self::new(nx, 1, nz)
    }

    /// Sizes as an array `[nx, ny, nz]`.
    #[inline]
    #[must_use]
    pub fn n(&self) -> [usize; 3] {
        [self.nx, self.ny, self.nz]
    }

    /// Number of cells.
    #[inline]
    #[must_use]
    pub fn cells(&self) -> usize {
        self.nx * self.ny * self.nz
    }

    /// Whether axis `a` (0 = x, 1 = y, 2 = z) has more than one cell.
    #[inline]
    #[must_use]
    pub fn active(&self, a: usize) -> bool {
        self.n()[a] > 1
    }

    /// Number of non-flat axes (2 for a plane, 3 for a volume).
    #[must_use]
    pub fn active_axes(&self) -> usize {
        (0..3).filter(|&a| self.active(a)).count()
    }

    /// Linear index of cell `(i, j, k)` (x fastest).
    #[inline]
    #[must_use]
    pub fn idx(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.ny + j) * self.nx + i
    }

    /// `(i, j, k)` of linear index `c`.
    #[inline]
    #[must_use]
    pub fn ijk(&self, c: usize) -> [usize; 3] {
        [
            c % self.nx,
            (c / self.nx) % self.ny,
            c / (self.nx * self.ny),
        ]
    }

    /// Sizes of the face grid of velocity component `a`: one more sample along `a`.
    #[inline]
    #[must_use]
    pub fn face_dims(&self, a: usize) -> [usize; 3] {
        let mut n = self.n();
        n[a] += 1;
        n
    }

    /// A zero-filled scalar grid of the cell size.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::Core`] if the grids cannot be allocated.
    pub fn zeros(&self) -> Result<Grid3<f32>> {
        Ok(Grid3::new(self.nx, self.ny, self.nz, 0.0)?)
    }
}

impl std::fmt::Display for Dims {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} × {} × {}", self.nx, self.ny, self.nz)
    }
}

/// What lies beyond one side of the domain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Side {
    /// A free-slip solid wall: zero normal velocity, `∂p/∂n = 0` (Fedkiw et al. 2001, §2).
    #[default]
    Wall,
    /// An open side at atmospheric pressure (`p = 0` just outside): flow may
    /// leave or enter, driven by the projection.
    Open,
}

/// The six sides of the domain: `[low, high]` along x, y and z.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Boundaries {
    /// `[x = 0, x = nx·h]`.
    pub x: [Side; 2],
    /// `[y = 0, y = ny·h]`.
    pub y: [Side; 2],
    /// `[z = 0, z = nz·h]` (floor, ceiling).
    pub z: [Side; 2],
}

impl Boundaries {
    /// A closed box: walls on all six sides.
    #[must_use]
    pub fn closed() -> Self {
        Self::default()
    }

    /// Walls everywhere except an open ceiling, so rising smoke can leave.
    #[must_use]
    pub fn open_top() -> Self {
        Self {
            z: [Side::Wall, Side::Open],
            ..Self::default()
        }
    }

    /// The side of axis `a` at end `e` (0 = low, 1 = high).
    #[inline]
    #[must_use]
    pub fn side(&self, a: usize, e: usize) -> Side {
        [self.x, self.y, self.z][a][e]
    }
}

/// The role of a cell in the pressure solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// Fluid: its pressure is an unknown.
    #[default]
    Fluid,
    /// Occupied by a solid: faces touching it carry the solid's velocity and
    /// the pressure gradient across them is zero (Neumann).
    Solid,
    /// Air (or a liquid surface cell): pressure fixed to 0 (Dirichlet).
    Air,
}

/// A velocity field on the staggered MAC grid (Fedkiw et al. App. A,
/// Fedkiw et al. 2001, App. A): `u` on x-faces (`(nx+1) × ny × nz`), `v` on
/// y-faces, `w` on z-faces. Face `u[i, j, k]` sits at `(i, j+½, k+½)·h`.
#[derive(Clone, Debug, PartialEq)]
pub struct MacVelocity {
    dims: Dims,
    comps: [Grid3<f32>; 3],
}

impl MacVelocity {
    /// A zero field on `dims`.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::Core`] if the grids cannot be allocated.
    pub fn zeros(dims: Dims) -> Result<Self> {
        let g = |a: usize| {
            let n = dims.face_dims(a);
            Grid3::new(n[0], n[1], n[2], 0.0f32)
        };
        Ok(Self {
            dims,
            comps: [g(0)?, g(1)?, g(2)?],
        })
    }

    /// Builds a field whose face samples are `f(axis, position_m)`, with
    /// positions in metres for cell size `h`.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::Core`] if the grids cannot be allocated.
    pub fn from_fn(dims: Dims, h: f32, f: impl Fn(usize, glam::Vec3) -> f32) -> Result<Self> {
        let mut m = Self::zeros(dims)?;
        for a in 0..3 {
            if !dims.active(a) {
                continue;
            }
            let n = dims.face_dims(a);
            let g = &mut m.comps[a];
            for k in 0..n[2] {
                for j in 0..n[1] {
                    for i in 0..n[0] {
                        let p = face_position(a, [i, j, k], h);
                        g[(i, j, k)] = f(a, p);
                    }
                }
            }
        }
        Ok(m)
    }

    /// The grid size in cells.
    #[inline]
    #[must_use]
    pub fn dims(&self) -> Dims {
        self.dims
    }

    /// Component `a` (0 = u, 1 = v, 2 = w) on its face grid.
    #[inline]
    #[must_use]
    pub fn comp(&self, a: usize) -> &Grid3<f32> {
        &self.comps[a]
    }

    /// Component `a`, mutably.
    #[inline]
    pub fn comp_mut(&mut self, a: usize) -> &mut Grid3<f32> {
        &mut self.comps[a]
    }

    /// All three components.
    #[inline]
    #[must_use]
    pub fn comps(&self) -> &[Grid3<f32>; 3] {
        &self.comps
    }

    /// All three components, mutably.
    #[inline]
    pub fn comps_mut(&mut self) -> &mut [Grid3<f32>; 3] {
        &mut self.comps
    }

    /// The velocity at cell centre `(i, j, k)`: the average of the two faces
    /// along each axis (Fedkiw et al. Fedkiw et al. 2001, App. A).
    #[inline]
    #[must_use]
    pub fn centre(&self, i: usize, j: usize, k: usize) -> glam::Vec3 {
        let c = &self.comps;
        glam::Vec3::new(
            0.5 * (c[0][(i, j, k)] + c[0][(i + 1, j, k)]),
            0.5 * (c[1][(i, j, k)] + c[1][(i, j + 1, k)]),
            0.5 * (c[2][(i, j, k)] + c[2][(i, j, k + 1)]),
        )
    }

    /// Kinetic energy `½ Σ_faces u² · h³` (unit density), accumulated in `f64`.
    #[must_use]
    pub fn kinetic_energy(&self, h: f32) -> f64 {
        let vol = f64::from(h).powi(3);
        // Σ v² per component in blocks of eight lane sums, the blocks added
        // in order (deterministic on any thread count; a single running sum
        // is a latency-bound chain of dependent adds).
        0.5 * vol
            * self
                .comps
                .iter()
                .map(|g| {
                    let s = g.as_slice();
                    crate::chunks::sum_blocks(
                        s.len().div_ceil(crate::chunks::BLOCK),
                        crate::chunks::BLOCK,
                        |bi| {
                            let r = bi * crate::chunks::BLOCK
                                ..((bi + 1) * crate::chunks::BLOCK).min(s.len());
                            crate::diffuse::lane_dot(&s[r.clone()], &s[r])
                        },
                    )
                })
                .sum::<f64>()
    }

    /// Largest speed component magnitude over all faces.
    #[must_use]
    pub fn max_abs(&self) -> f32 {
        self.comps
            .iter()
            .flat_map(|g| g.as_slice().iter())
            .fold(0.0f32, |m, &v| m.max(v.abs()))
    }

    /// Returns the first non-finite face value as an error naming the component.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::NonFinite`] naming the field and the first NaN or
    /// infinite sample.
    pub fn check_finite(&self, stage: &'static str) -> Result<()> {
        const NAMES: [&str; 3] = ["u", "v", "w"];
        for (a, g) in self.comps.iter().enumerate() {
            check_grid(g, NAMES[a], stage)?;
        }
        Ok(())
    }
}

/// World position (metres) of face `idx` of component `a` for cell size `h`.
#[inline]
#[must_use]
pub fn face_position(a: usize, idx: [usize; 3], h: f32) -> glam::Vec3 {
    let mut p = [
        (idx[0] as f32 + 0.5) * h,
        (idx[1] as f32 + 0.5) * h,
        (idx[2] as f32 + 0.5) * h,
    ];
    p[a] = idx[a] as f32 * h;
    glam::Vec3::from_array(p)
}

/// World position (metres) of the centre of cell `idx`.
#[inline]
#[must_use]
pub fn cell_centre(idx: [usize; 3], h: f32) -> glam::Vec3 {
    glam::Vec3::new(
        (idx[0] as f32 + 0.5) * h,
        (idx[1] as f32 + 0.5) * h,
        (idx[2] as f32 + 0.5) * h,
    )
}

/// Returns [`FluidError::NonFinite`] for the first NaN/inf sample of `g`.
pub(crate) fn check_grid(g: &Grid3<f32>, field: &'static str, stage: &'static str) -> Result<()> {
    // A vectorised parallel scan first (no early exit); the position of the
    // first bad sample is only looked for when there is one.
    if all_finite(g.as_slice()) {
        return Ok(());
    }
    if let Some(c) = g.as_slice().iter().position(|v| !v.is_finite()) {
        let (nx, ny, _) = g.dims();
        return Err(FluidError::NonFinite {
            field,
            index: [c % nx, (c / nx) % ny, c / (nx * ny)],
            value: g.as_slice()[c],
            stage,
        });
    }
    Ok(())
}

/// Whether every sample is finite: blocks in parallel, each a fold without
/// early exit (`|x| < ∞` is false for NaN and ±∞) so that it vectorises.
pub(crate) fn all_finite(v: &[f32]) -> bool {
    let bad = crate::chunks::sum_blocks(
        v.len().div_ceil(crate::chunks::BLOCK),
        crate::chunks::BLOCK,
        |bi| {
            let r = bi * crate::chunks::BLOCK..((bi + 1) * crate::chunks::BLOCK).min(v.len());
            let ok = v[r]
                .iter()
                .fold(1u32, |m, &x| m & u32::from(x.abs() < f32::INFINITY));
            f64::from(1 - ok)
        },
    );
    bad == 0.0
}

/// Checks that a user-supplied grid has the cell size of `dims`.
pub(crate) fn check_cell_grid(g: &Grid3<f32>, dims: Dims, what: &'static str) -> Result<()> {
    let (a, b, c) = g.dims();
    if [a, b, c] != dims.n() {
        return Err(FluidError::SizeMismatch {
            what,
            expected: dims.to_string(),
            actual: format!("{a} × {b} × {c}"),
        });
    }
    Ok(())
}

/// Per-step diagnostics returned by every solver's `step`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepReport {
    /// Pressure solve statistics of the last projection in the step (if any).
    pub pressure: Option<crate::pressure::SolveStats>,
    /// Largest `|∇·u|` over fluid cells after the step (1/s).
    pub max_divergence: f32,
    /// Kinetic energy `½ Σ u² h³` after the step (unit density).
    pub kinetic_energy: f64,
    /// Number of sub-steps taken (liquids: surface sub-steps; otherwise 1).
    pub substeps: u32,
    /// Total pressure-solver iterations over the step.
    pub pressure_iterations: u32,
}
