//! The planet's relief: the terran texture's chaos as height in metres, with
//! the bounds sphere tracing needs.

use glam::DVec3;

use natura_noise::{Fbm, Perlin};

use crate::earth::Terran;
use crate::error::{Result, non_negative, positive};
use crate::footprint::Footprint;
use crate::fractals::{fbm, spectral};
use crate::planet::params::PlanetDetailParams;

/// The octaves below the continents: an fBm continuing theirs (octave
/// `K + j` at frequency `f₀λ^(K+j)`), scaled by the continents' amplitude
/// at octave `K`.
#[derive(Debug)]
struct Detail {
    fbm: Fbm<Perlin>,
    /// Octaves of the continents before the detail starts.
    first: usize,
    /// Amplitude of the detail's first octave.
    scale: f64,
}

/// The displaced surface of a terrain planet: radius `R + h(dir)` in the unit
/// direction `dir`, with
///
/// ```text
/// h(dir) = relief_m·mtn_scale·max(b(S·dir) + offset − sea_level, 0)
/// ```
///
/// `b` the [`Terran`] texture's continents, evaluated in `f64` at the point
/// `S·dir` of the texture sphere (`S` = texture units per radius) and band
/// limited to the footprint. Oceans are the flat sea-level sphere `R`; land
/// rises continuously from the coastline. The texture's bump (a normal
/// perturbation of `bump_scale·b`, which jumps at the coast when
/// `offset ≠ sea_level`) is replaced by this displacement.
///
/// Precision: every coordinate stays `f64` from the world point to the
/// lattice, so at `R = 6 371 km` a 1 cm octave (lattice coordinates near
/// 6·10⁸) still resolves a millimetre to about 10⁻⁷ of a cell.
///
/// With [`PlanetDetailParams`] the continents' fBm is continued below its last
/// octave `K` by a second fBm of exponent `H_d`, octave `K + j` having
/// amplitude `λ^(−K·H)·λ^(−j·H_d)`: the two read as one fractal whose
/// spectrum steepens at the lower crossover.
///
/// The bounds sphere tracing needs — of the bump summed over `v` octaves
/// and of its slope — are tabulated per whole octave when the relief is
/// built; both are linear in the fraction of the last octave, so the tables
/// interpolate exactly. The slope bound is taken with the multifractal's
/// domain distortion at full strength (it only fades for footprints wider
/// than a fifth of the texture sphere), so it holds for every footprint.
#[derive(Debug)]
pub struct Relief {
    terran: Terran,
    detail: Option<Detail>,
    radius: f64,
    metres: f64,
    scale: f64,
    max_height: f64,
    ln_lacunarity: f64,
    total: f64,
    bound: Vec<f64>,
    slope: Vec<f64>,
    /// `tail[k]`: the summed squares of the per-octave bounds from octave `k` on.
    tail: Vec<f64>,
}

/// The RMS of one octave of the bump as a fraction of its bound (measured
/// over the sphere: 0.26 for Perlin octaves, whose bound is 1).
const OCTAVE_RMS: f64 = 0.26;

impl Relief {
    /// The relief of `terran` on a planet of radius `radius` (m), `relief_m`
    /// metres per unit of chaos, `texture_scale` texture units per radius,
    /// with optional `detail` below the continents.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) for a non-positive radius or
    /// scale, a negative relief, or detail parameters whose octaves fail
    /// natura-noise's checks.
    pub fn new(
        terran: Terran,
        radius: f64,
        relief_m: f64,
        texture_scale: f64,
        detail: Option<PlanetDetailParams>,
    ) -> Result<Self> {
        positive("radius_m", radius)?;
        non_negative("relief_m", relief_m)?;
        positive("texture_scale", texture_scale)?;
        let q = *terran.params();
        let metres = relief_m * q.mtn_scale.abs();
        let cs = *terran.continents_spectral();
        let mut total = cs.octaves;
        let detail = match (detail, terran.continents_fbm()) {
            (Some(d), Some(_)) => {
                d.validate()?;
                let k = cs.octaves as usize;
                let finest = super::params::detail_finest_octave(radius, texture_scale, &cs, &d)?;
                let octaves = finest - k as f64;
                if octaves > 0.0 {
                    total = finest;
                    let mut s = spectral(d.h, cs.lacunarity, octaves);
                    s.frequency = cs.frequency * cs.lacunarity.powi(k as i32);
                    Some(Detail {
                        fbm: fbm(q.seed, "detail", s)?,
                        first: k,
                        scale: terran
                            .continents_fbm()
                            .map_or(1.0, |f| f.spectral().gain().powi(k as i32)),
                    })
                } else {
                    None
                }
            }
            _ => None,
        };
        let n = total.ceil() as usize;
        let mut relief = Self {
            max_height: 0.0,
            ln_lacunarity: cs.lacunarity.ln(),
            terran,
            detail,
            radius,
            metres,
            scale: texture_scale,
            total,
            bound: Vec::new(),
            slope: Vec::new(),
            tail: Vec::new(),
        };
        relief.bound = (0..=n).map(|k| relief.bound_at(k as f64)).collect();
        relief.slope = (0..=n).map(|k| relief.slope_at(k as f64)).collect();
        let mut tail = vec![0.0; n + 1];
        for k in (0..n).rev() {
            let b = relief.bound[k + 1] - relief.bound[k];
            tail[k] = tail[k + 1] + b * b;
        }
        relief.tail = tail;
        let max_chaos = relief.bound_at(f64::INFINITY) + q.offset - q.sea_level;
        relief.max_height = metres * max_chaos.max(0.0);
        Ok(relief)
    }

    /// A bound on the bump over `v` visible octaves (continents and detail).
    fn bound_at(&self, v: f64) -> f64 {
        let c = self.terran.bump_bound_visible(v);
        match &self.detail {
            Some(d) => c + d.scale * d.fbm.bound_band(v - d.first as f64),
            None => c,
        }
    }

    /// A Lipschitz constant of the bump over `v` visible octaves.
    fn slope_at(&self, v: f64) -> f64 {
        let c = self
            .terran
            .bump_lipschitz_visible(Footprint::POINT, v, self.scale);
        match &self.detail {
            Some(d) => c + d.scale * d.fbm.lipschitz3_band(v - d.first as f64),
            None => c,
        }
    }

    /// Interpolates a per-octave table at `v` visible octaves.
    fn table(&self, t: &[f64], v: f64) -> f64 {
        let v = v.clamp(0.0, self.total);
        let k = (v as usize).min(t.len() - 1);
        match t.get(k + 1) {
            Some(&next) => t[k] + (v - k as f64) * (next - t[k]),
            None => t[k],
        }
    }

    /// The terran texture.
    #[must_use]
    pub fn terran(&self) -> &Terran {
        &self.terran
    }

    /// The sea-level radius `R`, metres.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// A bound on the height, metres (the shell `R ≤ r ≤ R + max_height`
    /// holds the whole surface).
    #[must_use]
    pub fn max_height(&self) -> f64 {
        self.max_height
    }

    /// The footprint in texture units of a footprint of `metres` on the surface.
    #[must_use]
    pub fn footprint(&self, metres: f64) -> Footprint {
        Footprint::new(metres.max(0.0) * self.scale / self.radius).unwrap_or(Footprint::POINT)
    }

    /// The texture-sphere point of the unit direction `dir`.
    #[must_use]
    pub fn texture_point(&self, dir: DVec3) -> DVec3 {
        dir * self.scale
    }

    /// The number of the continents' octaves footprint `fp` shows.
    #[must_use]
    pub fn visible(&self, fp: Footprint) -> f64 {
        self.terran.visible(fp)
    }

    /// The bump value `b` (continents and detail) in direction `dir`.
    #[must_use]
    pub fn bump(&self, dir: DVec3, fp: Footprint) -> f64 {
        let q = self.texture_point(dir);
        let b = self.terran.bump(q, fp);
        match &self.detail {
            Some(d) => {
                let v = self.visible(fp) - d.first as f64;
                b + d.scale * d.fbm.eval3_band(q, v)
            }
            None => b,
        }
    }

    /// How far the chaos of bump value `b` is above sea level (negative at sea).
    #[must_use]
    pub fn chaos_above_sea(&self, b: f64) -> f64 {
        let q = self.terran.params();
        b + q.offset - q.sea_level
    }

    /// Metres of height per unit of chaos above sea level.
    #[must_use]
    pub fn metres_per_chaos(&self) -> f64 {
        self.metres
    }

    /// The height for bump value `b`, metres.
    #[must_use]
    pub fn height_of(&self, b: f64) -> f64 {
        self.metres * self.chaos_above_sea(b).max(0.0)
    }

    /// The height above `R` in unit direction `dir`, metres.
    #[must_use]
    pub fn height(&self, dir: DVec3, fp: Footprint) -> f64 {
        self.height_of(self.bump(dir, fp))
    }

    /// A bound on `|b|` summed over `visible` octaves; the difference of two
    /// such bounds bounds the octaves between them.
    #[must_use]
    pub fn bump_bound(&self, visible: f64) -> f64 {
        self.table(&self.bound, visible)
    }

    /// The height and its gradient with respect to the texture-sphere point
    /// (metres per texture unit).
    #[must_use]
    pub fn height_grad(&self, dir: DVec3, fp: Footprint) -> (f64, DVec3) {
        let (b, g) = self.bump_grad(dir, fp);
        if self.terran.is_land(b) {
            (self.height_of(b), g * self.metres)
        } else {
            (0.0, DVec3::ZERO)
        }
    }

    /// The outward unit normal of the displaced surface at the world point
    /// `p` (on or near the surface).
    #[must_use]
    pub fn normal(&self, p: DVec3, fp: Footprint) -> DVec3 {
        self.normal_and_bump(p, fp).0
    }

    /// The outward unit normal at `p` and the bump value there (one
    /// evaluation of the fractal and its gradient).
    #[must_use]
    pub fn normal_and_bump(&self, p: DVec3, fp: Footprint) -> (DVec3, f64) {
        let (n, b, _) = self.normal_bump_and_land(p, fp);
        (n, b)
    }

    /// The RMS of the bump's octaves too fine for `visible` octaves (the
    /// part of the one straddling it that is faded out, and every finer
    /// one): 0.26 (the measured RMS of one octave over its bound) times the
    /// root of their summed squared bounds.
    #[must_use]
    pub fn unresolved_rms(&self, visible: f64) -> f64 {
        let n = self.tail.len() - 1;
        let v = visible.clamp(0.0, n as f64);
        let k = (v as usize).min(n);
        let part = if k < n {
            let b = (self.bound[k + 1] - self.bound[k]) * (1.0 - (v - k as f64));
            b * b + self.tail[k + 1]
        } else {
            0.0
        };
        OCTAVE_RMS * part.sqrt()
    }

    /// The half-width `a` of the smoothstep that filters the coast at
    /// footprint `fp` where the bump's gradient along the sphere is
    /// `along` (per texture unit): `a = √5·σ`, `σ² = (|∇b|·w)²/12 + σ_f²`
    /// the variance of the chaos over the footprint — its linear change
    /// across a box of width `w`, and the unresolved octaves' `σ_f` —
    /// matched to `smoothstep(−a, a, ·)` read as a distribution (variance
    /// `a²/5`).
    #[must_use]
    pub fn coast_width(&self, along: f64, fp: Footprint) -> f64 {
        let linear = along * fp.width();
        let fine = self.unresolved_rms(self.visible(fp));
        (5.0 * (linear * linear / 12.0 + fine * fine)).sqrt()
    }

    /// The outward unit normal at `p`, the bump value there, and the
    /// fraction of the footprint `fp` that is land: the coast, a level set
    /// of the bump, filtered over the footprint as
    /// `smoothstep(−a, a, chaos)` ([`coast_width`](Self::coast_width)) of
    /// the chaos above sea level: the share of land a footprint whose chaos
    /// varies about the centre's with the gradient across it and with the
    /// octaves too fine to sum holds, so coastlines are anti-aliased
    /// instead of a staircase of whole pixels, and a coast seen coarsely
    /// holds as much land as the finer coast it stands for.
    #[must_use]
    pub fn normal_bump_and_land(&self, p: DVec3, fp: Footprint) -> (DVec3, f64, f64) {
        let (n, b, land, _) = self.normal_bump_land_width(p, fp);
        (n, b, land)
    }

    /// [`normal_bump_and_land`](Self::normal_bump_and_land) and the coast's
    /// half-width `a` in chaos.
    #[must_use]
    pub fn normal_bump_land_width(&self, p: DVec3, fp: Footprint) -> (DVec3, f64, f64, f64) {
        let r = p.length();
        let n = p / r;
        let (b, g) = self.bump_grad(n, fp);
        let along = (g - n * n.dot(g)).length();
        let chaos = self.chaos_above_sea(b);
        let a = self.coast_width(along, fp);
        let land = if a > 0.0 {
            crate::footprint::smoothstep(-a, a, chaos)
        } else if chaos > 0.0 {
            1.0
        } else {
            0.0
        };
        let g = if self.terran.is_land(b) {
            g * self.metres
        } else {
            DVec3::ZERO
        };
        let tangential = g - n * n.dot(g);
        ((n - tangential * (self.scale / r)).normalize(), b, land, a)
    }

    /// The bump value and its gradient with respect to the texture-sphere
    /// point, continents and detail.
    #[must_use]
    pub fn bump_grad(&self, dir: DVec3, fp: Footprint) -> (f64, DVec3) {
        let q = self.texture_point(dir);
        let (mut b, mut g) = self.terran.bump_grad(q, fp);
        if let Some(d) = &self.detail {
            let v = self.visible(fp) - d.first as f64;
            let (db, dg) = d.fbm.eval_grad3_band(q, v);
            b += d.scale * db;
            g += dg * d.scale;
        }
        (b, g)
    }

    /// A Lipschitz constant of the height along the surface: metres of
    /// height per metre of movement at radius `R` or above.
    #[must_use]
    pub fn lipschitz(&self, fp: Footprint) -> f64 {
        self.lipschitz_visible(self.visible(fp))
    }

    /// [`lipschitz`](Self::lipschitz) for the height summed over `visible` octaves.
    #[must_use]
    pub fn lipschitz_visible(&self, visible: f64) -> f64 {
        self.metres * self.table(&self.slope, visible) * self.scale / self.radius
    }

    /// A bound on `|∂h/∂v|` in metres, `v` the visible octave count.
    #[must_use]
    pub fn band_slope(&self, visible: f64) -> f64 {
        if !(0.0..self.total).contains(&visible) {
            return 0.0;
        }
        let k = visible as usize;
        self.metres * (self.bound[k + 1] - self.bound[k])
    }

    /// `ln λ` of the continents (the visible octave count changes by
    /// `1/(t·ln λ)` per metre along a ray at distance `t`).
    #[must_use]
    pub fn ln_lacunarity(&self) -> f64 {
        self.ln_lacunarity
    }

    /// Starts an octave-by-octave evaluation of the bump in direction `dir`.
    pub(crate) fn probe(&self, dir: DVec3, fp: Footprint) -> Probe<'_> {
        let visible = self.visible(fp);
        Probe {
            relief: self,
            point: self.texture_point(dir),
            fp,
            visible,
            sum: 0.0,
            done: 0,
        }
    }
}

/// The bump at one point summed octave by octave, so a ray march can stop
/// as soon as the first octaves and a bound of the rest decide its step.
pub(crate) struct Probe<'a> {
    relief: &'a Relief,
    point: DVec3,
    fp: Footprint,
    /// Octaves the footprint shows.
    pub(crate) visible: f64,
    sum: f64,
    done: usize,
}

impl Probe<'_> {
    /// The bump summed over the first `m` octaves (`m ≤ visible`), reusing
    /// the octaves already summed (fBm continents and detail; the
    /// multifractal is summed afresh).
    pub(crate) fn partial(&mut self, m: usize) -> f64 {
        let r = self.relief;
        let Some(cont) = r.terran.continents_fbm() else {
            return r.terran.bump_visible(self.point, self.fp, m as f64);
        };
        let mut terms = [0.0f64; 64];
        while self.done < m {
            let (f, first, scale, v) = match &r.detail {
                Some(d) if self.done >= d.first => {
                    (&d.fbm, d.first, d.scale, self.visible - d.first as f64)
                }
                Some(d) => (cont, 0, 1.0, self.visible.min(d.first as f64)),
                None => (cont, 0, 1.0, self.visible),
            };
            let end = match &r.detail {
                Some(d) if self.done < d.first => m.min(d.first),
                _ => m,
            };
            let n = (end - self.done).min(64);
            f.eval3_band_terms(self.point, v, self.done - first, &mut terms[..n]);
            for x in &terms[..n] {
                self.sum += scale * x;
            }
            self.done += n;
        }
        self.sum
    }

    /// The bump over every visible octave.
    pub(crate) fn full(&mut self) -> f64 {
        let r = self.relief;
        if r.terran.continents_fbm().is_none() {
            return r.bump(self.point / r.scale, self.fp);
        }
        let n = self.visible.clamp(0.0, r.total).ceil() as usize;
        self.partial(n)
    }
}
