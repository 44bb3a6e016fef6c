//! [`PeriodicFluid`]: Stable Fluids on the n-torus with the FFT solver
//! (Stam 1999, §2.3), on Stam's cell-centred grid.

use super::*;

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
            fft: Fft3::new(dims),
            vel: zero3(dims)?,
            force: zero3(dims)?,
            force_sources: Vec::new(),
            subs: Substances::default(),
        })
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
