//! The source papers' plant models as pictures: Honda's branch tiers, a
//! clonal plant foraging over patches of light, roots in soil water and
//! tree crowns competing for light (open L-systems, Měch & Prusinkiewicz
//! 1996), collision-based phyllotaxis on a cone (Fowler et al. 1992) and
//! Ridley's packing on a disc and a pinnate leaf on a curved stem
//! (Prusinkiewicz et al. 2001, Alg. 5 and 4).
//!
//! ```text
//! cargo run --release --example plant_models                 # all, docs/gallery/plant
//! cargo run --release --example plant_models -- --model crowns --quick --out /tmp/m
//! ```

mod common;

use natura::core::glam::{DVec3, Vec3};
use natura::plant::models::Run;
use natura::plant::models::{
    clonal, compound, crowns, phyllotaxis, positional, roots, roots3d, tiers,
};
use natura::plant::preview::{PreviewCamera, PreviewParams, render};
use natura::plant::turtle::{SurfaceInstance, TurtleFrame};
use natura::plant::{Geometry, MeshParams, PlantMesh};

/// Renders `g` seen along `view` into `name` under `out`.
fn picture(g: &Geometry, view: Vec3, size: u32, out: &std::path::Path, name: &str) {
    let mesh = common::check(PlantMesh::from_geometry(g, &MeshParams::default()));
    let (lo, hi) = mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
    let cam = common::check(PreviewCamera::framing(lo, hi, view, None, 1.0));
    let img = common::check(render(&mesh, &PreviewParams::new(size, size, cam)));
    common::check(img.save_png(out.join(name)));
    println!("{name}: {} triangles", mesh.triangle_count());
}

/// Renders the final string of a model's run.
fn show(run: &Run, view: Vec3, size: u32, out: &std::path::Path, name: &str) {
    picture(&common::check(run.geometry()), view, size, out, name);
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

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let model: Option<String> = args.optional(
        "--model",
        "one of tiers, clonal, roots, roots3d, crowns, phyllotaxis, ridley, compound (default all)",
    );
    let out = args.out_dir("docs/gallery/plant");
    args.finish();
    const MODELS: [&str; 8] = [
        "tiers",
        "clonal",
        "roots",
        "roots3d",
        "crowns",
        "phyllotaxis",
        "ridley",
        "compound",
    ];
    if let Some(m) = model.as_deref().filter(|m| !MODELS.contains(m)) {
        common::fail(&format!("--model {m}: not one of {}", MODELS.join(", ")));
    }
    let want = |n: &str| model.as_deref().is_none_or(|m| m == n);
    let size = if quick { 192 } else { 400 };
    if want("tiers") {
        // Fig. 5: two tiers competing for space, seen from above.
        let (run, _) = common::check(tiers::tiers(&tiers::TiersParams::default()));
        show(&run, Vec3::NEG_Z, size, &out, "tiers.png");
    }
    if want("clonal") {
        // Fig. 7: the clone spreading over patches II, III and I, seen from
        // above, with random spacers and trifoliate leaves.
        let p = clonal::ClonalParams {
            steps: if quick { 60 } else { 182 },
            ..clonal::ClonalParams::fig7()
        };
        let (run, _) = common::check(clonal::clonal(&p));
        show(&run, Vec3::NEG_Z, size, &out, "clonal.png");
    }
    if want("roots") {
        // Fig. 9: roots in a vertical section of soil, wet on the left, dry on the right.
        let p = roots::RootParams {
            steps: if quick { 60 } else { 186 },
            ..roots::RootParams::default()
        };
        let (run, _) = common::check(roots::roots(&p));
        show(&run, Vec3::Y, size, &out, "roots.png");
    }
    if want("roots3d") {
        // Fig. 10: the same roots in a block of soil, seen obliquely.
        let mut p = roots3d::Roots3dParams::default();
        p.roots.steps = if quick { 60 } else { 301 };
        let (run, _) = common::check(roots3d::roots_3d(&p));
        show(&run, Vec3::new(0.5, 1.0, 0.3), size, &out, "roots3d.png");
    }
    if want("crowns") {
        // Fig. 14: two trees grown side by side, seen from the side.
        let p = crowns::CrownParams {
            years: if quick { 4 } else { 8 },
            trees_x: vec![-1.0, 1.0],
            ..crowns::CrownParams::default()
        };
        let run = common::check(crowns::crowns(&p));
        show(&run, Vec3::Y, size, &out, "crowns.png");
    }
    if want("phyllotaxis") {
        // Fig. 4: primordia on a cone, shrinking towards the tip.
        let v = common::check(phyllotaxis::phyllotaxis(
            &phyllotaxis::PhyllotaxisParams::default(),
        ));
        let g = spheres(v.iter().map(|p| (p.centre, p.radius)));
        picture(&g, Vec3::new(0.3, 0.5, -1.0), size, &out, "phyllotaxis.png");
    }
    if want("ridley") {
        // Fig. 13 (flat case): Vogel's pattern from Algorithm 5.
        let v = common::check(positional::ridley(1.0, 1e-5, |s| (s, 0.0), |_| 0.04));
        let g = spheres(v.iter().map(|o| {
            let a = o.angle_deg.to_radians();
            (
                DVec3::new(o.x * a.cos(), o.x * a.sin(), o.y),
                o.radius * 0.9,
            )
        }));
        picture(&g, Vec3::NEG_Z, size, &out, "ridley.png");
    }
    if want("compound") {
        // Fig. 7 (f): a pinnate leaf on an arching stem, seen from the side.
        let run = common::check(compound::compound(&compound::CompoundParams::fern()));
        show(&run, Vec3::NEG_X, size, &out, "compound.png");
    }
}
