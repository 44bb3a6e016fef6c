//! Plants drawn over the field they grow in, as Měch & Prusinkiewicz 1996
//! draw them: the roots of Fig. 9 over the soil's water in their vertical
//! section, the roots of Fig. 10 in their block of soil among
//! semi-transparent iso-surfaces of its water, and the clone of Fig. 7
//! over the three patches of light at three stages of its growth. The
//! fields are the models' own rasters (natura-plant's `SoilWater`,
//! `SoilWater3` and `LightPatches`) after the run, so the water the roots
//! took and the ground the ramets shade show as they are.

use natura::core::glam::{DVec3, Vec3};
use natura::core::preview::{PixelRays, PreviewCamera, Projector, Raster, facing, lambert};
use natura::core::{Boundary, Grid3, Image, NoProgress};
use natura::plant::models::{clonal, roots, roots3d};
use natura::plant::preview::PreviewParams;
use natura::plant::{Geometry, MeshParams, PlantMesh};

use crate::common::plot::{Canvas, Panel, Pen};

/// Soil with no water (linear RGB): a pale dry loam.
const DRY: Vec3 = Vec3::new(0.62, 0.47, 0.30);
/// Soil at [`WET_WATER`] and above: dark, blue-grey wet soil.
const WET: Vec3 = Vec3::new(0.05, 0.12, 0.30);
/// Water per cell drawn as fully wet (the wettest patch of the default
/// soil holds 6).
const WET_WATER: f64 = 6.0;
/// The roots' colour (linear RGB): pale, as the source draws them.
const ROOT: Vec3 = Vec3::new(0.95, 0.92, 0.82);

/// Ground in no light and in full light (linear RGB): the clone's patches
/// from shade to sun.
const SHADE: Vec3 = Vec3::new(0.10, 0.09, 0.07);
const SUN: Vec3 = Vec3::new(0.85, 0.80, 0.55);
/// Spacers (stolons) and live ramets (linear RGB).
const SPACER: Vec3 = Vec3::new(0.35, 0.20, 0.10);
const RAMET: Vec3 = Vec3::new(0.05, 0.40, 0.06);
/// Ramets that were born and have died.
const DEAD: Vec3 = Vec3::new(0.45, 0.40, 0.35);

/// The `[x0, x1, y0, y1]` extent of a raster of `nx × ny` cells of side
/// `cell` whose lower corner is `origin`.
fn extent(origin: [f64; 2], cell: f64, nx: usize, ny: usize) -> [f64; 4] {
    [
        origin[0],
        origin[0] + nx as f64 * cell,
        origin[1],
        origin[1] + ny as f64 * cell,
    ]
}

/// A canvas `width` pixels wide showing the data rectangle `range` at one
/// scale in x and y, its paper the raster `value` (row by row from the
/// bottom, `nx` a row, cells of side `cell` from `range`'s lower corner)
/// coloured by `colour`; each pixel the cell under its centre, so the
/// model's cells show as they are.
fn raster_canvas(
    width: usize,
    range: [f64; 4],
    cell: f64,
    (nx, ny): (usize, usize),
    value: &[f64],
    colour: impl Fn(f64) -> Vec3,
) -> (Canvas, Panel) {
    let per_px = (range[1] - range[0]) / width as f64;
    let height = ((range[3] - range[2]) / per_px).round().max(1.0) as usize;
    let canvas = Canvas::with_paper(width, height, |x, y| {
        let fx = range[0] + (x as f64 + 0.5) * per_px;
        let fy = range[3] - (y as f64 + 0.5) * per_px;
        let i = (((fx - range[0]) / cell).floor() as usize).min(nx - 1);
        let j = (((fy - range[2]) / cell).floor() as usize).min(ny - 1);
        colour(value[j * nx + i])
    });
    let panel = Panel::new([0.0, 0.0, width as f32, height as f32], range);
    (canvas, panel)
}

/// Draws the segments of `g` projected on the plane of axes `(a, b)`
/// (0 = x, 1 = y, 2 = z), at least `min_px` wide or their own width.
fn segments(canvas: &mut Canvas, panel: &Panel, g: &Geometry, (a, b): (usize, usize), pen: Pen) {
    let scale = f64::from(panel.rect[2] - panel.rect[0]) / (panel.range[1] - panel.range[0]);
    for k in 0..g.segment_count() {
        let (s, e) = (g.start[k], g.end[k]);
        let w = (f64::from(g.width0[k]) * scale) as f32;
        let pts = [
            (f64::from(s[a]), f64::from(s[b])),
            (f64::from(e[a]), f64::from(e[b])),
        ];
        canvas.line(
            panel,
            &pts,
            Pen {
                width: w.max(pen.width),
                ..pen
            },
        );
    }
}

/// Fig. 9: the roots of `run` over the water left in `soil`, the section
/// `width` pixels wide.
///
/// # Errors
///
/// Turtle errors of the run's geometry; natura-core's error if the image
/// cannot be allocated.
pub fn roots_on_water(
    run: &natura::plant::models::Run,
    soil: &roots::SoilWater,
    width: usize,
) -> Result<Image, crate::common::Exit> {
    let range = extent(soil.origin, soil.cell, soil.nx, soil.nz);
    let (mut canvas, panel) = raster_canvas(
        width,
        range,
        soil.cell,
        (soil.nx, soil.nz),
        &soil.water,
        |w| {
            let t = (w / WET_WATER).clamp(0.0, 1.0).sqrt() as f32;
            DRY.lerp(WET, t)
        },
    );
    segments(
        &mut canvas,
        &panel,
        &run.geometry()?,
        (0, 2),
        Pen::solid(ROOT, 1.2),
    );
    Ok(canvas.into_image()?)
}

/// Fig. 7: the clone of `p` after each of `stages` derivation steps, over
/// its patches of light, side by side, each panel `width` pixels wide:
/// spacers as lines, live ramets as discs of the radius they shade, dead
/// ones as rings.
///
/// # Errors
///
/// The errors of [`clonal::clonal`]; natura-core's error if the image
/// cannot be allocated.
pub fn clone_on_patches(
    p: &clonal::ClonalParams,
    stages: &[u32],
    width: usize,
) -> Result<Image, crate::common::Exit> {
    let mut panels = Vec::new();
    for &steps in stages {
        let (run, ground) = clonal::clonal(&clonal::ClonalParams { steps, ..p.clone() })?;
        let range = extent(ground.origin, ground.cell, ground.nx, ground.ny);
        let (mut canvas, panel) = raster_canvas(
            width,
            range,
            ground.cell,
            (ground.nx, ground.ny),
            &ground.light,
            |l| SHADE.lerp(SUN, l.clamp(0.0, 1.0) as f32),
        );
        segments(
            &mut canvas,
            &panel,
            &run.geometry()?,
            (0, 1),
            Pen::solid(SPACER, 1.0),
        );
        let scale = f64::from(panel.rect[2] - panel.rect[0]) / (range[1] - range[0]);
        let alive = |c: natura::core::glam::DVec3, r: f64| {
            ground
                .live
                .iter()
                .any(|&(l, lr)| l.distance(c) < 1e-9 && (lr - r).abs() < 1e-12)
        };
        for &(c, r) in &ground.born {
            if !alive(c, r) {
                let ring: Vec<(f64, f64)> = (0..=32)
                    .map(|k| {
                        let a = std::f64::consts::TAU * f64::from(k) / 32.0;
                        (c.x + r * a.cos(), c.y + r * a.sin())
                    })
                    .collect();
                canvas.line(&panel, &ring, Pen::solid(DEAD, 1.0));
            }
        }
        for &(c, r) in &ground.live {
            canvas.dots(&panel, &[(c.x, c.y)], RAMET, (r * scale) as f32);
        }
        panels.push(canvas);
    }
    // The stages side by side, a white gap of 8 pixels between them.
    let gap = 8;
    let (pw, ph) = panels.first().map_or((1, 1), Canvas::size);
    let n = panels.len().max(1);
    let w = n * pw + (n - 1) * gap;
    Ok(Image::from_fn(w, ph, |x, y| {
        let (k, x) = (x / (pw + gap), x % (pw + gap));
        if x < pw {
            panels[k].get(x, y)
        } else {
            Vec3::ONE
        }
    })?)
}

/// The levels of Fig. 10's iso-surfaces of the water the roots took, as
/// shares of the water a cell would hold without them, and each shell's
/// colour (linear RGB): outermost (least taken) blue, innermost (driest)
/// sand.
pub const SHELLS: [(f32, Vec3); 3] = [
    (0.02, Vec3::new(0.20, 0.42, 0.90)),
    (0.1, Vec3::new(0.50, 0.72, 0.95)),
    (0.4, Vec3::new(0.90, 0.78, 0.55)),
];
/// The opacity of one shell where the view meets it head-on; a shell seen
/// edge-on is more opaque, as a thin film is.
const SHELL_ALPHA: f32 = 0.25;
/// The block's background: dark soil, so the pale roots and the shells read.
const SOIL_DARK: Vec3 = Vec3::new(0.035, 0.03, 0.025);
/// Samples per pixel along each axis.
const BLOCK_SUPERSAMPLE: u32 = 2;
/// Soil shown around the roots' bounding box, in cells.
const BLOCK_MARGIN_CELLS: f32 = 12.0;

/// Fig. 10: the roots of the run `run` of `p` in their block of soil,
/// seen along `view`, with semi-transparent iso-surfaces of the water the
/// roots took, in a `size × size` picture. The water taken is the share of
/// the water of the same soil diffused for the same steps without roots
/// that `soil` no longer holds after the run, so the shells surround the roots and not
/// the borders of the painted patches, which diffusion alone moves. The
/// roots are drawn opaque by natura-core's rasterizer; along each sample's
/// ray the shells in front of them are found where the trilinear field
/// crosses a level, lit by the field's gradient and laid over, nearest
/// last.
///
/// # Errors
///
/// The soil's errors ([`roots3d::SoilWater3::new`]); turtle and mesh
/// errors of the run's geometry; natura-core's errors if the camera or the
/// picture cannot be made.
pub fn roots_in_block(
    run: &natura::plant::models::Run,
    p: &roots3d::Roots3dParams,
    soil: &roots3d::SoilWater3,
    size: u32,
    view: Vec3,
) -> Result<Image, crate::common::Exit> {
    let [nx, ny, nz] = soil.n;
    let taken = Grid3::from_vec(nx, ny, nz, water_taken(p, soil)?)?;
    let origin = DVec3::from(soil.origin).as_vec3();
    let cell = soil.cell as f32;
    let top = origin + Vec3::new(nx as f32, ny as f32, nz as f32) * cell;

    let mesh = PlantMesh::from_geometry(&run.geometry()?, &MeshParams::default())?;
    let (rlo, rhi) = mesh.bounds().unwrap_or((origin, top));
    let margin = Vec3::splat(BLOCK_MARGIN_CELLS * cell);
    let (lo, hi) = ((rlo - margin).max(origin), (rhi + margin).min(top));
    let camera = PreviewCamera::framing(lo, hi, view, None, 1.0)?;
    let look = PreviewParams::new(size, size, camera);
    let light = look.light.normalize();

    // The roots, opaque, into a frame of samples with their depth keys.
    let s = BLOCK_SUPERSAMPLE;
    let mut raster = Raster::new(size, size, s, SOIL_DARK)?;
    let (sw, sh) = raster.samples();
    let proj = Projector::new(&camera, sw, sh)?;
    for t in mesh.indices.chunks_exact(3) {
        let k = [t[0] as usize, t[1] as usize, t[2] as usize];
        let p = k.map(|i| mesh.positions[i]);
        let (Some(a), Some(b), Some(c)) =
            (proj.project(p[0]), proj.project(p[1]), proj.project(p[2]))
        else {
            continue;
        };
        let n = k.map(|i| mesh.normals[i]);
        raster.triangle([a, b, c], |f| {
            let at = f.mix(p);
            let normal = f.mix(n).normalize_or(Vec3::Z);
            ROOT * lambert(facing(normal, proj.to_viewer(at)), light, look.ambient)
        })?;
    }

    // The share of water taken at a point (cell centres are the samples).
    let field = |q: Vec3| {
        let u = (q - origin) / cell - 0.5;
        taken.sample_trilinear(u.x, u.y, u.z, Boundary::Clamp)
    };
    let h = 0.5 * cell;
    let gradient = |q: Vec3| {
        Vec3::new(
            field(q + Vec3::X * h) - field(q - Vec3::X * h),
            field(q + Vec3::Y * h) - field(q - Vec3::Y * h),
            field(q + Vec3::Z * h) - field(q - Vec3::Z * h),
        )
    };
    let step = 0.25 * cell;
    let ss = f64::from(s);
    let img =
        natura::core::preview::shade_pixels(size, size, s, "roots3d", &NoProgress, |px, py| {
            let (ix, iy) = ((px * ss) as usize, (py * ss) as usize);
            let (behind, key) = raster
                .sample(ix, iy)
                .unwrap_or((SOIL_DARK, f32::NEG_INFINITY));
            let ray = proj.ray_at((px * ss) as f32, (py * ss) as f32);
            let Some((t0, t1)) = slab(ray.origin, ray.dir, lo, hi) else {
                return behind;
            };
            // The shells crossed in front of the roots, nearest first.
            let mut layers = Vec::new();
            let mut t = t0;
            let mut prev = field(ray.origin + ray.dir * t);
            while t < t1 {
                let t_next = (t + step).min(t1);
                let q = ray.origin + ray.dir * t_next;
                if proj.depth_key(q) < key {
                    break;
                }
                let w = field(q);
                for &(level, colour) in &SHELLS {
                    if (prev - level) * (w - level) < 0.0 {
                        let f = (level - prev) / (w - prev);
                        let at = ray.origin + ray.dir * (t + f * (t_next - t));
                        let normal = facing(gradient(at).normalize_or(Vec3::Z), -ray.dir);
                        let head_on = normal.dot(-ray.dir).clamp(0.2, 1.0);
                        let alpha = 1.0 - (1.0 - SHELL_ALPHA).powf(1.0 / head_on);
                        layers.push((colour * lambert(normal, light, look.ambient), alpha));
                    }
                }
                prev = w;
                t = t_next;
            }
            layers
                .iter()
                .rev()
                .fold(behind, |c, &(shell, alpha)| c.lerp(shell, alpha))
        })?;
    Ok(img)
}

/// Where Fig. 10's two root systems start: 8 apart across the section (in
/// `y`), in the same water.
pub const TWO_SYSTEMS: [[f64; 2]; 2] = [[0.0, -4.0], [0.0, 4.0]];

/// The rootlets' elongation rates of Fig. 10's right panel (orders 1 and
/// 2; the main axes' as the default): a third and two fifths of the
/// default's.
pub const SLOW_ROOTLETS: [f64; 3] = [0.55, 0.08, 0.22];

/// Fig. 10: two root systems ([`TWO_SYSTEMS`]) grown by `p` in one block,
/// among iso-surfaces of the water they took ([`roots_in_block`]), with
/// the default rootlets (left) and with slower ones ([`SLOW_ROOTLETS`],
/// right), each panel `size` square, 8 white pixels between them.
///
/// # Errors
///
/// [`roots_in_block`]'s and the model's errors.
pub fn competing_roots(
    p: &roots3d::Roots3dParams,
    size: u32,
) -> Result<Image, crate::common::Exit> {
    let view = Vec3::new(0.5, 1.0, -0.3);
    let mut panels = Vec::new();
    for elongation in [p.roots.elongation, SLOW_ROOTLETS] {
        let q = roots3d::Roots3dParams {
            roots: roots::RootParams {
                elongation,
                ..p.roots.clone()
            },
            systems: TWO_SYSTEMS.to_vec(),
            ..p.clone()
        };
        let (run, soil) = roots3d::roots_3d(&q)?;
        panels.push(roots_in_block(&run, &q, &soil, size, view)?);
    }
    let gap = 8;
    let s = size as usize;
    Ok(Image::from_fn(2 * s + gap, s, |x, y| {
        if x < s {
            panels[0].get(x, y)
        } else if x >= s + gap {
            panels[1].get(x - s - gap, y)
        } else {
            None
        }
        .unwrap_or(Vec3::ONE)
    })?)
}

/// The share of its water each cell of `soil`, after a run of `p`, lost
/// to the roots: `1 − w / b`, `w` its water and `b` the water of the same
/// soil diffused for the same steps without roots (one diffusion a step and
/// one before the first, as the run's environment), 0 where `b` is 0.
///
/// # Errors
///
/// [`roots3d::SoilWater3::new`]'s errors for `p`.
pub fn water_taken(
    p: &roots3d::Roots3dParams,
    soil: &roots3d::SoilWater3,
) -> natura::plant::Result<Vec<f32>> {
    let mut bare = roots3d::SoilWater3::new(p)?;
    for _ in 0..=p.roots.steps {
        bare.diffuse();
    }
    Ok(bare
        .water
        .iter()
        .zip(&soil.water)
        .map(|(&b, &w)| if b > 0.0 { ((b - w) / b) as f32 } else { 0.0 })
        .collect())
}

/// The parameter interval `(t0, t1)` over which the ray `o + t·d` (t ≥ 0)
/// is inside the box `lo..hi`, or `None` if it misses it.
fn slab(o: Vec3, d: Vec3, lo: Vec3, hi: Vec3) -> Option<(f32, f32)> {
    let inv = d.recip();
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let t0 = a.min(b).max_element().max(0.0);
    let t1 = a.max(b).min_element();
    (t0 < t1).then_some((t0, t1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_water_taken_is_the_roots_and_nothing_else() {
        // Counted against the soil diffused for the run's steps, the water
        // taken is none far from the roots, where the painted patches'
        // borders still diffuse (a diffusion step more or less would show
        // there), and most of a cell's water beside a growing apex.
        let p = roots3d::Roots3dParams {
            roots: roots::RootParams {
                steps: 60,
                ..roots3d::Roots3dParams::default().roots
            },
            breadth: 40.0,
            ..roots3d::Roots3dParams::default()
        };
        let (run, soil) = roots3d::roots_3d(&p).unwrap();
        let taken = water_taken(&p, &soil).unwrap();
        let g = run.geometry().unwrap();
        let [nx, ny, _] = soil.n;
        let centre = |c: usize| {
            let (i, j, k) = (c % nx, (c / nx) % ny, c / (nx * ny));
            DVec3::new(
                soil.origin[0] + (i as f64 + 0.5) * soil.cell,
                soil.origin[1] + (j as f64 + 0.5) * soil.cell,
                soil.origin[2] + (k as f64 + 0.5) * soil.cell,
            )
        };
        let near = |q: DVec3| {
            g.end
                .iter()
                .map(|e| e.as_dvec3().distance(q))
                .fold(f64::INFINITY, f64::min)
        };
        let (mut far, mut most) = (0.0f32, 0.0f32);
        for (c, &t) in taken.iter().enumerate() {
            most = most.max(t);
            if near(centre(c)) > 12.0 * soil.cell {
                far = far.max(t.abs());
            }
        }
        assert!(far < 1e-4, "taken far from the roots: {far}");
        assert!(most > 0.3, "most taken beside the roots: {most}");
        assert!(soil.taken > 0.0);
    }
}
