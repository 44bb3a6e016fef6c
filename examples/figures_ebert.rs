//! Ebert's cloud figures (Ebert 2001) that the `clouds` example does not
//! show: cloud creatures of nine implicit spheres (Fig. 2) and a cumulus
//! grown by the volumetric implicit particle system (Fig. 8).
//!
//! ```text
//! cargo run --release --example figures_ebert                 # every figure
//! cargo run --release --example figures_ebert -- --quick      # small, for CI
//! ```
//!
//! Writes into `--out` (default `./figures_ebert/`); docs/figures.md sets
//! each beside the source's caption.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::cloudshot::{CUMULUS_EXTINCTION, Look, render, strip};
use common::figures::{self, Figure};
use common::{Exit, Run, outln};
use natura::core::glam::Vec3;
use natura::core::{Image, NoProgress};
use natura::volume::animate::{ImplicitParticles, ParticleParams};
use natura::volume::cloud::{Cloud, CloudParams, cloud};
use natura::volume::implicit::{Implicit, ImplicitPrimitive as P, Skeleton};

/// Ebert's cloud figures (Ebert 2001) not shown by the `clouds` example:
/// cloud creatures and the particle-system cumulus.
#[derive(Parser)]
#[command(name = "figures_ebert", version)]
struct Cli {
    /// Small and fast (CI): small frames of coarse voxels
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Noise seed
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_ebert")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Fig. 2: cloud creatures, each of nine implicit spheres
    Creatures,
    /// Fig. 8: a cumulus grown by the implicit particle system, 12 seeds to about 50
    Particles,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[Fig::Creatures, Fig::Particles];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::Creatures => &["ebert_fig02_cloud_creatures.png"],
            Fig::Particles => &["ebert_fig08_particle_cumulus.png"],
        }
    }
}

type R<T> = Result<T, Exit>;

fn main() -> ExitCode {
    common::run(run)
}

fn run() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let look = Look::new(cli.quick);
    let seed = cli.seed;
    figures::make(&out, &cli.only, |fig| {
        Ok(vec![match fig {
            Fig::Creatures => creatures(&look, seed)?,
            Fig::Particles => particle_cumulus(&look, seed, cli.quick)?,
        }])
    })
}

/// A rabbit of nine spheres, facing +x, about 10 m long: body, haunch,
/// head, two ears, tail, a fore paw and two hind feet. The source's
/// creatures were "made by positioning nine implicit spheres" in a GUI; it
/// does not give them.
fn rabbit() -> Vec<P> {
    vec![
        P::sphere(Vec3::new(0.6, 0.0, 3.0), 2.4),
        P::sphere(Vec3::new(-1.8, 0.0, 2.6), 2.3),
        P::sphere(Vec3::new(3.2, 0.0, 5.2), 1.6),
        P::sphere(Vec3::new(2.3, 0.0, 7.6), 0.8),
        P::sphere(Vec3::new(3.9, 0.0, 7.4), 0.8),
        P::sphere(Vec3::new(-4.2, 0.0, 3.4), 1.0),
        P::sphere(Vec3::new(2.8, 0.0, 0.9), 0.9),
        P::sphere(Vec3::new(-1.8, -1.3, 0.8), 1.0),
        P::sphere(Vec3::new(-1.8, 1.3, 0.8), 1.0),
    ]
}

/// A long-necked dragon of nine spheres, facing +x, about 13 m long:
/// haunch, body, chest, neck, head, snout, tail, a fore and a hind leg.
fn dragon() -> Vec<P> {
    vec![
        P::sphere(Vec3::new(-2.6, 0.0, 3.0), 2.1),
        P::sphere(Vec3::new(0.0, 0.0, 3.2), 2.3),
        P::sphere(Vec3::new(2.4, 0.0, 3.6), 2.0),
        P::sphere(Vec3::new(4.0, 0.0, 5.8), 1.3),
        P::sphere(Vec3::new(5.0, 0.0, 7.6), 1.4),
        P::sphere(Vec3::new(6.6, 0.0, 7.4), 0.9),
        P::sphere(Vec3::new(-5.4, 0.0, 4.6), 1.1),
        P::sphere(Vec3::new(2.4, 0.0, 1.0), 1.0),
        P::sphere(Vec3::new(-2.6, 0.0, 0.9), 1.0),
    ]
}

/// Fig. 2: the two creatures side by side, seen from the side, with the
/// cumulus parameters of Ebert's clouds.
fn creatures(look: &Look, seed: u64) -> R<Image> {
    let shots = [rabbit(), dragon()]
        .into_iter()
        .map(|prims| {
            let c: Cloud = cloud(prims, CloudParams::cumulus(), seed)?;
            render(
                &c,
                look,
                CUMULUS_EXTINCTION,
                Vec3::new(0.0, -1.9, 0.15),
                &NoProgress,
            )
        })
        .collect::<R<Vec<_>>>()?;
    Ok(strip(&shots)?)
}

/// Fig. 8's twelve seeds: spheres of 1 m on a 4 × 3 grid 2 m apart at
/// the cloud's base (the source gives the count, not the layout).
fn seeds() -> Vec<P> {
    (0..12)
        .map(|i| {
            P::sphere(
                Vec3::new((i % 4) as f32 * 2.0, (i / 4) as f32 * 2.0, 0.0),
                1.0,
            )
        })
        .collect()
}

/// The frames Fig. 8 shows, at 24 frames a second: the source's 200
/// frames ("less than 1 minute for 200 frames").
const FRAMES: [u32; 4] = [0, 66, 133, 200];

/// The particle system's implicit field at each of [`FRAMES`].
fn grow(seed: u64) -> R<Vec<Implicit>> {
    let mut s = ImplicitParticles::new(&seeds(), ParticleParams::default(), seed)?;
    let mut out = Vec::new();
    let mut frame = 0;
    for &f in &FRAMES {
        while frame < f {
            s.step(1.0 / 24.0)?;
            frame += 1;
        }
        out.push(s.implicit()?);
    }
    Ok(out)
}

/// The mean height of the primitives' centres (m).
fn mean_height(i: &Implicit) -> f32 {
    let ps = i.primitives();
    ps.iter()
        .map(|p| match p.skeleton {
            Skeleton::Point(c) => c.z,
            _ => 0.0,
        })
        .sum::<f32>()
        / ps.len() as f32
}

/// Fig. 8: the cumulus at frames 0, 66, 133 and 200, each frame framed on
/// the cloud as it is then.
fn particle_cumulus(look: &Look, seed: u64, quick: bool) -> R<Image> {
    let fields = grow(seed)?;
    let counts: Vec<usize> = fields.iter().map(|f| f.primitives().len()).collect();
    outln(format_args!(
        "  Fig. 8: primitives at frames {FRAMES:?}: {counts:?} (the source: 12 → about 50); mean height {:.1} → {:.1} m",
        mean_height(&fields[0]),
        mean_height(&fields[fields.len() - 1])
    ))?;
    let look = Look {
        cell: if quick { look.cell } else { 0.12 },
        ..*look
    };
    let shots = fields
        .into_iter()
        .map(|imp| {
            let c = Cloud::new(imp, CloudParams::cumulus(), seed)?;
            render(
                &c,
                &look,
                CUMULUS_EXTINCTION,
                Vec3::new(0.0, -2.0, 0.3),
                &NoProgress,
            )
        })
        .collect::<R<Vec<_>>>()?;
    Ok(strip(&shots)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cumulus_is_white_in_the_sun_and_shaded_away_from_it() {
        // The look of the cumulus figures (the `clouds` program's Fig. 1
        // shot): the sunlit side near white and well above the blue sky,
        // the side away from the sun darker.
        let (_, img) = common::cloudshot::cumulus(&Look::new(true), 7, &NoProgress).unwrap();
        let lum = |v: Vec3| 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
        let sky = lum(img.get(0, 0).unwrap());
        let px: Vec<f32> = (0..img.height())
            .flat_map(|y| (0..img.width()).map(move |x| (x, y)))
            .map(|(x, y)| lum(img.get(x, y).unwrap()))
            .collect();
        let brightest = px.iter().fold(0.0f32, |a, &b| a.max(b));
        assert!(brightest > 0.7, "sunlit side {brightest}");
        assert!(brightest > 2.0 * sky, "sunlit side {brightest}, sky {sky}");
        // The cloud's pixels (clearly apart from the sky): the shaded ones
        // are well below the sunlit ones.
        let cloud: Vec<f32> = px
            .iter()
            .copied()
            .filter(|&v| (v - sky).abs() > 0.1)
            .collect();
        assert!(cloud.len() > 100, "{} cloud pixels", cloud.len());
        let darkest = cloud.iter().fold(1.0f32, |a, &b| a.min(b));
        assert!(darkest < 0.75 * brightest, "{darkest} against {brightest}");
    }

    #[test]
    fn each_creature_is_nine_spheres() {
        // Fig. 2: "positioning nine implicit spheres".
        for c in [rabbit(), dragon()] {
            assert_eq!(c.len(), 9);
            assert!(c.iter().all(|p| matches!(p.skeleton, Skeleton::Point(_))));
        }
    }

    #[test]
    fn twelve_seeds_grow_to_about_fifty_primitives_and_rise() {
        // Fig. 8: 12 initial primitives, about 50 final, rising under
        // the upward turbulent force.
        let f = grow(7).unwrap();
        let n: Vec<usize> = f.iter().map(|i| i.primitives().len()).collect();
        assert_eq!(n[0], 12);
        assert!((35..=70).contains(&n[3]), "{n:?}");
        assert!(n.windows(2).all(|w| w[1] >= w[0]), "never fewer: {n:?}");
        assert!(mean_height(&f[3]) > mean_height(&f[0]) + 2.0);
    }
}
