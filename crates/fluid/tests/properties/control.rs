//! Control curves (Foster & Fedkiw 2001, §10): the spline and its rate
//! against closed forms, liquid led along a curve against the same liquid
//! left alone, and bad curves refused by name.

use super::*;
use natura_fluid::liquid::ControlCurve;

fn curve(points: Vec<Vec3>) -> ControlCurve {
    ControlCurve {
        points,
        rate: vec![(0.0, 0.5), (1.0, 1.5), (2.0, 0.0)],
        points_at: vec![0.0],
        radius: 0.1,
    }
}

#[test]
fn the_curve_passes_its_points_with_the_derivative_of_its_position() {
    let pts = vec![
        Vec3::new(0.1, 0.2, 0.3),
        Vec3::new(0.5, 0.2, 0.6),
        Vec3::new(0.9, 0.4, 0.5),
        Vec3::new(1.0, 0.8, 0.2),
    ];
    let c = curve(pts.clone());
    c.validate().unwrap();
    for (i, p) in pts.iter().enumerate() {
        let (x, _) = c.at(i as f32 / 3.0);
        assert!((x - *p).length() < 1e-5, "{x} against {p}");
    }
    // dF/dφ against central differences, inside segments.
    for s in [0.05f32, 0.3, 0.5, 0.71, 0.95] {
        let e = 1e-3;
        let fd = (c.at(s + e).0 - c.at(s - e).0) / (2.0 * e);
        let (_, d) = c.at(s);
        assert!(
            (fd - d).length() < 1e-2 * d.length().max(1.0),
            "{fd} against {d} at {s}"
        );
    }
    // The rate: linear between keys, held outside; its integral exact.
    assert_eq!(c.rate_at(-1.0), 0.5);
    assert!((c.rate_at(0.5) - 1.0).abs() < 1e-6);
    assert_eq!(c.rate_at(3.0), 0.0);
    // ∫₀² C = ½(0.5 + 1.5) + ½(1.5 + 0) = 1.75, in one step or many.
    assert!((c.advance(0.0, 2.0) - 1.75).abs() < 1e-6);
    let many: f32 = (0..40).map(|i| c.advance(i as f32 * 0.05, 0.05)).sum();
    assert!((many - 1.75).abs() < 1e-4, "{many}");
}

/// The liquid's centroid (m) from the cells with φ < 0.
/// Cells with liquid at their centre.
fn cells(l: &Liquid) -> f64 {
    l.level_set()
        .phi()
        .as_slice()
        .iter()
        .filter(|p| **p < 0.0)
        .count() as f64
}

fn centroid(l: &Liquid) -> Vec3 {
    let phi = l.level_set().phi();
    let (nx, ny, nz) = phi.dims();
    let (mut sum, mut n) = (Vec3::ZERO, 0.0f32);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if phi[(i, j, k)] < 0.0 {
                    sum += (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * l.h();
                    n += 1.0;
                }
            }
        }
    }
    sum / n
}

#[test]
fn liquid_is_led_along_the_curve() {
    // Without gravity a ball of liquid at rest stays where it is; a point
    // moving along a curve from its centre leads it along.
    let run = |controlled: bool| {
        let params = LiquidParams {
            gravity: Vec3::ZERO,
            ..LiquidParams::default()
        };
        let mut l = Liquid::new(Dims::new(32, 12, 16).unwrap(), 0.05, params).unwrap();
        l.fill(
            Shape::Sphere {
                centre: Vec3::new(0.4, 0.3, 0.4),
                radius: 0.15,
            },
            Vec3::ZERO,
        )
        .unwrap();
        if controlled {
            l.add_control(ControlCurve {
                points: vec![
                    Vec3::new(0.4, 0.3, 0.4),
                    Vec3::new(0.8, 0.3, 0.5),
                    Vec3::new(1.2, 0.3, 0.4),
                ],
                rate: vec![(0.0, 0.8)],
                points_at: vec![0.0, 0.05, 0.1],
                radius: 0.12,
            })
            .unwrap();
            assert_eq!(l.control_points().len(), 3);
        }
        let c0 = cells(&l);
        for _ in 0..10 {
            l.step(0.1).unwrap();
        }
        (centroid(&l), cells(&l) / c0, l)
    };
    let (still, _, _) = run(false);
    let (led, kept, l) = run(true);
    assert!(
        (still.x - 0.4).abs() < 0.02,
        "uncontrolled centroid {still}"
    );
    // The points ran 0.8 of the curve (to x ≈ 1.05) in the second.
    assert!(led.x > 0.7, "controlled centroid {led}");
    // Drawn out into a thread a few cells thick, the liquid's cells are
    // 0.82 of what they were (and its smoothed volume reads 1.23: neither
    // measure is sharp for so thin a shape); it neither vanishes nor grows.
    assert!((0.7..1.3).contains(&kept), "liquid cells kept {kept}");
    // Points past the curve's end stop acting.
    assert_eq!(l.control_points().len(), 3);
    let mut l = l;
    for _ in 0..3 {
        l.step(0.1).unwrap();
    }
    assert_eq!(l.control_points().len(), 0);
}

#[test]
fn bad_curves_are_refused_by_name() {
    let good = curve(vec![Vec3::ZERO, Vec3::ONE]);
    let cases: Vec<(ControlCurve, &str)> = vec![
        (
            ControlCurve {
                points: vec![Vec3::ZERO],
                ..good.clone()
            },
            "points",
        ),
        (
            ControlCurve {
                points: vec![Vec3::ZERO, Vec3::splat(f32::NAN)],
                ..good.clone()
            },
            "points",
        ),
        (
            ControlCurve {
                rate: vec![],
                ..good.clone()
            },
            "rate",
        ),
        (
            ControlCurve {
                rate: vec![(0.0, 1.0), (0.0, 2.0)],
                ..good.clone()
            },
            "rate",
        ),
        (
            ControlCurve {
                rate: vec![(0.0, -1.0)],
                ..good.clone()
            },
            "rate",
        ),
        (
            ControlCurve {
                points_at: vec![1.5],
                ..good.clone()
            },
            "points_at",
        ),
        (
            ControlCurve {
                radius: 0.0,
                ..good.clone()
            },
            "radius",
        ),
    ];
    let mut l = Liquid::new(Dims::new(8, 8, 8).unwrap(), 0.1, LiquidParams::default()).unwrap();
    for (c, name) in cases {
        let e = l.add_control(c).unwrap_err();
        assert!(
            matches!(&e, FluidError::InvalidParameter { name: n, .. } if *n == name),
            "{e} should name {name}"
        );
    }
}
