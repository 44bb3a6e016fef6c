//! "Building Planets" (Musgrave 2001): planets made from each basis
//! function, Voronoi seed table and fractal of natura-noise, as MojoWorld's figures show them.
//! Each planet is the unit sphere, its relief the fractal at the sphere's
//! point (bump-shaded by natura-texture's sphere preview, lit from the upper
//! left), coloured by altitude (meadow, scrub, rock, snow) over a sea
//! filled to a fixed fraction of the surface.

use natura::core::glam::{DVec3, Vec3};
use natura::core::{Image, NoProgress};
use natura::noise::{
    Checkerboard, Displace, Fbm, FeaturePoints, Field, HeteroTerrain, HeteroTerrainParams,
    HybridMultifractal, HybridParams, Metric, Perlin, Sine, SparseConvolution, SparseParams,
    Spectral, Steps, Value, VecNoise, Warped, Worley, WorleyFeature, WorleyParams,
};
use natura::texture::{Footprint, Sample, SolidTexture, TextureKind, preview};

use super::R;

/// How much of a planet's surface the sea covers (MojoWorld's "oceans"
/// fill to a level; the level is natura's choice).
pub(crate) const SEA_COVER: f64 = 0.45;

/// A planet: `field` at `scale`·(the unit sphere's point), its values
/// mapped to altitudes by the quantiles of a sample of the sphere, the sea
/// filling the lowest [`SEA_COVER`] unless `sea` is off.
pub(crate) struct Planet {
    field: Box<dyn Field>,
    scale: f64,
    /// The field's values at the 1st and 99th percentiles, and at the sea.
    lo: f64,
    hi: f64,
    sea: Option<f64>,
}

/// `n` points spread evenly over the unit sphere (a Fibonacci lattice).
pub(crate) fn sphere_points(n: usize) -> impl Iterator<Item = DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n).map(move |i| {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let r = (1.0 - z * z).sqrt();
        let a = golden * i as f64;
        DVec3::new(r * a.cos(), r * a.sin(), z)
    })
}

impl Planet {
    /// The planet of `field` (`scale` lattice units per planet radius),
    /// with a sea when `sea` is set.
    pub(crate) fn new(field: Box<dyn Field>, scale: f64, sea: bool) -> Self {
        let mut v: Vec<f64> = sphere_points(4096)
            .map(|p| field.eval3(p * scale))
            .collect();
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q) as usize];
        let (lo, hi) = (at(0.01), at(0.99));
        let sea = sea.then(|| at(SEA_COVER));
        Self {
            field,
            scale,
            lo,
            hi: if hi > lo { hi } else { lo + 1.0 },
            sea,
        }
    }

    /// Altitude in `[0, 1]` (clamped) of the field's value `v`.
    fn altitude(&self, v: f64) -> f64 {
        ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
    }

    /// Whether the point `p` of the unit sphere is under the sea.
    #[cfg(test)]
    fn is_sea(&self, p: DVec3) -> bool {
        self.sea
            .is_some_and(|s| self.field.eval3(p * self.scale) < s)
    }
}

/// Land by altitude `a` in `[0, 1]` above the shore `shore`.
fn land(a: f64, shore: f64) -> DVec3 {
    let t = ((a - shore) / (1.0 - shore).max(1e-9)).clamp(0.0, 1.0);
    let stops = [
        (0.0, DVec3::new(0.20, 0.32, 0.11)),
        (0.35, DVec3::new(0.42, 0.40, 0.22)),
        (0.65, DVec3::new(0.45, 0.40, 0.36)),
        (0.85, DVec3::new(0.85, 0.86, 0.88)),
        (1.0, DVec3::new(0.95, 0.96, 0.97)),
    ];
    for w in stops.windows(2) {
        let ((a0, c0), (a1, c1)) = (w[0], w[1]);
        if t <= a1 {
            return c0.lerp(c1, (t - a0) / (a1 - a0));
        }
    }
    stops[stops.len() - 1].1
}

/// Relief of the bump shading, in planet radii per unit of altitude.
const RELIEF: f64 = 0.06;

impl SolidTexture for Planet {
    fn name(&self) -> &'static str {
        "planet"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::ColourAndHeight
    }
    fn sample(&self, p: DVec3, _fp: Footprint) -> Sample {
        let a = self.altitude(self.field.eval3(p * self.scale));
        let shore = self.sea.map_or(0.0, |s| self.altitude(s));
        let (colour, height) = if self.sea.is_some() && a < shore {
            // The sea is a smooth sphere at its level, darker where deep.
            let deep = ((shore - a) / shore.max(1e-9)).clamp(0.0, 1.0);
            (
                DVec3::new(0.06, 0.16, 0.32).lerp(DVec3::new(0.02, 0.06, 0.16), deep),
                shore,
            )
        } else {
            (land(a, shore), a)
        };
        Sample {
            colour,
            opacity: 1.0,
            height: RELIEF * height,
        }
    }
}

/// fBm of `basis` with `h`, 8 octaves, λ = 2.
fn fbm<B: Field + 'static>(basis: B, h: f64) -> R<Box<dyn Field>> {
    Ok(Box::new(Fbm::new(
        basis,
        Spectral {
            h,
            lacunarity: 2.0,
            octaves: 8.0,
            ..Spectral::default()
        },
    )?))
}

/// A planet seen from the front.
fn draw(planet: &Planet, size: u32) -> R<Image> {
    Ok(preview::sphere(planet, size, false, &NoProgress)?)
}

/// Pictures side by side.
fn row(images: &[Image]) -> R<Image> {
    Ok(Image::contact_sheet(
        images,
        images.len(),
        4,
        Vec3::splat(0.0),
    )?)
}

/// Fig. 9: fBm of Perlin noise at MojoWorld's "roughness" −0.5, 0, 0.5, 1
/// and 1.5. Roughness is read as `1 − H`: −0.5 the smoothest (H = 1.5),
/// 1.5 the roughest (H = −0.5, amplitudes growing with frequency).
pub(crate) fn roughness(seed: u64, quick: bool) -> R<Image> {
    let size = if quick { 64 } else { 300 };
    let mut out = Vec::new();
    for r in [-0.5, 0.0, 0.5, 1.0, 1.5] {
        let planet = Planet::new(fbm(Perlin::new(seed), 1.0 - r)?, 1.5, true);
        out.push(draw(&planet, size)?);
    }
    row(&out)
}

/// Figs. 13 and 18–23: planets from fBm (H = 0.7) of each basis:
/// Perlin; Voronoi F1 by distance and by distance squared; sparse
/// convolution with the cone kernel; sine; linear (value noise); steps;
/// checkerboard. The bases' shapes show through, as the figures' point is.
pub(crate) fn bases(seed: u64, quick: bool) -> R<Image> {
    let size = if quick { 64 } else { 260 };
    let worley = |metric| {
        Worley::new(
            seed,
            WorleyParams {
                feature: WorleyFeature::F1,
                metric,
                ..WorleyParams::default()
            },
        )
    };
    let fields: Vec<Box<dyn Field>> = vec![
        fbm(Perlin::new(seed), 0.7)?,
        fbm(worley(Metric::Euclidean)?, 0.7)?,
        fbm(worley(Metric::EuclideanSquared)?, 0.7)?,
        fbm(SparseConvolution::new(seed, SparseParams::default())?, 0.7)?,
        fbm(Sine, 0.7)?,
        fbm(Value::new(seed), 0.7)?,
        fbm(Steps::new(seed), 0.7)?,
        fbm(Checkerboard, 0.7)?,
    ];
    let mut out = Vec::new();
    for f in fields {
        out.push(draw(&Planet::new(f, 1.5, true), size)?);
    }
    Ok(Image::contact_sheet(&out, 4, 4, Vec3::ZERO)?)
}

/// Fig. 24's seed tables in the caption's order (clockwise from the upper
/// left): 1, 4, 4v and 4g. natura-noise's definitions (the source gives
/// none): "n" a Poisson number of points per cell of mean n, "nv" that mean
/// varying smoothly over space (0.2 to 1.8 times n), "ng" Gaussian clusters
/// of varying spread (see `FeaturePoints`).
pub(crate) const SEED_TABLES: [(&str, FeaturePoints); 4] = [
    ("1", FeaturePoints::Poisson { density: 1.0 }),
    ("4", FeaturePoints::Poisson { density: 4.0 }),
    ("4v", FeaturePoints::Variable { density: 4.0 }),
    ("4g", FeaturePoints::Gaussian { density: 4.0 }),
];

/// Voronoi F1 (distance) with the seed table `points`.
fn voronoi(seed: u64, points: FeaturePoints) -> R<Worley> {
    Ok(Worley::new(
        seed,
        WorleyParams {
            feature: WorleyFeature::F1,
            metric: Metric::Euclidean,
            points,
            ..WorleyParams::default()
        },
    )?)
}

/// Fig. 24: planets from fBm (H = 0.7, as Fig. 19's) of Voronoi F1 with
/// seed tables 1, 4, 4v and 4g, going clockwise from the upper left as the
/// caption has them: table 4's cells are smaller than table 1's, 4v's are
/// small in some regions and large in others, 4g's come in knots of tiny
/// cells among large ones.
pub(crate) fn seed_tables(seed: u64, quick: bool) -> R<Image> {
    let size = if quick { 64 } else { 300 };
    let mut out = Vec::new();
    for (_, points) in SEED_TABLES {
        let planet = Planet::new(fbm(voronoi(seed, points)?, 0.7)?, 1.5, true);
        out.push(draw(&planet, size)?);
    }
    // A 2×2 sheet fills row by row: clockwise from the upper left is
    // sheet order 0, 1, 3, 2.
    out.swap(2, 3);
    Ok(Image::contact_sheet(&out, 2, 4, Vec3::ZERO)?)
}

/// Figs. 25–28 and 31: monofractal fBm (Perlin, roughness 0.3: H = 0.7)
/// with and without oceans; heterofractal (natura-noise's heterogeneous
/// terrain) and multifractal (its hybrid multifractal, which MojoWorld
/// calls "multifractal") each straight and plus a random vertical
/// displacement (low-frequency Perlin noise, so the smooth ground is not
/// all at one altitude); a function fractal (fBm whose basis is itself
/// fBm); fBm undistorted and with its domain distorted by vector noise.
pub(crate) fn fractals(seed: u64, quick: bool) -> R<Image> {
    let size = if quick { 64 } else { 260 };
    let spectral = Spectral {
        lacunarity: 2.0,
        octaves: 8.0,
        ..Spectral::default()
    };
    let displaced = |f: Box<dyn Field>| -> Box<dyn Field> {
        Box::new(Sum(
            f,
            Box::new(Scaled(Perlin::new(seed ^ 0x5eed), 0.6, 0.5)),
        ))
    };
    let hetero = || -> R<Box<dyn Field>> {
        Ok(Box::new(HeteroTerrain::new(
            Perlin::new(seed),
            HeteroTerrainParams {
                spectral,
                ..HeteroTerrainParams::default()
            },
        )?))
    };
    let hybrid = || -> R<Box<dyn Field>> {
        Ok(Box::new(HybridMultifractal::new(
            Perlin::new(seed),
            HybridParams {
                spectral,
                ..HybridParams::default()
            },
        )?))
    };
    let inner = Fbm::new(
        Perlin::new(seed ^ 0xf00),
        Spectral {
            h: 0.5,
            lacunarity: 2.0,
            octaves: 3.0,
            ..Spectral::default()
        },
    )?;
    let distorted = Warped {
        field: Fbm::new(Perlin::new(seed), Spectral { h: 0.7, ..spectral })?,
        warp: Displace::new(VecNoise::new(Perlin::new(seed ^ 0xd15)), 0.8)?,
    };
    let planets = [
        Planet::new(fbm(Perlin::new(seed), 0.7)?, 1.5, true),
        Planet::new(fbm(Perlin::new(seed), 0.7)?, 1.5, false),
        Planet::new(hetero()?, 1.5, true),
        Planet::new(displaced(hetero()?), 1.5, true),
        Planet::new(hybrid()?, 1.5, true),
        Planet::new(displaced(hybrid()?), 1.5, true),
        Planet::new(
            Box::new(Fbm::new(
                inner,
                Spectral {
                    h: 0.7,
                    lacunarity: 2.0,
                    octaves: 5.0,
                    ..Spectral::default()
                },
            )?),
            1.0,
            true,
        ),
        Planet::new(fbm(Perlin::new(seed), 0.7)?, 1.5, true),
        Planet::new(Box::new(distorted), 1.5, true),
    ];
    let mut out = Vec::new();
    for p in &planets {
        out.push(draw(p, size)?);
    }
    Ok(Image::contact_sheet(&out, 3, 4, Vec3::ZERO)?)
}

/// `a + b`.
struct Sum(Box<dyn Field>, Box<dyn Field>);

impl Field for Sum {
    fn eval2(&self, p: natura::noise::glam::DVec2) -> f64 {
        self.0.eval2(p) + self.1.eval2(p)
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.0.eval3(p) + self.1.eval3(p)
    }
    fn bound(&self) -> f64 {
        self.0.bound() + self.1.bound()
    }
    fn lipschitz2(&self) -> f64 {
        self.0.lipschitz2() + self.1.lipschitz2()
    }
    fn lipschitz3(&self) -> f64 {
        self.0.lipschitz3() + self.1.lipschitz3()
    }
}

/// `amplitude · f(frequency · p)`.
struct Scaled<F>(F, f64, f64);

impl<F: Field> Field for Scaled<F> {
    fn eval2(&self, p: natura::noise::glam::DVec2) -> f64 {
        self.1 * self.0.eval2(p * self.2)
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.1 * self.0.eval3(p * self.2)
    }
    fn bound(&self) -> f64 {
        self.1.abs() * self.0.bound()
    }
    fn lipschitz2(&self) -> f64 {
        self.1.abs() * self.2.abs() * self.0.lipschitz2()
    }
    fn lipschitz3(&self) -> f64 {
        self.1.abs() * self.2.abs() * self.0.lipschitz3()
    }
}

/// Figs. 9, 13, 18–23, 24, 25–28 and 31.
pub(crate) fn pictures(seed: u64, quick: bool) -> R<Vec<Image>> {
    Ok(vec![
        roughness(seed, quick)?,
        bases(seed, quick)?,
        seed_tables(seed, quick)?,
        fractals(seed, quick)?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sea_covers_its_share_of_the_sphere() {
        let planet = Planet::new(fbm(Perlin::new(3), 0.7).unwrap(), 1.5, true);
        let n = 20_000;
        let wet = sphere_points(n).filter(|&p| planet.is_sea(p)).count() as f64 / n as f64;
        assert!((wet - SEA_COVER).abs() < 0.02, "{wet}");
        let dry = Planet::new(fbm(Perlin::new(3), 0.7).unwrap(), 1.5, false);
        assert!(sphere_points(1000).all(|p| !dry.is_sea(p)));
    }

    /// Fig. 24's tables differ as the caption's names say: table 4's
    /// cells are smaller than table 1's (mean F1 over the sphere about
    /// `4^{-1/3}` as large), 4v's sizes vary between regions of the sphere
    /// more than 4's, and 4g's clusters leave wider gaps than 4's points.
    #[test]
    fn the_seed_tables_differ_as_named() {
        let f1 = |points| {
            let w = voronoi(5, points).unwrap();
            sphere_points(20_000)
                .map(|p| w.eval3(p * 6.0))
                .collect::<Vec<f64>>()
        };
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let [one, four, var, gauss] = SEED_TABLES.map(|(_, t)| f1(t));
        let ratio = mean(&four) / mean(&one);
        assert!((ratio - 0.25f64.cbrt()).abs() < 0.08, "{ratio}");
        // The spread of the means of 400 patches of 50 neighbouring points
        // (the Fibonacci lattice runs in bands, so these are strips).
        let patches = |v: &[f64]| {
            let m: Vec<f64> = v.chunks(50).map(mean).collect();
            let mm = mean(&m);
            (m.iter().map(|x| (x - mm).powi(2)).sum::<f64>() / m.len() as f64).sqrt() / mm
        };
        assert!(
            patches(&var) > 1.5 * patches(&four),
            "{} {}",
            patches(&var),
            patches(&four)
        );
        // Clusters leave gaps: at the same density, a random point's
        // nearest feature point is farther in 4g than in 4.
        let gaps = mean(&gauss) / mean(&four);
        assert!(gaps > 1.15, "{gaps}");
    }

    #[test]
    fn higher_roughness_means_more_relief_in_the_fine_octaves() {
        // Fig. 9: the fraction of a profile's variation in its finest
        // scales grows with roughness (H = 1 − roughness).
        let fine_share = |r: f64| {
            let f = fbm(Perlin::new(4), 1.0 - r).unwrap();
            let v: Vec<f64> = (0..4096)
                .map(|i| f.eval3(DVec3::new(i as f64 / 256.0, 0.3, 0.7)))
                .collect();
            let step = |k: usize| v.windows(k + 1).map(|w| (w[k] - w[0]).abs()).sum::<f64>();
            step(1) / step(64)
        };
        let shares: Vec<f64> = [-0.5, 0.0, 0.5, 1.0, 1.5].map(fine_share).to_vec();
        assert!(shares.windows(2).all(|w| w[1] > w[0]), "{shares:?}");
    }
}
