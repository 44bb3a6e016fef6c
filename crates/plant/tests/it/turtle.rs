//! Turtle interpretation: closed-form positions, frame orthonormality,
//! tropism, queries, generalized-cylinder chaining, differential geometry.

use approx::assert_abs_diff_eq;
use glam::DVec3;
use natura_plant::turtle::{TurtleFrame, track_curve};
use natura_plant::{Derivation, LSystem, Turtle, TurtleParams};

fn params_x(angle: f64) -> TurtleParams {
    TurtleParams {
        angle_deg: angle,
        start: TurtleFrame::new(DVec3::ZERO, DVec3::X, DVec3::Y),
        ..TurtleParams::default()
    }
}

fn end_point(src: &str, n: u32, p: TurtleParams) -> DVec3 {
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    d.derive(n).unwrap();
    let t = Turtle::new(&l, p).unwrap();
    let mut last = DVec3::ZERO;
    let s = d.string();
    t.visit(s, |_, st| last = st.frame.p).unwrap();
    // The state before the last module; add the last move if it is F.
    let g = t.interpret(s).unwrap();
    if let Some(e) = g.end.last()
        && s.symbols().last() == l.symbol("F").as_ref()
    {
        last = e.as_dvec3();
    }
    last
}

#[test]
fn koch_curve_ends_at_three_to_the_n() {
    for n in 0..4 {
        let e = end_point("axiom: F\nF -> F+F--F+F", n, params_x(60.0));
        assert_abs_diff_eq!(e.x, 3f64.powi(n as i32), epsilon = 1e-4);
        assert_abs_diff_eq!(e.y, 0.0, epsilon = 1e-4);
        assert_abs_diff_eq!(e.z, 0.0, epsilon = 1e-9);
    }
}

#[test]
fn closed_curves_close() {
    // ABOP Fig. 1.7a: the quadratic Koch island is closed for every n.
    let src = "axiom: F-F-F-F\nF -> F+FF-FF-F-F+F+FF-F-F+F+FF+FF-F";
    for n in 0..3 {
        let l = LSystem::parse(src).unwrap();
        let mut d = Derivation::new(&l, 0).unwrap();
        d.derive(n).unwrap();
        let g = Turtle::new(&l, params_x(90.0))
            .unwrap()
            .interpret(d.string())
            .unwrap();
        let last = g.end.last().unwrap();
        assert!(last.length() < 1e-3, "n={n}: {last}");
    }
}

#[test]
fn square_positions_closed_form() {
    let l = LSystem::parse("axiom: F(2)+F(2)+F(2)+F(2)").unwrap();
    let g = Turtle::new(&l, params_x(90.0))
        .unwrap()
        .interpret(l.axiom())
        .unwrap();
    let expect = [(2.0, 0.0), (2.0, 2.0), (0.0, 2.0), (0.0, 0.0)];
    for (e, (x, y)) in g.end.iter().zip(expect) {
        assert_abs_diff_eq!(e.x, x, epsilon = 1e-6);
        assert_abs_diff_eq!(e.y, y, epsilon = 1e-6);
    }
    // Pitch and roll: &(90) points the heading along −U, /(90) moves L to U.
    let mut f = TurtleFrame::default();
    f.pitch(std::f64::consts::FRAC_PI_2);
    assert_abs_diff_eq!((f.h - DVec3::Y).length(), 0.0, epsilon = 1e-12);
    let mut f = TurtleFrame::default();
    let u0 = f.u;
    f.roll(std::f64::consts::FRAC_PI_2);
    assert_abs_diff_eq!((f.l - u0).length(), 0.0, epsilon = 1e-12);
    let mut f = TurtleFrame::default();
    let l0 = f.l;
    f.turn(std::f64::consts::FRAC_PI_2);
    assert_abs_diff_eq!((f.h - l0).length(), 0.0, epsilon = 1e-12);
}

#[test]
fn frame_stays_orthonormal_after_a_million_turns() {
    let mut f = TurtleFrame::default();
    for k in 0..1_000_000u32 {
        let a = 0.1 + (k % 97) as f64 * 0.013;
        match k % 3 {
            0 => f.turn(a),
            1 => f.pitch(-a * 0.7),
            _ => f.roll(a * 1.3),
        }
    }
    assert_abs_diff_eq!(f.h.length(), 1.0, epsilon = 1e-12);
    assert_abs_diff_eq!(f.l.length(), 1.0, epsilon = 1e-12);
    assert_abs_diff_eq!(f.u.length(), 1.0, epsilon = 1e-12);
    assert_abs_diff_eq!(f.h.dot(f.l), 0.0, epsilon = 1e-12);
    assert_abs_diff_eq!((f.h.cross(f.l) - f.u).length(), 0.0, epsilon = 1e-12);
}

#[test]
fn tropism_bends_towards_its_vector() {
    let l = LSystem::parse("axiom: +(90)FFFFFFFFFFFFFFFFFFFF").unwrap();
    let p = TurtleParams {
        tropism: DVec3::new(0.0, 0.0, -1.0),
        elasticity: 0.2,
        ..TurtleParams::default()
    };
    let g = Turtle::new(&l, p).unwrap().interpret(l.axiom()).unwrap();
    let dirs: Vec<f32> = g
        .start
        .iter()
        .zip(&g.end)
        .map(|(a, b)| (*b - *a).normalize().z)
        .collect();
    assert_abs_diff_eq!(dirs[0], 0.0, epsilon = 1e-6);
    for w in dirs.windows(2) {
        assert!(w[1] < w[0], "{dirs:?}");
    }
    assert!(*dirs.last().unwrap() < -0.9);
    // Without elasticity the branch stays horizontal.
    let g = Turtle::new(&l, TurtleParams::default())
        .unwrap()
        .interpret(l.axiom())
        .unwrap();
    assert_abs_diff_eq!(g.end.last().unwrap().z, 0.0, epsilon = 1e-5);
}

#[test]
fn vogel_positions_from_query_modules() {
    // ABOP §4.1, eq. 4.1: the n-th organ at radius c·√n and angle n·137.5°.
    let src = "ω: A(0)\nA(n) -> +(137.5)[f(n^0.5)?P(0,0,0)]A(n+1)";
    let l = LSystem::parse(src).unwrap();
    let p = TurtleParams {
        start: TurtleFrame::new(DVec3::ZERO, DVec3::X, DVec3::Y),
        ..TurtleParams::default()
    };
    let t = Turtle::new(&l, p).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    d.derive(40).unwrap();
    d.fill_queries(&t).unwrap();
    let q = l.symbol("?P").unwrap();
    let s = d.string();
    let pts: Vec<&[f64]> = (0..s.len())
        .filter(|&i| s.symbol(i) == q)
        .map(|i| s.params(i))
        .collect();
    assert_eq!(pts.len(), 40);
    for (n, p) in pts.iter().enumerate() {
        let r = p[0].hypot(p[1]);
        assert_abs_diff_eq!(r, (n as f64).sqrt(), epsilon = 1e-9);
        if n > 0 {
            let phi = p[1].atan2(p[0]).to_degrees().rem_euclid(360.0);
            let expect = ((n + 1) as f64 * 137.5).rem_euclid(360.0);
            assert_abs_diff_eq!(phi, expect, epsilon = 1e-6);
        }
    }
}

#[test]
fn segments_chain_into_cylinders() {
    let l = LSystem::parse("axiom: F F [+F F] F f F").unwrap();
    let g = Turtle::new(&l, TurtleParams::default())
        .unwrap()
        .interpret(l.axiom())
        .unwrap();
    assert_eq!(g.segment_count(), 6);
    let none = u32::MAX;
    assert_eq!(g.prev, vec![none, 0, none, 2, 1, none]);
    assert_eq!(g.dist1[3], 4.0);
    assert_eq!(g.dist1[4], 3.0);
}

#[test]
fn polygons_and_surfaces() {
    let l = LSystem::parse("angle: 90\naxiom: {.f+f+f+f} ~L(2,1) @o(0.5) '(3)~O(1)").unwrap();
    let t = Turtle::new(&l, TurtleParams::for_lsystem(&l)).unwrap();
    let g = t.interpret(l.axiom()).unwrap();
    assert_eq!(g.polygons.len(), 1);
    assert_eq!(g.polygons[0].vertices.len(), 4);
    assert_eq!(g.surfaces.len(), 3);
    assert_eq!(g.surfaces[0].name, 'L');
    assert_eq!(g.surfaces[2].colour, 3);
    // The parser refuses an unbalanced axiom; the turtle, a string built otherwise.
    assert!(LSystem::parse("axiom: F]F").is_err());
    let l = LSystem::parse("axiom: F[F]").unwrap();
    let t = Turtle::new(&l, TurtleParams::default()).unwrap();
    assert!(t.interpret(&l.parse_string("F]F").unwrap()).is_err());
    let l = LSystem::parse("axiom: {.f.").unwrap();
    let t = Turtle::new(&l, TurtleParams::default()).unwrap();
    assert!(t.interpret(l.axiom()).is_err());
}

#[test]
fn homomorphism_draws_without_changing_the_string() {
    let src = "ω: A\nA -> AB\nhomomorphism:\nB -> F(2)";
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    d.derive(3).unwrap();
    assert_eq!(d.string().display(l.symbols()), "ABBB");
    let g = Turtle::new(&l, TurtleParams::default())
        .unwrap()
        .interpret(d.string())
        .unwrap();
    assert_eq!(g.segment_count(), 3);
    assert_abs_diff_eq!(g.end[2].z, 6.0);
}

#[test]
fn parallel_transport_tracks_a_helix() {
    // Prusinkiewicz et al. 2001, §3, eq. 10: the turtle tracks a curve given by
    // its tangent; the error shrinks linearly with the step.
    let (r, c) = (1.0f64, 0.3f64);
    let k = (r * r + c * c).sqrt();
    let point = |s: f64| DVec3::new(r * (s / k).cos(), r * (s / k).sin(), c * s / k);
    let tangent = |s: f64| DVec3::new(-r * (s / k).sin(), r * (s / k).cos(), c).normalize();
    let h0 = tangent(0.0);
    let start = TurtleFrame::new(point(0.0), h0, DVec3::Z.cross(h0));
    let err = |ds: f64| {
        let fr = track_curve(start, 6.0, ds, tangent).unwrap();
        fr.iter()
            .enumerate()
            .map(|(i, f)| (f.p - point(i as f64 * ds)).length())
            .fold(0.0, f64::max)
    };
    let (e1, e2) = (err(0.01), err(0.005));
    assert!(e1 < 0.05, "{e1}");
    let ratio = e1 / e2;
    assert!((1.6..2.5).contains(&ratio), "{e1} {e2} {ratio}");
    // A straight line keeps the frame (no twist about H).
    let fr = track_curve(TurtleFrame::default(), 1.0, 0.1, |_| DVec3::Z).unwrap();
    assert_eq!(fr.len(), 11);
    for f in &fr {
        assert_abs_diff_eq!((f.l - DVec3::NEG_X).length(), 0.0, epsilon = 1e-12);
    }
}

/// Mean `z` of the unit directions of the segments that end at a tip (no
/// segment starts where they end).
fn mean_tip_direction_z(g: &natura_plant::Geometry) -> f64 {
    let starts: std::collections::HashSet<[u32; 3]> = g
        .start
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    let dirs: Vec<f64> = g
        .start
        .iter()
        .zip(&g.end)
        .filter(|(_, b)| !starts.contains(&b.to_array().map(f32::to_bits)))
        .map(|(a, b)| f64::from((*b - *a).normalize().z))
        .collect();
    assert!(!dirs.is_empty());
    dirs.iter().sum::<f64>() / dirs.len() as f64
}

#[test]
fn tropism_directive_bends_the_ternary_tree_down() {
    // ABOP fig. 2.8a: T = (0, -1, 0) in the book's y-up frame, e = 0.22.
    let bent = include_str!("../../../../examples/lsystems/fig2_8.l");
    let straight: String = bent
        .lines()
        .filter(|l| !l.starts_with("tropism:"))
        .collect::<Vec<_>>()
        .join("\n");
    let tips = |src: &str| {
        let l = LSystem::parse(src).unwrap();
        let mut d = Derivation::new(&l, 0).unwrap();
        d.derive(l.derivation_length()).unwrap();
        let p = TurtleParams::for_lsystem(&l);
        let g = Turtle::new(&l, p).unwrap().interpret(d.string()).unwrap();
        (l, g)
    };
    let (lb, gb) = tips(bent);
    let (ls, gs) = tips(&straight);
    assert_eq!(lb.tropism(), Some(([0.0, 0.0, -1.0], 0.22)));
    assert_eq!(ls.tropism(), None);
    assert_eq!(gb.start.len(), gs.start.len());
    let (zb, zs) = (mean_tip_direction_z(&gb), mean_tip_direction_z(&gs));
    // Without tropism the tips point up on average; with it they droop.
    assert!(zs > 0.3, "{zs}");
    assert!(zb < zs - 0.3, "bent {zb} vs straight {zs}");
    // The directive sets exactly the turtle's own tropism fields.
    let p = TurtleParams {
        tropism: DVec3::new(0.0, 0.0, -1.0),
        elasticity: 0.22,
        ..TurtleParams::for_lsystem(&ls)
    };
    let mut d = Derivation::new(&ls, 0).unwrap();
    d.derive(ls.derivation_length()).unwrap();
    let g = Turtle::new(&ls, p).unwrap().interpret(d.string()).unwrap();
    assert_eq!(g.end, gb.end);
}

#[test]
fn tropism_directive_with_macros_and_heading() {
    // Expressions and macros are allowed; the heading bends towards T.
    let l = LSystem::parse("#define e 0.1\ntropism: 1, 0, 0, e*2\naxiom: FFFFFFFFFF").unwrap();
    assert_eq!(l.tropism(), Some(([1.0, 0.0, 0.0], 0.2)));
    let g = Turtle::new(&l, TurtleParams::for_lsystem(&l))
        .unwrap()
        .interpret(l.axiom())
        .unwrap();
    let xs: Vec<f32> = g
        .start
        .iter()
        .zip(&g.end)
        .map(|(a, b)| (*b - *a).normalize().x)
        .collect();
    for w in xs.windows(2) {
        assert!(w[1] > w[0], "{xs:?}");
    }
    assert!(*xs.last().unwrap() > 0.9, "{xs:?}");
}

#[test]
fn appended_geometry_keeps_each_plants_segments_and_links() {
    // Two plants in one geometry: every segment, link and surface of both,
    // the second's links shifted past the first's segments.
    let draw = |text: &str| {
        let l = LSystem::parse(text).unwrap();
        let mut d = Derivation::new(&l, 0).unwrap();
        d.derive(2).unwrap();
        Turtle::new(&l, TurtleParams::for_lsystem(&l))
            .unwrap()
            .interpret(d.string())
            .unwrap()
    };
    let a = draw("ω: F\nF -> F[+F]F\n");
    let b = draw("ω: FF~L(1)\n");
    let mut g = a.clone();
    g.append(&b);
    assert_eq!(g.segment_count(), a.segment_count() + b.segment_count());
    assert_eq!(g.surfaces.len(), a.surfaces.len() + b.surfaces.len());
    let n = a.segment_count();
    assert_eq!(&g.start[n..], &b.start[..]);
    assert_eq!(&g.prev[..n], &a.prev[..]);
    for (k, &p) in b.prev.iter().enumerate() {
        let q = g.prev[n + k];
        assert_eq!(q, if p == u32::MAX { p } else { p + n as u32 });
    }
    assert!(b.prev.iter().any(|&p| p != u32::MAX));
}
