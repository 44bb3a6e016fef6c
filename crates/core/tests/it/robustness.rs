//! Hostile coordinates and indices: typed answers, never a panic or overflow.

use natura_core::{Boundary, Grid2, HeightField};

#[test]
fn bilinear_sampling_at_nan_and_infinite_coordinates_gives_nan() {
    let g = Grid2::from_fn(4, 3, |x, y| (x + 10 * y) as f32).unwrap();
    let specials = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        f32::MIN,
    ];
    for &x in &specials {
        for b in [Boundary::Clamp, Boundary::Wrap, Boundary::Constant(7.0)] {
            let v = g.sample_bilinear(x, 1.0, b);
            let w = g.sample_bilinear(1.0, x, b);
            if x.is_finite() {
                assert!(v.is_finite() && w.is_finite(), "{x} {b:?}");
            } else {
                assert!(v.is_nan() && w.is_nan(), "{x} {b:?}: {v} {w}");
            }
        }
    }
}

#[test]
fn heightfield_points_out_of_range_have_a_checked_twin() {
    let hf = HeightField::new(Grid2::from_fn(3, 2, |x, y| (x + y) as f32).unwrap(), 2.0).unwrap();
    assert_eq!(hf.try_point(2, 1), Some(hf.point(2, 1)));
    assert_eq!(hf.try_point(3, 0), None);
    assert_eq!(hf.try_point(0, usize::MAX), None);
}
