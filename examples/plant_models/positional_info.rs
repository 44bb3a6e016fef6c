//! The figures of Prusinkiewicz et al. 2001 that `plant_models` draws:
//! the phyllotaxes of Algorithm 4 (Fig. 8), the pine cone of Algorithm 5
//! (Fig. 15) and the lilac, astilbe and silhouette tree of Algorithm 6
//! (Figs. 18–20).

use natura::core::glam::{DVec3, Vec3};
use natura::plant::models::Run as ModelRun;
use natura::plant::models::{compound, positional};
use natura::plant::preview::{PreviewCamera, PreviewParams, render};
use natura::plant::{Derivation, Geometry, LSystem, MeshParams, PlantMesh, TurtleParams};

use crate::common;
use crate::common::outln;

/// The generating curve of Fig. 15's cone, `(f_x, f_y)` by arc length, and
/// its length: an ovoid 4 long, 1.2 across at its widest, a third of the
/// way up, closed at both ends (our profile), parametrised by arc length
/// from a table of 4 096 chords.
pub fn pine_cone_profile() -> (f64, impl Fn(f64) -> (f64, f64)) {
    let shape = |u: f64| {
        let x = 1.2
            * (std::f64::consts::PI * u.powf(0.8))
                .sin()
                .max(0.0)
                .powf(0.7);
        (x, 4.0 * u)
    };
    crate::inflorescences::by_arc_length(shape, 4096)
}

/// The scales' radius on Fig. 15's cone: a tenth of the receptacle's
/// radius where they sit, plus 0.04 (smallest at the ends).
pub fn pine_cone_scale(curve: &impl Fn(f64) -> (f64, f64)) -> impl Fn(f64) -> f64 + '_ {
    move |s| 0.04 + 0.1 * curve(s).0
}

/// A scale's centre on the cone, the axis bent to the side by `0.06·y²`
/// (the source's post-deformation of a straight cone).
pub fn bent(o: &positional::Organ) -> DVec3 {
    let a = o.angle_deg.to_radians();
    DVec3::new(o.x * a.cos(), o.x * a.sin() + 0.06 * o.y * o.y, o.y)
}

/// Draws `g` from the side, its flowers (or the cone's scales: its only
/// surfaces) in `colour`.
pub fn flowers(
    g: &Geometry,
    colour: Vec3,
    size: u32,
    out: &std::path::Path,
    name: &str,
) -> common::Run {
    let mesh = PlantMesh::from_geometry(g, &MeshParams::default())?;
    let (lo, hi) = mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
    let cam = PreviewCamera::framing(lo, hi, Vec3::new(1.0, 0.4, 0.0), None, 1.0)?;
    let params = PreviewParams {
        leaf: colour,
        ..PreviewParams::new(size, size, cam)
    };
    let mut img = render(&mesh, &params)?;
    if name == "silhouette.png" {
        img = beside_silhouette(&img)?;
    }
    img.save_png(out.join(name))?;
    outln(format_args!(
        "{name}: {} segments, {} flowers or scales",
        g.segment_count(),
        g.surfaces.len()
    ))
}

/// Fig. 20's silhouette specification to the left of the tree's picture
/// `tree`: the child's length as a fraction of the longest ([`SILHOUETTE`],
/// as natura-plant's `Function` interpolates it and the model clamps it to
/// `[0, 1]`) against the position up
/// the trunk, drawn to both sides of the trunk (green) on the picture's
/// background, the trunk from its foot to its top in the picture's
/// height (the framing's margins of 3 %).
fn beside_silhouette(tree: &natura::core::Image) -> Result<natura::core::Image, common::Exit> {
    use crate::common::plot::{Canvas, Panel, Pen};
    let (w, h) = (tree.width(), tree.height());
    let bg = tree.get(0, 0).unwrap_or(Vec3::ONE);
    let pw = w / 2;
    let mut c = Canvas::with_paper(pw, h, |_, _| bg);
    let (hf, wf) = (h as f32, pw as f32);
    let panel = Panel::new(
        [0.08 * wf, 0.03 * hf, 0.92 * wf, 0.97 * hf],
        [-1.1, 1.1, 0.0, 1.0],
    );
    let f = natura::plant::lang::Function::new(&SILHOUETTE)?;
    let side = |sign: f64| -> Vec<(f64, f64)> {
        (0..=200)
            .map(|k| {
                let t = f64::from(k) / 200.0;
                (sign * f.eval(t).clamp(0.0, 1.0), t)
            })
            .collect()
    };
    c.line(
        &panel,
        &[(0.0, 0.0), (0.0, 1.0)],
        Pen::solid(Vec3::new(0.35, 0.22, 0.12), 2.0),
    );
    c.line(
        &panel,
        &side(1.0),
        Pen::solid(Vec3::new(0.1, 0.4, 0.08), 2.0),
    );
    c.line(
        &panel,
        &side(-1.0),
        Pen::solid(Vec3::new(0.1, 0.4, 0.08), 2.0),
    );
    let plot = c.into_image()?;
    Ok(natura::core::Image::from_fn(pw + w, h, |x, y| {
        if x < pw {
            plot.get(x, y)
        } else {
            tree.get(x - pw, y)
        }
        .unwrap_or(bg)
    })?)
}

/// An L-system of Algorithm 6 derived to the end (64 steps) and drawn with
/// stems `width` across, its flowers `~K` (of unit size in the listing)
/// `flower` across.
pub fn mapped(l: &LSystem, width: f64, flower: f64) -> Result<Geometry, common::Exit> {
    let mut d = Derivation::new(l, 0)?;
    d.derive(64)?;
    let run = ModelRun {
        turtle: TurtleParams {
            width,
            ..TurtleParams::for_lsystem(l)
        },
        string: d.string().clone(),
        lsystem: l.clone(),
    };
    let mut g = run.geometry()?;
    for f in &mut g.surfaces {
        (f.length, f.width) = (flower, flower);
    }
    Ok(g)
}

/// Fig. 19's astilbe: a spiral plume, the main axis 6 long with branches of
/// at most 2.5, 0.8 and 0.3, internodes of 0.25, branches at 45°, children
/// shortening linearly up their mother (our values).
pub fn astilbe() -> Result<LSystem, common::Exit> {
    Ok(positional::BranchMapping {
        max_len: vec![6.0, 2.5, 0.8, 0.3],
        internode: 0.25,
        angle_deg: 45.0,
        silhouette: natura::plant::lang::Function::new(&[(0.0, 1.0), (1.0, 0.0)])?,
        spiral: true,
    }
    .lsystem()?)
}

/// Fig. 20's tree: a trunk 12 long with decussate branches of at most 6,
/// then 1 and 0.3, internodes of 0.4, at 60°, along the silhouette
/// [`SILHOUETTE`] (our values): bare to a quarter of the trunk, widest at
/// 0.45, closing at the top.
pub fn silhouette_tree() -> Result<LSystem, common::Exit> {
    Ok(positional::BranchMapping {
        max_len: vec![12.0, 6.0, 1.0, 0.3],
        internode: 0.4,
        angle_deg: 60.0,
        silhouette: natura::plant::lang::Function::new(&SILHOUETTE)?,
        spiral: false,
    }
    .lsystem()?)
}

/// The crown silhouette of Fig. 20's tree: a child's length as a fraction
/// of the longest, by its node's position up its mother.
pub const SILHOUETTE: [(f64, f64); 5] = [
    (0.0, 0.0),
    (0.25, 0.0),
    (0.45, 1.0),
    (0.75, 0.6),
    (1.0, 0.0),
];

/// The lilac panicle of Fig. 18: Algorithm 6 with [`LILAC_MAX_LEN`],
/// internodes of 0.5, branches at 50° and children as long as the rest of
/// their mother's order (`branch_len(o, rel) = max_len[o+1]·(1 − rel)`),
/// derived to the end; the listing's flowers `~K`, of unit size, drawn
/// 0.3 across (a few internodes).
pub fn lilac() -> Result<Geometry, common::Exit> {
    let text = positional::branch_mapping_text(&LILAC_MAX_LEN, 0.5, 50.0, 1.0)?;
    mapped(&LSystem::parse(&text)?, 0.1, 0.3)
}

/// Fig. 18 b, *Syringa reticulata*: a broader, denser panicle than
/// [`lilac`]'s (Algorithm 6 with [`RETICULATA_MAX_LEN`], internodes of
/// 0.35, branches at 62°), its many small flowers drawn 0.24 across (our
/// values, read off the species' habit: the source prints none).
pub fn reticulata() -> Result<Geometry, common::Exit> {
    let text = positional::branch_mapping_text(&RETICULATA_MAX_LEN, 0.35, 62.0, 1.0)?;
    mapped(&LSystem::parse(&text)?, 0.08, 0.24)
}

/// The longest axis of each order of Fig. 18 b's *S. reticulata* panicle.
pub const RETICULATA_MAX_LEN: [f64; 4] = [6.0, 4.0, 1.8, 0.6];

/// The longest axis of each order of the lilac panicle of Fig. 18 (the
/// main axis, its branches, theirs; the last entry is the order the
/// listing indexes past the deepest): our values.
pub const LILAC_MAX_LEN: [f64; 4] = [8.0, 4.0, 1.5, 0.5];

/// Fig. 8's three shoots from Algorithm 4 ([`compound::compound`]): a
/// stem of 10 with organs shrinking from 2.2 long at its base to 0.4 at
/// its tip at 55°, the nodes every 0.5; `Φ = 0` with a pair at each node
/// (distichous), `Φ = 90°` with a pair (decussate) and `Φ = 137.5°` with
/// one organ at each node every 0.25 (spiral).
pub fn phyllotaxes() -> Result<Vec<compound::CompoundParams>, common::Exit> {
    let f = |pts: &[(f64, f64)]| natura::plant::lang::Function::new(pts);
    let base = compound::CompoundParams {
        leaflet_length: f(&[(0.0, 2.2), (10.0, 0.4)])?,
        leaflet_width: f(&[(0.0, 0.7), (10.0, 0.2)])?,
        branch_angle: f(&[(0.0, 55.0)])?,
        stem_width: f(&[(0.0, 0.14), (10.0, 0.04)])?,
        ..compound::CompoundParams::default()
    };
    Ok(vec![
        compound::CompoundParams {
            phyllotaxis_deg: 0.0,
            ..base.clone()
        },
        compound::CompoundParams {
            phyllotaxis_deg: 90.0,
            ..base.clone()
        },
        compound::CompoundParams {
            phyllotaxis_deg: 137.5,
            pairs: false,
            internode: f(&[(0.0, 0.25)])?,
            ..base
        },
    ])
}
