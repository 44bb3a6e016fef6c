//! The terran texture on a smooth sphere seen from orbit, point by point or
//! through natura-noise's SIMD batch evaluation.

use glam::{DVec3, Vec3};
use natura_core::simd::Simd;
use natura_core::{Image, NoProgress, Progress};

use crate::earth::terran::Terran;
use crate::error::{Result, direction, in_range};
use crate::footprint::Footprint;
use crate::row_fill::render_rows;
use crate::view::{View, sphere_hits};

/// A view of the unit sphere (the texture sphere) lit by a distant sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereView {
    /// The camera.
    pub view: View,
    /// Unit direction towards the sun.
    pub sun: DVec3,
    /// Light on the night side, as a fraction of full sun (0.05).
    pub ambient: f64,
}

impl SphereView {
    /// The sphere seen from `distance` radii above latitude `latitude` and
    /// longitude `longitude` (radians), looking at its centre with `vfov`.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) for a distance not above 1, a
    /// zero sun direction, or a bad field of view or resolution.
    pub fn orbit(
        distance: f64,
        latitude: f64,
        longitude: f64,
        vfov: f64,
        width: u32,
        height: u32,
        sun: DVec3,
    ) -> Result<Self> {
        in_range(
            "distance",
            distance,
            1.0 + 1e-9,
            1e12,
            "must be above the sphere (> 1 radius)",
        )?;
        let eye = DVec3::new(
            latitude.cos() * longitude.cos(),
            latitude.cos() * longitude.sin(),
            latitude.sin(),
        ) * distance;
        let up = if latitude.cos().abs() < 1e-6 {
            DVec3::X
        } else {
            DVec3::Z
        };
        Ok(Self {
            view: View::look_at(eye, DVec3::ZERO, up, vfov, width, height)?,
            sun: direction("sun", sun)?.normalize(),
            ambient: 0.05,
        })
    }

    /// Checks the sun and ambient light.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the bad field.
    pub fn validate(&self) -> Result<()> {
        direction("sun", self.sun)?;
        in_range("ambient", self.ambient, 0.0, 1.0, "must be in [0, 1]")?;
        Ok(())
    }

    /// Lambert shading of `albedo` at unit normal `n`.
    fn lit(&self, albedo: DVec3, n: DVec3) -> Vec3 {
        let k = self.ambient + (1.0 - self.ambient) * n.dot(self.sun.normalize()).max(0.0);
        (albedo * k).as_vec3()
    }
}

/// Renders a [`Terran`] texture on the unit sphere (one sample per pixel at
/// the pixel centre, footprint `t·pixel_angle`), unlit by bump, Lambert
/// shaded. [`render_points`](Self::render_points) evaluates each pixel with
/// the `f64` point path; [`render_batch`](Self::render_batch) gathers a row's
/// hit points and evaluates the continents and mottle fBm over them with
/// natura-noise's SIMD batch ([`natura_noise::Fbm::fill_points3_band`]),
/// then colours each pixel with the same [`Terran::shade`]. The two agree to
/// `f32` rounding of the noise. Multifractal continents have no batch path
/// and are evaluated point by point.
#[derive(Clone, Copy, Debug)]
pub struct TerranSphere<'a> {
    terran: &'a Terran,
}

/// Hit points of one image row.
struct RowHits {
    x: Vec<usize>,
    p: [Vec<f64>; 3],
    visible: Vec<f32>,
}

impl<'a> TerranSphere<'a> {
    /// A renderer of `terran`.
    #[must_use]
    pub fn new(terran: &'a Terran) -> Self {
        Self { terran }
    }

    fn hit(view: &SphereView, x: u32, y: u32) -> Option<(DVec3, Footprint)> {
        let v = &view.view;
        let d = v.pixel(x, y);
        let (t0, _) = sphere_hits(v.eye(), d, 1.0)?;
        (t0 > 0.0).then(|| {
            let fp = Footprint::new(t0 * v.pixel_angle()).unwrap_or(Footprint::POINT);
            (v.eye() + d * t0, fp)
        })
    }

    /// Renders `view` with the point path.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) for a bad view.
    pub fn render_points(&self, view: &SphereView, progress: &dyn Progress) -> Result<Image> {
        view.validate()?;
        let v = &view.view;
        render_rows(v.width(), v.height(), "terran", progress, |y, row| {
            for (x, px) in row.iter_mut().enumerate() {
                if let Some((p, fp)) = Self::hit(view, x as u32, y) {
                    let b = self.terran.bump(p, fp);
                    let m = self.terran.mottle(p, fp);
                    let c = self.terran.shade(b, p.normalize().z.abs(), m).colour;
                    *px = view.lit(c, p.normalize());
                }
            }
        })
    }

    /// Renders `view` through the batch path at the best SIMD level.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) for a bad view.
    pub fn render_batch(&self, view: &SphereView) -> Result<Image> {
        self.render_batch_with(Simd::best(), view, &NoProgress)
    }

    /// Renders `view` through the batch path at the level `simd`.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) for a bad view.
    pub fn render_batch_with(
        &self,
        simd: Simd,
        view: &SphereView,
        progress: &dyn Progress,
    ) -> Result<Image> {
        let Some(continents) = self.terran.continents_fbm() else {
            return self.render_points(view, progress);
        };
        view.validate()?;
        let v = &view.view;
        let t = self.terran;
        let ms = t.params().mottle_scale;
        let cs = *continents.spectral();
        let msp = *t.mottle_fbm().spectral();
        render_rows(
            v.width(),
            v.height(),
            "terran (batch)",
            progress,
            |y, row| {
                let mut hits = RowHits {
                    x: Vec::with_capacity(row.len()),
                    p: [(); 3].map(|()| Vec::with_capacity(row.len())),
                    visible: Vec::with_capacity(row.len()),
                };
                let mut mottle_visible = Vec::with_capacity(row.len());
                for x in 0..row.len() {
                    if let Some((p, fp)) = Self::hit(view, x as u32, y) {
                        hits.x.push(x);
                        hits.p[0].push(p.x);
                        hits.p[1].push(p.y);
                        hits.p[2].push(p.z);
                        hits.visible.push(fp.visible(&cs) as f32);
                        mottle_visible.push(fp.scaled(ms).visible(&msp) as f32);
                    }
                }
                let n = hits.x.len();
                if n == 0 {
                    return;
                }
                let [px, py, pz] = &hits.p;
                let mut bump = vec![0.0f32; n];
                let mut mottle = vec![0.0f32; n];
                // Lengths agree by construction, so the batch calls cannot fail.
                let _ =
                    continents.fill_points3_band_with(simd, px, py, pz, &hits.visible, &mut bump);
                let sx: Vec<f64> = px.iter().map(|v| v * ms).collect();
                let sy: Vec<f64> = py.iter().map(|v| v * ms).collect();
                let sz: Vec<f64> = pz.iter().map(|v| v * ms).collect();
                let _ = t.mottle_fbm().fill_points3_band_with(
                    simd,
                    &sx,
                    &sy,
                    &sz,
                    &mottle_visible,
                    &mut mottle,
                );
                for i in 0..n {
                    let p = DVec3::new(px[i], py[i], pz[i]).normalize();
                    let c = t
                        .shade(f64::from(bump[i]), p.z.abs(), f64::from(mottle[i]))
                        .colour;
                    row[hits.x[i]] = view.lit(c, p);
                }
            },
        )
    }
}
