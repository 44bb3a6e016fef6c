//! The source papers' plant models as pictures: Honda's branch tiers, a
//! clonal plant foraging over patches of light, roots in soil water, tree
//! crowns and conifers competing for light, a tree of the extended crowns
//! model with a climber on it and a stand of three trees (open L-systems,
//! Měch & Prusinkiewicz 1996), collision-based phyllotaxis on a cone
//! (Fowler et al. 1992) and Ridley's packing on a disc, a pinnate leaf on a
//! curved stem, three phyllotaxes set by one constant, a pine cone, a
//! strawflower, beargrass and a red-hot poker whose flowers Ridley's packing
//! places, a herb lily and a tulip whose leaves curve and twist by rates
//! along them, field garlic on curled stems, a lilac, an astilbe and a
//! tree shaped by a silhouette by branch mapping, and an ecosystem's stand
//! drawn with that tree, and a *Spiraea* twig whose shoots tropism stands
//! up (Prusinkiewicz et al. 2001, Alg. 1, 2, 5, 4 and 6).
//!
//! ```text
//! cargo run --release --example plant_models                 # all, into ./plant_models/
//! cargo run --release --example plant_models -- --model crowns --quick --out /tmp/m
//! cargo run --release --example plant_models -- --help       # every flag and its default
//! ```
//!
//! Writes `MODEL.png` for each model into `--out` (default:
//! `./plant_models/`); the clonal plant also writes `clonal_patches.png`
//! (three stages over its patches of light), the roots `roots_water.png`
//! (the roots over the water left in their section of soil) and the 3-D
//! roots `roots3d_water.png` (among iso-surfaces of the water they took).

mod common;
#[path = "plant_models/ecosystem.rs"]
mod ecosystem;
#[path = "plant_models/fields.rs"]
mod fields;
#[path = "plant_models/inflorescences.rs"]
mod inflorescences;
#[path = "plant_models/limbs.rs"]
mod limbs;
// The flower meshes and their rasterizer, shared with figures_fowler (of
// which this program uses a part).
#[allow(dead_code)]
#[path = "fowler/mesh.rs"]
mod mesh;
#[allow(dead_code)]
#[path = "fowler/organs.rs"]
mod organs;
#[path = "plant_models/positional_info.rs"]
mod positional_info;
#[path = "plant_models/spiraea.rs"]
mod spiraea;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::outln;
use natura::core::Image;
use natura::core::glam::{DVec3, Vec3};
use natura::plant::models::Run as ModelRun;
use natura::plant::models::{
    climber, clonal, compound, conifers, crowns, phyllotaxis, positional, roots, roots3d, tiers,
};
use natura::plant::preview::{PreviewCamera, PreviewParams, render};
use natura::plant::turtle::{SurfaceInstance, TurtleFrame};
use natura::plant::{Geometry, MeshParams, PlantMesh};
use positional_info::{
    astilbe, bent, flowers, lilac, mapped, phyllotaxes, pine_cone_profile, pine_cone_scale,
    reticulata, silhouette_tree,
};

/// The models, in the order they are drawn.
const MODELS: [&str; 24] = [
    "tiers",
    "clonal",
    "roots",
    "roots3d",
    "crowns",
    "extended",
    "climber",
    "conifers",
    "stand",
    "phyllotaxis",
    "ridley",
    "compound",
    "phyllotaxes",
    "lilac",
    "astilbe",
    "silhouette",
    "pinecone",
    "strawflower",
    "beargrass",
    "kniphofia",
    "lily",
    "garlic",
    "stand-silhouettes",
    "spiraea",
];

/// The source papers' plant models as pictures: Honda's branch tiers, a
/// clonal plant, roots in soil water (in a section and in 3-D), tree crowns
/// and conifers competing for light, a tree of the extended crowns model and
/// a climber on it, a stand of three trees, phyllotaxis on a cone,
/// Ridley's packing on a disc, a pinnate leaf, three phyllotaxes, a lilac,
/// an astilbe, a tree shaped by a silhouette, a pine cone, strawflowers,
/// beargrass, red-hot pokers, a herb lily and a tulip, field garlic and an
/// ecosystem's stand of silhouette trees, and a Spiraea twig. Writes
/// MODEL.png for each.
#[derive(Parser)]
#[command(name = "plant_models", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// Draw only this model [default: all]
    #[arg(long, value_parser = MODELS)]
    model: Option<String>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "plant_models")]
    out: PathBuf,
}

/// Renders `g` seen along `view` into `name` under `out`.
fn picture(g: &Geometry, view: Vec3, size: u32, out: &std::path::Path, name: &str) -> common::Run {
    let mesh = PlantMesh::from_geometry(g, &MeshParams::default())?;
    let (lo, hi) = mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
    let cam = PreviewCamera::framing(lo, hi, view, None, 1.0)?;
    let img = render(&mesh, &PreviewParams::new(size, size, cam))?;
    img.save_png(out.join(name))?;
    outln(format_args!("{name}: {} triangles", mesh.triangle_count()))
}

/// Renders the final string of a model's run.
fn show(run: &ModelRun, view: Vec3, size: u32, out: &std::path::Path, name: &str) -> common::Run {
    picture(&run.geometry()?, view, size, out, name)
}

/// A living leaf cluster of the crowns: its tree (1, 2, …), its centre and
/// its radius (m).
type Cluster = (usize, DVec3, f64);

/// How far the second tree of the crowns figure is moved (m).
const CROWNS_APART_M: f64 = 4.0;

/// How far the second tree of the conifers figure is moved (m).
const CONIFERS_APART_M: f64 = 3.0;

/// The final string of the crowns (or the conifers, whose leaves live
/// `leaf_years`) drawn with a sphere for each living leaf cluster, and
/// those clusters ([`leaf_clusters`]); the second tree moved `apart`
/// metres along x (its axiom's move `f` lengthened).
fn crown_geometry(
    run: &ModelRun,
    leaf_years: u32,
    apart: f64,
) -> Result<(Geometry, Vec<Cluster>), common::Exit> {
    let f = run.lsystem.symbols().get("f");
    let mut s = run.string.clone();
    // The second tree's first `f` outside any inner branch is the move to
    // its place. Lengthening it leaves every module's tree as it was.
    let (tree, depth) = trees(run);
    if let Some(i) = (0..s.len()).find(|&i| tree[i] == 2 && depth[i] == 1 && Some(s.symbol(i)) == f)
    {
        s.params_mut(i)[0] += apart;
    }
    let moved = ModelRun {
        lsystem: run.lsystem.clone(),
        string: s,
        turtle: run.turtle.clone(),
    };
    let mut g = moved.geometry()?;
    let clusters = leaf_clusters(&moved, leaf_years, &tree)?;
    g.surfaces
        .extend(spheres(clusters.iter().map(|&(_, c, r)| (c, r))).surfaces);
    Ok((g, clusters))
}

/// Two trees drawn side by side from the run's final string, as they grew
/// (left) and with the second moved `apart` metres (right), under one
/// camera framed on the pair moved apart; written to `name`.
fn grown_and_apart(
    run: &ModelRun,
    leaf_years: u32,
    apart: f64,
    size: u32,
    out: &std::path::Path,
    name: &str,
) -> common::Run {
    let (together, clusters) = crown_geometry(run, leaf_years, 0.0)?;
    let (moved, _) = crown_geometry(run, leaf_years, apart)?;
    let segments = together.segment_count();
    let (lo, hi) = moved.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
    let cam = PreviewCamera::framing(lo, hi, Vec3::Y, None, 1.0)?;
    let shots = [together, moved]
        .iter()
        .map(|g| {
            let mesh = PlantMesh::from_geometry(g, &MeshParams::default())?;
            Ok(render(&mesh, &PreviewParams::new(size, size, cam))?)
        })
        .collect::<Result<Vec<Image>, common::Exit>>()?;
    let sheet = Image::contact_sheet(&shots, 2, 0, Vec3::ONE)?;
    sheet.save_png(out.join(name))?;
    outln(format_args!(
        "{name}: {segments} segments, {} leaf clusters",
        clusters.len()
    ))
}

/// The tree of Fig. 12: the crowns model extended, a branch losing half
/// its branching angle a year once its sister is shed, grown `years`.
fn extended_params(years: u32) -> crowns::CrownParams {
    crowns::CrownParams {
        years,
        straightening: 0.5,
        ..crowns::CrownParams::default()
    }
}

/// The climber of Fig. 13 for `steps` steps, seeded on the ground 2 cm
/// from the bark of `tree`'s first segment (its trunk), on the side facing
/// +x.
fn climber_params(tree: &Geometry, steps: u32) -> climber::ClimberParams {
    // Scaled to the tree (about 9 m tall): leaves to be seen on it.
    let p = climber::ClimberParams {
        step: 0.1,
        leaf: 0.35,
        offset: 0.04,
        reach: 0.5,
        cell: 0.5,
        width: 0.04,
        ..climber::ClimberParams::default()
    };
    let (base, r) = tree
        .start
        .first()
        .zip(tree.width0.first())
        .map_or((Vec3::ZERO, 0.0), |(&b, &w)| (b, 0.5 * w));
    climber::ClimberParams {
        start: [
            f64::from(base.x + r) + p.offset,
            f64::from(base.y),
            f64::from(base.z) + p.step,
        ],
        steps,
        ..p
    }
}

/// The pair of Fig. 15: two conifers 2.5 m apart, grown `years`.
fn conifer_pair(years: u32) -> conifers::ConiferParams {
    conifers::ConiferParams {
        years,
        trees_x: vec![-1.25, 1.25],
        ..conifers::ConiferParams::default()
    }
}

/// The stand of Fig. 16: three trees 2.5 m apart in a row, grown `years`.
/// (Five trees 1.5 m apart, the inner ones die within 14 years.)
fn stand_params(years: u32) -> crowns::CrownParams {
    crowns::CrownParams {
        years,
        trees_x: (0..3).map(|i| (f64::from(i) - 1.0) * 2.5).collect(),
        ..crowns::CrownParams::default()
    }
}

/// The height of each tree's lowest living leaf cluster (`trees` trees;
/// infinite for a tree without one).
fn lowest_clusters(clusters: &[Cluster], trees: usize) -> Vec<f64> {
    let mut low = vec![f64::INFINITY; trees];
    for &(t, c, _) in clusters {
        if (1..=trees).contains(&t) {
            low[t - 1] = low[t - 1].min(c.z);
        }
    }
    low
}

/// For each module of the crowns' final string, the tree it belongs to
/// (1, 2, …: the axiom's top-level branches in order; 0 outside them) and
/// its bracket depth.
fn trees(run: &ModelRun) -> (Vec<usize>, Vec<usize>) {
    let syms = run.lsystem.symbols();
    let (open, close) = (syms.get("["), syms.get("]"));
    let s = &run.string;
    let (mut depth, mut tree) = (0usize, 0usize);
    let (mut trees, mut depths) = (Vec::with_capacity(s.len()), Vec::with_capacity(s.len()));
    for i in 0..s.len() {
        let sym = Some(s.symbol(i));
        if sym == open {
            if depth == 0 {
                tree += 1;
            }
            depth += 1;
        }
        trees.push(if depth == 0 { 0 } else { tree });
        depths.push(depth);
        if sym == close {
            depth = depth.saturating_sub(1);
        }
    }
    (trees, depths)
}

/// The living leaf clusters of the crowns ([`crowns::living_clusters`]),
/// each with its tree (from [`trees`]).
fn leaf_clusters(
    run: &ModelRun,
    leaf_years: u32,
    tree: &[usize],
) -> Result<Vec<Cluster>, common::Exit> {
    Ok(crowns::living_clusters(run, leaf_years)?
        .into_iter()
        .map(|c| (tree[c.module], c.centre, c.radius))
        .collect())
}

/// Spheres at the given centres and radii, as turtle geometry.
fn spheres(items: impl Iterator<Item = (DVec3, f64)>) -> Geometry {
    let mut g = Geometry::default();
    for (c, r) in items {
        g.surfaces.push(SurfaceInstance {
            name: 'O',
            frame: TurtleFrame {
                p: c,
                ..TurtleFrame::default()
            },
            length: r,
            width: r,
            colour: 0,
            distance: 0.0,
        });
    }
    g
}

fn main() -> ExitCode {
    common::run(plant_models)
}

/// The program: every error returns through [`common::run`].
fn plant_models() -> common::Run {
    let Cli { quick, model, out } = common::parse();
    let out = common::out_dir(&out)?;
    let want = |n: &str| model.as_deref().is_none_or(|m| m == n);
    let size = if quick { 192 } else { 400 };
    if want("tiers") {
        // Fig. 5: two tiers competing for space, seen from above.
        let (run, _) = tiers::tiers(&tiers::TiersParams::default())?;
        show(&run, Vec3::NEG_Z, size, &out, "tiers.png")?;
    }
    if want("clonal") {
        // Fig. 7: the clone spreading over patches II, III and I, seen from
        // above, with random spacers and trifoliate leaves.
        let p = clonal::ClonalParams {
            steps: if quick { 60 } else { 182 },
            ..clonal::ClonalParams::fig7()
        };
        let (run, _) = clonal::clonal(&p)?;
        show(&run, Vec3::NEG_Z, size, &out, "clonal.png")?;
        // The same clone at three stages over its patches of light, drawn
        // in the plane as the source's figure shows it.
        let stages = if quick { [10, 20, 60] } else { [15, 40, 182] };
        let img = fields::clone_on_patches(&p, &stages, size as usize)?;
        img.save_png(out.join("clonal_patches.png"))?;
        outln(format_args!("clonal_patches.png: steps {stages:?}"))?;
    }
    if want("roots") {
        // Fig. 9: roots in a vertical section of soil, wet on the left, dry on the right.
        let p = roots::RootParams {
            steps: if quick { 60 } else { 186 },
            ..roots::RootParams::default()
        };
        let (run, soil) = roots::roots(&p)?;
        show(&run, Vec3::Y, size, &out, "roots.png")?;
        // The same roots over the water left in their section.
        let img = fields::roots_on_water(&run, &soil, size as usize)?;
        img.save_png(out.join("roots_water.png"))?;
        outln(format_args!("roots_water.png: {} cells", soil.nx * soil.nz))?;
    }
    if want("roots3d") {
        // Fig. 10: the same roots in a block of soil, seen obliquely.
        let mut p = roots3d::Roots3dParams::default();
        p.roots.steps = if quick { 60 } else { 301 };
        let (run, _) = roots3d::roots_3d(&p)?;
        show(&run, Vec3::new(0.5, 1.0, 0.3), size, &out, "roots3d.png")?;
        // Two root systems competing for the water, among iso-surfaces of
        // the water they took: with the default rootlets (left) and with
        // slower ones (right).
        let img = fields::competing_roots(&p, size)?;
        img.save_png(out.join("roots3d_water.png"))?;
        outln(format_args!(
            "roots3d_water.png: {} levels",
            fields::SHELLS.len()
        ))?;
    }
    if want("crowns") {
        // Fig. 14: two trees grown side by side, seen from the side with
        // their leaf clusters; on the left as they grew, on the right moved
        // apart, so each crown shows it grew away from the other.
        let p = crowns::CrownParams {
            years: if quick { 4 } else { 8 },
            trees_x: vec![-1.0, 1.0],
            ..crowns::CrownParams::default()
        };
        let run = crowns::crowns(&p)?;
        grown_and_apart(&run, p.leaf_years, CROWNS_APART_M, size, &out, "crowns.png")?;
    }
    if want("extended") {
        // Fig. 12: the extended model, a branch whose sister was shed
        // turning into its mother's direction, drawn without its leaves.
        let p = extended_params(if quick { 8 } else { 24 });
        let run = crowns::crowns(&p)?;
        show(&run, Vec3::Y, size, &out, "extended.png")?;
    }
    if want("climber") {
        // Fig. 13: a climbing plant seeded at the foot of the tree of
        // Fig. 12, winding up its trunk and out along its branches.
        let tree = crowns::crowns(&extended_params(if quick { 8 } else { 24 }))?.geometry()?;
        let p = climber_params(&tree, if quick { 80 } else { 700 });
        let (run, env) = climber::climber(&p, &tree)?;
        let mut g = tree;
        g.append(&run.geometry()?);
        picture(&g, Vec3::new(0.6, 1.0, 0.0), size, &out, "climber.png")?;
        outln(format_args!(
            "climber: {} segments; apices stopped by crowding {}, off the bark {}",
            run.count("F"),
            env.crowded,
            env.unsupported
        ))?;
    }
    if want("conifers") {
        // Fig. 15: two conifers grown side by side in tiers, the lower
        // tiers wider (the phase effect); on the right moved apart, each
        // crown flattened on the side that faced the other.
        let p = conifer_pair(if quick { 6 } else { 15 });
        let run = conifers::conifers(&p)?;
        grown_and_apart(
            &run,
            p.leaf_years,
            CONIFERS_APART_M,
            size,
            &out,
            "conifers.png",
        )?;
    }
    if want("stand") {
        // Fig. 16: a row of three trees grown together: shaded by its
        // neighbours, the middle one sheds its lower branches and keeps
        // only its upper crown.
        let p = stand_params(if quick { 10 } else { 14 });
        let run = crowns::crowns(&p)?;
        let (g, clusters) = crown_geometry(&run, p.leaf_years, 0.0)?;
        picture(&g, Vec3::Y, size, &out, "stand.png")?;
        let lowest = lowest_clusters(&clusters, p.trees_x.len());
        let shown: Vec<String> = lowest.iter().map(|z| format!("{z:.1}")).collect();
        outln(format_args!(
            "stand: lowest living leaf cluster of each tree at {} m",
            shown.join(", ")
        ))?;
    }
    if want("phyllotaxis") {
        // Fig. 4: primordia on a cone, shrinking towards the tip.
        let v = phyllotaxis::phyllotaxis(&phyllotaxis::PhyllotaxisParams::default())?;
        let g = spheres(v.iter().map(|p| (p.centre, p.radius)));
        picture(&g, Vec3::new(0.3, 0.5, -1.0), size, &out, "phyllotaxis.png")?;
    }
    if want("ridley") {
        // Fig. 13 (flat case): Vogel's pattern from Algorithm 5.
        let v = positional::ridley(1.0, 1e-5, |s| (s, 0.0), |_| 0.04)?;
        let g = spheres(v.iter().map(|o| {
            let a = o.angle_deg.to_radians();
            (
                DVec3::new(o.x * a.cos(), o.x * a.sin(), o.y),
                o.radius * 0.9,
            )
        }));
        picture(&g, Vec3::NEG_Z, size, &out, "ridley.png")?;
    }
    if want("compound") {
        // Fig. 7 (f): a pinnate leaf on an arching stem, seen from the side.
        let run = compound::compound(&compound::CompoundParams::fern())?;
        show(&run, Vec3::NEG_X, size, &out, "compound.png")?;
    }
    if want("phyllotaxes") {
        // Fig. 8: one constant of Algorithm 4 sets the phyllotaxis: a
        // distichous, a decussate and a spiral shoot, seen from the side.
        let sheet = Image::contact_sheet(
            &phyllotaxes()?
                .iter()
                .map(|p| {
                    let g = compound::compound(p)?.geometry()?;
                    let mesh = PlantMesh::from_geometry(&g, &MeshParams::default())?;
                    let (lo, hi) = mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
                    let cam = PreviewCamera::framing(lo, hi, Vec3::new(1.0, 0.35, 0.0), None, 1.0)?;
                    Ok(render(&mesh, &PreviewParams::new(size, size, cam))?)
                })
                .collect::<Result<Vec<Image>, common::Exit>>()?,
            3,
            0,
            Vec3::ONE,
        )?;
        sheet.save_png(out.join("phyllotaxes.png"))?;
        outln(format_args!(
            "phyllotaxes.png: Φ = 0°, 90° (pairs), 137.5° (single)"
        ))?;
    }
    if want("lilac") {
        // Fig. 18: lilac panicles by branch mapping (Algorithm 6): each
        // branch repeats the distal part of the longest axis of its order,
        // in decussate pairs, a flower at every axis's end; (a) S. chinensis
        // 'Rubra', purple, and (b) S. reticulata, creamy white.
        flowers(
            &lilac()?,
            Vec3::new(0.42, 0.28, 0.62),
            size,
            &out,
            "lilac.png",
        )?;
        flowers(
            &reticulata()?,
            Vec3::new(0.85, 0.82, 0.66),
            size,
            &out,
            "lilac_reticulata.png",
        )?;
    }
    if want("astilbe") {
        // Fig. 19: the source's "small modification" of Algorithm 6, one
        // branch a node rolled 137.5° (spiral), an astilbe's plume.
        let g = mapped(&astilbe()?, 0.035, 0.22)?;
        flowers(&g, Vec3::new(0.86, 0.7, 0.78), size, &out, "astilbe.png")?;
    }
    if want("silhouette") {
        // Fig. 20: straight first-order axes and short higher orders: the
        // children's lengths along the trunk are the crown's silhouette.
        let g = mapped(&silhouette_tree()?, 0.1, 0.25)?;
        flowers(&g, Vec3::new(0.3, 0.55, 0.22), size, &out, "silhouette.png")?;
    }
    if want("pinecone") {
        // Fig. 15: a jack-pine cone, its scales placed by Algorithm 5 on an
        // ovoid receptacle, the axis bent afterwards.
        let (len, curve) = pine_cone_profile();
        let scales = positional::ridley(len, 1e-4, &curve, pine_cone_scale(&curve))?;
        let g = spheres(scales.iter().map(|o| (bent(o), 0.95 * o.radius)));
        flowers(&g, Vec3::new(0.42, 0.27, 0.15), size, &out, "pinecone.png")?;
    }
    // Figs. 9, 10 and 14: inflorescences placed by Algorithm 5.
    inflorescences::draw(want, quick, &out)?;
    // Figs. 4 and 5: limbs curved by Algorithms 1 and 2.
    limbs::draw(want, quick, &out)?;
    // Fig. 21: an ecosystem's plants as circles and as silhouette trees.
    ecosystem::draw(want, quick, &out)?;
    // Fig. 16: a Spiraea twig, its shoots upright by tropism.
    spiraea::draw(want, quick, &out)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_middle_tree_of_the_stand_keeps_only_its_upper_crown() {
        // Fig. 16: shaded from both sides, the middle tree sheds its lower
        // branches: its lowest living leaf cluster stands well above its
        // neighbours', and it still has a crown.
        let p = stand_params(10);
        let run = crowns::crowns(&p).unwrap();
        let clusters = leaf_clusters(&run, p.leaf_years, &trees(&run).0).unwrap();
        let low = lowest_clusters(&clusters, 3);
        assert!(low[1].is_finite(), "{low:?}");
        assert!(low[1] > low[0].max(low[2]) + 1.0, "{low:?}");
        let middle = clusters.iter().filter(|c| c.0 == 2).count();
        assert!(middle > 50, "{middle} clusters");
    }

    #[test]
    fn one_constant_sets_the_phyllotaxis() {
        // Fig. 8: the organs' directions round the stem (azimuths of their
        // headings, degrees) in node order.
        let azimuths = |p: &compound::CompoundParams| -> Vec<f64> {
            let g = compound::compound(p).unwrap().geometry().unwrap();
            g.surfaces
                .iter()
                .map(|s| s.frame.h.y.atan2(s.frame.h.x).to_degrees())
                .collect()
        };
        let near = |a: f64, b: f64, period: f64| {
            let r = (a - b).rem_euclid(period);
            r.min(period - r) < 1e-6
        };
        let shoots = phyllotaxes().unwrap();
        // Distichous: every organ in one plane, on either side.
        let a = azimuths(&shoots[0]);
        assert!(a.len() > 30 && a.iter().all(|&x| near(x, a[0], 180.0)));
        // Decussate: pairs turned 90° from node to node.
        let a = azimuths(&shoots[1]);
        assert!(a.iter().all(|&x| near(x, a[0], 90.0)));
        assert!(near(a[2], a[0] + 90.0, 180.0) && near(a[1], a[0] + 180.0, 360.0));
        // Spiral: one organ a node, each 137.5° round from the last.
        let a = azimuths(&shoots[2]);
        for w in a.windows(2) {
            let d = (w[1] - w[0]).rem_euclid(360.0);
            assert!((d - 137.5).abs() < 1e-6 || (d - 222.5).abs() < 1e-6, "{d}");
        }
    }

    #[test]
    fn the_two_lilacs_differ_in_habit() {
        // Fig. 18: S. reticulata's panicle is broader for its height and
        // denser in flowers than S. chinensis'.
        let shape = |g: &Geometry| {
            let (lo, hi) = g.bounds().unwrap();
            (
                (hi.x - lo.x).max(hi.y - lo.y) / (hi.z - lo.z),
                g.surfaces.len(),
            )
        };
        let (a, fa) = shape(&lilac().unwrap());
        let (b, fb) = shape(&reticulata().unwrap());
        assert!(b > 1.15 * a, "width/height {a} against {b}");
        assert!(fb > fa, "flowers {fa} against {fb}");
    }

    #[test]
    fn the_lilac_narrows_to_its_tip() {
        // Fig. 18: branch mapping makes each branch the distal part of the
        // longest of its order, so the branches shorten up the main axis
        // and the panicle is a cone: its lower third spreads half as wide
        // again as its upper third (the branches rise at 50°, so the lower
        // ones reach into the upper third), and every axis ends in a flower.
        let g = lilac().unwrap();
        let (lo, hi) = g.bounds().unwrap();
        let third = (hi.z - lo.z) / 3.0;
        let spread = |z0: f32, z1: f32| {
            g.end
                .iter()
                .filter(|e| e.z >= z0 && e.z < z1)
                .map(|e| e.truncate().length())
                .fold(0.0f32, f32::max)
        };
        let (low, high) = (spread(lo.z, lo.z + third), spread(hi.z - third, hi.z + 1.0));
        assert!(low > 1.5 * high, "{low} {high}");
        assert!(g.surfaces.len() > g.segment_count());
    }

    /// The first segments of the branches leaving the main axis (the
    /// vertical through the origin): `(height, azimuth in degrees)`, lowest
    /// first.
    fn first_order(g: &Geometry) -> Vec<(f32, f32)> {
        let on_axis = |p: Vec3| p.truncate().length() < 1e-4;
        let mut v: Vec<(f32, f32)> = g
            .start
            .iter()
            .zip(&g.end)
            .filter(|(a, b)| on_axis(**a) && !on_axis(**b))
            .map(|(a, b)| (a.z, (b.y - a.y).atan2(b.x - a.x).to_degrees()))
            .collect();
        v.sort_by(|p, q| p.0.total_cmp(&q.0));
        v
    }

    #[test]
    fn the_astilbe_branches_in_a_spiral() {
        // Fig. 19: one branch a node, each 137.5° round from the one below.
        let g = mapped(&astilbe().unwrap(), 0.035, 0.22).unwrap();
        let b = first_order(&g);
        assert!(b.len() > 15, "{}", b.len());
        for w in b.windows(2) {
            assert!(w[1].0 > w[0].0, "one branch a node");
            let d = (w[1].1 - w[0].1).rem_euclid(360.0);
            assert!((d - 137.5).abs() < 1e-3 || (d - 222.5).abs() < 1e-3, "{d}");
        }
    }

    #[test]
    fn the_silhouette_sets_the_crown() {
        // Fig. 20: the children's lengths follow the silhouette, which is
        // 0 up to a quarter of the trunk: no branch leaves the trunk below
        // a quarter of its length plus an internode (a node's branches sit
        // at the internode's top), and above it the branches come in
        // decussate pairs.
        let g = mapped(&silhouette_tree().unwrap(), 0.1, 0.25).unwrap();
        let b = first_order(&g);
        assert!(b.len() > 20, "{}", b.len());
        assert!(
            b.iter().all(|x| x.0 >= 0.25 * 12.0 + 0.4 - 1e-3),
            "{:?}",
            b[0]
        );
        for pair in b.chunks(2) {
            assert_eq!(pair[0].0, pair[1].0);
            let d = (pair[1].1 - pair[0].1).rem_euclid(360.0);
            assert!((d - 180.0).abs() < 1e-3, "{d}");
        }
        // The widest crown is where the silhouette peaks (near 0.45 of the
        // trunk): no segment reaches farther out than the longest branch of
        // 6 at 60° and its short children.
        let reach = g
            .end
            .iter()
            .map(|e| e.truncate().length())
            .fold(0.0f32, f32::max);
        assert!(reach > 4.0 && reach < 6.0 * 0.87 + 1.3, "{reach}");
    }

    #[test]
    fn the_cone_holds_as_many_scales_as_its_area_allows() {
        // Fig. 15 by Algorithm 5: the number of scales is the integral of
        // eq. 14, N = ∫ 2 f_x/ρ² ds over the receptacle (by the midpoint
        // rule on a much finer step), to within one; each scale 137.5°
        // round from the last.
        let (len, curve) = pine_cone_profile();
        let rho = pine_cone_scale(&curve);
        let scales = positional::ridley(len, 1e-4, &curve, &rho).unwrap();
        let n = 200_000;
        let h = len / f64::from(n);
        let integral: f64 = (0..n)
            .map(|k| {
                let s = (f64::from(k) + 0.5) * h;
                2.0 * curve(s).0 / (rho(s) * rho(s)) * h
            })
            .sum();
        assert!(
            (scales.len() as f64 - integral.floor()).abs() <= 1.0,
            "{} scales, N = {integral}",
            scales.len()
        );
        assert!(scales.len() > 100);
        for w in scales.windows(2) {
            assert!((w[1].angle_deg - w[0].angle_deg - 137.5).abs() < 1e-9);
        }
    }

    #[test]
    fn moving_the_second_crown_moves_only_it() {
        // Fig. 14's right panel: the same trees, the second `apart` metres
        // to the right; the first stays, and every leaf cluster is drawn in
        // both.
        let p = crowns::CrownParams {
            years: 3,
            trees_x: vec![-1.0, 1.0],
            ..crowns::CrownParams::default()
        };
        let run = crowns::crowns(&p).unwrap();
        let (a, _) = crown_geometry(&run, p.leaf_years, 0.0).unwrap();
        let (b, _) = crown_geometry(&run, p.leaf_years, 2.5).unwrap();
        assert!(!a.surfaces.is_empty());
        assert_eq!(a.surfaces.len(), b.surfaces.len());
        assert_eq!(a.segment_count(), b.segment_count());
        let (lo_a, hi_a) = a.bounds().unwrap();
        let (lo_b, hi_b) = b.bounds().unwrap();
        assert!((lo_a.x - lo_b.x).abs() < 1e-4, "{lo_a} {lo_b}");
        assert!((hi_b.x - hi_a.x - 2.5).abs() < 1e-3, "{hi_a} {hi_b}");
        // Half the segments (the first tree's) did not move.
        let same = a
            .start
            .iter()
            .zip(&b.start)
            .filter(|(u, v)| (**u - **v).length() < 1e-5)
            .count();
        assert!(same > 0 && same < a.segment_count(), "{same}");
    }
}
