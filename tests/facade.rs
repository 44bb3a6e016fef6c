//! The facade re-exports each crate under its module name.

#[cfg(feature = "core")]
#[test]
fn core_is_reachable_through_the_facade() {
    use natura::core::{HeightField, Seed};
    let hf = HeightField::from_fn(8, 8, 1.0, |i, j| {
        Seed(3).gaussian2(i as i64, j as i64) as f32
    })
    .unwrap();
    assert_eq!(hf.nx(), 8);
    assert!(hf.check_finite().is_ok());
}
