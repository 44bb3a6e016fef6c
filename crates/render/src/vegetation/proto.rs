//! Prototype meshes of the forest: the ecosystem's prototypes meshed by
//! natura-plant's turtle mesher (full detail), and for far trees a
//! low-polygon crown: a closed hull of rings around the leaves on a
//! three-sided trunk.
//!
//! Both are shaded smooth. A leaf's shading normal leans from its own
//! normal toward the normal of the ellipsoid around the crown, so a crown
//! of thousands of small leaves shades as one rounded body lit on its sunny
//! side rather than as a noise of facets (the "crown normals" of real-time
//! foliage rendering; the weight is natura's own); bark keeps the mesher's
//! smooth stem normals, and the hull's corners average the normals of the
//! faces that meet there.

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

/// Weight of the crown's ellipsoid normal in a leaf's shading normal.
pub const CROWN_NORMAL_WEIGHT: f32 = 0.7;

/// The full mesh of turtle geometry: its triangles, which are leaf, and
/// smooth shading normals (see the module docs).
///
/// # Errors
///
/// The mesher's errors for inconsistent geometry.
pub fn full_mesh(g: &Geometry) -> Result<Mesh> {
    let m = PlantMesh::from_geometry(g, &params())?;
    let mut tris = Vec::with_capacity(m.triangle_count());
    let mut leaf = Vec::with_capacity(m.triangle_count());
    let mut shading = Vec::with_capacity(m.triangle_count());
    let crown = Ellipsoid::around(
        m.triangles(Material::Leaf)
            .flat_map(|t| t.map(|i| m.positions[i as usize])),
    );
    for mat in [Material::Bark, Material::Leaf] {
        for corners in m.triangles(mat) {
            let p = corners.map(|i| m.positions[i as usize]);
            let n = corners.map(|i| m.normals[i as usize]);
            tris.push(p);
            leaf.push(mat == Material::Leaf);
            shading.push(match (&crown, mat) {
                (Some(e), Material::Leaf) => [0, 1, 2].map(|k| e.lean(p[k], n[k])),
                _ => n,
            });
        }
    }
    Ok(Mesh::with_shading(tris, leaf, shading))
}

/// Triangles of turtle geometry and whether each is leaf.
///
/// # Errors
///
/// The mesher's errors for inconsistent geometry.
pub fn triangles(g: &Geometry) -> Result<(Vec<[Vec3; 3]>, Vec<bool>)> {
    let m = full_mesh(g)?;
    Ok((m.tris, m.leaf))
}

/// The axis-aligned ellipsoid around a crown's leaves, centred on the
/// stem's axis.
struct Ellipsoid {
    centre_z: f32,
    /// Inverse squared semi-axes, horizontal and vertical.
    inv2: (f32, f32),
}

impl Ellipsoid {
    /// The ellipsoid spanning the points' heights and their farthest
    /// horizontal reach; `None` without points.
    fn around(points: impl Iterator<Item = Vec3>) -> Option<Self> {
        let (mut z0, mut z1, mut r) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
        for p in points {
            (z0, z1, r) = (z0.min(p.z), z1.max(p.z), r.max(p.truncate().length()));
        }
        if !z0.is_finite() {
            return None;
        }
        let (a, c) = (r.max(1e-3), (0.5 * (z1 - z0)).max(1e-3));
        Some(Self {
            centre_z: 0.5 * (z0 + z1),
            inv2: (1.0 / (a * a), 1.0 / (c * c)),
        })
    }

    /// The leaf normal `n` at `p` leant toward the ellipsoid's outward
    /// normal there (turned first to the ellipsoid's side).
    fn lean(&self, p: Vec3, n: Vec3) -> Vec3 {
        let q = Vec3::new(
            p.x * self.inv2.0,
            p.y * self.inv2.0,
            (p.z - self.centre_z) * self.inv2.1,
        );
        let Some(out) = q.try_normalize() else {
            return n;
        };
        let n = if n.dot(out) < 0.0 { -n } else { n };
        (n * (1.0 - CROWN_NORMAL_WEIGHT) + out * CROWN_NORMAL_WEIGHT)
            .try_normalize()
            .unwrap_or(out)
    }
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
    let shading = smooth_normals(&tris, &leaf);
    Mesh::with_shading(tris, leaf, shading)
}

/// Corner normals of `tris` averaged over the triangles of the same kind
/// (`leaf`) that share the corner's position, weighted by area; bark and
/// leaf corners are not mixed.
fn smooth_normals(tris: &[[Vec3; 3]], leaf: &[bool]) -> Vec<[Vec3; 3]> {
    use std::collections::BTreeMap;
    // Positions a rounding apart (the ring's last corner is its first, by
    // another angle) are one corner.
    let q = |v: f32| (v * 1e4).round() as i64;
    let key = |p: Vec3, l: bool| (q(p.x), q(p.y), q(p.z), l);
    let mut sum: BTreeMap<(i64, i64, i64, bool), Vec3> = BTreeMap::new();
    for (t, &l) in tris.iter().zip(leaf) {
        // Twice the area times the unit normal.
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        for &p in t {
            *sum.entry(key(p, l)).or_insert(Vec3::ZERO) += n;
        }
    }
    tris.iter()
        .zip(leaf)
        .map(|(t, &l)| t.map(|p| sum[&key(p, l)]))
        .collect()
}
