//! Tessendorf's FFT ocean: a 512² patch at several wind speeds, written as
//! false-colour height, slope (the notes' Fig. 7) and foam maps and a shaded
//! view, plus a short, exactly looping frame sequence.
//!
//! ```text
//! cargo run --release --example ocean                   # docs/gallery/ocean/
//! cargo run --release --example ocean -- --quick --out /tmp/ocean --exr
//! ```
//!
//! The view is orthographic, looking north and down at 55° from the
//! vertical, so the Fresnel reflectance varies with the slope; the sky is a
//! simple zenith-to-horizon gradient and the sun sits behind the waves to
//! the north, giving glitter. Foam accumulates from the Jacobian over a few
//! seconds before each picture.

mod common;

use natura::core::Image;
use natura::ocean::{
    Foam, FoamParams, Frame, Ocean, OceanParams, Phillips, Seed, Surface, export::FrameSequence,
    preview,
};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let size: usize = args.value("--size", if quick { 128 } else { 512 }, "samples per side");
    let seed: u64 = args.value("--seed", 7, "random seed");
    let frames: usize = args.value("--frames", if quick { 4 } else { 16 }, "frames in the loop");
    let exr = args.switch("--exr", "also write EXR maps of each wind speed");
    let out = args.out_dir("docs/gallery/ocean");
    args.finish();
    if frames == 0 {
        common::fail("--frames must be at least 1");
    }

    let view = preview::TopView::default();
    let winds: &[f64] = if quick { &[12.0] } else { &[6.0, 12.0, 20.0] };
    for &wind in winds {
        let (ocean, frame, foam) = common::check(warmed_up(size, 400.0, wind, None, seed, 40));
        let tag = format!("{wind:.0}ms");
        save(
            &out,
            &format!("height_{tag}.png"),
            &common::check(preview::height_image(&frame)),
        );
        save(
            &out,
            &format!("slope_{tag}.png"),
            &common::check(preview::slope_image(&frame)),
        );
        save(
            &out,
            &format!("foam_{tag}.png"),
            &common::check(preview::foam_image(&foam)),
        );
        let surface = common::check(Surface::new(&frame, Some(&foam)));
        save(
            &out,
            &format!("shaded_{tag}.png"),
            &common::check(view.render(&surface, size, ocean.extent())),
        );
        if exr {
            let p = out.join(format!("maps_{tag}.exr"));
            common::check(natura::ocean::export::write_maps(&p, &frame, Some(&foam)));
            println!("wrote {}", p.display());
        }
        let h = frame.height_variance().sqrt();
        println!(
            "wind {wind:>4.1} m/s: height rms {h:.2} m, Hs ≈ {:.2} m, min Jacobian {:.2}, foam cover {:.1}%",
            4.0 * h,
            frame.jacobian_grid().min(),
            100.0 * foam.fraction_above(0.1)
        );
    }

    // A looping sequence: frequencies quantised to multiples of 2π/T (eq. 18).
    let period = 8.0;
    let n = if quick { 64 } else { 256 };
    let (ocean, mut frame, mut foam) = common::check(warmed_up(
        n,
        100.0,
        10.0,
        Some(period),
        seed,
        (2.0 * period / 0.25) as usize,
    ));
    let mut seq = common::check(FrameSequence::new(&out, "loop"));
    let bar = common::Bar::new();
    use natura::core::Progress;
    bar.start("loop", frames as u64);
    let t0 = frame.time();
    for i in 0..frames {
        let t = t0 + period * i as f64 / frames as f64;
        common::check(ocean.evaluate_into(t, &mut frame));
        common::check(foam.update(&frame));
        let surface = common::check(Surface::new(&frame, Some(&foam)));
        common::check(seq.write_png(&common::check(view.render(&surface, n, ocean.extent()))));
        bar.advance(1);
    }
    bar.finish();
    println!(
        "wrote {} looping frames ({period} s period) and the maps to {}",
        seq.written().len(),
        out.display()
    );
}

/// Builds a patch and runs it for `steps` quarter-second steps so the foam
/// has built up; returns it with the last frame and the foam.
fn warmed_up(
    n: usize,
    extent: f64,
    wind: f64,
    loop_period: Option<f64>,
    seed: u64,
    steps: usize,
) -> natura::ocean::Result<(Ocean, Frame, Foam)> {
    let params = OceanParams {
        nx: n,
        ny: n,
        lx: extent,
        ly: extent,
        choppiness: 1.8,
        loop_period,
        ..OceanParams::default()
    };
    let spectrum = Phillips {
        wind_speed: wind,
        wind_direction: 0.35,
        small_wave_length: extent / n as f64,
        against_wind: 0.05,
        ..Phillips::default()
    };
    let ocean = Ocean::new(&params, &spectrum, Seed(seed))?;
    let mut frame = Frame::new(&ocean)?;
    let foam_params = FoamParams {
        threshold: 0.62,
        range: 0.25,
        decay_time: 2.5,
    };
    let mut foam = Foam::for_frame(&frame, foam_params)?;
    for i in 0..=steps {
        ocean.evaluate_into(i as f64 * 0.25, &mut frame)?;
        foam.update(&frame)?;
    }
    Ok((ocean, frame, foam))
}

fn save(out: &std::path::Path, name: &str, img: &Image) {
    let p = out.join(name);
    common::check(img.save_png(&p));
    println!("wrote {}", p.display());
}
