//! Pictures of plant meshes, drawn by natura-core's preview rasterizer
//! ([`natura_core::preview`]).
//!
//! Triangles are projected by an orthographic or perspective [`PreviewCamera`]
//! (natura-core's, re-exported here, with its framing of a bounding box),
//! filled with edge functions at sample centres, resolved with a z-buffer and
//! shaded with Lambert's law plus an ambient term, using the vertex normals
//! turned towards the viewer (every surface is lit on both sides) and the
//! vertex colours interpolated across the triangle. Supersampling (a box
//! filter over `s × s` samples per pixel) smooths edges. The rasterizer is
//! single-threaded and uses no randomness, so the same mesh and parameters
//! always give the same image. The result is a linear-light [`Image`];
//! `Image::to_srgb8` gives the RGB8 bytes and `Image::save_png` writes them
//! (atomically).
//!
//! Triangles with a vertex closer to a perspective camera than its near
//! plane, or behind an orthographic camera's screen, are skipped rather than
//! clipped (a preview frames the whole plant).

use crate::error::Result;
use crate::mesh::{Instance, Material, PlantMesh, invalid};
use glam::Vec3;
use natura_core::Image;
use natura_core::preview::{Projector, Raster, facing, lambert};

pub use natura_core::preview::{PreviewCamera, PreviewProjection};

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
        Ok(self.camera.validate()?)
    }
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
/// refuses the view (a field of view that rounds to 180°) or the
/// supersampled frame is too large to allocate.
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
    let s = params.supersample;
    let mut frame = Raster::new(params.width, params.height, s, params.background)?;
    let (w, h) = frame.samples();
    let view = Projector::new(&params.camera, w, h)?;
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
                // Lit vertex colours, computed once a sample of the triangle is drawn.
                let lit = |k: usize| {
                    let n = facing(normals[k], view.to_viewer(world[k]));
                    base * lambert(n, light, params.ambient)
                };
                let r = prim.first as usize..(prim.first + prim.count) as usize;
                for t in m.indices[r].chunks_exact(3) {
                    let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
                    if let (Some(pa), Some(pb), Some(pc)) = (screen[a], screen[b], screen[c]) {
                        let mut colours = None;
                        frame.triangle([pa, pb, pc], |f| {
                            f.mix(*colours.get_or_insert_with(|| [lit(a), lit(b), lit(c)]))
                        })?;
                    }
                }
            }
        }
    }
    Ok(frame.resolve()?)
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
