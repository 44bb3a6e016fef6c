//! Ray queries against instanced meshes: a two-level bounding volume
//! hierarchy (obvhs' compressed wide BVH8 of Ylitie, Karras & Laine 2017,
//! built by PLOC: the top level over the
//! instances' world boxes, one bottom level per prototype mesh over its
//! triangles, rays carried into each instance's frame), and the brute-force
//! path that tests every triangle of every instance, for checking it.
//!
//! Closest hits are decided by the key `(t, instance, triangle)`, so equal
//! distances resolve the same way whichever order the hierarchy visits.

use std::time::Duration;

use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::ray::{Ray as BvhRay, RayHit};

use super::tri;

/// The smallest `f32` above a finite `x` (`x` itself for ∞).
#[inline]
fn above(x: f32) -> f32 {
    if !x.is_finite() {
        x
    } else if x == 0.0 {
        f32::from_bits(1)
    } else if x > 0.0 {
        f32::from_bits(x.to_bits() + 1)
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

fn build(boxes: &[Aabb]) -> Option<CwBvh> {
    (!boxes.is_empty()).then(|| {
        build_cwbvh(
            boxes,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        )
    })
}

fn bvh_ray(o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> BvhRay {
    BvhRay::new(Vec3A::from(o), Vec3A::from(d), t_min.max(0.0), t_max)
}

/// A prototype mesh: triangles with their unit geometric normals and
/// whether each is leaf (else bark), and its bottom-level hierarchy.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Triangles, in the prototype's frame (base at the origin, +z up).
    pub tris: Vec<[Vec3; 3]>,
    /// Unit geometric normal per triangle.
    pub normals: Vec<Vec3>,
    /// Unit shading normal at each corner of each triangle, interpolated
    /// across it (smooth over a crown; the geometric normal where the mesh
    /// was built without them).
    pub shading: Vec<[Vec3; 3]>,
    /// Whether each triangle is leaf (true) or bark.
    pub leaf: Vec<bool>,
    /// Bounds of the triangles.
    pub bounds: (Vec3, Vec3),
    bvh: Option<CwBvh>,
}

impl Mesh {
    /// Builds the hierarchy over `tris` (degenerate triangles are dropped),
    /// shaded flat.
    #[must_use]
    pub fn new(tris: Vec<[Vec3; 3]>, leaf: Vec<bool>) -> Self {
        let shading = vec![[Vec3::ZERO; 3]; tris.len()];
        Self::with_shading(tris, leaf, shading)
    }

    /// As [`Self::new`], with a shading normal at each corner of each
    /// triangle (a corner whose normal is not finite and non-zero takes the
    /// triangle's geometric normal).
    #[must_use]
    pub fn with_shading(tris: Vec<[Vec3; 3]>, leaf: Vec<bool>, shading: Vec<[Vec3; 3]>) -> Self {
        let (mut t2, mut l2, mut normals) = (Vec::new(), Vec::new(), Vec::new());
        let mut s2 = Vec::new();
        for ((t, l), sh) in tris.into_iter().zip(leaf).zip(shading) {
            let n = (t[1] - t[0]).cross(t[2] - t[0]);
            if let Some(n) = n
                .try_normalize()
                .filter(|_| t.iter().all(|v| v.is_finite()))
            {
                t2.push(t);
                l2.push(l);
                normals.push(n);
                s2.push(sh.map(|c| c.try_normalize().unwrap_or(n)));
            }
        }
        let boxes: Vec<Aabb> = t2
            .iter()
            .map(|t| {
                Aabb::new(
                    Vec3A::from(t[0].min(t[1]).min(t[2])),
                    Vec3A::from(t[0].max(t[1]).max(t[2])),
                )
            })
            .collect();
        let bounds = t2.iter().flatten().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let bounds = if t2.is_empty() {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            bounds
        };
        Self {
            bvh: build(&boxes),
            tris: t2,
            normals,
            shading: s2,
            leaf: l2,
            bounds,
        }
    }

    /// Number of triangles.
    #[must_use]
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// Whether the mesh has no triangles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// The closest triangle `(t, index)` along `o + t·d` in `(t_min, t_max)`
    /// whose key `(t, index)` is below `(t_max, bound)`, through the hierarchy.
    fn closest(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let bvh = self.bvh.as_ref()?;
        let mut best: Option<(f32, u32)> = None;
        let mut hit = RayHit::none();
        bvh.ray_traverse(bvh_ray(o, d, t_min, above(t_max)), &mut hit, |r, id| {
            let k = bvh.primitive_indices[id];
            match tri::intersect(o, d, &self.tris[k as usize], t_min, above(r.tmax)) {
                Some(t) if t < t_max => {
                    if best.is_none_or(|(bt, bk)| t < bt || (t == bt && k < bk)) {
                        best = Some((t, k));
                    }
                    t
                }
                _ => f32::INFINITY,
            }
        });
        best
    }

    /// The same by testing every triangle in order.
    fn closest_brute(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut best: Option<(f32, u32)> = None;
        for (k, t) in self.tris.iter().enumerate() {
            let lim = best.map_or(t_max, |b| b.0);
            if let Some(t) = tri::intersect(o, d, t, t_min, lim) {
                best = Some((t, k as u32));
            }
        }
        best
    }

    /// Whether any triangle crosses `o + t·d` in `(t_min, t_max)`.
    pub(crate) fn any(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> bool {
        let Some(bvh) = &self.bvh else {
            return false;
        };
        !bvh.ray_traverse_miss(bvh_ray(o, d, t_min, t_max), |_, id| {
            let k = bvh.primitive_indices[id] as usize;
            tri::intersect(o, d, &self.tris[k], t_min, t_max).unwrap_or(f32::INFINITY)
        })
    }
}

/// One placed copy of a mesh: `world = position + scale · Rz(yaw) · local`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Index of the mesh.
    pub mesh: u32,
    /// Base of the plant, metres.
    pub position: Vec3,
    /// Uniform scale, metres per mesh unit.
    pub scale: f32,
    /// `(cos, sin)` of the rotation about +z.
    pub cos_sin: (f32, f32),
}

impl Placement {
    /// A world point or direction (`w = 0`) into the mesh's frame; directions
    /// are divided by the scale too, so ray parameters stay world distances.
    #[inline]
    pub(crate) fn local(&self, v: Vec3, point: bool) -> Vec3 {
        let q = if point { v - self.position } else { v };
        let (c, s) = self.cos_sin;
        Vec3::new(c * q.x + s * q.y, -s * q.x + c * q.y, q.z) / self.scale
    }

    /// A mesh-frame direction (a normal) into the world.
    #[inline]
    #[must_use]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        let (c, s) = self.cos_sin;
        Vec3::new(c * n.x - s * n.y, s * n.x + c * n.y, n.z)
    }

    /// The world box of the mesh's bounds `(lo, hi)` placed here.
    fn world_box(&self, (lo, hi): (Vec3, Vec3)) -> (Vec3, Vec3) {
        let (c, s) = self.cos_sin;
        let mut b = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for k in 0..8 {
            let p = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let w =
                self.position + self.scale * Vec3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z);
            b = (b.0.min(w), b.1.max(w));
        }
        b
    }
}

/// Optical depth past which [`Instanced::transmittance`] stops adding.
const OPAQUE_DEPTH: f32 = 6.9;

/// The closest hit of a ray on an instanced scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceHit {
    /// Ray parameter (world distance for a unit direction).
    pub t: f32,
    /// Index of the instance.
    pub instance: u32,
    /// Index of the triangle in the instance's mesh.
    pub triangle: u32,
}

/// Meshes placed many times, with the top-level hierarchy over the placements.
#[derive(Clone, Debug)]
pub struct Instanced {
    /// The prototype meshes.
    pub meshes: Vec<Mesh>,
    /// The placements.
    pub placements: Vec<Placement>,
    tlas: Option<CwBvh>,
}

impl Instanced {
    /// Builds the top level over the placements' world boxes (placements of
    /// empty meshes get an empty box far away and are never hit).
    #[must_use]
    pub fn new(meshes: Vec<Mesh>, placements: Vec<Placement>) -> Self {
        let boxes: Vec<Aabb> = placements
            .iter()
            .map(|p| {
                let (lo, hi) = p.world_box(meshes[p.mesh as usize].bounds);
                Aabb::new(Vec3A::from(lo), Vec3A::from(hi))
            })
            .collect();
        Self {
            tlas: build(&boxes),
            meshes,
            placements,
        }
    }

    /// The closest hit along `o + t·d` with `t` in `(t_min, t_max)`, through
    /// both levels of the hierarchy.
    #[must_use]
    pub fn closest(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<InstanceHit> {
        let tlas = self.tlas.as_ref()?;
        let mut best: Option<InstanceHit> = None;
        let mut hit = RayHit::none();
        tlas.ray_traverse(bvh_ray(o, d, t_min, above(t_max)), &mut hit, |r, id| {
            let i = tlas.primitive_indices[id];
            let p = &self.placements[i as usize];
            let lim = best.map_or(t_max, |b| above(b.t)).min(above(r.tmax));
            let m = &self.meshes[p.mesh as usize];
            match m.closest(p.local(o, true), p.local(d, false), t_min, lim) {
                Some((t, k)) => {
                    let better = best
                        .is_none_or(|b| t < b.t || (t == b.t && (i, k) < (b.instance, b.triangle)));
                    if better && t < t_max {
                        best = Some(InstanceHit {
                            t,
                            instance: i,
                            triangle: k,
                        });
                    }
                    t
                }
                None => f32::INFINITY,
            }
        });
        best
    }

    /// The same by testing every triangle of every instance, in order.
    #[must_use]
    pub fn closest_brute(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<InstanceHit> {
        let mut best: Option<InstanceHit> = None;
        for (i, p) in self.placements.iter().enumerate() {
            let lim = best.map_or(t_max, |b| b.t);
            let m = &self.meshes[p.mesh as usize];
            if let Some((t, k)) = m.closest_brute(p.local(o, true), p.local(d, false), t_min, lim) {
                best = Some(InstanceHit {
                    t,
                    instance: i as u32,
                    triangle: k,
                });
            }
        }
        best
    }

    /// Whether anything lies along `o + t·d` with `t` in `(t_min, t_max)`.
    #[must_use]
    pub fn occluded(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> bool {
        let Some(tlas) = &self.tlas else {
            return false;
        };
        !tlas.ray_traverse_miss(bvh_ray(o, d, t_min, t_max), |_, id| {
            let p = &self.placements[tlas.primitive_indices[id] as usize];
            let m = &self.meshes[p.mesh as usize];
            if m.any(p.local(o, true), p.local(d, false), t_min, t_max) {
                t_min
            } else {
                f32::INFINITY
            }
        })
    }

    /// The fraction of light passing along `o + t·d`, `t > t_min`, through
    /// the crowns as turbid media: `exp(−Σ τ)` over the placements whose
    /// crown the ray crosses, `media[mesh]` the crown of each mesh (`None`:
    /// no leaves, transparent). Stops adding once the light is under a
    /// thousandth.
    #[must_use]
    pub fn transmittance(
        &self,
        o: Vec3,
        d: Vec3,
        t_min: f32,
        media: &[Option<super::turbid::CrownMedium>],
    ) -> f32 {
        let Some(tlas) = &self.tlas else {
            return 1.0;
        };
        let mut depth = 0.0f32;
        tlas.ray_traverse_miss(bvh_ray(o, d, t_min, f32::INFINITY), |_, id| {
            let p = &self.placements[tlas.primitive_indices[id] as usize];
            if let Some(m) = &media[p.mesh as usize] {
                depth += m.optical_depth(p.local(o, true), p.local(d, false), t_min);
            }
            if depth > OPAQUE_DEPTH {
                t_min
            } else {
                f32::INFINITY
            }
        });
        (-depth).exp()
    }

    /// Whether anything lies along the ray, by testing every triangle.
    #[must_use]
    pub fn occluded_brute(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> bool {
        self.placements.iter().any(|p| {
            let m = &self.meshes[p.mesh as usize];
            let (lo, ld) = (p.local(o, true), p.local(d, false));
            m.tris
                .iter()
                .any(|t| tri::intersect(lo, ld, t, t_min, t_max).is_some())
        })
    }
}
