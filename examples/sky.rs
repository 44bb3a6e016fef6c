//! The physical sky for a sweep of sun elevations, as fisheye domes and
//! panoramas with the ground seen through the aerial perspective
//! (natura-atmos: Hillaire 2020 LUTs with multiple scattering).
//!
//! ```text
//! cargo run --release --example sky                 # docs/gallery/atmos/sky_*.png
//! cargo run --release --example sky -- --spectral   # 16-band spectral evaluation
//! ```

mod common;

use natura::atmos::sky::{
    Atmosphere, AtmosphereParams, Evaluation, Ground, SkyProjection, auto_exposure,
};
use natura::core::glam::{DVec3, Vec3};
use natura::core::{Image, Progress, ToneMap};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let spectral = args.switch("--spectral", "spectral instead of RGB evaluation");
    let size: usize = args.value(
        "--size",
        if quick { 96 } else { 256 },
        "fisheye diameter, pixels",
    );
    let altitude: f64 = args.ranged(
        "--altitude",
        300.0,
        0.0..=1e7,
        "camera altitude above the ground, m",
    );
    let out = args.out_dir("docs/gallery/atmos");
    args.finish();
    if !(8..=4096).contains(&size) {
        common::fail("--size must be in 8..=4096");
    }

    let mut params = AtmosphereParams::default();
    if spectral {
        params.evaluation = Evaluation::Spectral;
    }
    let bar = common::Bar::new();
    let atm = common::check(Atmosphere::with_progress(params, &bar));
    let camera = DVec3::new(0.0, 0.0, altitude);
    let elevations = [-6.0, -2.0, 0.0, 2.0, 5.0, 10.0, 25.0, 45.0, 80.0];
    let (pw, ph) = (size * 4, size);
    let cols = 3;
    let rows = elevations.len().div_ceil(cols);
    let mut fisheye = Vec::new();
    let mut panos = Vec::new();
    let ground = Ground {
        albedo: Vec3::new(0.12, 0.11, 0.09),
    };
    for (k, &el) in elevations.iter().enumerate() {
        bar.start(&format!("sun {el:+}°"), 2);
        let sun = common::check(Atmosphere::sun_at_elevation_deg(el));
        let view = common::check(atm.sky_view(camera, sun));
        let dome = common::check(view.render(SkyProjection::Fisheye, size, size, None, true));
        let pano = common::check(view.render(
            SkyProjection::Panorama {
                min_elevation: (-15f64).to_radians(),
                max_elevation: 45f64.to_radians(),
            },
            pw,
            ph,
            Some(ground),
            true,
        ));
        bar.advance(2);
        bar.finish();
        // Each panel gets its own camera exposure so twilight stays visible;
        // the printed stops show how much darker it really is.
        let ev = auto_exposure(&dome, 0.18).clamp(-20.0, 25.0);
        println!(
            "sun {el:+5.1}°: exposure {ev:+.1} EV, zenith {}",
            fmt(view.radiance(natura::atmos::Dir3::UP))
        );
        fisheye.push(dome.tone_mapped(ev, ToneMap::AcesFilmic));
        panos.push(pano.tone_mapped(ev, ToneMap::AcesFilmic));
        let _ = k;
    }
    let gap = 4;
    let sheet = common::check(Image::from_fn(
        cols * (size + gap) - gap,
        rows * (size + gap) - gap,
        |x, y| {
            let (c, r) = (x / (size + gap), y / (size + gap));
            let (ix, iy) = (x % (size + gap), y % (size + gap));
            let k = r * cols + c;
            if ix >= size || iy >= size || k >= fisheye.len() {
                return Vec3::splat(0.02);
            }
            fisheye[k].get(ix, iy).unwrap_or(Vec3::ZERO)
        },
    ));
    let strip = common::check(Image::from_fn(
        pw,
        elevations.len() * (ph + gap) - gap,
        |x, y| {
            let (k, iy) = (y / (ph + gap), y % (ph + gap));
            if iy >= ph {
                return Vec3::splat(0.02);
            }
            panos[k].get(x, iy).unwrap_or(Vec3::ZERO)
        },
    ));
    let tag = if spectral { "_spectral" } else { "" };
    for (name, img) in [
        (format!("sky_fisheye{tag}.png"), sheet),
        (format!("sky_panorama{tag}.png"), strip),
    ] {
        let path = out.join(name);
        common::check(img.save_png(&path));
        println!("wrote {}", path.display());
    }
}

fn fmt(c: Vec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", c.x, c.y, c.z)
}
