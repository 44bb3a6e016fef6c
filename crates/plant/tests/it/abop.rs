//! Published L-systems (Prusinkiewicz & Lindenmayer 1990, chapters 1–5;
//! Měch & Prusinkiewicz 1996; Prusinkiewicz et al. 2001) derived exactly:
//! whole strings for the small ones, module counts against closed forms or
//! length recurrences for the large ones, and context-sensitive systems
//! against a naive character-level reference implementation.

use natura_plant::{Derivation, LSystem, PlantError};

fn derive(src: &str, n: u32) -> (LSystem, String) {
    let l = LSystem::parse(src).unwrap_or_else(|e| panic!("{e}\n{src}"));
    let mut d = Derivation::new(&l, 7).unwrap();
    d.derive(n).unwrap();
    let s = d.string().display(l.symbols());
    (l, s)
}

fn count(s: &str, c: char) -> usize {
    s.chars().filter(|&x| x == c).count()
}

/// For a context-free, non-parametric, single-character L-system: the length
/// after `n` steps from the per-symbol successor lengths (a linear recurrence).
fn length_by_recurrence(axiom: &str, rules: &[(char, &str)], n: u32) -> usize {
    use std::collections::HashMap;
    let mut counts: HashMap<char, usize> = HashMap::new();
    for c in axiom.chars() {
        *counts.entry(c).or_default() += 1;
    }
    for _ in 0..n {
        let mut next: HashMap<char, usize> = HashMap::new();
        for (&c, &k) in &counts {
            match rules.iter().find(|r| r.0 == c) {
                Some((_, succ)) => {
                    for s in succ.chars() {
                        *next.entry(s).or_default() += k;
                    }
                }
                None => *next.entry(c).or_default() += k,
            }
        }
        counts = next;
    }
    counts.values().sum()
}

fn check_cf(axiom: &str, rules: &[(char, &str)], n: u32) {
    let mut src = format!("axiom: {axiom}\n");
    for (p, s) in rules {
        src.push_str(&format!("{p} -> {s}\n"));
    }
    let (_, got) = derive(&src, n);
    assert_eq!(
        got.chars().count(),
        length_by_recurrence(axiom, rules, n),
        "{src}"
    );
    assert_eq!(count(&got, '['), count(&got, ']'));
}

#[test]
fn algae_fibonacci() {
    // ABOP §1.2: Lindenmayer's Anabaena; lengths are Fibonacci numbers.
    let l = LSystem::parse("axiom: A\nA -> AB\nB -> A").unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    let fib = [1, 2, 3, 5, 8, 13, 21, 34, 55, 89];
    for &f in &fib {
        assert_eq!(d.string().len(), f);
        d.step().unwrap();
    }
    let (_, s) = derive("axiom: A\nA -> AB\nB -> A", 4);
    assert_eq!(s, "ABAABABA");
}

#[test]
fn koch_curve_counts() {
    // ABOP Fig. 1.9-style Koch curve F -> F+F--F+F: #F = 4^n, length (7·4^n − 4)/3.
    for n in 0..6 {
        let (_, s) = derive("axiom: F\nF -> F+F--F+F", n);
        assert_eq!(count(&s, 'F'), 4usize.pow(n));
        assert_eq!(s.len(), (7 * 4usize.pow(n) - 4) / 3);
    }
}

#[test]
fn quadratic_koch_island() {
    // ABOP Fig. 1.7a.
    let r = [('F', "F+FF-FF-F-F+F+FF-F-F+F+FF+FF-F")];
    let lens: Vec<usize> = (0..3)
        .map(|n| length_by_recurrence("F-F-F-F", &r, n))
        .collect();
    assert_eq!(lens, [7, 123, 2211]);
    for n in 0..3 {
        check_cf("F-F-F-F", &r, n);
    }
}

#[test]
fn quadratic_snowflake() {
    // ABOP Fig. 1.7b.
    check_cf("-F", &[('F', "F+F-F-F+F")], 4);
    let (_, s) = derive("axiom: -F\nF -> F+F-F-F+F", 1);
    assert_eq!(s, "-F+F-F-F+F");
}

#[test]
fn islands_and_lakes() {
    // ABOP Fig. 1.8.
    check_cf(
        "F+F+F+F",
        &[('F', "F+f-FF+F+FF+Ff+FF-f+FF-F-FF-Ff-FFF"), ('f', "ffffff")],
        2,
    );
}

#[test]
fn koch_curves_a_to_f() {
    // ABOP Fig. 1.9 a–f.
    for succ in [
        "FF-F-F-F-F-F+F",
        "FF-F-F-F-FF",
        "FF-F+F-F-FF",
        "FF-F--F-F",
        "F-FF--F-F",
        "F-F+F-F-F",
    ] {
        check_cf("F-F-F-F", &[('F', succ)], 3);
    }
}

#[test]
fn dragon_and_sierpinski_edge_rewriting() {
    // ABOP Fig. 1.10 a, b (F_l, F_r written L, R).
    check_cf("L", &[('L', "L+R+"), ('R', "-L-R")], 10);
    let (_, s) = derive("axiom: L\nL -> L+R+\nR -> -L-R", 2);
    assert_eq!(s, "L+R++-L-R+");
    check_cf("R", &[('L', "R+L+R"), ('R', "L-R-L")], 6);
}

#[test]
fn gosper_hexagonal_curve() {
    // ABOP Fig. 1.11a.
    check_cf(
        "L",
        &[('L', "L+R++R-L--LL-R+"), ('R', "-L+RR++R+L--L-R")],
        4,
    );
}

#[test]
fn hilbert_curve_3d() {
    // ABOP Fig. 1.19.
    check_cf(
        "A",
        &[
            ('A', "B-F+CFC+F-D&F^D-F+&&CFC+F+B//"),
            ('B', "A&F^CFB^F^D^^-F-D^|F^B|FC^F^A//"),
            ('C', "|D^|F^B-F+C^F^A&&FA&F^C+F+B^F^D//"),
            ('D', "|CFB-F+B|FA&F^A&&FB-F+B|FC//"),
        ],
        3,
    );
}

#[test]
fn bracketed_plants_a_to_f() {
    // ABOP Fig. 1.24 a–f.
    check_cf("F", &[('F', "F[+F]F[-F]F")], 5);
    check_cf("F", &[('F', "F[+F]F[-F][F]")], 5);
    check_cf("F", &[('F', "FF-[-F+F+F]+[+F-F-F]")], 4);
    check_cf("X", &[('X', "F[+X]F[-X]+X"), ('F', "FF")], 7);
    check_cf("X", &[('X', "F[+X][-X]FX"), ('F', "FF")], 7);
    check_cf("X", &[('X', "F-[[X]+X]+F[+FX]-X"), ('F', "FF")], 5);
    let (_, s) = derive("axiom: F\nF -> F[+F]F[-F]F", 1);
    assert_eq!(s, "F[+F]F[-F]F");
    // #F for 1.24a is 5^n.
    let (_, s) = derive("axiom: F\nF -> F[+F]F[-F]F", 5);
    assert_eq!(count(&s, 'F'), 5usize.pow(5));
}

#[test]
fn signal_propagation() {
    // ABOP §1.8: b < a -> b, b -> a; the signal moves one module per step.
    let src = "axiom: baaaaaaaa\nb < a -> b\nb -> a";
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    for k in 0..9 {
        let expect: String = (0..9).map(|i| if i == k { 'b' } else { 'a' }).collect();
        assert_eq!(d.string().display(l.symbols()), expect);
        d.step().unwrap();
    }
}

#[test]
fn abop_parametric_example() {
    // ABOP §1.10.1, the derivation printed beside Fig. 1.31's text.
    let src = "axiom: B(2)A(4,4)
        p1: A(x,y) : y <= 3 -> A(x*2,x+y)
        p2: A(x,y) : y > 3 -> B(x)A(x/y,0)
        p3: B(x) : x < 1 -> C
        p4: B(x) : x >= 1 -> B(x-1)";
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    let expect = [
        "B(2)A(4,4)",
        "B(1)B(4)A(1,0)",
        "B(0)B(3)A(2,1)",
        "CB(2)A(4,3)",
        "CB(1)A(8,7)",
    ];
    for e in expect {
        assert_eq!(d.string().display(l.symbols()), e);
        d.step().unwrap();
    }
    // Step 5: C B(0) B(8) A(8/7, 0).
    let s = d.string();
    assert_eq!(s.len(), 4);
    assert_eq!(s.params(2), &[8.0]);
    approx::assert_relative_eq!(s.params(3)[0], 8.0 / 7.0, max_relative = 1e-15);
}

#[test]
fn mech_example_contexts_read_old_string() {
    // Měch & Prusinkiewicz 1996, §4: the middle is always B(6)[A(3)].
    let src = "ω: A(1)B(3)A(5)
        p1: A(x) -> A(x+1) : 0.4
        p2: A(x) -> B(x-1) : 0.6
        p3: A(x) < B(y) > A(z) : y < 4 -> B(x+z)[A(y)]";
    let l = LSystem::parse(src).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for seed in 0..200 {
        let mut d = Derivation::new(&l, seed).unwrap();
        d.step().unwrap();
        let s = d.string().display(l.symbols());
        assert!(s.contains("B(6)[A(3)]"), "{s}");
        assert!(s.starts_with("A(2)") || s.starts_with("B(0)"), "{s}");
        assert!(s.ends_with("A(6)") || s.ends_with("B(4)"), "{s}");
        seen.insert(s);
    }
    assert_eq!(seen.len(), 4, "all four outcomes appear: {seen:?}");
    assert!(seen.contains("A(2)B(6)[A(3)]B(4)"));
}

#[test]
fn positional_information_eq2_blocks() {
    // Prusinkiewicz et al. 2001, §2, eq. 2.
    let src = "axiom: A(4)A(2)\nA(x) : {y = x+2;} y >= 5 {z = y/3;} -> B(z)C(z+1)";
    let (_, s) = derive(src, 1);
    assert_eq!(s, "B(2)C(3)A(2)");
}

#[test]
fn monopodial_tree_counts() {
    // ABOP Fig. 2.6: apices double each step; length 1 + 7(2^n − 1).
    let src = "#define r1 0.9
        #define r2 0.6
        #define a0 45
        #define a2 45
        #define d 137.5
        #define wr 0.707
        ω: A(1,10)
        p1: A(l,w) -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)
        p2: B(l,w) -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)
        p3: C(l,w) -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)";
    for n in 0..9u32 {
        let (_, s) = derive(src, n);
        let l = LSystem::parse(src).unwrap();
        let mut d = Derivation::new(&l, 0).unwrap();
        d.derive(n).unwrap();
        assert_eq!(d.string().len(), 1 + 7 * ((1 << n) - 1), "n={n}");
        assert_eq!(count(&s, 'F'), (1 << n) - 1);
    }
}

#[test]
fn ternary_tree_counts_and_scaling() {
    // ABOP Fig. 2.8.
    let src = "#define d1 94.74
        #define d2 132.63
        #define a 18.95
        #define lr 1.109
        #define vr 1.732
        ω: !(1)F(200)/(45)A
        p1: A -> !(vr)F(50)[&(a)F(50)A]/(d1)[&(a)F(50)A]/(d2)[&(a)F(50)A]
        p2: F(l) -> F(l*lr)
        p3: !(w) -> !(w*vr)";
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 0).unwrap();
    let n = 5;
    d.derive(n).unwrap();
    let s = d.string();
    assert_eq!(s.len(), 4 + 9 * (3usize.pow(n) - 1));
    // The trunk segment scales by lr each step.
    approx::assert_relative_eq!(
        s.params(1)[0],
        200.0 * 1.109f64.powi(n as i32),
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(
        s.params(0)[0],
        1.732f64.powi(n as i32),
        max_relative = 1e-12
    );
}

#[test]
fn vogel_spiral_string() {
    // ABOP §4.1 (Vogel's formula as an L-system): one organ per step.
    let src = "ω: A(0)\nA(n) -> +(137.5)[f(n^0.5)D]A(n+1)";
    let (l, _) = derive(src, 0);
    let mut d = Derivation::new(&l, 0).unwrap();
    d.derive(50).unwrap();
    let s = d.string();
    let dsym = l.symbol("D").unwrap();
    assert_eq!(s.symbols().iter().filter(|&&x| x == dsym).count(), 50);
    let fsym = l.symbol("f").unwrap();
    let radii: Vec<f64> = (0..s.len())
        .filter(|&i| s.symbol(i) == fsym)
        .map(|i| s.params(i)[0])
        .collect();
    for (k, r) in radii.iter().enumerate() {
        approx::assert_relative_eq!(*r, (k as f64).sqrt());
    }
}

#[test]
fn cordate_leaf_polygons() {
    // ABOP Fig. 5.5.
    check_cf(
        "[A][B]",
        &[('A', "[+A{.].C.}"), ('B', "[-B{.].C.}"), ('C', "GC")],
        8,
    );
}

#[test]
fn stochastic_frequencies_fig_1_27() {
    // ABOP Fig. 1.27: three successors with probabilities .33/.33/.34.
    let src = "ω: F
        F -> F[+F]F[-F]F : 0.33
        F -> F[+F]F : 0.33
        F -> F[-F]F : 0.34";
    let l = LSystem::parse(src).unwrap();
    let mut hits = [0usize; 3];
    let trials = 20_000;
    for seed in 0..trials {
        let mut d = Derivation::new(&l, seed).unwrap();
        d.step().unwrap();
        let s = d.string().display(l.symbols());
        let k = match s.as_str() {
            "F[+F]F[-F]F" => 0,
            "F[+F]F" => 1,
            "F[-F]F" => 2,
            other => panic!("unexpected {other}"),
        };
        hits[k] += 1;
    }
    for (h, p) in hits.iter().zip([0.33, 0.33, 0.34]) {
        let f = *h as f64 / trials as f64;
        // 5 standard deviations of a binomial proportion.
        let sd = (p * (1.0 - p) / trials as f64).sqrt();
        assert!((f - p).abs() < 5.0 * sd, "{f} vs {p}");
    }
    // Same seed, same string; many steps.
    let run = |seed| {
        let mut d = Derivation::new(&l, seed).unwrap();
        d.derive(5).unwrap();
        d.into_string()
    };
    assert_eq!(run(3), run(3));
    assert_ne!(run(3), run(4));
}

/// A naive reference: non-parametric single-character context-sensitive
/// L-systems with an ignore set, on `Vec<char>`, written independently of
/// the engine (recursive branch skipping).
fn naive_step(
    s: &[char],
    rules: &[(Option<char>, char, Option<char>, &str)],
    ignore: &str,
) -> Vec<char> {
    let left_of = |i: usize| -> Option<char> {
        let mut j = i;
        let mut depth = 0i32;
        while j > 0 {
            j -= 1;
            let c = s[j];
            if c == ']' {
                depth += 1;
            } else if c == '[' {
                if depth > 0 {
                    depth -= 1;
                }
            } else if depth == 0 && !ignore.contains(c) {
                return Some(c);
            }
        }
        None
    };
    let right_of = |i: usize| -> Option<char> {
        let mut j = i + 1;
        let mut depth = 0i32;
        while j < s.len() {
            let c = s[j];
            if c == '[' {
                depth += 1;
            } else if c == ']' {
                if depth == 0 {
                    return None;
                }
                depth -= 1;
            } else if depth == 0 && !ignore.contains(c) {
                return Some(c);
            }
            j += 1;
        }
        None
    };
    let mut out = Vec::new();
    for (i, &c) in s.iter().enumerate() {
        let r = rules.iter().find(|(l, p, r, _)| {
            *p == c
                && l.is_none_or(|l| left_of(i) == Some(l))
                && r.is_none_or(|r| right_of(i) == Some(r))
        });
        match r {
            Some((_, _, _, succ)) => out.extend(succ.chars()),
            None => out.push(c),
        }
    }
    out
}

#[test]
fn context_sensitive_fig_1_31_against_reference() {
    // ABOP Fig. 1.31 a–e: context-sensitive bracketed L-systems with #ignore: +-F.
    let tables: [(&str, [&str; 8], u32); 5] = [
        (
            "F1F1F1",
            ["0", "1[+F1F1]", "1", "1", "0", "1F1", "0", "0"],
            30,
        ),
        (
            "F1F1F1",
            ["1", "1[-F1F1]", "1", "1", "0", "1F1", "1", "0"],
            30,
        ),
        (
            "F1F1F1",
            ["0", "1", "0", "1[+F1F1]", "0", "1F1", "0", "0"],
            26,
        ),
        (
            "F0F1F1",
            ["1", "0", "0", "1F1", "1", "1[+F1F1]", "1", "0"],
            24,
        ),
        (
            "F1F1F1",
            ["0", "1[-F1F1]", "1", "1", "0", "1F1", "1", "0"],
            26,
        ),
    ];
    for (axiom, succ, n) in tables {
        let mut rules: Vec<(Option<char>, char, Option<char>, &str)> = Vec::new();
        let mut src = format!("#ignore: +-F\nω: {axiom}\n");
        for (k, s) in succ.iter().enumerate() {
            let (a, b, c) = (
                char::from(b'0' + ((k >> 2) & 1) as u8),
                char::from(b'0' + ((k >> 1) & 1) as u8),
                char::from(b'0' + (k & 1) as u8),
            );
            rules.push((Some(a), b, Some(c), s));
            src.push_str(&format!("{a} < {b} > {c} -> {s}\n"));
        }
        rules.push((None, '+', None, "-"));
        rules.push((None, '-', None, "+"));
        src.push_str("+ -> -\n- -> +\n");
        let l = LSystem::parse(&src).unwrap();
        let mut d = Derivation::new(&l, 0).unwrap();
        let mut reference: Vec<char> = axiom.chars().collect();
        for step in 0..n {
            d.step().unwrap();
            reference = naive_step(&reference, &rules, "+-F");
            let got = d.string().display(l.symbols());
            assert_eq!(
                got,
                reference.iter().collect::<String>(),
                "axiom {axiom} step {step}"
            );
        }
        assert!(d.string().len() > 20);
    }
}

#[test]
fn right_context_skips_branches_and_matches_brackets() {
    // A right context skips a complete branch; a bracketed pattern enters it.
    let (_, s) = derive("ω: A[B]C\nA > C -> X", 1);
    assert_eq!(s, "X[B]C");
    let (_, s) = derive("ω: A[B]C\nA > [B]C -> X", 1);
    assert_eq!(s, "X[B]C");
    let (_, s) = derive("ω: A[B]D\nA > [B]C -> X", 1);
    assert_eq!(s, "A[B]D");
    // The end of a branch stops a right context.
    let (_, s) = derive("ω: [A]C\nA > C -> X", 1);
    assert_eq!(s, "[A]C");
    // A left context crosses `[` into the parent axis and skips sibling branches.
    let (_, s) = derive("ω: B[C][D]E\nB < E -> X\nB < D -> Y", 1);
    assert_eq!(s, "B[C][Y]X");
    // Ignore and consider lists.
    let (_, s) = derive("#ignore: +\nω: A++B\nA < B -> X", 1);
    assert_eq!(s, "A++X");
    let (_, s) = derive("Consider: A B\nω: A+-FB\nA < B -> X", 1);
    assert_eq!(s, "A+-FX");
    let (_, s) = derive("ω: A+B\nA < B -> X", 1);
    assert_eq!(s, "A+B");
}

#[test]
fn tree_model_context_with_brackets_and_consider() {
    // The basipetal pattern of Měch & Prusinkiewicz 1996's tree model:
    // `!(…) > L(…) [!(…)] !(…)` with F and A ignored.
    let src = "Consider: ?E [ ] L !
        ω: !(1,0,0)F(1)L(1)A(1)[!(3,0,0)F(1)]!(4,0,0)
        !(w0,p0,n0) > L(v) [!(w1,p1,n1)] !(w2,p2,n2) -> !((w1^2+w2^2)^0.5,0,0)";
    let (_, s) = derive(src, 1);
    assert!(s.starts_with("!(5,0,0)"), "{s}");
}

#[test]
fn cut_erases_rest_of_branch() {
    let (_, s) = derive("ω: F[XA]W\nA -> %YZ", 1);
    assert_eq!(s, "F[X]W");
    let (_, s) = derive("ω: F[X[P]A[Q]R]W\nA -> %", 1);
    assert_eq!(s, "F[X[P]]W");
    let (_, s) = derive("ω: FAG\nA -> %", 1);
    assert_eq!(s, "F");
}

#[test]
fn decomposition_and_depth() {
    let src = "ω: A(3)\ndecomposition:\nmaximum depth: 10\nA(n) : n > 0 -> F A(n-1)";
    let l = LSystem::parse(src).unwrap();
    let d = Derivation::new(&l, 0).unwrap();
    assert_eq!(d.string().display(l.symbols()), "FFFA(0)");
    let src = "ω: A(30)\ndecomposition:\nmaximum depth: 10\nA(n) : n > 0 -> F A(n-1)";
    let l = LSystem::parse(src).unwrap();
    let e = Derivation::new(&l, 0).unwrap_err();
    assert!(matches!(e, PlantError::Depth { depth: 10, .. }), "{e}");
    assert_eq!(e.span().unwrap().line, 4);
    // Decomposition applies to successors at every step.
    let src = "ω: S\nS -> SB\ndecomposition:\nB -> CC";
    let (_, s) = derive(src, 2);
    assert_eq!(s, "SCCCC");
}

#[test]
fn random_functions_are_reproducible() {
    let src = "ω: A(0)\nA(x) -> A(nran(0,1)) B(ran(10))";
    let l = LSystem::parse(src).unwrap();
    let run = |seed| {
        let mut d = Derivation::new(&l, seed).unwrap();
        d.derive(3).unwrap();
        d.into_string()
    };
    assert_eq!(run(1), run(1));
    assert_ne!(run(1), run(2));
}
