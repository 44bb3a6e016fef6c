//! Height-field tests: construction, geometry, and exact file round trips.

use super::*;
use approx::assert_relative_eq;

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("natura-core-hf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A bumpy, asymmetric field so that any row flip or transpose shows.
pub(crate) fn bumpy(nx: usize, ny: usize) -> HeightField {
    HeightField::from_fn(nx, ny, 2.5, |i, j| {
        (i as f32 * 0.37).sin() * 120.0 + (j as f32 * 0.21).cos() * 80.0 + i as f32 * 0.5
            - j as f32 * 3.0
            + 1000.0
    })
    .unwrap()
}

#[test]
fn construction_refuses_nan_and_bad_cells() {
    let mut g = Grid2::new(4, 3, 0.0f32).unwrap();
    g[(2, 1)] = f32::INFINITY;
    let err = HeightField::new(g, 1.0).unwrap_err();
    assert!(
        matches!(err, CoreError::NonFinite { x: 2, y: 1, .. }),
        "{err}"
    );
    for c in [0.0, -1.0, f32::NAN] {
        assert!(HeightField::flat(2, 2, c, 0.0).is_err());
    }
}

#[test]
fn geometry() {
    let hf = HeightField::from_fn(11, 6, 2.0, |i, j| 3.0 * i as f32 - 1.0 * j as f32).unwrap();
    assert_eq!(hf.extent(), Vec2::new(20.0, 10.0));
    let b = hf.bounds();
    assert_eq!(b.min, Vec3::new(0.0, 0.0, -5.0));
    assert_eq!(b.max, Vec3::new(20.0, 10.0, 30.0));
    // h = 1.5 x − 0.5 y in world units: bilinear is exact, gradient is constant.
    assert_relative_eq!(
        hf.height_at(7.3, 4.1).unwrap(),
        1.5 * 7.3 - 0.5 * 4.1,
        epsilon = 1e-4
    );
    assert_eq!(hf.height_at(-0.1, 1.0), None);
    assert_eq!(hf.height_at(f32::NAN, 1.0), None);
    let g = hf.gradient_at(13.0, 3.0).unwrap();
    assert_relative_eq!(g.x, 1.5, epsilon = 1e-5);
    assert_relative_eq!(g.y, -0.5, epsilon = 1e-5);
    let n = hf.normal_at(5.0, 5.0).unwrap();
    assert_relative_eq!(n, Vec3::new(-1.5, 0.5, 1.0).normalize(), epsilon = 1e-5);
    assert_relative_eq!(
        hf.slope_at(1.0, 1.0).unwrap(),
        (1.5f32.hypot(0.5)).atan(),
        epsilon = 1e-5
    );
    let shade = hf.hillshade(Vec3::Z).unwrap();
    assert_relative_eq!(shade[(5, 3)], n.z, epsilon = 1e-5);
    assert!(hf.hillshade(Vec3::ZERO).is_err());
}

#[test]
fn raw_round_trip_is_exact() {
    let hf = bumpy(23, 17);
    let p = scratch("rt.raw");
    hf.save_raw(&p).unwrap();
    assert_eq!(HeightField::load_raw(&p, 23, 17, 2.5).unwrap(), hf);
    let err = HeightField::load_raw(&p, 17, 23 + 1, 2.5).unwrap_err();
    assert!(
        err.to_string().contains("rt.raw") && err.to_string().contains("expected"),
        "{err}"
    );
}

#[test]
fn raw_file_order_is_map_order() {
    let hf = HeightField::from_fn(2, 2, 1.0, |i, j| (i + 10 * j) as f32).unwrap();
    let p = scratch("order.raw");
    hf.save_raw(&p).unwrap();
    let b = std::fs::read(&p).unwrap();
    let first = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    assert_eq!(
        first, 10.0,
        "the first stored row is the one with the largest y"
    );
}

#[test]
fn exr_round_trip_is_bit_exact() {
    let mut hf = bumpy(31, 19);
    hf.heights_mut()[(3, 4)] = -0.0;
    hf.heights_mut()[(5, 6)] = f32::MIN_POSITIVE / 3.0; // subnormal
    let p = scratch("rt.exr");
    hf.save_exr(&p).unwrap();
    let back = HeightField::load_exr(&p, None).unwrap();
    assert_eq!(back.cell_size(), hf.cell_size());
    for (a, b) in back
        .heights()
        .as_slice()
        .iter()
        .zip(hf.heights().as_slice())
    {
        assert_eq!(a.to_bits(), b.to_bits());
    }
}

#[test]
fn png16_round_trip_within_one_step() {
    let hf = bumpy(29, 21);
    let (lo, hi) = hf.min_max();
    let p = scratch("rt.png");
    hf.save_png16(&p, (lo, hi)).unwrap();
    let back = HeightField::load_png16(&p, None, None).unwrap();
    assert_eq!(back.cell_size(), hf.cell_size());
    let step = (hi - lo) / 65535.0;
    for (a, b) in back
        .heights()
        .as_slice()
        .iter()
        .zip(hf.heights().as_slice())
    {
        assert!((a - b).abs() <= step, "{a} vs {b}, step {step}");
    }
    // A range that does not cover the data is refused, naming a cell.
    let err = hf.save_png16(&p, (lo + 10.0, hi)).unwrap_err();
    assert!(err.to_string().contains("cell ("), "{err}");
    assert!(hf.save_png16(&p, (5.0, 5.0)).is_err());
}

#[test]
fn png_without_range_needs_one() {
    let img = crate::Image::new(4, 4, Vec3::splat(0.5)).unwrap();
    let p = scratch("colour.png");
    img.save_png(&p).unwrap();
    let err = HeightField::load_png16(&p, Some(1.0), Some((0.0, 1.0))).unwrap_err();
    assert!(err.to_string().contains("greyscale"), "{err}");
}

#[test]
fn missing_file_is_named() {
    let err = HeightField::load_exr("/no/such/file.exr", Some(1.0)).unwrap_err();
    assert!(err.to_string().contains("/no/such/file.exr"));
    let err = HeightField::load("x.tiff", Some(1.0), None).unwrap_err();
    assert!(err.to_string().contains("extension"));
}

#[test]
fn box_downsample_keeps_the_extent_and_the_mean() {
    let hf = bumpy(64, 32);
    let d = hf.box_downsample(4).unwrap();
    assert_eq!((d.nx(), d.ny()), (16, 8));
    assert_eq!(d.cell_size(), hf.cell_size() * 4.0);
    let mean = |h: &HeightField| {
        let s = h.heights().as_slice();
        s.iter().map(|&v| f64::from(v)).sum::<f64>() / s.len() as f64
    };
    approx::assert_relative_eq!(mean(&d), mean(&hf), max_relative = 1e-5);
}
