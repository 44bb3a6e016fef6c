//! Musgrave 1993, Pl. 8.1 for `figures_musgrave`: "A panoramic rendering of
//! the Valles Marineris on Mars" through the panoramic virtual screen
//! (§8.3–8.4), 370° by 180°: nearly straight, parallel canyons bow across
//! the picture, and the screen's vertical sampling repeats past 360°.
//!
//! The source traced the USGS's elevation data derived from Viking images,
//! which natura does not have: the height field here is a synthetic canyon
//! system of the same morphology (the differences are listed in
//! docs/figures.md). Three troughs run east–west, nearly parallel, cut 4–7
//! km into a cratered plateau; their walls are steep at the rim and ease
//! into talus at the floor, with spurs and gullies. As in the plate, a
//! procedural texture with adaptive level of detail (natura-texture's
//! strata, their octaves limited to a pixel's footprint) shows the
//! topography, the triangles are shaded with smooth normals, and the sun
//! casts shadows; a dust haze thins with altitude.

use natura::atmos::medium::ExponentialMist;
use natura::atmos::{Dir3, Medium};
use natura::core::camera::{PanoramicCamera, Projection};
use natura::core::filter::PixelFilter;
use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::core::{Grid2, HeightField, Image, Seed};
use natura::noise::{Fbm, Field, Perlin, Spectral};
use natura::texture::Footprint;
use natura::texture::earth::{Strata, StrataParams};
use natura::trace::{MipmapTracer, Ray, Tracer};

use crate::common::Exit;
use crate::landscape::smoothstep;

type R<T> = Result<T, Exit>;

/// The field's side, m (the canyons' length in view).
pub(crate) const SIDE_M: f64 = 160_000.0;

/// One trough of the canyon system, along x.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Trough {
    /// Its axis's distance from the field's southern edge, m.
    pub y: f64,
    /// Half the width of its floor, m.
    pub half_floor: f64,
    /// The horizontal width of each wall, rim to floor, m.
    pub wall: f64,
    /// Its depth below the plateau, m.
    pub depth: f64,
    /// Where it begins and ends along x, m (it closes in a rounded head).
    pub x: (f64, f64),
}

/// The synthetic canyon system: a main trough flanked by two narrower ones
/// (the source's proportions are those of Valles Marineris' central
/// chasmata, scaled to a 160 km field: walls several km high, floors wider
/// than the walls).
pub(crate) const TROUGHS: [Trough; 3] = [
    Trough {
        y: 34_000.0,
        half_floor: 5_000.0,
        wall: 7_000.0,
        depth: 4_000.0,
        x: (-40_000.0, 125_000.0),
    },
    Trough {
        y: 80_000.0,
        half_floor: 13_000.0,
        wall: 10_000.0,
        depth: 6_500.0,
        x: (-40_000.0, 200_000.0),
    },
    Trough {
        y: 126_000.0,
        half_floor: 6_000.0,
        wall: 8_000.0,
        depth: 5_000.0,
        x: (30_000.0, 200_000.0),
    },
];

/// The depth of a wall, as a fraction of the trough's, at `u` across it
/// (0 at the floor's edge, 1 at the rim): `1 − u³`, a cliff at the rim
/// (slope 3 in these units) easing into talus at the floor (slope 0).
pub(crate) fn wall_profile(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    1.0 - u * u * u
}

/// An fBm of Perlin noise: 1/f^(2h+1), `octaves` from wavelength `wavelength` m.
fn fbm(seed: u64, h: f64, octaves: f64, wavelength: f64) -> R<Fbm<Perlin>> {
    Ok(Fbm::new(
        Perlin::new(seed),
        Spectral {
            h,
            lacunarity: 2.0,
            octaves,
            frequency: 1.0 / wavelength,
            ..Spectral::default()
        },
    )?)
}

/// A crater: centre, radius (m).
type Crater = (DVec2, f64);

/// 48 craters on the field, radii 0.6–6 km from a power law (more small
/// than large), placed at random.
fn craters(seed: u64) -> Vec<Crater> {
    let s = Seed(seed).derive("craters");
    (0..48)
        .map(|k| {
            let k = k as i64;
            let c = DVec2::new(s.uniform2(k, 0), s.uniform2(k, 1)) * SIDE_M;
            // The cumulative count of craters larger than r falls as r⁻²:
            // r = r_min·(1 − u)^(−1/2), capped.
            let r = (600.0 * (1.0 - 0.97 * s.uniform2(k, 2)).powf(-0.5)).min(6_000.0);
            (c, r)
        })
        .collect()
}

/// A crater's relief at distance `d` from its centre: a bowl 0.2 r deep
/// inside a raised rim 0.04 r high that fades over a quarter radius outside.
fn crater_relief(d: f64, r: f64) -> f64 {
    let q = d / r;
    let bowl = if q < 1.0 {
        0.2 * r * (q * q - 1.0)
    } else {
        0.0
    };
    bowl + 0.04 * r * (-((q - 1.0) / 0.25).powi(2)).exp()
}

/// The canyon system's heights on an `n × n` grid over [`SIDE_M`] (the
/// plateau near 0 m).
pub(crate) fn canyon_field(seed: u64, n: usize) -> R<HeightField> {
    let warp = fbm(seed, 0.8, 4.0, 40_000.0)?;
    let plateau = fbm(seed.wrapping_add(1), 0.8, 8.0, 15_000.0)?;
    let spurs = fbm(seed.wrapping_add(2), 0.6, 5.0, 6_000.0)?;
    let gullies = fbm(seed.wrapping_add(3), 0.7, 5.0, 1.0)?;
    let floor = fbm(seed.wrapping_add(4), 0.9, 6.0, 8_000.0)?;
    let craters = craters(seed);
    let cell = SIDE_M / (n - 1) as f64;
    let h = Grid2::par_from_fn(n, n, |i, j| {
        let p = DVec2::new(i as f64, j as f64) * cell;
        // The axes wander by a few km; the walls' width varies by half,
        // which makes spurs and alcoves; gullies run down the walls (the
        // noise stretched across the trough, along y).
        let yw = p.y + 3_000.0 * warp.eval2(p);
        let spur = 1.0 + 0.5 * spurs.eval2(p);
        let gully = gullies.eval2(DVec2::new(p.x / 1_500.0, p.y / 9_000.0));
        let (mut cut, mut open) = (0.0f64, 0.0f64);
        for t in &TROUGHS {
            // Beyond its ends a trough closes: the lateral distance grows.
            let past = (t.x.0 - p.x).max(p.x - t.x.1).max(0.0);
            let d = (yw - t.y).abs().hypot(past);
            let wall = t.wall * spur;
            let u = (d - t.half_floor) / wall;
            let g = wall_profile(u);
            let on_wall = if (0.0..1.0).contains(&u) {
                4.0 * u * (1.0 - u)
            } else {
                0.0
            };
            let floor_relief = 250.0 * floor.eval2(p) * g;
            cut = cut.max(t.depth * g + 350.0 * gully * on_wall + floor_relief);
            open = open.max(g);
        }
        let mut z = 150.0 * plateau.eval2(p);
        for &(c, r) in &craters {
            let d = p.distance(c);
            if d < 2.0 * r {
                z += crater_relief(d, r);
            }
        }
        (z * (1.0 - open) - cut) as f32
    })?;
    Ok(HeightField::new(h, cell as f32)?)
}

/// Pl. 8.1's field of view, degrees.
pub(crate) const FOV_DEG: (f32, f32) = (370.0, 180.0);

/// The dust haze: extinction at the plateau (per metre, most in blue: the
/// dust is red) thinning by `e` every 11 km, Mars's scale height.
fn haze() -> R<ExponentialMist> {
    Ok(ExponentialMist::new(
        DVec3::new(0.5e-5, 0.7e-5, 1.0e-5),
        DVec3::new(0.62, 0.42, 0.28),
        0.0,
        11_000.0,
    )?)
}

/// The Martian sky by direction (linear RGB): butterscotch at the horizon,
/// darker overhead, brighter about the sun.
fn sky(d: Vec3, sun: Vec3) -> Vec3 {
    let up = d.z.max(0.0).sqrt();
    let base = Vec3::new(0.70, 0.47, 0.31).lerp(Vec3::new(0.32, 0.21, 0.15), up);
    let glow = (-(d.dot(sun).clamp(-1.0, 1.0)).acos() / 0.2).exp();
    base + Vec3::new(0.9, 0.8, 0.7) * (0.5 * glow)
}

/// The panoramic camera of the plate: 1.5 km above the plateau over the
/// main trough, a little north of its axis, facing east along the canyons.
pub(crate) fn camera(w: u32, h: u32) -> R<PanoramicCamera> {
    let main = TROUGHS[1];
    let (x, y) = (60_000.0f32, (main.y + 0.3 * main.half_floor) as f32);
    Ok(PanoramicCamera::new(
        Vec3::new(x, y, EYE_M),
        Vec3::X,
        Vec3::Z,
        FOV_DEG.0.to_radians(),
        FOV_DEG.1.to_radians(),
        Projection::Spherical,
        w,
        h,
    )?)
}

/// The eye's altitude, m (the plateau lies near 0 m).
const EYE_M: f32 = 1_500.0;

/// Pl. 8.1: the panorama, 1480 × 720 at 2 × 2 rays a pixel (370 × 180 at
/// one when `quick`).
pub(crate) fn picture(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 257 } else { 1025 };
    let hf = canyon_field(seed, n)?;
    let tracer = MipmapTracer::new(&hf)?;
    let ((w, h), ss) = if quick {
        ((370u32, 180u32), 1usize)
    } else {
        ((1480, 720), 2)
    };
    let cam = camera(w, h)?;
    let strata = Strata::new(StrataParams {
        seed,
        txtscale: 1.0 / 4_000.0,
        turbscale: 0.08,
        ..StrataParams::default()
    })?;
    let dust_edge = fbm(seed.wrapping_add(5), 0.7, 5.0, 600.0)?;
    let dunes = fbm(seed.wrapping_add(6), 0.6, 5.0, 5_000.0)?;
    let haze = haze()?;
    let sun = Vec3::new(0.35, -0.75, 0.42).normalize();
    let pixel_angle = f64::from(FOV_DEG.0.to_radians()) / f64::from(w * ss as u32);
    // Linear RGB: the strata's tans reddened, fine dust on the flats, dark
    // basaltic sand on the canyon floors.
    let tint = DVec3::new(1.05, 0.62, 0.42);
    let dust = DVec3::new(0.52, 0.24, 0.11);
    let sand = DVec3::new(0.20, 0.11, 0.07);
    let shade = |ray: Ray| -> Vec3 {
        let o = ray.origin;
        let d = ray.dir.normalize();
        let Some(hit) = tracer.trace(&Ray::new(o, d), 0.0, f32::INFINITY) else {
            return match Dir3::new(d.as_dvec3()) {
                Ok(dir) => haze
                    .attenuation_to_infinity(o.as_dvec3(), dir)
                    .apply(sky(d, sun).as_dvec3())
                    .as_vec3(),
                Err(_) => Vec3::ZERO,
            };
        };
        let p = hit.point.as_dvec3();
        let n = hit.smooth_normal;
        let fp = Footprint::of_pixel(f64::from(hit.t), pixel_angle).unwrap_or(Footprint::POINT);
        let rock = strata.colour(p, fp) * tint;
        let flat = smoothstep(
            0.86,
            0.97,
            f64::from(n.z) + 0.05 * dust_edge.eval2(p.truncate()),
        );
        // Dark sand in patches (dune fields) on the canyon floors.
        let low = smoothstep(-2_500.0, -3_500.0, p.z)
            * 0.85
            * smoothstep(-0.3, 0.4, dunes.eval2(p.truncate()));
        let ground = dust.lerp(sand, low);
        let albedo = rock.lerp(ground, flat);
        let lit = n.dot(sun).max(0.0);
        let shadowed = lit > 0.0
            && tracer.occluded(
                &Ray::new(hit.point + hit.geometric_normal * 2.0, sun),
                0.0,
                f32::INFINITY,
            );
        let direct = if shadowed { 0.0 } else { f64::from(lit) };
        let sun_light = DVec3::new(1.0, 0.92, 0.82) * 1.6;
        let sky_light = DVec3::new(0.36, 0.25, 0.18) * (0.5 + 0.5 * f64::from(n.z));
        let c = albedo * (sun_light * direct + sky_light);
        haze.composite(o.as_dvec3(), p, c).as_vec3()
    };
    let step = 1.0 / ss as f32;
    let frame = Grid2::par_from_fn(w as usize * ss, h as usize * ss, |i, j| {
        shade(cam.ray_at((i as f32 + 0.5) * step, (j as f32 + 0.5) * step))
    })?;
    Ok(PixelFilter::camera().resolve(&frame, ss)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walls_are_cliffs_at_the_rim_and_talus_at_the_floor() {
        assert_eq!((wall_profile(0.0), wall_profile(1.0)), (1.0, 0.0));
        assert_eq!((wall_profile(-0.5), wall_profile(1.5)), (1.0, 0.0));
        let slope = |u: f64| (wall_profile(u - 1e-6) - wall_profile(u + 1e-6)) / 2e-6;
        assert!((slope(1.0 - 1e-6) - 3.0).abs() < 1e-4);
        assert!(slope(1e-3) < 1e-5);
        for k in 1..100 {
            let u = f64::from(k) / 100.0;
            assert!(wall_profile(u) < wall_profile(u - 0.01));
            assert!(slope(u) > slope(u - 0.01));
        }
    }

    #[test]
    fn the_troughs_are_cut_kilometres_into_the_plateau() {
        let hf = canyon_field(1993, 161).unwrap();
        let main = TROUGHS[1];
        // Along the main trough's axis, over its middle: the floor, within
        // its own relief of the trough's depth.
        for k in 0..=40 {
            let x = 20_000.0 + 3_000.0 * f64::from(k);
            let z = f64::from(hf.height_at(x as f32, main.y as f32).unwrap());
            assert!(
                (z + main.depth).abs() < 700.0,
                "x = {x}: {z} m, depth {}",
                main.depth
            );
        }
        // North of the last trough: the plateau (its median within its own
        // relief of 0 m; craters dig into it here and there).
        let mut z: Vec<f32> = (0..=40)
            .map(|k| hf.height_at(4_000.0 * k as f32, 154_000.0).unwrap())
            .collect();
        z.sort_by(f32::total_cmp);
        assert!(z[20].abs() < 300.0, "{}", z[20]);
    }

    #[test]
    fn the_panorama_repeats_past_360_degrees() {
        // 370 columns for 370°: column x + 360 looks where column x does.
        let img = picture(1993, true).unwrap();
        let p = img.pixels();
        let (w, h) = (img.width(), img.height());
        assert_eq!((w, h), (370, 180));
        let mut diff = 0.0f64;
        for x in 0..w - 360 {
            for y in 0..h {
                diff += f64::from((p[(x, y)] - p[(x + 360, y)]).abs().max_element());
            }
        }
        let mean = diff / ((w - 360) * h) as f64;
        assert!(mean < 2e-3, "{mean}");
        // …and not where its neighbour does: the test can tell columns apart.
        let mut other = 0.0f64;
        for y in 0..h {
            other += f64::from((p[(0, y)] - p[(180, y)]).abs().max_element());
        }
        assert!(other / h as f64 > 10.0 * mean.max(1e-4), "{other}");
    }
}
