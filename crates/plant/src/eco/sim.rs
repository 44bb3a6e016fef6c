//! The population simulation: seeding, growth, old age and self-thinning by
//! domination between intersecting circles of influence.
//!
//! Deussen et al. 1998, §4.3: every plant is a circle, its ecological
//! neighbourhood (after Firbank & Watkinson). Circles grow; when two
//! intersect, the plant of lower competitive ability is dominated and dies
//! with the probability its species gives; a plant that reaches its species'
//! maximum size is old and dies. Competitive ability is
//! `vigor × size / max size`, with vigor a randomised function of how well the
//! site's wetness (and here also light) suits the species.
//!
//! The source runs this as an open L-system whose environment resolves the
//! collisions and does not say in which order; here all collisions of a step
//! are decided at once against the state before the step, which makes the
//! result independent of order and of the number of threads. With a
//! dominated plant always dying, no two circles intersect after a step.
//! The source's growth rate and initial radius interval are not printed; they
//! are parameters here.
//!
//! Self-thinning (the source's Fig. 5): on the thinning line the circles
//! cover a constant share of the ground, so the log of the mean area falls
//! with slope −1 against the log of the density; with mass ∝ area^{3/2}
//! that is Ricklefs' −3/2 in mass. The source writes "area raised to the
//! power of −3/2"; the power is +3/2 (with −3/2 the mass slope would be
//! +3/2, mass growing with crowding). The `figures_deussen` example
//! measures both slopes.

use glam::Vec3;
use natura_core::{Progress, Seed, check};

use super::in_order;
use super::site::Site;
use super::species::Species;
use crate::error::{PlantError, Result};

/// Parameters of an ecosystem simulation.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct EcoParams {
    /// The species (at most 65 535).
    pub species: Vec<Species>,
    /// Simulation steps (the source's mountain meadow ran 25).
    pub steps: u32,
    /// Seed of every random choice.
    pub seed: Seed,
    /// Direction towards the sun, for the terrain's light.
    pub sun: Vec3,
    /// Most living plants allowed at any time (a memory guard).
    pub max_plants: usize,
}

impl Default for EcoParams {
    /// Trees, shrubs, wet shrubs and grass over 25 steps (the source's step count for its
    /// mountain meadow; the species values are our own).
    fn default() -> Self {
        Self {
            species: vec![
                Species::tree(),
                Species::default(),
                Species::wet_shrub(),
                Species::grass(),
            ],
            steps: 25,
            seed: Seed(1998),
            sun: Vec3::new(-1.0, 1.0, 1.5),
            max_plants: 20_000_000,
        }
    }
}

impl EcoParams {
    /// Checks every species and the global values.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field (a species' own errors name its field).
    pub fn validate(&self) -> Result<()> {
        check::count(
            "EcoParams::species",
            self.species.len(),
            1,
            u16::MAX as usize,
            "between 1 and 65535 species",
        )?;
        for s in &self.species {
            s.validate()?;
        }
        check::count(
            "EcoParams::steps",
            self.steps as usize,
            0,
            1 << 20,
            "at most 2^20 steps",
        )?;
        check::finite3("EcoParams::sun", self.sun.as_dvec3())?;
        if self.sun.length_squared() == 0.0 {
            return Err(PlantError::InvalidParameter {
                name: "EcoParams::sun",
                value: format!("{}", self.sun),
                reason: "must be a non-zero direction".into(),
            });
        }
        check::count(
            "EcoParams::max_plants",
            self.max_plants,
            1,
            1 << 30,
            "between 1 and 2^30",
        )?;
        Ok(())
    }
}

/// One living plant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plant {
    /// Position on the ground plane, metres.
    pub x: f32,
    /// Position on the ground plane, metres.
    pub y: f32,
    /// Radius of the circle of influence, metres.
    pub radius: f32,
    /// Vigor in `[0, 1.5]`: site suitability with random spread.
    pub vigor: f32,
    /// Unique id: step of birth, species and draw index.
    pub id: u64,
    /// Index of the species in [`EcoParams::species`].
    pub species: u16,
    /// Whether the plant was dominated in the last step and survived (it does not grow next step).
    pub dominated: bool,
}

impl Plant {
    /// Competitive ability `vigor × radius / max_radius` (Deussen et al. 1998, §4.3).
    #[inline]
    #[must_use]
    pub fn ability(&self, max_radius: f32) -> f32 {
        self.vigor * self.radius / max_radius
    }

    /// Step in which the plant was sown (0 = the initial population).
    #[must_use]
    pub fn born(&self) -> u32 {
        (self.id >> 40) as u32
    }
}

/// What one step did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Seeds that established.
    pub seeded: usize,
    /// Plants that reached their maximum size and died.
    pub old: usize,
    /// Plants dominated by a neighbour that died.
    pub thinned: usize,
    /// Dominated plants that survived.
    pub survived: usize,
    /// Living plants after the step.
    pub alive: usize,
}

/// A plant population over a terrain.
#[derive(Clone, Debug)]
pub struct Ecosystem {
    params: EcoParams,
    site: Site,
    plants: Vec<Plant>,
    step: u32,
    /// Largest maximum radius of all species: the spatial grid's half cell.
    r_max: f32,
    max_r: Vec<f32>,
}

/// Most seeds one species draws in one step: a plant's id holds the draw's
/// index in 24 bits.
pub const MAX_SEEDS_PER_SPECIES: u64 = 1 << 24;

/// Most cells of the spatial grid that finds intersecting circles (its cell
/// is twice the largest `max_radius` of the species): 2²⁶, a 256 MiB index.
pub const MAX_GRID_CELLS: u64 = 1 << 26;

/// Uniform number in `[0, 1)` from the ecosystem seed and four indices.
#[inline]
fn uniform(seed: Seed, a: u64, b: u64, c: u64, d: u64) -> f32 {
    seed.uniform(&[a as i64, b as i64, c as i64, d as i64]) as f32
}

impl Ecosystem {
    /// Analyses the terrain and sows the initial population (step 0).
    ///
    /// # Errors
    ///
    /// [`EcoParams::validate`]'s errors; [`Site::new`]'s errors for a bad field;
    /// [`PlantError::InvalidParameter`] naming `Species::max_radius` if the
    /// neighbour grid would exceed [`MAX_GRID_CELLS`], naming
    /// `Species::initial_per_ha` if a species would draw more seeds than
    /// [`MAX_SEEDS_PER_SPECIES`] or all together more than
    /// `EcoParams::max_plants` (checked before anything is allocated), and
    /// naming `EcoParams::max_plants` if the initial population exceeds it.
    pub fn new(hf: &natura_core::HeightField, params: EcoParams) -> Result<Self> {
        params.validate()?;
        let site = Site::new(hf, params.sun)?;
        Self::sown(site, params)
    }

    /// As [`Self::new`] on a site whose wetness is given ([`Site::with_wetness`]):
    /// the plants read the same map as whatever else reads `wetness` (a
    /// renderer's materials), not one computed from `hf` alone.
    ///
    /// # Errors
    ///
    /// As [`Self::new`]; [`Site::with_wetness`]'s errors for a wetness map
    /// of the wrong size or with values outside `[0, 1]`.
    pub fn with_wetness(
        hf: &natura_core::HeightField,
        wetness: natura_core::Grid2<f32>,
        params: EcoParams,
    ) -> Result<Self> {
        params.validate()?;
        let site = Site::with_wetness(hf, params.sun, wetness)?;
        Self::sown(site, params)
    }

    /// The ecosystem on `site` (built for `params.sun`, `params` validated)
    /// with its initial population sown.
    fn sown(site: Site, params: EcoParams) -> Result<Self> {
        let max_r: Vec<f32> = params.species.iter().map(|s| s.max_radius as f32).collect();
        let r_max = max_r.iter().copied().fold(0.0, f32::max);
        let mut eco = Self {
            params,
            site,
            plants: Vec::new(),
            step: 0,
            r_max,
            max_r,
        };
        eco.check_grid()?;
        eco.plants = eco.sow(0, "Species::initial_per_ha", |s| s.initial_per_ha)?;
        eco.check_size()?;
        eco.sort_by_cell();
        Ok(eco)
    }

    /// An ecosystem resumed from a saved population: `plants` as
    /// [`Self::plants`] gave them after `step` steps of a simulation with
    /// the same terrain and parameters. Stepping on from here, or
    /// instancing, gives what the original ecosystem gives, bit for bit
    /// (every draw is indexed by seed, step and plant id, not by history).
    ///
    /// # Errors
    ///
    /// [`EcoParams::validate`]'s and [`Site::new`]'s errors;
    /// [`PlantError::InvalidParameter`] naming `Ecosystem::resume` if `step`
    /// exceeds [`EcoParams::steps`], the population exceeds
    /// [`EcoParams::max_plants`], or a plant lies outside the terrain, has
    /// a non-finite or non-positive radius, a vigor outside `[0, 1.5]`, or
    /// a species index out of range; naming `Species::max_radius` if the
    /// neighbour grid would exceed [`MAX_GRID_CELLS`].
    pub fn resume(
        hf: &natura_core::HeightField,
        params: EcoParams,
        plants: Vec<Plant>,
        step: u32,
    ) -> Result<Self> {
        Self::resumed(hf, None, params, plants, step)
    }

    /// As [`Self::resume`] for an ecosystem made by [`Self::with_wetness`]
    /// with the same `wetness`.
    ///
    /// # Errors
    ///
    /// As [`Self::resume`]; [`Site::with_wetness`]'s errors.
    pub fn resume_with_wetness(
        hf: &natura_core::HeightField,
        wetness: natura_core::Grid2<f32>,
        params: EcoParams,
        plants: Vec<Plant>,
        step: u32,
    ) -> Result<Self> {
        Self::resumed(hf, Some(wetness), params, plants, step)
    }

    /// [`Self::resume`] on `wetness` if given, else on the field's own.
    fn resumed(
        hf: &natura_core::HeightField,
        wetness: Option<natura_core::Grid2<f32>>,
        params: EcoParams,
        plants: Vec<Plant>,
        step: u32,
    ) -> Result<Self> {
        params.validate()?;
        let refuse = |value: String, reason: &str| PlantError::InvalidParameter {
            name: "Ecosystem::resume",
            value,
            reason: reason.to_owned(),
        };
        if step > params.steps {
            return Err(refuse(
                format!("step {step}"),
                &format!("at most EcoParams::steps = {}", params.steps),
            ));
        }
        if plants.len() > params.max_plants {
            return Err(refuse(
                format!("{} plants", plants.len()),
                &format!("at most EcoParams::max_plants = {}", params.max_plants),
            ));
        }
        let site = match wetness {
            Some(w) => Site::with_wetness(hf, params.sun, w)?,
            None => Site::new(hf, params.sun)?,
        };
        let (ex, ey) = site.extent();
        let n = params.species.len();
        if let Some((i, p)) = plants.iter().enumerate().find(|(_, p)| {
            !((0.0..=ex).contains(&p.x)
                && (0.0..=ey).contains(&p.y)
                && p.radius.is_finite()
                && p.radius > 0.0
                && (0.0..=1.5).contains(&p.vigor)
                && usize::from(p.species) < n)
        }) {
            return Err(refuse(
                format!("plant {i}: {p:?}"),
                "plants inside the terrain, with finite positive radii, vigor in [0, 1.5] \
                 and a species of the parameters",
            ));
        }
        let max_r: Vec<f32> = params.species.iter().map(|s| s.max_radius as f32).collect();
        let r_max = max_r.iter().copied().fold(0.0, f32::max);
        let mut eco = Self {
            params,
            site,
            plants,
            step,
            r_max,
            max_r,
        };
        eco.check_grid()?;
        // Stable: a population saved in grid order keeps its order.
        eco.sort_by_cell();
        Ok(eco)
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &EcoParams {
        &self.params
    }

    /// The terrain's site maps.
    #[must_use]
    pub fn site(&self) -> &Site {
        &self.site
    }

    /// The living plants, in spatial-grid order.
    #[must_use]
    pub fn plants(&self) -> &[Plant] {
        &self.plants
    }

    /// Steps simulated so far.
    #[must_use]
    pub fn steps(&self) -> u32 {
        self.step
    }

    /// Height of the terrain under a plant, metres.
    #[must_use]
    pub fn ground(&self, p: &Plant) -> f32 {
        self.site.height(p.x, p.y)
    }

    fn check_size(&self) -> Result<()> {
        if self.plants.len() > self.params.max_plants {
            return Err(PlantError::InvalidParameter {
                name: "EcoParams::max_plants",
                value: self.params.max_plants.to_string(),
                reason: format!(
                    "the population reached {} plants at step {}",
                    self.plants.len(),
                    self.step
                ),
            });
        }
        Ok(())
    }

    /// Refuses a spatial grid (cells of twice the largest `max_radius` over
    /// the terrain's extent) of more than [`MAX_GRID_CELLS`] cells, before
    /// anything is allocated for it.
    fn check_grid(&self) -> Result<()> {
        let (ex, ey) = self.site.extent();
        let c = f64::from(self.cell());
        let cells = (f64::from(ex) / c + 1.0) * (f64::from(ey) / c + 1.0);
        if cells > MAX_GRID_CELLS as f64 {
            return Err(PlantError::InvalidParameter {
                name: "Species::max_radius",
                value: self.r_max.to_string(),
                reason: format!(
                    "the largest max_radius sets the neighbour grid's cell (2 × max_radius); \
                     over this {ex} m × {ey} m terrain it would need {cells:.3e} cells, at most \
                     {MAX_GRID_CELLS}: the largest max_radius must be at least {:.3e} m here",
                    (f64::from(ex) * f64::from(ey) / MAX_GRID_CELLS as f64).sqrt() / 2.0
                ),
            });
        }
        Ok(())
    }

    /// Seeds each species draws in step `step` at `rate(species)` per
    /// hectare (`name` is that rate's parameter), checked before anything is
    /// allocated for them: a species draws at most [`MAX_SEEDS_PER_SPECIES`]
    /// seeds per step, and all species together at most
    /// [`EcoParams::max_plants`] and no more than the memory cap
    /// ([`natura_core::MAX_GRID_BYTES`]) holds.
    fn sow_counts(
        &self,
        step: u32,
        name: &'static str,
        rate: &impl Fn(&Species) -> f64,
    ) -> Result<Vec<u64>> {
        let (ex, ey) = self.site.extent();
        let ha = f64::from(ex) * f64::from(ey) / 1e4;
        let seed = self.params.seed.derive("eco.sow");
        let per_draw = std::mem::size_of::<Option<Plant>>() as f64;
        let all =
            (self.params.max_plants as f64).min(natura_core::MAX_GRID_BYTES as f64 / per_draw);
        let one = all.min(MAX_SEEDS_PER_SPECIES as f64);
        let mut total = 0.0;
        let mut counts = Vec::with_capacity(self.params.species.len());
        for (si, sp) in self.params.species.iter().enumerate() {
            let expected = rate(sp) * ha;
            total += expected;
            if !(expected <= one && total <= all) {
                return Err(PlantError::InvalidParameter {
                    name,
                    value: format!("{} (species \"{}\")", rate(sp), sp.name),
                    reason: format!(
                        "over this terrain's {ha:.4} ha the species would draw {expected:.3e} \
                         seeds in one step ({total:.3e} with the species before it); at most \
                         {one:.0} per species and {all:.0} in all (EcoParams::max_plants = {} \
                         and the memory cap), so at most {:.3e} per hectare here",
                        self.params.max_plants,
                        one / ha
                    ),
                });
            }
            let whole = expected.floor();
            let extra = f64::from(uniform(seed, u64::from(step), si as u64, u64::MAX, 0));
            counts.push(whole as u64 + u64::from(extra < expected - whole));
        }
        Ok(counts)
    }

    /// Seeds of every species for step `step`, `rate(species)` per hectare
    /// (`name` is that rate's parameter, for errors).
    ///
    /// # Errors
    ///
    /// As [`Self::sow_counts`].
    fn sow(
        &self,
        step: u32,
        name: &'static str,
        rate: impl Fn(&Species) -> f64,
    ) -> Result<Vec<Plant>> {
        let counts = self.sow_counts(step, name, &rate)?;
        let (ex, ey) = self.site.extent();
        let seed = self.params.seed.derive("eco.sow");
        let mut out = Vec::new();
        for ((si, sp), &n) in self.params.species.iter().enumerate().zip(&counts) {
            let site = &self.site;
            let born = in_order::map(n as usize, |k| {
                let k = k as u64;
                let (st, s) = (u64::from(step), si as u64);
                let x = uniform(seed, st, s, k, 1) * ex;
                let y = uniform(seed, st, s, k, 2) * ey;
                let (i, j) = site.nearest(x, y);
                if !sp.admits(site.altitude[(i, j)], site.slope[(i, j)]) {
                    return None;
                }
                let suit = sp.suitability(site.wetness[(i, j)], site.light[(i, j)]);
                if uniform(seed, st, s, k, 3) >= suit {
                    return None;
                }
                let spread = sp.vigor_spread as f32;
                let vigor = suit * (1.0 + spread * (uniform(seed, st, s, k, 4) - 0.5));
                let r0 =
                    sp.r0_min as f32 + (sp.r0_max - sp.r0_min) as f32 * uniform(seed, st, s, k, 5);
                Some(Plant {
                    x,
                    y,
                    radius: r0,
                    vigor,
                    id: (st << 40) | (s << 24) | k,
                    species: si as u16,
                    dominated: false,
                })
            });
            out.extend(born.into_iter().flatten());
        }
        Ok(out)
    }

    /// Cell size of the spatial grid: twice the largest radius, so intersecting circles
    /// always lie in neighbouring cells.
    fn cell(&self) -> f32 {
        2.0 * self.r_max
    }

    fn grid_dims(&self) -> (usize, usize) {
        let (ex, ey) = self.site.extent();
        let c = self.cell();
        ((ex / c) as usize + 1, (ey / c) as usize + 1)
    }

    fn cell_of(&self, p: &Plant, gx: usize, gy: usize) -> usize {
        let c = self.cell();
        let i = ((p.x / c) as usize).min(gx - 1);
        let j = ((p.y / c) as usize).min(gy - 1);
        j * gx + i
    }

    /// Sorts the plants by grid cell (stable) and returns the cell start offsets.
    fn sort_by_cell(&mut self) -> Vec<u32> {
        let (gx, gy) = self.grid_dims();
        let keys = in_order::map(self.plants.len(), |i| {
            self.cell_of(&self.plants[i], gx, gy) as u32
        });
        let mut start = vec![0u32; gx * gy + 1];
        for &k in &keys {
            start[k as usize + 1] += 1;
        }
        for c in 0..gx * gy {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut sorted = vec![self.plants.first().copied().unwrap_or(EMPTY); self.plants.len()];
        for (p, &k) in self.plants.iter().zip(&keys) {
            sorted[fill[k as usize] as usize] = *p;
            fill[k as usize] += 1;
        }
        self.plants = sorted;
        start
    }

    /// Whether plant `i` is dominated by an intersecting neighbour (plants sorted by cell).
    fn is_dominated(&self, i: usize, start: &[u32], gx: usize, gy: usize) -> bool {
        let p = &self.plants[i];
        let a = p.ability(self.max_r[p.species as usize]);
        let c = self.cell_of(p, gx, gy);
        let (ci, cj) = (c % gx, c / gx);
        for nj in cj.saturating_sub(1)..=(cj + 1).min(gy - 1) {
            let lo = start[nj * gx + ci.saturating_sub(1)] as usize;
            let hi = start[nj * gx + (ci + 1).min(gx - 1) + 1] as usize;
            for (k, q) in self.plants[lo..hi].iter().enumerate() {
                if lo + k == i {
                    continue;
                }
                let (dx, dy) = (q.x - p.x, q.y - p.y);
                let rr = q.radius + p.radius;
                if dx * dx + dy * dy < rr * rr {
                    let b = q.ability(self.max_r[q.species as usize]);
                    if b > a || (b == a && q.id < p.id) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// One step: growth, old age, seeding, then domination.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming `Species::seeds_per_ha` if
    /// the step's seeds would exceed the bounds [`Ecosystem::new`] states
    /// for the initial ones, and naming `EcoParams::max_plants` if the
    /// population exceeds it.
    pub fn step(&mut self) -> Result<StepStats> {
        self.step += 1;
        let mut stats = StepStats::default();
        // Growth; plants dominated last step and still alive do not grow.
        let species = &self.params.species;
        in_order::for_each_mut(&mut self.plants, |_, p| {
            if !p.dominated {
                p.radius += (species[p.species as usize].growth as f32) * p.vigor;
            }
            p.dominated = false;
        });
        let before = self.plants.len();
        let max_r = &self.max_r;
        in_order::retain(&mut self.plants, |_, p| {
            p.radius < max_r[p.species as usize]
        });
        stats.old = before - self.plants.len();
        let born = self.sow(self.step, "Species::seeds_per_ha", |s| s.seeds_per_ha)?;
        stats.seeded = born.len();
        self.plants.extend(born);
        self.check_size()?;
        let start = self.sort_by_cell();
        let (gx, gy) = self.grid_dims();
        let species = &self.params.species;
        let seed = self.params.seed.derive("eco.domination");
        let st = u64::from(self.step);
        let fate = in_order::map(self.plants.len(), |i| {
            if !self.is_dominated(i, &start, gx, gy) {
                return 0u8;
            }
            let p = &self.plants[i];
            let survive = species[p.species as usize].survive_domination as f32;
            if uniform(seed, st, p.id, 0, 0) < survive {
                1
            } else {
                2
            }
        });
        for &f in &fate {
            stats.survived += usize::from(f == 1);
            stats.thinned += usize::from(f == 2);
        }
        in_order::for_each_mut(&mut self.plants, |i, p| p.dominated = fate[i] == 1);
        in_order::retain(&mut self.plants, |i, _| fate[i] != 2);
        stats.alive = self.plants.len();
        Ok(stats)
    }

    /// Runs the remaining steps of [`EcoParams::steps`], reporting progress.
    ///
    /// # Errors
    ///
    /// As [`Ecosystem::step`].
    pub fn run(&mut self, progress: &dyn Progress) -> Result<Vec<StepStats>> {
        let total = self.params.steps;
        let mut out = Vec::new();
        progress.start("ecosystem", u64::from(total.saturating_sub(self.step)));
        while self.step < total {
            out.push(self.step()?);
            progress.advance(1);
        }
        progress.finish();
        Ok(out)
    }
}

const EMPTY: Plant = Plant {
    x: 0.0,
    y: 0.0,
    radius: 0.0,
    vigor: 0.0,
    id: 0,
    species: 0,
    dominated: false,
};
