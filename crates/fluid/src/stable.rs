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

/// Stable Fluids on a periodic domain with the FFT solver (Stam 1999, §2.3).
#[derive(Clone, Debug)]
pub struct PeriodicFluid {
    dims: Dims,
    h: f32,
    params: StableParams,
    fft: Fft3,
    vel: [Grid3<f32>; 3],
    force: [Grid3<f32>; 3],
    force_sources: Vec<ForceSource>,
    subs: Substances,
}

impl PeriodicFluid {
    /// A fluid at rest on `dims` cells of size `h` metres.
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`FluidError::InvalidParameter`]
    /// for a cell size that is not finite and positive, and [`FluidError::Core`] if
    /// the grids cannot be allocated.
    pub fn new(dims: Dims, h: f32, params: StableParams) -> Result<Self> {
        check_h(h)?;
        params.validate()?;
        Ok(Self {
            dims,
            h,
            params,
            fft: Fft3::new(dims),
            vel: zero3(dims)?,
            force: zero3(dims)?,
            force_sources: Vec::new(),
            subs: Substances::default(),
        })
    }

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

    /// Cell-centred velocity components (m/s).
    #[must_use]
    pub fn velocity(&self) -> &[Grid3<f32>; 3] {
        &self.vel
    }

    /// Cell-centred velocity, mutably (e.g. to set initial conditions).
    pub fn velocity_mut(&mut self) -> &mut [Grid3<f32>; 3] {
        &mut self.vel
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

    /// Kinetic energy `½ Σ |u|² h³` (unit density).
    #[must_use]
    pub fn kinetic_energy(&self) -> f64 {
        let vol = f64::from(self.h).powi(3);
        0.5 * vol
            * self
                .vel
                .iter()
                .flat_map(|g| g.as_slice())
                .map(|&v| f64::from(v) * f64::from(v))
                .sum::<f64>()
    }

    /// Projects the current velocity (no diffusion), e.g. after setting an
    /// initial field by hand.
    pub fn project(&mut self) {
        fft::diffuse_project(
            &self.fft,
            &mut self.vel,
            self.h,
            0.0,
            self.params.filter,
            self.params.variant,
            true,
        );
    }

    /// Advances by `dt` seconds: Vstep then Sstep (Stam 1999, §3.2).
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] naming `dt` unless it is finite and
    /// positive, and [`FluidError::NonFinite`] naming the field and stage if the step
    /// produces a NaN or infinite value.
    pub fn step(&mut self, dt: f32) -> Result<StepReport> {
        error::check_dt(dt)?;
        let (dims, h) = (self.dims, self.h);
        // w1 = w0 + dt f
        let mut f = zero3(dims)?;
        force_field(&mut f, dims, h, &self.force_sources, &self.force)?;
        for a in 0..3 {
            if dims.active(a) {
                for (v, &fv) in self.vel[a].as_mut_slice().iter_mut().zip(f[a].as_slice()) {
                    *v += dt * fv;
                }
            }
        }
        // w2(x) = w1(p(x, −dt)), every component traced through w1.
        let w1 = self.vel.clone();
        {
            let vs = VelSampler::collocated(&w1, dims);
            for a in 0..3 {
                if dims.active(a) {
                    let src = advect::centre_sampler(&w1[a], true);
                    advect::advect(
                        self.vel[a].as_mut_slice(),
                        &src,
                        &vs,
                        dt / h,
                        &self.params.advection,
                        None,
                    );
                }
            }
        }
        grid::check_grid(&self.vel[0], "u", "advection")?;
        // Diffuse and project in Fourier space.
        let nu_dt = f64::from(self.params.viscosity) * f64::from(dt);
        fft::diffuse_project(
            &self.fft,
            &mut self.vel,
            h,
            nu_dt,
            self.params.filter,
            self.params.variant,
            true,
        );
        for (a, name) in ["u", "v", "w"].into_iter().enumerate() {
            grid::check_grid(&self.vel[a], name, "projection")?;
        }
        // Sstep: source, advect with the new velocity, diffuse, dissipate.
        self.subs.add_sources(dims, h, dt);
        let vs = VelSampler::collocated(&self.vel, dims);
        for (s, field) in self.subs.specs.iter().zip(self.subs.fields.iter_mut()) {
            let old = field.clone();
            advect::advect(
                field.as_mut_slice(),
                &advect::centre_sampler(&old, true),
                &vs,
                dt / h,
                &self.params.advection,
                None,
            );
            fft::diffuse_scalar(
                &self.fft,
                field,
                h,
                f64::from(s.diffusion) * f64::from(dt),
                self.params.filter,
                self.params.variant,
            );
            let k = 1.0 / (1.0 + dt * s.dissipation);
            field.as_mut_slice().iter_mut().for_each(|v| *v *= k);
        }
        self.subs.check_finite("substance step")?;
        self.force
            .iter_mut()
            .for_each(|g| g.as_mut_slice().fill(0.0));
        Ok(StepReport {
            pressure: None,
            max_divergence: self.max_divergence(),
            kinetic_energy: self.kinetic_energy(),
            substeps: 1,
            pressure_iterations: 0,
        })
    }

    /// Largest |central-difference divergence| (the discrete divergence that
    /// [`FftVariant::ModifiedWavenumber`] zeroes exactly).
    #[must_use]
    pub fn max_divergence(&self) -> f32 {
        let d = self.dims;
        let n = d.n();
        let mut m = 0.0f32;
        for c in 0..d.cells() {
            let ijk = d.ijk(c);
            let mut s = 0.0;
            for a in 0..3 {
                if !d.active(a) {
                    continue;
                }
                let mut p = ijk;
                let mut q = ijk;
                p[a] = (ijk[a] + 1) % n[a];
                q[a] = (ijk[a] + n[a] - 1) % n[a];
                let g = self.vel[a].as_slice();
                s += (g[d.idx(p[0], p[1], p[2])] - g[d.idx(q[0], q[1], q[2])]) / (2.0 * self.h);
            }
            m = m.max(s.abs());
        }
        m
    }
}

/// Stable Fluids in a box with walls, open sides and obstacles, on the MAC grid.
#[derive(Clone, Debug)]
pub struct BoundedFluid {
    dims: Dims,
    h: f32,
    params: StableParams,
    vel: MacVelocity,
    solid: Obstacles,
    force: [Grid3<f32>; 3],
    force_sources: Vec<ForceSource>,
    subs: Substances,
    projector: Projector,
    /// Work vectors of the implicit diffusion, reused every step.
    scratch: diffuse::Scratch,
    /// The step's copy of the velocity before advection, kept between
    /// steps so that a step does not allocate (and page-fault) it.
    spare: MacVelocity,
    /// Diffusion roles of faces and cells, rebuilt when the solids move.
    roles: Roles,
    /// The step's force field (user field plus sources), kept between
    /// steps so that a step does not allocate it.
    fbuf: [Grid3<f32>; 3],
}

/// The implicit diffusion's sample roles (faces per axis, cells), which
/// depend only on the cell kinds and the boundaries: cached between steps
/// and rebuilt when either changes (a moving obstacle changes the kinds).
#[derive(Clone, Debug, Default)]
struct Roles {
    /// The cell kinds and boundaries the roles were built for (`None`: not built).
    key: Option<(Vec<CellKind>, Boundaries)>,
    /// Per axis: fixed faces (walls, faces of solid cells) are [`DIRICHLET`]
    /// (1), the others [`FREE`] (0).
    faces: [Vec<u8>; 3],
    /// Per cell: solid cells are [`EXCLUDED`], the others [`FREE`].
    cells: Vec<u8>,
}

impl Roles {
    /// Brings the roles up to date with `kinds` and `bounds`.
    fn update(&mut self, dims: Dims, kinds: &[CellKind], bounds: &Boundaries) {
        if let Some((k, b)) = &self.key
            && k.as_slice() == kinds
            && b == bounds
        {
            return;
        }
        // Fixed faces (1) are Dirichlet data, free faces (0) unknowns.
        const _: () = assert!(diffuse::FREE == 0 && diffuse::DIRICHLET == 1);
        for a in 0..3 {
            self.faces[a] = if dims.active(a) {
                mac::fixed_faces(dims, kinds, bounds, a)
            } else {
                Vec::new()
            };
        }
        self.cells = kinds
            .iter()
            .map(|&k| if k == CellKind::Solid { EXCLUDED } else { FREE })
            .collect();
        self.key = Some((kinds.to_vec(), *bounds));
    }
}

impl BoundedFluid {
    /// A fluid at rest on `dims` cells of size `h` metres.
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`FluidError::InvalidParameter`]
    /// for a cell size that is not finite and positive, and [`FluidError::Core`] if
    /// the grids cannot be allocated.
    pub fn new(dims: Dims, h: f32, params: StableParams) -> Result<Self> {
        check_h(h)?;
        params.validate()?;
        Ok(Self {
            dims,
            h,
            params,
            vel: MacVelocity::zeros(dims)?,
            solid: Obstacles::new(dims)?,
            force: zero3(dims)?,
            force_sources: Vec::new(),
            subs: Substances::default(),
            projector: Projector::new(),
            scratch: diffuse::Scratch::default(),
            spare: MacVelocity::zeros(dims)?,
            roles: Roles::default(),
            fbuf: zero3(dims)?,
        })
    }

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

    /// Adds an obstacle; it must lie inside the grid.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] for a shape with non-finite or
    /// degenerate extents, and [`FluidError::OutsideGrid`] if it lies outside the grid.
    pub fn add_obstacle(&mut self, o: Obstacle) -> Result<()> {
        self.solid.add(o, self.dims, self.h)
    }

    /// Adds a substance.
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

    /// Per-step force field at cell centres (m/s²), cleared after each step.
    pub fn force_mut(&mut self) -> &mut [Grid3<f32>; 3] {
        &mut self.force
    }

    /// The MAC velocity.
    #[must_use]
    pub fn velocity(&self) -> &MacVelocity {
        &self.vel
    }

    /// The MAC velocity, mutably.
    pub fn velocity_mut(&mut self) -> &mut MacVelocity {
        &mut self.vel
    }

    /// Cell kinds (fluid or solid).
    #[must_use]
    pub fn cell_kinds(&self) -> &Grid3<CellKind> {
        &self.solid.kinds
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

    /// Pressure of the last projection (m²/s², unit density).
    #[must_use]
    pub fn pressure(&self) -> Option<Grid3<f32>> {
        self.projector.pressure(self.dims)
    }

    /// Projects the current velocity (e.g. after setting it by hand).
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::NonFinite`] if the velocity or the pressure is not
    /// finite, and [`FluidError::InvalidParameter`] for a non-positive `dt`.
    pub fn project(&mut self, dt: f32) -> Result<crate::pressure::SolveStats> {
        let sv = crate::shape::solid_face_velocity(
            self.dims,
            self.h,
            &self.solid.owner,
            &self.solid.list,
        );
        let mut vel = self.vel.clone();
        mac::enforce_solids(
            &mut vel,
            self.solid.kinds.as_slice(),
            &self.params.bounds,
            &sv,
        );
        let st = self.projector.project(
            &mut vel,
            &self.solid.kinds,
            &self.params.bounds,
            self.h,
            dt,
            &self.params.solver,
        )?;
        self.vel = vel;
        Ok(st)
    }

    /// Drops the cached diffusion roles (tests: the cache against a rebuild).
    #[cfg(test)]
    pub(crate) fn forget_roles(&mut self) {
        self.roles = Roles::default();
    }

    /// Advances by `dt` seconds: force → advect → diffuse → project, then the
    /// substances (Stam 1999, §3.2). Moving obstacles advance at the end.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] naming `dt` unless it is finite and
    /// positive, and [`FluidError::NonFinite`] naming the field and stage if the step
    /// produces a NaN or infinite value.
    pub fn step(&mut self, dt: f32) -> Result<StepReport> {
        error::check_dt(dt)?;
        let (dims, h) = (self.dims, self.h);
        let bounds = self.params.bounds;
        force_field(&mut self.fbuf, dims, h, &self.force_sources, &self.force)?;
        mac::add_centre_forces(
            &mut self.vel,
            &self.fbuf,
            dt,
            self.solid.kinds.as_slice(),
            &bounds,
        );
        let solids = Solids {
            kinds: self.solid.kinds.as_slice(),
            dims,
        };
        let has_solids = self.solid.list.iter().len() > 0;
        // w1: the velocity the advection reads, copied into the spare
        // buffer (no allocation).
        for a in 0..3 {
            self.spare
                .comp_mut(a)
                .as_mut_slice()
                .copy_from_slice(self.vel.comp(a).as_slice());
        }
        let w1 = &self.spare;
        {
            let vs = VelSampler::mac(w1);
            for a in 0..3 {
                if dims.active(a) {
                    advect::advect(
                        self.vel.comp_mut(a).as_mut_slice(),
                        &advect::face_sampler(w1.comp(a), a),
                        &vs,
                        dt / h,
                        &self.params.advection,
                        has_solids.then_some(&solids),
                    );
                }
            }
        }
        self.vel.check_finite("advection")?;
        // Work on the advected field in the spare slot; `self.vel` holds
        // the step's start velocity until the swap after the projection.
        std::mem::swap(&mut self.vel, &mut self.spare);
        let vel = &mut self.spare;
        {
            let sv = crate::shape::solid_face_velocity(
                self.dims,
                self.h,
                &self.solid.owner,
                &self.solid.list,
            );
            mac::enforce_solids(vel, self.solid.kinds.as_slice(), &bounds, &sv);
        }
        // The cell kinds do not change until the obstacles advance at the
        // end of the step: one check of the cached roles serves the
        // velocity's and the substances' diffusion.
        self.roles
            .update(dims, self.solid.kinds.as_slice(), &bounds);
        let coef = self.params.viscosity * dt / (h * h);
        if coef > 0.0 {
            for a in 0..3 {
                if !dims.active(a) {
                    continue;
                }
                let n = dims.face_dims(a);
                let role = &self.roles.faces[a];
                diffuse::diffuse_in(
                    &mut self.scratch,
                    vel.comp_mut(a).as_mut_slice(),
                    n,
                    coef,
                    role,
                );
            }
        }
        let stats =
            self.projector
                .project(vel, &self.solid.kinds, &bounds, h, dt, &self.params.solver)?;
        vel.check_finite("projection")?;
        // The start velocity's buffer becomes the next step's spare.
        std::mem::swap(&mut self.vel, &mut self.spare);
        // Substances.
        self.subs.add_sources(dims, h, dt);
        let vs = VelSampler::mac(&self.vel);
        let role = &self.roles.cells;
        for (s, field) in self.subs.specs.iter().zip(self.subs.fields.iter_mut()) {
            let old = field.clone();
            advect::advect(
                field.as_mut_slice(),
                &advect::centre_sampler(&old, false),
                &vs,
                dt / h,
                &self.params.advection,
                has_solids.then_some(&solids),
            );
            diffuse::diffuse_in(
                &mut self.scratch,
                field.as_mut_slice(),
                dims.n(),
                s.diffusion * dt / (h * h),
                role,
            );
            let k = 1.0 / (1.0 + dt * s.dissipation);
            field.as_mut_slice().iter_mut().for_each(|v| *v *= k);
        }
        self.subs.check_finite("substance step")?;
        self.force
            .iter_mut()
            .for_each(|g| g.as_mut_slice().fill(0.0));
        self.solid.advance(dt, self.dims, self.h);
        Ok(StepReport {
            pressure: Some(stats),
            max_divergence: mac::max_fluid_divergence(&self.vel, &self.solid.kinds, h)?,
            kinetic_energy: self.vel.kinetic_energy(h),
            substeps: 1,
            pressure_iterations: stats.iterations,
        })
    }
}
