//! Ebert's procedural clouds (Ebert 2001, "Cloud Modeling" and "Animating
//! Volumetric Procedural Clouds"): the nine-sphere cumulus, cirrus, a
//! cirrostratus layer over cirrus, the cumulus warped along the jet stream with an eased
//! amount, and "A Cloud is Born". Rendered with Ebert's shadow-table march
//! plus the multiple-scattering cache; the cumulus is also
//! written as an OpenVDB file with `--vdb` (and always with `--quick`).
//!
//! ```text
//! cargo run --release --example clouds                 # 480 × 320 frames
//! cargo run --release --example clouds -- --quick      # small, for CI
//! cargo run --release --example clouds -- --seed 3 --vdb --out renders
//! cargo run --release --example clouds -- --help       # every flag and its default
//! ```
//!
//! Writes `clouds_cumulus.png`, `clouds_cumulus_detail.png` (the cumulus
//! eroded by noise detail down to the pixels' footprint), `clouds_cirrus.png`,
//! `clouds_cirrostratus.png`, `clouds_jet_stream.png` and `clouds_born.png`
//! (and `cumulus.vdb`) into
//! `--out` (default: `./clouds/`), with a progress bar per picture.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::cloudshot::{
    CUMULUS_EXTINCTION, CUMULUS_VIEW, Look, SHOT, cumulus, render, render_detailed, strip,
};
use common::{Exit, Run, outln};
use natura::core::glam::Vec3;
use natura::core::{Image, Progress};
use natura::volume::animate::{cloud_is_born, eased_amount, keyed_implicit};
use natura::volume::cloud::{
    Cloud, CloudParams, JetStream, cirrostratus_primitives, cloud, nine_sphere_cumulus,
};
use natura::volume::detail::DetailParams;
use natura::volume::grid::GridDensity;
use natura::volume::vdb;

/// Ebert's procedural clouds: the nine-sphere cumulus, cirrus, cirrostratus
/// over cirrus, the cumulus warped along the jet stream and "A Cloud is
/// Born", rendered with shadow tables and multiple scattering. Writes
/// clouds_cumulus.png, clouds_cumulus_detail.png, clouds_cirrus.png, clouds_cirrostratus.png,
/// clouds_jet_stream.png and clouds_born.png (and cumulus.vdb with --vdb or
/// --quick).
#[derive(Parser)]
#[command(name = "clouds", version)]
struct Cli {
    /// Small and fast (CI): 96 × 64 frames of coarse voxels; also writes
    /// cumulus.vdb
    #[arg(long)]
    quick: bool,
    /// Noise seed
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Also write the cumulus as cumulus.vdb (OpenVDB)
    #[arg(long)]
    vdb: bool,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "clouds")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(clouds)
}

fn clouds() -> Run {
    let cli: Cli = common::parse();
    let Cli {
        quick,
        seed,
        vdb: write_vdb,
        out,
    } = cli;
    let out = common::out_dir(&out)?;
    let write_vdb = write_vdb || quick;
    let look = Look::new(quick);
    let bar = common::Bar::new();

    // (a) The nine-sphere cumulus with the source's parameters.
    bar.start("cumulus", SHOT + u64::from(write_vdb));
    let (cumulus, img) = cumulus(&look, seed, &bar)?;
    img.save_png(out.join("clouds_cumulus.png"))?;
    if write_vdb {
        let baked = GridDensity::bake(&cumulus, look.cell)?;
        vdb::write_vdb(out.join("cumulus.vdb"), &[("density", &baked)])?;
        bar.advance(1);
    }
    bar.finish();

    // (a') The same cumulus eroded by noise detail down to the pixels'
    // footprint: its voxels alone are soft at this distance.
    bar.start("cumulus with detail", SHOT);
    let detail = DetailParams {
        feature_m: 1.5,
        octaves: 8,
        ..DetailParams::default()
    };
    render_detailed(
        &cumulus,
        &look,
        CUMULUS_EXTINCTION,
        CUMULUS_VIEW,
        Some((detail, seed)),
        &bar,
    )?
    .save_png(out.join("clouds_cumulus_detail.png"))?;
    bar.finish();

    // (b) Cirrus (Fig. 3): the three cylinders of the cirrostratus figure
    // alone, with the cirrus parameters, sheared along the jet stream.
    let cirrus_params = CloudParams {
        noise_frequency: 0.3,
        displacement: 1.5,
        ..CloudParams::cirrus(Vec3::new(6.0, 0.0, 0.0))
    };
    let big = Look {
        cell: look.cell * 4.0,
        ..look
    };
    bar.start("cirrus", SHOT);
    let ci = cloud(cirrostratus_primitives()[1..].to_vec(), cirrus_params, seed)?;
    render(&ci, &big, 120.0, Vec3::new(0.0, -0.9, -0.35), &bar)?
        .save_png(out.join("clouds_cirrus.png"))?;
    bar.finish();

    // (c) Cirrostratus (Fig. 4): one large ellipsoid over the cylinders.
    bar.start("cirrostratus", SHOT);
    let cs = cloud(cirrostratus_primitives(), cirrus_params, seed)?;
    // The cirrus parameters' density is small (scale 0.2 under the
    // exponent 1.5, about 0.05 in the veil): at 120 /m the veil is opaque
    // in its middle and milky toward its edges, where the sky shows through.
    render(&cs, &big, 120.0, Vec3::new(0.0, -0.9, -0.35), &bar)?
        .save_png(out.join("clouds_cirrostratus.png"))?;
    bar.finish();

    // (d) The jet-stream warp, eased in over 96 frames; the primitives stay put.
    let frames = [0u32, 32, 64, 96];
    bar.start("jet stream", SHOT * frames.len() as u64);
    let shots = frames
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
            let c: Cloud = cloud(nine_sphere_cumulus(), p, seed)?;
            render(
                &c,
                &look,
                CUMULUS_EXTINCTION,
                Vec3::new(0.0, -2.6, 0.25),
                &bar,
            )
        })
        .collect::<Result<Vec<Image>, Exit>>()?;
    strip(&shots)?.save_png(out.join("clouds_jet_stream.png"))?;
    bar.finish();

    // (e) A Cloud is Born: three elements move together and grow.
    let keys = cloud_is_born();
    let times = [0.0f32, 0.35, 0.7, 1.0];
    bar.start("cloud is born", SHOT * times.len() as u64);
    let shots = times
        .iter()
        .map(|&t| {
            let imp = keyed_implicit(&keys, t)?;
            let c = natura::volume::cloud::Cloud::new(imp, CloudParams::cumulus(), seed)?;
            render(
                &c,
                &look,
                CUMULUS_EXTINCTION,
                Vec3::new(0.0, -2.0, 0.25),
                &bar,
            )
        })
        .collect::<Result<Vec<Image>, Exit>>()?;
    strip(&shots)?.save_png(out.join("clouds_born.png"))?;
    bar.finish();
    outln(format_args!(
        "wrote clouds_cumulus.png, clouds_cirrus.png, clouds_cirrostratus.png, clouds_jet_stream.png and clouds_born.png{} to {}",
        if write_vdb { ", cumulus.vdb" } else { "" },
        out.display()
    ))
}
