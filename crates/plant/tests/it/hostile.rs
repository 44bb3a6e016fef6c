//! Hostile L-system text: deep nesting, exponential macros, huge arrays,
//! endless derivations, runaway interpretation rules, polygons of many
//! vertices and numbers out of range all end in a typed error naming what
//! the text says, quickly and within the stated limits.

use natura_plant::turtle::{MAX_POLYGON_VERTICES, TurtleFrame, track_curve};
use natura_plant::{Derivation, LSystem, Limits, PlantError, Turtle, TurtleParams};

fn syntax(text: &str) -> (PlantError, String) {
    let e = LSystem::parse(text).unwrap_err();
    let m = e.to_string();
    assert!(matches!(e, PlantError::Syntax { .. }), "{m}");
    (e, m)
}

fn small() -> Limits {
    Limits {
        max_modules: 1000,
        max_params: 4000,
        max_work: 100_000,
    }
}

#[test]
fn deep_parentheses_are_refused_and_moderate_ones_work() {
    let deep = format!("axiom: A({}1{})", "(".repeat(5000), ")".repeat(5000));
    let (e, m) = syntax(&deep);
    assert!(m.contains("nested deeper than 256"), "{m}");
    assert_eq!(e.span().unwrap().line, 1);
    let ok = format!("axiom: A({}1{})", "(".repeat(200), ")".repeat(200));
    let l = LSystem::parse(&ok).unwrap();
    assert_eq!(l.axiom().params(0), &[1.0]);
}

#[test]
fn deep_prefix_operators_ternaries_and_blocks_are_refused() {
    for text in [
        format!("axiom: A({}1)", "-".repeat(30_000)),
        format!("axiom: A({}1)", "!".repeat(30_000)),
        format!("axiom: A({}2)", "2^".repeat(30_000)),
        format!("axiom: A({}1{})", "1?(".repeat(5000), ":1)".repeat(5000)),
        format!(
            "axiom: A(1)\nA(x) : {{ {} x = 1; {} }} 1 -> A(x)",
            "if (1) {".repeat(5000),
            "}".repeat(5000)
        ),
    ] {
        let (e, m) = syntax(&text);
        assert!(m.contains("nested deeper than"), "{m}");
        assert!(e.span().is_some());
    }
}

#[test]
fn a_flat_sum_of_thirty_thousand_terms_works() {
    let sum = vec!["1"; 30_000].join("+");
    let l = LSystem::parse(&format!("axiom: A({sum})\nA(x) -> A(x+{sum})")).unwrap();
    assert_eq!(l.axiom().params(0), &[30_000.0]);
    let mut d = Derivation::new(&l, 0).unwrap();
    d.step().unwrap();
    assert_eq!(d.string().params(0), &[60_000.0]);
    let and = vec!["1"; 30_000].join(" && ");
    let l = LSystem::parse(&format!("axiom: A({and})")).unwrap();
    assert_eq!(l.axiom().params(0), &[1.0]);
}

#[test]
fn maximum_depth_is_capped() {
    for section in ["decomposition", "homomorphism"] {
        let (_, m) = syntax(&format!(
            "axiom: A\n{section}:\nmaximum depth: 100000\nA -> A"
        ));
        assert!(m.contains("`maximum depth: 100000`"), "{m}");
        assert!(m.contains("256"), "{m}");
    }
    // At the cap, a rule that recurses for ever stops with a depth error.
    let l = LSystem::parse("axiom: A\ndecomposition:\nmaximum depth: 256\nA -> A").unwrap();
    let e = Derivation::new(&l, 0).unwrap_err();
    assert!(matches!(e, PlantError::Depth { depth: 256, .. }), "{e}");
}

#[test]
fn doubling_macros_are_refused() {
    let mut text = String::from("#define a0 1\n");
    for k in 1..=30 {
        text.push_str(&format!("#define a{k} (a{0} + a{0})\n", k - 1));
    }
    text.push_str("axiom: A(a30)");
    let (_, m) = syntax(&text);
    assert!(m.contains("operations"), "{m}");
}

#[test]
fn arrays_are_bounded_in_all() {
    let mut text = String::new();
    for k in 0..300 {
        text.push_str(&format!("array M{k}[10000000] = {{1}}\n"));
    }
    text.push_str("axiom: A");
    let (_, m) = syntax(&text);
    assert!(m.contains("`M1`") && m.contains("16777216"), "{m}");
    let (_, m) = syntax("array M[1e8] = {1}\naxiom: A");
    assert!(m.contains("`M`") && m.contains("1..=10000000"), "{m}");
}

#[test]
fn a_text_over_the_source_limit_is_refused_before_parsing() {
    let text = " ".repeat(natura_plant::lang::MAX_SOURCE_BYTES + 1);
    let (_, m) = syntax(&text);
    assert!(m.contains("16 MiB"), "{m}");
}

#[test]
fn an_endless_derivation_runs_out_of_work() {
    let l = LSystem::parse("derivation length: 4294967295\naxiom: A").unwrap();
    let mut d = Derivation::with_limits(&l, 0, small()).unwrap();
    let e = d.derive(l.derivation_length()).unwrap_err();
    let m = e.to_string();
    assert!(m.contains("`max_work` = 100000"), "{m}");
    assert!(
        matches!(
            e,
            PlantError::Work {
                max_work: 100_000,
                ..
            }
        ),
        "{m}"
    );
    assert!(d.work() <= 100_000);
}

#[test]
fn decomposition_and_interpretation_output_count_against_the_limits() {
    // The axiom decomposes into 2^40 modules.
    let rule = "maximum depth: 64\nA(n) : n > 0 -> A(n-1)A(n-1)";
    let l = LSystem::parse(&format!("axiom: A(40)\ndecomposition:\n{rule}")).unwrap();
    let e = Derivation::with_limits(&l, 0, small()).unwrap_err();
    assert!(
        matches!(
            e,
            PlantError::Growth {
                max_modules: 1000,
                ..
            }
        ),
        "{e}"
    );
    let l = LSystem::parse(&format!("axiom: A(40)\nhomomorphism:\n{rule}")).unwrap();
    let d = Derivation::with_limits(&l, 0, small()).unwrap();
    let t = Turtle::new(&l, TurtleParams::default())
        .unwrap()
        .with_limits(small());
    let e = t.interpret(d.string()).unwrap_err();
    assert!(
        matches!(
            e,
            PlantError::Growth {
                max_modules: 1000,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn the_buffers_stay_within_the_stated_memory() {
    // The documented figure holds at the defaults.
    assert!(Limits::default().memory_bound() <= 2_500_000_000);
    // Runaway growth stops with the buffers no larger than the limits.
    let l = LSystem::parse("axiom: A(1)\nA(x) -> A(x)A(x)B").unwrap();
    let limits = Limits {
        max_modules: 1000,
        max_params: 700,
        max_work: u64::MAX,
    };
    let mut d = Derivation::with_limits(&l, 0, limits).unwrap();
    let e = d.derive(30).unwrap_err();
    assert!(matches!(e, PlantError::Growth { .. }), "{e}");
    let bound = 2 * (4 * 1000 + 4 * 1001 + 8 * 700);
    assert!(d.memory_bytes() <= bound, "{} > {bound}", d.memory_bytes());
}

#[test]
fn many_polygon_vertices_are_refused_quickly() {
    let n = 100_000;
    let text = format!("axiom: {{{}}}", "+f".repeat(n));
    let l = LSystem::parse(&text).unwrap();
    let d = Derivation::new(&l, 0).unwrap();
    let t = Turtle::new(&l, TurtleParams::default()).unwrap();
    let e = t.interpret(d.string()).unwrap_err();
    let m = e.to_string();
    assert!(matches!(e, PlantError::Interpret { .. }), "{m}");
    assert!(m.contains(&MAX_POLYGON_VERTICES.to_string()), "{m}");
    // At the limit (`{` records the first vertex), a polygon still meshes.
    let text = format!(
        "angle: 0.3\naxiom: {{{}}}",
        "+f".repeat(MAX_POLYGON_VERTICES - 1)
    );
    let l = LSystem::parse(&text).unwrap();
    let d = Derivation::new(&l, 0).unwrap();
    let t = Turtle::new(&l, TurtleParams::for_lsystem(&l)).unwrap();
    let g = t.interpret(d.string()).unwrap();
    assert_eq!(g.polygons.len(), 1);
}

#[test]
fn track_curve_refuses_too_many_samples() {
    let e = track_curve(TurtleFrame::default(), 1e300, 1e-300, |_| glam::DVec3::Z).unwrap_err();
    let m = e.to_string();
    assert!(matches!(e, PlantError::InvalidParameter { .. }), "{m}");
    assert!(m.contains("ds"), "{m}");
    for (len, ds) in [
        (f64::NAN, 0.1),
        (1.0, 0.0),
        (-1.0, 0.1),
        (1.0, f64::INFINITY),
    ] {
        assert!(track_curve(TurtleFrame::default(), len, ds, |_| glam::DVec3::Z).is_err());
    }
}

#[test]
fn out_of_range_sizes_name_the_module_or_directive() {
    let l = LSystem::parse("axiom: F(1)F(1e308)").unwrap();
    let t = Turtle::new(&l, TurtleParams::for_lsystem(&l)).unwrap();
    let e = t.interpret(l.axiom()).unwrap_err();
    let m = e.to_string();
    assert!(m.contains("F(1e308)") && m.contains("step length"), "{m}");
    assert!(m.contains("1e12"), "{m}");
    let (_, m) = syntax("step: 1e300\naxiom: F");
    assert!(m.contains("`step: 1e300`") && m.contains("1e12"), "{m}");
    let (_, m) = syntax("tropism: 1e300, 0, 0, 1\naxiom: F");
    assert!(m.contains("`tropism:`") && m.contains("1e300"), "{m}");
    let l = LSystem::parse("axiom: !(1e300)F").unwrap();
    let t = Turtle::new(&l, TurtleParams::default()).unwrap();
    let m = t.interpret(l.axiom()).unwrap_err().to_string();
    assert!(m.contains("!(1e300)") && m.contains("width"), "{m}");
}

#[test]
fn unbalanced_brackets_are_syntax_errors() {
    for (text, line, col) in [
        ("axiom: F[F", 1, 9),
        ("axiom: F\nF -> F[+F", 2, 7),
        ("axiom: F]F", 1, 9),
        ("axiom: F\n\nF -> F]", 3, 7),
    ] {
        let (e, m) = syntax(text);
        assert_eq!(e.span().unwrap(), natura_plant::Span::new(line, col), "{m}");
        assert!(m.contains('[') || m.contains(']'), "{m}");
    }
    let (_, m) = syntax("axiom: A(1");
    assert!(m.contains("`(`"), "{m}");
    let (_, m) = syntax("axiom: A(1 B");
    assert!(m.contains("`(`"), "{m}");
}

#[test]
fn a_byte_order_mark_is_accepted() {
    let l = LSystem::parse("\u{feff}axiom: F\nF -> FF").unwrap();
    assert_eq!(l.axiom().display(l.symbols()), "F");
}

#[test]
fn a_cut_in_the_axiom_is_applied() {
    let l = LSystem::parse("axiom: F[F%F[F]F]F").unwrap();
    let d = Derivation::new(&l, 0).unwrap();
    assert_eq!(d.string().display(l.symbols()), "F[F]F");
}

mod property {
    use natura_plant::{Derivation, LSystem, Limits, PlantError, Turtle, TurtleParams};
    use proptest::prelude::*;

    const TOKENS: &[&str] = &[
        "A",
        "B",
        "F",
        "f",
        "+",
        "-",
        "[",
        "]",
        "{",
        "}",
        ".",
        "%",
        "(",
        ")",
        ",",
        "1",
        "2.5",
        "1e308",
        "-1e308",
        "1e-300",
        "x",
        "y",
        "->",
        ":",
        "<",
        ">",
        "\n",
        "axiom: ",
        "derivation length: ",
        "maximum depth: ",
        "decomposition:\n",
        "homomorphism:\n",
        "#define m ",
        "#define g(a) ",
        "m",
        "g(",
        "array M[",
        "= {",
        "M[",
        "if (",
        "while (",
        ";",
        "?",
        "!",
        "^",
        "*",
        "/",
        "&&",
        "||",
        "~L",
        "@o",
        " ",
        "4294967295",
        "999999",
        "step: ",
        "angle: ",
        "tropism: ",
        "seed: ",
        "\u{feff}",
        "ε",
        "(((((((((((((((((",
        ")))))))))))))))))",
        "/*",
        "*/",
        "p1: ",
        "A(x) -> A(x+1)",
        "A -> AA",
        "x = x + 1;",
    ];

    fn text() -> impl Strategy<Value = String> {
        prop_oneof![
            // Random mixes of the language's tokens (up to 64 KiB).
            prop::collection::vec(prop::sample::select(TOKENS), 0..4000).prop_map(|t| t.concat()),
            // A production or an axiom around deep nesting.
            (
                0usize..2000,
                prop::sample::select(&["(", "-", "!", "2^", "1?("][..])
            )
                .prop_map(|(n, t)| format!("axiom: A({}1)\nA(x) -> A(x)", t.repeat(n))),
            // Huge numbers and counts in directives.
            (
                prop::sample::select(
                    &[
                        "derivation length",
                        "maximum depth",
                        "step",
                        "angle",
                        "seed"
                    ][..]
                ),
                any::<f64>()
            )
                .prop_map(|(k, v)| format!("{k}: {v:e}\naxiom: F(1)[+F]F\nF -> FF")),
            // Arbitrary characters, and arbitrary bytes read as text.
            "\\PC{0,2000}",
            prop::collection::vec(any::<u8>(), 0..4000)
                .prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]
        #[test]
        fn any_text_derives_within_limits_or_errs_with_a_position(text in text()) {
            assert!(text.len() <= 64 << 10);
            let l = match LSystem::parse(&text) {
                Ok(l) => l,
                Err(e) => {
                    let s = e.span();
                    prop_assert!(s.is_some_and(|s| s.line >= 1 && s.col >= 1), "{}", e);
                    return Ok(());
                }
            };
            let limits = Limits { max_modules: 5000, max_params: 20_000, max_work: 200_000 };
            let Ok(mut d) = Derivation::with_limits(&l, 7, limits) else {
                return Ok(());
            };
            let r = d.derive(l.derivation_length());
            prop_assert!(d.work() <= limits.max_work + limits.max_modules as u64);
            prop_assert!(d.string().len() <= limits.max_modules);
            prop_assert!(d.string().param_count() <= limits.max_params);
            if let Err(e) = r {
                let positioned = e.span().is_some();
                prop_assert!(
                    positioned || matches!(e, PlantError::Growth { .. } | PlantError::Work { .. }),
                    "{}", e
                );
                return Ok(());
            }
            let t = Turtle::new(&l, TurtleParams::for_lsystem(&l)).unwrap().with_limits(limits);
            if let Ok(g) = t.interpret(d.string())
                && let Some((lo, hi)) = g.bounds() {
                    prop_assert!(lo.is_finite() && hi.is_finite());
                }
        }
    }
}
