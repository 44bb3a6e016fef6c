//! Detail down to the pixel footprint: off is the base bit for bit; the
//! fast and reference renderers see one field and agree as well with detail
//! as without; the detail keeps its energy below the pixels' Nyquist limit
//! and has energy just below it; the base's upper bounds still hold; bad
//! parameters are refused by name.

use glam::Vec3;
use natura_core::Aabb;
use natura_core::fft::{self, Complex, FftDirection};
use natura_volume::cloud::{CloudParams, cloud, nine_sphere_cumulus};
use natura_volume::density::Homogeneous;
use natura_volume::detail::{DetailParams, Detailed};
use natura_volume::gas::{Steam, SteamParams};
use natura_volume::grid::GridDensity;
use natura_volume::layer::{LayerClouds, LayerParams};
use natura_volume::phase::CloudPhase;
use natura_volume::transport::{
    FastRenderer, FastSettings, LookAtCamera, MediumParams, ReferenceRenderer, ReferenceSettings,
    Scene, Sun,
};
use natura_volume::{Density, VolumeError};
use proptest::prelude::*;

/// A xorshift stream in `[0, 1)`.
fn uniform(seed: u32) -> impl FnMut() -> f32 {
    let mut s = seed.max(1);
    move || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        (s >> 8) as f32 / (1 << 24) as f32
    }
}

fn points_in(b: &Aabb, n: usize, seed: u32) -> Vec<Vec3> {
    let mut u = uniform(seed);
    (0..n)
        .map(|_| b.min + (b.max - b.min) * Vec3::new(u(), u(), u()))
        .collect()
}

/// Detail for Ebert's 10 m cumulus seen from `eye` with pixels of `angle`.
fn cumulus_detail(eye: Vec3, angle: f32) -> DetailParams {
    DetailParams {
        feature_m: 1.5,
        ..DetailParams::default()
    }
    .seen_from(eye, angle)
}

fn cumulus_grid() -> GridDensity {
    let c = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 7).unwrap();
    GridDensity::bake(&c, 0.25).unwrap()
}

/// The density at many points, as bits, point by point and in one batch.
fn bits(d: &dyn Density, pts: &[Vec3]) -> (Vec<u32>, Vec<u32>) {
    let point = pts.iter().map(|&p| d.density(p).to_bits()).collect();
    let (x, y, z): (Vec<f32>, Vec<f32>, Vec<f32>) = (
        pts.iter().map(|p| p.x).collect(),
        pts.iter().map(|p| p.y).collect(),
        pts.iter().map(|p| p.z).collect(),
    );
    let mut out = vec![0.0; pts.len()];
    d.density_batch(&x, &y, &z, &mut out).unwrap();
    (point, out.iter().map(|v| v.to_bits()).collect())
}

/// Off (no detail, or an amplitude of 0) is the base density bit for bit,
/// point by point and in batches, for the wrapper and for each model's
/// own `detail` key; on, it changes the density.
#[test]
fn detail_off_is_the_base_bit_for_bit() {
    let g = cumulus_grid();
    let pts = points_in(&g.bounds(), 4000, 11);
    let eye = Vec3::new(0.0, -30.0, 3.0);
    let base = bits(&g, &pts);
    let off = Detailed::without_detail(&g);
    assert_eq!(bits(&off, &pts), base);
    let zero = DetailParams {
        amplitude: 0.0,
        ..cumulus_detail(eye, 1e-3)
    };
    assert_eq!(bits(&Detailed::new(&g, &zero, 3).unwrap(), &pts), base);
    let on = Detailed::new(&g, &cumulus_detail(eye, 1e-3), 3).unwrap();
    assert_ne!(bits(&on, &pts).0, base.0);

    // Ebert's cumulus, point and batch paths.
    let plain = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 7).unwrap();
    let p0 = CloudParams {
        detail: Some(zero),
        ..CloudParams::cumulus()
    };
    let c0 = cloud(nine_sphere_cumulus(), p0, 7).unwrap();
    assert_eq!(bits(&c0, &pts), bits(&plain, &pts));
    let p1 = CloudParams {
        detail: Some(cumulus_detail(eye, 1e-3)),
        ..CloudParams::cumulus()
    };
    let c1 = cloud(nine_sphere_cumulus(), p1, 7).unwrap();
    assert_ne!(bits(&c1, &pts).0, bits(&plain, &pts).0);

    // The layer clouds.
    let lp = LayerParams::default();
    let layer = LayerClouds::new(lp, 5).unwrap();
    let lpts = points_in(&lp.bounds(), 4000, 12);
    let zl = LayerClouds::new(
        LayerParams {
            detail: Some(DetailParams {
                amplitude: 0.0,
                ..DetailParams::default()
            }),
            ..lp
        },
        5,
    )
    .unwrap();
    assert_eq!(bits(&zl, &lpts), bits(&layer, &lpts));

    // Steam.
    let sp = SteamParams::default();
    let steam = Steam::new(sp, 2).unwrap();
    let spts = points_in(&steam.bounds(), 4000, 13);
    let zs = Steam::new(
        SteamParams {
            detail: Some(DetailParams {
                feature_m: 0.01,
                amplitude: 0.0,
                ..DetailParams::default()
            }),
            ..sp
        },
        2,
    )
    .unwrap();
    assert_eq!(bits(&zs, &spts), bits(&steam, &spts));
}

/// Erosion only removes density: everywhere in `[0, base]`, finite.
#[test]
fn eroded_density_lies_between_zero_and_the_base() {
    let g = cumulus_grid();
    let d = DetailParams {
        amplitude: 1.0,
        warp: 1.0,
        ..cumulus_detail(Vec3::new(0.0, -30.0, 3.0), 1e-4)
    };
    let on = Detailed::new(&g, &d, 9).unwrap();
    let mut eroded = 0;
    for p in points_in(&g.bounds(), 20_000, 14) {
        let (v, b) = (on.density(p), g.density(p));
        assert!(v.is_finite() && v >= 0.0 && v <= b, "{v} vs {b}");
        eroded += usize::from(v < b);
    }
    assert!(eroded > 1000, "{eroded}");
}

fn lit_scene(density: &dyn Density) -> Scene<'_> {
    let medium = MediumParams {
        extinction: 6.0,
        albedo: 0.99,
        phase: CloudPhase::default(),
    };
    Scene {
        sun: Some(Sun {
            direction: Vec3::new(-0.4, -0.5, 0.77).normalize(),
            irradiance: Vec3::splat(3.0),
        }),
        ..Scene::new(density, medium, Vec3::new(0.15, 0.2, 0.3))
    }
}

/// The relative luminance error of the fast mode against the reference on
/// the pixels whose rays lose more than 2 % to the volume.
fn fast_vs_reference(density: &dyn Density, camera: &LookAtCamera) -> f64 {
    let scene = lit_scene(density);
    let reference = ReferenceRenderer::new(
        &scene,
        ReferenceSettings {
            samples_per_pixel: 48,
            ..ReferenceSettings::default()
        },
    )
    .unwrap()
    .render(camera)
    .unwrap();
    let fast = FastRenderer::new(
        &scene,
        FastSettings {
            step: 0.05,
            ..FastSettings::default()
        }
        .multiple_scattering(),
    )
    .unwrap();
    let image = fast.render(camera).unwrap();
    let lum = |c: Vec3| f64::from(natura_core::colour::luminance(c));
    let res = camera.resolution();
    let (mut d, mut s) = (0.0, 0.0);
    for y in 0..res.y {
        for x in 0..res.x {
            let ray = camera.ray_at(x as f32 + 0.5, y as f32 + 0.5).dir;
            if fast.transmittance(camera.eye(), ray, f32::INFINITY) >= 0.98 {
                continue;
            }
            let (xi, yi) = (x as usize, y as usize);
            let (a, r) = (image.pixels()[(xi, yi)], reference.pixels()[(xi, yi)]);
            d += (lum(a) - lum(r)).abs();
            s += lum(r);
        }
    }
    d / s
}

/// The fast renderer and the reference see one field: the scene's density
/// samples are the wrapper's, bit for bit, point by point and in batches;
/// and the fast mode agrees with the reference with detail as well as it
/// does without (within 1.25 times the error, plus 0.02).
#[test]
fn fast_and_reference_see_the_same_detailed_field() {
    let g = cumulus_grid();
    let b = g.bounds();
    let c = (b.min + b.max) * 0.5;
    let r = (b.max - b.min).length() * 0.5;
    let eye = c + Vec3::new(0.0, -2.6 * r, 0.3 * r);
    let (w, h) = (20u32, 14u32);
    let fov = 45f32.to_radians();
    let camera = LookAtCamera::look_at(eye, c, Vec3::Z, fov, w, h).unwrap();
    let on = Detailed::new(&g, &cumulus_detail(eye, fov / h as f32), 3).unwrap();
    let scene = lit_scene(&on);
    let pts = points_in(&b, 5000, 15);
    let (point, batch) = bits(scene.density, &pts);
    assert_eq!(point, batch);
    let own: Vec<u32> = pts.iter().map(|&p| on.density(p).to_bits()).collect();
    assert_eq!(point, own);
    let without = fast_vs_reference(&g, &camera);
    let with = fast_vs_reference(&on, &camera);
    eprintln!(
        "fast vs reference, relative luminance error: without detail {without:.4}, with {with:.4}"
    );
    assert!(with <= 1.25 * without + 0.02, "{with} vs {without}");
}

/// A constant base of 0.3 in a box whose full-cloud density is 1: what is
/// left is the erosion alone.
struct Thin(Homogeneous, f32);

impl Density for Thin {
    fn density(&self, p: Vec3) -> f32 {
        self.0.density(p) * self.1
    }
    fn bounds(&self) -> Aabb {
        self.0.bounds()
    }
    fn max_density(&self) -> f32 {
        1.0
    }
}

/// The fraction of the energy (mean removed, Hann window) of `v`, sampled
/// `dx` apart, above the frequency `f` and in `[lo, f]`.
fn energy_fractions(v: &[f64], dx: f64, lo: f64, f: f64) -> (f64, f64) {
    let n = v.len();
    let mean = v.iter().sum::<f64>() / n as f64;
    let mut buf: Vec<Complex<f64>> = v
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let hann = 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / n as f64).cos();
            Complex::new((x - mean) * hann, 0.0)
        })
        .collect();
    fft::plan_f64(n, FftDirection::Forward).process(&mut buf);
    let (mut total, mut above, mut band) = (0.0, 0.0, 0.0);
    for (k, c) in buf.iter().enumerate().take(n / 2 + 1).skip(1) {
        let freq = k as f64 / (n as f64 * dx);
        let e = c.norm_sqr();
        total += e;
        if freq > f {
            above += e;
        } else if freq >= lo {
            band += e;
        }
    }
    (above / total, band / total)
}

/// A row of the detailed density along an arc of radius `r` about the eye
/// (an image row at distance `r`), 16 samples a pixel of `angle`, 512 pixels.
fn row(on: &dyn Density, r: f64, angle: f32) -> (Vec<f64>, f64) {
    let over = 16usize;
    let dt = f64::from(angle) / over as f64;
    let v = (0..512 * over)
        .map(|i| {
            let t = i as f64 * dt;
            let q = Vec3::new((r * t.cos()) as f32, (r * t.sin()) as f32, 300.0);
            f64::from(on.density(q))
        })
        .collect();
    (v, r * dt)
}

/// Along an image row at two distances (an arc about the eye, 16 samples a
/// pixel), the detailed density keeps under 10⁻³ of its energy above the
/// Nyquist frequency of the pixel grid, `1/(2w)` with `w = r·α`; and it has
/// detail just below it: its energy within the two octaves below the limit
/// is at least 10 times that of the same field for pixels 4 times as large
/// (whose octaves stop two octaves sooner), and at least 20 times its own
/// energy above the limit.
#[test]
fn no_energy_above_the_pixels_nyquist_limit() {
    let region = Aabb {
        min: Vec3::splat(-1e5),
        max: Vec3::splat(1e5),
    };
    for thickness in [0.3f32, 0.6] {
        let base = Thin(Homogeneous::new(region, 1.0).unwrap(), thickness);
        let angle = 1e-3f32;
        let p = DetailParams {
            feature_m: 200.0,
            ..DetailParams::default()
        };
        let on = Detailed::new(&base, &p.seen_from(Vec3::ZERO, angle), 21).unwrap();
        let coarse = Detailed::new(&base, &p.seen_from(Vec3::ZERO, 4.0 * angle), 21).unwrap();
        for r in [1500.0f64, 12_000.0] {
            let nyquist = 0.5 / (r * f64::from(angle));
            let (v, dx) = row(&on, r, angle);
            let (above, below) = energy_fractions(&v, dx, 0.25 * nyquist, nyquist);
            let (c, _) = row(&coarse, r, angle);
            let (_, below_coarse) = energy_fractions(&c, dx, 0.25 * nyquist, nyquist);
            // Fractions of different totals: compare energies.
            let total = |v: &[f64]| {
                let m = v.iter().sum::<f64>() / v.len() as f64;
                v.iter().map(|x| (x - m) * (x - m)).sum::<f64>()
            };
            let (band, band_coarse) = (below * total(&v), below_coarse * total(&c));
            eprintln!(
                "base {thickness}, r = {r} m: energy above the Nyquist limit {above:.2e} of the total, in the two octaves below it {below:.2e}; those two octaves hold {:.0} times the energy of pixels 4 times as large",
                band / band_coarse.max(1e-300)
            );
            assert!(above < 1e-3, "{above}");
            assert!(below > 20.0 * above, "{below} vs {above}");
            assert!(band > 10.0 * band_coarse, "{band} vs {band_coarse}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// `bound_in` stays an upper bound of the detailed density on random
    /// boxes (Ebert's cumulus, whose own bound follows the primitives).
    #[test]
    fn bound_in_is_an_upper_bound(
        cx in -8.0f32..8.0, cy in -8.0f32..8.0, cz in -3.0f32..10.0,
        sx in 0.05f32..6.0, sy in 0.05f32..6.0, sz in 0.05f32..6.0,
        amplitude in 0.0f32..=1.0, warp in 0.0f32..=1.0, seed in 0u32..1000,
    ) {
        let p = CloudParams {
            detail: Some(DetailParams {
                amplitude,
                warp,
                ..cumulus_detail(Vec3::new(0.0, -25.0, 3.0), 2e-3)
            }),
            ..CloudParams::cumulus()
        };
        let c = cloud(nine_sphere_cumulus(), p, 7).unwrap();
        let on = Detailed::new(
            cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 7).unwrap(),
            &DetailParams { amplitude, warp, ..cumulus_detail(Vec3::ZERO, 1e-3) },
            u64::from(seed),
        )
        .unwrap();
        let b = Aabb {
            min: Vec3::new(cx, cy, cz),
            max: Vec3::new(cx + sx, cy + sy, cz + sz),
        };
        let (bc, bo) = (c.bound_in(&b), on.bound_in(&b));
        for q in points_in(&b, 300, seed + 1) {
            prop_assert!(c.density(q) <= bc, "{} > {bc}", c.density(q));
            prop_assert!(on.density(q) <= bo, "{} > {bo}", on.density(q));
        }
    }
}

fn invalid_name(e: VolumeError) -> &'static str {
    match e {
        VolumeError::InvalidParameter { name, .. } => name,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

/// Bad parameters are refused by name, before any work, by the wrapper and
/// by every model that takes them.
#[test]
fn bad_detail_parameters_are_refused_by_name() {
    let ok = DetailParams::default();
    let cases = [
        (
            "feature_m",
            DetailParams {
                feature_m: f32::NAN,
                ..ok
            },
        ),
        (
            "feature_m",
            DetailParams {
                feature_m: -3.0,
                ..ok
            },
        ),
        (
            "feature_m",
            DetailParams {
                feature_m: 0.0,
                ..ok
            },
        ),
        ("octaves", DetailParams { octaves: 25, ..ok }),
        ("h", DetailParams { h: f32::NAN, ..ok }),
        (
            "amplitude",
            DetailParams {
                amplitude: -0.1,
                ..ok
            },
        ),
        // More than 1 would make the eroded density negative.
        (
            "amplitude",
            DetailParams {
                amplitude: 1.5,
                ..ok
            },
        ),
        (
            "amplitude",
            DetailParams {
                amplitude: f32::NAN,
                ..ok
            },
        ),
        ("warp", DetailParams { warp: 2.0, ..ok }),
        (
            "eye",
            DetailParams {
                eye: [0.0, f32::INFINITY, 0.0],
                ..ok
            },
        ),
        (
            "pixel_angle",
            DetailParams {
                pixel_angle: 0.0,
                ..ok
            },
        ),
        (
            "pixel_angle",
            DetailParams {
                pixel_angle: -1e-3,
                ..ok
            },
        ),
        (
            "pixel_angle",
            DetailParams {
                pixel_angle: f32::NAN,
                ..ok
            },
        ),
        (
            "pixel_angle",
            DetailParams {
                pixel_angle: 2.0,
                ..ok
            },
        ),
    ];
    let g = cumulus_grid();
    for (name, p) in cases {
        assert_eq!(invalid_name(p.validate().unwrap_err()), name);
        assert_eq!(invalid_name(Detailed::new(&g, &p, 1).unwrap_err()), name);
        let cp = CloudParams {
            detail: Some(p),
            ..CloudParams::cumulus()
        };
        assert_eq!(
            invalid_name(cloud(nine_sphere_cumulus(), cp, 1).unwrap_err()),
            name
        );
        let lp = LayerParams {
            detail: Some(p),
            ..LayerParams::default()
        };
        assert_eq!(invalid_name(LayerClouds::new(lp, 1).unwrap_err()), name);
        let sp = SteamParams {
            detail: Some(p),
            ..SteamParams::default()
        };
        assert_eq!(invalid_name(Steam::new(sp, 1).unwrap_err()), name);
    }
}
