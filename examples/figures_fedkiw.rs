//! Fedkiw, Stam & Jensen's smoke figures (Fedkiw et al. 2001): smoke
//! rising by its buoyancy alone (Fig. 3), past several objects (Fig. 4)
//! and around a ball (Fig. 5), the rotor (Fig. 6), linear against monotone
//! cubic interpolation of falling smoke (Fig. 8), and the 1-D Hermite cubic
//! against the monotone one (Fig. 9).
//!
//! ```text
//! cargo run --release --example figures_fedkiw                 # every figure
//! cargo run --release --example figures_fedkiw -- --quick      # small, for CI
//! cargo run --release --example figures_fedkiw -- --only rising
//! ```
//!
//! Writes into `--out` (default `./figures_fedkiw/`); docs/figures.md sets
//! each beside the source's caption. The world is z up: the paper's height
//! y is z here.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure, enlarge};
use common::plot::{Canvas, Panel, Pen, colour};
use common::{Exit, Run, outln};
use natura::core::glam::{Quat, Vec3};
use natura::core::{Grid3, Image};
use natura::fluid::advect::Advection;
use natura::fluid::export::render_smoke_volume;
use natura::fluid::grid::{Boundaries, Dims};
use natura::fluid::interp::{CubicLimiter, Interpolation, monotone_cubic};
use natura::fluid::shape::{Obstacle, Shape};
use natura::fluid::smoke::{Smoke, SmokeParams, SmokeSource};

/// Fedkiw, Stam & Jensen's smoke figures (Fedkiw et al. 2001): rising
/// smoke, smoke past objects and around a ball, the rotor, linear against
/// monotone cubic interpolation, and the 1-D Hermite comparison.
#[derive(Parser)]
#[command(name = "figures_fedkiw", version)]
struct Cli {
    /// Small and fast (CI): coarser grids, shorter runs
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_fedkiw")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Fig. 3: smoke rising by its buoyancy alone, its vortices kept
    Rising,
    /// Fig. 4: smoke blown past several objects (low albedo)
    Objects,
    /// Fig. 5: smoke rising around a sphere
    Sphere,
    /// Fig. 6: a box rotating inside a smoke cloud
    Rotor,
    /// Fig. 8: falling smoke, linear (top) against monotone cubic (bottom)
    Interpolation,
    /// Fig. 9: the 1-D Hermite cubic overshoots; the monotone one does not
    Hermite,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[
        Fig::Rising,
        Fig::Objects,
        Fig::Sphere,
        Fig::Rotor,
        Fig::Interpolation,
        Fig::Hermite,
    ];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::Rising => &["fedkiw_fig03_rising.png"],
            Fig::Objects => &["fedkiw_fig04_objects.png"],
            Fig::Sphere => &["fedkiw_fig05_sphere.png"],
            Fig::Rotor => &["fedkiw_fig06_rotor.png"],
            Fig::Interpolation => &["fedkiw_fig08_linear_cubic.png"],
            Fig::Hermite => &["fedkiw_fig09_hermite.png"],
        }
    }
}

type R<T> = Result<T, Exit>;

#[path = "fedkiw/objects.rs"]
mod objects;

fn main() -> ExitCode {
    common::run(run)
}

fn run() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let q = cli.quick;
    figures::make(&out, &cli.only, |fig| {
        Ok(match fig {
            Fig::Rising => vec![rising(q)?],
            Fig::Objects => vec![objects::objects(q)?],
            Fig::Sphere => vec![objects::sphere(q)?],
            Fig::Rotor => vec![rotor(q)?],
            Fig::Interpolation => vec![interpolation(q)?],
            Fig::Hermite => vec![hermite_figure()?],
        })
    })
}

// ---------------------------------------------------------------- Fig. 3

/// Fig. 3's scene: smoke rising under its buoyancy alone ("the only
/// external force", §6) in the source's grid of 100 × 100 × 40 cells, the
/// second its height (here `n × 2n/5 × n`, z up) over 2 × 0.8 × 2 m, walls
/// and an open ceiling, with the default vorticity confinement. The source
/// gives nothing else: a warm source 0.36 m across a little above the
/// floor's centre places smoke of density 1 at 25 K above ambient each
/// step. Unless `buoyant`, the buoyancy's coefficients are zero (a
/// control: nothing then moves the smoke).
fn rising_smoke(n: usize, buoyant: bool) -> R<Smoke> {
    let h = 2.0 / n as f32;
    let lift = SmokeParams::default();
    let params = SmokeParams {
        alpha: if buoyant { lift.alpha } else { 0.0 },
        beta: if buoyant { lift.beta } else { 0.0 },
        advection: cubic_advection(),
        ..SmokeParams::default()
    };
    let hot = params.ambient_temperature + 25.0;
    let mut smoke = Smoke::new(Dims::new(n, 2 * n / 5, n)?, h, params)?;
    smoke.add_source(SmokeSource {
        shape: Shape::Sphere {
            centre: Vec3::new(1.0, 0.4, 0.25),
            radius: 0.18,
        },
        density: 1.0,
        temperature: hot,
        velocity: None,
    })?;
    Ok(smoke)
}

/// The mean vorticity magnitude `|∇ × u|` over the cells with smoke (1/s).
fn vorticity_in_smoke(smoke: &Smoke) -> R<f64> {
    let w = smoke.vorticity()?;
    let rho = smoke.density();
    let (nx, ny, nz) = rho.dims();
    let (mut sum, mut n) = (0.0f64, 0usize);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if rho[(i, j, k)] > 0.05 {
                    let v = Vec3::new(w[0][(i, j, k)], w[1][(i, j, k)], w[2][(i, j, k)]);
                    sum += f64::from(v.length());
                    n += 1;
                }
            }
        }
    }
    Ok(sum / n.max(1) as f64)
}

/// Fig. 3: the plume from the side at four times, lit from above and the
/// left.
fn rising(quick: bool) -> R<Image> {
    let n = if quick { 25 } else { 100 };
    let mut smoke = rising_smoke(n, true)?;
    let h = smoke.h();
    let dt = 0.02;
    let (steps, every) = if quick { (40, 10) } else { (160, 40) };
    let light = Vec3::new(-0.5, -0.4, 1.0).normalize();
    let mut frames = Vec::new();
    for s in 1..=steps {
        smoke.step(dt)?;
        if s % every == 0 {
            frames.push(render_smoke_volume(
                smoke.density(),
                h,
                16.0,
                0.9,
                light,
                1,
                Vec3::splat(0.05),
            )?);
        }
    }
    outln(format_args!(
        "  Fig. 3: mean vorticity in the smoke {:.2} /s after {:.1} s",
        vorticity_in_smoke(&smoke)?,
        steps as f32 * dt
    ))?;
    sheet(&frames, if quick { 4 } else { 2 }, frames.len())
}

/// Advection with monotone cubic interpolation (Fritsch–Carlson), the
/// source's choice.
pub(crate) fn cubic_advection() -> Advection {
    Advection {
        interpolation: Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
        ..Advection::default()
    }
}

/// `frames` each enlarged `k` times, `columns` to a row, on white.
pub(crate) fn sheet(frames: &[Image], k: usize, columns: usize) -> R<Image> {
    let shots = frames
        .iter()
        .map(|i| enlarge(i, k))
        .collect::<R<Vec<_>>>()?;
    Ok(Image::contact_sheet(&shots, columns, 6, Vec3::ONE)?)
}

// ---------------------------------------------------------------- Fig. 6

/// The paddle's spin (rad/s).
const ROTOR_SPIN: f32 = 6.0;

/// The rotor's scene: a 2 × 2 × 1 m box of air, `n` cells across, a smoke
/// cloud of radius 0.45 m about the centre and a paddle turning about the
/// vertical axis through it at [`ROTOR_SPIN`]. No buoyancy: only the paddle
/// moves the smoke. The source gives its grid (120 × 60 × 120) and nothing
/// else.
fn rotor_smoke(n: usize) -> R<Smoke> {
    let h = 2.0 / n as f32;
    let dims = Dims::new(n, n, n / 2)?;
    let params = SmokeParams {
        alpha: 0.0,
        beta: 0.0,
        epsilon: 2.0,
        advection: cubic_advection(),
        bounds: Boundaries::closed(),
        ..SmokeParams::default()
    };
    let mut smoke = Smoke::new(dims, h, params)?;
    let centre = Vec3::new(1.0, 1.0, 0.5);
    smoke.add_obstacle(Obstacle {
        shape: Shape::OrientedBox {
            centre,
            half: Vec3::new(0.32, 0.05, 0.14),
            rotation: Quat::IDENTITY,
        },
        velocity: Vec3::ZERO,
        angular_velocity: Vec3::new(0.0, 0.0, ROTOR_SPIN),
        temperature: None,
    })?;
    let cloud = smoke.density_mut();
    for k in 0..n / 2 {
        for j in 0..n {
            for i in 0..n {
                let p = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * h;
                if (p - centre).length() < 0.45 {
                    cloud[(i, j, k)] = 1.0;
                }
            }
        }
    }
    Ok(smoke)
}

/// The density's second moment about the rotor's vertical axis
/// (`Σ ρ r²`, r horizontal, in m²).
fn spread_about_axis(rho: &Grid3<f32>, h: f32) -> f64 {
    let (nx, ny, nz) = rho.dims();
    let mut m = 0.0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let x = (i as f64 + 0.5) * f64::from(h) - 1.0;
                let y = (j as f64 + 0.5) * f64::from(h) - 1.0;
                m += f64::from(rho[(i, j, k)]) * (x * x + y * y);
            }
        }
    }
    m
}

/// Fig. 6: the rotor seen from the side (top row) and from above (bottom
/// row) at four times.
fn rotor(quick: bool) -> R<Image> {
    let n = if quick { 24 } else { 80 };
    let mut smoke = rotor_smoke(n)?;
    let h = smoke.h();
    let dt = 0.02;
    let (steps, every) = if quick { (12, 4) } else { (120, 40) };
    let light = Vec3::new(0.4, -0.3, 1.0).normalize();
    let shoot = |s: &Smoke, normal: usize| {
        render_smoke_volume(s.density(), h, 6.0, 0.9, light, normal, Vec3::splat(0.12))
    };
    let (mut side, mut top) = (vec![shoot(&smoke, 1)?], vec![shoot(&smoke, 2)?]);
    let m0 = spread_about_axis(smoke.density(), h);
    for s in 1..=steps {
        smoke.step(dt)?;
        if s % every == 0 {
            side.push(shoot(&smoke, 1)?);
            top.push(shoot(&smoke, 2)?);
        }
    }
    outln(format_args!(
        "  Fig. 6: spread about the axis grew {:.2}× in {:.1} s",
        spread_about_axis(smoke.density(), h) / m0,
        steps as f32 * dt
    ))?;
    let columns = side.len();
    let mut shots = side;
    shots.extend(top);
    sheet(&shots, if quick { 4 } else { 3 }, columns)
}

// ---------------------------------------------------------------- Fig. 8

/// Fig. 8's scene: a cold blob of smoke falling in a 1 × 1 × 2 m box of
/// `n × n × 2n` cells (the source's grid is 20 × 20 × 40), advected with
/// `interpolation`. The blob is 30 K below ambient, so it sinks under
/// buoyancy; the source does not give its set-up.
fn falling_smoke(n: usize, interpolation: Interpolation) -> R<Smoke> {
    let h = 1.0 / n as f32;
    let params = SmokeParams {
        epsilon: 0.0,
        advection: Advection {
            interpolation,
            ..Advection::default()
        },
        bounds: Boundaries::closed(),
        ..SmokeParams::default()
    };
    let ambient = params.ambient_temperature;
    let mut smoke = Smoke::new(Dims::new(n, n, 2 * n)?, h, params)?;
    let centre = Vec3::new(0.5, 0.5, 1.55);
    for k in 0..2 * n {
        for j in 0..n {
            for i in 0..n {
                let p = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * h;
                if (p - centre).length() < 0.22 {
                    smoke.density_mut()[(i, j, k)] = 1.0;
                    smoke.temperature_mut()[(i, j, k)] = ambient - 30.0;
                }
            }
        }
    }
    Ok(smoke)
}

/// Runs `smoke` for `steps` steps of `dt`, returning the frames taken
/// every `every` steps and the mean seconds per step.
fn fall(smoke: &mut Smoke, steps: usize, every: usize, dt: f32) -> R<(Vec<Grid3<f32>>, f64)> {
    let mut frames = Vec::new();
    let t0 = Instant::now();
    for s in 1..=steps {
        smoke.step(dt)?;
        if s % every == 0 {
            frames.push(smoke.density().clone());
        }
    }
    Ok((frames, t0.elapsed().as_secs_f64() / steps as f64))
}

/// `Σ |∇ρ|²` over the grid by forward differences (per cell², unitless):
/// the detail a field keeps; numerical dissipation lowers it.
fn gradient_energy(rho: &Grid3<f32>) -> f64 {
    let (nx, ny, nz) = rho.dims();
    let mut e = 0.0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let v = f64::from(rho[(i, j, k)]);
                let dx = if i + 1 < nx {
                    f64::from(rho[(i + 1, j, k)]) - v
                } else {
                    0.0
                };
                let dy = if j + 1 < ny {
                    f64::from(rho[(i, j + 1, k)]) - v
                } else {
                    0.0
                };
                let dz = if k + 1 < nz {
                    f64::from(rho[(i, j, k + 1)]) - v
                } else {
                    0.0
                };
                e += dx * dx + dy * dy + dz * dz;
            }
        }
    }
    e
}

/// The two runs of Fig. 8: (frames, seconds per step) for linear and for
/// monotone cubic interpolation.
type Runs = [(Vec<Grid3<f32>>, f64); 2];

fn interpolation_runs(n: usize, steps: usize, every: usize) -> R<Runs> {
    let dt = 0.02;
    let mut lin = falling_smoke(n, Interpolation::Linear)?;
    let mut cub = falling_smoke(
        n,
        Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
    )?;
    Ok([
        fall(&mut lin, steps, every, dt)?,
        fall(&mut cub, steps, every, dt)?,
    ])
}

/// Fig. 8: falling smoke, linear interpolation (top row) against the
/// monotone cubic (bottom row), on the source's 20 × 20 × 40 grid.
fn interpolation(quick: bool) -> R<Image> {
    let n = 20;
    let (steps, every) = if quick { (40, 10) } else { (120, 20) };
    let runs = interpolation_runs(n, steps, every)?;
    let h = 1.0 / n as f32;
    let light = Vec3::new(0.3, -0.5, 1.0).normalize();
    let mut shots = Vec::new();
    for (name, (frames, per_step)) in ["linear", "monotone cubic"].iter().zip(&runs) {
        outln(format_args!(
            "  Fig. 8: {name:<14} {:6.2} ms per step, Σ|∇ρ|² at the end {:.2}",
            per_step * 1e3,
            gradient_energy(frames.last().ok_or_else(|| Exit::new(2, "no frames"))?)
        ))?;
        for f in frames {
            let img = render_smoke_volume(f, h, 8.0, 0.9, light, 1, Vec3::splat(0.1))?;
            shots.push(enlarge(&img, 8)?);
        }
    }
    Ok(Image::contact_sheet(&shots, runs[0].0.len(), 6, Vec3::ONE)?)
}

// ---------------------------------------------------------------- Fig. 9

/// The Hermite cubic through `f0` (s = 0) and `f1` (s = 1) with central
/// slopes from `fm` and `f2` and no limiting (Catmull–Rom): the curve the
/// source's Fig. 9 shows overshooting. With `printed_a3`, the cubic term
/// as App. B prints it (`d_k + d_{k+1} − Δ_k`), which misses `f1`.
fn hermite(fm: f32, f0: f32, f1: f32, f2: f32, s: f32, printed_a3: bool) -> f32 {
    let (d0, d1, delta) = (0.5 * (f1 - fm), 0.5 * (f2 - f0), f1 - f0);
    let a3 = d0 + d1 - if printed_a3 { 1.0 } else { 2.0 } * delta;
    let a2 = 3.0 * delta - 2.0 * d0 - d1;
    ((a3 * s + a2) * s + d0) * s + f0
}

/// How a curve through samples is drawn.
#[derive(Clone, Copy)]
enum Curve {
    /// The unlimited Hermite cubic, `true`: with App. B's printed a3.
    Hermite(bool),
    /// natura's monotone cubic with this limiter.
    Monotone(CubicLimiter),
}

/// The pieces of `curve` through `data` (unit spacing, end values
/// repeated) as `(x, y)` polylines, `per` points per interval: one piece,
/// or one per interval for App. B's printed a3, whose pieces do not meet.
fn curve_pieces(data: &[f32], curve: Curve, per: usize) -> Vec<Vec<(f64, f64)>> {
    let at = |i: isize| data[i.clamp(0, data.len() as isize - 1) as usize];
    let mut pieces = vec![Vec::new()];
    for k in 0..data.len() as isize - 1 {
        let (fm, f0, f1, f2) = (at(k - 1), at(k), at(k + 1), at(k + 2));
        let y = |s: f32| match curve {
            Curve::Hermite(printed) => hermite(fm, f0, f1, f2, s, printed),
            Curve::Monotone(lim) => monotone_cubic(fm, f0, f1, f2, s, lim),
        };
        let last = pieces.len() - 1;
        for m in 0..=per {
            let s = m as f32 / per as f32;
            pieces[last].push((k as f64 + f64::from(s), f64::from(y(s))));
        }
        if let Curve::Hermite(true) = curve {
            pieces.push(Vec::new());
        }
    }
    pieces.retain(|p| !p.is_empty());
    pieces
}

/// Fig. 9's data: a step, where central slopes make the Hermite cubic
/// overshoot both plateaus (by 2/27 of the step).
const STEP: [f32; 8] = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
/// App. B's counterexample to "no overshoot": the paper's sign-only
/// limiter rises to 10.767 on the second interval.
const RAMP: [f32; 4] = [0.0, 10.0, 10.1, 10.2];
/// Linear data, on which the printed a3 jumps at every sample.
const LINE: [f32; 4] = [0.0, 1.0, 2.0, 3.0];

/// Fig. 9 and the two errata beside it: left, the Hermite cubic (dashed)
/// overshoots a step that the monotone cubic (solid) follows; middle, the
/// sign-only limiter the paper prints (dashed) overshoots App. B's ramp,
/// the Fritsch–Carlson limiter (solid) does not; right, App. B's printed
/// a3 (dashed) leaves the data, the corrected cubic (solid) passes through.
fn hermite_figure() -> R<Image> {
    let mut c = Canvas::new(1200, 400);
    let ranges = [
        [-0.5, 8.5, -0.25, 1.25],
        [-0.3, 3.3, -1.0, 12.0],
        [-0.3, 3.3, -0.5, 6.5],
    ];
    let cells = c.grid(3, 1, 14.0, [0.0, 1.0, 0.0, 1.0]);
    let cases: [(&[f32], Curve, Curve); 3] = [
        (
            &STEP,
            Curve::Hermite(false),
            Curve::Monotone(CubicLimiter::FritschCarlson),
        ),
        (
            &RAMP,
            Curve::Monotone(CubicLimiter::PaperSignOnly),
            Curve::Monotone(CubicLimiter::FritschCarlson),
        ),
        (&LINE, Curve::Hermite(true), Curve::Hermite(false)),
    ];
    for ((cell, range), (data, dashed, solid)) in cells.iter().zip(ranges).zip(cases) {
        let panel = Panel::new(cell.rect, range);
        c.axes(&panel, [1.0, if range[3] > 5.0 { 2.0 } else { 0.25 }]);
        for piece in curve_pieces(data, dashed, 64) {
            c.line(&panel, &piece, Pen::dashed(colour::RED, 1.6));
        }
        for piece in curve_pieces(data, solid, 64) {
            c.line(&panel, &piece, Pen::solid(colour::BLUE, 1.8));
        }
        let samples: Vec<(f64, f64)> = data
            .iter()
            .enumerate()
            .map(|(i, &v)| (i as f64, f64::from(v)))
            .collect();
        c.dots(&panel, &samples, colour::INK, 4.0);
    }
    Ok(c.into_image()?)
}

#[cfg(test)]
mod tests {
    use super::objects::{objects_smoke, sphere_smoke};
    use super::*;

    /// The extremes of `curve` through `data`, sampled finely.
    fn extremes(data: &[f32], curve: Curve) -> (f32, f32) {
        curve_pieces(data, curve, 1000)
            .iter()
            .flatten()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.1 as f32), hi.max(p.1 as f32))
            })
    }

    #[test]
    fn the_hermite_cubic_overshoots_the_step_and_the_monotone_one_does_not() {
        // Fig. 9: central slopes overshoot both plateaus of a steep step.
        let (lo, hi) = extremes(&STEP, Curve::Hermite(false));
        // The cubic 1 + s/2 − s² + s³/2 peaks at s = 1/3: 1 + 2/27.
        assert!(
            (hi - (1.0 + 2.0 / 27.0)).abs() < 1e-4 && (lo + 2.0 / 27.0).abs() < 1e-4,
            "{lo} {hi}"
        );
        let (lo, hi) = extremes(&STEP, Curve::Monotone(CubicLimiter::FritschCarlson));
        assert!(lo >= 0.0 && hi <= 1.0, "{lo} {hi}");
    }

    #[test]
    fn the_papers_sign_only_limiter_reaches_10_767_on_its_counterexample() {
        // App. B claims no overshoot; on (0, 10, 10.1, 10.2) the sign-only
        // limiter peaks at 10.767 (the digest's computed value), the
        // Fritsch–Carlson limiter at the data's 10.2.
        let (_, hi) = extremes(&RAMP, Curve::Monotone(CubicLimiter::PaperSignOnly));
        assert!((hi - 10.767).abs() < 2e-3, "{hi}");
        let (lo, hi) = extremes(&RAMP, Curve::Monotone(CubicLimiter::FritschCarlson));
        assert!(lo >= 0.0 && hi <= 10.2 + 1e-5, "{lo} {hi}");
    }

    #[test]
    fn the_printed_a3_misses_the_next_sample_and_the_corrected_one_hits_it() {
        // App. B as printed: f(s = 1) = f_k + 2Δ_k, so 3 instead of 2 on
        // (0, 1, 2, 3) between the samples 1 and 2.
        assert_eq!(hermite(0.0, 1.0, 2.0, 3.0, 1.0, true), 3.0);
        assert_eq!(hermite(0.0, 1.0, 2.0, 3.0, 1.0, false), 2.0);
        // The corrected cubic is exact on linear data.
        for m in 0..=10 {
            let s = m as f32 / 10.0;
            assert!((hermite(0.0, 1.0, 2.0, 3.0, s, false) - (1.0 + s)).abs() < 1e-6);
        }
    }

    #[test]
    fn monotone_cubic_falling_smoke_keeps_more_detail_and_no_new_extremes() {
        // Fig. 8: the cubic keeps finer detail than linear interpolation;
        // with the Fritsch–Carlson limiter neither creates density above
        // the blob's 1 or below 0 (no sources: a maximum principle).
        let runs = interpolation_runs(12, 30, 30).unwrap();
        let last = |r: &(Vec<Grid3<f32>>, f64)| r.0.last().unwrap().clone();
        let (lin, cub) = (last(&runs[0]), last(&runs[1]));
        let (el, ec) = (gradient_energy(&lin), gradient_energy(&cub));
        assert!(ec > 1.2 * el, "cubic {ec} linear {el}");
        for g in [&lin, &cub] {
            let s = g.as_slice();
            assert!(s.iter().all(|&v| (-1e-6..=1.0 + 1e-5).contains(&v)));
        }
        // Both carry the blob down: its centre of mass is below its start.
        let z = |g: &Grid3<f32>| {
            let (nx, ny, nz) = g.dims();
            let (mut m, mut mz) = (0.0f64, 0.0f64);
            for k in 0..nz {
                for j in 0..ny {
                    for i in 0..nx {
                        m += f64::from(g[(i, j, k)]);
                        mz += f64::from(g[(i, j, k)]) * (k as f64 + 0.5) / nx as f64;
                    }
                }
            }
            mz / m
        };
        assert!(z(&lin) < 1.5 && z(&cub) < 1.5, "{} {}", z(&lin), z(&cub));
    }

    #[test]
    fn the_rotor_throws_smoke_out_sideways_and_draws_air_in_along_its_axis() {
        // Fig. 6's caption: smoke pushed out horizontally, sucked in
        // vertically.
        let n = 24;
        let mut smoke = rotor_smoke(n).unwrap();
        let h = smoke.h();
        let m0 = spread_about_axis(smoke.density(), h);
        for _ in 0..60 {
            smoke.step(0.02).unwrap();
        }
        let m1 = spread_about_axis(smoke.density(), h);
        assert!(m1 > 1.1 * m0, "spread {m0} → {m1}");
        // Vertical velocity on the axis: down above the paddle, up below.
        let w = smoke.velocity().comp(2);
        let (c, nz) = (n / 2, n / 2);
        let above = w[(c, c, nz - 2)];
        let below = w[(c, c, 2)];
        assert!(above < 0.0 && below > 0.0, "above {above} below {below}");
    }

    /// The smoke (Σ ρ over cells) beyond `x` (m) and above `z` (m).
    fn beyond(smoke: &Smoke, x: f32, z: f32) -> f64 {
        let rho = smoke.density();
        let (nx, ny, nz) = rho.dims();
        let h = smoke.h();
        let mut sum = 0.0f64;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    if (i as f32 + 0.5) * h > x && (k as f32 + 0.5) * h > z {
                        sum += f64::from(rho[(i, j, k)]);
                    }
                }
            }
        }
        sum
    }

    #[test]
    fn smoke_passes_the_objects_and_rises_around_the_ball() {
        // Fig. 4: the smoke rises past the three objects to above the
        // highest (whose top is at 0.75 m at most).
        let mut smoke = objects_smoke(32).unwrap();
        assert_eq!(beyond(&smoke, 0.0, 0.75), 0.0);
        for _ in 0..200 {
            smoke.step(0.02).unwrap();
        }
        let past = beyond(&smoke, 0.0, 0.75);
        assert!(past > 1.0, "smoke above the highest object: {past}");
        // Fig. 5: the plume rises around the ball to above its top (0.85 m)
        // within 4 s, on a grid of 40 cells across (on coarser ones it
        // lingers under the ball longer).
        let mut smoke = sphere_smoke(40).unwrap();
        assert_eq!(beyond(&smoke, 0.0, 0.9), 0.0);
        for _ in 0..200 {
            smoke.step(0.02).unwrap();
        }
        let above = beyond(&smoke, 0.0, 0.9);
        assert!(above > 1.0, "smoke above the ball: {above}");
    }

    #[test]
    fn the_rising_smoke_is_lifted_by_its_buoyancy_alone() {
        // Fig. 3: buoyancy is the only external force. After 1.2 s the
        // plume's top is far above its source (0.25 m up, 0.18 m in radius) and
        // the flow swirls; with the buoyancy's coefficients at zero nothing
        // moves: the smoke stays in the source and the air is still.
        let height = |lift: bool| {
            let mut smoke = rising_smoke(25, lift).unwrap();
            for _ in 0..60 {
                smoke.step(0.02).unwrap();
            }
            // The top of the smoke: the highest cell denser than 0.05.
            let rho = smoke.density();
            let (nx, ny, nz) = rho.dims();
            let top = (0..nz)
                .filter(|&k| (0..ny).any(|j| (0..nx).any(|i| rho[(i, j, k)] > 0.05)))
                .max()
                .unwrap_or(0);
            (
                (top as f64 + 0.5) * f64::from(smoke.h()),
                vorticity_in_smoke(&smoke).unwrap(),
            )
        };
        let (lifted, swirl) = height(true);
        let (still, calm) = height(false);
        assert!(lifted > 0.55, "the smoke's top at {lifted} m");
        assert!(still < 0.4, "without buoyancy its top at {still} m");
        assert!(
            swirl > 1.0 && calm < 1e-6,
            "vorticity {swirl} against {calm}"
        );
    }

    #[test]
    fn every_figure_writes_its_files() {
        assert_eq!(Fig::ALL.len(), 6);
        for f in Fig::ALL {
            assert_eq!(f.files().len(), 1);
        }
    }
}
