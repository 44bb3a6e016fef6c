//! Oracle tests: the grid tracer and the mipmap tracer return the same first
//! hit as brute force over all triangles, on random fields and rays of every
//! awkward sort.

use crate::common;

use common::*;
use natura_core::HeightField;
use natura_trace::{GridTracer, Hit, MipmapTracer, Ray, Tracer, brute_force};
use proptest::prelude::*;

fn scene() -> impl Strategy<Value = (HeightField, Ray, (f32, f32))> {
    any_field().prop_flat_map(|hf| {
        let r = ray_for(&hf);
        (Just(hf), r, t_range())
    })
}

/// Same hit: `t` within 1e-4 relative; the same cell and triangle, or — only
/// where the hit lies on an edge shared by two triangles — the same point.
fn same(a: &Hit, b: &Hit, scale: f32) -> Result<(), String> {
    let tol = 1e-4 * b.t.abs().max(1.0);
    if (a.t - b.t).abs() > tol {
        return Err(format!("t {} vs oracle {}", a.t, b.t));
    }
    if (a.cell, a.triangle) != (b.cell, b.triangle) && (a.point - b.point).length() > 1e-3 * scale {
        return Err(format!(
            "different triangle away from a shared edge: {:?}/{:?} at {} vs oracle {:?}/{:?} at {}",
            a.cell, a.triangle, a.point, b.cell, b.triangle, b.point
        ));
    }
    Ok(())
}

fn check(name: &str, got: Option<Hit>, want: Option<Hit>, scale: f32) -> Result<(), TestCaseError> {
    match (got, want) {
        (None, None) => Ok(()),
        (Some(a), Some(b)) => same(&a, &b, scale)
            .map_err(|e| TestCaseError::fail(format!("{name}: {e}\n got {a:?}\n want {b:?}"))),
        (a, b) => Err(TestCaseError::fail(format!(
            "{name}: hit {:?} but oracle {:?}",
            a, b
        ))),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6000, ..ProptestConfig::default() })]

    #[test]
    fn tracers_match_brute_force((hf, ray, (t0, t1)) in scene()) {
        let want = brute_force(&hf, &ray, t0, t1).unwrap();
        let (lo, hi) = hf.min_max();
        let scale = (hi - lo).max(hf.extent().max_element()).max(1.0);
        let grid = GridTracer::new(&hf).unwrap();
        let mip = MipmapTracer::new(&hf).unwrap();
        check("grid", grid.trace(&ray, t0, t1), want, scale)?;
        check("mipmap", mip.trace(&ray, t0, t1), want, scale)?;
        // Any-hit agrees with closest-hit on whether anything lies in range.
        prop_assert_eq!(grid.occluded(&ray, t0, t1), want.is_some());
        prop_assert_eq!(mip.occluded(&ray, t0, t1), want.is_some());
    }
}
