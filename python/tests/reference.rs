//! The reference values of the Python tests (`python/tests/reference.json`),
//! computed here through natura's Rust API: the noises on a 2-D and a 3-D
//! lattice and at 2-D and 3-D points, synthesis, every erosion model, the
//! drainage analysis, an L-system's string and mesh, ocean fields, and (in
//! `reference/more.rs`) a rendered scene, an ecosystem, clouds and smoke,
//! solid textures and the sky. The test fails if
//! the file differs from what the Rust API computes now; `NATURA_BLESS=1
//! cargo test --release -p natura-python --test reference` rewrites it. The
//! Python tests compute the same values through `natura` and compare them
//! bit for bit, so the two together show the bindings equal the Rust API.

#[path = "reference/more.rs"]
mod more;

use std::fmt::Write as _;
use std::sync::Arc;

use natura_core::{HeightField, NoProgress, Seed};
use natura_noise::glam::{DVec2, DVec3};
use natura_noise::{
    Checkerboard, DistNoise, Fbm, Field, FilteredFbm, HeteroTerrain, HybridMultifractal, Lattice2,
    Lattice3, Multifractal, Perlin, RidgedMultifractal, Simplex, Sine, SparseConvolution, Spectral,
    StatsByAltitude, Steps, Turbulence, Value, VlNoise, Worley,
};
use natura_plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams};
use natura_terrain::analysis::{fill_depressions, flow_accumulation_mfd, strahler_order, wetness};
use natura_terrain::erosion::{
    Diffusion, DropletErosion, MusgraveHydraulic, PipeModel, StreamPower, Thermal,
};
use natura_terrain::synth::{
    FaultParams, SpectralParams, SraParams, poisson_faults, spectral_synthesis,
    successive_random_additions,
};

/// FNV-1a over the little-endian bytes of `values` (`natura`'s tests hash
/// the arrays' bytes the same way).
fn fnv(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

fn hash_f32(v: &[f32]) -> u64 {
    fnv(v.iter().flat_map(|x| x.to_le_bytes()))
}

/// The points of the point tests (the Python tests build the same arrays).
fn points2() -> Vec<DVec2> {
    (0..37)
        .map(|i| {
            let t = f64::from(i);
            DVec2::new(t * 0.173 - 3.1, (t * 0.61).sin() * 4.7 + 0.05)
        })
        .collect()
}

fn points3() -> Vec<DVec3> {
    points2()
        .iter()
        .enumerate()
        .map(|(i, p)| DVec3::new(p.x, p.y, (i as f64) * 0.29 - 5.3))
        .collect()
}

fn noise_line(name: &str, f: &dyn Field, perlin3: Option<Perlin>) -> String {
    let l2 = Lattice2::new(DVec2::new(0.3, -1.2), DVec2::new(0.37, 0.29), 17, 9).unwrap();
    let mut g2 = vec![0.0f32; l2.len()];
    f.fill_grid2(&l2, &mut g2).unwrap();
    let l3 = Lattice3::new(
        DVec3::new(-0.7, 0.4, 2.5),
        DVec3::new(0.41, 0.23, 0.5),
        11,
        5,
        3,
    )
    .unwrap();
    let mut g3 = vec![0.0f32; l3.len()];
    f.fill_grid3(&l3, &mut g3).unwrap();
    let p2: Vec<f32> = points2().iter().map(|&p| f.eval2(p) as f32).collect();
    let p3: Vec<f32> = match perlin3 {
        Some(perlin) => {
            let pts = points3();
            let (x, y, z): (Vec<f64>, Vec<f64>, Vec<f64>) = (
                pts.iter().map(|p| p.x).collect(),
                pts.iter().map(|p| p.y).collect(),
                pts.iter().map(|p| p.z).collect(),
            );
            let mut out = vec![0.0f32; pts.len()];
            perlin.fill_points3(&x, &y, &z, &mut out).unwrap();
            out
        }
        None => points3().iter().map(|&p| f.eval3(p) as f32).collect(),
    };
    format!(
        "    \"{name}\": {{\"grid2\": {}, \"grid3\": {}, \"points2\": {}, \"points3\": {}}}",
        hash_f32(&g2),
        hash_f32(&g3),
        hash_f32(&p2),
        hash_f32(&p3)
    )
}

fn noises() -> Vec<String> {
    let p = Perlin::new(7);
    let s = Spectral::default();
    let b: Arc<dyn Field> = Arc::new(p);
    let mut v = vec![
        noise_line("perlin", &p, Some(p)),
        noise_line("value", &Value::new(7), None),
        noise_line("simplex", &Simplex::new(7), None),
        noise_line("worley", &Worley::new(7, Default::default()).unwrap(), None),
        noise_line(
            "sparse_convolution",
            &SparseConvolution::new(7, Default::default()).unwrap(),
            None,
        ),
        noise_line("sine", &Sine, None),
        noise_line("steps", &Steps::new(7), None),
        noise_line("checkerboard", &Checkerboard, None),
        noise_line("fbm", &Fbm::new(p, s).unwrap(), None),
        noise_line("turbulence", &Turbulence::new(p, s).unwrap(), None),
        noise_line(
            "multifractal",
            &Multifractal::new(p, Default::default()).unwrap(),
            None,
        ),
        noise_line(
            "hetero_terrain",
            &HeteroTerrain::new(p, Default::default()).unwrap(),
            None,
        ),
        noise_line(
            "hybrid_multifractal",
            &HybridMultifractal::new(p, Default::default()).unwrap(),
            None,
        ),
        noise_line(
            "ridged_multifractal",
            &RidgedMultifractal::new(p, Default::default()).unwrap(),
            None,
        ),
        noise_line(
            "stats_by_altitude",
            &StatsByAltitude::new(p, Default::default()).unwrap(),
            None,
        ),
        noise_line("filtered_fbm", &FilteredFbm::new(p, s, 0.0).unwrap(), None),
        noise_line("dist_noise", &DistNoise::dist_noise(p, 1.0).unwrap(), None),
        noise_line("vl_noise", &VlNoise::vl_noise(p, 1.0).unwrap(), None),
    ];
    // A non-default case: fBm of Worley F2−F1 with H = 0.9, 5.5 octaves,
    // through a shared `dyn Field` basis as the bindings hold it.
    let w = Worley::new(
        3,
        natura_noise::WorleyParams {
            feature: natura_noise::WorleyFeature::F2MinusF1,
            ..Default::default()
        },
    )
    .unwrap();
    let s2 = s.with_h(0.9).with_octaves(5.5).with_frequency(0.5);
    v.push(noise_line(
        "fbm_worley_f2_minus_f1",
        &Fbm::new(w, s2).unwrap(),
        None,
    ));
    v.push(noise_line("fbm_dyn_perlin", &Fbm::new(b, s).unwrap(), None));
    v
}

fn terrain() -> Vec<String> {
    let start = spectral_synthesis(48, 40, 10.0, &SpectralParams::default(), Seed(3)).unwrap();
    let mut v = vec![format!(
        "    \"spectral\": {}",
        hash_f32(start.heights().as_slice())
    )];
    let sra = successive_random_additions(48, 40, 10.0, &SraParams::default(), Seed(3)).unwrap();
    v.push(format!(
        "    \"sra\": {}",
        hash_f32(sra.heights().as_slice())
    ));
    let faults = poisson_faults(48, 40, 10.0, &FaultParams::default(), Seed(3)).unwrap();
    v.push(format!(
        "    \"faults\": {}",
        hash_f32(faults.heights().as_slice())
    ));
    let run = |name: &str, f: &dyn Fn(&mut HeightField)| {
        let mut hf = start.clone();
        f(&mut hf);
        format!("    \"{name}\": {}", hash_f32(hf.heights().as_slice()))
    };
    let np = &NoProgress;
    v.push(run("thermal", &|hf| {
        let mut m = Thermal::new(Default::default(), hf).unwrap();
        m.run(hf, 20, np).unwrap();
    }));
    v.push(run("hydraulic", &|hf| {
        let mut m = MusgraveHydraulic::new(Default::default(), hf).unwrap();
        m.run(hf, 20, np).unwrap();
    }));
    v.push(run("droplet", &|hf| {
        let mut m = DropletErosion::new(Default::default(), hf, Seed(5)).unwrap();
        m.run(hf, 2000, np).unwrap();
    }));
    v.push(run("pipe", &|hf| {
        let mut m = PipeModel::new(Default::default(), hf).unwrap();
        m.run(hf, 20, np).unwrap();
    }));
    v.push(run("stream_power", &|hf| {
        let mut m = StreamPower::new(Default::default(), hf).unwrap();
        m.run(hf, 20, np).unwrap();
    }));
    v.push(run("diffusion", &|hf| {
        let mut m = Diffusion::new(Default::default(), hf).unwrap();
        m.run(hf, 20, np).unwrap();
    }));
    let (filled, depth) = fill_depressions(&start).unwrap();
    v.push(format!(
        "    \"fill_depressions\": [{}, {}]",
        hash_f32(filled.heights().as_slice()),
        hash_f32(depth.as_slice())
    ));
    let area = flow_accumulation_mfd(&start, 1.1).unwrap();
    v.push(format!(
        "    \"flow_accumulation\": {}",
        hash_f32(area.as_slice())
    ));
    let order = strahler_order(&start, 5000.0).unwrap();
    v.push(format!(
        "    \"strahler_order\": {}",
        fnv(order.as_slice().iter().copied())
    ));
    let wet = wetness(&start).unwrap();
    v.push(format!("    \"wetness\": {}", hash_f32(wet.as_slice())));
    v
}

/// The bush of The Algorithmic Beauty of Plants, fig. 1.25
/// (examples/lsystems/fig1_25.l), 4 steps: its string and its mesh.
fn plant() -> Vec<String> {
    let text = include_str!("../../examples/lsystems/fig1_25.l");
    let l = LSystem::parse(text).unwrap();
    let mut d = Derivation::new(&l, 1).unwrap();
    d.derive(4).unwrap();
    let s = d.string();
    let shown = s.display(l.symbols());
    let geo = Turtle::new(&l, TurtleParams::for_lsystem(&l))
        .unwrap()
        .interpret(s)
        .unwrap();
    let m = PlantMesh::from_geometry(&geo, &MeshParams::default()).unwrap();
    let pos: Vec<f32> = m.positions.iter().flat_map(|p| p.to_array()).collect();
    let nrm: Vec<f32> = m.normals.iter().flat_map(|p| p.to_array()).collect();
    vec![
        format!("    \"string_hash\": {}", fnv(shown.bytes())),
        format!("    \"string_len\": {}", shown.len()),
        format!("    \"positions\": {}", hash_f32(&pos)),
        format!("    \"normals\": {}", hash_f32(&nrm)),
        format!(
            "    \"indices\": {}",
            fnv(m.indices.iter().flat_map(|i| i.to_le_bytes()))
        ),
        format!("    \"vertices\": {}", m.positions.len()),
        format!("    \"triangles\": {}", m.indices.len() / 3),
    ]
}

/// A 32² TMA patch in finite depth, choppy enough to fold (foam forms),
/// evaluated at 0, 1.5 and 4 s with foam: each field's hash over the three
/// times (as the Python side stacks them), and a Phillips patch's height
/// at 2 s.
fn ocean() -> Vec<String> {
    use natura_ocean::spectrum::{Directional, Spreading};
    use natura_ocean::{
        Dispersion, Foam, FoamParams, FrameField, Jonswap, Ocean, OceanParams, Phillips, Tma,
    };
    let dispersion = Dispersion::FiniteDepth {
        g: natura_ocean::G,
        depth: 20.0,
    };
    let params = OceanParams {
        nx: 32,
        ny: 32,
        lx: 80.0,
        ly: 60.0,
        dispersion,
        choppiness: 3.0,
        ..OceanParams::default()
    };
    let spectrum = Directional {
        spectrum: Tma {
            jonswap: Jonswap {
                wind_speed: 14.0,
                fetch: 20_000.0,
                ..Jonswap::default()
            },
            depth: 20.0,
        },
        spreading: Spreading::Cos2s { s: 6.0 },
        wind_direction: 0.4,
        dispersion,
    };
    let ocean = Ocean::new(&params, &spectrum, Seed(5)).unwrap();
    let mut fields: Vec<Vec<f32>> = vec![Vec::new(); FrameField::ALL.len() + 1];
    let mut frame = ocean.evaluate(0.0).unwrap();
    let mut foam = Foam::for_frame(&frame, FoamParams::default()).unwrap();
    for t in [0.0, 1.5, 4.0] {
        ocean.evaluate_into(t, &mut frame).unwrap();
        for (v, f) in fields.iter_mut().zip(FrameField::ALL) {
            v.extend_from_slice(frame.field(f).as_slice());
        }
        foam.update(&frame).unwrap();
        fields[FrameField::ALL.len()].extend_from_slice(foam.coverage().as_slice());
    }
    let names = FrameField::ALL.iter().map(|f| f.name()).chain(["foam"]);
    let mut v: Vec<String> = names
        .zip(&fields)
        .map(|(n, f)| format!("    \"{n}\": {}", hash_f32(f)))
        .collect();
    let phillips = Ocean::new(
        &OceanParams {
            nx: 16,
            ny: 32,
            lx: 50.0,
            ly: 100.0,
            ..OceanParams::default()
        },
        &Phillips {
            wind_speed: 9.0,
            small_wave_length: 0.05,
            ..Phillips::default()
        },
        Seed(0),
    )
    .unwrap();
    let h = phillips.evaluate(2.0).unwrap();
    v.push(format!(
        "    \"phillips_height\": {}",
        hash_f32(h.height().as_slice())
    ));
    v
}

#[test]
fn reference_values_match_the_rust_api() {
    let mut text = String::from("{\n  \"noise\": {\n");
    text += &noises().join(",\n");
    text += "\n  },\n  \"terrain\": {\n";
    text += &terrain().join(",\n");
    text += "\n  },\n  \"plant\": {\n";
    text += &plant().join(",\n");
    text += "\n  },\n  \"ocean\": {\n";
    text += &ocean().join(",\n");
    for (name, lines) in [
        ("render", more::render()),
        ("eco", more::eco()),
        ("volume", more::volume()),
        ("texture", more::texture()),
        ("sky", more::sky()),
    ] {
        write!(text, "\n  }},\n  \"{name}\": {{\n").unwrap();
        text += &lines.join(",\n");
    }
    writeln!(text, "\n  }}\n}}").unwrap();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/reference.json");
    if std::env::var_os("NATURA_BLESS").is_some() {
        std::fs::write(path, &text).unwrap();
    }
    let stored = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        stored == text,
        "{path} differs from the Rust API's values; \
         rerun with NATURA_BLESS=1 after an intended change:\n{text}"
    );
}
