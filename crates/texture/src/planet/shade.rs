//! What a ray sees: the lit surface, the cloud shell and the rings, composited
//! through the atmosphere.

use glam::DVec3;
use natura_atmos::medium::Attenuation;
use natura_atmos::{Dir3, Medium};

use super::{Air, Planet, Surface};
use crate::footprint::Footprint;
use crate::normal::bump;
use crate::planet::height::Relief;
use crate::planet::trace::{SurfaceHit, TraceSettings};
use crate::texture::TextureKind;
use crate::view::{equator_plane_hit, sphere_hits};

/// Radiance of the sun's disc relative to the sun's colour (the disc is far
/// brighter than anything it lights).
pub const SUN_DISC: f64 = 20.0;

/// Strength and exponent of the sun's glint on the sea: the ocean
/// specularity Musgrave 1993 §5.6.4 says "would also be desirable", here
/// a Blinn–Phong lobe.
const GLINT: (f64, i32) = (0.35, 96);

/// How far above and below the coast's bump value the terran colours
/// blended at a coastline are taken (a tiny step: the shades just either
/// side of it).
const COAST_STEP: f64 = 1e-9;

/// How far (metres) a point must be from the cloud shell or the ring plane
/// to be shadowed by it; points on the layer itself are lit by the sun.
const SELF_SHADOW_MARGIN_M: f64 = 1.0;

/// A semi-transparent layer a ray crosses: distance, colour, opacity.
#[derive(Clone, Copy, Debug)]
struct Layer {
    t: f64,
    colour: DVec3,
    alpha: f64,
}

impl Planet {
    /// The radiance (linear RGB, sun = 1) seen along the ray from `o` in
    /// unit direction `d` whose pixel subtends `pixel_angle`.
    ///
    /// The surface (if the ray meets it) is lit by the sun through the
    /// atmosphere, shadowed by terrain, clouds and rings; the cloud shell
    /// and the ring plane in front of it are composited over it, and every
    /// stretch of the ray between them is attenuated and in-scattered by
    /// the umbra-switched radial atmosphere. A ray that meets nothing sees
    /// black space (or the sun's disc) through the atmosphere: the blue
    /// limb from orbit, the sky from the ground.
    #[must_use]
    pub fn radiance(
        &self,
        o: DVec3,
        d: DVec3,
        pixel_angle: f64,
        settings: &TraceSettings,
    ) -> DVec3 {
        self.radiance_over(o, d, pixel_angle, settings, &|d| self.background(d))
    }

    /// [`Self::radiance`] with `behind(d)`, the radiance beyond the planet's
    /// atmosphere along `d`, in place of black space and the sun's disc: a
    /// ray that meets nothing of the planet sees it through the atmosphere
    /// and the cloud and ring layers (another body behind the planet, a
    /// star field), attenuated and in-scattered as the surface would be.
    #[must_use]
    pub fn radiance_over(
        &self,
        o: DVec3,
        d: DVec3,
        pixel_angle: f64,
        settings: &TraceSettings,
        behind: &dyn Fn(DVec3) -> DVec3,
    ) -> DVec3 {
        let hit = self.trace(o, d, pixel_angle, settings);
        let far = hit.map_or(f64::INFINITY, |h| h.t);
        let mut layers = [Layer {
            t: 0.0,
            colour: DVec3::ZERO,
            alpha: 0.0,
        }; 3];
        let mut n = 0;
        if let (Some(clouds), Some(c)) = (&self.clouds, &self.params.clouds) {
            let rc = self.radius() + c.altitude_m;
            if let Some((a, b)) = sphere_hits(o, d, rc) {
                for t in [a, b] {
                    if t > 0.0 && t < far {
                        let p = o + d * t;
                        let fp = Footprint::new(Self::footprint_m(t, pixel_angle) / rc)
                            .unwrap_or(Footprint::POINT);
                        let alpha = clouds.density(p / p.length(), fp);
                        if alpha > 0.0 {
                            let fpm = Self::footprint_m(t, pixel_angle);
                            let colour = c.albedo * self.light_on(p, p.normalize(), false, fpm);
                            layers[n] = Layer { t, colour, alpha };
                            n += 1;
                        }
                    }
                }
            }
        }
        if let Some(rings) = &self.rings
            && let Some(t) = equator_plane_hit(o, d)
            && t > 0.0
            && t < far
        {
            let p = o + d * t;
            let fp = Footprint::new(Self::footprint_m(t, pixel_angle) / self.radius())
                .unwrap_or(Footprint::POINT);
            let alpha = rings.density_at(p.length() / self.radius(), fp);
            if alpha > 0.0 {
                let fpm = Self::footprint_m(t, pixel_angle);
                let colour = crate::texture::display_to_linear(rings.params().colour)
                    * self.light_on(p, DVec3::Z, true, fpm);
                layers[n] = Layer { t, colour, alpha };
                n += 1;
            }
        }
        let layers = &mut layers[..n];
        layers.sort_by(|a, b| a.t.total_cmp(&b.t));

        let mut l = match &hit {
            Some(h) => self.surface_radiance(h, d, settings),
            None => behind(d),
        };
        // Far to near: the stretch behind each layer, then the layer.
        let mut end = hit.map(|h| h.point);
        for layer in layers.iter().rev() {
            let p = o + d * layer.t;
            l = self.attenuation(p, end, d).apply(l);
            l = layer.colour * layer.alpha + l * (1.0 - layer.alpha);
            end = Some(p);
        }
        self.attenuation(o, end, d).apply(l)
    }

    /// The atmosphere between `a` and `b` (or to infinity along `d`): the
    /// umbra-switched radial atmosphere, its in-scattered light dimmed and
    /// tinted by [`haze_light`](Self::haze_light) where the segment passes
    /// closest to the planet.
    fn attenuation(&self, a: DVec3, b: Option<DVec3>, d: DVec3) -> Attenuation {
        let Some(air) = &self.air else {
            return Attenuation::NONE;
        };
        let (mut att, reach) = match b {
            Some(b) => (air.umbra.attenuation(a, b), (b - a).length()),
            None => match Dir3::new(d) {
                Ok(dir) => (air.umbra.attenuation_to_infinity(a, dir), f64::INFINITY),
                Err(_) => return Attenuation::NONE,
            },
        };
        let closest = a + d * (-a.dot(d)).clamp(0.0, reach);
        att.in_scatter *= self.haze_light(closest);
        att
    }

    /// How brightly, and in what colour, the haze around `p` is lit: the
    /// Lambert shading of the atmosphere (Musgrave 1993 §4.1.6.5, Plate 4.6,
    /// which gives no blend function; here `smoothstep(−0.15, 0.35, n·l)` of
    /// the normal at the point), so the day side's haze dims towards the
    /// terminator instead of ending at the umbra's edge, times the sun's
    /// transmittance through the day air to `p`. Plate 4.6 fades the haze's
    /// colour by hand from a pale grey at high noon to red at the terminator;
    /// here the red comes from the sunlight's own path, which grows long
    /// through the air where the sun is low and loses its blue on the way.
    /// 1 when the shading is off.
    fn haze_light(&self, p: DVec3) -> DVec3 {
        match (&self.params.atmosphere, &self.air) {
            (Some(a), Some(air)) if a.lambert_haze => {
                let lambert =
                    crate::footprint::smoothstep(-0.15, 0.35, p.normalize_or_zero().dot(self.sun));
                Self::through_air(air, p, self.sun) * lambert
            }
            _ => DVec3::ONE,
        }
    }

    /// The day air's transmittance from `p` toward the unit direction `sun`
    /// (1 for a direction that is not unit).
    fn through_air(air: &Air, p: DVec3, sun: DVec3) -> DVec3 {
        Dir3::new(sun).map_or(DVec3::ONE, |dir| {
            let tau = air.day.optical_depth_to_infinity(p, dir);
            DVec3::new((-tau.x).exp(), (-tau.y).exp(), (-tau.z).exp())
        })
    }

    /// What a ray that meets nothing sees behind the atmosphere.
    fn background(&self, d: DVec3) -> DVec3 {
        let light = &self.params.light;
        if d.dot(self.sun) >= light.sun_radius.cos() {
            light.sun_colour * SUN_DISC
        } else {
            DVec3::ZERO
        }
    }

    /// The sunlight reaching `p` (colour, before the cosine): the sun through
    /// the day atmosphere, times the shadows of the clouds and rings, looked
    /// up with a footprint of `footprint_m` metres.
    fn sunlight(&self, p: DVec3, footprint_m: f64) -> DVec3 {
        let mut k = self.params.light.sun_colour;
        if let Some(air) = &self.air {
            k *= Self::through_air(air, p, self.sun);
        }
        if let (Some(clouds), Some(c)) = (&self.clouds, &self.params.clouds)
            && c.shadows
        {
            let rc = self.radius() + c.altitude_m;
            // Points on the shell itself (a cloud being lit) are not shadowed
            // by it: the margin keeps rounding from deciding.
            if p.length() < rc - SELF_SHADOW_MARGIN_M
                && let Some((_, t)) = sphere_hits(p, self.sun, rc)
            {
                let q = p + self.sun * t;
                let fp = Footprint::new(footprint_m / rc).unwrap_or(Footprint::POINT);
                k *= 1.0 - clouds.density(q / q.length(), fp);
            }
        }
        if let Some(rings) = &self.rings
            && let Some(t) = equator_plane_hit(p, self.sun)
            && t > SELF_SHADOW_MARGIN_M
        {
            let q = p + self.sun * t;
            let fp = Footprint::new(footprint_m / self.radius()).unwrap_or(Footprint::POINT);
            k *= 1.0 - rings.density_at(q.length() / self.radius(), fp);
        }
        k
    }

    /// Ambient plus Lambert-weighted sunlight on a surface with normal `n`
    /// at `p` (`two_sided` for the rings, lit from either face; the planet's
    /// own shadow is tested then), with footprint `footprint_m` metres.
    fn light_on(&self, p: DVec3, n: DVec3, two_sided: bool, footprint_m: f64) -> DVec3 {
        let ambient = DVec3::splat(self.params.light.ambient);
        let mut cos = n.dot(self.sun);
        if two_sided {
            cos = cos.abs();
            if let Some((t0, _)) = sphere_hits(p, self.sun, self.radius())
                && t0 > 0.0
            {
                return ambient;
            }
        }
        if cos <= 0.0 {
            return ambient;
        }
        ambient + self.sunlight(p, footprint_m) * cos
    }

    /// The albedos (linear RGB) either side of the coast at the hit `h`
    /// in the unit direction `dir` with bump value `b`, land share and
    /// coast half-width `(land, a)` (chaos) and slope `slope`: the land's
    /// and the sea's, each taken at least `a/2` of chaos from the coast —
    /// about the mean of its own part of a footprint the coast crosses, so
    /// a coarse pixel is not painted with the thin beach or shelf its
    /// centre happens to lie on. By biome when the planet has
    /// [`Biomes`](crate::planet::Biomes), else by the terran texture's
    /// climate index.
    fn shore_colours(
        &self,
        relief: &Relief,
        dir: DVec3,
        b: f64,
        (land, width): (f64, f64),
        h: &SurfaceHit,
        slope: f64,
    ) -> (DVec3, DVec3) {
        let metres = relief.metres_per_chaos();
        let chaos = relief.chaos_above_sea(b);
        let shore = b - chaos;
        let (above, below) = (
            b.max(shore + (0.5 * width).max(COAST_STEP)),
            b.min(shore - (0.5 * width).max(COAST_STEP)),
        );
        if let Some(biomes) = &self.biomes {
            let sea = if land < 1.0 {
                let temp = biomes.temperature(dir.z, 0.0);
                biomes.sea(temp, -relief.chaos_above_sea(below) * metres)
            } else {
                DVec3::ZERO
            };
            let ground = if land > 0.0 {
                let height = relief.height_of(above);
                let fp = Footprint::new(h.footprint_m / self.radius()).unwrap_or(Footprint::POINT);
                let temp = biomes.temperature(dir.z, height);
                // The height's spread over the footprint: the coast's
                // half-width is √5 standard deviations of the chaos.
                let spread = biomes.spread(metres * width / 5f64.sqrt());
                biomes.land(temp, biomes.moisture(dir, fp), height, slope, spread)
            } else {
                DVec3::ZERO
            };
            return (ground, sea);
        }
        let t = relief.terran();
        let mottle = t.mottle(relief.texture_point(dir), h.footprint);
        let lat = dir.z.abs();
        (
            t.shade(above, lat, mottle).colour,
            t.shade(below, lat, mottle).colour,
        )
    }

    /// The light leaving the surface hit `h` towards the eye.
    fn surface_radiance(&self, h: &SurfaceHit, d: DVec3, settings: &TraceSettings) -> DVec3 {
        let p = h.point;
        let dir = p.normalize();
        match &self.surface {
            Surface::Terrain(relief) => {
                let fp = h.footprint;
                let (n, b, land, width) = relief.normal_bump_land_width(p, fp);
                let c = n.dot(dir).clamp(1e-6, 1.0);
                let slope = (1.0 - c * c).sqrt() / c;
                let (land_colour, sea_colour) =
                    self.shore_colours(relief, dir, b, (land, width), h, slope);
                // Land and sea each lit by its own normal and blended by the
                // footprint's share of each, so the coast is filtered in
                // radiance, not only in colour (a steep shore beside a flat
                // sea would otherwise still step from pixel to pixel).
                let ambient = DVec3::splat(self.params.light.ambient);
                let (cos_land, cos_sea) = (n.dot(self.sun), dir.dot(self.sun));
                let mut sun = DVec3::ZERO;
                if cos_land.max(cos_sea) > 0.0 {
                    let eps = (settings.epsilon * h.footprint_m).max(settings.min_epsilon_m);
                    let normal = if cos_land > 0.0 { n } else { dir };
                    let visible = if self.params.light.terrain_shadows {
                        self.terrain_visibility(p, normal, self.sun, h.footprint_m, eps)
                    } else {
                        1.0
                    };
                    if visible > 0.0 {
                        sun = self.sunlight(p, h.footprint_m) * visible;
                    }
                }
                let on_land = land_colour * (ambient + sun * cos_land.max(0.0));
                let half = (self.sun - d).normalize_or_zero();
                let glint = sun * (GLINT.0 * dir.dot(half).max(0.0).powi(GLINT.1));
                let on_sea = sea_colour * (ambient + sun * cos_sea.max(0.0)) + glint;
                on_sea.lerp(on_land, land)
            }
            Surface::Textured(tex) => {
                let s = tex.sample(dir, h.footprint);
                let n = match tex.kind() {
                    TextureKind::Height | TextureKind::ColourAndHeight => {
                        bump(dir, tex.height_gradient(dir, h.footprint))
                    }
                    _ => dir,
                };
                s.colour * self.light_on(p, n, false, h.footprint_m)
            }
        }
    }
}
