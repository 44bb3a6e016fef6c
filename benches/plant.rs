//! natura-plant throughput, with the `symbios` crate as peer on the same L-systems:
//!
//! * `plant_derive/context_free_{natura,symbios}`: a parametric, bracketed,
//!   context-free L-system derived 11 steps from its axiom (≈ 1 M modules at
//!   the end; modules written per second over all steps);
//! * `plant_derive/context_sensitive_{natura,symbios}`: one step of a
//!   parametric L-system with left and right contexts and an ignore list
//!   (`F` ignored) on a 500 k-module string (modules rewritten per second);
//! * `plant_derive/ten_million_natura`: the context-free system derived from
//!   its axiom until its string holds over 10 M modules (time per derivation);
//! * `plant_mesh/{mesh,turtle_mesh}`: the turtle's geometry of a 3-D bush of
//!   ≈ 200 k segments meshed (8 radial segments), alone and with the turtle
//!   (segments per second).
//!
//! Memory per module (capacity of the string's arrays) is printed at the start.
//!
//! ```text
//! cargo bench --bench plant -- plant_derive
//! cargo bench --bench plant -- plant_mesh
//! ```

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use natura::plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams};

/// The context-free workload, in each engine's syntax (same productions).
const CF_NATURA: &str =
    "axiom: A(1)\nA(x) -> B(x) [ C(x) A(x*0.7) ] [ D(x) A(x*0.7) ] B(x) A(x*0.9)\nB(x) -> B(x*1.1)";
const CF_SYMBIOS: &str =
    "omega: A(1)\nA(x) -> B(x) [ C(x) A(x*0.7) ] [ D(x) A(x*0.7) ] B(x) A(x*0.9)\nB(x) -> B(x*1.1)";
const CF_STEPS: u32 = 11;

/// The context-sensitive workload's productions (both engines read `#ignore:`).
const CS_RULES: &str = "#ignore: F\nA(x) < B(y) > C(z) -> B((x+z)*0.5)\nB(y) < C(z) -> C(z*0.9+y*0.1)\nC(z) < A(x) -> A(x+1)";
const CS_UNITS: usize = 100_000;

fn cs_axiom() -> String {
    "A(1) F(1) B(2) F(1) C(3) ".repeat(CS_UNITS)
}

fn natura_cf(steps: u32) -> (LSystem, u64) {
    let l = LSystem::parse(CF_NATURA).expect("natura parses the workload");
    let mut d = Derivation::new(&l, 1).unwrap();
    let mut written = 0u64;
    for _ in 0..steps {
        d.step().unwrap();
        written += d.string().len() as u64;
    }
    (l, written)
}

fn symbios_system(src: &str) -> symbios::System {
    let mut s = symbios::System::from_source(src).expect("symbios parses the workload");
    s.max_capacity = 64 << 20;
    s
}

fn derive(c: &mut Criterion) {
    let (l, written) = natura_cf(CF_STEPS);
    let mut sym = symbios_system(CF_SYMBIOS);
    sym.derive(CF_STEPS as usize).unwrap();
    {
        let mut d = Derivation::new(&l, 1).unwrap();
        d.derive(CF_STEPS).unwrap();
        let s = d.string();
        assert_eq!(
            s.len(),
            sym.state.len(),
            "both engines derive the same string"
        );
        eprintln!(
            "context-free: {} modules, {} parameters; {:.2} B per module in the string's capacity ({:.2} B with both buffers)",
            s.len(),
            s.param_count(),
            s.memory_bytes() as f64 / s.len() as f64,
            d.memory_bytes() as f64 / s.len() as f64
        );
    }
    let mut g = c.benchmark_group("plant_derive");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    g.throughput(Throughput::Elements(written));
    g.bench_function("context_free_natura", |b| {
        b.iter(|| {
            let mut d = Derivation::new(&l, 1).unwrap();
            d.derive(CF_STEPS).unwrap();
            black_box(d.string().len())
        })
    });
    g.bench_function("context_free_symbios", |b| {
        b.iter_custom(|iters| {
            let mut t = Duration::ZERO;
            for _ in 0..iters {
                sym.reset();
                let start = Instant::now();
                sym.derive(CF_STEPS as usize).unwrap();
                t += start.elapsed();
                black_box(sym.state.len());
            }
            t
        })
    });

    let axiom = cs_axiom();
    let lcs = LSystem::parse(&format!("axiom: A(0)\n{CS_RULES}")).unwrap();
    let start = lcs.parse_string(&axiom).unwrap();
    let mut scs = symbios_system(&format!("omega: {axiom}\n{CS_RULES}"));
    g.throughput(Throughput::Elements(start.len() as u64));
    g.bench_function("context_sensitive_natura", |b| {
        let mut d = Derivation::new(&lcs, 1).unwrap();
        b.iter_custom(|iters| {
            let mut t = Duration::ZERO;
            for _ in 0..iters {
                d.string_mut().clone_from(&start);
                let t0 = Instant::now();
                d.step().unwrap();
                t += t0.elapsed();
                black_box(d.string().len());
            }
            t
        })
    });
    g.bench_function("context_sensitive_symbios", |b| {
        b.iter_custom(|iters| {
            let mut t = Duration::ZERO;
            for _ in 0..iters {
                scs.reset();
                let t0 = Instant::now();
                scs.derive(1).unwrap();
                t += t0.elapsed();
                black_box(scs.state.len());
            }
            t
        })
    });

    // The smallest step count that reaches 10 M modules.
    let mut d = Derivation::new(&l, 1).unwrap();
    while d.string().len() < 10_000_000 {
        d.step().unwrap();
    }
    let (n, len) = (d.steps(), d.string().len());
    drop(d);
    eprintln!("ten million: {len} modules after {n} steps");
    g.throughput(Throughput::Elements(len as u64));
    g.bench_function("ten_million_natura", |b| {
        b.iter(|| {
            let mut d = Derivation::new(&l, 1).unwrap();
            d.derive(n).unwrap();
            black_box(d.string().len())
        })
    });
    g.finish();
}

fn mesh(c: &mut Criterion) {
    let src = "angle: 22.5\naxiom: A\nA -> [&FL!A]/////'[&FL!A]///////'[&FL!A]\nF -> S/////F\nS -> FL\nL -> ['''^^~L(0.6,0.3)]";
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 1).unwrap();
    d.derive(9).unwrap();
    let t = Turtle::new(&l, TurtleParams::for_lsystem(&l)).unwrap();
    let geo = t.interpret(d.string()).unwrap();
    let p = MeshParams::default();
    let segs = geo.segment_count() as u64;
    let m = PlantMesh::from_geometry(&geo, &p).unwrap();
    eprintln!(
        "mesh: {segs} segments, {} surfaces -> {} vertices, {} triangles",
        geo.surfaces.len(),
        m.vertex_count(),
        m.triangle_count()
    );
    let mut g = c.benchmark_group("plant_mesh");
    g.sample_size(10).measurement_time(Duration::from_secs(6));
    g.throughput(Throughput::Elements(segs));
    g.bench_function("mesh", |b| {
        b.iter(|| black_box(PlantMesh::from_geometry(&geo, &p).unwrap().vertex_count()))
    });
    g.bench_function("turtle_mesh", |b| {
        b.iter(|| {
            let geo = t.interpret(d.string()).unwrap();
            black_box(PlantMesh::from_geometry(&geo, &p).unwrap().vertex_count())
        })
    });
    g.finish();
}

criterion_group!(benches, derive, mesh);
criterion_main!(benches);
