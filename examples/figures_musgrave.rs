//! Musgrave's plates (Musgrave 1993, Musgrave et al. 1989) that no other
//! example shows, re-made by composing natura's models: "Misty Mountains"
//! (Pl. 1.2, strata in exponential mist), "Zabriskie Point"'s planar mirage
//! (Pl. 1.3), the patch that goes from planar to space filling (Pl. 2.2, MKM
//! 5), the terrain models as rendered patches (the fractal dimension from 2
//! to 3, Pl. 2.3; statistics by altitude with "Spirit Lake", Pl. 2.4–2.5;
//! the ridge by position, Pl. 2.6; Terrain(), Pl. 2.8; "Hell", Pl. 2.9), a
//! stream-bed patch before and after hydraulic erosion and thermal
//! weathering (Pl. 2.10–2.11, MKM 2 and 9), dunes by slumping (Pl.
//! 2.12–2.13, MKM 7 and 8), "Gaea & Selene" (Pl. 4.3–4.4), a quarter-lit planet with the umbra model and
//! with the shaded atmosphere (Pl. 4.5–4.6), a diffusion-limited aggregate
//! in radial fog (Pl. 4.7), the "Fractal
//! Mandala" of glowing gas (Pl. 4.8), the dispersing prism under the
//! empirical bow (Pl. 4.9), the physical bow's spectral aliasing and its
//! jittered antialiasing (Pl. 4.10–4.11), the full-circle rainbow modulated by fBm (Pl.
//! 4.12), "Bay Fog" (Pl. 5.1), the stages of the terran texture (Pl.
//! 5.9a–f), the ridged basis built from the Perlin basis (Musgrave 2001,
//! fig. 17), planets made from each basis, Voronoi seed table and fractal
//! (Musgrave 2001, figs. 9, 13, 18–28, 31), the multifractal Milky
//! Way (Musgrave 2001, fig. 32), and "Slickrock I" and "III" in random fBm
//! colour and a GIT texture, and a picture repainted by the GIT filter
//! (Musgrave 1998, figs. 15.13–15.15), and a 370° × 180° panorama of a
//! canyon system on Mars through the panoramic virtual screen (Pl. 8.1).
//!
//! ```text
//! cargo run --release --example figures_musgrave                 # into ./figures_musgrave/
//! cargo run --release --example figures_musgrave -- --quick --out /tmp/musgrave
//! cargo run --release --example figures_musgrave -- --only space-filling
//! cargo run --release --example figures_musgrave -- --help       # every flag and its default
//! ```
//!
//! One picture per plate (`musgrave_pl2-2_space_filling.png`, …);
//! docs/figures.md sets each beside the source's caption. The world is z up.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure};
use common::{Exit, Run, outln};
use natura::atmos::Dir3;
use natura::atmos::medium::{ExponentialMist, HomogeneousFog};
use natura::atmos::mirage::{PlanarMirage, StratifiedAir};
use natura::core::camera::PinholeCamera;
use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::core::{HeightField, Image};
use natura::noise::{Driven, DrivenKind, Fade, Fbm, Field, Param, Perlin, Spectral};
use natura::texture::earth::{Strata, StrataParams};
use natura::trace::{MipmapTracer, Ray, Tracer};

/// Musgrave's plates (Musgrave 1993; Musgrave et al. 1989) that no other
/// example shows: "Misty Mountains", the planar mirage of "Zabriskie Point",
/// the planar-to-space-filling patch, the terrain models as rendered
/// patches (Pl. 2.3–2.9), fluvial erosion before and after (Pl.
/// 2.10–2.11), dunes by slumping (Pl. 2.12–2.13), DLA in radial fog, the fractal
/// mandala, the prism under the empirical bow, the full-circle rainbow
/// modulated by fBm, "Bay Fog", the multifractal Milky Way (Musgrave
/// 2001), and Slickrock in GIT colour and the GIT filter (Musgrave 1998).
#[derive(Parser)]
#[command(name = "figures_musgrave", version)]
struct Cli {
    /// Small and fast (CI): smaller patches and pictures
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Random seed
    #[arg(long, default_value_t = 1993)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_musgrave")]
    out: PathBuf,
}

/// The plates, in the dissertation's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Pl. 1.2: "Misty Mountains": strata and exponential mist
    MistyMountains,
    /// Pl. 1.3: "Zabriskie Point": badlands over a planar mirage
    Zabriskie,
    /// Pl. 2.2 (MKM 5): a patch going from planar to space filling, β = 1/x
    SpaceFilling,
    /// Pl. 2.3 (MKM 6): fractal dimension from 2 to 3 across the patch
    Dimension,
    /// Pl. 2.4–2.5 (MKM 3, 11): statistics by altitude, with "Spirit Lake"
    SpiritLake,
    /// Pl. 2.6 (MKM 4): a ridge line by horizontal position
    Ridge,
    /// Pl. 2.8: Terrain(), the heterogeneous terrain model
    Terrain,
    /// Pl. 2.9: "Hell": ridged heterogeneous terrain over lava
    Hell,
    /// Pl. 2.10–2.11 (MKM 2, 9): a stream-bed patch before and after 2000
    /// steps of hydraulic erosion and thermal weathering
    Fluvial,
    /// Pl. 2.12–2.13 (MKM 7, 8): a patch of non-uniform lacunarity before
    /// and after 100 steps of thermal weathering (dunes)
    Dunes,
    /// Pl. 4.3–4.4: "Gaea & Selene": a planet occulting its moon, and the occultation close up
    GaeaSelene,
    /// Pl. 4.5–4.6: a quarter-lit planet with the cylinder-umbra model, and with the shaded atmosphere
    Umbra,
    /// Pl. 4.7: a diffusion-limited aggregate in radial fog
    DlaFog,
    /// Pl. 4.8: "Fractal Mandala": balls of gas glowing like black bodies
    Mandala,
    /// Pl. 4.9: a dispersing prism on a checkerboard under the empirical bow
    Prism,
    /// Pl. 4.10–4.11: the physical rainbow's spectral aliasing, and jittered
    SpectralAliasing,
    /// Pl. 4.12: a full-circle rainbow on black, modulated by 2-D fBm
    FullCircleBow,
    /// Pl. 5.1: "Bay Fog": an fBm fog sheet on a plane, with its shadows
    BayFog,
    /// Pl. 5.9a–f: the stages of the terran texture's construction
    TerranStages,
    /// Musgrave 2001, fig. 17: the ridged basis built from the Perlin basis
    RidgedBasis,
    /// Musgrave 2001, figs. 9, 13, 18–28, 31: planets from each basis, seed table and fractal
    Planets,
    /// Musgrave 2001, fig. 32: a multifractal Milky Way
    MilkyWay,
    /// Pl. 4.2 (MKM 12): "Carolina": receding ridges in exponential mist
    Carolina,
    /// Pl. 4.1: "Slickrock": ridged terrain in exponential mist with the
    /// Rayleigh approximation, over a black background
    SlickrockMist,
    /// Pl. 5.8 (Musgrave 1998, fig. 15.18): "Other State": Saturn over the
    /// windywave sea
    OtherState,
    /// Musgrave 1998, figs. 15.7–15.8: "Spirit Lake" and "Lethe": lakes
    /// under the ripples bump map
    Lakes,
    /// Musgrave 1998, figs. 15.13–15.14: "Slickrock I" and "III": ridged
    /// terrain in random fBm colour and in a GIT texture
    Slickrock,
    /// Musgrave 1998, fig. 15.15: a picture repainted by the GIT filter
    GitFilter,
    /// Pl. 8.1: a panorama of a canyon system on Mars, 370° × 180°, through
    /// the panoramic virtual screen
    VallesMarineris,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[
        Fig::MistyMountains,
        Fig::Zabriskie,
        Fig::SpaceFilling,
        Fig::Dimension,
        Fig::SpiritLake,
        Fig::Ridge,
        Fig::Terrain,
        Fig::Hell,
        Fig::Fluvial,
        Fig::Dunes,
        Fig::GaeaSelene,
        Fig::Umbra,
        Fig::DlaFog,
        Fig::Mandala,
        Fig::Prism,
        Fig::SpectralAliasing,
        Fig::FullCircleBow,
        Fig::BayFog,
        Fig::TerranStages,
        Fig::RidgedBasis,
        Fig::Planets,
        Fig::MilkyWay,
        Fig::SlickrockMist,
        Fig::Carolina,
        Fig::OtherState,
        Fig::Lakes,
        Fig::Slickrock,
        Fig::GitFilter,
        Fig::VallesMarineris,
    ];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::MistyMountains => &["musgrave_pl1-2_misty_mountains.png"],
            Fig::Zabriskie => &["musgrave_pl1-3_zabriskie_mirage.png"],
            Fig::SpaceFilling => &["musgrave_pl2-2_space_filling.png"],
            Fig::Dimension => &["musgrave_pl2-3_dimension_2_to_3.png"],
            Fig::SpiritLake => &["musgrave_pl2-4_spirit_lake.png"],
            Fig::Ridge => &["musgrave_pl2-6_ridge.png"],
            Fig::Terrain => &["musgrave_pl2-8_terrain.png"],
            Fig::Hell => &["musgrave_pl2-9_hell.png"],
            Fig::Fluvial => &[
                "musgrave_pl2-10_stream_bed.png",
                "musgrave_pl2-11_eroded.png",
            ],
            Fig::Dunes => &[
                "musgrave_pl2-12_dunes_before.png",
                "musgrave_pl2-13_dunes_after.png",
            ],
            Fig::GaeaSelene => &[
                "musgrave_pl4-3_gaea_selene.png",
                "musgrave_pl4-4_gaea_selene_detail.png",
            ],
            Fig::Umbra => &[
                "musgrave_pl4-5_umbra.png",
                "musgrave_pl4-6_shaded_atmosphere.png",
            ],
            Fig::DlaFog => &["musgrave_pl4-7_dla_radial_fog.png"],
            Fig::Mandala => &["musgrave_pl4-8_fractal_mandala.png"],
            Fig::Prism => &["musgrave_pl4-9_prism_empirical_bow.png"],
            Fig::SpectralAliasing => &[
                "musgrave_pl4-10_spectral_aliasing.png",
                "musgrave_pl4-11_jittered.png",
            ],
            Fig::FullCircleBow => &["musgrave_pl4-12_full_circle_bow.png"],
            Fig::BayFog => &["musgrave_pl5-1_bay_fog.png"],
            Fig::TerranStages => &["musgrave_pl5-9_terran_stages.png"],
            Fig::RidgedBasis => &["musgrave2001_fig17_ridged_basis.png"],
            Fig::Planets => &[
                "musgrave2001_fig09_roughness.png",
                "musgrave2001_figs13_18-23_bases.png",
                "musgrave2001_fig24_seed_tables.png",
                "musgrave2001_figs25-28_31_fractals.png",
            ],
            Fig::MilkyWay => &["musgrave2001_fig32_milky_way.png"],
            Fig::SlickrockMist => &["musgrave_pl4-1_slickrock.png"],
            Fig::Carolina => &["musgrave_pl4-2_carolina.png"],
            Fig::OtherState => &["musgrave_pl5-8_other_state.png"],
            Fig::Lakes => &[
                "musgrave1998_fig15-7_spirit_lake.png",
                "musgrave1998_fig15-8_lethe.png",
            ],
            Fig::Slickrock => &[
                "musgrave1998_fig15-13_slickrock_i.png",
                "musgrave1998_fig15-14_slickrock_iii.png",
            ],
            Fig::GitFilter => &["musgrave1998_fig15-15_git_filter.png"],
            Fig::VallesMarineris => &["musgrave_pl8-1_valles_marineris.png"],
        }
    }
}

type R<T> = Result<T, Exit>;

#[path = "musgrave/bay_fog.rs"]
mod bay_fog;
#[path = "musgrave/carolina.rs"]
mod carolina;
#[path = "musgrave/dla_fog.rs"]
mod dla_fog;
#[path = "musgrave/erosion.rs"]
mod erosion;
#[path = "musgrave/full_circle_bow.rs"]
mod full_circle_bow;
#[path = "musgrave/gaea_selene.rs"]
mod gaea_selene;
#[path = "musgrave/lakes.rs"]
mod lakes;
#[path = "musgrave/landscape.rs"]
mod landscape;
#[path = "musgrave/mandala.rs"]
mod mandala;
#[path = "musgrave/milky_way.rs"]
mod milky_way;
#[path = "musgrave/other_state.rs"]
mod other_state;
#[path = "musgrave/patches.rs"]
mod patches;
#[path = "musgrave/planets.rs"]
mod planets;
#[path = "musgrave/prism.rs"]
mod prism;
#[path = "musgrave/ridged_basis.rs"]
mod ridged_basis;
#[path = "musgrave/slickrock.rs"]
mod slickrock;
#[path = "musgrave/spectral_aliasing.rs"]
mod spectral_aliasing;
#[path = "musgrave/terran_stages.rs"]
mod terran_stages;
#[path = "musgrave/umbra.rs"]
mod umbra;
#[path = "musgrave/valles.rs"]
mod valles;
use landscape::{
    Landscape, desert_sky, misty_sky, ridged_field, smoothstep, strata_albedo, supersampled,
};

fn main() -> ExitCode {
    common::run(figures)
}

fn figures() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    figures::make(&out, &cli.only, |fig| {
        Ok(match fig {
            Fig::MistyMountains => vec![misty_mountains(cli.seed, cli.quick)?],
            Fig::Zabriskie => vec![zabriskie(cli.seed, cli.quick)?],
            Fig::SpaceFilling => vec![space_filling(cli.seed, cli.quick)?],
            Fig::Dimension => vec![patches::dimension_2_to_3(
                cli.seed,
                plate_2_2_spectral(),
                cli.quick,
            )?],
            Fig::SpiritLake => vec![patches::spirit_lake(cli.seed, cli.quick)?],
            Fig::Ridge => vec![patches::ridge(cli.seed, cli.quick)?],
            Fig::Terrain => vec![patches::terrain(cli.seed, cli.quick)?],
            Fig::Hell => vec![patches::hell(cli.seed, cli.quick)?],
            Fig::Fluvial => erosion::fluvial(cli.seed, cli.quick)?,
            Fig::Dunes => erosion::dunes(cli.seed, cli.quick)?,
            Fig::GaeaSelene => gaea_selene::pair(cli.seed, cli.quick)?,
            Fig::Umbra => umbra::pair(cli.seed, cli.quick)?,
            Fig::DlaFog => vec![dla_fog::dla_picture(cli.seed, cli.quick)?],
            Fig::Mandala => vec![mandala::mandala_picture(cli.quick)?],
            Fig::Prism => vec![prism::prism_picture(cli.quick)?],
            Fig::SpectralAliasing => spectral_aliasing::pair(cli.quick)?,
            Fig::FullCircleBow => vec![full_circle_bow::picture(cli.seed, cli.quick)?],
            Fig::BayFog => vec![bay_fog::bay_fog_picture(cli.seed, cli.quick)?],
            Fig::TerranStages => vec![terran_stages::picture(cli.seed, cli.quick)?],
            Fig::RidgedBasis => vec![ridged_basis::picture(cli.seed, cli.quick)?],
            Fig::Planets => planets::pictures(cli.seed, cli.quick)?,
            Fig::MilkyWay => vec![milky_way::milky_way_picture(cli.seed, cli.quick)?],
            Fig::SlickrockMist => vec![slickrock::plate(cli.seed, cli.quick)?],
            Fig::Carolina => vec![carolina::carolina(cli.seed, cli.quick)?],
            Fig::OtherState => vec![other_state::other_state(cli.seed, cli.quick)?],
            Fig::Lakes => lakes::pair(cli.seed, cli.quick)?,
            Fig::Slickrock => slickrock::pair(cli.seed, cli.quick)?,
            Fig::GitFilter => vec![slickrock::git_filtered(cli.seed, cli.quick)?],
            Fig::VallesMarineris => vec![valles::picture(cli.seed, cli.quick)?],
        })
    })
}

// ---------------------------------------------------------------- Pl. 1.2

/// Pl. 1.2's mist: extinction at the valley floor (per metre, slightly more
/// in blue) and its scale height, m (the source gives neither).
const MIST_EXTINCTION: [f64; 3] = [1.6e-3, 1.75e-3, 2.0e-3];
const MIST_SCALE_HEIGHT_M: f64 = 400.0;

/// Pl. 1.2's exponential-by-altitude mist (Musgrave 1993, §4.1.5).
fn misty_mist() -> R<ExponentialMist> {
    let [r, g, b] = MIST_EXTINCTION;
    Ok(ExponentialMist::new(
        DVec3::new(r, g, b),
        DVec3::new(0.86, 0.88, 0.92),
        0.0,
        MIST_SCALE_HEIGHT_M,
    )?)
}

/// Pl. 1.2 "Misty Mountains": ridged mountains banded by natura-texture's
/// sedimentary strata, rising out of exponential mist that fills the
/// valleys, the ridges receding into it.
fn misty_mountains(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 257 } else { 1025 };
    let hf = ridged_field(seed, n, 24_000.0, 7000.0, 0.2, 1600.0, |_, _| 1.0)?;
    let tracer = MipmapTracer::new(&hf)?;
    let strata = Strata::new(StrataParams {
        seed,
        txtscale: 1.0 / 150.0,
        turbscale: 0.15,
        ..StrataParams::default()
    })?;
    let mist = misty_mist()?;
    let scene = Landscape {
        tracer: &tracer,
        albedo: &strata_albedo(&strata),
        medium: &mist,
        sun: Vec3::new(-0.6, 0.5, 0.45).normalize(),
        sky: &misty_sky,
        shadows: false,
    };
    let (w, h) = if quick { (320, 180) } else { (1200, 675) };
    let x0 = 12_000.0;
    let ground = hf.height_at(x0, 1500.0).unwrap_or(0.0);
    let eye = Vec3::new(x0, 1500.0, ground.max(0.0) + 1300.0);
    let camera = PinholeCamera::look_at(
        eye,
        Vec3::new(x0, 18_000.0, 0.0),
        Vec3::Z,
        32f32.to_radians(),
        w,
        h,
    )?;
    let img = supersampled(w, h, if quick { 1 } else { 2 }, |x, y| {
        scene.look(eye, camera.ray_at(x, y).dir.normalize())
    })?;
    outln(format_args!(
        "  Pl. 1.2: mist extinction {:.2}/km at the floor, falling by e every {MIST_SCALE_HEIGHT_M} m",
        MIST_EXTINCTION[1] * 1000.0
    ))?;
    Ok(img)
}

// ---------------------------------------------------------------- Pl. 1.3

/// Air temperatures above and below Pl. 1.3's mirage plane, K: 20 °C air
/// over a 60 °C layer on the desert floor (the source gives none).
const MIRAGE_AIR_K: [f64; 2] = [293.15, 333.15];
/// Sea-level pressure, Pa.
const PRESSURE_PA: f64 = 101_325.0;
/// The mirage plane's and the eye's heights above the floor, m.
const MIRAGE_PLANE_M: f64 = 0.5;
const EYE_M: f64 = 1.7;

/// The mirage plane of Pl. 1.3 (Musgrave 1993, §4.3): one index step.
fn mirage_plane() -> R<PlanarMirage> {
    let [above, below] = MIRAGE_AIR_K;
    Ok(PlanarMirage::from_temperatures(
        MIRAGE_PLANE_M,
        above,
        below,
        PRESSURE_PA,
    )?)
}

/// Badlands: a flat floor, then separate ridged multifractal hills (the
/// part above half the peak kept, up to 130 m) in a belt 3.6 km to 5.8 km
/// out, on an 8 km square: gaps between them open onto the far floor and
/// the sky, which the mirage mirrors.
fn badlands(seed: u64, n: usize) -> R<HeightField> {
    ridged_field(seed, n, 8192.0, 1600.0, 0.5, 130.0, |_, y| {
        smoothstep(3600.0, 4400.0, y) * (1.0 - smoothstep(5000.0, 5800.0, y))
    })
}

/// Pl. 1.3: badlands seen across a hot desert floor through Musgrave's
/// planar mirage, whose normal an fBm bump tilts by about 0.1°: below the
/// horizon, within the critical grazing angle, the sky and the feet of the
/// hills appear mirrored. Strata texture on the hills, a light haze.
fn zabriskie(seed: u64, quick: bool) -> R<Image> {
    let plane = mirage_plane()?;
    let critical = plane
        .critical_grazing_angle()
        .ok_or_else(|| Exit::new(2, "the mirage layer is not thinner"))?;
    let hf = badlands(seed, if quick { 257 } else { 1025 })?;
    let tracer = MipmapTracer::new(&hf)?;
    let strata = Strata::new(StrataParams {
        seed,
        txtscale: 1.0 / 30.0,
        ..StrataParams::default()
    })?;
    let bump = Fbm::new(
        Perlin::new(seed ^ 0x13),
        Spectral {
            octaves: 4.0,
            frequency: 0.02,
            ..Spectral::default()
        },
    )?;
    let haze = HomogeneousFog::new(
        DVec3::new(2.2e-5, 2.8e-5, 3.6e-5),
        DVec3::new(0.78, 0.82, 0.9),
    )?;
    let scene = Landscape {
        tracer: &tracer,
        albedo: &strata_albedo(&strata),
        medium: &haze,
        sun: Vec3::new(-0.55, -0.45, 0.70).normalize(),
        sky: &desert_sky,
        shadows: false,
    };
    let look = |o: Vec3, d: Vec3| scene.look(o, d);
    let (w, h) = if quick { (360, 150) } else { (1200, 500) };
    let eye = Vec3::new(4096.0, 300.0, EYE_M as f32);
    let pitch = 0.55f32.to_radians();
    let camera = PinholeCamera::look_at(
        eye,
        eye + Vec3::new(0.0, pitch.cos(), pitch.sin()),
        Vec3::Z,
        4.2f32.to_radians(),
        w,
        h,
    )?;
    let mut err = None;
    let mut pixel = |x: f32, y: f32| {
        let d = camera.ray_at(x, y).dir.normalize();
        let hit_first = tracer.trace(&Ray::new(eye, d), 0.0, f32::INFINITY);
        let Ok(dir) = Dir3::new(d.as_dvec3()) else {
            return Vec3::ZERO;
        };
        let Some(meet) = plane.interact(eye.as_dvec3(), dir, None) else {
            return look(eye, d);
        };
        if hit_first.is_some_and(|hh| f64::from(hh.t) < meet.point.distance(eye.as_dvec3())) {
            return look(eye, d);
        }
        // The bumped normal at the meeting point.
        let g = bump.eval_grad2(DVec2::new(meet.point.x, meet.point.y)).1 * 0.002;
        let normal = match Dir3::new(DVec3::new(-g.x, -g.y, 1.0)) {
            Ok(n) => n,
            Err(e) => {
                err.get_or_insert(e);
                return Vec3::ZERO;
            }
        };
        let Some(meet) = plane.interact(eye.as_dvec3(), dir, Some(normal)) else {
            return look(eye, d);
        };
        let at = meet.point.as_vec3();
        let r = meet.reflectance as f32;
        let mut c = look(at + Vec3::Z * 1e-3, meet.reflected.as_vec3()) * r;
        if let Some(t) = meet.refracted {
            c += look(at - Vec3::Z * 1e-3, t.as_vec3()) * (1.0 - r);
        }
        c
    };
    let img = supersampled(w, h, if quick { 1 } else { 3 }, &mut pixel)?;
    if let Some(e) = err {
        return Err(e.into());
    }
    outln(format_args!(
        "  Pl. 1.3: indices {:.6} over {:.6}; critical grazing angle {:.2}°, so the mirage starts {:.0} m out",
        StratifiedAir::index_of(MIRAGE_AIR_K[0], PRESSURE_PA),
        StratifiedAir::index_of(MIRAGE_AIR_K[1], PRESSURE_PA),
        critical.to_degrees(),
        (EYE_M - MIRAGE_PLANE_M) / critical.tan()
    ))?;
    Ok(img)
}

// ---------------------------------------------------------------- Pl. 2.2

/// The spectral exponent β of a profile of fBm with exponent H: a profile's
/// power spectrum falls as 1/f^β with β = 2H + 1 (Musgrave 1993, §2.2.1.4;
/// natura-noise's [`GainConvention::H`](natura::noise::GainConvention::H)).
/// Plate 2.3's pairs (H = 1, β = 3) and (H = 0, β = 1) obey it.
fn beta_of_h(h: f64) -> f64 {
    2.0 * h + 1.0
}

/// The H of β = 1/x: H = (1/x − 1)/2, which goes from ∞ (planar, 1/f^∞)
/// as x → 0 to 0 (space filling, 1/f^1 in a profile) at x = 1. The source
/// prints "H = 1/x − 3/2" (Musgrave 1993, §2.3.2.2; Musgrave et al. 1989,
/// §3.2), which would be H = −1/2 at x = 1, past space filling, and would
/// break Plate 2.3's pairs.
fn h_of_x(x: f64) -> f64 {
    0.5 * (1.0 / x - 1.0)
}

/// The H the source prints for β = 1/x.
#[cfg(test)]
fn printed_h_of_x(x: f64) -> f64 {
    1.0 / x - 1.5
}

/// H across the patch, `h_of_x` of the point's x (the patch spans x in
/// (0, 1]); unbounded as x → 0, so its bounds are infinite.
#[derive(Clone, Copy, Debug)]
struct BetaOverX;

impl Field for BetaOverX {
    fn eval2(&self, p: DVec2) -> f64 {
        h_of_x(p.x)
    }
    fn eval3(&self, p: DVec3) -> f64 {
        h_of_x(p.x)
    }
    fn bound(&self) -> f64 {
        f64::INFINITY
    }
    fn lipschitz2(&self) -> f64 {
        f64::INFINITY
    }
    fn lipschitz3(&self) -> f64 {
        f64::INFINITY
    }
}

/// The longest and shortest wavelengths of Plate 2.2 in patch widths: the
/// upper and lower crossover scales "approximately 7 and 1/128"
/// (Musgrave 1993, §2.3.2.2).
const CROSSOVERS: [f64; 2] = [7.0, 1.0 / 128.0];

/// Plate 2.2's spectrum (Plate 2.3's too): λ = 2, the first octave at the
/// upper crossover and as many octaves as reach the lower one.
fn plate_2_2_spectral() -> Spectral {
    Spectral {
        h: 0.5,
        lacunarity: 2.0,
        octaves: (CROSSOVERS[0] / CROSSOVERS[1]).log2(),
        frequency: 1.0 / CROSSOVERS[0],
        ..Spectral::default()
    }
}

/// Plate 2.2's fBm: Perlin noise with the sources' cubic fade, λ = 2, the
/// first octave at the upper crossover and as many octaves as reach the
/// lower one (log₂ 896 ≈ 9.81), H = (1/x − 1)/2 at each point.
fn plate_2_2_fbm(seed: u64) -> R<Driven<Perlin>> {
    let basis = Perlin::with_fade(seed, Fade::Cubic);
    Ok(Driven::new(basis, plate_2_2_spectral(), DrivenKind::Fbm)?
        .with_h(Param::Field(std::sync::Arc::new(BetaOverX))))
}

/// The patch: `n` samples across x in (0, 1] (x = (i + 1)/n, never 0) and
/// half as many along y, heights scaled by `relief`.
fn patch(fbm: &Driven<Perlin>, n: usize, relief: f64) -> R<HeightField> {
    let cell = 1.0 / n as f32;
    let ny = n / 2;
    Ok(HeightField::from_fn(n, ny, cell, |i, j| {
        let p = DVec2::new((i + 1) as f64 / n as f64, (j + 1) as f64 / n as f64);
        (relief * fbm.eval2(p)) as f32
    })?)
}

/// Pl. 2.2: the patch seen from the front and above, flat-shaded in one
/// stone colour so the roughness reads from the shading alone.
fn space_filling(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 96 } else { 512 };
    let fbm = plate_2_2_fbm(seed)?;
    let hf = patch(&fbm, n, 0.1)?;
    for x in [0.1, 0.25, 0.5, 0.75, 1.0] {
        outln(format_args!(
            "  Pl. 2.2: x = {x:<4}: β = {:.2}, H = {:.2}",
            beta_of_h(h_of_x(x)),
            h_of_x(x)
        ))?;
    }
    let size = if quick { (320, 200) } else { (1200, 750) };
    let stone = Vec3::new(0.72, 0.62, 0.50);
    patches::render_patch(&hf, size, Vec3::new(0.55, 0.66, 0.82), &|_, _| {
        patches::Facet {
            albedo: stone,
            emission: Vec3::ZERO,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura::atmos::Medium;
    use natura::terrain::analysis::path_h;

    #[test]
    fn the_ridged_basis_peaks_where_the_perlin_basis_crosses_zero() {
        // Fig. 17: along a row, every sign change of the Perlin basis is a
        // ridge of one minus its absolute value (a value within the step's
        // reach of 1), and the ridged basis is 1 − |N| everywhere.
        let n = Perlin::with_fade(7, Fade::Cubic);
        let r = natura::noise::Ridged(n);
        let h = 1e-3;
        let (mut crossings, mut prev) = (0, n.eval2(DVec2::new(0.0, 2.37)));
        for i in 1..=4000 {
            let p = DVec2::new(f64::from(i) * h, 2.37);
            let v = n.eval2(p);
            assert!((r.eval2(p) - (1.0 - v.abs())).abs() < 1e-12);
            if v * prev < 0.0 {
                crossings += 1;
                // |N| ≤ its Lipschitz constant times the step at a crossing.
                assert!(r.eval2(p) >= 1.0 - n.lipschitz2() * h, "{p}");
            }
            prev = v;
        }
        assert!(crossings >= 2, "{crossings}");
    }

    #[test]
    fn docs_figures_md_links_every_picture() {
        let missing = common::figures::unlisted_in_figures_md::<Fig>();
        assert!(missing.is_empty(), "not in docs/figures.md: {missing:?}");
        let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
        for f in Fig::ALL {
            for name in f.files() {
                assert!(docs.join("gallery/figures").join(name).is_file(), "{name}");
            }
        }
    }

    #[test]
    fn the_mist_has_the_sources_mean_extinction() {
        // Musgrave 1993, eq. 4.1.5: along a ray from altitude z₁ to z₂ (in
        // scale heights) the mean extinction is (e^−z₁ − e^−z₂)/(z₂ − z₁),
        // and e^−z₁ for a level ray (eq. 4.1.6); τ is it times the length.
        let mist = misty_mist().unwrap();
        let h = MIST_SCALE_HEIGHT_M;
        let (a, b) = (DVec3::new(0.0, 0.0, 200.0), DVec3::new(0.0, 9000.0, 1100.0));
        let (z1, z2) = (a.z / h, b.z / h);
        let mean = ((-z1).exp() - (-z2).exp()) / (z2 - z1);
        let tau = mist.optical_depth(a, b);
        let want = DVec3::from(MIST_EXTINCTION) * mean * a.distance(b);
        assert!(
            ((tau - want) / want).abs().max_element() < 1e-9,
            "{tau} {want}"
        );
        let level = mist.optical_depth(a, a + DVec3::Y * 5000.0);
        let want = DVec3::from(MIST_EXTINCTION) * (-z1).exp() * 5000.0;
        assert!(((level - want) / want).abs().max_element() < 1e-12);
    }

    #[test]
    fn the_mirage_air_is_1_00027_and_reflects_totally_below_half_a_degree() {
        // Musgrave 1993, §4.3.2: air at room temperature and pressure has
        // an index of approximately 1.00027 (Gladstone–Dale here; the
        // source's rounding is ±5e-6).
        let n = StratifiedAir::index_of(MIRAGE_AIR_K[0], PRESSURE_PA);
        assert!((n - 1.00027).abs() < 5e-6, "{n}");
        // 60 °C under 20 °C air: a critical grazing angle near 0.46°.
        let plane = mirage_plane().unwrap();
        let c = plane.critical_grazing_angle().unwrap();
        assert!((c.to_degrees() - 0.46).abs() < 0.01, "{}", c.to_degrees());
        // Below it the eye's ray is mirrored whole (TIR, no refraction);
        // above it most of the light goes through.
        let eye = DVec3::new(0.0, 0.0, EYE_M);
        for (grazing, total) in [(0.5 * c, true), (2.0 * c, false)] {
            let d = Dir3::new(DVec3::new(0.0, grazing.cos(), -grazing.sin())).unwrap();
            let m = plane.interact(eye, d, None).unwrap();
            assert_eq!(m.refracted.is_none(), total, "{grazing}");
            assert_eq!(m.reflectance == 1.0, total);
            assert!((m.reflected.get().z - grazing.sin()).abs() < 1e-12);
        }
    }

    #[test]
    fn beta_over_x_goes_from_planar_to_space_filling() {
        // Pl. 2.2: β = 1/x on (0, 1]; 1/f^∞ at the left edge, space filling
        // (H = 0, D_f = 3) at the right.
        for x in [0.05, 0.2, 0.5, 0.8, 1.0] {
            assert!((beta_of_h(h_of_x(x)) - 1.0 / x).abs() < 1e-12, "{x}");
        }
        assert_eq!(h_of_x(1.0), 0.0);
        assert!(h_of_x(1e-6) > 1e5);
        // Pl. 2.3's pairs (H = 1, β = 3), (H = 0, β = 1).
        assert_eq!((beta_of_h(1.0), beta_of_h(0.0)), (3.0, 1.0));
    }

    #[test]
    fn the_printed_h_of_beta_over_x_is_not_beta_equals_2h_plus_1() {
        // The printed H = 1/x − 3/2 agrees with β = 2H + 1 only at x = 1/2
        // and reaches H = −1/2 (past space filling) at x = 1.
        assert!((printed_h_of_x(0.5) - h_of_x(0.5)).abs() < 1e-12);
        assert_eq!(printed_h_of_x(1.0), -0.5);
        for x in [0.25, 0.4, 2.0 / 3.0, 0.9] {
            assert!((beta_of_h(printed_h_of_x(x)) - 1.0 / x).abs() > 0.1, "{x}");
        }
    }

    #[test]
    fn the_crossovers_give_about_ten_octaves() {
        // Upper and lower crossover scales ≈ 7 and 1/128: log₂ 896 octaves.
        let f = plate_2_2_fbm(1).unwrap();
        assert!((f.spectral.octaves - 9.807).abs() < 1e-3);
        assert!((f.spectral.frequency - 1.0 / 7.0).abs() < 1e-15);
    }

    /// The variogram H of profiles along y at a fixed x, over lags inside
    /// the crossovers (1/64 to 1/8 of the patch), averaged over 8 seeds.
    fn measured_h(x: f64) -> (f64, f64) {
        let hs: Vec<f64> = (0..8)
            .map(|s| {
                let f = plate_2_2_fbm(100 + s).unwrap();
                let v: Vec<f64> = (0..4096)
                    .map(|j| f.eval2(DVec2::new(x, j as f64 / 256.0)))
                    .collect();
                path_h(&v, 4, 32).unwrap()
            })
            .collect();
        let m = hs.iter().sum::<f64>() / hs.len() as f64;
        let var = hs.iter().map(|h| (h - m).powi(2)).sum::<f64>() / (hs.len() - 1) as f64;
        (m, (var / hs.len() as f64).sqrt())
    }

    #[test]
    fn the_patch_has_the_h_of_beta_over_x() {
        // Profiles at x = 0.4, 1/2, 2/3, where β = 1/x gives H = 0.75, 0.5,
        // 0.25 and the printed formula 1.0, 0.5, 0. The noise basis biases
        // the variogram estimate by up to ±0.1 for H ≤ 0.5 (its smooth
        // interpolant); the 8 seeds' standard error is ≈ 0.01.
        for x in [0.4, 0.5, 2.0 / 3.0] {
            let (m, se) = measured_h(x);
            assert!(se < 0.03, "x = {x}: standard error {se}");
            assert!((m - h_of_x(x)).abs() < 0.1, "x = {x}: H {m}");
            if x != 0.5 {
                assert!(
                    (m - h_of_x(x)).abs() < (m - printed_h_of_x(x)).abs() - 0.1,
                    "x = {x}: H {m} nearer the printed {}",
                    printed_h_of_x(x)
                );
            }
        }
    }
}
