//! The rasterizer against a ray-cast oracle, watertightness, order
//! independence, supersampled coverage, determinism and bad input.

use glam::{Vec2, Vec3};

use super::*;
use crate::NoProgress;
use crate::seed::{mix64, unit_f64};

/// A deterministic number in `[lo, hi)` from key `k`.
fn rnd(k: u64, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * unit_f64(mix64(k)) as f32
}

/// A random triangle in the box `[-1, 1]³` (index `t`).
fn world_triangle(t: u64) -> [Vec3; 3] {
    let c = |k: u64| {
        Vec3::new(
            rnd(k, -1.0, 1.0),
            rnd(k + 1, -1.0, 1.0),
            rnd(k + 2, -1.0, 1.0),
        )
    };
    [c(t * 9), c(t * 9 + 3), c(t * 9 + 6)]
}

fn cameras() -> [PreviewCamera; 2] {
    let (eye, target, up) = (
        Vec3::new(0.7, -4.0, 1.3),
        Vec3::new(0.1, 0.0, -0.2),
        Vec3::Z,
    );
    [
        PreviewCamera {
            eye,
            target,
            up,
            projection: PreviewProjection::Orthographic { height: 2.7 },
        },
        PreviewCamera {
            eye,
            target,
            up,
            projection: PreviewProjection::Perspective { fov_y_deg: 45.0 },
        },
    ]
}

/// Möller–Trumbore: the ray parameter where `ray` meets triangle `t`.
fn hit(ray: Ray, t: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = ray.origin - t[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = ray.dir.dot(q) / det;
    let d = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && d >= 0.0).then_some(d)
}

/// Distance in pixels from `(x, y)` to the nearest edge of screen triangle `s`.
fn edge_distance(s: [[f32; 3]; 3], x: f32, y: f32) -> f32 {
    (0..3)
        .map(|k| {
            let (a, b) = (
                Vec2::new(s[k][0], s[k][1]),
                Vec2::new(s[(k + 1) % 3][0], s[(k + 1) % 3][1]),
            );
            let t = ((Vec2::new(x, y) - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (a + t * (b - a) - Vec2::new(x, y)).length()
        })
        .fold(f32::MAX, f32::min)
}

#[test]
fn coverage_and_depth_match_a_ray_cast_oracle() {
    let (w, h) = (48u32, 36u32);
    for camera in cameras() {
        let proj = Projector::new(&camera, w, h).unwrap();
        let (mut agree, mut checked) = (0, 0);
        for t in 0..40 {
            let tri = world_triangle(t);
            let s = tri.map(|p| proj.project(p).unwrap());
            let mut r = Raster::new(w, h, 1, Vec3::ZERO).unwrap();
            r.triangle(s, |_| Vec3::ONE).unwrap();
            for y in 0..h as usize {
                for x in 0..w as usize {
                    let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                    let oracle = hit(proj.ray_at(px, py), tri);
                    let (c, depth) = r.sample(x, y).unwrap();
                    if edge_distance(s, px, py) < 1e-3 {
                        continue; // rounding may put the centre on either side
                    }
                    checked += 1;
                    assert_eq!(
                        c == Vec3::ONE,
                        oracle.is_some(),
                        "triangle {t} at ({x}, {y})"
                    );
                    if let Some(d) = oracle {
                        let ray = proj.ray_at(px, py);
                        let want = proj.depth_key(ray.at(d));
                        assert!(
                            (depth - want).abs() <= 1e-4 * want.abs().max(1.0),
                            "{depth} {want}"
                        );
                        agree += 1;
                    }
                }
            }
        }
        // The triangles were on screen: the check compared many covered samples.
        assert!(agree > 1000 && checked > 40 * 1500, "{agree} {checked}");
    }
}

/// A grid of quads over the whole `w × h` frame, each cut into two
/// triangles along a random diagonal, interior vertices moved by `jitter`
/// (half-pixel steps when `snap`, so many edges pass through sample
/// centres), the winding of each triangle random.
fn mesh(w: f32, h: f32, n: usize, snap: bool) -> Vec<[[f32; 3]; 3]> {
    let cell = Vec2::new(w / n as f32, h / n as f32);
    let vertex = |i: usize, j: usize| {
        let mut p = Vec2::new(i as f32, j as f32) * cell;
        if i > 0 && i < n && j > 0 && j < n {
            let k = (i * 97 + j) as u64 * 4;
            let d = Vec2::new(rnd(k, -0.3, 0.3), rnd(k + 1, -0.3, 0.3)) * cell;
            p += if snap { (d * 2.0).round() * 0.5 } else { d };
        }
        [p.x, p.y, 1.0]
    };
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let [a, b, c, d] = [
                vertex(i, j),
                vertex(i + 1, j),
                vertex(i + 1, j + 1),
                vertex(i, j + 1),
            ];
            let k = (j * n + i) as u64 * 4 + 1_000_000;
            let pair = if rnd(k, 0.0, 1.0) < 0.5 {
                [[a, b, c], [a, c, d]]
            } else {
                [[a, b, d], [b, c, d]]
            };
            for (m, t) in pair.into_iter().enumerate() {
                let flip = rnd(k + 1 + m as u64, 0.0, 1.0) < 0.5;
                tris.push(if flip { [t[0], t[2], t[1]] } else { t });
            }
        }
    }
    tris
}

#[test]
fn triangles_sharing_edges_cover_each_sample_once() {
    let (w, h) = (40u32, 30u32);
    for snap in [true, false] {
        let tris = mesh(w as f32, h as f32, 6, snap);
        let mut count = vec![0u32; (w * h) as usize];
        for t in &tris {
            // Each triangle alone, so a shared sample cannot hide behind the z-test.
            let mut r = Raster::new(w, h, 1, Vec3::ZERO).unwrap();
            r.triangle(*t, |f| {
                count[f.y * w as usize + f.x] += 1;
                Vec3::ONE
            })
            .unwrap();
        }
        let bad: Vec<usize> = (0..count.len()).filter(|&k| count[k] != 1).collect();
        assert!(
            bad.is_empty(),
            "snap {snap}: samples covered ≠ once: {:?}",
            &bad[..bad.len().min(8)]
        );
    }
}

#[test]
fn drawing_order_does_not_change_the_picture() {
    let proj = Projector::new(&cameras()[1], 40, 30).unwrap();
    let tris: Vec<[[f32; 3]; 3]> = (0..60)
        .map(|t| world_triangle(t).map(|p| proj.project(p).unwrap()))
        .collect();
    let draw = |order: &[usize]| {
        let mut r = Raster::new(40, 30, 2, Vec3::ZERO).unwrap();
        for &t in order {
            let c = Vec3::new(t as f32, 1.0, 2.0);
            r.triangle(tris[t], |f| c + f.mix([Vec3::X, Vec3::Y, Vec3::Z]))
                .unwrap();
        }
        r.resolve()
            .unwrap()
            .pixels()
            .as_slice()
            .iter()
            .flat_map(|c| c.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    let forward: Vec<usize> = (0..tris.len()).collect();
    let mut shuffled = forward.clone();
    for k in (1..shuffled.len()).rev() {
        shuffled.swap(k, (mix64(k as u64 + 77) % (k as u64 + 1)) as usize);
    }
    let reverse: Vec<usize> = forward.iter().rev().copied().collect();
    let reference = draw(&forward);
    assert_eq!(reference, draw(&shuffled));
    assert_eq!(reference, draw(&reverse));
}

/// The area of the unit pixel square at `(x, y)` below (y-down: `py >`) the
/// line `py = m·px + b`, integrated numerically.
fn analytic(x: usize, y: usize, m: f64, b: f64) -> f64 {
    let n = 4000;
    (0..n)
        .map(|k| {
            let px = x as f64 + (k as f64 + 0.5) / n as f64;
            ((y as f64 + 1.0) - (m * px + b).max(y as f64)).clamp(0.0, 1.0)
        })
        .sum::<f64>()
        / n as f64
}

#[test]
fn supersampling_a_half_plane_gives_its_area() {
    let (w, h, m, b) = (16usize, 12usize, 0.37f64, 3.3f64);
    for s in [1u32, 2, 3, 4, 8] {
        // The half-plane as a huge triangle, and as a closure of coordinates.
        let line = |px: f64| m * px + b;
        let mut r = Raster::new(w as u32, h as u32, s, Vec3::ZERO).unwrap();
        let sf = s as f32;
        let (x0, x1) = (-100.0f32, 100.0f32);
        let tri = [
            [x0, line(f64::from(x0)) as f32 * sf, 1.0],
            [x1, line(f64::from(x1)) as f32 * sf, 1.0],
            [0.0, 1e4, 1.0],
        ];
        let tri = tri.map(|v| [v[0] * sf, v[1], v[2]]);
        r.triangle(tri, |_| Vec3::ONE).unwrap();
        // The box: a pixel's value is the area it covers.
        let raster = r.resolve_with(PixelFilter::BOX).unwrap();
        let closure = shade_pixels_filtered(
            w as u32,
            h as u32,
            s,
            PixelFilter::BOX,
            "half-plane",
            &NoProgress,
            |px, py| {
                if py > line(px) { Vec3::ONE } else { Vec3::ZERO }
            },
        )
        .unwrap();
        for x in 0..w {
            for y in 0..h {
                let want = analytic(x, y, m, b);
                for img in [&raster, &closure] {
                    let got = f64::from(img.get(x, y).unwrap().x);
                    // One row of samples at most on either side of the edge.
                    assert!(
                        (got - want).abs() <= 1.0 / f64::from(s) + 1e-6,
                        "s {s} ({x}, {y}) {got} {want}"
                    );
                }
            }
        }
        // Down each column of samples, within one sample (1/s² of a pixel).
        let (sw, sh) = r.samples();
        for i in 0..sw as usize {
            let px = (i as f64 + 0.5) / f64::from(s);
            let covered = (0..sh as usize)
                .filter(|&j| r.sample(i, j).unwrap().0 == Vec3::ONE)
                .count();
            let exact = (h as f64 - line(px)).clamp(0.0, h as f64) * f64::from(s);
            assert!(
                (covered as f64 - exact).abs() <= 1.0,
                "s {s} column {i}: {covered} {exact}"
            );
        }
    }
}

#[cfg(feature = "parallel")]
#[test]
fn pictures_are_the_same_on_any_number_of_threads() {
    let cam = Projector::new(&cameras()[1], 37, 23).unwrap();
    let run = || {
        let img = trace_pixels(&cam, 3, "spheres", &NoProgress, |ray| {
            let t = hit(ray, world_triangle(1)).unwrap_or(0.0);
            Vec3::new(t, ray.dir.x.sin(), ray.dir.z)
        })
        .unwrap();
        img.pixels()
            .as_slice()
            .iter()
            .flat_map(|c| c.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(run);
    assert_eq!(one, pool(3).install(run));
    assert_eq!(one, run());
    let mut r = Raster::new(8, 8, 2, Vec3::ZERO).unwrap();
    let tri = world_triangle(2).map(|p| {
        Projector::new(&cameras()[0], 16, 16)
            .unwrap()
            .project(p)
            .unwrap()
    });
    r.triangle(tri, |f| f.mix([Vec3::X, Vec3::Y, Vec3::Z]))
        .unwrap();
    let again = r.clone();
    assert_eq!(
        r.resolve().unwrap().pixels().as_slice(),
        again.resolve().unwrap().pixels().as_slice()
    );
}

#[test]
fn bad_input_is_an_error_naming_the_parameter() {
    let name = |e: ParamError| e.name;
    assert_eq!(check_size(0, 8, 1).map_err(name), Err("width"));
    assert_eq!(
        check_size(8, MAX_RESOLUTION + 1, 1).map_err(name),
        Err("height")
    );
    assert_eq!(check_size(8, 8, 0).map_err(name), Err("supersample"));
    assert_eq!(
        check_size(8, 8, MAX_SUPERSAMPLE + 1).map_err(name),
        Err("supersample")
    );
    assert_eq!(
        check_size(MAX_RESOLUTION, 8, 2).map_err(name),
        Err("supersample")
    );
    assert!(Raster::new(8, 0, 1, Vec3::ZERO).is_err());
    assert!(Raster::new(8, 8, 0, Vec3::ZERO).is_err());
    // Allowed sides, but far too many samples to hold: refused, not allocated.
    assert!(Raster::new(MAX_RESOLUTION, MAX_RESOLUTION, 1, Vec3::ZERO).is_err());
    assert!(shade_pixels(0, 8, 1, "", &NoProgress, |_, _| Vec3::ZERO).is_err());
    assert!(shade_pixels(8, 8, 0, "", &NoProgress, |_, _| Vec3::ZERO).is_err());
    let mut r = Raster::new(8, 8, 1, Vec3::ZERO).unwrap();
    for bad in [f32::NAN, f32::INFINITY] {
        let e = r.triangle([[0.0, 0.0, 1.0], [bad, 4.0, 1.0], [4.0, 4.0, 1.0]], |_| {
            Vec3::ONE
        });
        assert_eq!(e.map_err(name), Err("vertices"));
    }
    // A degenerate triangle draws nothing.
    assert_eq!(
        r.triangle([[0.0, 0.0, 1.0], [2.0, 2.0, 1.0], [4.0, 4.0, 1.0]], |_| {
            Vec3::ONE
        }),
        Ok(0)
    );
    let [ortho, _] = cameras();
    assert!(Projector::new(&ortho, 0, 8).is_err());
    let mut bad = ortho;
    bad.up = bad.target - bad.eye;
    assert_eq!(bad.validate().map_err(name), Err("PreviewCamera::up"));
    bad = ortho;
    bad.eye = Vec3::NAN;
    assert!(Projector::new(&bad, 8, 8).is_err());
    let framing = |lo: Vec3, dir: Vec3, fov: Option<f32>, aspect: f32| {
        PreviewCamera::framing(lo, Vec3::ONE, dir, fov, aspect).map_err(name)
    };
    assert_eq!(framing(Vec3::NAN, Vec3::Y, None, 1.0), Err("bounds"));
    assert_eq!(framing(Vec3::ZERO, Vec3::ZERO, None, 1.0), Err("view_dir"));
    assert_eq!(framing(Vec3::ZERO, Vec3::Y, None, 0.0), Err("aspect"));
    assert_eq!(
        framing(Vec3::ZERO, Vec3::Y, Some(180.0), 1.0),
        Err("PreviewCamera::projection.fov_y_deg")
    );
    assert!(
        Projector::new(&cameras()[1], 8, 8)
            .unwrap()
            .project(Vec3::NAN)
            .is_none()
    );
}

proptest::proptest! {
    /// Any finite triangle, however large or thin, draws without panicking
    /// and writes only samples inside the frame, as many as it reports.
    #[test]
    fn any_finite_triangle_draws_without_panicking(
        v in proptest::array::uniform3(proptest::array::uniform3(-1e30f32..1e30f32)),
        scale in proptest::sample::select(vec![1e-6f32, 1.0, 1e3, 1e30]),
    ) {
        let v = v.map(|p| [p[0] / 1e30 * 40.0 * scale, p[1] / 1e30 * 40.0 * scale, p[2]]);
        let mut r = Raster::new(16, 16, 2, Vec3::ZERO).unwrap();
        let mut seen = 0;
        let n = r.triangle(v, |f| {
            seen += 1;
            assert!(f.x < 32 && f.y < 32);
            Vec3::ONE
        });
        proptest::prop_assert!(n.is_ok());
        proptest::prop_assert_eq!(n.unwrap(), seen);
    }
}
