//! Musgrave 1998, figs. 15.7–15.8: "Spirit Lake" (a noise-based water bump
//! map in a multifractal valley) and "Lethe" (a polygon subdivision
//! terrain with water, sedimentary strata and a cratered moon).

use natura::atmos::Medium;
use natura::atmos::medium::{ExponentialMist, HomogeneousFog};
use natura::core::camera::PinholeCamera;
use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::core::{HeightField, Image, Seed};
use natura::noise::{Field, Perlin, StatsByAltitude, StatsByAltitudeParams};
use natura::terrain::synth::{SubdivisionParams, subdivide};
use natura::texture::earth::{Luna, LunaParams, Strata, StrataParams};
use natura::texture::normal::bump;
use natura::texture::water::{Ripples, RipplesParams};
use natura::texture::{Footprint, SolidTexture};
use natura::trace::{MipmapTracer, Ray, Tracer};

use crate::R;
use crate::landscape::{Landscape, misty_sky, picture_size, smoothstep, supersampled};
use crate::patches::rescaled;

/// Water's reflectance at normal incidence (index 1.333).
const F0: f32 = 0.02;

/// The water of a lake: its level, its surface a bump map (a texture's
/// height gradient: the ripples, the book's noise-based water, or the
/// windywave sea) and its own colour.
pub(crate) struct Water<'a> {
    pub level: f32,
    pub ripples: &'a dyn SolidTexture,
    /// Ripple texture units per metre.
    pub per_metre: f64,
    /// The water's own colour, lit.
    pub body: Vec3,
}

/// A lake in a landscape, reflecting the land and the sky by Schlick's
/// Fresnel and showing the dark water below by the rest.
pub(crate) struct Lake<'a, M> {
    pub land: &'a Landscape<'a, M>,
    pub water: Water<'a>,
    /// Footprint of one ray per metre of distance.
    pub ray_angle: f64,
}

impl<M: Medium> Lake<'_, M> {
    /// The radiance reaching `o` from direction `d` (unit).
    pub(crate) fn look(&self, o: Vec3, d: Vec3) -> Vec3 {
        let w = &self.water;
        let land = self.land.tracer.trace(&Ray::new(o, d), 0.0, f32::INFINITY);
        if d.z < 0.0 && o.z > w.level {
            let t = (w.level - o.z) / d.z;
            if land.is_none_or(|h| t < h.t) {
                let p = o + d * t;
                let fp = Footprint::new(f64::from(t) * self.ray_angle * w.per_metre)
                    .unwrap_or(Footprint::POINT);
                let g = w.ripples.height_gradient(p.as_dvec3() * w.per_metre, fp) * w.per_metre;
                let n = bump(DVec3::Z, g).as_vec3();
                let mut r = d - n * (2.0 * d.dot(n));
                if r.z < 1e-3 {
                    r = Vec3::new(r.x, r.y, 1e-3).normalize();
                }
                let cos = (-d.dot(n)).clamp(0.0, 1.0);
                let f = F0 + (1.0 - F0) * (1.0 - cos).powi(5);
                let seen = self.land.look(p + Vec3::Z * 0.05, r);
                let c = seen * f + w.body * (1.0 - f);
                return self
                    .land
                    .medium
                    .composite(o.as_dvec3(), p.as_dvec3(), c.as_dvec3())
                    .as_vec3();
            }
        }
        // The land, or the sky, as traced above.
        self.land.shade(o, d, land)
    }
}

/// The lake picture ([`picture_size`]) seen from `eye` looking north and
/// down by `pitch` radians, `fov` radians from top to bottom.
pub(crate) fn lake_picture<M: Medium>(
    land: &Landscape<'_, M>,
    water: Water<'_>,
    eye: Vec3,
    (pitch, fov): (f32, f32),
    quick: bool,
) -> R<Image> {
    let ((w, h), ss) = picture_size(quick);
    let (s, c) = pitch.sin_cos();
    let cam = PinholeCamera::look_at(eye, eye + Vec3::new(0.0, c, -s), Vec3::Z, fov, w, h)?;
    let lake = Lake {
        land,
        water,
        ray_angle: f64::from(fov) / f64::from(h) / ss as f64,
    };
    supersampled(w, h, ss, |x, y| {
        lake.look(eye, cam.ray_at(x, y).dir.normalize())
    })
}

/// Fig. 15.7's valley: statistics by altitude over the Perlin basis (the
/// multifractal of Plates 2.4–2.5), 4 km by 2 km with 500 m of relief,
/// its lowest 18 % flooded. Returns the field and the lake's level.
pub(crate) fn spirit_lake_valley(seed: u64, n: usize) -> R<(HeightField, f32)> {
    let f = StatsByAltitude::new(Perlin::new(seed), StatsByAltitudeParams::default())?;
    let ny = n / 2;
    let raw: Vec<f64> = (0..n * ny)
        .map(|k| {
            let p = DVec2::new((k % n) as f64, (k / n) as f64) / n as f64;
            f.eval2(p * 4.0)
        })
        .collect();
    let hf = rescaled(&raw, (n, ny), 4000.0 / n as f32, 500.0)?;
    let mut v = hf.heights().as_slice().to_vec();
    v.sort_by(f32::total_cmp);
    Ok((hf, v[(v.len() - 1) * 18 / 100]))
}

/// Fig. 15.7, "Spirit Lake": the valley's lake under a light breeze
/// (ripples a few metres long, stretched across the wind), meadows, rock
/// and snow by altitude, seen from its southern shore through light haze.
fn spirit_lake(seed: u64, quick: bool) -> R<Image> {
    let (hf, level) = spirit_lake_valley(seed, if quick { 256 } else { 1024 })?;
    let tracer = MipmapTracer::new(&hf)?;
    let albedo = |p: DVec3, _| {
        let a = (p.z as f32 - level) / (500.0 - level);
        let meadow = Vec3::new(0.20, 0.30, 0.11);
        let rock = Vec3::new(0.42, 0.37, 0.31);
        let snow = Vec3::new(0.85, 0.87, 0.90);
        let z = f64::from(a);
        meadow
            .lerp(rock, smoothstep(0.25, 0.55, z) as f32)
            .lerp(snow, smoothstep(0.78, 0.9, z) as f32)
    };
    let haze = HomogeneousFog::new(DVec3::new(4e-5, 5e-5, 7e-5), DVec3::new(0.78, 0.83, 0.9))?;
    let land = Landscape {
        tracer: &tracer,
        albedo: &albedo,
        medium: &haze,
        sun: Vec3::new(-0.4, 0.5, 0.55).normalize(),
        sky: &misty_sky,
        shadows: false,
    };
    let ripples = Ripples::new(RipplesParams {
        seed,
        km: 0.02,
        scale: DVec3::new(1.0, 3.0, 1.0),
        ..RipplesParams::default()
    })?;
    let x0 = 2000.0;
    let eye = Vec3::new(
        x0,
        40.0,
        hf.height_at(x0, 40.0).unwrap_or(0.0).max(level) + 45.0,
    );
    let water = Water {
        level,
        ripples: &ripples,
        per_metre: 1.0 / 6.0,
        body: Vec3::new(0.012, 0.025, 0.03),
    };
    lake_picture(&land, water, eye, (0.06, 0.6), quick)
}

/// Fig. 15.8's terrain: Fournier–Fussell–Carpenter subdivision (the
/// default H = 0.8), 3 km square, over a basin 2 km across in its middle
/// (a parabola twice the subdivision's standard deviation deep at 1 km), stretched
/// to 420 m of relief, its lowest quarter flooded.
pub(crate) fn lethe_terrain(seed: u64, n: usize) -> R<(HeightField, f32)> {
    let sub = subdivide(
        n,
        n,
        3000.0 / (n - 1) as f32,
        &SubdivisionParams::default(),
        Seed(seed),
    )?;
    let z = sub.heights().as_slice();
    let mean = z.iter().map(|&v| f64::from(v)).sum::<f64>() / z.len() as f64;
    let sd = (z
        .iter()
        .map(|&v| (f64::from(v) - mean).powi(2))
        .sum::<f64>()
        / z.len() as f64)
        .sqrt();
    let raw: Vec<f64> = (0..n * n)
        .map(|k| {
            let p = DVec2::new((k % n) as f64, (k / n) as f64) / (n - 1) as f64 - 0.5;
            let bowl = (p.length() / 0.33).powi(2).min(1.6);
            f64::from(z[k]) + 2.0 * sd * bowl
        })
        .collect();
    let hf = rescaled(&raw, (n, n), 3000.0 / (n - 1) as f32, 420.0)?;
    let mut v = hf.heights().as_slice().to_vec();
    v.sort_by(f32::total_cmp);
    Ok((hf, v[(v.len() - 1) / 4]))
}

/// The moon of Fig. 15.8: natura-texture's `Luna` on a disc `radius`
/// radians across centred on `towards`, lit from `sun`, over `sky`.
fn with_moon(sky: Vec3, d: Vec3, towards: Vec3, radius: f32, luna: &Luna, sun: Vec3) -> Vec3 {
    let (u, v) = towards.any_orthonormal_pair();
    let (x, y) = (d.dot(u) / radius, d.dot(v) / radius);
    let r2 = x * x + y * y;
    if d.dot(towards) <= 0.0 || r2 >= 1.0 {
        return sky;
    }
    // The moon's sphere point facing the viewer, its normal.
    let n = u * x + v * y - towards * (1.0 - r2).sqrt();
    let c = luna.sample(n.as_dvec3(), Footprint::POINT).colour.as_vec3();
    let lit = n.dot(sun).max(0.0);
    sky + c * (0.9 * lit)
}

/// Fig. 15.8, "Lethe": the jagged subdivision terrain banded by
/// sedimentary strata, a still lake with faint ripples reflecting it, and
/// a large cratered moon in a dusk sky.
fn lethe(seed: u64, quick: bool) -> R<Image> {
    let (hf, level) = lethe_terrain(seed, if quick { 129 } else { 513 })?;
    let tracer = MipmapTracer::new(&hf)?;
    let strata = Strata::new(StrataParams {
        seed,
        txtscale: 1.0 / 40.0,
        ..StrataParams::default()
    })?;
    let albedo = |p: DVec3, _| strata.colour(p, Footprint::POINT).as_vec3();
    // Mist thinning upwards, so the sky and the moon show through it.
    let haze = ExponentialMist::new(
        DVec3::new(1.2e-4, 1.4e-4, 1.8e-4),
        DVec3::new(0.45, 0.42, 0.50),
        0.0,
        300.0,
    )?;
    let luna = Luna::new(LunaParams {
        seed,
        ..LunaParams::default()
    })?;
    let sun = Vec3::new(0.8, 0.3, 0.25).normalize();
    let moon = Vec3::new(-0.35, 1.0, 0.14).normalize();
    let sky = |d: Vec3| {
        let up = d.z.max(0.0).sqrt();
        let dusk = Vec3::new(0.55, 0.45, 0.55).lerp(Vec3::new(0.10, 0.12, 0.28), up);
        with_moon(dusk, d, moon, 0.06, &luna, sun)
    };
    let land = Landscape {
        tracer: &tracer,
        albedo: &albedo,
        medium: &haze,
        sun,
        sky: &sky,
        shadows: false,
    };
    let ripples = Ripples::new(RipplesParams {
        seed: seed ^ 1,
        km: 0.006,
        ..RipplesParams::default()
    })?;
    // From the basin's southern rim, 60 m over the ground, looking north
    // across the lake.
    let (x0, y0) = (1500.0, 380.0);
    let eye = Vec3::new(
        x0,
        y0,
        hf.height_at(x0, y0).unwrap_or(0.0).max(level) + 60.0,
    );
    let water = Water {
        level,
        ripples: &ripples,
        per_metre: 1.0 / 4.0,
        body: Vec3::new(0.01, 0.015, 0.02),
    };
    lake_picture(&land, water, eye, (0.07, 0.6), quick)
}

/// Figs. 15.7 and 15.8.
pub(crate) fn pair(seed: u64, quick: bool) -> R<Vec<Image>> {
    Ok(vec![spirit_lake(seed, quick)?, lethe(seed, quick)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn still_water_mirrors_the_sky_by_fresnel() {
        // A flooded flat field, still water (no ripples), clear air: a ray
        // meeting the water at 45° sees F(45°)·sky(reflected) plus the
        // water's own colour for the rest.
        let hf = HeightField::from_fn(9, 9, 10.0, |_, _| 0.0).unwrap();
        let tracer = MipmapTracer::new(&hf).unwrap();
        let clear = HomogeneousFog::new(DVec3::ZERO, DVec3::ZERO).unwrap();
        let sky = |d: Vec3| Vec3::new(0.2, 0.4, 0.8) * (1.0 + d.z);
        let albedo = |_: DVec3, _| Vec3::ONE;
        let land = Landscape {
            tracer: &tracer,
            albedo: &albedo,
            medium: &clear,
            sun: Vec3::Z,
            sky: &sky,
            shadows: false,
        };
        let ripples = Ripples::new(RipplesParams {
            km: 0.0,
            ..RipplesParams::default()
        })
        .unwrap();
        let body = Vec3::new(0.01, 0.02, 0.03);
        let lake = Lake {
            land: &land,
            water: Water {
                level: 1.0,
                ripples: &ripples,
                per_metre: 1.0,
                body,
            },
            ray_angle: 0.0,
        };
        let d = Vec3::new(0.0, 1.0, -1.0).normalize();
        let got = lake.look(Vec3::new(40.0, 20.0, 11.0), d);
        let f = F0 + (1.0 - F0) * (1.0 - d.z.abs()).powi(5);
        let want = sky(Vec3::new(0.0, d.y, -d.z)) * f + body * (1.0 - f);
        assert!((got - want).abs().max_element() < 1e-5, "{got} {want}");
        // Above the water, the sky itself.
        let up = Vec3::new(0.0, 0.6, 0.8);
        assert!(
            (lake.look(Vec3::new(40.0, 20.0, 11.0), up) - sky(up))
                .abs()
                .max_element()
                < 1e-6
        );
    }

    #[test]
    fn lethes_lake_lies_in_the_middle_of_its_basin() {
        // More of the basin's middle is under water than of its rim.
        for seed in [1993, 7] {
            let (hf, level) = lethe_terrain(seed, 129).unwrap();
            let (mut inner, mut outer) = ((0, 0), (0, 0));
            for j in 0..129 {
                for i in 0..129 {
                    let r = DVec2::new(i as f64 / 128.0 - 0.5, j as f64 / 128.0 - 0.5).length();
                    let wet = usize::from(hf.heights()[(i, j)] <= level);
                    if r < 0.25 {
                        inner = (inner.0 + wet, inner.1 + 1);
                    } else if r > 0.4 {
                        outer = (outer.0 + wet, outer.1 + 1);
                    }
                }
            }
            let (fi, fo) = (
                inner.0 as f64 / inner.1 as f64,
                outer.0 as f64 / outer.1 as f64,
            );
            assert!(fi > 2.0 * fo && fi > 0.4, "inner {fi}, outer {fo}");
        }
    }
}
