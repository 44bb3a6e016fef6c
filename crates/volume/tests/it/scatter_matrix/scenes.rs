//! The scene matrix's scenes (shapes, phases, suns, skies, cameras and
//! settings), its renders and its error measures against the reference.

use glam::Vec3;
use natura_core::{Aabb, Grid3};
use natura_volume::Density;
use natura_volume::density::{Ball, Homogeneous, ray_box};
use natura_volume::grid::GridDensity;
use natura_volume::phase::CloudPhase;
use natura_volume::transport::{
    FastRenderer, FastSettings, LookAtCamera, MediumParams, ReferenceRenderer, ReferenceSettings,
    Scene, Shadows, Sun,
};

/// The shapes of the matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A ball of radius 1 m; its thickness is the diameter.
    Ball,
    /// A 4 × 4 × 1 m slab; its thickness is the vertical one.
    Slab,
    /// A 2 m voxel blob (a soft ball with lumps); its thickness is the
    /// optical depth across its centre.
    Blob,
}

/// Where the sun stands, seen from the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SunAt {
    /// Behind the viewer, 30° up (back-scattering).
    Behind,
    /// To the right, 30° up (side-scattering).
    Beside,
    /// Ahead, 30° up, behind the volume (forward scattering, backlit).
    Ahead,
}

/// What lights a scene besides the sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sky {
    /// Nothing: a black sky.
    Black,
    /// A uniform blue sky of radiance [`SKY`] from every direction.
    Blue,
}

/// The uniform sky's radiance (luminance about 0.06: a horizontal
/// surface receives about a sixth of the sun's irradiance from it, as
/// under a clear sky).
pub const SKY: Vec3 = Vec3::new(0.04, 0.06, 0.10);

/// One scene of the matrix.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    pub shape: Shape,
    pub phase: CloudPhase,
    pub sun: SunAt,
    pub sky: Sky,
    pub albedo: f32,
    /// Optical thickness (see [`Shape`]).
    pub tau: f32,
}

pub const PHASES: [CloudPhase; 7] = [
    CloudPhase::HenyeyGreenstein(0.0),
    CloudPhase::HenyeyGreenstein(0.3),
    CloudPhase::HenyeyGreenstein(0.6),
    CloudPhase::HenyeyGreenstein(0.8),
    CloudPhase::HenyeyGreenstein(-0.3),
    CloudPhase::Cloud { diameter_um: 5.0 },
    CloudPhase::Cloud { diameter_um: 20.0 },
];
pub const ALBEDOS: [f32; 4] = [0.8, 0.95, 0.99, 0.999];
pub const TAUS: [f32; 6] = [0.3, 1.0, 3.0, 8.0, 20.0, 50.0];

pub fn phase_name(p: &CloudPhase) -> String {
    match p {
        CloudPhase::HenyeyGreenstein(g) => format!("HG {g:+.1}"),
        CloudPhase::Cloud { diameter_um } => format!("cloud {diameter_um} µm"),
        other => format!("{other:?}"),
    }
}

/// Every scene: shapes × phases × suns (63), the albedo and the thickness
/// spread over them by two co-prime strides, so each phase meets several
/// of each; each under the black sky and under the blue one (126).
pub fn full_matrix() -> Vec<Case> {
    let mut out = Vec::new();
    for sky in [Sky::Black, Sky::Blue] {
        let mut k = 0usize;
        for shape in [Shape::Ball, Shape::Slab, Shape::Blob] {
            for phase in PHASES {
                for sun in [SunAt::Behind, SunAt::Beside, SunAt::Ahead] {
                    out.push(Case {
                        shape,
                        phase,
                        sun,
                        sky,
                        albedo: ALBEDOS[(k * 3) % ALBEDOS.len()],
                        tau: TAUS[(k * 5 + k / 7) % TAUS.len()],
                    });
                    k += 1;
                }
            }
        }
    }
    out
}

/// A few scenes for the test run: one per phase family, thin to moderate,
/// and a thick HG 0.8 ball under the blue sky.
pub fn reduced_matrix() -> Vec<Case> {
    let c = |shape, phase, sun, sky, albedo, tau| Case {
        shape,
        phase,
        sun,
        sky,
        albedo,
        tau,
    };
    vec![
        c(Shape::Ball, PHASES[0], SunAt::Beside, Sky::Black, 0.99, 4.0),
        c(Shape::Ball, PHASES[2], SunAt::Ahead, Sky::Black, 0.95, 3.0),
        c(Shape::Slab, PHASES[3], SunAt::Behind, Sky::Black, 0.99, 2.0),
        c(
            Shape::Blob,
            PHASES[6],
            SunAt::Beside,
            Sky::Black,
            0.999,
            4.0,
        ),
        c(Shape::Ball, PHASES[4], SunAt::Behind, Sky::Black, 0.8, 1.0),
        c(Shape::Ball, PHASES[3], SunAt::Beside, Sky::Blue, 0.99, 8.0),
    ]
}

/// The voxel blob: a soft ball of radius 1 m on a 24³ grid, with lumps
/// from a sum of sines; its maximum density is about 1.
pub fn blob() -> GridDensity {
    let n = 24usize;
    let cell = 2.2 / n as f32;
    let origin = Vec3::splat(-1.1);
    let mut g = Grid3::new(n, n, n, 0.0f32).unwrap();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = origin + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * cell;
                let r2 = p.length_squared();
                let lumps = 0.75
                    + 0.25 * (5.0 * p.x + 1.0).sin() * (4.0 * p.y + 2.0).sin() * (6.0 * p.z).cos();
                g.as_mut_slice()[(z * n + y) * n + x] = ((1.0 - r2).max(0.0) * lumps).min(1.0);
            }
        }
    }
    GridDensity::new(g, origin, cell).unwrap()
}

/// The density of a case, at unit scale (its extinction sets the thickness).
pub fn density(shape: Shape) -> Box<dyn Density> {
    match shape {
        Shape::Ball => Box::new(Ball::new(Vec3::ZERO, 1.0, 1.0).unwrap()),
        Shape::Slab => Box::new(
            Homogeneous::new(
                Aabb {
                    min: Vec3::new(-2.0, -2.0, -0.5),
                    max: Vec3::new(2.0, 2.0, 0.5),
                },
                1.0,
            )
            .unwrap(),
        ),
        Shape::Blob => Box::new(blob()),
    }
}

/// The density's column (∫ρ ds) along its thickness.
pub fn column(shape: Shape, d: &dyn Density) -> f32 {
    match shape {
        Shape::Ball => 2.0,
        Shape::Slab => 1.0,
        Shape::Blob => {
            let n = 2000;
            (0..n)
                .map(|i| {
                    d.density(Vec3::new(
                        -1.1 + 2.2 * (i as f32 + 0.5) / n as f32,
                        0.0,
                        0.0,
                    ))
                })
                .sum::<f32>()
                * 2.2
                / n as f32
        }
    }
}

pub fn sun_of(at: SunAt) -> Sun {
    // The camera looks along +y.
    let (e, a) = (
        30f32.to_radians(),
        match at {
            SunAt::Behind => 180f32,
            SunAt::Beside => 90.0,
            SunAt::Ahead => 0.0,
        },
    );
    let a = a.to_radians();
    Sun {
        direction: Vec3::new(e.cos() * a.sin(), e.cos() * a.cos(), e.sin()),
        irradiance: Vec3::splat(1.0),
    }
}

pub fn camera(shape: Shape, px: u32) -> LookAtCamera {
    let (eye, fov) = match shape {
        Shape::Ball | Shape::Blob => (Vec3::new(0.0, -3.2, 0.6), 42f32),
        Shape::Slab => (Vec3::new(0.0, -6.0, 2.5), 50.0),
    };
    LookAtCamera::look_at(eye, Vec3::ZERO, Vec3::Z, fov.to_radians(), px, px).unwrap()
}

/// The fast settings of the comparison: eye steps of 1/200 of the box's
/// diagonal, a 96-node shadow table, the default multiple scattering, the
/// forward peak truncated. The knobs `MATRIX_CELLS`, `MATRIX_ORDER`,
/// `MATRIX_ZONAL`, `MATRIX_TABLE`, `MATRIX_RAYS`, `MATRIX_SINGLE` and
/// `MATRIX_NOTRUNC` (in `fast_lums`) change the cache's grid, band and zonal
/// tail, the table's nodes, replace the table by direct shadow rays in steps
/// of that many metres, turn multiple scattering off, or keep the forward
/// peak in the transport, for studies.
pub fn fast_settings(b: &Aabb) -> FastSettings {
    FastSettings {
        step: (b.max - b.min).length() / 200.0,
        shadows: Shadows::Table(96),
        ..FastSettings::default()
    }
    .multiple_scattering()
}

/// The luminance of every pixel of an image, row by row.
pub fn lums(img: &natura_core::Image) -> Vec<f64> {
    img.pixels()
        .as_slice()
        .iter()
        .map(|&c| f64::from(natura_core::colour::luminance(c)))
        .collect()
}

/// The errors of one scene.
#[derive(Clone, Copy, Debug)]
pub struct Errors {
    /// Relative error of the total, noise subtracted (signed).
    pub total: f64,
    /// The reference's own relative noise on the total.
    pub noise: f64,
    /// Block error, noise subtracted.
    pub block: f64,
}

/// A scene's images: fast-mode luminance and the two reference renders.
pub struct Measured {
    pub fast: Vec<f64>,
    pub ref_a: Vec<f64>,
    pub ref_b: Vec<f64>,
    /// The sky let through each pixel ([`background`]), the same for both.
    pub sky: Vec<f64>,
    pub px: usize,
}

/// The scene of a case over its density `d` (at unit scale).
pub fn scene<'a>(c: &Case, d: &'a dyn Density) -> Scene<'a> {
    Scene {
        sun: Some(sun_of(c.sun)),
        ..Scene::new(
            d,
            MediumParams {
                extinction: c.tau / column(c.shape, d),
                albedo: c.albedo,
                phase: c.phase,
            },
            match c.sky {
                Sky::Black => Vec3::ZERO,
                Sky::Blue => SKY,
            },
        )
    }
}

/// The sky's luminance let through each pixel: the sky's luminance times
/// the pixel's transmittance, averaged over 4 × 4 rays across the pixel,
/// each ray's optical depth summed over 800 steps through the volume's
/// box. Zero under the black sky.
pub fn background(c: &Case, px: u32) -> Vec<f64> {
    let n = px as usize;
    if c.sky == Sky::Black {
        return vec![0.0; n * n];
    }
    let d = density(c.shape);
    let ext = f64::from(c.tau / column(c.shape, d.as_ref()));
    let b = d.bounds();
    let cam = camera(c.shape, px);
    let sky = f64::from(natura_core::colour::luminance(SKY));
    let mut out = Vec::with_capacity(n * n);
    for y in 0..n {
        for x in 0..n {
            let mut t = 0.0;
            for j in 0..4 {
                for i in 0..4 {
                    let ray = cam.ray_at(
                        x as f32 + (i as f32 + 0.5) / 4.0,
                        y as f32 + (j as f32 + 0.5) / 4.0,
                    );
                    let Some((t0, t1)) = ray_box(ray.origin, ray.dir.recip(), &b) else {
                        t += 1.0;
                        continue;
                    };
                    let steps = 800;
                    let dt = (t1 - t0) / steps as f32;
                    let depth: f64 = (0..steps)
                        .map(|k| f64::from(d.density(ray.at(t0 + (k as f32 + 0.5) * dt))))
                        .sum::<f64>()
                        * f64::from(dt)
                        * ext;
                    t += (-depth).exp();
                }
            }
            out.push(sky * t / 16.0);
        }
    }
    out
}

/// The reference's longest path: its default, or `MATRIX_DEPTH` (a
/// study's knob: the light of paths longer than the default's).
pub fn reference_depth() -> u32 {
    std::env::var("MATRIX_DEPTH")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(ReferenceSettings::default().max_depth)
}

pub fn render_case(c: &Case, px: u32, spp: u32) -> Measured {
    let d = density(c.shape);
    let scene = scene(c, d.as_ref());
    let cam = camera(c.shape, px);
    let fast = FastRenderer::new(&scene, fast_settings(&d.bounds()))
        .unwrap()
        .render(&cam)
        .unwrap();
    let reference = |seed| {
        let r = ReferenceRenderer::new(
            &scene,
            ReferenceSettings {
                samples_per_pixel: spp,
                seed,
                max_depth: reference_depth(),
                ..ReferenceSettings::default()
            },
        )
        .unwrap();
        lums(&r.render(&cam).unwrap())
    };
    Measured {
        fast: lums(&fast),
        ref_a: reference(1),
        ref_b: reference(2),
        sky: background(c, px),
        px: px as usize,
    }
}

/// `√max(e² − σ², 0)` with the sign of `e`.
pub fn denoise(e: f64, sigma: f64) -> f64 {
    e.signum() * (e * e - sigma * sigma).max(0.0).sqrt()
}

pub fn errors(m: &Measured) -> Errors {
    let n = m.px;
    // The light the volume sends: each image less the sky it lets through.
    let fast: Vec<f64> = m.fast.iter().zip(&m.sky).map(|(f, s)| f - s).collect();
    let reference: Vec<f64> = m
        .ref_a
        .iter()
        .zip(&m.ref_b)
        .zip(&m.sky)
        .map(|((a, b), s)| 0.5 * (a + b) - s)
        .collect();
    let half_diff: Vec<f64> = m
        .ref_a
        .iter()
        .zip(&m.ref_b)
        .map(|(a, b)| 0.5 * (a - b))
        .collect();
    // The noise of a sum of pixels: Var(Σ (A−B)/2) is estimated by Σ ((A−B)/2)²,
    // which is the variance of the mean (A+B)/2 summed.
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    let r_total = sum(&reference);
    let sigma_total = half_diff.iter().map(|x| x * x).sum::<f64>().sqrt();
    let total = denoise(sum(&fast) - r_total, sigma_total) / r_total;
    // Blocks of 4 × 4 pixels.
    let b = 4;
    let mut blocks = Vec::new();
    for by in 0..n / b {
        for bx in 0..n / b {
            let (mut f, mut r, mut s2) = (0.0, 0.0, 0.0);
            for y in by * b..(by + 1) * b {
                for x in bx * b..(bx + 1) * b {
                    let i = y * n + x;
                    f += fast[i];
                    r += reference[i];
                    s2 += half_diff[i] * half_diff[i];
                }
            }
            blocks.push((f, r, s2.sqrt()));
        }
    }
    let brightest = blocks.iter().map(|b| b.1).fold(0.0, f64::max);
    let seen: Vec<_> = blocks.iter().filter(|b| b.1 > 0.02 * brightest).collect();
    let block = seen
        .iter()
        .map(|(f, r, s)| denoise(f - r, *s).abs())
        .sum::<f64>()
        / seen.iter().map(|b| b.1).sum::<f64>();
    Errors {
        total,
        noise: sigma_total / r_total,
        block,
    }
}

pub fn describe(c: &Case) -> String {
    format!(
        "{:<5} {:<13} {:<6} {:<4} ω {:<5} τ {:<4}",
        format!("{:?}", c.shape),
        phase_name(&c.phase),
        format!("{:?}", c.sun),
        match c.sky {
            Sky::Black => "",
            Sky::Blue => "sky",
        },
        c.albedo,
        c.tau
    )
}
