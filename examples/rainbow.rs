//! A rainbow over a plain: primary and secondary bows with reversed colours
//! and Alexander's dark band between them, from Musgrave's precomputed drop
//! table (natura-atmos `rainbow`) lit by the physical sky's sunlight, plus a
//! plot of the table itself.
//!
//! ```text
//! cargo run --release --example rainbow      # docs/gallery/atmos/rainbow*.png
//! ```

mod common;

use natura::atmos::Dir3;
use natura::atmos::rainbow::{Rainbow, RainbowParams};
use natura::atmos::sky::{Atmosphere, AtmosphereParams, Ground, SkyProjection, auto_exposure};
use natura::core::glam::{DVec3, Vec3};
use natura::core::{Image, ToneMap};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let width: usize = args.value(
        "--width",
        if quick { 240 } else { 960 },
        "image width, pixels",
    );
    let sun_el: f64 = args.value("--sun", 8.0, "sun elevation, degrees (behind the camera)");
    let rain: f64 = args.value(
        "--rain",
        2e-4,
        "rain extinction, 1/m (drop cross-section per volume)",
    );
    let out = args.out_dir("docs/gallery/atmos");
    args.finish();
    if !(16..=8192).contains(&width) {
        common::fail("--width must be in 16..=8192");
    }
    if !(0.0..=40.0).contains(&sun_el) {
        common::fail("--sun must be in 0..=40 degrees (the bow sinks below the horizon above 42°)");
    }
    let height = width * 9 / 16;

    let params = RainbowParams {
        rays_per_wavelength: if quick { 5_000 } else { 50_000 },
        ..RainbowParams::default()
    };
    let bow = common::check(Rainbow::new(&params));
    let atm = common::check(Atmosphere::new(AtmosphereParams::default()));
    // The sun behind the camera (azimuth 180°), the camera looking at azimuth 0.
    let sun = common::check(Dir3::from_angles(sun_el.to_radians(), std::f64::consts::PI));
    let view = common::check(atm.sky_view(DVec3::new(0.0, 0.0, 2.0), sun));
    let projection = SkyProjection::Pinhole {
        fov_y: 62f64.to_radians(),
        yaw: 0.0,
        pitch: 18f64.to_radians(),
    };
    let ground = Ground {
        albedo: Vec3::new(0.10, 0.14, 0.07),
    };
    let background = common::check(view.render(projection, width, height, Some(ground), true));
    let e_sun = view.sun_irradiance().as_dvec3();
    // A rain curtain from 400 m to 2400 m in front of the camera.
    let (near, depth) = (400.0f32, 2000.0f32);
    let img = common::check(Image::from_fn(width, height, |x, y| {
        let bg = background.get(x, y).unwrap_or(Vec3::ZERO);
        let Some(d) = projection.direction(x, y, width, height) else {
            return bg;
        };
        let reach = view.ground_distance(d).unwrap_or(f32::INFINITY);
        let rain_depth = (reach - near).clamp(0.0, depth);
        let dir = common::check(Dir3::from_f32(d));
        common::check(bow.apply(bg.as_dvec3(), dir, sun, e_sun, rain, f64::from(rain_depth)))
            .as_vec3()
    }));
    let ev = auto_exposure(&img, 0.18);
    let path = out.join("rainbow.png");
    common::check(img.tone_mapped(ev, ToneMap::AcesFilmic).save_png(&path));
    println!("wrote {}", path.display());

    // The table: colour strip and R, G, B curves from 30° to 60°.
    let (pw, strip, plot) = (if quick { 300 } else { 900 }, 40usize, 200usize);
    let t = bow.table();
    let at = |x: usize| t.lookup((30.0 + 30.0 * (x as f64 + 0.5) / pw as f64).to_radians());
    let peak = (0..pw).map(|x| at(x).max_element()).fold(0.0, f64::max);
    let chart = common::check(Image::from_fn(pw, strip + plot, |x, y| {
        let c = at(x) / peak;
        if y < strip {
            return ToneMap::AcesFilmic.apply(c.as_vec3() * 3.0);
        }
        let level = 1.0 - (y - strip) as f64 / plot as f64;
        let hit = |v: f64| (v - level).abs() < 1.2 / plot as f64;
        let mut px = Vec3::splat(0.03);
        if hit(c.x) {
            px.x = 1.0;
        }
        if hit(c.y) {
            px.y = 1.0;
        }
        if hit(c.z) {
            px.z = 1.0;
        }
        // Degree ticks every 5°.
        if (x * 30 / pw) % 5 == 0 && (x * 30) % pw < 30 {
            px += Vec3::splat(0.15);
        }
        px
    }));
    let path = out.join("rainbow_table.png");
    common::check(chart.save_png(&path));
    println!("wrote {}", path.display());
    println!(
        "table: primary+secondary carry {:.2}% of intercepted light",
        100.0 * t.total().y
    );
}
