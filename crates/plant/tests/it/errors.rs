//! Bad input: typed errors with line and column, never a panic.

use natura_plant::{Derivation, LSystem, Limits, PlantError};
use proptest::prelude::*;

#[test]
fn syntax_errors_point_at_line_and_column() {
    let e = LSystem::parse("axiom: A\nA(x -> B").unwrap_err();
    let s = e.span().unwrap();
    assert_eq!(s.line, 2);
    assert!(matches!(e, PlantError::Syntax { .. }), "{e}");
    let e = LSystem::parse("axiom: A\n\nA -> B(y)").unwrap_err();
    assert!(
        matches!(
            e,
            PlantError::Undefined {
                what: "variable",
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(e.span().unwrap(), natura_plant::Span::new(3, 8));
    let e = LSystem::parse("axiom: A\nA(x) -> B(foo(x))").unwrap_err();
    assert!(
        matches!(
            e,
            PlantError::Undefined {
                what: "function",
                ..
            }
        ),
        "{e}"
    );
    let e = LSystem::parse("A -> B").unwrap_err();
    assert!(e.to_string().contains("no axiom"), "{e}");
    let e = LSystem::parse("axiom: A /* open").unwrap_err();
    assert!(matches!(e, PlantError::Syntax { .. }));
}

#[test]
fn division_by_zero_and_nan_name_the_production() {
    let l = LSystem::parse("axiom: A(0)\np7: A(x) -> A(1/x)").unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    let e = d.step().unwrap_err();
    match &e {
        PlantError::Eval {
            span,
            production,
            message,
        } => {
            assert_eq!(span.line, 2);
            assert_eq!(span.col, 16);
            assert_eq!(production, "production p7");
            assert!(message.contains("division by zero"));
        }
        other => panic!("{other}"),
    }
    // The string is left as before the failed step.
    assert_eq!(d.string().display(l.symbols()), "A(0)");
    let l = LSystem::parse("axiom: A(-1)\nA(x) -> A(sqrt(x))").unwrap();
    let e = Derivation::new(&l, 0).unwrap().step().unwrap_err();
    assert!(e.to_string().contains("NaN"), "{e}");
    let l = LSystem::parse("axiom: A(5)\narray M[2] = {1, 2}\nA(x) -> A(M[x])").unwrap();
    let e = Derivation::new(&l, 0).unwrap().step().unwrap_err();
    assert!(e.to_string().contains("out of range"), "{e}");
}

#[test]
fn runaway_growth_is_reported() {
    let l = LSystem::parse("axiom: A\nA -> AA").unwrap();
    let limits = Limits {
        max_modules: 1000,
        max_params: 1000,
        ..Limits::default()
    };
    let mut d = Derivation::with_limits(&l, 0, limits).unwrap();
    let e = d.derive(20).unwrap_err();
    match e {
        PlantError::Growth {
            step, max_modules, ..
        } => {
            assert_eq!(step, 10);
            assert_eq!(max_modules, 1000);
        }
        other => panic!("{other}"),
    }
    let l =
        LSystem::parse("axiom: A(0)\nA(x) : { while (1) { x = x + 1; } } x > 0 -> A(x)").unwrap();
    let e = Derivation::new(&l, 0).unwrap().step().unwrap_err();
    assert!(e.to_string().contains("loop"), "{e}");
}

const SAMPLE: &str = "#define r1 0.94
#define Prob(x) (0.12 + x*0.42)
#ignore: + -
derivation length: 4
axiom: A(1)B(3)A(5)
p1: A(x) -> A(x+1) : Prob(0.5)
p2: A(x) -> B(x-1) : 0.6
p3: A(x) < B(y) > A(z) : y < 4 -> B(x+z)[A(y)]
B(x) : { t = x*2; } t < 9 { u = t+1; } -> B(u)
decomposition:
C -> FF";

fn check(text: &str) {
    match LSystem::parse(text) {
        Ok(l) => {
            if let Ok(mut d) = Derivation::with_limits(
                &l,
                1,
                Limits {
                    max_modules: 10_000,
                    max_params: 40_000,
                    ..Limits::default()
                },
            ) {
                for _ in 0..3 {
                    if d.step().is_err() {
                        break;
                    }
                }
            }
        }
        Err(e) => {
            if let Some(s) = e.span() {
                assert!(s.line >= 1 && s.col >= 1, "{e}");
            }
        }
    }
}

proptest! {
    #[test]
    fn random_text_never_panics(s in "[A-Fa-f0-9xy()\\[\\]<>:;,+*/%^&|!?@~{}#.= \\n-]{0,80}") {
        check(&s);
        check(&format!("axiom: A\n{s}"));
    }

    #[test]
    fn mutated_text_never_panics(pos in 0usize..400, len in 0usize..6, ins in "[ -~\\n]{0,6}") {
        let chars: Vec<char> = SAMPLE.chars().collect();
        let a = pos.min(chars.len());
        let b = (a + len).min(chars.len());
        let mutated: String = chars[..a].iter().copied().chain(ins.chars()).chain(chars[b..].iter().copied()).collect();
        check(&mutated);
    }
}

#[test]
fn sample_parses() {
    let l = LSystem::parse(SAMPLE).unwrap();
    assert_eq!(l.derivation_length(), 4);
    let mut d = Derivation::new(&l, 3).unwrap();
    d.derive(4).unwrap();
}

#[test]
fn malformed_tropism_directive_names_line_and_column() {
    let cases: [(&str, u32, u32); 5] = [
        // Too few values: points after the last one.
        ("axiom: F\ntropism: 0, 0", 2, 14),
        // A missing comma: points at the stray value.
        ("axiom: F\ntropism: 0, 0 1 0.2", 2, 15),
        // Extra text after four values.
        ("axiom: F\ntropism: 0, 0, -1, 0.2, 7", 2, 23),
        // A zero vector: points at its first value.
        ("axiom: F\n\ntropism: 0, 0, 0, 0.2", 3, 10),
        // Empty.
        ("axiom: F\ntropism:", 2, 9),
    ];
    for (src, line, col) in cases {
        let e = LSystem::parse(src).unwrap_err();
        assert!(matches!(e, PlantError::Syntax { .. }), "{src:?}: {e}");
        assert_eq!(
            e.span(),
            Some(natura_plant::Span::new(line, col)),
            "{src:?}: {e}"
        );
    }
    // Undefined names, failing arithmetic and a second directive are typed too.
    let e = LSystem::parse("axiom: F\ntropism: 0, 0, -1, k").unwrap_err();
    assert!(matches!(e, PlantError::Undefined { .. }), "{e}");
    assert_eq!(e.span().unwrap().line, 2);
    let e = LSystem::parse("axiom: F\ntropism: 0, 0, -1, 1/0").unwrap_err();
    assert!(e.span().is_some_and(|s| s.line == 2), "{e}");
    let e = LSystem::parse("tropism: 0,0,-1,0.2\naxiom: F\ntropism: 0,0,-1,0.2").unwrap_err();
    assert_eq!(e.span().unwrap().line, 3, "{e}");
}
