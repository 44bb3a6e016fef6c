//! Prototype meshes of the forest: the ecosystem's prototypes meshed by
//! natura-plant's turtle mesher (full detail), and for far trees a
//! low-polygon crown: a closed hull of rings around the leaves on a
//! three-sided trunk.

use glam::Vec3;
use natura_plant::mesh::{Material, MeshParams, PlantMesh};
use natura_plant::turtle::Geometry;

use super::bvh::Mesh;
use crate::error::Result;

/// Mesh settings for trees seen from tens of metres away: four-sided
/// stems without caps, leaves of two rows (four triangles).
fn params() -> MeshParams {
    MeshParams {
        radial_segments: 4,
        caps: false,
        leaf_rows: 2,
        double_sided_leaves: false,
    }
}

/// Triangles of turtle geometry and whether each is leaf.
///
/// # Errors
///
/// The mesher's errors for inconsistent geometry.
pub fn triangles(g: &Geometry) -> Result<(Vec<[Vec3; 3]>, Vec<bool>)> {
    let m = PlantMesh::from_geometry(g, &params())?;
    let mut tris = Vec::with_capacity(m.triangle_count());
    let mut leaf = Vec::with_capacity(m.triangle_count());
    for mat in [Material::Bark, Material::Leaf] {
        for [a, b, c] in m.triangles(mat) {
            tris.push([
                m.positions[a as usize],
                m.positions[b as usize],
                m.positions[c as usize],
            ]);
            leaf.push(mat == Material::Leaf);
        }
    }
    Ok((tris, leaf))
}

/// Sectors around the crown hull.
const SECTORS: usize = 12;
/// Rings up the crown hull.
const RINGS: usize = 6;

/// A low-polygon stand-in for a full tree mesh: its leaves' vertices binned
/// by height band and azimuth sector, each ring vertex at `shrink` times the
/// farthest leaf of its bin (crowns are porous: the hull is drawn opaque, so
/// it is drawn a little smaller), closed at the crown's bottom and top, on
/// a three-sided trunk from the ground to the crown. Bark-only meshes get
/// the trunk alone.
#[must_use]
pub fn crown_hull(full: &Mesh, shrink: f32) -> Mesh {
    let leaves: Vec<Vec3> = full
        .tris
        .iter()
        .zip(&full.leaf)
        .filter(|(_, l)| **l)
        .flat_map(|(t, _)| t.iter().copied())
        .collect();
    let (lo, hi) = full.bounds;
    let mut tris = Vec::new();
    let mut leaf = Vec::new();
    let (z0, z1) = leaves
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), p| {
            (a.min(p.z), b.max(p.z))
        });
    let trunk_top = if leaves.is_empty() {
        hi.z
    } else {
        z0 + 0.3 * (z1 - z0)
    };
    // The trunk: a thin three-sided prism.
    let w = 0.012 * (hi.z - lo.z).max(1e-3);
    let base: Vec<Vec3> = (0..3)
        .map(|k| {
            let a = k as f32 * std::f32::consts::TAU / 3.0;
            Vec3::new(w * a.cos(), w * a.sin(), 0.0)
        })
        .collect();
    for k in 0..3 {
        let (a, b) = (base[k], base[(k + 1) % 3]);
        let up = Vec3::Z * trunk_top;
        tris.push([a, b, b + up]);
        tris.push([a, b + up, a + up]);
        leaf.extend([false, false]);
    }
    if leaves.is_empty() {
        return Mesh::new(tris, leaf);
    }
    // Farthest leaf per (ring, sector).
    let dz = ((z1 - z0) / RINGS as f32).max(1e-6);
    let mut r = [[0.0f32; SECTORS]; RINGS];
    for p in &leaves {
        let ring = (((p.z - z0) / dz) as usize).min(RINGS - 1);
        let a = p.y.atan2(p.x).rem_euclid(std::f32::consts::TAU);
        let s = ((a / std::f32::consts::TAU * SECTORS as f32) as usize).min(SECTORS - 1);
        r[ring][s] = r[ring][s].max(p.truncate().length());
    }
    // Fill empty bins from the ring's mean, so the hull stays closed and round.
    for ring in &mut r {
        let (sum, n) = ring
            .iter()
            .filter(|v| **v > 0.0)
            .fold((0.0, 0), |(s, n), v| (s + v, n + 1));
        let mean = if n > 0 { sum / n as f32 } else { 0.0 };
        for v in ring.iter_mut() {
            *v = shrink * if *v > 0.0 { 0.5 * (*v + mean) } else { mean };
        }
    }
    let vertex = |ring: usize, s: usize| {
        let a = (s as f32 + 0.5) * std::f32::consts::TAU / SECTORS as f32;
        let rr = r[ring][s % SECTORS];
        Vec3::new(rr * a.cos(), rr * a.sin(), z0 + (ring as f32 + 0.5) * dz)
    };
    let bottom = Vec3::new(0.0, 0.0, z0);
    let top = Vec3::new(0.0, 0.0, z1);
    for s in 0..SECTORS {
        tris.push([bottom, vertex(0, s + 1), vertex(0, s)]);
        tris.push([top, vertex(RINGS - 1, s), vertex(RINGS - 1, s + 1)]);
        leaf.extend([true, true]);
        for ring in 0..RINGS - 1 {
            let (a, b) = (vertex(ring, s), vertex(ring, s + 1));
            let (c, d) = (vertex(ring + 1, s + 1), vertex(ring + 1, s));
            tris.push([a, b, c]);
            tris.push([a, c, d]);
            leaf.extend([true, true]);
        }
    }
    Mesh::new(tris, leaf)
}
