//! Fig. 21 of Prusinkiewicz et al. 2001: an ecosystem simulation shown
//! directly, each plant a circle, and realistically, each plant a tree
//! whose silhouette matches the shape the ecosystem gives it. The
//! ecosystem is natura-plant's (Deussen et al. 1998's individual-based
//! simulation, `eco::Ecosystem`) of its tree species on flat ground; the
//! tree is the branch-mapped tree of Fig. 20, its crown's outline set by a
//! silhouette function (Algorithm 6), scaled so that its crown's radius is
//! the plant's circle and its height in proportion.

use natura::core::glam::{DVec3, Vec3};
use natura::core::{HeightField, Image, NoProgress};
use natura::plant::eco::{EcoParams, Ecosystem, Species, top_view};
use natura::plant::{Material, MeshParams, PlantMesh};

use crate::common::{Exit, outln};
use crate::mesh::{Mesh, View, render};
use crate::positional_info::{mapped, silhouette_tree};

/// The stand's side (m) and the ecosystem's steps.
const SIDE_M: f64 = 60.0;
const STEPS: u32 = 30;
/// The half-width of the silhouette tree's crown, in its own units (its
/// longest branch, 6).
const CROWN_HALF_WIDTH: f64 = 6.0;

/// The ecosystem of the figure: its tree species alone on flat ground
/// `SIDE_M` square, run `STEPS` steps.
///
/// # Errors
///
/// The ecosystem's errors (none for these values).
pub fn stand() -> Result<Ecosystem, Exit> {
    let n = 31;
    let cell = SIDE_M as f32 / (n - 1) as f32;
    let hf = HeightField::from_fn(n, n, cell, |_, _| 0.0)?;
    let mut eco = Ecosystem::new(
        &hf,
        EcoParams {
            species: vec![Species::tree()],
            steps: STEPS,
            ..EcoParams::default()
        },
    )?;
    eco.run(&NoProgress)?;
    Ok(eco)
}

/// Fig. 21: the stand from above, each plant its circle (top), and the same
/// stand seen obliquely, each plant the silhouette tree scaled to its
/// circle (bottom), both `width` pixels wide. Returns the picture and the
/// trees drawn.
///
/// # Errors
///
/// The ecosystem's, the tree's and the renderer's errors.
pub fn silhouettes(width: u32) -> Result<(Image, usize), Exit> {
    let eco = stand()?;
    let top = top_view(&eco, width as usize)?;
    let tree = PlantMesh::from_geometry(
        &mapped(&silhouette_tree()?, 0.1, 0.25)?,
        &MeshParams::default(),
    )?;
    let (lo, hi) = tree.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
    let foot = DVec3::new(
        f64::from(0.5 * (lo.x + hi.x)),
        f64::from(0.5 * (lo.y + hi.y)),
        f64::from(lo.z),
    );
    let mut m = Mesh::default();
    // The ground, a pale meadow.
    m.patch(
        1,
        1,
        |u, v| DVec3::new(u * SIDE_M, v * SIDE_M, 0.0),
        |_, _| Vec3::new(0.42, 0.44, 0.2),
    );
    let tri: Vec<[u32; 3]> = tree
        .indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let mut leaf = vec![false; tree.positions.len()];
    for p in tree
        .primitives
        .iter()
        .filter(|p| p.material == Material::Leaf)
    {
        for &k in &tree.indices[p.first as usize..(p.first + p.count) as usize] {
            leaf[k as usize] = true;
        }
    }
    let plants = eco.plants();
    for (i, p) in plants.iter().enumerate() {
        let s = f64::from(p.radius) / CROWN_HALF_WIDTH;
        let turn = i as f64 * 2.39996;
        let (sn, cs) = turn.sin_cos();
        let place = |q: Vec3| {
            let d = (q.as_dvec3() - foot) * s;
            DVec3::new(
                d.x * cs - d.y * sn + f64::from(p.x),
                d.x * sn + d.y * cs + f64::from(p.y),
                d.z,
            )
        };
        let pos: Vec<DVec3> = tree.positions.iter().map(|&q| place(q)).collect();
        let nrm: Vec<DVec3> = tree
            .normals
            .iter()
            .map(|n| {
                let n = n.as_dvec3();
                DVec3::new(n.x * cs - n.y * sn, n.x * sn + n.y * cs, n.z)
            })
            .collect();
        let green = Vec3::new(0.05, 0.2, 0.03) * (0.8 + 0.4 * ((i as f32 * 0.618).fract()));
        let col: Vec<Vec3> = leaf
            .iter()
            .map(|&l| if l { green } else { Vec3::new(0.3, 0.2, 0.12) })
            .collect();
        m.add_triangles(&pos, &nrm, &col, &tri);
    }
    let view = View {
        background: Vec3::new(0.55, 0.65, 0.8),
        ..View::along(Vec3::new(0.35, 1.0, -0.35))
    }
    .zoomed(2.0);
    let side = render(&m, &view, width, width * 2 / 3)?;
    // The two panels, the top view above.
    let (tw, th) = (top.width(), top.height());
    let (sw, sh) = (side.width(), side.height());
    let img = Image::from_fn(tw.max(sw), th + 8 + sh, |x, y| {
        if y < th {
            top.get(x, y).unwrap_or(Vec3::ONE)
        } else if y < th + 8 {
            Vec3::ONE
        } else {
            side.get(x, y - th - 8).unwrap_or(Vec3::ONE)
        }
    })?;
    Ok((img, plants.len()))
}

/// Draws Fig. 21 into `out` as `silhouettes_stand.png` when `want` names
/// `stand-silhouettes`, small when `quick`.
///
/// # Errors
///
/// [`silhouettes`]' errors; natura-core's if the picture cannot be written.
pub fn draw(want: impl Fn(&str) -> bool, quick: bool, out: &std::path::Path) -> crate::common::Run {
    if want("stand-silhouettes") {
        let (img, n) = silhouettes(if quick { 240 } else { 700 })?;
        img.save_png(out.join("silhouettes_stand.png"))?;
        outln(format_args!("silhouettes_stand.png: {n} trees"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_trees_crown_is_as_wide_as_the_scale_assumes() {
        // Each plant's tree is scaled by its radius over CROWN_HALF_WIDTH:
        // the silhouette tree's crown must be that wide across its trunk,
        // or the realistic stand would not match the circles.
        let tree = PlantMesh::from_geometry(
            &mapped(&silhouette_tree().unwrap(), 0.1, 0.25).unwrap(),
            &MeshParams::default(),
        )
        .unwrap();
        let (lo, hi) = tree.bounds().unwrap();
        let half = 0.5 * f64::from((hi.x - lo.x).max(hi.y - lo.y));
        assert!(
            (half / CROWN_HALF_WIDTH - 1.0).abs() < 0.15,
            "half-width {half}"
        );
        // And the stand has trees of several sizes.
        let eco = stand().unwrap();
        let r: Vec<f32> = eco.plants().iter().map(|p| p.radius).collect();
        let (lo, hi) = r
            .iter()
            .fold((f32::MAX, 0.0f32), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(r.len() > 10 && hi > 3.0 * lo, "{r:?}");
    }
}
