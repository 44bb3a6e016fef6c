//! Ebert's procedural clouds (Ebert 2001, "Cloud Modeling" and "Animating
//! Volumetric Procedural Clouds"): the nine-sphere cumulus, a cirrostratus
//! layer over cirrus, the cumulus warped along the jet stream with an eased
//! amount, and "A Cloud is Born". Rendered with Ebert's shadow-table march
//! plus the octave multiple-scattering approximation; the cumulus is also
//! written as an OpenVDB file with `--vdb` (and always with `--quick`).
//!
//! ```text
//! cargo run --release --example clouds                 # 480 × 320 frames
//! cargo run --release --example clouds -- --quick      # small, for CI
//! ```

mod common;

use natura::core::Image;
use natura::core::glam::Vec3;
use natura::volume::animate::{cloud_is_born, eased_amount, keyed_implicit};
use natura::volume::cloud::{
    Cloud, CloudParams, JetStream, cirrostratus_primitives, cloud, nine_sphere_cumulus,
};
use natura::volume::grid::GridDensity;
use natura::volume::render::{
    FastRenderer, FastSettings, LookAtCamera, MediumParams, Scene, Shadows, Sun,
};
use natura::volume::{Density, vdb};

struct Look {
    width: usize,
    height: usize,
    cell: f32,
}

fn render(d: &dyn Density, look: &Look, extinction: f32, view: Vec3) -> Image {
    let b = d.bounds();
    let c = (b.min + b.max) * 0.5;
    let r = (b.max - b.min).length() * 0.5;
    let baked = common::check(GridDensity::bake(d, look.cell));
    let scene = Scene {
        sun: Some(Sun {
            direction: Vec3::new(-0.5, -0.6, 0.62).normalize(),
            irradiance: Vec3::new(3.2, 3.0, 2.7),
        }),
        ..Scene::new(
            &baked,
            MediumParams {
                extinction,
                ..MediumParams::default()
            },
            Vec3::new(0.18, 0.3, 0.55),
        )
    };
    let settings = FastSettings {
        step: look.cell * 0.5,
        shadows: Shadows::Table(96),
        ..FastSettings::default()
    }
    .multiple_scattering();
    let camera = common::check(LookAtCamera::look_at(
        c + view * r,
        c,
        Vec3::Z,
        40f32.to_radians(),
        look.width as u32,
        look.height as u32,
    ));
    let fast = common::check(FastRenderer::new(&scene, settings));
    common::check(fast.render(&camera)).tone_mapped(0.0, natura::core::ToneMap::AcesFilmic)
}

/// Images side by side with 4 px white gaps.
fn strip(shots: &[Image]) -> Image {
    let (w, h) = (shots[0].width(), shots[0].height());
    common::check(Image::from_fn(
        w * shots.len() + 4 * (shots.len() - 1),
        h,
        |x, y| {
            let (k, r) = (x / (w + 4), x % (w + 4));
            if r >= w {
                Vec3::ONE
            } else {
                shots[k].get(r, y).unwrap_or(Vec3::ONE)
            }
        },
    ))
}

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let seed: u64 = args.value("--seed", 7, "noise seed");
    let write_vdb = args.switch("--vdb", "also write the cumulus as cumulus.vdb");
    let out = args.out_dir("docs/gallery/volume");
    args.finish();
    let look = if quick {
        Look {
            width: 96,
            height: 64,
            cell: 0.4,
        }
    } else {
        Look {
            width: 480,
            height: 320,
            cell: 0.08,
        }
    };

    // (a) The nine-sphere cumulus with the source's parameters.
    let cumulus = common::check(cloud(nine_sphere_cumulus(), CloudParams::cumulus(), seed));
    let img = render(&cumulus, &look, 4.0, Vec3::new(0.0, -2.4, 0.25));
    common::check(img.save_png(out.join("clouds_cumulus.png")));
    if write_vdb || quick {
        let baked = common::check(GridDensity::bake(&cumulus, look.cell));
        common::check(vdb::write_vdb(
            out.join("cumulus.vdb"),
            &[("density", &baked)],
        ));
    }

    // (b) Cirrostratus: one large ellipsoid over cylinders, cirrus parameters.
    let cs = common::check(cloud(
        cirrostratus_primitives(),
        CloudParams {
            noise_frequency: 0.3,
            displacement: 1.5,
            ..CloudParams::cirrus(Vec3::new(6.0, 0.0, 0.0))
        },
        seed,
    ));
    let big = Look {
        cell: look.cell * 4.0,
        ..look
    };
    common::check(
        render(&cs, &big, 12.0, Vec3::new(0.0, -0.9, -0.35))
            .save_png(out.join("clouds_cirrostratus.png")),
    );

    // (c) The jet-stream warp, eased in over 96 frames; the primitives stay put.
    let frames = [0u32, 32, 64, 96];
    let shots: Vec<Image> = frames
        .iter()
        .map(|&f| {
            let p = CloudParams {
                frame: f,
                jet_stream: Some(JetStream {
                    vector: Vec3::new(5.0, 0.0, 0.0),
                    amount: eased_amount(f, 0, 96),
                }),
                ..CloudParams::cumulus()
            };
            let c: Cloud = common::check(cloud(nine_sphere_cumulus(), p, seed));
            render(&c, &look, 4.0, Vec3::new(0.0, -2.6, 0.25))
        })
        .collect();
    common::check(strip(&shots).save_png(out.join("clouds_jet_stream.png")));

    // (d) A Cloud is Born: three elements move together and grow.
    let keys = cloud_is_born();
    let shots: Vec<Image> = [0.0f32, 0.35, 0.7, 1.0]
        .iter()
        .map(|&t| {
            let imp = common::check(keyed_implicit(&keys, t));
            let c = common::check(natura::volume::cloud::Cloud::new(
                imp,
                CloudParams::cumulus(),
                seed,
            ));
            render(&c, &look, 4.0, Vec3::new(0.0, -2.0, 0.25))
        })
        .collect();
    common::check(strip(&shots).save_png(out.join("clouds_born.png")));
    println!(
        "wrote clouds_cumulus.png, clouds_cirrostratus.png, clouds_jet_stream.png and clouds_born.png{} to {}",
        if write_vdb || quick {
            ", cumulus.vdb"
        } else {
            ""
        },
        out.display()
    );
}
