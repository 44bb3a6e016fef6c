//! Fowler, Prusinkiewicz & Battjes's figures (Fowler et al. 1992): flower
//! heads, fruits and cacti whose organs are placed by the collision-based
//! model of spiral phyllotaxis (natura-plant's `models::phyllotaxis`),
//! Figs. 4–15.
//!
//! ```text
//! cargo run --release --example figures_fowler                 # every figure
//! cargo run --release --example figures_fowler -- --quick      # small, for CI
//! cargo run --release --example figures_fowler -- --only coneflower
//! ```
//!
//! Writes into `--out` (default `./figures_fowler/`); docs/figures.md sets
//! each beside the source's caption. The primordia are placed on each
//! figure's receptacle, then replaced by organ meshes (petals, florets,
//! buds, bells, drupelets, spines, parachutes) at their organ frames (§3.1),
//! and drawn with natura-core's preview rasterizer. The world is z up.

mod common;

#[path = "fowler/heads.rs"]
mod heads;
#[path = "fowler/mesh.rs"]
mod mesh;
#[path = "fowler/organs.rs"]
mod organs;
#[path = "fowler/scenes.rs"]
mod scenes;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure};
use common::{Exit, Run, outln};
use natura::core::Image;
use natura::core::glam::{DMat3, DVec3, Vec3};

use heads::Head;
use mesh::{Mesh, View, render};

/// Fowler et al. 1992's figures: heads, fruits and cacti made by
/// collision-based phyllotaxis.
#[derive(Parser)]
#[command(name = "figures_fowler", version)]
struct Cli {
    /// Small and fast (CI): small pictures, coarse organs
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_fowler")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Fig. 4: green coneflower
    Coneflower,
    /// Fig. 5: daisies and chrysanthemums
    Daisies,
    /// Fig. 6: "Raspberry-os"
    Raspberries,
    /// Fig. 7: flowers of buttonbush
    Buttonbush,
    /// Fig. 8: seed head of goatsbeard
    Goatsbeard,
    /// Fig. 9: Mammillaria geminispina
    Mammillaria,
    /// Fig. 10: cauliflowers and broccoli
    Brassicas,
    /// Fig. 11: a table of cacti
    Cacti,
    /// Fig. 12: flower shop
    FlowerShop,
    /// Fig. 13: grape hyacinths
    GrapeHyacinths,
    /// Fig. 14: inflorescences of water smartweed
    Smartweed,
    /// Fig. 15: window sill
    WindowSill,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[
        Fig::Coneflower,
        Fig::Daisies,
        Fig::Raspberries,
        Fig::Buttonbush,
        Fig::Goatsbeard,
        Fig::Mammillaria,
        Fig::Brassicas,
        Fig::Cacti,
        Fig::FlowerShop,
        Fig::GrapeHyacinths,
        Fig::Smartweed,
        Fig::WindowSill,
    ];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::Coneflower => &["fowler_fig04_coneflower.png"],
            Fig::Daisies => &["fowler_fig05_daisies.png"],
            Fig::Raspberries => &["fowler_fig06_raspberries.png"],
            Fig::Buttonbush => &["fowler_fig07_buttonbush.png"],
            Fig::Goatsbeard => &["fowler_fig08_goatsbeard.png"],
            Fig::Mammillaria => &["fowler_fig09_mammillaria.png"],
            Fig::Brassicas => &["fowler_fig10_cauliflower_broccoli.png"],
            Fig::Cacti => &["fowler_fig11_table_of_cacti.png"],
            Fig::FlowerShop => &["fowler_fig12_flower_shop.png"],
            Fig::GrapeHyacinths => &["fowler_fig13_grape_hyacinths.png"],
            Fig::Smartweed => &["fowler_fig14_water_smartweed.png"],
            Fig::WindowSill => &["fowler_fig15_window_sill.png"],
        }
    }
}

type R<T> = Result<T, Exit>;

/// Picture size and organ detail.
#[derive(Clone, Copy, Debug)]
pub struct Detail {
    /// Picture width and height of a square figure, pixels.
    pub size: u32,
    /// Tessellation: 1 coarse, 2 fine.
    pub res: u32,
}

fn main() -> ExitCode {
    common::run(run)
}

fn run() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let d = if cli.quick {
        Detail { size: 240, res: 1 }
    } else {
        Detail { size: 900, res: 2 }
    };
    figures::make(&out, &cli.only, |fig| Ok(vec![draw(fig, d)?]))
}

/// Reports a head's organ count and triangles.
fn report(what: &str, h: &Head) -> Run {
    outln(format_args!(
        "  {what}: {} organs placed, {} triangles",
        h.organs,
        h.mesh.triangles()
    ))
}

/// Adds `h` to `scene` at `at`, its axis turned by `rot`, scaled by `s`.
fn add(scene: &mut Mesh, h: &Mesh, at: [f64; 3], rot: DMat3, s: f64) {
    scene.put(h, DVec3::from_array(at), rot, s);
}

/// A tilt of the head's axis by `a` radians about x then a turn by `b` about z.
fn tilt(a: f64, b: f64) -> DMat3 {
    DMat3::from_rotation_z(b) * DMat3::from_rotation_x(a)
}

fn draw(fig: Fig, d: Detail) -> R<Image> {
    let res = d.res;
    let front = |down: f32| View::along(Vec3::new(0.0, 1.0, -down));
    match fig {
        Fig::Coneflower => {
            let h = heads::coneflower(res)?;
            report("coneflower", &h)?;
            render(
                &h_crop(&h.mesh, -2.4),
                &front(0.45).zoomed(1.5),
                d.size,
                d.size,
            )
        }
        Fig::Daisies => {
            let daisy = heads::daisy(organs::colour::WHITE, res)?;
            let pink = heads::chrysanthemum(Vec3::new(0.75, 0.12, 0.4), res)?;
            let gold = heads::chrysanthemum(Vec3::new(0.9, 0.5, 0.05), res)?;
            report("daisy", &daisy)?;
            report("chrysanthemum", &pink)?;
            let mut s = Mesh::default();
            add(&mut s, &daisy.mesh, [-2.6, 0.6, 0.0], tilt(0.35, 0.2), 1.0);
            add(&mut s, &daisy.mesh, [2.6, 0.9, 0.3], tilt(0.3, -0.3), 0.95);
            add(&mut s, &daisy.mesh, [0.9, 3.2, 1.2], tilt(0.2, 0.1), 0.9);
            add(
                &mut s,
                &pink.mesh,
                [-0.2, -0.8, -0.3],
                tilt(0.45, 0.0),
                1.15,
            );
            add(&mut s, &gold.mesh, [-1.8, 3.0, 0.8], tilt(0.35, 0.5), 1.0);
            render(&s, &front(1.1).zoomed(1.4), d.size * 4 / 3, d.size)
        }
        Fig::Raspberries => scenes::raspberries(res, d),
        Fig::Buttonbush => scenes::buttonbush(res, d),
        Fig::Goatsbeard => {
            let h = heads::goatsbeard(res)?;
            report("goatsbeard", &h)?;
            render(
                &h_crop(&h.mesh, -4.0),
                &front(0.25).zoomed(1.35),
                d.size,
                d.size,
            )
        }
        Fig::Mammillaria => {
            let h = heads::geminispina(res)?;
            report("Mammillaria geminispina", &h)?;
            let mut s = Mesh::default();
            add(&mut s, &h.mesh, [0.0, 0.0, 0.0], DMat3::IDENTITY, 1.0);
            add(&mut s, &h.mesh, [1.55, 0.9, -0.2], tilt(0.25, 2.0), 0.7);
            add(&mut s, &h.mesh, [-1.4, 0.7, -0.25], tilt(-0.3, 1.0), 0.6);
            render(&s, &front(0.6).zoomed(1.5), d.size, d.size)
        }
        Fig::Brassicas => scenes::brassicas(res, d),
        Fig::Cacti => scenes::cacti(res, d),
        Fig::FlowerShop => scenes::flower_shop(res, d),
        Fig::GrapeHyacinths => scenes::grape_hyacinths(res, d),
        Fig::Smartweed => scenes::smartweed(res, d),
        Fig::WindowSill => scenes::window_sill(res, d),
    }
}

/// `m` without what lies below `z` (a stem's long foot), by dropping the
/// triangles there.
fn h_crop(m: &Mesh, z: f64) -> Mesh {
    m.clipped_below(z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura::plant::models::phyllotaxis::Primordium;

    fn separated(v: &[Primordium]) -> bool {
        v.iter().enumerate().all(|(n, a)| {
            v[..n]
                .iter()
                .all(|b| a.centre.distance(b.centre) >= a.radius + b.radius - 1e-9)
        })
    }

    #[test]
    fn every_figures_receptacle_is_packed_without_collisions() {
        // The receptacles and sizes the figures use: every pair of
        // primordia at least r_i + r_j apart, and more than a handful
        // placed.
        let cases = [
            (
                natura::plant::models::phyllotaxis::Receptacle::Cone {
                    radius: 1.0,
                    height: 1.5,
                },
                0.12,
                0.05,
            ),
            (heads::low_dome(0.25), 0.085, 0.03),
            (heads::cactus_body(1.6), 0.13, 0.09),
            (heads::dome(), 0.2, 0.13),
        ];
        for (rec, a, b) in cases {
            let (v, f) = heads::place(rec, a, b, [0.0, 0.98]).unwrap();
            assert!(v.len() > 40, "{}", v.len());
            assert!(separated(&v));
            assert_eq!(f.len(), v.len());
        }
    }

    #[test]
    fn the_coneflowers_disk_florets_shrink_towards_the_tip() {
        // Fig. 4: "the size of disk florets decreases linearly towards the
        // tip of the cone".
        let rec = natura::plant::models::phyllotaxis::Receptacle::Cone {
            radius: 1.0,
            height: 1.5,
        };
        let (v, f) = heads::place(rec, 0.12, 0.05, [0.0, 1.0]).unwrap();
        for (q, o) in v.iter().zip(&f) {
            assert!((q.radius - (0.12 - 0.07 * q.t)).abs() < 1e-12);
            assert_eq!(o.scale, q.radius);
        }
        let top = v.iter().max_by(|a, b| a.t.total_cmp(&b.t)).unwrap();
        assert!(top.radius < 0.07 && top.t > 0.7, "{top:?}");
        // The first ring (the ray florets) sits at the base and fills
        // until a primordium collides (§2.3): 13 rays, a Fibonacci number,
        // with room on the circle for 26.
        let ring = v.iter().take_while(|q| q.t < 1e-9).count();
        assert_eq!(ring, 13);
        assert!(v[ring..].iter().all(|q| q.t > 1e-9));
    }

    #[test]
    fn docs_figures_md_links_every_picture() {
        let missing = common::figures::unlisted_in_figures_md::<Fig>();
        assert!(missing.is_empty(), "not in docs/figures.md: {missing:?}");
    }

    #[test]
    fn a_quick_figure_is_drawn_and_is_the_same_twice() {
        let d = Detail { size: 64, res: 1 };
        let a = draw(Fig::Raspberries, d).unwrap();
        let b = draw(Fig::Raspberries, d).unwrap();
        assert_eq!(a.to_srgb8(), b.to_srgb8());
        let bg = View::along(Vec3::Y).background;
        let covered = a.pixels().as_slice().iter().filter(|&&c| c != bg).count();
        assert!(covered > 64 * 64 / 10, "{covered}");
    }
}
