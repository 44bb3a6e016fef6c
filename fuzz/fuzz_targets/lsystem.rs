//! Any text as an L-system: parsed, derived under small limits and
//! interpreted by the turtle. Each stage gives a result or an error (with a
//! line and column for errors about the text), never a panic, an abort or
//! unbounded work; geometry that is produced is finite.
#![no_main]

use libfuzzer_sys::fuzz_target;
use natura_plant::{Derivation, LSystem, Limits, Turtle, TurtleParams};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let lsys = match LSystem::parse(text) {
        Ok(l) => l,
        Err(e) => {
            if let Some(s) = e.span() {
                assert!(s.line >= 1 && s.col >= 1, "{e}");
            }
            return;
        }
    };
    let limits = Limits {
        max_modules: 20_000,
        max_params: 80_000,
        max_work: 1_000_000,
    };
    let Ok(mut d) = Derivation::with_limits(&lsys, 1, limits) else {
        return;
    };
    // The whole derivation length: the work limit ends a long one.
    if d.derive(lsys.derivation_length()).is_err() {
        assert!(d.work() <= limits.max_work + limits.max_modules as u64);
        return;
    }
    assert!(d.work() <= limits.max_work + limits.max_modules as u64);
    assert!(d.string().len() <= limits.max_modules);
    let Ok(turtle) = Turtle::new(&lsys, TurtleParams::for_lsystem(&lsys)) else {
        return;
    };
    if let Ok(g) = turtle.with_limits(limits).interpret(d.string()) {
        if let Some((lo, hi)) = g.bounds() {
            assert!(lo.is_finite() && hi.is_finite());
        }
    }
});
