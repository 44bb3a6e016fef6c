//! [`BoundedFluid`]: Stable Fluids in a box with walls, open sides and
//! obstacles, velocity on the staggered MAC grid.

use super::*;

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
    shared_inputs!();

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

    /// Adds an obstacle; it must lie inside the grid.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] for a shape with non-finite or
    /// degenerate extents, and [`FluidError::OutsideGrid`] if it lies outside the grid.
    pub fn add_obstacle(&mut self, o: Obstacle) -> Result<()> {
        self.solid.add(o, self.dims, self.h)
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

    /// Adds the substances' sources, then advects them through the new
    /// velocity (paths clipped at solids when `has_solids`), diffuses and
    /// dissipates them.
    fn step_substances(&mut self, dt: f32, has_solids: bool) {
        let (dims, h) = (self.dims, self.h);
        let solids = Solids {
            kinds: self.solid.kinds.as_slice(),
            dims,
        };
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
        self.step_substances(dt, has_solids);
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
