//! Tessendorf's FFT ocean: a 512² patch at several wind speeds, written as
//! false-colour height, slope (the notes' Fig. 7) and foam maps and a shaded
//! view, plus a short, exactly looping frame sequence.
//!
//! ```text
//! cargo run --release --example ocean                   # into ./ocean/
//! cargo run --release --example ocean -- --quick --out /tmp/ocean --exr
//! cargo run --release --example ocean -- --help          # every flag and its default
//! ```
//!
//! Writes the maps of each wind speed (`height_*.png`, `slope_*.png`,
//! `foam_*.png`, `shaded_*.png`, and `maps_*.exr` with `--exr`) and the
//! loop's frames (`loop_*.png`) into `--out` (default: `./ocean/`), with a
//! progress bar per wind speed and one for the loop.
//!
//! The view is orthographic, looking north and down at 55° from the
//! vertical, so the Fresnel reflectance varies with the slope; the sky is a
//! simple zenith-to-horizon gradient and the sun sits behind the waves to
//! the north, giving glitter. Foam accumulates from the Jacobian over a few
//! seconds before each picture, new foam covering the wind's whitecap
//! fraction (Monahan's law: about 0.2%, 1.8% and 10% at 6, 12 and 20 m/s).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::{Image, Progress};
use natura::ocean::{
    Foam, FoamParams, Frame, Ocean, OceanParams, Phillips, Seed, Surface, export::FrameSequence,
    preview, whitecap_coverage,
};

/// Tessendorf's FFT ocean: a patch at several wind speeds, each written as
/// false-colour height, slope and foam maps and a shaded view
/// (height_*.png, slope_*.png, foam_*.png, shaded_*.png, and maps_*.exr
/// with --exr), plus an exactly looping frame sequence (loop_*.png).
#[derive(Parser)]
#[command(name = "ocean", version)]
struct Cli {
    /// Small and fast (CI): a smaller patch, one wind speed, fewer frames
    #[arg(long)]
    quick: bool,
    /// Samples per side of the maps (a power of two) [default: 512; 128
    /// with --quick]
    #[arg(long, value_parser = common::in_range(16usize, 2048))]
    size: Option<usize>,
    /// Random seed
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Frames in the loop [default: 16; 4 with --quick]
    #[arg(long, value_parser = common::in_range(1usize, 10_000))]
    frames: Option<usize>,
    /// Also write EXR maps of each wind speed
    #[arg(long)]
    exr: bool,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "ocean")]
    out: PathBuf,
}

/// Quarter-second steps run before a wind speed's pictures, so the foam
/// has built up.
const WARM_UP: usize = 40;

fn main() -> ExitCode {
    common::run(ocean_example)
}

fn ocean_example() -> Run {
    let cli: Cli = common::parse();
    let quick = cli.quick;
    let size = cli.size.unwrap_or(if quick { 128 } else { 512 });
    let frames = cli.frames.unwrap_or(if quick { 4 } else { 16 });
    let (seed, exr) = (cli.seed, cli.exr);
    let out = common::out_dir(&cli.out)?;

    let view = preview::TopView::default();
    let winds: &[f64] = if quick { &[12.0] } else { &[6.0, 12.0, 20.0] };
    let bar = common::Bar::new();
    for &wind in winds {
        // The warm-up's steps, then one unit per file.
        let files = 4 + usize::from(exr);
        bar.start(&format!("wind {wind:.0} m/s"), (WARM_UP + 1 + files) as u64);
        let (ocean, frame, foam) = warmed_up(size, 400.0, wind, None, seed, WARM_UP, &bar)?;
        let tag = format!("{wind:.0}ms");
        let mut wrote = Vec::new();
        let mut save = |name: String, img: Image| -> Run {
            let p = out.join(name);
            img.save_png(&p)?;
            wrote.push(p);
            bar.advance(1);
            Ok(())
        };
        save(format!("height_{tag}.png"), preview::height_image(&frame)?)?;
        save(format!("slope_{tag}.png"), preview::slope_image(&frame)?)?;
        save(format!("foam_{tag}.png"), preview::foam_image(&foam)?)?;
        let surface = Surface::new(&frame, Some(&foam))?;
        save(
            format!("shaded_{tag}.png"),
            view.render(&surface, size, ocean.extent())?,
        )?;
        if exr {
            let p = out.join(format!("maps_{tag}.exr"));
            natura::ocean::export::write_maps(&p, &frame, Some(&foam))?;
            wrote.push(p);
            bar.advance(1);
        }
        bar.finish();
        for p in &wrote {
            outln(format_args!("wrote {}", p.display()))?;
        }
        let h = frame.height_variance().sqrt();
        outln(format_args!(
            "wind {wind:>4.1} m/s: height rms {h:.2} m, Hs ≈ {:.2} m, min Jacobian {:.2}, foam cover {:.1}%",
            4.0 * h,
            frame.jacobian_grid().min(),
            100.0 * foam.fraction_above(0.1)
        ))?;
    }

    // A looping sequence: frequencies quantised to multiples of 2π/T (eq. 18).
    let period = 8.0;
    let n = if quick { 64 } else { 256 };
    let steps = (2.0 * period / 0.25) as usize;
    // The warm-up's steps, then one unit per frame.
    bar.start("loop", (steps + 1 + frames) as u64);
    let (ocean, mut frame, mut foam) = warmed_up(n, 100.0, 10.0, Some(period), seed, steps, &bar)?;
    let mut seq = FrameSequence::new(&out, "loop")?;
    let t0 = frame.time();
    for i in 0..frames {
        let t = t0 + period * i as f64 / frames as f64;
        ocean.evaluate_into(t, &mut frame)?;
        foam.update(&frame)?;
        let surface = Surface::new(&frame, Some(&foam))?;
        seq.write_png(&view.render(&surface, n, ocean.extent())?)?;
        bar.advance(1);
    }
    bar.finish();
    outln(format_args!(
        "wrote {} looping frames ({period} s period) and the maps to {}",
        seq.written().len(),
        out.display()
    ))
}

/// Builds a patch and runs it for `steps` quarter-second steps so the foam
/// has built up, advancing `progress` once per step (`steps + 1` in all);
/// returns it with the last frame and the foam.
fn warmed_up(
    n: usize,
    extent: f64,
    wind: f64,
    loop_period: Option<f64>,
    seed: u64,
    steps: usize,
    progress: &dyn Progress,
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
    // New foam on the wind's whitecap coverage (Monahan's law): the most
    // compressed water of the first frame sets the Jacobian's threshold.
    ocean.evaluate_into(0.0, &mut frame)?;
    let foam_params = FoamParams::with_coverage(&frame, whitecap_coverage(wind), 0.25, 2.5)?;
    let mut foam = Foam::for_frame(&frame, foam_params)?;
    for i in 0..=steps {
        ocean.evaluate_into(i as f64 * 0.25, &mut frame)?;
        foam.update(&frame)?;
        progress.advance(1);
    }
    Ok((ocean, frame, foam))
}
