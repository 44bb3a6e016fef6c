//! Plate 5.1 of `figures_musgrave`, "Bay Fog": a stratus layer made as an
//! fBm texture on a plane (natura-atmos's `FogSheet`) filling the low
//! ground between ridged hills, thinning where the ground rises to meet it
//! and shading the sunlight beneath it.

use natura::atmos::medium::FogSheet;
use natura::core::Image;
use natura::core::camera::PinholeCamera;
use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::noise::{Fbm, Field, Perlin, Spectral};
use natura::texture::earth::{Strata, StrataParams};
use natura::trace::MipmapTracer;

use crate::common::Exit;
use crate::landscape::{Landscape, misty_sky, ridged_field, strata_albedo, supersampled};

type R<T> = Result<T, Exit>;

/// The fog's top, m, and its extinction at density 1, per metre.
pub(crate) const FOG_TOP_M: f64 = 90.0;
pub(crate) const FOG_EXTINCTION: f64 = 0.03;

/// The sheet: density 0.35 + fBm of (x, y) at 1.5 km (clear where that is
/// ≤ 0), white.
pub(crate) fn bay_fog(seed: u64) -> R<FogSheet<impl Fn(DVec2) -> f64 + Send + Sync>> {
    let fbm = Fbm::new(
        Perlin::new(seed ^ 0x51),
        Spectral {
            octaves: 6.0,
            frequency: 1.0 / 1500.0,
            ..Spectral::default()
        },
    )?;
    Ok(FogSheet::new(
        DVec3::splat(FOG_EXTINCTION),
        DVec3::new(0.93, 0.94, 0.96),
        FOG_TOP_M,
        move |p: DVec2| 0.35 + fbm.eval2(p),
    )?)
}

/// Pl. 5.1: hills (ridged multifractal, the lowest 35 % cut flat to make
/// the bay, up to 500 m) seen from a hilltop across the fogged bay.
pub(crate) fn bay_fog_picture(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 257 } else { 1025 };
    let hf = ridged_field(seed ^ 0xba, n, 16_000.0, 5000.0, 0.35, 500.0, |_, _| 1.0)?;
    let tracer = MipmapTracer::new(&hf)?;
    let strata = Strata::new(StrataParams {
        seed,
        txtscale: 1.0 / 400.0,
        turbscale: 0.3,
        ..StrataParams::default()
    })?;
    let fog = bay_fog(seed)?;
    let scene = Landscape {
        tracer: &tracer,
        albedo: &strata_albedo(&strata),
        medium: &fog,
        sun: Vec3::new(0.5, 0.3, 0.55).normalize(),
        sky: &misty_sky,
        shadows: true,
    };
    let (w, h) = if quick { (320, 180) } else { (1200, 675) };
    let (x0, y0) = (8000.0, 600.0);
    let ground = hf.height_at(x0, y0).unwrap_or(0.0).max(0.0);
    let eye = Vec3::new(x0, y0, ground + 450.0);
    let camera = PinholeCamera::look_at(
        eye,
        Vec3::new(x0, 9000.0, 0.0),
        Vec3::Z,
        40f32.to_radians(),
        w,
        h,
    )?;
    supersampled(w, h, if quick { 1 } else { 2 }, |x, y| {
        scene.look(eye, camera.ray_at(x, y).dir.normalize())
    })
}
