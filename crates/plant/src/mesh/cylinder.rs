//! Chains of segments as generalized cylinders: shared rings at joints,
//! mitred and parallel-transported, capped at both ends.

use super::{MeshParams, PlantMesh};
use crate::turtle::Geometry;
use glam::{Vec2, Vec3};

/// The largest widening of a mitred joint ring (a joint that folds back on
/// itself would otherwise need an unbounded one).
const MAX_MITRE: f32 = 3.0;

/// Segments grouped into chains: `next[k]` continues `k` (or `u32::MAX`),
/// `starts` are the first segments of the chains, in increasing order.
#[derive(Debug)]
pub(super) struct Chains {
    next: Vec<u32>,
    starts: Vec<u32>,
}

impl Chains {
    /// Links each segment to the first later segment that continues it from
    /// its end point without folding back; any other segment starts a chain of its own.
    pub fn new(g: &Geometry) -> Self {
        let n = g.start.len();
        let mut next = vec![u32::MAX; n];
        let mut starts = Vec::new();
        for k in 0..n {
            let p = g.prev[k];
            let joined = p != u32::MAX && (p as usize) < k && next[p as usize] == u32::MAX && {
                let (a, b) = (g.end[p as usize], g.start[k]);
                let scale = a.abs().max(b.abs()).max_element().max(1.0);
                let (dp, dk) = (
                    g.end[p as usize] - g.start[p as usize],
                    g.end[k] - g.start[k],
                );
                // A turn sharper than about 154° (towards a reversal) starts a
                // new tube: no joint ring can join such segments smoothly.
                a.distance(b) <= 1e-5 * scale && dp.dot(dk) > -0.9 * dp.length() * dk.length()
            };
            if joined {
                next[p as usize] = k as u32;
            } else {
                starts.push(k as u32);
            }
        }
        Self { next, starts }
    }

    /// Number of chains.
    pub fn len(&self) -> usize {
        self.starts.len()
    }
}

/// Vertices and indices of the bark: `(n + c)(R + 1)` ring vertices and
/// `6 R n` indices for `n` segments in `c` chains, plus `2 c (R + 1)`
/// vertices and `6 c R` indices of caps.
pub(super) fn counts(chains: &Chains, p: &MeshParams) -> (usize, usize) {
    let r = p.radial_segments as usize;
    let (n, c) = (chains.next.len(), chains.len());
    let caps = usize::from(p.caps);
    (
        (n + c) * (r + 1) + caps * 2 * c * (r + 1),
        6 * r * n + caps * 6 * c * r,
    )
}

/// The rotation of `v` that takes unit `a` to unit `b` along the shortest
/// arc (parallel transport of a frame vector between two tangents).
#[inline]
fn transport(v: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let k = a.cross(b);
    let c = a.dot(b);
    if c <= -0.999_999 {
        // A reversal: any half-turn about an axis ⟂ a works; keep v (it lies in the plane).
        return v;
    }
    v + k.cross(v) + k.cross(k.cross(v)) / (1.0 + c)
}

/// Writes one ring of `R + 1` vertices (the last repeats the first's position, `u = 1`).
struct Ring<'a> {
    cs: &'a [(f32, f32)],
    positions: [Vec3; 65],
    normals: [Vec3; 65],
}

impl Ring<'_> {
    /// Places the ring at `centre` in the plane ⟂ `t`, starting at `refv`,
    /// radius `r`, mitred for a tube along unit `d`.
    #[inline]
    fn place(&mut self, centre: Vec3, t: Vec3, refv: Vec3, r: f32, d: Vec3) {
        let b = t.cross(refv);
        let mitred = t.dot(d) < 0.999_999;
        for (j, &(c, s)) in self.cs.iter().enumerate() {
            let rho = refv * c + b * s;
            let mut k = r;
            if mitred {
                let x = rho.dot(d);
                k *= (1.0 - x * x)
                    .max(1.0 / (MAX_MITRE * MAX_MITRE))
                    .sqrt()
                    .recip();
            }
            self.positions[j] = centre + rho * k;
            self.normals[j] = rho;
        }
    }

    fn push_ring(&self, m: &mut PlantMesh, v: f32, wind: f32) -> u32 {
        let base = m.positions.len() as u32;
        let r = self.cs.len() - 1;
        let inv = 1.0 / r as f32;
        m.positions.extend_from_slice(&self.positions[..=r]);
        m.normals.extend_from_slice(&self.normals[..=r]);
        m.uvs.extend((0..=r).map(|j| Vec2::new(j as f32 * inv, v)));
        m.wind.extend(std::iter::repeat_n(wind, r + 1));
        base
    }

    /// A flat cap: the centre and the ring's first `R` points, facing `normal`;
    /// `outward` picks the winding (the end cap) or its reverse (the start cap).
    fn push_cap(&self, m: &mut PlantMesh, centre: Vec3, normal: Vec3, wind: f32, end: bool) {
        let base = m.positions.len() as u32;
        let r = self.cs.len() - 1;
        m.positions.push(centre);
        m.positions.extend_from_slice(&self.positions[..r]);
        m.normals.extend(std::iter::repeat_n(normal, r + 1));
        m.uvs.push(Vec2::splat(0.5));
        m.uvs.extend(
            self.cs[..r]
                .iter()
                .map(|&(c, s)| Vec2::new(0.5 + 0.5 * c, 0.5 + 0.5 * s)),
        );
        m.wind.extend(std::iter::repeat_n(wind, r + 1));
        let r = r as u32;
        for j in 0..r {
            let (a, b) = (base + 1 + j, base + 1 + (j + 1) % r);
            if end {
                m.indices.extend_from_slice(&[base, a, b]);
            } else {
                m.indices.extend_from_slice(&[base, b, a]);
            }
        }
    }
}

/// Joins ring `a` to ring `b` (both `R + 1` vertices) with `2 R` triangles facing outward.
#[inline]
fn join(m: &mut PlantMesh, a: u32, b: u32, r: u32) {
    for j in 0..r {
        m.indices
            .extend_from_slice(&[a + j, a + j + 1, b + j + 1, a + j, b + j + 1, b + j]);
    }
}

/// Unit direction of segment `k`, or `fallback` for a zero-length one.
#[inline]
fn direction(g: &Geometry, k: usize, fallback: Vec3) -> Vec3 {
    let d = g.end[k] - g.start[k];
    let l = d.length();
    if l > 1e-12 * g.end[k].abs().max_element().max(1.0) {
        d / l
    } else {
        fallback
    }
}

/// A unit vector ⟂ unit `t`, as close to `v` as possible.
#[inline]
fn perpendicular(v: Vec3, t: Vec3) -> Vec3 {
    let w = v - t * v.dot(t);
    let l = w.length();
    if l > 1e-6 {
        w / l
    } else {
        t.any_orthonormal_vector()
    }
}

/// Appends the bark of every chain to `m`.
pub(super) fn build(
    g: &Geometry,
    chains: &Chains,
    p: &MeshParams,
    inv_max: f32,
    m: &mut PlantMesh,
) {
    let r = p.radial_segments;
    let cs: Vec<(f32, f32)> = (0..=r)
        .map(|j| {
            let a = std::f64::consts::TAU * f64::from(j % r) / f64::from(r);
            (a.cos() as f32, a.sin() as f32)
        })
        .collect();
    let mut ring = Ring {
        cs: &cs,
        positions: [Vec3::ZERO; 65],
        normals: [Vec3::ZERO; 65],
    };
    let wind = |d: f32| (d * inv_max).clamp(0.0, 1.0);
    for &k0 in &chains.starts {
        let mut k = k0 as usize;
        let mut d = direction(g, k, Vec3::Z);
        let mut t = d;
        let mut refv = perpendicular(g.up[k], t);
        ring.place(g.start[k], t, refv, 0.5 * g.width0[k], d);
        let w0 = wind(g.dist0[k]);
        if p.caps {
            ring.push_cap(m, g.start[k], -t, w0, false);
        }
        let mut a = ring.push_ring(m, g.dist0[k], w0);
        loop {
            let n = chains.next[k];
            let wk = wind(g.dist1[k]);
            if n == u32::MAX {
                let rv = perpendicular(transport(refv, t, d), d);
                ring.place(g.end[k], d, rv, 0.5 * g.width1[k], d);
                let b = ring.push_ring(m, g.dist1[k], wk);
                join(m, a, b, r);
                if p.caps {
                    ring.push_cap(m, g.end[k], d, wk, true);
                }
                break;
            }
            let n = n as usize;
            let dn = direction(g, n, d);
            let sum = d + dn;
            let tn = if sum.length_squared() > 1e-12 {
                sum.normalize()
            } else {
                d
            };
            refv = perpendicular(transport(refv, t, tn), tn);
            t = tn;
            ring.place(g.end[k], t, refv, 0.5 * g.width0[n], d);
            let b = ring.push_ring(m, g.dist1[k], wk);
            join(m, a, b, r);
            a = b;
            k = n;
            d = dn;
        }
    }
}
