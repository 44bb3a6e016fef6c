//! Musgrave 1993, Plate 5.8 (Musgrave 1998, figs. 15.17–15.18): "Other
//! State", Saturn and its rings over a sea of the windywave texture.

use natura::atmos::medium::ExponentialMist;
use natura::core::glam::{DVec3, Vec3};
use natura::core::{HeightField, Image};
use natura::texture::giants::{GasGiant, GasGiantParams, Rings, RingsParams};
use natura::texture::water::{WindyWave, WindyWaveParams};
use natura::texture::{Footprint, display_to_linear};
use natura::trace::MipmapTracer;

use crate::R;
use crate::lakes::{Water, lake_picture};
use crate::landscape::Landscape;

/// Saturn in the sky: a banded giant of angular radius `radius` towards
/// `towards`, its rings (natura-texture's `Rings`: a 1-D fBm of the
/// radius as the disc's density, in planet radii) in the plane normal to
/// `axis`, lit from `sun`. Returns the colour over `behind`.
pub(crate) struct Saturn {
    pub giant: GasGiant,
    pub rings: Rings,
    pub towards: Vec3,
    pub axis: Vec3,
    pub radius: f32,
    pub sun: Vec3,
}

impl Saturn {
    /// What the ray `d` from the eye sees of the planet and its rings,
    /// over `behind`.
    pub(crate) fn over(&self, behind: Vec3, d: Vec3) -> Vec3 {
        // The planet one unit of radius across, `1 / sin(radius)` away.
        let c = (self.towards / self.radius.sin()).as_dvec3();
        let d = d.as_dvec3();
        let axis = self.axis.as_dvec3();
        let sun = self.sun.as_dvec3();
        // The sphere: |t·d − c|² = 1.
        let b = d.dot(c);
        let disc = b * b - c.length_squared() + 1.0;
        let t_sphere = (disc >= 0.0).then(|| b - disc.sqrt());
        let planet = t_sphere.map(|t| {
            let n = d * t - c;
            // The bands run round the axis: the texture's z is the axis.
            let (e1, e2) = axis.any_orthonormal_pair();
            let q = DVec3::new(n.dot(e1), n.dot(e2), n.dot(axis));
            let albedo = self
                .giant
                .colour(q, Footprint::new(2e-3).unwrap_or(Footprint::POINT));
            albedo * (n.dot(sun).max(0.0) * 1.1 + 0.03)
        });
        // The ring plane: (t·d − c)·axis = 0.
        let dn = d.dot(axis);
        let ring = (dn.abs() > 1e-9)
            .then(|| c.dot(axis) / dn)
            .filter(|&t| t > 0.0)
            .and_then(|t| {
                let r = (d * t - c).length();
                let a = self.rings.density_at(r, Footprint::new(2e-3).ok()?);
                (a > 0.0).then_some((t, a))
            });
        let ring_colour = |t: f64| {
            // The planet's shadow on the rings: the ray to the sun from
            // the ring point meets the sphere.
            let p = d * t - c;
            let b = p.dot(sun);
            let shadowed = b < 0.0 && b * b - p.length_squared() + 1.0 >= 0.0;
            let lit = if shadowed { 0.05 } else { 0.8 };
            display_to_linear(self.rings.params().colour) * lit
        };
        let back = planet.unwrap_or(behind.as_dvec3());
        let out = match (ring, t_sphere) {
            // Rings in front of the planet, or around it: over what is behind.
            (Some((t, a)), ts) if ts.is_none_or(|s| t < s) => back.lerp(ring_colour(t), a),
            _ => back,
        };
        out.as_vec3()
    }
}

/// Plate 5.8 / Fig. 15.18: Saturn, its rings open about 30° and half-lit,
/// low over a sea under "a subtle use of the windywave shader" (gusts
/// roughening the water in patches), at dusk.
pub(crate) fn other_state(seed: u64, quick: bool) -> R<Image> {
    // An open sea: a field far below the water.
    let floor = HeightField::from_fn(9, 9, 4000.0, |_, _| -500.0)?;
    let tracer = MipmapTracer::new(&floor)?;
    let sun = Vec3::new(-0.8, 0.45, 0.18).normalize();
    let towards = Vec3::new(0.3, 1.0, 0.28).normalize();
    let saturn = Saturn {
        giant: GasGiant::new(GasGiantParams {
            seed,
            ..GasGiantParams::saturn()
        })?,
        rings: Rings::new(RingsParams {
            seed,
            ..RingsParams::default()
        })?,
        towards,
        // Tilted towards the eye, the rings open about 30°.
        axis: (Vec3::new(0.3, 0.0, 1.0) - towards * 0.8).normalize(),
        radius: 0.075,
        sun,
    };
    let sky = |d: Vec3| {
        let up = d.z.max(0.0).sqrt();
        let dusk = Vec3::new(0.62, 0.48, 0.42).lerp(Vec3::new(0.05, 0.07, 0.18), up);
        saturn.over(dusk, d)
    };
    let albedo = |_: DVec3, _| Vec3::ZERO;
    // Sea haze thinning upwards: the horizon fades, the sky stays clear.
    let clear = ExponentialMist::new(DVec3::splat(4e-5), DVec3::new(0.62, 0.48, 0.42), 0.0, 200.0)?;
    let land = Landscape {
        tracer: &tracer,
        albedo: &albedo,
        medium: &clear,
        sun,
        sky: &sky,
        shadows: false,
    };
    let sea = WindyWave::new(WindyWaveParams {
        seed,
        km: 0.05,
        ..WindyWaveParams::default()
    })?;
    let water = Water {
        level: 0.0,
        ripples: &sea,
        per_metre: 1.0 / 8.0,
        body: Vec3::new(0.006, 0.012, 0.016),
    };
    lake_picture(&land, water, Vec3::new(0.0, 0.0, 6.0), (-0.12, 0.7), quick)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn saturn() -> Saturn {
        Saturn {
            giant: GasGiant::new(GasGiantParams::saturn()).unwrap(),
            rings: Rings::new(RingsParams::default()).unwrap(),
            towards: Vec3::Y,
            axis: Vec3::new(0.0, -0.5, 1.0).normalize(),
            radius: 0.1,
            sun: Vec3::new(0.0, -1.0, 0.2).normalize(),
        }
    }

    #[test]
    fn the_planet_covers_its_angular_radius_and_the_rings_reach_past_it() {
        let s = saturn();
        let behind = Vec3::new(0.0, 0.0, 1.0);
        let at = |angle: f32| {
            // Along the ring plane's horizontal line through the centre.
            s.over(behind, Vec3::new(angle.sin(), angle.cos(), 0.0))
        };
        // Inside the disc: the planet, not the background.
        assert_ne!(at(0.05), behind);
        // Beyond the rings' outer radius (2.3 planet radii): background.
        let beyond = (2.4f32 * 0.1f32.sin()).asin();
        assert_eq!(at(beyond + 0.01), behind);
        // Between the planet and the rings' outer edge, in the ring band
        // (1.25–2.3 radii) along the plane: some ring.
        let band = (1.8f32 * 0.1f32.sin()).asin();
        assert_ne!(at(band), behind);
        // Far from the planet: background exactly.
        assert_eq!(s.over(behind, Vec3::new(0.0, 0.0, 1.0)), behind);
    }
}
