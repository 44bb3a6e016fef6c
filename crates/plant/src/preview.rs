//! Pictures of plant meshes: a small deterministic software rasterizer.
//!
//! Triangles are projected by an orthographic or perspective [`PreviewCamera`]
//! (natura-core's [`OrthographicCamera`] or [`PinholeCamera`] does the
//! projection; the framing and the degrees of a preview's field of view are
//! this module's),
//! filled with edge functions at pixel centres, resolved with a z-buffer and
//! shaded per pixel with Lambert's law plus an ambient term, using the
//! interpolated vertex normal turned towards the viewer (every surface is
//! lit on both sides). Supersampling (a box filter over `s × s` samples per
//! pixel) smooths edges. The rasterizer is single-threaded and uses no
//! randomness, so the same mesh and parameters always give the same image.
//! The result is a linear-light [`Image`]; `Image::to_srgb8` gives the RGB8
//! bytes and `Image::save_png` writes them (atomically).
//!
//! Triangles with a vertex closer to a perspective camera than its near
//! plane, or behind an orthographic camera's screen, are skipped rather than
//! clipped (a preview frames the whole plant).

use crate::error::Result;
use crate::mesh::{Instance, Material, PlantMesh, invalid};
use glam::Vec3;
use natura_core::Image;
use natura_core::camera::{OrthographicCamera, PinholeCamera};

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum PreviewProjection {
    /// Parallel projection; `height` is the visible height in metres.
    Orthographic {
        /// Visible height in metres.
        height: f32,
    },
    /// Pinhole projection with the vertical field of view in degrees.
    Perspective {
        /// Vertical field of view in degrees, in (0, 180).
        fov_y_deg: f32,
    },
}

/// A camera looking from `eye` at `target`, `up` pointing up in the picture.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PreviewCamera {
    /// Position of the eye.
    pub eye: Vec3,
    /// Point looked at (the centre of the picture).
    pub target: Vec3,
    /// Direction that appears upward (need not be ⟂ to the view).
    pub up: Vec3,
    /// The projection.
    pub projection: PreviewProjection,
}

impl PreviewCamera {
    /// Returns a camera looking along `view_dir` that frames the box
    /// `lo..hi` with a small margin in a picture of the given aspect ratio
    /// (width / height), with z up in the picture (y up if looking along z).
    /// For a perspective camera pass the field of view; `None` gives an
    /// orthographic one.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) for a non-finite box, a zero or
    /// non-finite `view_dir`, a non-positive aspect or a field of view outside (0, 180).
    pub fn framing(
        lo: Vec3,
        hi: Vec3,
        view_dir: Vec3,
        fov_y_deg: Option<f32>,
        aspect: f32,
    ) -> Result<Self> {
        if !lo.is_finite() || !hi.is_finite() {
            return Err(invalid("bounds", format!("{lo}..{hi}"), "must be finite"));
        }
        let f = view_dir
            .try_normalize()
            .ok_or_else(|| invalid("view_dir", view_dir, "must be finite and non-zero"))?;
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(invalid("aspect", aspect, "must be finite and > 0"));
        }
        let up = if f.cross(Vec3::Z).length() > 1e-3 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let r = f.cross(up).normalize();
        let u = r.cross(f);
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-3);
        let (mut r0, mut r1, mut u0, mut u1) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for k in 0..8 {
            let c = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            ) - centre;
            r0 = r0.min(c.dot(r));
            r1 = r1.max(c.dot(r));
            u0 = u0.min(c.dot(u));
            u1 = u1.max(c.dot(u));
        }
        let target = centre + r * (0.5 * (r0 + r1)) + u * (0.5 * (u0 + u1));
        let cam = match fov_y_deg {
            None => {
                let h = ((u1 - u0).max((r1 - r0) / aspect) * 1.06).max(1e-3);
                Self {
                    eye: target - f * (4.0 * radius),
                    target,
                    up,
                    projection: PreviewProjection::Orthographic { height: h },
                }
            }
            Some(fov) => {
                let half = 0.5 * fov.to_radians();
                let half = half.min((half.tan() * aspect).atan());
                Self {
                    eye: target - f * (1.08 * radius / half.sin()),
                    target,
                    up,
                    projection: PreviewProjection::Perspective { fov_y_deg: fov },
                }
            }
        };
        cam.validate()?;
        Ok(cam)
    }

    /// Checks the camera can project.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) naming the field.
    pub fn validate(&self) -> Result<()> {
        let f = self.target - self.eye;
        if !self.eye.is_finite() || !self.target.is_finite() || f.length() < 1e-9 {
            return Err(invalid(
                "PreviewCamera::target",
                format!("eye {} target {}", self.eye, self.target),
                "eye and target must be finite and distinct",
            ));
        }
        if !self.up.is_finite() || f.normalize().cross(self.up).length() < 1e-6 {
            return Err(invalid(
                "PreviewCamera::up",
                self.up,
                "must be finite and not parallel to the view",
            ));
        }
        match self.projection {
            PreviewProjection::Orthographic { height } if !(height.is_finite() && height > 0.0) => {
                Err(invalid(
                    "PreviewCamera::projection.height",
                    height,
                    "must be finite and > 0",
                ))
            }
            PreviewProjection::Perspective { fov_y_deg }
                if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) =>
            {
                Err(invalid(
                    "PreviewCamera::projection.fov_y_deg",
                    fov_y_deg,
                    "must lie in (0, 180)",
                ))
            }
            _ => Ok(()),
        }
    }
}

/// Settings of a preview picture.
#[derive(Clone, Debug, PartialEq)]
pub struct PreviewParams {
    /// Width in pixels (1 to 16384).
    pub width: u32,
    /// Height in pixels (1 to 16384).
    pub height: u32,
    /// Samples per pixel along each axis (1 to 4).
    pub supersample: u32,
    /// The camera.
    pub camera: PreviewCamera,
    /// Direction towards the light (need not be unit).
    pub light: Vec3,
    /// Ambient fraction of the light, in [0, 1].
    pub ambient: f32,
    /// Background colour (linear RGB).
    pub background: Vec3,
    /// Colour of bark triangles (linear RGB).
    pub bark: Vec3,
    /// Colour of leaf triangles (linear RGB).
    pub leaf: Vec3,
}

impl PreviewParams {
    /// A `width × height` picture through `camera`, lit from the upper left
    /// front, with the materials' default colours on a pale background.
    #[must_use]
    pub fn new(width: u32, height: u32, camera: PreviewCamera) -> Self {
        Self {
            width,
            height,
            supersample: 2,
            camera,
            light: Vec3::new(-0.4, -0.8, 0.9),
            ambient: 0.3,
            background: Vec3::new(0.85, 0.88, 0.9),
            bark: Material::Bark.base_colour(),
            leaf: Material::Leaf.base_colour(),
        }
    }

    /// Checks sizes, colours, light and camera.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) naming the field.
    pub fn validate(&self) -> Result<()> {
        use natura_core::check;
        check::count(
            "PreviewParams::width",
            self.width as usize,
            1,
            16384,
            "must lie in 1..=16384",
        )?;
        check::count(
            "PreviewParams::height",
            self.height as usize,
            1,
            16384,
            "must lie in 1..=16384",
        )?;
        check::count(
            "PreviewParams::supersample",
            self.supersample as usize,
            1,
            4,
            "must lie in 1..=4",
        )?;
        check::in_range(
            "PreviewParams::ambient",
            f64::from(self.ambient),
            0.0,
            1.0,
            "must lie in [0, 1]",
        )?;
        if self.light.try_normalize().is_none() {
            return Err(invalid(
                "PreviewParams::light",
                self.light,
                "must be finite and non-zero",
            ));
        }
        for (name, c) in [
            ("PreviewParams::background", self.background),
            ("PreviewParams::bark", self.bark),
            ("PreviewParams::leaf", self.leaf),
        ] {
            check::non_negative3(name, c.as_dvec3())?;
        }
        self.camera.validate()
    }
}

/// The camera's projection (natura-core's [`OrthographicCamera`] or
/// [`PinholeCamera`]) and what the rasterizer adds to it: the view axis for
/// the depth key and the perspective near plane.
struct View {
    eye: Vec3,
    f: Vec3,
    projection: Projection,
    near: f32,
}

/// The projection of a [`View`].
enum Projection {
    Orthographic(OrthographicCamera),
    Perspective(PinholeCamera),
}

impl View {
    fn new(c: &PreviewCamera, w: u32, h: u32) -> Result<Self> {
        let projection = match c.projection {
            PreviewProjection::Orthographic { height } => Projection::Orthographic(
                OrthographicCamera::look_at(c.eye, c.target, c.up, height, w, h)?,
            ),
            PreviewProjection::Perspective { fov_y_deg } => Projection::Perspective(
                PinholeCamera::look_at(c.eye, c.target, c.up, fov_y_deg.to_radians(), w, h)?,
            ),
        };
        let f = match &projection {
            Projection::Orthographic(o) => o.direction(),
            Projection::Perspective(p) => p.direction(),
        };
        Ok(Self {
            eye: c.eye,
            f,
            projection,
            near: 1e-4 * (c.target - c.eye).length(),
        })
    }

    /// Screen x, y (pixels) and the depth key (larger is nearer, affine in
    /// screen space), or `None` behind the near plane (perspective) or the
    /// screen (orthographic).
    #[inline]
    fn project(&self, p: Vec3) -> Option<[f32; 3]> {
        let z = (p - self.eye).dot(self.f);
        let (q, key) = match &self.projection {
            Projection::Perspective(c) => {
                if z < self.near {
                    return None;
                }
                (c.project(p)?, 1.0 / z)
            }
            Projection::Orthographic(c) => (c.project(p)?, -z),
        };
        Some([q.x, q.y, key])
    }

    /// Unit vector from `p` towards the viewer.
    #[inline]
    fn to_viewer(&self, p: Vec3) -> Vec3 {
        match self.projection {
            Projection::Perspective(_) => (self.eye - p).normalize_or(-self.f),
            Projection::Orthographic(_) => -self.f,
        }
    }
}

/// The supersampled frame being drawn.
struct Frame {
    w: usize,
    h: usize,
    depth: Vec<f32>,
    colour: Vec<Vec3>,
}

/// Renders one mesh at the origin.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if `params` or the mesh ([`PlantMesh::check`]) is invalid.
pub fn render(mesh: &PlantMesh, params: &PreviewParams) -> Result<Image> {
    render_instances(&[(mesh, &[Instance::default()])], params)
}

/// Renders every mesh at each of its instances.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if `params`, a mesh ([`PlantMesh::check`])
/// or an instance ([`Instance::validate`]) is invalid;
/// [`PlantError::Core`](crate::PlantError::Core) if natura-core's camera
/// refuses the view (a field of view that rounds to 180°).
pub fn render_instances(
    items: &[(&PlantMesh, &[Instance])],
    params: &PreviewParams,
) -> Result<Image> {
    params.validate()?;
    for (m, inst) in items {
        m.check()?;
        for i in inst.iter() {
            i.validate()?;
        }
    }
    let s = params.supersample as usize;
    let (w, h) = (params.width as usize * s, params.height as usize * s);
    let view = View::new(&params.camera, w as u32, h as u32)?;
    let mut fr = Frame {
        w,
        h,
        depth: vec![f32::NEG_INFINITY; w * h],
        colour: vec![params.background; w * h],
    };
    let light = params.light.normalize();
    let mut screen: Vec<Option<[f32; 3]>> = Vec::new();
    let mut world: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    for (m, inst) in items {
        for i in inst.iter() {
            world.clear();
            world.extend(m.positions.iter().map(|&p| i.transform_point(p)));
            normals.clear();
            normals.extend(m.normals.iter().map(|&n| i.transform_normal(n)));
            screen.clear();
            screen.extend(world.iter().map(|&p| view.project(p)));
            for prim in &m.primitives {
                let base = match prim.material {
                    Material::Bark => params.bark,
                    Material::Leaf => params.leaf,
                };
                let r = prim.first as usize..(prim.first + prim.count) as usize;
                for t in m.indices[r].chunks_exact(3) {
                    let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
                    if let (Some(pa), Some(pb), Some(pc)) = (screen[a], screen[b], screen[c]) {
                        let shade = |k: usize, n: Vec3| {
                            let v = view.to_viewer(world[k]);
                            let n = if n.dot(v) < 0.0 { -n } else { n };
                            let lam = n.dot(light).max(0.0);
                            base * (params.ambient + (1.0 - params.ambient) * lam)
                        };
                        fill(
                            &mut fr,
                            [pa, pb, pc],
                            [normals[a], normals[b], normals[c]],
                            &shade,
                            [a, b, c],
                        );
                    }
                }
            }
        }
    }
    let (ow, oh) = (params.width as usize, params.height as usize);
    let inv = 1.0 / (s * s) as f32;
    Ok(Image::from_fn(ow, oh, |x, y| {
        let mut acc = Vec3::ZERO;
        for j in 0..s {
            for i in 0..s {
                acc += fr.colour[(y * s + j) * w + x * s + i];
            }
        }
        acc * inv
    })?)
}

/// Renders `mesh` into a `width × height` picture framed by
/// [`PreviewCamera::framing`] along `view_dir` (orthographic for `fov_y_deg = None`),
/// with the default light and colours of [`PreviewParams::new`].
///
/// # Errors
///
/// As [`PreviewCamera::framing`] and [`render`]; [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter)
/// for an empty mesh.
pub fn snapshot(
    mesh: &PlantMesh,
    width: u32,
    height: u32,
    view_dir: Vec3,
    fov_y_deg: Option<f32>,
) -> Result<Image> {
    let (lo, hi) = mesh
        .bounds()
        .ok_or_else(|| invalid("mesh", "no vertices", "a picture needs something to draw"))?;
    let aspect = width.max(1) as f32 / height.max(1) as f32;
    let camera = PreviewCamera::framing(lo, hi, view_dir, fov_y_deg, aspect)?;
    render(mesh, &PreviewParams::new(width, height, camera))
}

/// Fills one triangle: z-test per sample, then shades with the interpolated normal.
fn fill(
    fr: &mut Frame,
    p: [[f32; 3]; 3],
    n: [Vec3; 3],
    shade: &dyn Fn(usize, Vec3) -> Vec3,
    idx: [usize; 3],
) {
    let edge = |a: [f32; 3], b: [f32; 3], x: f32, y: f32| {
        (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])
    };
    let area = edge(p[0], p[1], p[2][0], p[2][1]);
    if area.is_nan() || area.abs() <= 1e-12 {
        return;
    }
    let xs = [p[0][0], p[1][0], p[2][0]];
    let ys = [p[0][1], p[1][1], p[2][1]];
    let x0 = xs.iter().copied().fold(f32::MAX, f32::min).floor().max(0.0);
    let x1 = xs
        .iter()
        .copied()
        .fold(f32::MIN, f32::max)
        .ceil()
        .min(fr.w as f32);
    let y0 = ys.iter().copied().fold(f32::MAX, f32::min).floor().max(0.0);
    let y1 = ys
        .iter()
        .copied()
        .fold(f32::MIN, f32::max)
        .ceil()
        .min(fr.h as f32);
    if !(x0 < x1 && y0 < y1) {
        return;
    }
    let inv = 1.0 / area;
    let mut lit: Option<[Vec3; 3]> = None;
    for y in y0 as usize..y1 as usize {
        let py = y as f32 + 0.5;
        for x in x0 as usize..x1 as usize {
            let px = x as f32 + 0.5;
            let w0 = edge(p[1], p[2], px, py) * inv;
            let w1 = edge(p[2], p[0], px, py) * inv;
            let w2 = 1.0 - w0 - w1;
            if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                continue;
            }
            let key = w0 * p[0][2] + w1 * p[1][2] + w2 * p[2][2];
            let k = y * fr.w + x;
            if key > fr.depth[k] {
                fr.depth[k] = key;
                let c = *lit.get_or_insert_with(|| {
                    [
                        shade(idx[0], n[0]),
                        shade(idx[1], n[1]),
                        shade(idx[2], n[2]),
                    ]
                });
                fr.colour[k] = c[0] * w0 + c[1] * w1 + c[2] * w2;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshParams;
    use crate::{Derivation, LSystem, Turtle, TurtleParams};

    fn tree() -> PlantMesh {
        let l = LSystem::parse("axiom: F[+F~L(0.5,0.2)][-F]F").unwrap();
        let mut d = Derivation::new(&l, 0).unwrap();
        d.derive(0).unwrap();
        let t = Turtle::new(
            &l,
            TurtleParams {
                angle_deg: 30.0,
                ..TurtleParams::default()
            },
        )
        .unwrap();
        let g = t.interpret(d.string()).unwrap();
        PlantMesh::from_geometry(&g, &MeshParams::default()).unwrap()
    }

    #[test]
    fn draws_the_plant_and_is_deterministic() {
        let m = tree();
        let (lo, hi) = m.bounds().unwrap();
        for fov in [None, Some(40.0)] {
            let cam = PreviewCamera::framing(lo, hi, Vec3::Y, fov, 1.0).unwrap();
            let p = PreviewParams::new(64, 64, cam);
            let a = render(&m, &p).unwrap();
            let b = render(&m, &p).unwrap();
            assert_eq!(a.to_srgb8(), b.to_srgb8());
            let bg = p.background;
            let covered = a.pixels().as_slice().iter().filter(|&&c| c != bg).count();
            assert!(covered > 40 && covered < 64 * 64 / 2, "{covered}");
            // The framed plant touches neither edge column (margin) but spans the middle.
            assert!((0..64).all(|y| a.get(0, y) == Some(bg)));
        }
    }

    #[test]
    fn nearer_surface_wins() {
        // Two squares facing the camera at different depths, the far one drawn last.
        let quad = |z: f32| {
            let mut m = PlantMesh::default();
            for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                m.positions.push(Vec3::new(x, y, z));
                m.normals.push(Vec3::Z);
                m.uvs.push(glam::Vec2::ZERO);
                m.wind.push(0.0);
            }
            m.indices = vec![0, 1, 2, 0, 2, 3];
            m
        };
        let (mut near, mut far) = (quad(1.0), quad(0.0));
        near.primitives = vec![crate::mesh::Primitive {
            material: Material::Leaf,
            first: 0,
            count: 6,
        }];
        far.primitives = vec![crate::mesh::Primitive {
            material: Material::Bark,
            first: 0,
            count: 6,
        }];
        let cam = PreviewCamera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: PreviewProjection::Orthographic { height: 4.0 },
        };
        let mut p = PreviewParams::new(8, 8, cam);
        p.light = Vec3::Z;
        p.ambient = 0.0;
        let one = [Instance::default()];
        let img = render_instances(&[(&near, &one), (&far, &one)], &p).unwrap();
        let c = img.get(4, 4).unwrap();
        assert!((c - p.leaf).length() < 1e-6, "{c}");
    }

    #[test]
    fn bad_parameters_are_errors() {
        let m = tree();
        let (lo, hi) = m.bounds().unwrap();
        let cam = PreviewCamera::framing(lo, hi, Vec3::Y, None, 1.0).unwrap();
        let mut p = PreviewParams::new(0, 8, cam);
        assert!(render(&m, &p).is_err());
        p.width = 8;
        p.light = Vec3::ZERO;
        assert!(render(&m, &p).is_err());
        p.light = Vec3::Z;
        p.camera.up = p.camera.target - p.camera.eye;
        assert!(render(&m, &p).is_err());
        assert!(PreviewCamera::framing(lo, hi, Vec3::NAN, None, 1.0).is_err());
        assert!(PreviewCamera::framing(lo, hi, Vec3::Y, Some(180.0), 1.0).is_err());
    }
}
