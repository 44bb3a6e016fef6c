//! Stam's *Stable Fluids* (SIGGRAPH 1999; Stam 1999), 2-D and 3-D.
//!
//! One step is `w0 → add force → w1 → advect → w2 → diffuse → w3 → project
//! → w4` (Stam 1999, §2.2, Fig. 1): forces are added in place (Stam 1999, §2.2), every velocity
//! component is traced back through the force-added field `w1` (Stam 1999, §2.2,
//! Stam 1999, §3.2), diffusion is implicit (Stam 1999, §2.2) and the projection makes the field
//! divergence-free (Stam 1999, §2.2). Moving substances follow
//! `∂a/∂t = −u·∇a + κ_a∇²a − α_a a + S_a` (Stam 1999, §2.4; the source prints `κ_a∇²`
//! without its operand, an erratum) with the new velocity (Stam 1999, §3.2), and
//! dissipation divides by `1 + dt·α_a` (Stam 1999, §2.4).
//!
//! Two domains:
//!
//! * [`PeriodicFluid`]: the n-torus with the FFT solver (Stam 1999, §2.3), on
//!   Stam's cell-centred (collocated) grid. Output tiles seamlessly.
//! * [`BoundedFluid`]: a box with walls, open sides and obstacles. Instead of
//!   the paper's collocated grid with FISHPAK's mixed wide/compact stencils
//!   (Stam 1999, App. B, which only approximately projects),
//!   velocity lives on the staggered MAC grid whose divergence and gradient
//!   compose to the compact Laplacian, so the projected field is discretely
//!   divergence-free to the solver tolerance.

use glam::Vec3;
use natura_core::Grid3;

use crate::advect::{self, Advection, Solids, VelSampler};
use crate::diffuse::{self, EXCLUDED, FREE};
use crate::error::{self, FluidError, Result};
use crate::fft::{self, DiffusionFilter, Fft3, FftVariant};
use crate::grid::{self, Boundaries, CellKind, Dims, MacVelocity, StepReport};
use crate::mac::{self, Projector};
use crate::pressure::SolverParams;
use crate::shape::{Obstacle, Obstacles, Shape, voxelise};

/// The inputs both domains share, written once: grid size and cell size,
/// substances with their sources, and force regions. Expanded inside each
/// solver's `impl` (each has the fields `dims`, `h`, `subs`, `force` and
/// `force_sources`).
macro_rules! shared_inputs {
    () => {
        /// Grid size.
        #[must_use]
        pub fn dims(&self) -> Dims {
            self.dims
        }

        /// Cell size (m).
        #[must_use]
        pub fn h(&self) -> f32 {
            self.h
        }

        /// Adds a substance (initially zero everywhere).
        ///
        /// # Errors
        ///
        /// Returns [`FluidError::InvalidParameter`] for a negative or non-finite
        /// diffusion or dissipation rate, and [`FluidError::Core`] if its grid cannot be
        /// allocated.
        pub fn add_substance(&mut self, s: Substance) -> Result<SubstanceId> {
            self.subs.add(self.dims, s)
        }

        /// Adds a persistent source of substance `id`; it must lie inside the grid.
        ///
        /// # Errors
        ///
        /// Returns [`FluidError::InvalidParameter`] for non-finite amounts or shapes, and
        /// [`FluidError::OutsideGrid`] if the source lies outside the grid.
        pub fn add_source(&mut self, id: SubstanceId, src: ScalarSource) -> Result<()> {
            self.subs.check(id)?;
            check_scalar_source(self.dims, self.h, &src)?;
            self.subs.sources.push((id.0, src));
            Ok(())
        }

        /// Adds a persistent force region; it must lie inside the grid.
        ///
        /// # Errors
        ///
        /// Returns [`FluidError::InvalidParameter`] for a non-finite force or shape, and
        /// [`FluidError::OutsideGrid`] if it lies outside the grid.
        pub fn add_force_source(&mut self, s: ForceSource) -> Result<()> {
            check_force_source(self.dims, self.h, &s)?;
            self.force_sources.push(s);
            Ok(())
        }

        /// Per-step force field at cell centres (m/s²), cleared after each step —
        /// the interactive forces `F` of the main loop (Stam 1999, §3.2).
        pub fn force_mut(&mut self) -> &mut [Grid3<f32>; 3] {
            &mut self.force
        }

        /// The field of substance `id`.
        ///
        /// # Errors
        ///
        /// Returns [`FluidError::InvalidParameter`] naming `substance id` if there is no such
        /// substance.
        pub fn substance(&self, id: SubstanceId) -> Result<&Grid3<f32>> {
            self.subs.check(id)?;
            Ok(&self.subs.fields[id.0])
        }

        /// The field of substance `id`, mutably.
        ///
        /// # Errors
        ///
        /// Returns [`FluidError::InvalidParameter`] naming `substance id` if there is no such
        /// substance.
        pub fn substance_mut(&mut self, id: SubstanceId) -> Result<&mut Grid3<f32>> {
            self.subs.check(id)?;
            Ok(&mut self.subs.fields[id.0])
        }
    };
}

mod bounded;
mod periodic;

pub use bounded::BoundedFluid;
pub use periodic::PeriodicFluid;

/// A moving substance (dye, smoke density, temperature, texture coordinate).
#[derive(Clone, Debug, PartialEq)]
pub struct Substance {
    /// A name for reports and files.
    pub name: String,
    /// Diffusion constant κ (m²/s), `kS` in the paper (Stam 1999, §3.1).
    pub diffusion: f32,
    /// Dissipation rate α (1/s), `aS` in the paper (Stam 1999, §3.1).
    pub dissipation: f32,
}

impl Substance {
    /// A substance that neither diffuses nor dissipates.
    #[must_use]
    pub fn passive(name: &str) -> Self {
        Self {
            name: name.to_owned(),
            diffusion: 0.0,
            dissipation: 0.0,
        }
    }

    fn validate(&self) -> Result<()> {
        error::non_negative("substance diffusion", f64::from(self.diffusion))?;
        error::non_negative("substance dissipation", f64::from(self.dissipation))
    }
}

/// Handle of a substance added to a solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SubstanceId(pub usize);

/// A region that adds `rate` units of a substance per second to every cell
/// whose centre lies inside `shape` (the `S_a` term, Stam 1999, §2.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalarSource {
    /// The region.
    pub shape: Shape,
    /// Units per second.
    pub rate: f32,
}

/// A region that accelerates the fluid by `acceleration` (m/s²) in every
/// cell whose centre lies inside `shape` (the force `f`, Stam 1999, §2.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceSource {
    /// The region.
    pub shape: Shape,
    /// Acceleration (m/s²).
    pub acceleration: Vec3,
}

/// Parameters of both Stable Fluids solvers.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct StableParams {
    /// Kinematic viscosity ν (m²/s), `visc` (Stam 1999, §3.1). The paper gives no value;
    /// default 1e-4.
    pub viscosity: f32,
    /// Advection scheme; default linear semi-Lagrangian with RK2 (Stam 1999, §3.2).
    pub advection: Advection,
    /// Periodic solver: diffusion filter (default the paper's rational one).
    pub filter: DiffusionFilter,
    /// Periodic solver: spectral or finite-difference wavenumbers.
    pub variant: FftVariant,
    /// Bounded solver: pressure solver and tolerance.
    pub solver: SolverParams,
    /// Bounded solver: domain sides.
    pub bounds: Boundaries,
}

impl Default for StableParams {
    fn default() -> Self {
        Self {
            viscosity: 1e-4,
            advection: Advection::default(),
            filter: DiffusionFilter::Rational,
            variant: FftVariant::Spectral,
            solver: SolverParams::default(),
            bounds: Boundaries::closed(),
        }
    }
}

impl StableParams {
    /// Checks every parameter: viscosity finite and `>= 0`, solver settings valid.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        error::non_negative("viscosity", f64::from(self.viscosity))?;
        self.solver.validate()
    }
}

fn check_h(h: f32) -> Result<()> {
    error::positive("cell size h", f64::from(h))
}

/// Substances and their sources, shared by both solvers.
#[derive(Clone, Debug, Default)]
struct Substances {
    specs: Vec<Substance>,
    fields: Vec<Grid3<f32>>,
    sources: Vec<(usize, ScalarSource)>,
}

impl Substances {
    fn add(&mut self, dims: Dims, s: Substance) -> Result<SubstanceId> {
        s.validate()?;
        self.specs.push(s);
        self.fields.push(dims.zeros()?);
        Ok(SubstanceId(self.specs.len() - 1))
    }

    fn check(&self, id: SubstanceId) -> Result<()> {
        if id.0 < self.specs.len() {
            Ok(())
        } else {
            Err(FluidError::InvalidParameter {
                name: "substance id",
                value: id.0.to_string(),
                reason: "no such substance",
            })
        }
    }

    fn add_sources(&mut self, dims: Dims, h: f32, dt: f32) {
        for (id, src) in &self.sources {
            let f = &mut self.fields[*id];
            let mask = voxelise(&[Obstacle::fixed(src.shape)], dims, h);
            for (v, m) in f.as_mut_slice().iter_mut().zip(mask) {
                if m != u16::MAX {
                    *v += dt * src.rate;
                }
            }
        }
    }

    fn check_finite(&self, stage: &'static str) -> Result<()> {
        for f in &self.fields {
            grid::check_grid(f, "substance", stage)?;
        }
        Ok(())
    }
}

/// The step's force field: `extra` (the user's per-step field) plus the
/// persistent force sources, written into `f` (cell-sized grids; a user
/// field of another size is an error).
fn force_field(
    f: &mut [Grid3<f32>; 3],
    dims: Dims,
    h: f32,
    sources: &[ForceSource],
    extra: &[Grid3<f32>; 3],
) -> Result<()> {
    for (o, e) in f.iter_mut().zip(extra) {
        grid::check_cell_grid(e, dims, "force field")?;
        o.as_mut_slice().copy_from_slice(e.as_slice());
    }
    for s in sources {
        let mask = voxelise(&[Obstacle::fixed(s.shape)], dims, h);
        for (c, m) in mask.into_iter().enumerate() {
            if m != u16::MAX {
                for a in 0..3 {
                    if dims.active(a) {
                        f[a].as_mut_slice()[c] += s.acceleration[a];
                    }
                }
            }
        }
    }
    Ok(())
}

fn check_force_source(dims: Dims, h: f32, s: &ForceSource) -> Result<()> {
    s.shape.check_inside(dims, h, "force source")?;
    if !s.acceleration.is_finite() {
        return Err(FluidError::InvalidParameter {
            name: "acceleration",
            value: format!("{:?}", s.acceleration),
            reason: "must be finite",
        });
    }
    Ok(())
}

fn check_scalar_source(dims: Dims, h: f32, s: &ScalarSource) -> Result<()> {
    s.shape.check_inside(dims, h, "substance source")?;
    error::finite("source rate", f64::from(s.rate))
}

fn zero3(dims: Dims) -> Result<[Grid3<f32>; 3]> {
    Ok([dims.zeros()?, dims.zeros()?, dims.zeros()?])
}
