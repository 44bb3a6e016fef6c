//! Surface materials: altitude-, slope-, flow- and deposition-driven albedo,
//! perturbed by fractal noise, with Lambert or Oren–Nayar diffuse reflection.
//!
//! The layering follows Musgrave's practice of "driving parameters with
//! functions" (Musgrave 2001, "Driving Function Parameters with Functions"): snow lies
//! where altitude, slope, sun and wind let it ([`crate::snow`]), with a
//! fractal edge band-limited at the footprint; rock shows where
//! the slope exceeds a threshold; vegetation grows below the tree line,
//! densest where the drainage network keeps the ground wet; sediment shows
//! where erosion deposited it; sand rims the water.

use glam::{DVec2, DVec3, Vec3};
use natura_core::colour::srgb_decode_rgb;
use natura_core::{HeightField, smoothstep};
use natura_noise::{Fbm, Field, Perlin, Spectral, visible_octaves};

use crate::error::Result;
use crate::scene::{Diffuse, MaterialDesc};
use crate::snow::{Shelter, SnowCover};
use crate::surface_textures::SurfaceTextures;

/// Everything the material mapping reads at a surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// World position, metres.
    pub point: Vec3,
    /// Unit shading normal before bump detail (z up).
    pub normal: Vec3,
    /// Sediment deposited by erosion here, metres (≥ 0).
    pub deposition_m: f32,
    /// Wetness from the drainage area, 0 (ridge) to 1 (main river).
    pub wetness: f32,
}

/// The procedural material mapping of a scene (see the module docs).
#[derive(Debug)]
pub struct Materials {
    desc: MaterialDesc,
    water_level: Option<f32>,
    lin: Albedos,
    /// Perturbs the snow line and the vegetation boundary (large scale).
    large: Fbm<Perlin>,
    /// Mottles colour (medium scale).
    mottle: Fbm<Perlin>,
    /// Bump detail (small scale).
    bump: Fbm<Perlin>,
    cos_rock: (f32, f32),
    snow: SnowCover,
    sigma: Option<(f32, f32)>,
    /// Solid textures at the footprint (strata, grain), if the scene has them.
    textures: Option<SurfaceTextures>,
}

#[derive(Clone, Copy, Debug)]
struct Albedos {
    snow: Vec3,
    rock: Vec3,
    grass: Vec3,
    forest: Vec3,
    soil: Vec3,
    sediment: Vec3,
    sand: Vec3,
}

impl Materials {
    /// Builds the mapping from the scene's material description (validated by
    /// [`crate::SceneDesc::validate`]), the water level, and a seed.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Noise`](crate::RenderError::Noise) if the texture noise cannot be built
    /// from the description.
    pub fn new(
        desc: &MaterialDesc,
        water_level: Option<f32>,
        seed: natura_core::Seed,
    ) -> Result<Self> {
        let lin = |c: [f32; 3]| srgb_decode_rgb(Vec3::from(c));
        let s = |name: &str| seed.derive(name).0;
        let large = Fbm::new(
            Perlin::new(s("snow-line")),
            Spectral::default()
                .with_h(0.8)
                .with_octaves(5.0)
                .with_frequency(1.0 / 900.0),
        )?;
        let mottle = Fbm::new(
            Perlin::new(s("mottle")),
            Spectral::default()
                .with_h(0.6)
                .with_octaves(4.0)
                .with_frequency(1.0 / 60.0),
        )?;
        let bump_freq = if desc.bump_size_m > 0.0 {
            1.0 / f64::from(desc.bump_size_m)
        } else {
            1.0
        };
        let bump = Fbm::new(
            Perlin::new(s("bump")),
            Spectral::default()
                .with_h(0.7)
                .with_octaves(4.0)
                .with_frequency(bump_freq),
        )?;
        let band = 5f32.to_radians();
        let rock = desc.rock_slope_deg.to_radians();
        let sigma = match desc.diffuse {
            Diffuse::Lambert => None,
            Diffuse::OrenNayar { sigma_deg } => {
                let s2 = sigma_deg.to_radians().powi(2);
                Some((1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)))
            }
        };
        Ok(Self {
            desc: desc.clone(),
            water_level,
            lin: Albedos {
                snow: lin(desc.snow),
                rock: lin(desc.rock),
                grass: lin(desc.grass),
                forest: lin(desc.forest),
                soil: lin(desc.soil),
                sediment: lin(desc.sediment),
                sand: lin(desc.sand),
            },
            large,
            mottle,
            bump,
            // n.z above the first edge: not rock; below the second: rock.
            cos_rock: ((rock - band).max(0.0).cos(), (rock + band).min(1.5).cos()),
            snow: SnowCover::new(desc, s("snow-edge"))?,
            sigma,
            textures: None,
        })
    }

    /// The same mapping with the scene's solid textures (or none).
    #[must_use]
    pub fn with_textures(self, textures: Option<SurfaceTextures>) -> Self {
        Self { textures, ..self }
    }

    /// The same mapping with the snow's sun exposure toward `sun` (a unit
    /// vector toward the sun), the ground whose slope holds it and, if
    /// given, the wind's shelter and drift ([`SnowCover::with_exposure`]).
    #[must_use]
    pub fn with_snow_exposure(
        self,
        sun: Vec3,
        ground: Option<HeightField>,
        shelter: Option<(Shelter, f32)>,
    ) -> Self {
        Self {
            snow: self.snow.with_exposure(sun, ground, shelter),
            ..self
        }
    }

    /// The fraction of the ground under snow at a surface sample seen with
    /// a footprint of `footprint_m` metres ([`SnowCover::cover`]).
    #[must_use]
    pub fn snow_cover(&self, s: &SurfaceSample, footprint_m: f32) -> f32 {
        let p = s.point.as_dvec3();
        let large = self.large.eval2(DVec2::new(p.x, p.y)) as f32;
        self.snow.cover(s.point, s.normal, large, footprint_m)
    }

    /// The linear albedo at a surface sample (point-sampled textures).
    #[must_use]
    pub fn albedo(&self, s: &SurfaceSample) -> Vec3 {
        self.albedo_at(s, 0.0)
    }

    /// The linear albedo at a surface sample seen by a pixel whose
    /// footprint there is `footprint_m` metres wide: the solid textures, if
    /// any, show the detail that footprint resolves.
    #[must_use]
    pub fn albedo_at(&self, s: &SurfaceSample, footprint_m: f32) -> Vec3 {
        self.albedo_with_snow_at(s, footprint_m, footprint_m)
    }

    /// [`Self::albedo_at`], with the snow's cover seen over a footprint
    /// `snow_footprint_m` metres wide instead ([`Self::snow_cover`]): the
    /// pixel's footprint on ground seen at a slant, stretched along the
    /// view. The cover is a threshold of its edge noise, snow (albedo near
    /// 0.85) or bare ground (near 0.15): noise left finer than the footprint
    /// turns into strips of full cover narrower than a pixel, which one
    /// sample of a pixel catches and its neighbours miss. The mottling and
    /// solid textures modulate the colour by some per cent and keep
    /// `footprint_m`.
    #[must_use]
    pub fn albedo_with_snow_at(
        &self,
        s: &SurfaceSample,
        footprint_m: f32,
        snow_footprint_m: f32,
    ) -> Vec3 {
        let d = &self.desc;
        let a = &self.lin;
        let p = s.point.as_dvec3();
        let h = s.point.z;
        let large = self.large.eval2(DVec2::new(p.x, p.y)) as f32;
        let mottle = self.mottle.eval2(DVec2::new(p.x, p.y)) as f32;
        let nz = s.normal.z;

        let rock = smoothstep(self.cos_rock.0, self.cos_rock.1, nz);
        let tree = d.tree_line_m + 0.6 * d.snow_line_noise_m * large;
        let veg = smoothstep(tree + 120.0, tree - 120.0, h) * (1.0 - rock);
        let forest = veg
            * smoothstep(0.35, 0.75, s.wetness + 0.35 * large + 0.25 * mottle)
            * smoothstep(0.80, 0.92, nz);
        let mut c = a.soil.lerp(a.grass, veg);
        c = c.lerp(a.forest, forest);
        if d.sediment_min_m > 0.0 {
            let sed = smoothstep(d.sediment_min_m, 3.0 * d.sediment_min_m, s.deposition_m);
            c = c.lerp(a.sediment, sed * (1.0 - 0.5 * rock));
        }
        let rock_colour = a.rock * (1.0 + 0.25 * large);
        let rock_colour = match &self.textures {
            Some(t) if rock > 0.0 => t.rock(s.point, footprint_m, rock_colour),
            _ => rock_colour,
        };
        c = c.lerp(rock_colour, rock);
        if let Some(level) = self.water_level {
            // Sand only on gentle shores, in patches.
            let beach = smoothstep(level + d.beach_height_m, level + 0.3 * d.beach_height_m, h)
                * smoothstep(0.93, 0.99, nz)
                * smoothstep(-0.2, 0.3, mottle + 0.5 * large);
            c = c.lerp(a.sand, beach);
        }
        let snow = self.snow.cover(s.point, s.normal, large, snow_footprint_m);
        c = c.lerp(a.snow, snow);
        // Mottling: ±15 % brightness variation, less on snow.
        let c = c * (1.0 + (0.15 - 0.1 * snow) * mottle);
        let c = match &self.textures {
            Some(t) => c * t.grain(s.point, footprint_m),
            None => c,
        };
        c.clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// The shading normal with procedural bump detail band-limited at the
    /// pixel's footprint (metres): each octave fades out as the footprint
    /// approaches half its wavelength (natura-noise's band-limited fBm,
    /// Musgrave 1993, §5.1.2), so no octave finer than a pixel flips the
    /// normal of a single pixel (which showed as isolated dark specks, on
    /// snow lit only by the blue sky).
    #[must_use]
    pub fn bumped_normal(&self, point: Vec3, normal: Vec3, footprint_m: f32) -> Vec3 {
        let d = &self.desc;
        if d.bump_size_m <= 0.0 || d.bump_strength <= 0.0 {
            return normal;
        }
        let sp = self.bump.spectral();
        // The band's own Nyquist margin: an octave fades from a quarter to
        // half a wavelength per pixel.
        let visible = visible_octaves(f64::from(footprint_m.max(0.0)), sp.frequency, sp.lacunarity);
        if visible <= 0.0 {
            return normal;
        }
        let p = point.as_dvec3();
        let (_, g) = self
            .bump
            .eval_grad3_band(DVec3::new(p.x, p.y, p.z), visible);
        // The field's gradient is per metre times its frequency; scale to slope units.
        let g = (g.as_vec3() * d.bump_size_m) * d.bump_strength;
        let tangential = g - normal * g.dot(normal);
        (normal - tangential).try_normalize().unwrap_or(normal)
    }

    /// Diffuse reflection factor `f` such that reflected radiance is
    /// `albedo/π · E · cosθᵢ · f` (Lambert: `f = 1`; Oren–Nayar's qualitative
    /// model: `A + B·max(0, cos(φᵢ − φᵣ))·sin α·tan β`).
    ///
    /// `n`, `l` (toward the light) and `v` (toward the viewer) are unit vectors.
    #[must_use]
    pub fn diffuse_factor(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        let Some((a, b)) = self.sigma else { return 1.0 };
        oren_nayar(a, b, n, l, v)
    }
}

/// Oren–Nayar's qualitative model factor with precomputed `A`, `B`.
#[must_use]
pub fn oren_nayar(a: f32, b: f32, n: Vec3, l: Vec3, v: Vec3) -> f32 {
    let ci = n.dot(l).clamp(0.0, 1.0);
    let cr = n.dot(v).clamp(0.0, 1.0);
    let lp = l - n * ci;
    let vp = v - n * cr;
    let denom = (lp.length_squared() * vp.length_squared()).sqrt();
    let cos_phi = if denom > 1e-12 {
        (lp.dot(vp) / denom).max(0.0)
    } else {
        0.0
    };
    // α = max(θi, θr) has the smaller cosine; β = min(θi, θr) the larger.
    let (c_alpha, c_beta) = if ci < cr { (ci, cr) } else { (cr, ci) };
    let sin_alpha = (1.0 - c_alpha * c_alpha).max(0.0).sqrt();
    let tan_beta = (1.0 - c_beta * c_beta).max(0.0).sqrt() / c_beta.max(1e-4);
    a + b * cos_phi * sin_alpha * tan_beta
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::MaterialDesc;
    use natura_core::Seed;

    fn materials(diffuse: Diffuse) -> Materials {
        let desc = MaterialDesc {
            diffuse,
            ..MaterialDesc::default()
        };
        Materials::new(&desc, Some(100.0), Seed(1)).unwrap()
    }

    fn sample(z: f32, normal: Vec3) -> SurfaceSample {
        SurfaceSample {
            point: Vec3::new(1234.0, 567.0, z),
            normal: normal.normalize(),
            deposition_m: 0.0,
            wetness: 0.2,
        }
    }

    #[test]
    fn snow_high_rock_steep_vegetation_low() {
        let m = materials(Diffuse::Lambert);
        let d = MaterialDesc::default();
        let flat = Vec3::Z;
        let high = m.albedo(&sample(d.snow_line_m + 3.0 * d.snow_line_noise_m, flat));
        let low = m.albedo(&sample(d.tree_line_m - 500.0, flat));
        let steep = m.albedo(&sample(d.tree_line_m - 500.0, Vec3::new(1.0, 0.0, 0.4)));
        let steep_high = m.albedo(&sample(
            d.snow_line_m + 3.0 * d.snow_line_noise_m,
            Vec3::new(1.0, 0.0, 0.3),
        ));
        assert!(high.min_element() > 0.6, "snow is white: {high}");
        assert!(low.y > low.z && low.y > 0.05, "low ground is green: {low}");
        assert!(
            (steep.x - steep.y).abs() < 0.1,
            "steep ground is grey rock: {steep}"
        );
        assert!(
            steep_high.max_element() < 0.6,
            "snow does not hold on cliffs: {steep_high}"
        );
    }

    #[test]
    fn sediment_and_beach_show() {
        let m = materials(Diffuse::Lambert);
        // Sand lies in patches along gentle shores: some shore points are sand.
        let sandy = (0..64)
            .map(|k| {
                let mut s = sample(100.5, Vec3::Z);
                s.point.x += 37.0 * k as f32;
                m.albedo(&s).x
            })
            .fold(0.0f32, f32::max);
        // Inland grass at the same spots is darker than the brightest shore.
        let grass = (0..64)
            .map(|k| {
                let mut s = sample(130.0, Vec3::Z);
                s.point.x += 37.0 * k as f32;
                m.albedo(&s).x
            })
            .fold(0.0f32, f32::max);
        assert!(
            sandy > grass + 0.03,
            "beach sand {sandy} is lighter than grass {grass}"
        );
        let mut s = sample(101.0, Vec3::Z);
        s.point.z = 400.0;
        let plain = m.albedo(&s);
        s.deposition_m = 5.0;
        let gravel = m.albedo(&s);
        assert!(
            gravel.min_element() > plain.min_element(),
            "{gravel} vs {plain}"
        );
    }

    #[test]
    fn oren_nayar_reduces_to_lambert_at_zero_roughness_and_is_bounded() {
        let n = Vec3::Z;
        for (l, v) in [
            (Vec3::new(0.3, 0.1, 0.9), Vec3::new(-0.5, 0.2, 0.8)),
            (Vec3::new(0.9, 0.0, 0.1), Vec3::new(0.8, 0.1, 0.2)),
        ] {
            let (l, v) = (l.normalize(), v.normalize());
            assert!((oren_nayar(1.0, 0.0, n, l, v) - 1.0).abs() < 1e-6);
            let m = materials(Diffuse::OrenNayar { sigma_deg: 30.0 });
            let f = m.diffuse_factor(n, l, v);
            // The factor can exceed 1 at grazing incidence (retro-reflection),
            // but the reflected radiance factor f·cosθᵢ stays bounded.
            assert!(f.is_finite() && f > 0.0 && f * n.dot(l) < 1.0, "{f}");
        }
        // Back-scatter (light behind the viewer) is brighter than forward-scatter for rough surfaces.
        let m = materials(Diffuse::OrenNayar { sigma_deg: 30.0 });
        let l = Vec3::new(0.7, 0.0, 0.7).normalize();
        let back = m.diffuse_factor(n, l, l);
        let fwd = m.diffuse_factor(n, l, Vec3::new(-0.7, 0.0, 0.7).normalize());
        assert!(back > fwd, "{back} vs {fwd}");
    }

    #[test]
    fn bump_fades_with_footprint() {
        let m = materials(Diffuse::Lambert);
        let p = Vec3::new(10.3, 20.7, 300.0);
        assert_eq!(m.bumped_normal(p, Vec3::Z, 100.0), Vec3::Z);
        let near = m.bumped_normal(p, Vec3::Z, 0.01);
        assert!((near.length() - 1.0).abs() < 1e-5 && near != Vec3::Z);
    }
}
