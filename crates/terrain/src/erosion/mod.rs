//! Erosion: the second pass over a stored height field that carves drainage
//! networks, talus slopes and rounded hills (Musgrave et al. 1989, §2.2, Musgrave 1993, §2.4).
//!
//! | model | module | source |
//! |---|---|---|
//! | hydraulic (fluvial), corrected and mass-conserving | [`hydraulic`] | Musgrave et al. 1989, §4.1, Musgrave 1993, §2.4.1 |
//! | thermal weathering with a talus angle | [`thermal`] | Musgrave et al. 1989, §4.2, Musgrave 1993, §2.4.2 |
//! | diffusive creep | [`diffusion`] | Musgrave 1993, §2.4.3 |
//! | virtual-pipe shallow water | [`pipe`] | Mei et al. 2007, §3 |
//! | particle (droplet) | [`droplet`] | Beyer 2015 |
//! | stream power with uplift | [`stream_power`] | Braun & Willett 2013 |
//!
//! Every model is a struct built from its `Params` (validated) and the field's
//! size, holding its state (water, sediment, …) and scratch buffers, with a
//! `step` and a `run(…, &dyn Progress)`. Grid models update synchronously
//! (Jacobi, double-buffered, gather form), so results are bit-identical on any
//! number of threads. An optional [`Erodibility`] map (e.g. rock strata from
//! [`Erodibility::strata`]) scales how easily each cell erodes (Musgrave 1993, §2.4.4).

/// A grid model's `run` and `step`, written once: both check the height
/// field against the model's size (`nx`, `ny` fields) and then call the
/// model's `step_unchecked`; `run` reports each step to `progress`.
/// Arguments: the method's name in errors, its progress label, and the
/// rustdoc summary of one step.
macro_rules! stepped_model {
    ($method:literal, $label:literal, $step_doc:literal) => {
        /// Runs `steps` steps, reporting each to `progress`.
        ///
        /// # Errors
        ///
        /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if `hf` is not the size the model was
        /// built for, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
        /// naming `height` for a NaN, infinite or out-of-range height.
        pub fn run(
            &mut self,
            hf: &mut HeightField,
            steps: u32,
            progress: &dyn natura_core::Progress,
        ) -> Result<()> {
            let size = (self.nx, self.ny);
            $crate::erosion::run_steps($method, $label, hf, size, steps, progress, |hf| {
                self.step_unchecked(hf);
            })
        }

        #[doc = $step_doc]
        ///
        /// # Errors
        ///
        /// As [`run`](Self::run).
        pub fn step(&mut self, hf: &mut HeightField) -> Result<()> {
            $crate::erosion::check_field($method, hf, self.nx, self.ny)?;
            self.step_unchecked(hf);
            Ok(())
        }
    };
}

pub mod diffusion;
pub mod droplet;
pub mod hydraulic;
pub mod pipe;
pub mod stream_power;
pub mod thermal;

use natura_core::{Grid2, HeightField, Progress};

use crate::error::{Result, TerrainError, check_grid, invalid, min_size, same_size};

pub use diffusion::{Diffusion, DiffusionParams};
pub use droplet::{DropletErosion, DropletParams};
pub use hydraulic::{MusgraveHydraulic, MusgraveParams, RainLaw};
pub use pipe::{PipeModel, PipeParams, SedimentTransport};
pub use stream_power::{Depressions, StreamPower, StreamPowerParams};
pub use thermal::{Thermal, ThermalParams};

/// Which neighbours a grid cell exchanges material with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Neighbourhood {
    /// The 4 axial neighbours (distance 1 cell).
    Four,
    /// The 8 axial and diagonal neighbours (distances 1 and √2 cells).
    Eight,
}

impl Neighbourhood {
    /// Number of neighbours.
    #[must_use]
    pub fn count(self) -> usize {
        match self {
            Neighbourhood::Four => 4,
            Neighbourhood::Eight => 8,
        }
    }

    /// `(dx, dy, distance in cells)` of each neighbour.
    #[must_use]
    pub fn offsets(self) -> &'static [(i32, i32, f32)] {
        const D: f32 = std::f32::consts::SQRT_2;
        match self {
            Neighbourhood::Four => &[(-1, 0, 1.0), (1, 0, 1.0), (0, -1, 1.0), (0, 1, 1.0)],
            Neighbourhood::Eight => &[
                (-1, 0, 1.0),
                (1, 0, 1.0),
                (0, -1, 1.0),
                (0, 1, 1.0),
                (-1, -1, D),
                (1, -1, D),
                (-1, 1, D),
                (1, 1, D),
            ],
        }
    }
}

/// What lies beyond the edge of the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Edges {
    /// Nothing: no exchange across the edge (material is conserved).
    Closed,
    /// The grid wraps around (a torus; material is conserved).
    Periodic,
    /// A sink below everything: water and sediment that flow off the grid
    /// leave the simulation and are counted as outflow (hydraulic models only).
    Open,
}

impl Edges {
    /// The neighbour of `(x, y)` at offset `(dx, dy)`: `Some(index)` inside (or
    /// wrapped), `None` across a closed or open edge.
    #[inline]
    pub(crate) fn resolve(
        self,
        x: usize,
        y: usize,
        dx: i32,
        dy: i32,
        nx: usize,
        ny: usize,
    ) -> Option<usize> {
        let (mut i, mut j) = (x as i64 + i64::from(dx), y as i64 + i64::from(dy));
        let inside = i >= 0 && j >= 0 && i < nx as i64 && j < ny as i64;
        if inside {
            return Some(j as usize * nx + i as usize);
        }
        match self {
            Edges::Periodic => {
                i = i.rem_euclid(nx as i64);
                j = j.rem_euclid(ny as i64);
                Some(j as usize * nx + i as usize)
            }
            Edges::Closed | Edges::Open => None,
        }
    }
}

/// A per-cell erodibility multiplier (≥ 0, finite): 1 is the model's nominal
/// rate, 0 unerodible rock, 2 twice as soft. Models multiply their rate
/// constants (thermal `talus_rate`, hydraulic softness, stream-power `K`,
/// droplet erosion) by it — the "hardness map" of Musgrave 1993, §2.4.4.
#[derive(Clone, Debug, PartialEq)]
pub struct Erodibility {
    map: Grid2<f32>,
    max: f32,
}

impl Erodibility {
    /// Wraps a grid of multipliers; refuses NaN, infinite or negative values (naming the cell).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::NonFinite`] or [`TerrainError::InvalidParameter`]
    /// naming the first cell whose multiplier is NaN, infinite or negative.
    pub fn new(map: Grid2<f32>) -> Result<Self> {
        check_grid("erodibility", &map)?;
        if let Some((x, y, &v)) = map.find(|&v| v < 0.0) {
            return Err(invalid(
                "erodibility",
                format!("{v} at cell ({x}, {y})"),
                "must be >= 0",
            ));
        }
        let max = map.max();
        Ok(Self { map, max })
    }

    /// Rock strata (Musgrave 1998, Musgrave 1993, §2.4.4): horizontal beds `bed_m` metres thick
    /// alternating between `soft` and `hard` multipliers with a smooth
    /// transition, indexed by the cell's altitude in `hf` plus an optional
    /// perturbation field (metres, e.g. fBm) that warps the beds.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`] for a non-positive or non-finite
    /// bed thickness or a negative or non-finite hardness,
    /// [`TerrainError::SizeMismatch`] or [`TerrainError::NonFinite`] for a warp grid
    /// of the wrong size or with a NaN, and [`TerrainError::Core`] if the map
    /// cannot be allocated.
    pub fn strata(
        hf: &HeightField,
        bed_m: f32,
        soft: f32,
        hard: f32,
        warp: Option<&Grid2<f32>>,
    ) -> Result<Self> {
        crate::error::positive("strata bed_m", f64::from(bed_m))?;
        crate::error::non_negative("strata soft", f64::from(soft))?;
        crate::error::non_negative("strata hard", f64::from(hard))?;
        if let Some(w) = warp {
            same_size("strata warp", w, hf.nx(), hf.ny())?;
            check_grid("strata warp", w)?;
        }
        let h = hf.heights();
        let map = Grid2::from_fn(hf.nx(), hf.ny(), |i, j| {
            let z = h[(i, j)] + warp.map_or(0.0, |w| w[(i, j)]);
            let phase = (z / bed_m).rem_euclid(1.0);
            // Smooth periodic blend: hard in the middle of each bed, soft at its boundaries.
            let t = 0.5 - 0.5 * (std::f32::consts::TAU * phase).cos();
            soft + (hard - soft) * t
        })?;
        Self::new(map)
    }

    /// The multipliers.
    #[must_use]
    pub fn map(&self) -> &Grid2<f32> {
        &self.map
    }

    /// The largest multiplier (used in stability limits).
    #[must_use]
    pub fn max(&self) -> f32 {
        self.max
    }
}

/// Checks an explicit model's per-neighbour rate: in `(0, 1 / neighbours]`,
/// the stability limit of moving material to every neighbour at once.
pub(crate) fn check_neighbour_rate(
    name: &'static str,
    rate: f64,
    neighbourhood: Neighbourhood,
    why: &str,
) -> Result<()> {
    let limit = 1.0 / neighbourhood.count() as f64;
    if rate > 0.0 && rate <= limit {
        Ok(())
    } else {
        Err(invalid(
            name,
            rate,
            format!("must lie in (0, {limit}] (1 / neighbours, {why})"),
        ))
    }
}

/// Refuses open edges for a model that conserves material (`what` names it).
pub(crate) fn check_conserving_edges(name: &'static str, edges: Edges, what: &str) -> Result<()> {
    if edges == Edges::Open {
        Err(invalid(
            name,
            "Open",
            format!("{what} conserves material: use Closed or Periodic"),
        ))
    } else {
        Ok(())
    }
}

/// Checks a height field for use by a grid model of size `(nx, ny)`.
pub(crate) fn check_field(
    method: &'static str,
    hf: &HeightField,
    nx: usize,
    ny: usize,
) -> Result<()> {
    if (hf.nx(), hf.ny()) != (nx, ny) {
        return Err(TerrainError::SizeMismatch {
            what: "height field",
            expected: format!("{nx} × {ny} (the size the model was built for)"),
            actual: format!("{} × {}", hf.nx(), hf.ny()),
        });
    }
    let _ = method;
    check_heights(hf)
}

/// Largest height magnitude the erosion models accept, metres (1000 km; f32
/// still resolves 6 cm there). Beyond it their squared slopes and fluxes leave
/// f32's range and the result would be NaN.
pub const MAX_HEIGHT: f32 = 1e6;

/// Checks every height is finite and within ±[`MAX_HEIGHT`], naming the first
/// one that is not.
pub(crate) fn check_heights(hf: &HeightField) -> Result<()> {
    match hf
        .heights()
        .find(|v| !v.is_finite() || v.abs() > MAX_HEIGHT)
    {
        None => Ok(()),
        Some((x, y, &value)) if !value.is_finite() => {
            Err(natura_core::CoreError::NonFinite { x, y, value }.into())
        }
        Some((x, y, &value)) => Err(TerrainError::InvalidParameter {
            name: "height",
            value: format!("{value} at ({x}, {y})"),
            reason: "erosion needs heights within ±1e6 m".into(),
        }),
    }
}

/// Checks the size of a new grid model: at least 3 × 3 samples.
pub(crate) fn check_model_size(method: &'static str, hf: &HeightField) -> Result<()> {
    min_size(method, hf.nx(), hf.ny(), 3, 3)?;
    check_heights(hf)
}

/// A model's `run`: checks `hf` against the model's size `(nx, ny)`, then
/// takes `steps` steps, reporting each to `progress` under `label`.
pub(crate) fn run_steps(
    method: &'static str,
    label: &'static str,
    hf: &mut HeightField,
    (nx, ny): (usize, usize),
    steps: u32,
    progress: &dyn Progress,
    mut step: impl FnMut(&mut HeightField),
) -> Result<()> {
    check_field(method, hf, nx, ny)?;
    progress.start(label, u64::from(steps));
    for _ in 0..steps {
        step(hf);
        progress.advance(1);
    }
    progress.finish();
    Ok(())
}

/// Checks an optional erodibility map against the field size.
pub(crate) fn check_erodibility(e: Option<&Erodibility>, nx: usize, ny: usize) -> Result<()> {
    if let Some(e) = e {
        same_size("erodibility map", &e.map, nx, ny)?;
    }
    Ok(())
}

/// Checks an erodibility map that scales a dissolving constant `k_s`
/// (a fraction per step): the field's size, and `max × k_s ≤ 1`.
pub(crate) fn check_softness(e: &Erodibility, nx: usize, ny: usize, k_s: f64) -> Result<()> {
    check_erodibility(Some(e), nx, ny)?;
    if f64::from(e.max()) * k_s > 1.0 {
        return Err(invalid("erodibility", e.max(), "max × k_s must be ≤ 1"));
    }
    Ok(())
}
