//! Shading: the light leaving the terrain, the water, the trees and the
//! sky toward the viewer, with their shadows (Musgrave 1993, ch. 3–4).
//! Tracing and pixel loops live in the parent module and call these.

use super::*;

impl Renderer<'_> {
    /// The share of the sun's light the trees let through to `p` (beyond
    /// `t_min` metres) as a pixel of footprint `footprint` metres sees it,
    /// `own` the tree `p` lies on ([`Forest::sun_visibility`]); 1 without
    /// a forest.
    pub(super) fn trees_sun(&self, p: Vec3, t_min: f32, footprint: f32, own: Option<u32>) -> f32 {
        self.forest.as_ref().map_or(1.0, |f| {
            f.sun_visibility(p, self.sun, t_min, footprint, own)
        })
    }

    /// Radiance leaving a tree toward `-d`: the sun unless the terrain or a
    /// tree (its own crown included) is in the way, and skylight.
    pub(super) fn shade_tree(&self, f: &Forest, h: &TreeHit, d: Vec3) -> Vec3 {
        // Past the surface hit by a few centimetres, so the shadow ray of a
        // leaf lit from behind passes through it (its transmitted light).
        let eps = 0.03 + 1e-6 * h.point.abs().max_element();
        let fp = RayCone {
            at_origin_m: h.t * self.pixel_angle,
            per_metre: self.pixel_angle,
        };
        let terrain_lets = self.sun.z > 0.0
            && !self.tracer.occluded_footprint(
                &Ray::new(h.point, self.sun),
                eps,
                f32::INFINITY,
                fp,
            );
        let visible = if terrain_lets {
            self.trees_sun(h.point, eps, fp.at_origin_m, Some(h.instance))
        } else {
            0.0
        };
        let light = Light {
            sun: self.sun,
            // The clouds' shadow dims the sun on trees as on the ground.
            sun_irradiance: self.sun_irradiance * self.cloud_shadow(h.point),
            sky_irradiance: self.sky_irradiance,
        };
        f.shade(h, d, &light, visible)
    }

    /// The sky seen from `o` along unit `d` (a ray that left the terrain),
    /// with the sun's disc and the clouds in front of both.
    pub(super) fn sky(&self, o: Vec3, d: Vec3) -> Vec3 {
        self.sky_with(o, d, true)
    }

    /// [`Self::sky`], with the sun's disc only if `disc` (the wind sea's
    /// reflection leaves it to the glitter).
    pub(super) fn sky_with(&self, o: Vec3, d: Vec3, disc: bool) -> Vec3 {
        let sky = self.view.radiance_f32(d);
        let disc = if disc {
            Dir3::from_f32(d).map_or(Vec3::ZERO, |dir| self.view.sun_disc(dir))
        } else {
            Vec3::ZERO
        };
        match self.clouds.as_ref().and_then(|c| c.view(o, d)) {
            Some(c) => c.radiance + sky * c.transmittance + disc * c.sun_transmittance,
            None => sky + disc,
        }
    }

    /// The fraction of the sun's light the clouds let through to `p`.
    pub(super) fn cloud_shadow(&self, p: Vec3) -> f32 {
        self.clouds.as_ref().map_or(1.0, |c| c.sun_transmittance(p))
    }

    pub(super) fn terrain_point(&self, h: &Hit) -> TerrainPoint {
        TerrainPoint {
            point: h.point,
            geo: h.geometric_normal,
            smooth: h.smooth_normal,
        }
    }

    /// The width, metres, of a pixel's footprint on a surface of unit
    /// normal `n` met at distance `t` along the unit view direction `d`:
    /// `t·α` across the view (`α` the pixel's angle), stretched by `1/|d·n|`
    /// along it where the view grazes the surface; their geometric mean is
    /// the isotropic width the water's waves and the snow's cover are
    /// filtered to.
    pub(super) fn surface_footprint(&self, t: f32, d: Vec3, n: Vec3) -> f32 {
        t * self.pixel_angle / d.dot(n).abs().max(1e-3).sqrt()
    }

    /// Radiance leaving a terrain point toward `-d`, at distance `t` from the viewer.
    pub(super) fn shade_terrain(&self, tp: &TerrainPoint, d: Vec3, t: f32) -> Vec3 {
        let w = self.world;
        let cell = w.terrain.cell_size();
        let (gx, gy) = (tp.point.x / cell, tp.point.y / cell);
        let sample = SurfaceSample {
            point: tp.point,
            normal: tp.smooth,
            deposition_m: w.deposition.sample_bilinear(gx, gy, Boundary::Clamp),
            wetness: w.wetness.sample_bilinear(gx, gy, Boundary::Clamp),
        };
        let footprint = t * self.pixel_angle;
        // The snow is seen over the pixel's footprint on the ground, which a
        // grazing view stretches: over its width across the view only, the
        // snow's edge noise left strips of snow a fraction of a pixel tall
        // on slopes seen edge-on, and one sample of a pixel caught a strip
        // its neighbours missed (rows of lone white pixels on far slopes).
        let on_ground = self.surface_footprint(t, d, tp.smooth);
        let albedo = self
            .materials
            .albedo_with_snow_at(&sample, footprint, on_ground);
        let n = self.materials.bumped_normal(tp.point, tp.smooth, footprint);
        let v = -d;
        let mut l = Vec3::ZERO;
        let mut e_sun = None;

        // The sun's light through the clouds here.
        let cloud = self.cloud_shadow(tp.point);
        // Direct sun, with a shadow ray from just above the surface.
        let cos_i = n.dot(self.sun);
        if cos_i > 0.0 && tp.geo.dot(self.sun) > -0.05 {
            let eps = 1e-2 * cell + 1e-5 * tp.point.abs().max_element();
            let shadow = Ray::new(tp.point + tp.geo * eps, self.sun);
            let fp = RayCone {
                at_origin_m: footprint,
                per_metre: self.pixel_angle,
            };
            let trees = if self
                .tracer
                .occluded_footprint(&shadow, eps, f32::INFINITY, fp)
            {
                0.0
            } else {
                self.trees_sun(shadow.origin, eps, footprint, None)
            };
            if trees > 0.0 {
                let f = self.materials.diffuse_factor(n, self.sun, v) * cloud * trees;
                l += albedo / std::f32::consts::PI * self.sun_irradiance * cos_i * f;
                e_sun = Some(self.sun_irradiance * cos_i * f);
            }
        }
        // Sky light over the visible hemisphere, plus light bounced off the
        // surroundings (under the clouds' shadow as this point is) for
        // normals that face down-slope.
        let light = Light {
            sun: self.sun,
            sun_irradiance: self.sun_irradiance * cloud,
            sky_irradiance: self.sky_irradiance,
        };
        let up = 0.5 * (1.0 + n.z);
        let bounce = 0.5 * (1.0 - n.z) * light.bounced();
        l += albedo / std::f32::consts::PI * (self.sky_irradiance * up + bounce);
        match &self.forest {
            // The forest's floor, and its canopy beyond the trees.
            Some(f) => f.ground_radiance(
                &Ground {
                    point: tp.point,
                    dir: d,
                    normal: tp.smooth,
                    footprint,
                    albedo,
                    sun: e_sun.unwrap_or(Vec3::ZERO),
                    sky: self.sky_irradiance * up + bounce,
                    sun_visible: e_sun.is_some(),
                    radiance: l,
                },
                &light,
            ),
            None => l,
        }
    }

    /// The normal of the fBm ripples at `p`, band-limited to a pixel of the
    /// given footprint (metres): octaves finer than the footprint fade out
    /// (the RenderMan `vfBm` filter of natura-noise's [`FilteredFbm`]), so
    /// distant water tends to its mean plane instead of aliasing into glitter.
    pub(super) fn ripple_normal(&self, p: Vec3, footprint: f32) -> Vec3 {
        let wdesc = &self.world.scene.water;
        if wdesc.ripple_height_m <= 0.0 {
            return Vec3::Z;
        }
        let width = f64::from(footprint);
        let q = DVec2::new(f64::from(p.x), f64::from(p.y));
        // Central differences at a tenth of the finest wavelength kept.
        let h = (0.1 * width).max(0.01 * wdesc.ripple_size_m / 128.0);
        let fx = self.ripples.eval2_width(q + DVec2::X * h, width)
            - self.ripples.eval2_width(q - DVec2::X * h, width);
        let fy = self.ripples.eval2_width(q + DVec2::Y * h, width)
            - self.ripples.eval2_width(q - DVec2::Y * h, width);
        let g = DVec2::new(fx, fy) * (wdesc.ripple_height_m / (2.0 * h));
        Vec3::new(-g.x as f32, -g.y as f32, 1.0).normalize()
    }

    /// Radiance leaving the water surface at `p` toward `-d` (`reflect_terrain`:
    /// whether reflection rays may hit the terrain, off for secondary bounces).
    pub(super) fn shade_water(&self, p: Vec3, d: Vec3, t: f32, reflect_terrain: bool) -> Vec3 {
        let wdesc = &self.world.scene.water;
        let footprint = self.surface_footprint(t, d, Vec3::Z);
        let wave = self
            .wind_sea
            .as_ref()
            .map(|s| s.sample(Vec2::new(p.x, p.y), footprint));
        let n = if let Some(w) = &wave {
            w.normal
        } else if let Some(ocean) = &self.ocean {
            // Normals of the wind sea, flattened where a pixel covers many
            // wavelengths (the mean normal of a rough patch is its plane).
            let patch = wdesc.ocean_patch_m as f32;
            let fade = 1.0 - natura_core::smoothstep(0.01 * patch, 0.2 * patch, footprint);
            let n = ocean.normal_at(Vec2::new(p.x, p.y));
            (Vec3::Z + (n - Vec3::Z) * fade).normalize()
        } else {
            self.ripple_normal(p, footprint)
        };
        let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
        let fr = fresnel(1.0, WATER_IOR, f64::from(cos_i)).unpolarized() as f32;

        // Reflection: the trees and terrain (mountains mirrored in the lake) or
        // the sky and sun.
        let mut r = d - 2.0 * d.dot(n) * n;
        if r.z < 1e-4 {
            r.z = r.z.abs().max(1e-4);
            r = r.normalize();
        }
        let reflected = if reflect_terrain {
            let rray = Ray::new(p + Vec3::Z * 1e-2, r);
            // At a shoreline the exact water plane lies below the interpolated
            // surface of its cell; a ray leaving it starts under the traced
            // surface, so it sees only the bare terrain (the rising shore).
            let under = self.surface_height(rray.origin) > rray.origin.z;
            let hit = if under {
                self.ground
                    .trace(&rray, 0.0, f32::INFINITY)
                    .map(SurfaceHit::Terrain)
            } else {
                let fp = RayCone {
                    at_origin_m: t * self.pixel_angle,
                    per_metre: self.pixel_angle,
                };
                let first = self.tracer.trace_footprint(&rray, 0.0, f32::INFINITY, fp);
                self.intersect(&rray, first.as_ref())
            };
            // Trees on the shore stand in the mirror image too.
            let tree = self.tree_before(&rray, hit.as_ref());
            let (lt, tr) = match (tree, hit) {
                (Some((f, h)), _) => (self.shade_tree(f, &h, r), h.t),
                (None, Some(SurfaceHit::Water { t: tr, point })) => {
                    (self.shade_water(point, r, t + tr, false), tr)
                }
                (None, Some(SurfaceHit::Terrain(h))) => {
                    (self.shade_terrain(&self.terrain_point(&h), r, t + h.t), h.t)
                }
                (None, None) => (self.sky_with(p, r, wave.is_none()), f32::INFINITY),
            };
            if tr.is_finite() {
                let ap = self.view.aerial_perspective_f32(r, tr);
                lt * ap.transmittance + ap.in_scatter
            } else {
                lt
            }
        } else {
            self.sky_with(p, r, wave.is_none())
        };

        // Transmission: the bed seen through absorbing, scattering water.
        let sigma = Vec3::from(wdesc.extinction_per_m);
        let albedo = Vec3::from(wdesc.scatter_albedo);
        let ambient = self.sun_irradiance * (self.sun.z.max(0.0) * self.cloud_shadow(p))
            + self.sky_irradiance;
        let body = albedo * ambient / std::f32::consts::PI;
        let eta = (1.0 / WATER_IOR) as f32;
        let cos_t2 = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
        let transmitted = if cos_t2 > 0.0 {
            let tdir = (eta * d + (eta * cos_i - cos_t2.sqrt()) * n).normalize();
            let tray = Ray::new(p - Vec3::Z * 1e-2, tdir);
            match self.ground.trace(&tray, 0.0, 2_000.0) {
                Some(h) => {
                    let tp = self.terrain_point(&h);
                    let water_depth = (p.z - h.point.z).max(0.0);
                    let sun_path = water_depth / self.sun.z.max(0.05);
                    let bed = self.shade_terrain(&tp, tdir, t + h.t) * exp3(-sigma * sun_path);
                    let att = exp3(-sigma * h.t);
                    bed * att + body * (Vec3::ONE - att)
                }
                None => body,
            }
        } else {
            Vec3::ZERO
        };
        let surface = fr * reflected + (1.0 - fr) * transmitted;
        match &wave {
            Some(w) => surface + self.sun_glitter(w, p, d, footprint),
            None => surface,
        }
    }

    /// The sun's glitter on the wind sea at `p` seen along `d`
    /// ([`glitter`]), where the terrain and trees let the sun through.
    fn sun_glitter(&self, w: &crate::water::WaveSample, p: Vec3, d: Vec3, footprint: f32) -> Vec3 {
        let e = self.sun_irradiance * self.cloud_shadow(p);
        let g = glitter(w, d, self.sun, e, |c| {
            fresnel(1.0, WATER_IOR, f64::from(c)).unpolarized() as f32
        });
        // Skip the shadow ray where the glitter could not show.
        if g.max_element() <= 1e-3 * e.max_element() {
            return Vec3::ZERO;
        }
        let o = p + Vec3::Z * 1e-2;
        let fp = RayCone {
            at_origin_m: footprint,
            per_metre: self.pixel_angle,
        };
        if self
            .tracer
            .occluded_footprint(&Ray::new(o, self.sun), 0.0, f32::INFINITY, fp)
        {
            return Vec3::ZERO;
        }
        g * self.trees_sun(o, 1e-2, footprint, None)
    }

    /// Rain between `rain_distance_m` and the hit: extinction of what is behind
    /// and the rainbow's single scattering (Musgrave 1993, §4.2.4.3.2).
    pub(super) fn rain(&self, rb: &Rainbow, d: Vec3, dist: f32, behind: Vec3) -> Vec3 {
        let a = &self.world.scene.atmosphere;
        let start = a.rain_distance_m as f32;
        let end = dist.min(start + 6_000.0);
        if end <= start {
            return behind;
        }
        let len = f64::from(end - start);
        let beta = a.rain_extinction_per_m;
        let (Ok(view), sun) = (Dir3::from_f32(d), self.world.sun_dir()) else {
            return behind;
        };
        let bow = rb
            .radiance(view, sun, self.sun_irradiance.as_dvec3(), beta, len)
            .map(|v| v.as_vec3())
            .unwrap_or(Vec3::ZERO);
        let ap = self.view.aerial_perspective_f32(d, start);
        behind * (-(beta * len) as f32).exp() + bow * ap.transmittance
    }
}

#[inline]
pub(super) fn exp3(v: Vec3) -> Vec3 {
    Vec3::new(v.x.exp(), v.y.exp(), v.z.exp())
}
