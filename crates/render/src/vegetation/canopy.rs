//! The forest to the horizon: beyond the instanced trees, an aggregate
//! canopy layer over the terrain, grown from the same ecosystem.
//!
//! **Cover.** Every terrain sample gets the establishment suitability the
//! ecosystem's seeding reads (natura-plant's [`Species::admits`] for
//! altitude and slope, times [`Species::suitability`] for wetness and light;
//! summed over the canopy species, as their seeds fall independently;
//! Deussen et al. 1998, §4.3). The instanced stand near the camera is the
//! calibration: its trees' crown areas per terrain cell, averaged over cells
//! of equal suitability, give the crown-area index `a` (crown area per ground
//! area) a cell of that suitability carries after seeding, growth and
//! self-thinning. The far layer is that table applied to the whole terrain,
//! so the forest's density beyond the trees is the stand's own.
//!
//! **Seen cover and light.** Crowns are a Boolean model: crowns of radius
//! `R` and depth `H` placed at random, as in the geometric-optical canopy
//! model of Li & Strahler 1992, whose gap probability along a direction at
//! zenith angle θ is `exp(−a·(1 + s·tan θ))` on level ground (on a slope,
//! `tan θ` becomes the ray's horizontal run through the layer per metre of
//! crown height), here with each crown's shadow taken as an upright
//! cone's: `s = H/(πR)`, its side silhouette `R·H` relative to its top
//! `πR²` (our simplification of their spheroids). The model's two
//! constants, the crowns' opacity (their crown-area index counts each crown
//! as a solid disc of its full reach, but crowns are porous) and the slant
//! `s`, are fitted to the stand itself: rays traced down through the
//! instanced trees at 0°, 60° and 80° from the zenith give the fractions the
//! trees stop, and the least-squares pair reproduces them. A pixel
//! sees crowns with probability `1 − gap(view)` and the floor otherwise;
//! the floor is sunlit through `gap(sun)` and sees the sky through
//! `gap(45°)`. A crown's radiance is that of a Lambertian sphere at the
//! phase angle α between the viewer and the sun, `(2/3)·Φ(α)·ρ·E/π` with
//! `Φ(α) = (sin α + (π − α) cos α)/π` (Lambert's law integrated over the
//! sphere's lit, visible half), dimmed by the crowns' mutual shading as
//! the far hulls are ([`super::CROWN_HULL_SHADE`]), plus the skylight a
//! crown's surface sees ([`CROWN_OPENNESS`]) and the lit ground's light
//! from below ([`Light::bounced`]), as on the instanced trees.
//!
//! **Seam.** The instanced trees thin out over the outer quarter of the
//! forest's radius with probability `1 − near_share(d)`
//! ([`super::near_share`]); the layer's index is multiplied by the same
//! `1 − near_share(d)`, so the cover seen across the switch stays the
//! stand's. A fractal mottle at the scale of the stand's clumps, filtered
//! to the pixel's footprint (natura-noise's [`FilteredFbm`]), keeps the
//! layer from looking like paint; its octaves finer than a pixel fade out,
//! so the mean stays the table's.
//!
//! **Floor.** Under crowns near or far the ground is leaf litter and moss
//! (natura's own colours), mottled at the metre scale, and the trees hide
//! part of the sky from it.
//!
//! The per-pixel work is a few bilinear look-ups and two filtered fBm
//! evaluations, whatever the number of trees.

use glam::{DVec2, Vec2, Vec3};
use natura_core::{Boundary, Grid2, HeightField};
use natura_noise::{FilteredFbm, Perlin, Spectral};
use natura_plant::eco::Species;
use natura_plant::eco::catalogue::Look;

use super::bvh::Instanced;
use super::shade::{CROWN_OPENNESS, Light};
use super::{CROWN_HULL_SHADE, near_share};
use crate::error::Result;

/// Bins of the suitability table over `[0, MAX_SUIT]`.
const BINS: usize = 24;
/// Suitability summed over species above which the table holds its last value.
const MAX_SUIT: f32 = 2.0;
/// Calibration cells a bin needs before its mean is trusted.
const MIN_CELLS: u32 = 12;
/// Terrain samples per side of a cell of the colour grid.
const COLOUR_STEP: usize = 4;
/// Largest `tan θ` the gap probabilities take (a ray within a degree of the
/// horizon sees only crowns anyway).
const MAX_TAN: f32 = 60.0;

/// Linear albedo of the forest floor under crowns: leaf litter and moss
/// (natura's own value).
pub const LITTER: Vec3 = Vec3::new(0.055, 0.045, 0.028);

/// Figures of a canopy layer: what the stand taught it and the cover it
/// gives.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CanopyStats {
    /// Crown-area index per suitability bin (bins of width
    /// `2 / 24` from 0), as the layer applies it.
    pub table: Vec<f32>,
    /// Mean crown-area index of the instanced stand over its forested
    /// calibration cells (suitability above 0, fully inside the stand).
    pub stand_index: f32,
    /// Mean crown-area index the layer gives the same cells.
    pub layer_index: f32,
    /// The crowns' side-to-top ratio `s` of the gap probability, as the
    /// probes through the stand fit it.
    pub slant: f32,
    /// The factor from the stand's crown-area index to the Boolean model's,
    /// as the probes fit it.
    pub opacity: f32,
    /// The fraction of probe rays the stand stops at each probe angle, and
    /// the model's fitted fraction.
    pub probes: Vec<(f32, f32)>,
}

/// A tree of the instanced stand as the calibration sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StandTree {
    /// Foot of the tree, metres.
    pub position: Vec3,
    /// Horizontal crown radius, metres.
    pub crown_radius: f32,
    /// Height, metres.
    pub height: f32,
}

/// What the canopy needs of a world: its terrain and maps, the water, the
/// canopy species over the whole terrain and their looks, and the stand.
pub(crate) struct CanopyInput<'a> {
    pub terrain: &'a HeightField,
    pub surface: &'a HeightField,
    pub wetness: &'a Grid2<f32>,
    pub sun: Vec3,
    pub water: f32,
    /// Canopy species (trees and shrubs), altitudes normalised over the
    /// whole terrain, with their looks.
    pub species: Vec<(Species, Look)>,
    pub season: f32,
    pub eye: Vec2,
    pub radius: f32,
    pub trees: Vec<StandTree>,
    /// The instanced stand, for the probes.
    pub stand: &'a Instanced,
    pub seed: natura_core::Seed,
}

/// The canopy layer of a world (see the module docs).
#[derive(Debug)]
pub struct Canopy {
    /// Crown-area index of the far forest per terrain sample.
    far: Grid2<f32>,
    /// Canopy leaf albedo per cell of `COLOUR_STEP` samples.
    colour: Grid2<Vec3>,
    /// Crown-area index of the instanced trees per terrain sample (for the
    /// floor's sky), smoothed over 3×3 samples.
    near: Grid2<f32>,
    cell: f32,
    eye: Vec2,
    radius: f32,
    slant: f32,
    /// The crowns' side-to-top ratio of their full reach, `H/(πR)` of the
    /// stand's mean crown depth `H` and reach `R`: the floor's sky.
    reach_slant: f32,
    /// Mean height of the stand's crowns' tops, metres.
    height: f32,
    /// The stand's opacity: its crown-area index times this is the Boolean
    /// model's (crowns are porous, and narrower than their reach).
    opacity: f32,
    clumps: FilteredFbm<Perlin>,
    floor: FilteredFbm<Perlin>,
    stats: CanopyStats,
}

/// Grid of `f(i, j)` over `w × h`, in parallel rows where the crate is.
fn grid<T: Default + Clone + Send + Sync>(
    w: usize,
    h: usize,
    f: impl Fn(usize, usize) -> T + Sync + Send,
) -> Result<Grid2<T>> {
    #[cfg(feature = "parallel")]
    let g = Grid2::par_from_fn(w, h, f)?;
    #[cfg(not(feature = "parallel"))]
    let g = Grid2::from_fn(w, h, f)?;
    Ok(g)
}

/// Lambert's phase law for a diffuse sphere at phase angle `α`.
fn lambert_phase(cos_alpha: f32) -> f32 {
    let a = cos_alpha.clamp(-1.0, 1.0).acos();
    (a.sin() + (std::f32::consts::PI - a) * a.cos()) / std::f32::consts::PI
}

/// The horizontal run, per metre of crown height, of unit direction `d`
/// through a layer of upright crowns on ground of unit normal `n`:
/// `n_z·|d_h| / |d·n|`, which is `tan θ` of `d`'s zenith angle θ on level
/// ground and shrinks on a slope facing the ray; capped at [`MAX_TAN`].
fn run(d: Vec3, n: Vec3) -> f32 {
    let h = n.z.abs() * d.truncate().length();
    let v = d.dot(n).abs();
    if h >= MAX_TAN * v { MAX_TAN } else { h / v }
}

impl Canopy {
    /// Builds the layer: suitability over the terrain, the stand's table,
    /// the far index, the colours and the near index.
    pub(crate) fn new(inp: &CanopyInput<'_>) -> Result<Self> {
        let (nx, ny) = (inp.terrain.nx(), inp.terrain.ny());
        let cell = inp.terrain.cell_size();
        let site =
            natura_plant::eco::Site::with_wetness(inp.terrain, inp.sun, inp.wetness.clone())?;
        let (g, s) = (inp.terrain.heights(), inp.surface.heights());
        let dry = |i: usize, j: usize| s[(i, j)] <= g[(i, j)] && g[(i, j)] > inp.water;
        let suit = grid(nx, ny, |i, j| {
            if !dry(i, j) {
                return 0.0;
            }
            let (alt, slope) = (site.altitude[(i, j)], site.slope[(i, j)]);
            let (wet, light) = (site.wetness[(i, j)], site.light[(i, j)]);
            inp.species
                .iter()
                .filter(|(sp, _)| sp.admits(alt, slope))
                .map(|(sp, _)| sp.suitability(wet, light))
                .sum::<f32>()
        })?;
        // The stand's crown area per terrain cell.
        let mut area = Grid2::new(nx, ny, 0.0f32)?;
        let (mut depth, mut rad, mut wsum, mut tops) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for t in &inp.trees {
            let (i, j) = (
                ((t.position.x / cell).round().max(0.0) as usize).min(nx - 1),
                ((t.position.y / cell).round().max(0.0) as usize).min(ny - 1),
            );
            let a = std::f32::consts::PI * t.crown_radius * t.crown_radius;
            area[(i, j)] += a / (cell * cell);
            depth += f64::from(a * 0.7 * t.height);
            rad += f64::from(a * t.crown_radius);
            wsum += f64::from(a);
            tops += f64::from(a * t.height);
        }
        let height = if wsum > 0.0 {
            (tops / wsum) as f32
        } else {
            0.0
        };
        let slant = if wsum > 0.0 {
            (depth / (std::f64::consts::PI * rad)) as f32
        } else {
            1.0
        }
        .clamp(0.2, 8.0);
        let table = calibrate(&suit, &area, cell, inp.eye, inp.radius);
        let lookup = |v: f32| table_at(&table, v);
        let far = grid(nx, ny, |i, j| lookup(suit[(i, j)]))?;
        let (stand_index, layer_index) = means(&suit, &area, &far, cell, inp.eye, inp.radius);
        let probes = probe(inp, &far);
        let reach_slant = slant;
        let (opacity, slant, fit) = fit(&probes, slant);
        let colour = colours(inp, &site, nx, ny)?;
        let near = grid(nx, ny, |i, j| {
            let mut sum = 0.0;
            for dj in -1i64..=1 {
                for di in -1i64..=1 {
                    let (a, b) = (i as i64 + di, j as i64 + dj);
                    if a >= 0 && b >= 0 && (a as usize) < nx && (b as usize) < ny {
                        sum += area[(a as usize, b as usize)];
                    }
                }
            }
            sum / 9.0
        })?;
        let s = |n: &str| inp.seed.derive(n).0;
        let clumps = FilteredFbm::new(
            Perlin::new(s("canopy.clumps")),
            Spectral::default()
                .with_h(0.6)
                .with_octaves(5.0)
                .with_frequency(1.0 / 90.0),
            0.0,
        )?;
        let floor = FilteredFbm::new(
            Perlin::new(s("canopy.floor")),
            Spectral::default()
                .with_h(0.5)
                .with_octaves(4.0)
                .with_frequency(1.0 / 3.0),
            0.0,
        )?;
        Ok(Self {
            far,
            colour,
            near,
            cell,
            eye: inp.eye,
            radius: inp.radius,
            slant,
            reach_slant,
            height,
            opacity,
            clumps,
            floor,
            stats: CanopyStats {
                table,
                stand_index,
                layer_index,
                slant,
                opacity,
                probes: fit,
            },
        })
    }

    /// Figures of the layer.
    #[must_use]
    pub fn stats(&self) -> &CanopyStats {
        &self.stats
    }

    /// The mean crown-area index the layer gives the forested land (its
    /// index above 0) at horizontal distances from the eye in `[r0, r1)`
    /// metres, before the share the trees take near the eye, and the number
    /// of terrain samples it averages; for the stand's own figure see
    /// [`CanopyStats::stand_index`].
    #[must_use]
    pub fn mean_index_between(&self, r0: f32, r1: f32) -> (f32, usize) {
        let (nx, ny) = self.far.dims();
        let (mut sum, mut n) = (0.0f64, 0usize);
        for j in 0..ny {
            for i in 0..nx {
                let a = self.far[(i, j)];
                let d = (Vec2::new(i as f32, j as f32) * self.cell - self.eye).length();
                if a > 0.0 && d >= r0 && d < r1 {
                    sum += f64::from(a);
                    n += 1;
                }
            }
        }
        ((sum / n.max(1) as f64) as f32, n)
    }

    /// The layer's crown-area index at `p` (metres; the table's value times
    /// the far share of `p`'s distance from the eye), before the mottle.
    #[must_use]
    pub fn far_index(&self, p: Vec3) -> f32 {
        self.far_share(p, 0.0) * self.table_index(p)
    }

    /// The table's crown-area index at `p`, whatever the distance.
    fn table_index(&self, p: Vec3) -> f32 {
        self.far
            .sample_bilinear(p.x / self.cell, p.y / self.cell, Boundary::Clamp)
    }

    /// The layer's share of the forest a ray sees at the ground point `p`
    /// whose last `run` metres of horizontal travel (toward `p`, from the
    /// eye's side) lie in the crowns: the share at the middle of that run,
    /// so that where the trees thin out the crowns the ray passed on its way
    /// count as trees and not again as layer.
    fn far_share(&self, p: Vec3, run: f32) -> f32 {
        let dist = (p.truncate() - self.eye).length();
        1.0 - near_share((dist - 0.5 * run).max(0.0), self.radius)
    }

    /// The Boolean model's crown-area index at `p` (all the layer's, at any
    /// distance), with the clumps a pixel `footprint` metres wide resolves.
    fn index_at(&self, p: Vec3, footprint: f32) -> f32 {
        let a = self.opacity * self.table_index(p);
        if a <= 0.0 {
            return 0.0;
        }
        let m = self.clumps.eval2_width(
            DVec2::new(f64::from(p.x), f64::from(p.y)),
            f64::from(footprint),
        ) as f32;
        a * (1.0 + 1.6 * m).max(0.0)
    }

    /// The fraction of crowns a ray along unit `d` meets before the ground
    /// `p` of unit normal `n` through the layer of index `a` (before its
    /// share).
    fn seen(&self, p: Vec3, n: Vec3, d: Vec3, a: f32) -> f32 {
        let r = run(d, n);
        let a = a * self.far_share(p, self.height * r);
        1.0 - (-a * (1.0 + self.slant * r)).exp()
    }

    /// The fraction of a pixel `footprint` metres wide looking along unit
    /// `d` at the ground point `p` of unit normal `n` that the layer's
    /// crowns cover.
    #[must_use]
    pub fn view_cover(&self, p: Vec3, n: Vec3, d: Vec3, footprint: f32) -> f32 {
        let a = self.index_at(p, footprint);
        if a <= 0.0 {
            return 0.0;
        }
        self.seen(p, n, d, a)
    }

    /// Radiance toward `-d` of the ground `g` under the forest: the layer's
    /// crowns and the floor between them (see the module docs); `g.radiance`
    /// unchanged where there is no forest.
    #[must_use]
    pub fn ground_radiance(&self, g: &Ground, light: &Light) -> Vec3 {
        let p = g.point;
        let a_all = self.index_at(p, g.footprint);
        let a_far = a_all * self.far_share(p, 0.0);
        let a_near = self
            .near
            .sample_bilinear(p.x / self.cell, p.y / self.cell, Boundary::Clamp);
        // The floor under the crowns' full reach (the index before the
        // opacity: branches and trunks shade it too).
        let a = a_far / self.opacity + a_near;
        if a <= 0.0 {
            return g.radiance;
        }
        let inv_pi = std::f32::consts::FRAC_1_PI;
        // The floor: litter and moss under the crowns, seeing less sky.
        let under = 1.0 - (-8.0 * a).exp();
        let q = DVec2::new(f64::from(p.x), f64::from(p.y));
        let grain = self.floor.eval2_width(q, f64::from(g.footprint)) as f32;
        let floor = g.albedo.lerp(LITTER * (1.0 + 0.5 * grain), under);
        let sky_gap = (-a * (1.0 + self.reach_slant)).exp();
        let sun_gap = (-a_far * (1.0 + self.slant * run(light.sun, g.normal))).exp();
        let ground = floor * inv_pi * (g.sun * sun_gap + g.sky * sky_gap);
        if a_far <= 0.0 {
            return ground;
        }
        // The crowns.
        let seen = self.seen(p, g.normal, g.dir, a_all);
        let rho = self.colour.sample_bilinear(
            p.x / (self.cell * COLOUR_STEP as f32),
            p.y / (self.cell * COLOUR_STEP as f32),
            Boundary::Clamp,
        );
        // The sky on three quarters of the crown's seen surface, the lit
        // ground's light ([`Light::bounced`]) on the last quarter.
        let mut crown =
            rho * inv_pi * (light.sky_irradiance * 0.75 + light.bounced() * 0.25) * CROWN_OPENNESS;
        if g.sun_visible {
            let phase = lambert_phase((-g.dir).dot(light.sun));
            crown += rho * inv_pi * light.sun_irradiance * (2.0 / 3.0 * phase);
        }
        crown * CROWN_HULL_SHADE * seen + ground * (1.0 - seen)
    }
}

/// A ground point as the terrain's shading sees it, for
/// [`Canopy::ground_radiance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// The point, metres.
    pub point: Vec3,
    /// Unit direction of the ray that met it.
    pub dir: Vec3,
    /// Unit normal of the ground there (before bump detail).
    pub normal: Vec3,
    /// Width of the pixel's footprint there, metres.
    pub footprint: f32,
    /// The terrain's albedo there.
    pub albedo: Vec3,
    /// Sun irradiance the bare ground receives (zero in shadow), times its
    /// diffuse factor.
    pub sun: Vec3,
    /// Sky and bounced irradiance the bare ground receives.
    pub sky: Vec3,
    /// Whether the sun reaches the ground here (the terrain's shadow ray).
    pub sun_visible: bool,
    /// The bare ground's radiance, returned where there is no forest.
    pub radiance: Vec3,
}

/// Tangents of the probes' zenith angles (0°, 60°, 80°).
const PROBE_TAN: [f32; 3] = [0.0, 1.732_050_8, 5.671_282];
/// Probe rays per angle.
const PROBES: i64 = 1500;

/// One probe: the layer's crown-area index where it ends, the run of its
/// direction there ([`run`]), its angle's index, and whether the stand
/// stopped it.
type Probe = (f32, f32, usize, bool);

/// Rays down through the stand onto its inner 60 % at each of
/// [`PROBE_TAN`]'s angles, from random azimuths, ending on the terrain
/// (stateless hashes of the probe's index under the canopy's seed).
fn probe(inp: &CanopyInput<'_>, far: &Grid2<f32>) -> Vec<Probe> {
    let top = 1.5 * inp.trees.iter().map(|t| t.height).fold(1.0f32, f32::max);
    let cell = inp.terrain.cell_size();
    let seed = inp.seed.derive("canopy.probe");
    let mut out = Vec::new();
    for (ai, &tan) in PROBE_TAN.iter().enumerate() {
        for k in 0..PROBES {
            let u = |c: i64| seed.uniform(&[ai as i64, k, c]) as f32;
            let r = 0.6 * inp.radius * u(0).sqrt();
            let phi = std::f32::consts::TAU * u(1);
            let (x, y) = (inp.eye.x + r * phi.cos(), inp.eye.y + r * phi.sin());
            let (Some(z), Some(n)) = (inp.terrain.height_at(x, y), inp.terrain.normal_at(x, y))
            else {
                continue;
            };
            let a = far.sample_bilinear(x / cell, y / cell, Boundary::Clamp);
            if a <= 0.0 {
                continue;
            }
            let psi = std::f32::consts::TAU * u(2);
            let c = 1.0 / (1.0 + tan * tan).sqrt();
            let d = Vec3::new(-tan * c * psi.cos(), -tan * c * psi.sin(), -c);
            let len = top / c;
            let q = Vec3::new(x, y, z);
            let hit = inp.stand.occluded(q - d * len, d, 0.0, len - 0.3);
            out.push((a, run(d, n), ai, hit));
        }
    }
    out
}

/// The opacity and slant whose Boolean model best matches the probes'
/// stopped fractions at every angle (least squares over a grid of both),
/// and per angle the measured and the fitted fraction; `(1, slant)` and
/// nothing without probes.
fn fit(probes: &[Probe], slant: f32) -> (f32, f32, Vec<(f32, f32)>) {
    let m = PROBE_TAN.len();
    let mut n = vec![0usize; m];
    let mut hit = vec![0usize; m];
    for &(_, _, ai, h) in probes {
        n[ai] += 1;
        hit[ai] += usize::from(h);
    }
    if n.iter().any(|&c| c < 50) {
        return (1.0, slant, Vec::new());
    }
    let measured: Vec<f32> = (0..m).map(|i| hit[i] as f32 / n[i] as f32).collect();
    let predict = |p: f32, s: f32| {
        let mut sum = vec![0.0f64; m];
        for &(a, r, ai, _) in probes {
            sum[ai] += f64::from(1.0 - (-p * a * (1.0 + s * r)).exp());
        }
        (0..m)
            .map(|i| (sum[i] / n[i] as f64) as f32)
            .collect::<Vec<f32>>()
    };
    let mut best = (f32::INFINITY, 1.0, slant);
    for pi in 1..=40 {
        for si in 0..=60 {
            let (p, s) = (0.05 * pi as f32, 0.1 * si as f32);
            let e: f32 = predict(p, s)
                .iter()
                .zip(&measured)
                .map(|(a, b)| (a - b) * (a - b))
                .sum();
            if e < best.0 {
                best = (e, p, s);
            }
        }
    }
    let fitted = predict(best.1, best.2);
    (best.1, best.2, measured.into_iter().zip(fitted).collect())
}

/// The crown-area index per suitability bin: the stand's cells (fully
/// inside it, suitability above 0) averaged per bin, empty bins filled by
/// linear interpolation and held beyond the ends.
fn calibrate(suit: &Grid2<f32>, area: &Grid2<f32>, cell: f32, eye: Vec2, radius: f32) -> Vec<f32> {
    let mut sum = [0.0f64; BINS];
    let mut n = [0u32; BINS];
    for_stand_cells(suit, cell, eye, radius, |i, j, v| {
        let b = bin(v);
        sum[b] += f64::from(area[(i, j)]);
        n[b] += 1;
    });
    let known: Vec<(usize, f32)> = (0..BINS)
        .filter(|&b| n[b] >= MIN_CELLS)
        .map(|b| (b, (sum[b] / f64::from(n[b])) as f32))
        .collect();
    (0..BINS)
        .map(|b| match known.iter().position(|&(k, _)| k >= b) {
            None => known.last().map_or(0.0, |k| k.1),
            Some(0) => known[0].1 * (b as f32 + 0.5) / (known[0].0 as f32 + 0.5),
            Some(q) => {
                let ((b0, v0), (b1, v1)) = (known[q - 1], known[q]);
                let t = (b - b0) as f32 / (b1 - b0) as f32;
                v0 + (v1 - v0) * t
            }
        })
        .collect()
}

/// The bin of suitability `v`.
fn bin(v: f32) -> usize {
    ((v / MAX_SUIT * BINS as f32) as usize).min(BINS - 1)
}

/// The table's value at suitability `v`: linear between bin centres, 0 at
/// suitability 0.
fn table_at(table: &[f32], v: f32) -> f32 {
    if v <= 0.0 {
        return 0.0;
    }
    let x = v / MAX_SUIT * BINS as f32 - 0.5;
    if x <= 0.0 {
        return table[0] * (v / MAX_SUIT * BINS as f32 / 0.5).min(1.0);
    }
    let b = (x as usize).min(BINS - 1);
    let t = x - b as f32;
    let next = table[(b + 1).min(BINS - 1)];
    table[b] + (next - table[b]) * t.min(1.0)
}

/// Calls `f(i, j, suitability)` for every forested terrain cell fully
/// inside the stand (nearer the eye than 70 % of its radius).
fn for_stand_cells(
    suit: &Grid2<f32>,
    cell: f32,
    eye: Vec2,
    radius: f32,
    mut f: impl FnMut(usize, usize, f32),
) {
    let r = 0.7 * radius;
    let (nx, ny) = suit.dims();
    let lo = |v: f32| ((v - r) / cell).floor().max(0.0) as usize;
    let hi = |v: f32, n: usize| (((v + r) / cell).ceil().max(0.0) as usize).min(n - 1);
    for j in lo(eye.y)..=hi(eye.y, ny) {
        for i in lo(eye.x)..=hi(eye.x, nx) {
            let p = Vec2::new(i as f32, j as f32) * cell;
            let v = suit[(i, j)];
            if v > 0.0 && (p - eye).length() <= r {
                f(i, j, v);
            }
        }
    }
}

/// Mean crown-area index of the stand and of the layer's table over the
/// stand's forested cells.
fn means(
    suit: &Grid2<f32>,
    area: &Grid2<f32>,
    far: &Grid2<f32>,
    cell: f32,
    eye: Vec2,
    radius: f32,
) -> (f32, f32) {
    let (mut a, mut b, mut n) = (0.0f64, 0.0f64, 0u64);
    for_stand_cells(suit, cell, eye, radius, |i, j, _| {
        a += f64::from(area[(i, j)]);
        b += f64::from(far[(i, j)]);
        n += 1;
    });
    let n = n.max(1) as f64;
    ((a / n) as f32, (b / n) as f32)
}

/// The canopy's leaf albedo per colour cell: the species' colours at the
/// season, weighted by their suitability at the cell's centre sample.
fn colours(
    inp: &CanopyInput<'_>,
    site: &natura_plant::eco::Site,
    nx: usize,
    ny: usize,
) -> Result<Grid2<Vec3>> {
    let (cx, cy) = (nx.div_ceil(COLOUR_STEP), ny.div_ceil(COLOUR_STEP));
    let fallback = inp
        .species
        .iter()
        .map(|(_, l)| l.leaf_at(inp.season))
        .sum::<Vec3>()
        / inp.species.len().max(1) as f32;
    grid(cx, cy, |ci, cj| {
        let i = (ci * COLOUR_STEP + COLOUR_STEP / 2).min(nx - 1);
        let j = (cj * COLOUR_STEP + COLOUR_STEP / 2).min(ny - 1);
        let (alt, slope) = (site.altitude[(i, j)], site.slope[(i, j)]);
        let (wet, light) = (site.wetness[(i, j)], site.light[(i, j)]);
        let (mut c, mut w) = (Vec3::ZERO, 0.0f32);
        for (sp, look) in &inp.species {
            // Every species counts a little, so the colour varies smoothly
            // across the edges of the bands.
            let s = sp.suitability(wet, light) * if sp.admits(alt, slope) { 1.0 } else { 0.05 };
            c += look.leaf_at(inp.season) * s;
            w += s;
        }
        if w > 0.0 { c / w } else { fallback }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_phase_is_one_at_full_phase_and_zero_at_new() {
        approx::assert_relative_eq!(lambert_phase(1.0), 1.0, epsilon = 1e-6);
        approx::assert_relative_eq!(lambert_phase(-1.0), 0.0, epsilon = 1e-6);
        // Quarter phase: 1/π.
        approx::assert_relative_eq!(
            lambert_phase(0.0),
            std::f32::consts::FRAC_1_PI,
            epsilon = 1e-6
        );
    }

    #[test]
    fn the_table_interpolates_between_known_bins_and_holds_beyond() {
        let mut t = vec![0.0; BINS];
        for (b, v) in t.iter_mut().enumerate() {
            *v = 0.01 * b as f32;
        }
        // At a bin's centre the bin's value.
        let centre = |b: usize| (b as f32 + 0.5) * MAX_SUIT / BINS as f32;
        approx::assert_relative_eq!(table_at(&t, centre(5)), 0.05, epsilon = 1e-6);
        approx::assert_relative_eq!(
            table_at(&t, 0.5 * (centre(5) + centre(6))),
            0.055,
            epsilon = 1e-6
        );
        assert_eq!(table_at(&t, 0.0), 0.0);
        approx::assert_relative_eq!(table_at(&t, 10.0), 0.01 * (BINS - 1) as f32);
    }
}
