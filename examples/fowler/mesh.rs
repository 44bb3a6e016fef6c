//! Coloured triangle meshes for the organs of Fowler et al.'s figures,
//! built from small parametric patches (the source's organs are Bézier
//! surfaces), placed by natura-plant's organ frames and drawn with
//! natura-core's preview rasterizer (Lambert shading plus ambient, as
//! natura-plant's plant previews).

use natura::core::Image;
use natura::core::glam::{DMat3, DVec3, Vec3};
use natura::core::preview::{PreviewCamera, Projector, Raster, facing, lambert};
use natura::plant::models::phyllotaxis::OrganFrame;

use crate::common::Exit;

/// A triangle mesh with a colour at every vertex (linear RGB).
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pos: Vec<DVec3>,
    nrm: Vec<DVec3>,
    col: Vec<Vec3>,
    tri: Vec<[u32; 3]>,
}

impl Mesh {
    /// Triangles in the mesh.
    pub fn triangles(&self) -> usize {
        self.tri.len()
    }

    /// A `nu × nv` grid patch: `f(u, v)` the point at `u, v ∈ [0, 1]`,
    /// `colour(u, v)` its colour; normals are the mean of the faces'
    /// around each vertex.
    pub fn patch(
        &mut self,
        nu: u32,
        nv: u32,
        f: impl Fn(f64, f64) -> DVec3,
        colour: impl Fn(f64, f64) -> Vec3,
    ) {
        let base = self.pos.len() as u32;
        let (nu, nv) = (nu.max(1), nv.max(1));
        for j in 0..=nv {
            for i in 0..=nu {
                let (u, v) = (f64::from(i) / f64::from(nu), f64::from(j) / f64::from(nv));
                self.pos.push(f(u, v));
                self.nrm.push(DVec3::ZERO);
                self.col.push(colour(u, v));
            }
        }
        let at = |i: u32, j: u32| base + j * (nu + 1) + i;
        for j in 0..nv {
            for i in 0..nu {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                for t in [[a, b, c], [a, c, d]] {
                    let [p, q, r] = t.map(|k| self.pos[k as usize]);
                    let n = (q - p).cross(r - p);
                    if n.length_squared() > 0.0 {
                        for k in t {
                            self.nrm[k as usize] += n;
                        }
                        self.tri.push(t);
                    }
                }
            }
        }
        for n in &mut self.nrm[base as usize..] {
            *n = n.normalize_or(DVec3::Z);
        }
    }

    /// A surface of revolution about local `+z`: `profile(s)` the radius and
    /// height at `s ∈ [0, 1]`, `lobes(θ)` a factor on the radius around the
    /// axis (1 for a round one).
    pub fn revolve(
        &mut self,
        segments: u32,
        rings: u32,
        profile: impl Fn(f64) -> (f64, f64),
        lobes: impl Fn(f64) -> f64,
        colour: impl Fn(f64) -> Vec3,
    ) {
        let tau = std::f64::consts::TAU;
        self.patch(
            segments,
            rings,
            |u, v| {
                let (r, h) = profile(v);
                let a = u * tau;
                let r = r * lobes(a);
                DVec3::new(r * a.cos(), r * a.sin(), h)
            },
            |_, v| colour(v),
        );
    }

    /// A sphere of radius `r` at `c`.
    pub fn sphere(&mut self, c: DVec3, r: f64, res: u32, colour: Vec3) {
        let pi = std::f64::consts::PI;
        self.revolve(
            2 * res,
            res,
            |s| ((pi * s).sin() * r, -(pi * s).cos() * r),
            |_| 1.0,
            |_| colour,
        );
        let n = (2 * res + 1) * (res + 1);
        let first = self.pos.len() - n as usize;
        for p in &mut self.pos[first..] {
            *p += c;
        }
    }

    /// A thin tube of radius `r` from `a` to `b`.
    pub fn tube(&mut self, a: DVec3, b: DVec3, r: f64, res: u32, colour: Vec3) {
        let axis = b - a;
        let len = axis.length();
        if len <= 0.0 {
            return;
        }
        let mut m = Mesh::default();
        m.revolve(res, 1, |s| (r, s * len), |_| 1.0, |_| colour);
        self.append(&m, |p| a + along(axis / len, p), |n| along(axis / len, n));
    }

    /// Adds triangles `tri` over the vertices `pos` with normals `nrm` and
    /// colours `col` (one each a vertex).
    #[allow(dead_code)] // plant_models draws its stand of trees with it
    pub fn add_triangles(&mut self, pos: &[DVec3], nrm: &[DVec3], col: &[Vec3], tri: &[[u32; 3]]) {
        let base = self.pos.len() as u32;
        self.pos.extend_from_slice(pos);
        self.nrm
            .extend(nrm.iter().map(|n| n.normalize_or(DVec3::Z)));
        self.col.extend_from_slice(col);
        self.tri.extend(tri.iter().map(|t| t.map(|k| k + base)));
    }

    /// Adds `other` with its points mapped by `point` and normals by `dir`.
    pub fn append(
        &mut self,
        other: &Mesh,
        point: impl Fn(DVec3) -> DVec3,
        dir: impl Fn(DVec3) -> DVec3,
    ) {
        let base = self.pos.len() as u32;
        self.pos.extend(other.pos.iter().map(|&p| point(p)));
        self.nrm
            .extend(other.nrm.iter().map(|&n| dir(n).normalize_or(DVec3::Z)));
        self.col.extend_from_slice(&other.col);
        self.tri
            .extend(other.tri.iter().map(|t| t.map(|k| k + base)));
    }

    /// Adds `organ` (modelled with its contact point at the origin, `+z`
    /// the receptacle's normal, `+x` the curve's tangent, unit size) at
    /// `frame`, scaled by the frame's primordium radius.
    pub fn place(&mut self, organ: &Mesh, frame: &OrganFrame) {
        self.append(organ, |p| frame.to_world(p), |n| frame.turn(n));
    }

    /// Adds `other` scaled by `s`, turned by `rot` and moved by `at`.
    pub fn put(&mut self, other: &Mesh, at: DVec3, rot: DMat3, s: f64) {
        self.append(other, |p| at + rot * (s * p), |n| rot * n);
    }

    /// Multiplies every colour by `k`.
    pub fn tint(&mut self, k: Vec3) {
        for c in &mut self.col {
            *c *= k;
        }
    }

    /// The mesh without the triangles that reach below height `z`.
    pub fn clipped_below(&self, z: f64) -> Mesh {
        let mut m = self.clone();
        m.tri
            .retain(|t| t.iter().all(|&k| self.pos[k as usize].z >= z));
        m
    }

    /// A box from `lo` to `hi` (its six faces).
    pub fn slab(&mut self, lo: DVec3, hi: DVec3, colour: Vec3) {
        let d = hi - lo;
        let faces: [(DVec3, DVec3, DVec3); 6] = [
            (lo, DVec3::new(d.x, 0.0, 0.0), DVec3::new(0.0, d.y, 0.0)),
            (
                lo + DVec3::Z * d.z,
                DVec3::new(d.x, 0.0, 0.0),
                DVec3::new(0.0, d.y, 0.0),
            ),
            (lo, DVec3::new(d.x, 0.0, 0.0), DVec3::new(0.0, 0.0, d.z)),
            (
                lo + DVec3::Y * d.y,
                DVec3::new(d.x, 0.0, 0.0),
                DVec3::new(0.0, 0.0, d.z),
            ),
            (lo, DVec3::new(0.0, d.y, 0.0), DVec3::new(0.0, 0.0, d.z)),
            (
                lo + DVec3::X * d.x,
                DVec3::new(0.0, d.y, 0.0),
                DVec3::new(0.0, 0.0, d.z),
            ),
        ];
        for (o, a, b) in faces {
            self.patch(1, 1, |u, v| o + a * u + b * v, |_, _| colour);
        }
    }

    /// The axis-aligned bounds of the triangles, or `None` for a mesh
    /// without any.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let first = self.pos[*self.tri.first()?.first()? as usize];
        Some(
            self.tri
                .iter()
                .flatten()
                .map(|&k| self.pos[k as usize])
                .fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))),
        )
    }
}

/// `p` in the frame whose `+z` is the unit vector `z` (any perpendicular
/// `x`).
pub fn along(z: DVec3, p: DVec3) -> DVec3 {
    let (x, y) = z.any_orthonormal_pair();
    p.x * x + p.y * y + p.z * z
}

/// How a picture is lit and seen.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Direction the camera looks along.
    pub dir: Vec3,
    /// Vertical field of view in degrees (`None`: orthographic).
    pub fov: Option<f32>,
    /// Direction towards the light.
    pub light: Vec3,
    /// Background colour (linear RGB).
    pub background: Vec3,
    /// How much closer than the framing of the bounds the camera stands
    /// (the framing fits the box's bounding sphere, loose for flat scenes).
    pub zoom: f32,
}

impl View {
    /// Looking along `dir` through a 30° lens, lit from the upper left front.
    pub fn along(dir: Vec3) -> Self {
        Self {
            dir,
            fov: Some(30.0),
            light: Vec3::new(-0.5, -0.8, 0.9),
            background: Vec3::new(0.05, 0.06, 0.08),
            zoom: 1.0,
        }
    }

    /// The same view `zoom` times closer.
    pub fn zoomed(self, zoom: f32) -> Self {
        Self { zoom, ..self }
    }
}

/// Draws `mesh` into a `width × height` picture framed to its bounds.
///
/// # Errors
///
/// An empty mesh, or what natura-core's camera and rasterizer refuse.
pub fn render(mesh: &Mesh, view: &View, width: u32, height: u32) -> Result<Image, Exit> {
    let (lo, hi) = mesh
        .bounds()
        .ok_or_else(|| Exit::new(2, "a picture needs something to draw"))?;
    let aspect = width as f32 / height as f32;
    let mut cam = PreviewCamera::framing(lo.as_vec3(), hi.as_vec3(), view.dir, view.fov, aspect)?;
    if !(view.zoom.is_finite() && view.zoom > 0.0) {
        return Err(Exit::new(2, format!("zoom {} must be > 0", view.zoom)));
    }
    cam.eye = cam.target + (cam.eye - cam.target) / view.zoom;
    let mut frame = Raster::new(width, height, 3, view.background)?;
    let (w, h) = frame.samples();
    let proj = Projector::new(&cam, w, h)?;
    let light = view.light.normalize();
    let world: Vec<Vec3> = mesh.pos.iter().map(|p| p.as_vec3()).collect();
    let screen: Vec<Option<[f32; 3]>> = world.iter().map(|&p| proj.project(p)).collect();
    let lit: Vec<Vec3> = world
        .iter()
        .zip(&mesh.nrm)
        .zip(&mesh.col)
        .map(|((&p, n), &c)| {
            let n = facing(n.as_vec3(), proj.to_viewer(p));
            c * lambert(n, light, 0.3)
        })
        .collect();
    for t in &mesh.tri {
        let [a, b, c] = t.map(|k| k as usize);
        if let (Some(pa), Some(pb), Some(pc)) = (screen[a], screen[b], screen[c]) {
            frame.triangle([pa, pb, pc], |f| f.mix([lit[a], lit[b], lit[c]]))?;
        }
    }
    Ok(frame.resolve()?)
}
