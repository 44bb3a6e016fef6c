//! Erosion gallery: a ridged-multifractal terrain eroded by each natura-terrain
//! method, written as hill-shaded relief pictures, a flow map and 16-bit height
//! maps.
//!
//! ```text
//! cargo run --release --example erosion                 # 1024², docs/gallery/terrain
//! cargo run --release --example erosion -- --quick --out /tmp/erosion
//! ```

mod common;

use std::path::Path;

use natura::core::glam::Vec3;
use natura::core::{HeightField, Image, Seed};
use natura::noise::{Perlin, RidgedMultifractal, RidgedParams, Spectral};
use natura::terrain::analysis::{self, Depressions};
use natura::terrain::erosion::{
    Diffusion, DiffusionParams, DropletErosion, DropletParams, Edges, Erodibility,
    MusgraveHydraulic, MusgraveParams, PipeModel, PipeParams, StreamPower, StreamPowerParams,
    Thermal, ThermalParams,
};
use natura::terrain::export;
use natura::terrain::synth::{FieldMapping, fill_noise};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let size: usize = args.value("--size", if quick { 128 } else { 1024 }, "samples per side");
    let seed: u64 = args.value("--seed", 7, "random seed");
    let only: Option<String> = args.optional(
        "--only",
        "one method: stream_power, musgrave, pipe, droplets, thermal, diffusion, combined",
    );
    let out = args.out_dir("docs/gallery/terrain");
    args.finish();
    if size < 16 {
        common::fail("--size must be at least 16");
    }
    const METHODS: [&str; 7] = [
        "stream_power",
        "musgrave",
        "pipe",
        "droplets",
        "thermal",
        "diffusion",
        "combined",
    ];
    if let Some(o) = only.as_deref().filter(|o| !METHODS.contains(o)) {
        common::fail(&format!("--only {o}: not one of {}", METHODS.join(", ")));
    }
    let want = |name: &str| only.as_deref().is_none_or(|o| o == name);
    let bar = common::Bar::new();
    // Work scales with the grid so --quick stays quick; steps are per 1024².
    let scale = size as f64 / 1024.0;
    let steps = |n: f64| ((n * scale).round() as u32).max(10);
    let cell = 10.0 * 1024.0 / size as f32; // a 10 km tile at any resolution

    // ---- the ridged multifractal (natura-noise), 1500 m of relief.
    let spectral = Spectral::default()
        .with_h(1.0)
        .with_lacunarity(2.0)
        .with_octaves(9.0)
        .with_frequency(1.0 / 3500.0);
    let ridged = common::check(RidgedMultifractal::new(
        Perlin::new(seed),
        RidgedParams {
            spectral,
            ..Default::default()
        },
    ));
    let mut base = common::check(fill_noise(
        size,
        size,
        cell,
        &FieldMapping {
            frequency: 1.0,
            height_m: 1.0,
            ..Default::default()
        },
        &ridged,
    ));
    let (lo, hi) = base.min_max();
    base.heights_mut()
        .as_mut_slice()
        .iter_mut()
        .for_each(|v| *v = (*v - lo) / (hi - lo) * 1500.0);
    save_relief(&base, &out.join("erosion_before.png"));
    common::check(export::save_height_png16(
        &downsample_hf(&base),
        out.join("erosion_before_height.png"),
    ));

    // ---- stream power with uplift: the drainage network. The map edge is the
    // base level (sea level, 0 m) that every river reaches.
    let mut sp_hf = base.clone();
    let (nx, ny) = (sp_hf.nx(), sp_hf.ny());
    for j in 0..ny {
        for i in 0..nx {
            if i == 0 || j == 0 || i == nx - 1 || j == ny - 1 {
                sp_hf.heights_mut()[(i, j)] = 0.0;
            }
        }
    }
    let strata = common::check(Erodibility::strata(&base, 120.0, 1.4, 0.6, None));
    let sp_params = StreamPowerParams {
        k: 4e-5,
        dt_yr: 10_000.0,
        ..Default::default()
    };
    let mut sp =
        common::check(StreamPower::new(sp_params, &sp_hf).and_then(|m| m.with_erodibility(strata)));
    if want("stream_power") || want("combined") {
        common::check(sp.run(&mut sp_hf, steps(120.0), &bar));
    }
    if want("stream_power") {
        save_relief(&sp_hf, &out.join("erosion_stream_power.png"));
        common::check(export::save_height_png16(
            &downsample_hf(&sp_hf),
            out.join("erosion_stream_power_height.png"),
        ));
        let area = common::check(analysis::flow_accumulation_d8(&sp_hf, Depressions::Route));
        save(
            common::check(export::flow_image(&area)),
            &out.join("erosion_flow.png"),
        );
    }

    if want("musgrave") {
        // ---- Musgrave–Kolb–Mace hydraulic (corrected) + thermal, as in MKM Plate 9.
        let mut mkm_hf = base.clone();
        let mkm = MusgraveParams {
            rain_period: 20,
            k_c: 5.0,
            ..Default::default()
        };
        let mut m = common::check(MusgraveHydraulic::new(mkm, &mkm_hf));
        common::check(m.run(&mut mkm_hf, steps(200.0), &bar));
        let th = ThermalParams {
            talus_rate: 0.05,
            ..Default::default()
        };
        common::check(
            Thermal::new(th.clone(), &mkm_hf)
                .and_then(|mut t| t.run(&mut mkm_hf, steps(100.0), &bar).map(|_| ())),
        );
        save_relief(&mkm_hf, &out.join("erosion_musgrave.png"));
    }

    if want("pipe") {
        // ---- virtual-pipe shallow water.
        let mut pipe_hf = base.clone();
        let pp = PipeParams {
            edges: Edges::Open,
            rain_m_per_s: 0.02,
            k_c: 0.1,
            ..Default::default()
        };
        let mut pipe = common::check(PipeModel::new(pp, &pipe_hf));
        common::check(pipe.run(&mut pipe_hf, steps(600.0), &bar));
        save_relief(&pipe_hf, &out.join("erosion_pipe.png"));
    }

    if want("droplets") {
        // ---- droplets.
        let mut drop_hf = base.clone();
        let mut drops = common::check(DropletErosion::new(
            DropletParams::default(),
            &drop_hf,
            Seed(seed),
        ));
        common::check(drops.run(
            &mut drop_hf,
            (400_000.0 * scale * scale).max(5000.0) as u64,
            &bar,
        ));
        save_relief(&drop_hf, &out.join("erosion_droplets.png"));
    }

    // ---- thermal weathering and diffusion alone.
    if want("thermal") {
        let mut th_hf = base.clone();
        common::check(
            Thermal::new(
                ThermalParams {
                    talus_rate: 0.1,
                    ..Default::default()
                },
                &th_hf,
            )
            .and_then(|mut t| t.run(&mut th_hf, steps(300.0), &bar).map(|_| ())),
        );
        save_relief(&th_hf, &out.join("erosion_thermal.png"));
    }

    if want("diffusion") {
        let mut df_hf = base.clone();
        common::check(
            Diffusion::new(DiffusionParams::default(), &df_hf)
                .and_then(|mut d| d.run(&mut df_hf, steps(100.0), &bar).map(|_| ())),
        );
        save_relief(&df_hf, &out.join("erosion_diffusion.png"));
    }

    if want("combined") {
        // ---- the landscape pipeline: stream power, then pipe-model and thermal detail.
        let mut combo = sp_hf.clone();
        let mut pipe = common::check(PipeModel::new(
            PipeParams {
                edges: Edges::Open,
                ..Default::default()
            },
            &combo,
        ));
        common::check(pipe.run(&mut combo, steps(300.0), &bar));
        common::check(
            Thermal::new(
                ThermalParams {
                    talus_rate: 0.05,
                    ..Default::default()
                },
                &combo,
            )
            .and_then(|mut t| t.run(&mut combo, steps(50.0), &bar).map(|_| ())),
        );
        save_relief(&combo, &out.join("erosion_combined.png"));
        let hi = analysis::hypsometric_integral(&combo).unwrap_or(0.0);
        println!("hypsometric integral after stream power + pipe + thermal {hi:.3}");
        common::check(export::save_height_png16(
            &downsample_hf(&combo),
            out.join("erosion_combined_height.png"),
        ));
        let deposit = common::check(pipe.deposition());
        save(
            Image::false_colour(&deposit, natura::core::Ramp::Coolwarm, -2.0, 2.0),
            &out.join("erosion_deposition.png"),
        );
    }

    let hi_before = analysis::hypsometric_integral(&base).unwrap_or(0.0);
    println!("{size} × {size} cells of {cell} m; hypsometric integral before {hi_before:.3}");
    println!("wrote pictures to {}", out.display());
}

/// Gallery pictures are at most 512 px across (PNG size); heights stay f32.
fn downsample_hf(hf: &HeightField) -> HeightField {
    let factor = hf.nx().max(hf.ny()).div_ceil(512).max(1);
    common::check(hf.box_downsample(factor))
}

fn save_relief(hf: &HeightField, path: &Path) {
    let img = common::check(export::relief_image(
        hf,
        Vec3::new(-1.0, 1.0, 0.9).normalize(),
    ));
    save(img, path);
}

/// Writes `img`, box-filtered to at most 512 px across.
fn save(img: Image, path: &Path) {
    common::check(common::check(img.fit_within(512)).save_png(path));
}
