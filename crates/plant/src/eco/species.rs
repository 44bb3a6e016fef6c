//! Species of an ecosystem: the five parameters of Deussen et al. 1998, §4.3
//! ("multi-species" simulation), the site preferences that turn the terrain
//! into vigor, and the L-system each species' prototypes are grown from.

use natura_core::check;

use crate::error::{PlantError, Result};

/// One plant species of an [`Ecosystem`](super::Ecosystem).
///
/// Deussen et al. 1998, §4.3, name the parameters (i) number of new plants
/// per step, (ii) maximum size, (iii) average growth rate, (iv) probability of
/// surviving domination and (v) preference for wet or dry areas; they print
/// no values. Here the wet/dry preference is a Gaussian window on the
/// normalised wetness, and the same window is used for the terrain's light;
/// altitude and slope are hard limits on where a seed may establish.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Species {
    /// Name (for files and pictures).
    pub name: String,
    /// New plants per hectare per step, (i): seeds fall uniformly and establish only on suitable sites.
    pub seeds_per_ha: f64,
    /// Plants per hectare sown before the first step (the initial population).
    pub initial_per_ha: f64,
    /// Radius of a seedling's circle of influence, metres (drawn uniformly in `[r0_min, r0_max]`).
    pub r0_min: f64,
    /// Upper end of the seedling radius interval, metres.
    pub r0_max: f64,
    /// Maximum radius, metres, (ii): a plant that reaches it is old and dies.
    pub max_radius: f64,
    /// Average growth of the radius per step at vigor 1, metres, (iii).
    pub growth: f64,
    /// Probability that a dominated plant survives the step, (iv) (shade tolerance).
    pub survive_domination: f64,
    /// Preferred normalised wetness in `[0, 1]` (0 = driest site of the terrain, 1 = wettest), (v).
    pub wet_optimum: f64,
    /// Width (standard deviation) of the wetness preference.
    pub wet_tolerance: f64,
    /// Preferred terrain light in `[0, 1]` (the hill-shade under the ecosystem's sun).
    pub light_optimum: f64,
    /// Width (standard deviation) of the light preference.
    pub light_tolerance: f64,
    /// Lowest normalised altitude where the species establishes (0 = the terrain's lowest point).
    pub altitude_min: f64,
    /// Highest normalised altitude where the species establishes (1 = the highest point).
    pub altitude_max: f64,
    /// Steepest slope where the species establishes, radians.
    pub max_slope: f64,
    /// Random spread of vigor: vigor is the site suitability times `1 + spread·(u − ½)`, u uniform.
    pub vigor_spread: f64,
    /// L-system of the species' prototypes (cpfg text); one derivation step per size class step.
    pub lsystem: String,
    /// Derivation steps that give the prototype of a plant at `max_radius`.
    pub max_steps: u32,
}

/// Most plants per hectare a species may sow ([`Species::seeds_per_ha`],
/// [`Species::initial_per_ha`]): one per square centimetre.
pub const MAX_PER_HA: f64 = 1e8;

/// Smallest radius of a circle of influence, metres (a millimetre seedling).
pub const MIN_RADIUS_M: f64 = 1e-3;

/// Largest radius of a circle of influence, metres, and largest growth per step.
pub const MAX_RADIUS_M: f64 = 1e3;

/// A small ABOP-style bush (Prusinkiewicz & Lindenmayer 1990, Fig. 1.25) used by the default species.
const BUSH: &str = "angle: 22.5
ω: !(0.1)A
A -> [&FL!A]/////'[&FL!A]///////'[&FL!A]
F -> S/////F
S -> FL
L -> ['''^^{-f+f+f-|-f+f+f}]";

/// A monopodial tree (ABOP Fig. 2.6 style, whorls of three laterals).
const TREE: &str = "angle: 30
ω: !(0.3)F(2)A(1)
A(l) -> F(l)[&(35)B(l*0.6)]/(120)[&(35)B(l*0.6)]/(120)[&(35)B(l*0.6)]/(137)A(l*0.9)
B(l) -> F(l)[-(30)$C(l*0.6)][+(30)$C(l*0.6)]B(l*0.8)
C(l) -> F(l)~L(0.6,0.3)C(l*0.8)";

/// A grass tuft: a fan of bent blades.
const GRASS: &str = "angle: 18
ω: [&(20)B]/(72)[&(25)B]/(72)[&(15)B]/(72)[&(30)B]/(72)[&(22)B]
B -> F(0.3)&(8)B";

impl Default for Species {
    /// A mid-sized shrub of average preferences (own values: the source gives none).
    fn default() -> Self {
        Self {
            name: "shrub".into(),
            seeds_per_ha: 40.0,
            initial_per_ha: 200.0,
            r0_min: 0.1,
            r0_max: 0.3,
            max_radius: 2.0,
            growth: 0.12,
            survive_domination: 0.1,
            wet_optimum: 0.5,
            wet_tolerance: 0.35,
            light_optimum: 0.7,
            light_tolerance: 0.5,
            altitude_min: 0.0,
            altitude_max: 1.0,
            max_slope: 40f64.to_radians(),
            vigor_spread: 0.4,
            lsystem: BUSH.into(),
            max_steps: 5,
        }
    }
}

impl Species {
    /// A tree of dry, bright, lower slopes (own values).
    #[must_use]
    pub fn tree() -> Self {
        Self {
            name: "tree".into(),
            seeds_per_ha: 12.0,
            initial_per_ha: 60.0,
            r0_min: 0.2,
            r0_max: 0.5,
            max_radius: 5.0,
            growth: 0.25,
            survive_domination: 0.02,
            wet_optimum: 0.35,
            wet_tolerance: 0.3,
            light_optimum: 0.8,
            light_tolerance: 0.4,
            altitude_min: 0.0,
            altitude_max: 0.8,
            max_slope: 32f64.to_radians(),
            vigor_spread: 0.4,
            lsystem: TREE.into(),
            max_steps: 6,
        }
    }

    /// A wet-loving shrub of valley floors and channels (own values).
    #[must_use]
    pub fn wet_shrub() -> Self {
        Self {
            name: "wet_shrub".into(),
            wet_optimum: 0.9,
            wet_tolerance: 0.2,
            light_optimum: 0.6,
            survive_domination: 0.2,
            ..Self::default()
        }
    }

    /// A grass tuft that survives shade often and grows anywhere but on cliffs (own values).
    #[must_use]
    pub fn grass() -> Self {
        Self {
            name: "grass".into(),
            seeds_per_ha: 400.0,
            initial_per_ha: 2000.0,
            r0_min: 0.05,
            r0_max: 0.15,
            max_radius: 0.5,
            growth: 0.05,
            survive_domination: 0.3,
            wet_optimum: 0.55,
            wet_tolerance: 0.5,
            light_optimum: 0.9,
            light_tolerance: 0.6,
            altitude_min: 0.0,
            altitude_max: 1.0,
            max_slope: 45f64.to_radians(),
            vigor_spread: 0.5,
            lsystem: GRASS.into(),
            max_steps: 6,
        }
    }

    /// Checks every field against its physical range: densities in
    /// `[0, 10⁸]` per hectare (one plant per square centimetre), radii in
    /// `[10⁻³, 10³]` metres (a millimetre seedling to a kilometre-wide
    /// circle of influence) with `r0_min ≤ r0_max < max_radius`, growth in
    /// `(0, 10³]` metres per step, probabilities and normalised site values
    /// in `[0, 1]`.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field, its value and its range.
    pub fn validate(&self) -> Result<()> {
        let density =
            |n, v| check::in_range(n, v, 0.0, MAX_PER_HA, "plants per hectare in [0, 1e8]");
        density("Species::seeds_per_ha", self.seeds_per_ha)?;
        density("Species::initial_per_ha", self.initial_per_ha)?;
        let radius = |n, v| {
            check::in_range(
                n,
                v,
                MIN_RADIUS_M,
                MAX_RADIUS_M,
                "a radius in [1e-3, 1e3] metres",
            )
        };
        radius("Species::r0_min", self.r0_min)?;
        radius("Species::r0_max", self.r0_max)?;
        radius("Species::max_radius", self.max_radius)?;
        if self.r0_max < self.r0_min || self.r0_max >= self.max_radius {
            return Err(PlantError::InvalidParameter {
                name: "Species::r0_max",
                value: self.r0_max.to_string(),
                reason: "must lie in [r0_min, max_radius)".into(),
            });
        }
        check::positive("Species::growth", self.growth)?;
        check::in_range(
            "Species::growth",
            self.growth,
            0.0,
            MAX_RADIUS_M,
            "metres per step in (0, 1e3]",
        )?;
        let unit = |n, v| check::in_range(n, v, 0.0, 1.0, "a number in [0, 1]");
        unit("Species::survive_domination", self.survive_domination)?;
        unit("Species::wet_optimum", self.wet_optimum)?;
        unit("Species::light_optimum", self.light_optimum)?;
        unit("Species::altitude_min", self.altitude_min)?;
        unit("Species::altitude_max", self.altitude_max)?;
        if self.altitude_max < self.altitude_min {
            return Err(PlantError::InvalidParameter {
                name: "Species::altitude_max",
                value: self.altitude_max.to_string(),
                reason: "must be at least altitude_min".into(),
            });
        }
        check::positive("Species::wet_tolerance", self.wet_tolerance)?;
        check::positive("Species::light_tolerance", self.light_tolerance)?;
        check::in_range(
            "Species::max_slope",
            self.max_slope,
            0.0,
            std::f64::consts::FRAC_PI_2,
            "an angle in [0, π/2] radians",
        )?;
        check::in_range(
            "Species::vigor_spread",
            self.vigor_spread,
            0.0,
            2.0,
            "a number in [0, 2]",
        )?;
        check::count(
            "Species::max_steps",
            self.max_steps as usize,
            0,
            12,
            "at most 12 derivation steps",
        )?;
        Ok(())
    }

    /// Site suitability in `[0, 1]` at normalised wetness `wet` and light `light`:
    /// the product of the two Gaussian preference windows.
    #[inline]
    #[must_use]
    pub fn suitability(&self, wet: f32, light: f32) -> f32 {
        let g = |v: f32, o: f64, t: f64| {
            let z = (f64::from(v) - o) / t;
            (-0.5 * z * z).exp() as f32
        };
        g(wet, self.wet_optimum, self.wet_tolerance)
            * g(light, self.light_optimum, self.light_tolerance)
    }

    /// Whether a seed may establish at normalised altitude `alt` on slope `slope` (radians).
    #[inline]
    #[must_use]
    pub fn admits(&self, alt: f32, slope: f32) -> bool {
        let a = f64::from(alt);
        a >= self.altitude_min && a <= self.altitude_max && f64::from(slope) <= self.max_slope
    }
}
