//! Fedkiw, Stam & Jensen 2001, Figs. 4–5: smoke rising past objects and
//! round a ball, rendered with the objects stopping the eye's and the
//! light's rays.

use natura::core::glam::{Quat, Vec3};
use natura::core::{Grid3, Image};
use natura::fluid::export::render_smoke_volume_with_solids;
use natura::fluid::grid::Dims;
use natura::fluid::shape::{Obstacle, Shape};
use natura::fluid::smoke::{Smoke, SmokeParams, SmokeSource};

use crate::{R, cubic_advection, sheet};

/// Fig. 4's scene (the source gives its grid, 160 × 80 × 80, and "low
/// albedo"; the rest is ours): a 2 × 1 × 1 m box, `n` cells along x, walls
/// and an open ceiling; three warm sources on the floor (0.24 m square,
/// 0.12 m deep, 30 K above ambient) send smoke up past a ball, a box turned
/// 30° about the vertical and a tilted slab, one above each.
pub(crate) fn objects_smoke(n: usize) -> R<Smoke> {
    let sources = [0.45f32, 1.0, 1.55].map(|x| Shape::Cuboid {
        min: Vec3::new(x - 0.12, 0.38, 0.0),
        max: Vec3::new(x + 0.12, 0.62, 0.12),
    });
    warm_smoke(
        Dims::new(n, n / 2, n / 2)?,
        2.0 / n as f32,
        &sources,
        &objects_shapes(),
    )
}

fn objects_shapes() -> [Shape; 3] {
    [
        Shape::Sphere {
            centre: Vec3::new(0.5, 0.5, 0.42),
            radius: 0.14,
        },
        Shape::OrientedBox {
            centre: Vec3::new(1.0, 0.5, 0.62),
            half: Vec3::new(0.1, 0.14, 0.1),
            rotation: Quat::from_rotation_z(30f32.to_radians()),
        },
        Shape::OrientedBox {
            centre: Vec3::new(1.5, 0.5, 0.36),
            half: Vec3::new(0.18, 0.2, 0.025),
            rotation: Quat::from_rotation_y(-25f32.to_radians()),
        },
    ]
}

/// Fig. 5's scene (the source's grid is 90 × 135 × 90, the second its
/// height): a 1 × 1 × 1.5 m box, `n` cells across, a warm source 0.3 m
/// square on the floor's centre (30 K above ambient) and a ball 0.3 m across
/// whose centre is 0.7 m up; walls and an open ceiling.
pub(crate) fn sphere_smoke(n: usize) -> R<Smoke> {
    let source = Shape::Cuboid {
        min: Vec3::new(0.35, 0.35, 0.0),
        max: Vec3::new(0.65, 0.65, 0.08),
    };
    warm_smoke(
        Dims::new(n, n, 3 * n / 2)?,
        1.0 / n as f32,
        &[source],
        &[sphere_shape()],
    )
}

/// Smoke of the default parameters with monotone cubic advection in a box
/// of `dims` cells of `h` m: warm `sources` (density 1, 30 K above
/// ambient) and fixed `obstacles`.
fn warm_smoke(dims: Dims, h: f32, sources: &[Shape], obstacles: &[Shape]) -> R<Smoke> {
    let params = SmokeParams {
        advection: cubic_advection(),
        ..SmokeParams::default()
    };
    let warm = params.ambient_temperature + 30.0;
    let mut smoke = Smoke::new(dims, h, params)?;
    for &shape in sources {
        smoke.add_source(SmokeSource {
            shape,
            density: 1.0,
            temperature: warm,
            velocity: None,
        })?;
    }
    for &shape in obstacles {
        smoke.add_obstacle(Obstacle::fixed(shape))?;
    }
    Ok(smoke)
}

fn sphere_shape() -> Shape {
    Shape::Sphere {
        centre: Vec3::new(0.5, 0.5, 0.7),
        radius: 0.15,
    }
}

/// The cells whose centres lie inside any of `shapes`.
fn solid_cells(dims: (usize, usize, usize), h: f32, shapes: &[Shape]) -> R<Grid3<bool>> {
    Ok(Grid3::from_fn(dims.0, dims.1, dims.2, |i, j, k| {
        let p = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * h;
        shapes.iter().any(|s| s.sdf(p) < 0.0)
    })?)
}

/// Frames of `smoke` every `every` of `steps` steps of `dt`, seen along y
/// with `solids` drawn in clay.
#[allow(clippy::too_many_arguments)]
fn solid_frames(
    smoke: &mut Smoke,
    solids: &Grid3<bool>,
    steps: usize,
    every: usize,
    dt: f32,
    extinction: f32,
    albedo: f32,
    light: Vec3,
) -> R<Vec<Image>> {
    let h = smoke.h();
    let mut frames = Vec::new();
    for s in 1..=steps {
        smoke.step(dt)?;
        if s % every == 0 {
            frames.push(render_smoke_volume_with_solids(
                smoke.density(),
                solids,
                Vec3::new(0.62, 0.42, 0.30),
                h,
                extinction,
                albedo,
                light,
                1,
                Vec3::new(0.55, 0.62, 0.72),
            )?);
        }
    }
    Ok(frames)
}

/// Fig. 4: the smoke rising past the three objects at four times, from the
/// side, dark (albedo 0.3) as the caption has it.
pub(crate) fn objects(quick: bool) -> R<Image> {
    let n = if quick { 32 } else { 96 };
    let mut smoke = objects_smoke(n)?;
    let solids = solid_cells(smoke.density().dims(), smoke.h(), &objects_shapes())?;
    let (steps, every) = if quick { (30, 15) } else { (240, 60) };
    let light = Vec3::new(-0.3, -0.5, 1.0).normalize();
    let frames = solid_frames(&mut smoke, &solids, steps, every, 0.02, 12.0, 0.3, light)?;
    sheet(&frames, 3, 2)
}

/// Fig. 5: the plume rising around the ball at four times, from the side.
pub(crate) fn sphere(quick: bool) -> R<Image> {
    let n = if quick { 24 } else { 80 };
    let mut smoke = sphere_smoke(n)?;
    let solids = solid_cells(smoke.density().dims(), smoke.h(), &[sphere_shape()])?;
    let (steps, every) = if quick { (30, 15) } else { (200, 50) };
    let light = Vec3::new(-0.5, -0.4, 1.0).normalize();
    let frames = solid_frames(&mut smoke, &solids, steps, every, 0.02, 16.0, 0.9, light)?;
    sheet(&frames, if quick { 4 } else { 2 }, frames.len())
}
