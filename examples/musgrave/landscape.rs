//! The landscape pieces Plates 1.2 and 1.3 of `figures_musgrave` share:
//! strata-coloured terrain traced through a medium, ridged multifractal
//! height fields and supersampled pictures.

use natura::atmos::{Dir3, Medium};
use natura::core::filter::PixelFilter;
use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::core::{Grid2, HeightField, Image};
use natura::noise::{Field, Perlin, RidgedMultifractal, RidgedParams, Spectral};
use natura::texture::Footprint;
use natura::texture::earth::Strata;
use natura::trace::{Hit, MipmapTracer, Ray, Tracer};

use crate::common::Exit;

type R<T> = Result<T, Exit>;

/// Terrain seen along rays: coloured by a solid texture, lit by a sun
/// (with shadows) and the sky, through a medium; the sky where a ray
/// misses.
pub(crate) struct Landscape<'a, M> {
    /// The terrain.
    pub tracer: &'a MipmapTracer<'a>,
    /// Its colour (linear RGB) at a point seen from a distance (m).
    pub albedo: &'a dyn Fn(DVec3, f64) -> Vec3,
    /// The air between.
    pub medium: &'a M,
    /// Towards the sun.
    pub sun: Vec3,
    /// The sky's radiance by direction, before the medium.
    pub sky: &'a dyn Fn(Vec3) -> Vec3,
    /// Whether the medium shades the sunlight too (a fog sheet's shadows).
    pub shadows: bool,
}

impl<M: Medium> Landscape<'_, M> {
    /// The radiance reaching `o` from direction `d` (unit).
    pub(crate) fn look(&self, o: Vec3, d: Vec3) -> Vec3 {
        self.shade(o, d, self.tracer.trace(&Ray::new(o, d), 0.0, f32::INFINITY))
    }

    /// [`Landscape::look`] for the ray's terrain hit already traced (`None`:
    /// it leaves the terrain for the sky).
    pub(crate) fn shade(&self, o: Vec3, d: Vec3, hit: Option<Hit>) -> Vec3 {
        let sun_light = Vec3::new(1.0, 0.95, 0.85) * 1.1;
        let sky_light = Vec3::new(0.35, 0.42, 0.55);
        match hit {
            None => match Dir3::new(d.as_dvec3()) {
                Ok(dir) => self
                    .medium
                    .attenuation_to_infinity(o.as_dvec3(), dir)
                    .apply((self.sky)(d).as_dvec3())
                    .as_vec3(),
                Err(_) => Vec3::ZERO,
            },
            Some(h) => {
                let p = h.point.as_dvec3();
                let albedo = (self.albedo)(p, f64::from(h.t));
                let n = h.smooth_normal;
                let lit = n.dot(self.sun).max(0.0);
                let from = Ray::new(h.point + h.geometric_normal * 0.5, self.sun);
                let shadow = lit > 0.0 && self.tracer.occluded(&from, 0.0, f32::INFINITY);
                let direct = if shadow { 0.0 } else { lit };
                let through = match Dir3::new(self.sun.as_dvec3()) {
                    Ok(s) if self.shadows && direct > 0.0 => {
                        let tau = self.medium.optical_depth_to_infinity(p, s);
                        Vec3::new(
                            (-tau.x).exp() as f32,
                            (-tau.y).exp() as f32,
                            (-tau.z).exp() as f32,
                        )
                    }
                    _ => Vec3::ONE,
                };
                let c = albedo * (sun_light * through * direct + sky_light * (0.5 + 0.5 * n.z));
                self.medium
                    .composite(o.as_dvec3(), p, c.as_dvec3())
                    .as_vec3()
            }
        }
    }
}

/// The colour of `strata` at a point, unfiltered (the plates' renders
/// supersample instead).
pub(crate) fn strata_albedo(strata: &Strata) -> impl Fn(DVec3, f64) -> Vec3 + '_ {
    |p, _| strata.colour(p, Footprint::POINT).as_vec3()
}

/// A desert sky: pale at the horizon, blue above.
pub(crate) fn desert_sky(d: Vec3) -> Vec3 {
    let up = d.z.max(0.0);
    Vec3::new(0.80, 0.84, 0.90).lerp(Vec3::new(0.32, 0.48, 0.78), (up * 12.0).min(1.0).sqrt())
}

/// A misty sky: the mist's white at the horizon, pale blue above.
pub(crate) fn misty_sky(d: Vec3) -> Vec3 {
    Vec3::new(0.86, 0.88, 0.92).lerp(Vec3::new(0.45, 0.58, 0.80), d.z.clamp(0.0, 1.0).sqrt())
}

/// The size of the rendered plates and their rays a pixel side: 320 × 180
/// at one ray when `quick`, else 1200 × 675 at 2 × 2.
pub(crate) fn picture_size(quick: bool) -> ((u32, u32), usize) {
    if quick {
        ((320, 180), 1)
    } else {
        ((1200, 675), 2)
    }
}

/// `pixel` at s × s rays on a regular grid in each pixel, resolved by the
/// camera's pixel filter (natura-core's `PixelFilter::camera`).
pub(crate) fn supersampled(
    w: u32,
    h: u32,
    ss: usize,
    mut pixel: impl FnMut(f32, f32) -> Vec3,
) -> R<Image> {
    let step = 1.0 / ss as f32;
    let frame = Grid2::from_fn(w as usize * ss, h as usize * ss, |i, j| {
        pixel((i as f32 + 0.5) * step, (j as f32 + 0.5) * step)
    })?;
    Ok(PixelFilter::camera().resolve(&frame, ss)?)
}

/// Ridged multifractal heights (Musgrave's ridged basis, 9 octaves, H = 1,
/// λ = 2, first wavelength `wavelength` m) on an n × n grid `side` metres
/// across, times `mask(x, y)`; the part below `cut` of the peak dropped and
/// the rest scaled to reach `top` metres.
pub(crate) fn ridged_field(
    seed: u64,
    n: usize,
    side: f64,
    wavelength: f64,
    cut: f64,
    top: f64,
    mask: impl Fn(f64, f64) -> f64,
) -> R<HeightField> {
    let ridged = RidgedMultifractal::new(
        Perlin::new(seed),
        RidgedParams {
            spectral: Spectral {
                h: 1.0,
                lacunarity: 2.0,
                octaves: 9.0,
                frequency: 1.0 / wavelength,
                ..Spectral::default()
            },
            ..RidgedParams::default()
        },
    )?;
    let cell = side / (n - 1) as f64;
    let raw: Vec<f64> = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64 * cell, (k / n) as f64 * cell);
            mask(x, y) * ridged.eval2(DVec2::new(x, y))
        })
        .collect();
    let peak = raw.iter().copied().fold(f64::MIN_POSITIVE, f64::max);
    Ok(HeightField::from_fn(n, n, cell as f32, |i, j| {
        (top * (raw[j * n + i] / peak - cut).max(0.0) / (1.0 - cut)) as f32
    })?)
}

/// 0 below `a`, 1 above `b`, smooth between.
pub(crate) fn smoothstep(a: f64, b: f64, v: f64) -> f64 {
    let t = ((v - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}
