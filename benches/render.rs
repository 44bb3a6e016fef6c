//! natura-render: the default landscape scene at 1280×720, 1 spp.
//!
//! The world's stages (synthesis, erosion, lakes, atmosphere) are timed once
//! and printed; criterion then measures the acceleration build and the render
//! (camera samples per second through the integrator, each with its shadow,
//! reflection and refraction rays) on the default thread pool.

use std::sync::OnceLock;
use std::time::Instant;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use natura::core::NoProgress;
use natura::render::{Renderer, SceneDesc, World};

fn world() -> &'static World {
    static W: OnceLock<World> = OnceLock::new();
    W.get_or_init(|| {
        let mut scene = SceneDesc::default();
        scene.render.width = 1280;
        scene.render.height = 720;
        scene.render.spp = 1;
        // The rows keep measuring the terrain's acceleration structures and
        // the integrator; the clouds' build (their bake, direction grid and
        // shadow map) shows in the main job's acceleration stage.
        scene.clouds.enabled = false;
        let t0 = Instant::now();
        let w = World::build(&scene, &NoProgress).expect("default scene builds");
        println!(
            "world build (default scene, {} threads):",
            rayon::current_num_threads()
        );
        for (stage, d) in &w.times.stages {
            println!("  {stage:>12}: {:8.3} s", d.as_secs_f64());
        }
        println!("  {:>12}: {:8.3} s", "total", t0.elapsed().as_secs_f64());
        w
    })
}

fn render(c: &mut Criterion) {
    let w = world();
    let mut g = c.benchmark_group("render");
    g.sample_size(10);
    g.measurement_time(std::time::Duration::from_secs(20));
    g.bench_function("acceleration_build", |b| {
        b.iter(|| Renderer::new(w, &NoProgress).unwrap())
    });
    let r = Renderer::new(w, &NoProgress).unwrap();
    g.throughput(Throughput::Elements(1280 * 720));
    g.bench_function("render_1280x720_1spp", |b| {
        b.iter(|| r.render(&NoProgress).unwrap())
    });
    g.finish();
}

criterion_group!(benches, render);
criterion_main!(benches);
