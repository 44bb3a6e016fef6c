//! Fractal triangle meshes: FFC polygon subdivision of arbitrary triangle
//! meshes (Fournier et al. 1982, §4.1.2), for terrain that is not a regular grid (a base mesh
//! of measured points, a planet's facets).
//!
//! Each triangle splits into four through its edge midpoints; each midpoint is
//! the edge's centre displaced by a Gaussian of deviation `scale·2^(−hℓ)` along
//! the **averaged vertex normal** of the edge's endpoints — Fournier et al.'s fix for the
//! gaps that per-polygon normals open between non-coplanar neighbours
//! (Fig. 14, Fournier et al. 1982, §4.1.2). New vertices carry the normalised mean of their
//! endpoints' normals, so normals never depend on which polygons are present.
//! Random numbers are keyed by invariant vertex identifiers (a midpoint's id
//! is a hash of its endpoints' ids), so two meshes that share an edge produce
//! bit-identical points on it even when subdivided independently, and
//! original vertices never move.

use std::collections::HashMap;

use glam::DVec3;
use natura_core::Seed;

use crate::error::{Result, TerrainError, invalid};
use crate::synth::subdivision::MidpointParams;

/// The deepest mesh subdivision accepted (each level multiplies faces by 4).
pub const MAX_MESH_LEVELS: u32 = 12;

/// A triangle mesh with invariant vertex identifiers and vertex normals.
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// Vertex positions, metres (z up).
    pub positions: Vec<DVec3>,
    /// Unit vertex normals (displacement directions).
    pub normals: Vec<DVec3>,
    /// Invariant vertex identifiers used to key random numbers.
    pub ids: Vec<u64>,
    /// Triangles as counter-clockwise vertex index triples.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// A mesh with vertex `i` identified by `i` and normals averaged over the
    /// incident triangles (area weighted).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`] for a non-finite vertex or an
    /// index past the vertices.
    pub fn new(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        let ids = (0..positions.len() as u64).collect();
        Self::with_ids(positions, ids, triangles)
    }

    /// A mesh with caller-chosen vertex identifiers (shared vertices of separate
    /// meshes must carry the same id) and face-averaged normals.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`] if there is not one id per
    /// vertex, and [`TerrainError::InvalidParameter`] for a non-finite vertex
    /// or an index past the vertices.
    pub fn with_ids(
        positions: Vec<DVec3>,
        ids: Vec<u64>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self> {
        let mut normals = vec![DVec3::ZERO; positions.len()];
        validate_topology(&positions, &ids, &triangles)?;
        for t in &triangles {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += n;
            }
        }
        let normals = normals
            .into_iter()
            .map(|n| n.normalize_or(DVec3::Z))
            .collect();
        Ok(Self {
            positions,
            normals,
            ids,
            triangles,
        })
    }

    /// A mesh with explicit normals (e.g. shared between tiles so that
    /// independently subdivided tiles agree on shared edges).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`] if there is not one id and one
    /// normal per vertex, and [`TerrainError::InvalidParameter`] for a
    /// non-finite vertex or an index past the vertices.
    pub fn with_normals(
        positions: Vec<DVec3>,
        normals: Vec<DVec3>,
        ids: Vec<u64>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self> {
        validate_topology(&positions, &ids, &triangles)?;
        if normals.len() != positions.len() {
            return Err(TerrainError::SizeMismatch {
                what: "normals",
                expected: positions.len().to_string(),
                actual: normals.len().to_string(),
            });
        }
        let normals = normals
            .into_iter()
            .map(|n| n.normalize_or(DVec3::Z))
            .collect();
        Ok(Self {
            positions,
            normals,
            ids,
            triangles,
        })
    }

    /// Length of the longest edge.
    #[must_use]
    pub fn max_edge(&self) -> f64 {
        self.triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| self.positions[a as usize].distance(self.positions[b as usize]))
            .fold(0.0, f64::max)
    }
}

fn validate_topology(positions: &[DVec3], ids: &[u64], triangles: &[[u32; 3]]) -> Result<()> {
    if ids.len() != positions.len() {
        return Err(TerrainError::SizeMismatch {
            what: "vertex ids",
            expected: positions.len().to_string(),
            actual: ids.len().to_string(),
        });
    }
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(invalid(
            "positions",
            format!("vertex {i} = {}", positions[i]),
            "must be finite",
        ));
    }
    if let Some(t) = triangles
        .iter()
        .position(|t| t.iter().any(|&i| i as usize >= positions.len()))
    {
        return Err(invalid(
            "triangles",
            format!("triangle {t} = {:?}", triangles[t]),
            "refers to a vertex that does not exist",
        ));
    }
    Ok(())
}

/// Subdivides `mesh` `levels` times (FFC fractal triangles): `4^levels` times as many
/// triangles; for a single triangle `(2^L + 1)(2^L + 2)/2` vertices.
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`] for a non-finite vertex, an index
/// past the vertices or a non-positive edge length.
pub fn subdivide_mesh(
    mesh: &TriMesh,
    p: &MidpointParams,
    levels: u32,
    seed: Seed,
) -> Result<TriMesh> {
    p.validate()?;
    if levels > MAX_MESH_LEVELS {
        return Err(invalid(
            "levels",
            levels,
            format!("must be at most {MAX_MESH_LEVELS}"),
        ));
    }
    let std = p.level_std(levels);
    let seed = seed.derive("ffc-mesh");
    let mut m = mesh.clone();
    for l in 1..=levels {
        m = split_once(&m, std[l as usize], seed);
    }
    Ok(m)
}

/// Subdivides until no edge is longer than `max_edge` metres (Fournier et al. 1982, §4.1.2).
/// Fails if that would take more than [`MAX_MESH_LEVELS`] levels.
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`] for a non-finite vertex, an index
/// past the vertices or a non-positive edge length.
pub fn subdivide_mesh_until(
    mesh: &TriMesh,
    p: &MidpointParams,
    max_edge: f64,
    seed: Seed,
) -> Result<TriMesh> {
    p.validate()?;
    if !(max_edge.is_finite() && max_edge > 0.0) {
        return Err(invalid("max_edge", max_edge, "must be finite and > 0"));
    }
    let std = p.level_std(MAX_MESH_LEVELS);
    let seed = seed.derive("ffc-mesh");
    let mut m = mesh.clone();
    let mut l = 0;
    while m.max_edge() > max_edge {
        if l == MAX_MESH_LEVELS {
            return Err(invalid(
                "max_edge",
                max_edge,
                format!("needs more than {MAX_MESH_LEVELS} levels"),
            ));
        }
        l += 1;
        m = split_once(&m, std[l as usize], seed);
    }
    Ok(m)
}

fn split_once(m: &TriMesh, sd: f64, seed: Seed) -> TriMesh {
    let mut out = TriMesh {
        positions: m.positions.clone(),
        normals: m.normals.clone(),
        ids: m.ids.clone(),
        triangles: Vec::with_capacity(m.triangles.len() * 4),
    };
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |a: u32, b: u32, out: &mut TriMesh| -> u32 {
        let (lo, hi) = if m.ids[a as usize] <= m.ids[b as usize] {
            (a, b)
        } else {
            (b, a)
        };
        *edges.entry((lo, hi)).or_insert_with(|| {
            let (ia, ib) = (m.ids[lo as usize], m.ids[hi as usize]);
            let id = seed.hash(&[ia as i64, ib as i64]);
            let n = (m.normals[lo as usize] + m.normals[hi as usize]).normalize_or_zero();
            let g = Seed(id ^ seed.0).gaussian(&[1]);
            let p = (m.positions[lo as usize] + m.positions[hi as usize]) * 0.5 + n * (g * sd);
            out.positions.push(p);
            out.normals.push(if n == DVec3::ZERO {
                m.normals[lo as usize]
            } else {
                n
            });
            out.ids.push(id);
            (out.positions.len() - 1) as u32
        })
    };
    for &[a, b, c] in &m.triangles {
        let ab = midpoint(a, b, &mut out);
        let bc = midpoint(b, c, &mut out);
        let ca = midpoint(c, a, &mut out);
        out.triangles
            .extend_from_slice(&[[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_fixed_vertices() {
        let tri = TriMesh::new(
            vec![DVec3::ZERO, DVec3::X * 100.0, DVec3::Y * 100.0],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let p = MidpointParams {
            scale: 10.0,
            ..Default::default()
        };
        for l in 0..5u32 {
            let s = subdivide_mesh(&tri, &p, l, Seed(1)).unwrap();
            assert_eq!(s.triangles.len(), 4usize.pow(l));
            let n = (1usize << l) + 1;
            assert_eq!(s.positions.len(), n * (n + 1) / 2);
            assert_eq!(&s.positions[..3], &tri.positions[..]);
        }
        let s = subdivide_mesh_until(
            &tri,
            &MidpointParams {
                scale: 0.0,
                ..Default::default()
            },
            10.0,
            Seed(1),
        )
        .unwrap();
        assert!(s.max_edge() <= 10.0);
    }

    #[test]
    fn shared_edge_is_identical_when_subdivided_separately() {
        // Two non-coplanar triangles sharing the edge (ids 10, 11); shared normals given.
        let (a, b) = (DVec3::ZERO, DVec3::X * 100.0);
        let n = vec![DVec3::Z; 3];
        let t1 = TriMesh::with_normals(
            vec![a, b, DVec3::new(50.0, 80.0, 30.0)],
            n.clone(),
            vec![10, 11, 12],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let t2 = TriMesh::with_normals(
            vec![b, a, DVec3::new(50.0, -80.0, -20.0)],
            n,
            vec![11, 10, 13],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let p = MidpointParams {
            scale: 10.0,
            ..Default::default()
        };
        let s1 = subdivide_mesh(&t1, &p, 4, Seed(3)).unwrap();
        let s2 = subdivide_mesh(&t2, &p, 4, Seed(3)).unwrap();
        let on_edge = |m: &TriMesh| {
            let mut v: Vec<(u64, [u64; 3])> = m
                .positions
                .iter()
                .zip(&m.ids)
                .filter(|(q, _)| q.y.abs() < 1e-9 && q.z.abs() >= 0.0)
                .map(|(q, &id)| (id, q.to_array().map(f64::to_bits)))
                .collect();
            v.sort();
            v
        };
        let (e1, e2) = (on_edge(&s1), on_edge(&s2));
        // Every vertex keyed from the shared edge appears in both with equal bits.
        let ids1: std::collections::HashMap<u64, [u64; 3]> = s1
            .ids
            .iter()
            .copied()
            .zip(s1.positions.iter().map(|q| q.to_array().map(f64::to_bits)))
            .collect();
        let ids2: std::collections::HashMap<u64, [u64; 3]> = s2
            .ids
            .iter()
            .copied()
            .zip(s2.positions.iter().map(|q| q.to_array().map(f64::to_bits)))
            .collect();
        let shared: Vec<_> = ids1.keys().filter(|k| ids2.contains_key(k)).collect();
        assert_eq!(shared.len(), 17, "2^4 + 1 points on the shared edge");
        for k in shared {
            assert_eq!(ids1[k], ids2[k]);
        }
        let _ = (e1, e2);
    }
}
