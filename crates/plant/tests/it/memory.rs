//! Memory of the module string: at most 32 bytes per module plus 8 per
//! parameter, measured from the capacity of its arrays after a derivation.

use natura_plant::{Derivation, LSystem};

#[test]
fn string_memory_per_module() {
    for (src, steps) in [
        (
            "axiom: A(1)\nA(x) -> B(x)[C(x)A(x*0.7)][D(x)A(x*0.7)]B(x)A(x*0.9)\nB(x) -> B(x*1.1)",
            8,
        ),
        ("axiom: X\nX -> F-[[X]+X]+F[+FX]-X\nF -> FF", 6),
        ("axiom: A(1,2,3)\nA(x,y,z) -> A(x+1,y,z)[B(z)]A(y,z,x)", 12),
    ] {
        let l = LSystem::parse(src).unwrap();
        let mut d = Derivation::new(&l, 1).unwrap();
        d.derive(steps).unwrap();
        let s = d.string();
        let bound = 32 * s.len() + 8 * s.param_count();
        assert!(s.len() > 1000, "{src}: {}", s.len());
        assert!(
            s.memory_bytes() <= bound,
            "{src}: {} bytes for {} modules, {} parameters",
            s.memory_bytes(),
            s.len(),
            s.param_count()
        );
        // Both buffers of the derivation together stay within twice the bound.
        assert!(d.memory_bytes() <= 2 * bound);
    }
}
