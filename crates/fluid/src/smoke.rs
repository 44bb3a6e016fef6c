//! Fedkiw, Stam & Jensen, *Visual Simulation of Smoke* (SIGGRAPH 2001;
//! Fedkiw et al. 2001), 2-D and 3-D.
//!
//! Inviscid incompressible Euler with unit density (Fedkiw et al. 2001, §2) on the
//! staggered MAC grid (Fedkiw et al. 2001, App. A). One step (Fedkiw et al. 2001, §4):
//!
//! 1. forces at cell centres — buoyancy `f = −αρ z + β(T − T_amb) z` (eq. 8,
//!    Fedkiw et al. 2001, §2), vorticity confinement `f = ε h (N × ω)` (Fedkiw et al. 2001, §3, eq. 11) and
//!    user forces — multiplied by `dt` and averaged to faces (Fedkiw et al. 2001, App. A);
//! 2. semi-Lagrangian advection of the velocity from face midpoints, paths
//!    clipped at occupied voxels (Fedkiw et al. 2001, §4), linear or monotone cubic
//!    (App. B with the a3 and overshoot errata fixed, see [`crate::interp`]);
//! 3. projection with Neumann conditions at occupied voxels (Fedkiw et al. 2001, §4),
//!    solved by multigrid- or MIC(0)-preconditioned CG to a stated relative
//!    residual (the paper stops after "about 20 iterations");
//! 4. advection of temperature and density with the new velocity (Fedkiw et al. 2001, §4);
//! 5. sources and object rules: occupied voxels take the object's
//!    temperature, density 0 inside and, on boundary voxels, the density of
//!    the unoccupied neighbours (Fedkiw et al. 2001, §4).
//!
//! The parameters α, β, T_amb and ε have no values in the paper;
//! the defaults are library choices documented on [`SmokeParams`].

use glam::Vec3;
use natura_core::Grid3;

use crate::advect::{self, Advection, Solids, VelSampler};
use crate::error::{self, FluidError, Result};
use crate::grid::{self, Boundaries, CellKind, Dims, MacVelocity, StepReport};
use crate::mac::{self, Projector};
use crate::pressure::{SolveStats, SolverParams};
use crate::shape::{Obstacle, Obstacles, Shape, solid_face_velocity, voxelise};

/// Parameters of the smoke model.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SmokeParams {
    /// α: downward acceleration per unit smoke density (m/s² per unit), eq. 8.
    /// Default 0.05.
    pub alpha: f32,
    /// β: upward acceleration per kelvin above ambient (m/s²/K), eq. 8.
    /// Default `9.81 / 293.15`, the Boussinesq value for air.
    pub beta: f32,
    /// Ambient temperature `T_amb` (K). Default 293.15.
    pub ambient_temperature: f32,
    /// Vorticity confinement strength ε (1/s), eq. 11. Default 2; 0 disables it.
    pub epsilon: f32,
    /// Advection of velocity, temperature and density.
    pub advection: Advection,
    /// Pressure solver and tolerance.
    pub solver: SolverParams,
    /// Domain sides (default: walls with an open ceiling).
    pub bounds: Boundaries,
}

impl Default for SmokeParams {
    fn default() -> Self {
        Self {
            alpha: 0.05,
            beta: 9.81 / 293.15,
            ambient_temperature: 293.15,
            epsilon: 2.0,
            advection: Advection::default(),
            solver: SolverParams::default(),
            bounds: Boundaries::open_top(),
        }
    }
}

impl SmokeParams {
    /// Checks every parameter (finite; ε, α, β ≥ 0; ambient temperature > 0).
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        error::non_negative("alpha", f64::from(self.alpha))?;
        error::non_negative("beta", f64::from(self.beta))?;
        error::positive("ambient_temperature", f64::from(self.ambient_temperature))?;
        error::non_negative("epsilon", f64::from(self.epsilon))?;
        self.solver.validate()
    }
}

/// A region where smoke is placed each step ("place densities and heat
/// sources", Fedkiw et al. 2001, §6): inside `shape` density and temperature are raised to
/// at least the given values, and with `velocity` the free faces inside are
/// set to it (an inflow jet).
///
/// With the `serde` feature `velocity` may be left out (no inflow).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct SmokeSource {
    /// The region.
    pub shape: Shape,
    /// Smoke density placed.
    pub density: f32,
    /// Temperature placed (K).
    pub temperature: f32,
    /// Optional inflow velocity (m/s).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub velocity: Option<Vec3>,
}

/// The smoke solver.
#[derive(Clone, Debug)]
pub struct Smoke {
    dims: Dims,
    h: f32,
    params: SmokeParams,
    vel: MacVelocity,
    density: Grid3<f32>,
    temperature: Grid3<f32>,
    solid: Obstacles,
    sources: Vec<SmokeSource>,
    source_cells: Vec<Vec<usize>>,
    force: [Grid3<f32>; 3],
    projector: Projector,
    time: f64,
}

impl Smoke {
    /// Still air at ambient temperature on `dims` cells of size `h` metres.
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`FluidError::InvalidParameter`]
    /// for a cell size that is not finite and positive, and [`FluidError::Core`] if
    /// the grids cannot be allocated.
    pub fn new(dims: Dims, h: f32, params: SmokeParams) -> Result<Self> {
        error::positive("cell size h", f64::from(h))?;
        params.validate()?;
        Ok(Self {
            dims,
            h,
            params,
            vel: MacVelocity::zeros(dims)?,
            density: dims.zeros()?,
            temperature: Grid3::new(dims.nx, dims.ny, dims.nz, params.ambient_temperature)?,
            solid: Obstacles::new(dims)?,
            sources: Vec::new(),
            source_cells: Vec::new(),
            force: [dims.zeros()?, dims.zeros()?, dims.zeros()?],
            projector: Projector::new(),
            time: 0.0,
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

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &SmokeParams {
        &self.params
    }

    /// Simulated time (s).
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Adds an obstacle (must lie inside the grid); its cells become occupied.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] for a shape with non-finite or
    /// degenerate extents, and [`FluidError::OutsideGrid`] if it lies outside the grid.
    pub fn add_obstacle(&mut self, o: Obstacle) -> Result<()> {
        self.solid.add(o, self.dims, self.h)
    }

    /// The obstacles at the current time.
    #[must_use]
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.solid.list
    }

    /// Adds a smoke source (must lie inside the grid, finite values).
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] for non-finite amounts or shapes, and
    /// [`FluidError::OutsideGrid`] if the source lies outside the grid.
    pub fn add_source(&mut self, s: SmokeSource) -> Result<()> {
        s.shape.check_inside(self.dims, self.h, "smoke source")?;
        error::non_negative("source density", f64::from(s.density))?;
        error::positive("source temperature", f64::from(s.temperature))?;
        if let Some(v) = s.velocity
            && !v.is_finite()
        {
            return Err(FluidError::InvalidParameter {
                name: "source velocity",
                value: format!("{v:?}"),
                reason: "must be finite",
            });
        }
        let mask = voxelise(&[Obstacle::fixed(s.shape)], self.dims, self.h);
        self.source_cells.push(
            mask.iter()
                .enumerate()
                .filter(|(_, m)| **m != u16::MAX)
                .map(|(c, _)| c)
                .collect(),
        );
        self.sources.push(s);
        Ok(())
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

    /// Smoke density ρ at cell centres.
    #[must_use]
    pub fn density(&self) -> &Grid3<f32> {
        &self.density
    }

    /// Smoke density, mutably (place smoke by hand).
    pub fn density_mut(&mut self) -> &mut Grid3<f32> {
        &mut self.density
    }

    /// Temperature T (K) at cell centres.
    #[must_use]
    pub fn temperature(&self) -> &Grid3<f32> {
        &self.temperature
    }

    /// Temperature, mutably.
    pub fn temperature_mut(&mut self) -> &mut Grid3<f32> {
        &mut self.temperature
    }

    /// Occupied (solid) and fluid cells.
    #[must_use]
    pub fn cell_kinds(&self) -> &Grid3<CellKind> {
        &self.solid.kinds
    }

    /// User forces at cell centres (m/s²), cleared after each step.
    pub fn force_mut(&mut self) -> &mut [Grid3<f32>; 3] {
        &mut self.force
    }

    /// Buoyancy (eq. 8) at cell centres: only the z component is non-zero.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::Core`] if the grids cannot be allocated.
    pub fn buoyancy(&self) -> Result<[Grid3<f32>; 3]> {
        let d = self.dims;
        let mut f = [d.zeros()?, d.zeros()?, d.zeros()?];
        let (a, b, t0) = (
            self.params.alpha,
            self.params.beta,
            self.params.ambient_temperature,
        );
        for ((o, &rho), &t) in f[2]
            .as_mut_slice()
            .iter_mut()
            .zip(self.density.as_slice())
            .zip(self.temperature.as_slice())
        {
            *o = -a * rho + b * (t - t0);
        }
        Ok(f)
    }

    /// The confinement force (eq. 11) of the current velocity.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] for a negative or non-finite `epsilon`,
    /// and [`FluidError::Core`] if the grids cannot be allocated.
    pub fn confinement_force(&self) -> Result<[Grid3<f32>; 3]> {
        mac::confinement_force(&self.vel, self.h, self.params.epsilon)
    }

    /// Vorticity at cell centres (App. A).
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::Core`] if the grids cannot be allocated.
    pub fn vorticity(&self) -> Result<[Grid3<f32>; 3]> {
        mac::vorticity(&self.vel, self.h)
    }

    /// MAC divergence at cell centres.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::Core`] if the grid cannot be allocated.
    pub fn divergence(&self) -> Result<Grid3<f32>> {
        mac::divergence(&self.vel, self.h)
    }

    /// Pressure of the last projection (m²/s², unit density).
    #[must_use]
    pub fn pressure(&self) -> Option<Grid3<f32>> {
        self.projector.pressure(self.dims)
    }

    /// Projects the current velocity, e.g. after setting it by hand.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::NonFinite`] if the velocity or the pressure is not
    /// finite, and [`FluidError::InvalidParameter`] for a non-positive `dt`.
    pub fn project(&mut self, dt: f32) -> Result<SolveStats> {
        self.enforce();
        self.projector.project(
            &mut self.vel,
            &self.solid.kinds,
            &self.params.bounds,
            self.h,
            dt,
            &self.params.solver,
        )
    }

    fn enforce(&mut self) {
        let sv = solid_face_velocity(self.dims, self.h, &self.solid.owner, &self.solid.list);
        mac::enforce_solids(
            &mut self.vel,
            self.solid.kinds.as_slice(),
            &self.params.bounds,
            &sv,
        );
    }

    /// Advances by `dt` seconds (Fedkiw et al. 2001, §4).
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
        // 1. Forces: user + buoyancy + confinement, centres → faces.
        let mut f = self.buoyancy()?;
        if self.params.epsilon > 0.0 {
            let c = self.confinement_force()?;
            for a in 0..3 {
                for (o, &v) in f[a].as_mut_slice().iter_mut().zip(c[a].as_slice()) {
                    *o += v;
                }
            }
        }
        for a in 0..3 {
            for (o, &v) in f[a].as_mut_slice().iter_mut().zip(self.force[a].as_slice()) {
                *o += v;
            }
        }
        mac::add_centre_forces(&mut self.vel, &f, dt, self.solid.kinds.as_slice(), &bounds);
        self.vel.check_finite("forces")?;
        // 2. Advect velocity from face midpoints, clipped at solids.
        let kinds_now = self.solid.kinds.as_slice().to_vec();
        let solids = Solids {
            kinds: &kinds_now,
            dims,
        };
        let clip = (!self.solid.list.is_empty()).then_some(&solids);
        let old = self.vel.clone();
        {
            let vs = VelSampler::mac(&old);
            for a in 0..3 {
                if dims.active(a) {
                    advect::advect(
                        self.vel.comp_mut(a).as_mut_slice(),
                        &advect::face_sampler(old.comp(a), a),
                        &vs,
                        dt / h,
                        &self.params.advection,
                        clip,
                    );
                }
            }
        }
        self.vel.check_finite("advection")?;
        // Source jets set their faces before the projection.
        self.apply_source_velocity();
        // 3. Project.
        self.enforce();
        let stats = self.projector.project(
            &mut self.vel,
            &self.solid.kinds,
            &bounds,
            h,
            dt,
            &self.params.solver,
        )?;
        self.vel.check_finite("projection")?;
        // 4. Advect T and ρ with the new velocity.
        // Both share the cell-centred geometry: each path is traced once.
        let vs = VelSampler::mac(&self.vel);
        let (t0, d0) = (self.temperature.clone(), self.density.clone());
        advect::advect_many(
            &mut [self.temperature.as_mut_slice(), self.density.as_mut_slice()],
            &[
                advect::centre_sampler(&t0, false),
                advect::centre_sampler(&d0, false),
            ],
            &vs,
            dt / h,
            &self.params.advection,
            clip,
        );
        grid::check_grid(&self.temperature, "temperature", "scalar advection")?;
        grid::check_grid(&self.density, "density", "scalar advection")?;
        // 5. Sources and object rules.
        for (s, cells) in self.sources.iter().zip(&self.source_cells) {
            for &c in cells {
                let d = &mut self.density.as_mut_slice()[c];
                *d = d.max(s.density);
                let t = &mut self.temperature.as_mut_slice()[c];
                *t = t.max(s.temperature);
            }
        }
        self.apply_object_rules();
        self.time += f64::from(dt);
        if self.solid.advance(dt, self.dims, self.h) {
            self.apply_object_rules();
        }
        self.force
            .iter_mut()
            .for_each(|g| g.as_mut_slice().fill(0.0));
        Ok(StepReport {
            pressure: Some(stats),
            max_divergence: mac::max_fluid_divergence(&self.vel, &self.solid.kinds, h)?,
            kinetic_energy: self.vel.kinetic_energy(h),
            substeps: 1,
            pressure_iterations: stats.iterations,
        })
    }

    fn apply_source_velocity(&mut self) {
        let d = self.dims;
        for (s, cells) in self.sources.iter().zip(&self.source_cells) {
            let Some(v) = s.velocity else { continue };
            for &c in cells {
                let ijk = d.ijk(c);
                for a in 0..3 {
                    if !d.active(a) {
                        continue;
                    }
                    let mut hi = ijk;
                    hi[a] += 1;
                    for f in [ijk, hi] {
                        if !mac::face_fixed(
                            d,
                            self.solid.kinds.as_slice(),
                            &self.params.bounds,
                            a,
                            f,
                        ) {
                            self.vel.comp_mut(a)[(f[0], f[1], f[2])] = v[a];
                        }
                    }
                }
            }
        }
    }

    /// Occupied voxels: object temperature, zero density inside, and on
    /// boundary voxels the mean density of their unoccupied neighbours (Fedkiw et al. 2001, §4).
    fn apply_object_rules(&mut self) {
        if self.solid.list.is_empty() {
            return;
        }
        let d = self.dims;
        let n = d.n();
        let rho = self.density.clone();
        for c in 0..d.cells() {
            let o = self.solid.owner[c];
            if o == u16::MAX {
                continue;
            }
            if let Some(t) = self.solid.list[usize::from(o)].temperature {
                self.temperature.as_mut_slice()[c] = t;
            }
            let ijk = d.ijk(c);
            let mut sum = 0.0;
            let mut cnt = 0;
            for a in 0..3 {
                for e in [-1i64, 1] {
                    let q = ijk[a] as i64 + e;
                    if n[a] == 1 || q < 0 || q >= n[a] as i64 {
                        continue;
                    }
                    let mut nb = ijk;
                    nb[a] = q as usize;
                    let ni = d.idx(nb[0], nb[1], nb[2]);
                    if self.solid.owner[ni] == u16::MAX {
                        sum += rho.as_slice()[ni];
                        cnt += 1;
                    }
                }
            }
            self.density.as_mut_slice()[c] = if cnt > 0 { sum / cnt as f32 } else { 0.0 };
        }
    }
}
