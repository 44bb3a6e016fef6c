//! Leaf-material geometry: polygons (ear-clipped in their plane) and the
//! predefined surfaces `~L` leaf, `~P` petal, `~K` flower, `@o` disc, `@O` sphere.

use super::{MeshParams, PlantMesh};
use crate::turtle::{Geometry, SurfaceInstance};
use glam::{DVec3, Vec2, Vec3};

/// The predefined surfaces this mesher knows.
pub(super) const KNOWN: [char; 5] = ['L', 'P', 'K', 'o', 'O'];

/// Petals of the flower `~K`.
const FLOWER_PETALS: u32 = 5;

fn sphere_stacks(p: &MeshParams) -> u32 {
    (p.radial_segments / 2).max(2)
}

/// Vertices and indices of one surface, single-sided.
fn surface_counts(name: char, p: &MeshParams) -> (usize, usize) {
    let r = p.radial_segments as usize;
    let n = p.leaf_rows as usize;
    let leaf = (3 * n - 1, 12 * (n - 1));
    match name {
        'L' | 'P' => leaf,
        'K' => (
            leaf.0 * FLOWER_PETALS as usize,
            leaf.1 * FLOWER_PETALS as usize,
        ),
        'o' => (r + 1, 3 * r),
        'O' => {
            let s = sphere_stacks(p) as usize;
            ((s + 1) * (r + 1), 3 * r * (2 * s - 2))
        }
        _ => (0, 0),
    }
}

/// Vertices and indices of the leaf material.
pub(super) fn counts(g: &Geometry, p: &MeshParams) -> (usize, usize) {
    let (mut v, mut i) = (0, 0);
    for poly in &g.polygons {
        let n = poly.vertices.len();
        if n >= 3 {
            v += n;
            i += 3 * (n - 2);
        }
    }
    for s in &g.surfaces {
        let (a, b) = surface_counts(s.name, p);
        v += a;
        i += b;
    }
    let sides = if p.double_sided_leaves { 2 } else { 1 };
    (v * sides, i * sides)
}

/// Appends every polygon and surface to `m`.
pub(super) fn build(g: &Geometry, p: &MeshParams, inv_max: f32, m: &mut PlantMesh) {
    let v0 = m.positions.len();
    let i0 = m.indices.len();
    let wind = |d: f32| (d * inv_max).clamp(0.0, 1.0);
    let mut scratch: Vec<u32> = Vec::new();
    let mut flat: Vec<Vec2> = Vec::new();
    for poly in &g.polygons {
        if poly.vertices.len() >= 3 {
            polygon(
                &poly.vertices,
                wind(poly.distance),
                m,
                &mut scratch,
                &mut flat,
            );
        }
    }
    for s in &g.surfaces {
        let w = wind(s.distance);
        match s.name {
            'L' => blade(s, &s.frame.h, s.frame.l, 0.8, 1.0, p, w, m),
            'P' => blade(s, &s.frame.h, s.frame.l, 1.5, 1.0, p, w, m),
            'K' => flower(s, p, w, m),
            'o' => disc(s, p, w, m),
            'O' => sphere(s, p, w, m),
            _ => {}
        }
    }
    if p.double_sided_leaves {
        let v1 = m.positions.len();
        let i1 = m.indices.len();
        m.positions.extend_from_within(v0..v1);
        m.normals.extend_from_within(v0..v1);
        m.uvs.extend_from_within(v0..v1);
        m.wind.extend_from_within(v0..v1);
        for n in &mut m.normals[v1..] {
            *n = -*n;
        }
        let shift = (v1 - v0) as u32;
        for t in i0 / 3..i1 / 3 {
            let (a, b, c) = (m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]);
            m.indices
                .extend_from_slice(&[a + shift, c + shift, b + shift]);
        }
    }
}

/// Newell's normal of a polygon (unit; +z for a degenerate one).
fn newell(v: &[Vec3]) -> Vec3 {
    let mut n = DVec3::ZERO;
    for (k, a) in v.iter().enumerate() {
        let (a, b) = (a.as_dvec3(), v[(k + 1) % v.len()].as_dvec3());
        n += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let n = n.as_vec3();
    n.try_normalize().unwrap_or(Vec3::Z)
}

/// Twice the signed area of the 2-D triangle `a b c` (positive if counter-clockwise).
#[inline]
fn cross2(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    (b - a).perp_dot(c - a)
}

/// A polygon: its vertices with the plane's normal, ear-clipped into `n − 2`
/// triangles counter-clockwise about the normal (a fan where no ear is left,
/// as for a self-intersecting outline). UVs span the polygon's bounding
/// rectangle in its plane.
fn polygon(v: &[Vec3], wind: f32, m: &mut PlantMesh, idx: &mut Vec<u32>, flat: &mut Vec<Vec2>) {
    let n = newell(v);
    let e1 = n.any_orthonormal_vector();
    let e2 = n.cross(e1);
    flat.clear();
    flat.extend(
        v.iter()
            .map(|&p| Vec2::new((p - v[0]).dot(e1), (p - v[0]).dot(e2))),
    );
    let (lo, hi) = flat
        .iter()
        .fold((flat[0], flat[0]), |(lo, hi), &q| (lo.min(q), hi.max(q)));
    let ext = (hi - lo).max(Vec2::splat(1e-12));
    let base = m.positions.len() as u32;
    m.positions.extend_from_slice(v);
    m.normals.extend(std::iter::repeat_n(n, v.len()));
    m.uvs.extend(flat.iter().map(|&q| (q - lo) / ext));
    m.wind.extend(std::iter::repeat_n(wind, v.len()));
    idx.clear();
    idx.extend(0..v.len() as u32);
    let mut guard = 0;
    let mut k = 0;
    while idx.len() > 3 {
        let len = idx.len();
        let (a, b, c) = (idx[(k + len - 1) % len], idx[k % len], idx[(k + 1) % len]);
        let (pa, pb, pc) = (flat[a as usize], flat[b as usize], flat[c as usize]);
        let convex = cross2(pa, pb, pc) > 0.0;
        let ear = convex
            && !idx.iter().any(|&q| {
                q != a && q != b && q != c && {
                    let x = flat[q as usize];
                    cross2(pa, pb, x) >= 0.0 && cross2(pb, pc, x) >= 0.0 && cross2(pc, pa, x) >= 0.0
                }
            });
        if ear || guard > len {
            m.indices.extend_from_slice(&[base + a, base + b, base + c]);
            idx.remove(k % len);
            guard = 0;
        } else {
            k = (k + 1) % len;
            guard += 1;
        }
    }
    m.indices
        .extend_from_slice(&[base + idx[0], base + idx[1], base + idx[2]]);
}

/// A leaf or petal blade along `h` across `l` with half-width profile
/// `½ width · sin(π t^shape)` (`shape < 1`: widest below the middle, a leaf;
/// `> 1`: widest towards the tip, a petal), facing `h × l`.
#[allow(clippy::too_many_arguments)]
fn blade(
    s: &SurfaceInstance,
    h: &DVec3,
    l: DVec3,
    shape: f64,
    width_scale: f64,
    p: &MeshParams,
    wind: f32,
    m: &mut PlantMesh,
) {
    let rows = p.leaf_rows;
    let o = s.frame.p;
    let (h, l) = (*h, l);
    let u = h.cross(l).normalize_or(DVec3::Z).as_vec3();
    let base = m.positions.len() as u32;
    let half = 0.5 * s.width * width_scale;
    let mut push = |q: DVec3, uv: Vec2| {
        m.positions.push(q.as_vec3());
        m.normals.push(u);
        m.uvs.push(uv);
        m.wind.push(wind);
    };
    push(o, Vec2::new(0.5, 0.0));
    for i in 1..rows {
        let t = f64::from(i) / f64::from(rows);
        let w = half * (std::f64::consts::PI * t.powf(shape)).sin();
        let c = o + h * (s.length * t);
        let tv = t as f32;
        push(c + l * w, Vec2::new(0.0, tv));
        push(c, Vec2::new(0.5, tv));
        push(c - l * w, Vec2::new(1.0, tv));
    }
    push(o + h * s.length, Vec2::new(0.5, 1.0));
    // Row i (1-based) holds left, centre, right at base + 3i − 2 …
    let row = |i: u32| base + 3 * i - 2;
    let tip = base + 3 * rows - 2;
    let (l1, c1, r1) = (row(1), row(1) + 1, row(1) + 2);
    m.indices.extend_from_slice(&[base, c1, l1, base, r1, c1]);
    for i in 1..rows - 1 {
        let (la, ca, ra) = (row(i), row(i) + 1, row(i) + 2);
        let (lb, cb, rb) = (row(i + 1), row(i + 1) + 1, row(i + 1) + 2);
        m.indices
            .extend_from_slice(&[ca, cb, lb, ca, lb, la, ra, rb, cb, ra, cb, ca]);
    }
    let (ln, cn, rn) = (row(rows - 1), row(rows - 1) + 1, row(rows - 1) + 2);
    m.indices.extend_from_slice(&[cn, tip, ln, rn, tip, cn]);
}

/// Five petals around the heading, tilted 30° up from the plane ⟂ `H`.
fn flower(s: &SurfaceInstance, p: &MeshParams, wind: f32, m: &mut PlantMesh) {
    let f = &s.frame;
    let tilt = 30f64.to_radians();
    for i in 0..FLOWER_PETALS {
        let a = std::f64::consts::TAU * f64::from(i) / f64::from(FLOWER_PETALS);
        let radial = f.l * a.cos() + f.u * a.sin();
        let h = radial * tilt.cos() + f.h * tilt.sin();
        let l = -f.l * a.sin() + f.u * a.cos();
        blade(s, &h, l, 1.5, 0.6, p, wind, m);
    }
}

/// A disc of radius `length` in the plane ⟂ `H`, facing `H`.
fn disc(s: &SurfaceInstance, p: &MeshParams, wind: f32, m: &mut PlantMesh) {
    let f = &s.frame;
    let r = p.radial_segments;
    let base = m.positions.len() as u32;
    let n = f.h.as_vec3().normalize_or(Vec3::Z);
    m.positions.push(f.p.as_vec3());
    m.uvs.push(Vec2::splat(0.5));
    for j in 0..r {
        let a = std::f64::consts::TAU * f64::from(j) / f64::from(r);
        let (sn, c) = a.sin_cos();
        m.positions
            .push((f.p + (f.l * c + f.u * sn) * s.length).as_vec3());
        m.uvs
            .push(Vec2::new(0.5 + 0.5 * c as f32, 0.5 + 0.5 * sn as f32));
    }
    m.normals.extend(std::iter::repeat_n(n, r as usize + 1));
    m.wind.extend(std::iter::repeat_n(wind, r as usize + 1));
    // L × U = H, so counter-clockwise in (L, U) faces H.
    for j in 0..r {
        m.indices
            .extend_from_slice(&[base, base + 1 + j, base + 1 + (j + 1) % r]);
    }
}

/// A sphere of radius `length` centred on the turtle, poles along `H`.
fn sphere(s: &SurfaceInstance, p: &MeshParams, wind: f32, m: &mut PlantMesh) {
    let f = &s.frame;
    let r = p.radial_segments;
    let st = sphere_stacks(p);
    let base = m.positions.len() as u32;
    for i in 0..=st {
        let th = std::f64::consts::PI * f64::from(i) / f64::from(st);
        let (sz, cz) = th.sin_cos();
        for j in 0..=r {
            let a = std::f64::consts::TAU * f64::from(j % r) / f64::from(r);
            let (sa, ca) = a.sin_cos();
            // From −H (i = 0) to +H (i = st); (L, U, H) is right-handed.
            let dir = (f.l * ca + f.u * sa) * sz - f.h * cz;
            let n = if i == 0 {
                -f.h
            } else if i == st {
                f.h
            } else {
                dir
            };
            m.positions.push((f.p + dir * s.length).as_vec3());
            m.normals.push(n.as_vec3().normalize_or(Vec3::Z));
            m.uvs
                .push(Vec2::new(j as f32 / r as f32, i as f32 / st as f32));
            m.wind.push(wind);
        }
    }
    let w = r + 1;
    for i in 0..st {
        for j in 0..r {
            let a = base + i * w + j;
            let (b, c, d) = (a + 1, a + w, a + w + 1);
            if i > 0 {
                m.indices.extend_from_slice(&[a, b, d]);
            }
            if i + 1 < st {
                m.indices.extend_from_slice(&[a, d, c]);
            }
        }
    }
}
