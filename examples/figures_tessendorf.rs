//! Tessendorf's figures (Tessendorf 2001, "Simulating Ocean Water") that
//! the ocean example does not show, re-made with natura-ocean: Gerstner
//! profiles, the quantised dispersion relation, the |k̂·ŵ|⁶ spectrum,
//! choppy profiles with the Jacobian and its smaller eigenvalue, and the
//! Fresnel reflectivity from above and from below.
//!
//! ```text
//! cargo run --release --example figures_tessendorf                 # into ./figures_tessendorf/
//! cargo run --release --example figures_tessendorf -- --quick --out /tmp/tess
//! cargo run --release --example figures_tessendorf -- --only fresnel
//! cargo run --release --example figures_tessendorf -- --help       # every flag and its default
//! ```
//!
//! One picture per figure or pair of figures (`tessendorf_fig03-04_gerstner.png`,
//! …); docs/figures.md sets each beside the source's caption. Plots carry
//! no text; where the source draws a dashed and a solid curve, so do they.
//! The world is z up: the notes' height y is z here.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure};
use common::plot::{Canvas, Panel, Pen, colour};
use common::{Exit, Run, outln};
use natura::core::colour::srgb_decode;
use natura::core::glam::{DVec2, Vec3};
use natura::core::preview::{PreviewCamera, PreviewProjection, Projector, Raster};
use natura::core::{Grid2, Image};
use natura::ocean::optics::{N_AIR, N_WATER, critical_angle, fresnel_reflectance, reflect};
use natura::ocean::preview::TopView;
use natura::ocean::{
    Dispersion, DispersionRelation, Frame, G, GerstnerSea, GerstnerWave, Ocean, OceanParams,
    Phillips, Quantized, Seed,
};

/// Tessendorf's ocean figures (Tessendorf 2001) not shown by the ocean
/// example: Gerstner profiles, quantised dispersion, the |k̂·ŵ|⁶ spectrum,
/// choppy profiles with the Jacobian and its eigenvalue, and Fresnel
/// reflectivity from air and from water.
#[derive(Parser)]
#[command(name = "figures_tessendorf", version)]
struct Cli {
    /// Small and fast (CI): smaller grids
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Random seed
    #[arg(long, default_value_t = 2001)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_tessendorf")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Figs. 3-4: two single-mode Gerstner profiles and a 3-mode one
    Gerstner,
    /// Fig. 5: ω = √(gk) and its quantisation for repeat times of 20 s and 100 s
    Dispersion,
    /// Figs. 6-8: height, x-slope, and height with |k̂·ŵ|⁶, in grey
    Directional,
    /// Figs. 14-16 and 19-20: choppy profiles, their evolution, the Jacobian and J₋
    Choppy,
    /// Figs. 21-22: Fresnel reflectivity, air to water and water to air
    Fresnel,
    /// Figs. 9, 17-18, 23-24: perspective renders (facet sizes, chop, shaders)
    Renders,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[
        Fig::Gerstner,
        Fig::Dispersion,
        Fig::Directional,
        Fig::Choppy,
        Fig::Fresnel,
        Fig::Renders,
    ];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::Gerstner => &["tessendorf_fig03-04_gerstner.png"],
            Fig::Dispersion => &["tessendorf_fig05_quantised_dispersion.png"],
            Fig::Directional => &["tessendorf_fig06-08_directional.png"],
            Fig::Choppy => &[
                "tessendorf_fig14_choppy_profile.png",
                "tessendorf_fig15_choppy_sequence.png",
                "tessendorf_fig16_jacobian.png",
                "tessendorf_fig19_profiles.png",
                "tessendorf_fig20_eigenvalue.png",
            ],
            Fig::Fresnel => &["tessendorf_fig21-22_fresnel.png"],
            Fig::Renders => &[
                "tessendorf_fig09_facet_sizes.png",
                "tessendorf_fig17-18_chop.png",
                "tessendorf_fig23-24_shaders.png",
            ],
        }
    }
}

type R<T> = Result<T, Exit>;

fn main() -> ExitCode {
    common::run(figures)
}

fn figures() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let seed = Seed(cli.seed);
    figures::make(&out, &cli.only, |fig| {
        Ok(match fig {
            Fig::Gerstner => vec![gerstner()?],
            Fig::Dispersion => vec![dispersion()?],
            Fig::Directional => vec![directional(seed, cli.quick)?],
            Fig::Choppy => choppy(seed, cli.quick)?,
            Fig::Fresnel => vec![fresnel()?],
            Fig::Renders => renders(seed, cli.quick)?,
        })
    })
}

/// The mean of the squares of `v` (its variance about zero), in f64.
fn mean_square(v: &[f32]) -> f64 {
    v.iter().map(|&x| f64::from(x) * f64::from(x)).sum::<f64>() / v.len().max(1) as f64
}

/// A Gerstner sea of waves travelling along +x: (wavelength m, kA, phase).
fn gerstner_sea(waves: &[(f64, f64, f64)]) -> R<GerstnerSea> {
    let deep = Dispersion::Deep { g: G };
    let w = waves
        .iter()
        .map(|&(length, ka, phase)| {
            let k = std::f64::consts::TAU / length;
            GerstnerWave::new(DVec2::new(k, 0.0), ka / k, phase, &deep)
        })
        .collect();
    Ok(GerstnerSea::new(w)?)
}

/// The profile (x, z) of the particles with rest positions 0..`length` m on y = 0.
fn gerstner_profile(sea: &GerstnerSea, length: f64) -> Vec<(f64, f64)> {
    (0..=800)
        .map(|i| {
            let p = sea.position(DVec2::new(length * f64::from(i) / 800.0, 0.0), 0.0);
            (p.x, p.z)
        })
        .collect()
}

/// The seas of Figs. 3-4. The source gives no parameters; these are a
/// gentle and a steep single wave, and three waves with Σ kA = 0.9.
fn gerstner_seas() -> R<[GerstnerSea; 3]> {
    Ok([
        gerstner_sea(&[(20.0, 0.4, 0.0)])?,
        gerstner_sea(&[(12.0, 0.9, 0.0)])?,
        gerstner_sea(&[(24.0, 0.4, 0.0), (9.0, 0.3, 1.3), (5.5, 0.2, 4.1)])?,
    ])
}

/// Figs. 3-4: the two single-mode profiles (top two) and the 3-mode one,
/// drawn to scale.
fn gerstner() -> R<Image> {
    let mut c = Canvas::new(900, 540);
    let rows = c.grid(1, 3, 8.0, [0.0, 1.0, 0.0, 1.0]);
    for (k, sea) in gerstner_seas()?.iter().enumerate() {
        let panel = Panel::equal_aspect(rows[k].rect, [0.0, 60.0], 0.0);
        c.axes(&panel, [5.0, 1.0]);
        c.line(
            &panel,
            &gerstner_profile(sea, 60.0),
            Pen::solid(colour::BLUE, 1.6),
        );
    }
    Ok(c.into_image()?)
}

/// Fig. 5: ω = √(gk) (black) and its quantisation to multiples of
/// ω₀ = 2π/T for T = 20 s (red) and T = 100 s (blue), 0 ≤ k ≤ 0.2 rad/m.
fn dispersion() -> R<Image> {
    let deep = Dispersion::Deep { g: G };
    let mut c = Canvas::new(800, 560);
    let panel = Panel::new([30.0, 20.0, 780.0, 540.0], [0.0, 0.2, 0.0, 1.45]);
    c.axes(&panel, [0.02, 0.2]);
    let ks: Vec<f64> = (0..=4000).map(|i| 0.2 * f64::from(i) / 4000.0).collect();
    let curve = |r: &dyn DispersionRelation| -> Vec<(f64, f64)> {
        ks.iter().map(|&k| (k, r.omega(k))).collect()
    };
    for (period, col) in [(20.0, colour::RED), (100.0, colour::BLUE)] {
        let q = Quantized::new(deep, period)?;
        c.line(&panel, &curve(&q), Pen::solid(col, 1.5));
        outln(format_args!(
            "  Fig. 5: T = {period} s: ω₀ = {:.4} rad/s; waves longer than {:.0} m stand still",
            q.omega0(),
            std::f64::consts::TAU * G / (q.omega0() * q.omega0())
        ))?;
    }
    c.line(&panel, &curve(&deep), Pen::solid(colour::INK, 1.5));
    Ok(c.into_image()?)
}

/// The Phillips spectrum of Figs. 6-8: V = 31 m/s along +x, ℓ = 1 m,
/// directional exponent `p` (2 in eq. 23, 6 in Fig. 8).
fn gale(p: f64) -> Phillips {
    Phillips {
        wind_speed: 31.0,
        wind_direction: 0.0,
        small_wave_length: 1.0,
        direction_exponent: p,
        ..Phillips::default()
    }
}

/// A grey picture of the top-left `n × n` of `g`, from the grid's minimum
/// (black) to its maximum (white).
fn grey(g: &Grid2<f32>, n: usize) -> R<Image> {
    let (lo, hi) = g.min_max();
    let span = (hi - lo).max(1e-12);
    Ok(Image::from_fn(
        n.min(g.width()),
        n.min(g.height()),
        |x, y| Vec3::splat(srgb_decode((g[(x, y)] - lo) / span)),
    )?)
}

/// Figs. 6-8: one 1000 m patch (512² samples; 128² with --quick) under a
/// 31 m/s gale along +x: height (6) and x-slope (7) with |k̂·ŵ|², height
/// with |k̂·ŵ|⁶ (8), greyscale, side by side; each shows the top-left 750 m
/// of the patch.
fn directional(seed: Seed, quick: bool) -> R<Image> {
    let n = if quick { 128 } else { 512 };
    let params = OceanParams {
        nx: n,
        ny: n,
        lx: 1000.0,
        ly: 1000.0,
        ..OceanParams::default()
    };
    // The top-left 3/4 of the patch, so the sheet stays small.
    let crop = 3 * n / 4;
    let mut shots = Vec::new();
    for p in [2.0, 6.0] {
        let frame = Ocean::new(&params, &gale(p), seed)?.evaluate(0.0)?;
        let ratio =
            mean_square(frame.slope_y().as_slice()) / mean_square(frame.slope_x().as_slice());
        outln(format_args!(
            "  Figs. 6-8: |k̂·ŵ|^{p}: slope variance across / along the wind {ratio:.3} (1/(p+1) = {:.3} for a wide band)",
            1.0 / (p + 1.0)
        ))?;
        shots.push(grey(frame.height(), crop)?);
        if p == 2.0 {
            shots.push(grey(frame.slope_x(), crop)?);
        }
    }
    let factor = if quick { 1 } else { 2 };
    let small: Vec<Image> = shots
        .iter()
        .map(|s| s.box_downsample(factor))
        .collect::<natura::core::Result<_>>()?;
    Ok(Image::contact_sheet(&small, 3, 6, Vec3::ONE)?)
}

/// A wind sea for the choppy figures: 200 m patch, 6 m/s along +x (waves
/// of about 30 m), |k̂·ŵ|⁶ so that a slice along the wind shows the waves'
/// shape.
fn choppy_ocean(seed: Seed, quick: bool, choppiness: f64) -> R<Ocean> {
    let n = if quick { 256 } else { 512 };
    let params = OceanParams {
        nx: n,
        ny: n,
        lx: 200.0,
        ly: 200.0,
        choppiness,
        ..OceanParams::default()
    };
    let spectrum = Phillips {
        wind_speed: 6.0,
        small_wave_length: 0.2,
        direction_exponent: 6.0,
        ..Phillips::default()
    };
    Ok(Ocean::new(&params, &spectrum, seed)?)
}

/// The smallest J₋ of `frame`.
fn min_j_minus(frame: &Frame) -> f32 {
    let (nx, ny) = frame.dims();
    (0..nx * ny)
        .map(|k| frame.eigen(k % nx, k / nx).j_minus)
        .fold(f32::MAX, f32::min)
}

/// The row of `frame` with the most negative J₋ (the strongest fold).
fn folded_row(frame: &Frame) -> usize {
    let (nx, ny) = frame.dims();
    (0..ny)
        .map(|j| {
            let m = (0..nx)
                .map(|i| frame.eigen(i, j).j_minus)
                .fold(f32::MAX, f32::min);
            (j, m)
        })
        .fold((0, f32::MAX), |a, b| if b.1 < a.1 { b } else { a })
        .0
}

/// Samples `i0..i0 + len` of row `j`: the undisplaced profile (x, h), the
/// displaced one (x + D_x, h), J and J₋.
struct Slice {
    flat: Vec<(f64, f64)>,
    chop: Vec<(f64, f64)>,
    jac: Vec<(f64, f64)>,
    j_minus: Vec<(f64, f64)>,
}

fn slice(frame: &Frame, j: usize, i0: usize, len: usize) -> Slice {
    let dx = f64::from(frame.cell_size().x);
    let nx = frame.dims().0;
    let mut s = Slice {
        flat: Vec::new(),
        chop: Vec::new(),
        jac: Vec::new(),
        j_minus: Vec::new(),
    };
    for k in 0..len {
        let i = (i0 + k) % nx;
        let x = (k as f64) * dx;
        let p = frame.position(i, j);
        let h = f64::from(p.z);
        s.flat.push((x, h));
        s.chop.push((x + f64::from(p.x) - (i as f64) * dx, h));
        s.jac.push((x, f64::from(frame.jacobian(i, j))));
        s.j_minus.push((x, f64::from(frame.eigen(i, j).j_minus)));
    }
    s
}

/// Figs. 14-16 and 19-20 from one seed: a slice 100 m long along the
/// wind, through the row with the strongest fold.
fn choppy(seed: Seed, quick: bool) -> R<Vec<Image>> {
    let (mild, strong) = (4.0, 6.0);
    let ocean = choppy_ocean(seed, quick, mild)?;
    let frame = ocean.evaluate(0.0)?;
    let hard = choppy_ocean(seed, quick, strong)?.evaluate(0.0)?;
    let dx = f64::from(frame.cell_size().x);
    let len = (100.0 / dx) as usize;
    let j = folded_row(&hard);
    outln(format_args!(
        "  min J₋ over the patch: {:.2} (choppiness {mild}), {:.2} ({strong})",
        min_j_minus(&frame),
        min_j_minus(&hard)
    ))?;
    // Start the slice 30 m before the row's deepest fold.
    let nx = frame.dims().0;
    let deepest = (0..nx)
        .min_by(|&a, &b| {
            hard.eigen(a, j)
                .j_minus
                .total_cmp(&hard.eigen(b, j).j_minus)
        })
        .unwrap_or(0);
    let i0 = (deepest + nx - (30.0 / dx) as usize) % nx;
    let s = slice(&frame, j, i0, len);
    let hmax = s.flat.iter().map(|p| p.1.abs()).fold(0.5, f64::max) * 1.2;
    let wide = [900.0f32, 300.0];
    let profile_panel = |rect| Panel::new(rect, [0.0, 100.0, -hmax, hmax]);

    // Fig. 14: dashed without, solid with the displacement.
    let mut c14 = Canvas::new(wide[0] as usize, wide[1] as usize);
    let p = profile_panel([8.0, 8.0, wide[0] - 8.0, wide[1] - 8.0]);
    c14.axes(&p, [10.0, 1.0]);
    c14.line(&p, &s.flat, Pen::dashed(colour::INK, 1.3));
    c14.line(&p, &s.chop, Pen::solid(colour::BLUE, 1.6));

    // Fig. 15: the displaced profile every 0.5 s, top to bottom.
    let steps = 5;
    let mut c15 = Canvas::new(900, 110 * steps);
    let rows = c15.grid(1, steps, 5.0, [0.0, 1.0, 0.0, 1.0]);
    let mut f = frame.clone();
    for (k, row) in rows.iter().enumerate() {
        ocean.evaluate_into(0.5 * k as f64, &mut f)?;
        let p = profile_panel(row.rect);
        c15.axes(&p, [10.0, 0.0]);
        c15.line(
            &p,
            &slice(&f, j, i0, len).chop,
            Pen::solid(colour::BLUE, 1.4),
        );
    }

    // Fig. 16: the profiles and, below, the Jacobian J along the displaced one.
    let jmin = s.jac.iter().map(|p| p.1).fold(-0.5, f64::min);
    let jmax = s.jac.iter().map(|p| p.1).fold(1.5, f64::max);
    let c16 = profile_and(&s, hmax, &s.jac, [jmin, jmax])?;

    // Figs. 19-20: no chop against strong chop, and J₋ below.
    let t = slice(&hard, j, i0, len);
    let mut c19 = Canvas::new(wide[0] as usize, wide[1] as usize);
    let p = profile_panel([8.0, 8.0, wide[0] - 8.0, wide[1] - 8.0]);
    c19.axes(&p, [10.0, 1.0]);
    c19.line(&p, &t.flat, Pen::solid(colour::INK, 1.3));
    c19.line(&p, &t.chop, Pen::solid(colour::RED, 1.5));
    let lo = t.j_minus.iter().map(|p| p.1).fold(-0.5, f64::min);
    let hi = t.j_minus.iter().map(|p| p.1).fold(1.5, f64::max);
    let c20 = profile_and(&t, hmax, &t.j_minus, [lo, hi])?;
    let folds = t.j_minus.iter().filter(|p| p.1 < 0.0).count();
    outln(format_args!(
        "  Figs. 14-20: choppiness {mild} and {strong} (the notes' λ = −{mild}, −{strong}); \
         {folds} of {len} samples of the strong slice have J₋ < 0"
    ))?;
    Ok(vec![
        c14.into_image()?,
        c15.into_image()?,
        c16,
        c19.into_image()?,
        c20,
    ])
}

/// The displaced profile (top; red dots where the lower curve is negative)
/// over a second curve (bottom) with its zero line.
fn profile_and(s: &Slice, hmax: f64, lower: &[(f64, f64)], range: [f64; 2]) -> R<Image> {
    let mut c = Canvas::new(900, 460);
    let top = Panel::new([8.0, 8.0, 892.0, 238.0], [0.0, 100.0, -hmax, hmax]);
    let bottom = Panel::new([8.0, 248.0, 892.0, 452.0], [0.0, 100.0, range[0], range[1]]);
    c.axes(&top, [10.0, 1.0]);
    c.line(&top, &s.flat, Pen::dashed(colour::GUIDE, 1.0));
    c.line(&top, &s.chop, Pen::solid(colour::BLUE, 1.6));
    let folded: Vec<(f64, f64)> = s
        .chop
        .iter()
        .zip(lower)
        .filter(|(_, l)| l.1 < 0.0)
        .map(|(p, _)| *p)
        .collect();
    c.dots(&top, &folded, colour::RED, 2.0);
    c.axes(&bottom, [10.0, 0.5]);
    c.line(
        &bottom,
        &[(0.0, 1.0), (100.0, 1.0)],
        Pen::dashed(colour::GUIDE, 1.0),
    );
    c.line(&bottom, lower, Pen::solid(colour::RED, 1.5));
    Ok(c.into_image()?)
}

/// The reflectivity at `from_surface` degrees (the source's axis: 0 grazing,
/// 90 normal incidence), from index `n_i` into `n_t`.
fn reflectivity(from_surface: f64, n_i: f64, n_t: f64) -> f64 {
    fresnel_reflectance(from_surface.to_radians().sin(), n_i, n_t)
}

/// Figs. 21-22: R from air into water (left) and from water into air
/// (right) against the angle from the surface, 0-90°; a grey line marks
/// where total internal reflection begins (41.4° from the surface).
fn fresnel() -> R<Image> {
    let mut c = Canvas::new(900, 360);
    let cells = c.grid(2, 1, 10.0, [0.0, 90.0, 0.0, 1.05]);
    let angles: Vec<f64> = (0..=900).map(|i| f64::from(i) / 10.0).collect();
    for (k, (n_i, n_t)) in [(N_AIR, N_WATER), (N_WATER, N_AIR)].into_iter().enumerate() {
        let panel = cells[k];
        c.axes(&panel, [10.0, 0.1]);
        if let Some(theta) = critical_angle(n_i, n_t) {
            let edge = 90.0 - theta.to_degrees();
            c.line(
                &panel,
                &[(edge, 0.0), (edge, 1.05)],
                Pen::dashed(colour::GUIDE, 1.0),
            );
            outln(format_args!(
                "  Fig. 22: total internal reflection from {:.1}° from the normal ({edge:.1}° from the surface)",
                theta.to_degrees()
            ))?;
        }
        let r: Vec<(f64, f64)> = angles
            .iter()
            .map(|&a| (a, reflectivity(a, n_i, n_t)))
            .collect();
        c.line(&panel, &r, Pen::solid(colour::INK, 1.6));
    }
    outln(format_args!(
        "  Fig. 21: R at normal incidence {:.4}",
        reflectivity(90.0, N_AIR, N_WATER)
    ))?;
    Ok(c.into_image()?)
}

/// How a render shades the water.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Look {
    /// A generic plastic: grey-blue, diffuse plus a highlight (Figs. 17-18, 23).
    Plastic,
    /// natura-ocean's water shader: Fresnel-weighted sky and upwelling light (Figs. 9, 24).
    Water,
}

/// A perspective view over `frame`'s surface from 0.1 patch lengths up,
/// the patch tiled 3 × 2 (it is periodic) and continued to the horizon by a
/// flat plane, under natura-ocean's preview sky.
fn render_view(frame: &Frame, look: Look, size: (u32, u32)) -> R<Image> {
    let (nx, ny) = frame.dims();
    let l = frame.extent().x;
    let top = TopView::default();
    let sky = |d: Vec3| top.sky(d);
    let eye = Vec3::new(0.5 * l, -0.05 * l, 0.12 * l);
    let camera = PreviewCamera {
        eye,
        target: Vec3::new(0.5 * l, 0.25 * l, 0.0),
        up: Vec3::Z,
        projection: PreviewProjection::Perspective { fov_y_deg: 30.0 },
    };
    let mut raster = Raster::new(size.0, size.1, 2, top.horizon)?;
    let (w, h) = raster.samples();
    let view = Projector::new(&camera, w, h)?;
    let light = Vec3::new(-0.85, 0.35, 0.3).normalize();
    let shade = |p: Vec3, n: Vec3| -> Vec3 {
        let n = n.normalize_or(Vec3::Z);
        let incident = (p - eye).normalize_or(Vec3::Y);
        match look {
            Look::Water => top.shader.shade(incident, n, p.distance(eye), Some(&sky)),
            Look::Plastic => {
                let highlight = reflect(incident, n).dot(light).max(0.0).powi(40);
                Vec3::new(0.30, 0.34, 0.40) * (0.25 + 0.75 * n.dot(light).max(0.0))
                    + Vec3::splat(0.6 * highlight)
            }
        }
    };
    // One tile's points and normals with a wrapped last row and column.
    let (tx, ty) = (nx + 1, ny + 1);
    let mut pos = Vec::with_capacity(tx * ty);
    let mut nrm = Vec::with_capacity(tx * ty);
    for j in 0..ty {
        for i in 0..tx {
            let wrap = Vec3::new((i / nx) as f32 * l, (j / ny) as f32 * l, 0.0);
            pos.push(frame.position(i % nx, j % ny) + wrap);
            nrm.push(frame.normal_up(i % nx, j % ny));
        }
    }
    for (ox, oy) in [
        (-1.0, 0.0),
        (0.0, 0.0),
        (1.0, 0.0),
        (-1.0, 1.0),
        (0.0, 1.0),
        (1.0, 1.0),
    ] {
        let off = Vec3::new(ox * l, oy * l, 0.0);
        let world: Vec<Vec3> = pos.iter().map(|&p| p + off).collect();
        let screen: Vec<Option<[f32; 3]>> = world.iter().map(|&p| view.project(p)).collect();
        for j in 0..ny {
            for i in 0..nx {
                let k = j * tx + i;
                for t in [[k, k + 1, k + tx + 1], [k, k + tx + 1, k + tx]] {
                    let [a, b, c] = t;
                    if let (Some(sa), Some(sb), Some(sc)) = (screen[a], screen[b], screen[c]) {
                        raster.triangle([sa, sb, sc], |f| {
                            shade(
                                f.mix([world[a], world[b], world[c]]),
                                f.mix([nrm[a], nrm[b], nrm[c]]),
                            )
                        })?;
                    }
                }
            }
        }
    }
    // Calm water from the tiles' far edge to the horizon.
    let far = [(-60.0, 2.0), (61.0, 2.0), (61.0, 400.0), (-60.0, 400.0)]
        .map(|(x, y)| Vec3::new(x * l, y * l, 0.0));
    for t in [[0, 1, 2], [0, 2, 3]] {
        let p = t.map(|i| far[i]);
        if let [Some(a), Some(b), Some(c)] = p.map(|q| view.project(q)) {
            raster.triangle([a, b, c], |f| shade(f.mix(p), Vec3::Z))?;
        }
    }
    Ok(raster.resolve()?)
}

/// A wind sea of `n`² samples over `length` metres, `wind` m/s along +y
/// (away from the camera), with `choppiness`.
fn render_ocean(seed: Seed, n: usize, length: f64, wind: f64, choppiness: f64) -> R<Frame> {
    let params = OceanParams {
        nx: n,
        ny: n,
        lx: length,
        ly: length,
        choppiness,
        ..OceanParams::default()
    };
    let spectrum = Phillips {
        wind_speed: wind,
        wind_direction: std::f64::consts::FRAC_PI_2,
        small_wave_length: 0.0,
        ..Phillips::default()
    };
    Ok(Ocean::new(&params, &spectrum, seed)?.evaluate(0.0)?)
}

/// Figs. 9, 17-18 and 23-24 as perspective views: the water shader on a
/// 6.4 m patch at facet sizes 10, 5 and 2.5 cm (9, top to bottom); a 64 m
/// patch without and with strong chop in plastic (17, 18); the choppy
/// patch in plastic and in the water shader (23, 24).
fn renders(seed: Seed, quick: bool) -> R<Vec<Image>> {
    let size = if quick { (200, 112) } else { (400, 225) };
    let facets: &[usize] = if quick {
        &[16, 32, 64]
    } else {
        &[64, 128, 256]
    };
    let mut fig9 = Vec::new();
    for &n in facets {
        let frame = render_ocean(seed, n, 6.4, 3.0, 0.0)?;
        fig9.push(render_view(&frame, Look::Water, size)?);
    }
    let n = if quick { 64 } else { 256 };
    let calm = render_ocean(seed, n, 64.0, 9.0, 0.0)?;
    let chop = render_ocean(seed, n, 64.0, 9.0, 2.0)?;
    let (plain, choppy) = (
        render_view(&calm, Look::Plastic, size)?,
        render_view(&chop, Look::Plastic, size)?,
    );
    let water = render_view(&chop, Look::Water, size)?;
    let white = Vec3::ONE;
    Ok(vec![
        Image::contact_sheet(&fig9, 1, 4, white)?,
        Image::contact_sheet(&[plain, choppy.clone()], 2, 4, white)?,
        Image::contact_sheet(&[choppy, water], 2, 4, white)?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura::ocean::Spectrum;

    #[test]
    fn gerstner_profiles_do_not_loop_below_ka_one() {
        // Figs. 3-4: kA < 1 keeps the profile a graph (x increases along it);
        // kA ≥ 1 would loop, and a single wave that steep is refused.
        for sea in gerstner_seas().unwrap() {
            assert!(sea.is_loop_free());
            let p = gerstner_profile(&sea, 60.0);
            assert!(p.windows(2).all(|w| w[1].0 > w[0].0));
        }
        assert!(gerstner_sea(&[(10.0, 1.0, 0.0)]).is_err());
    }

    #[test]
    fn quantised_dispersion_of_fig_5() {
        let deep = Dispersion::Deep { g: G };
        for (period, omega0) in [(20.0, 0.314_159), (100.0, 0.062_832)] {
            let q = Quantized::new(deep, period).unwrap();
            assert!((q.omega0() - omega0).abs() < 1e-6);
            for i in 0..=2000 {
                let k = 0.2 * f64::from(i) / 2000.0;
                let (w, wq) = (deep.omega(k), q.omega(k));
                assert!(wq <= w && w - wq < q.omega0(), "T {period}, k {k}");
                assert_eq!((wq / q.omega0()).fract(), 0.0);
            }
        }
        // T = 20 s: deep-water waves longer than 2πg/ω₀² ≈ 624 m stand still.
        let q = Quantized::new(deep, 20.0).unwrap();
        let k_still = q.omega0().powi(2) / G;
        assert!((std::f64::consts::TAU / k_still - 624.0).abs() < 1.0);
        assert_eq!(q.omega(0.99 * k_still), 0.0);
        assert!(q.omega(1.01 * k_still) > 0.0);
    }

    #[test]
    fn the_sixth_power_aligns_the_waves_with_the_wind() {
        // Fig. 8: |k̂·ŵ|^p leaves the slope variance across the wind 1/(p+1)
        // of that along it (the angular integrals of sin² and cos² times
        // |cos|^p): 1/3 for eq. 23's p = 2, 1/7 for p = 6.
        let (l, n) = (8000.0, 1024i32);
        let dk = std::f64::consts::TAU / l;
        for p in [2.0, 6.0] {
            let s = gale(p);
            let (mut along, mut across) = (0.0, 0.0);
            for a in -n / 2..n / 2 {
                for b in -n / 2..n / 2 {
                    let k = DVec2::new(f64::from(a) * dk, f64::from(b) * dk);
                    let d = s.density(k);
                    along += k.x * k.x * d;
                    across += k.y * k.y * d;
                }
            }
            let ratio = across / along;
            assert!((ratio * (p + 1.0) - 1.0).abs() < 0.03, "p {p}: {ratio}");
        }
    }

    #[test]
    fn folds_are_where_the_smaller_eigenvalue_is_negative() {
        // Figs. 16, 20: without chop J₋ = J₊ = 1; with strong chop, J = J₋ J₊,
        // J₊ stays positive, and the slice folds (x + D_x runs backwards)
        // only where J₋ < 0.
        let flat = choppy_ocean(Seed(9), true, 0.0)
            .unwrap()
            .evaluate(0.0)
            .unwrap();
        let e = flat.eigen(3, 5);
        assert_eq!((e.j_minus, e.j_plus), (1.0, 1.0));
        let frame = choppy_ocean(Seed(9), true, 6.0)
            .unwrap()
            .evaluate(0.0)
            .unwrap();
        let (nx, ny) = frame.dims();
        let mut folded = 0;
        for j in 0..ny {
            for i in 0..nx {
                let e = frame.eigen(i, j);
                let jac = frame.jacobian(i, j);
                assert!((e.j_minus * e.j_plus - jac).abs() < 1e-4 * (1.0 + jac.abs()));
                assert!(e.j_plus > 0.0);
                if frame.jxx()[(i, j)] < 0.0 {
                    assert!(e.j_minus < 0.0);
                    folded += 1;
                }
            }
        }
        assert!(folded > 0, "strong chop folds somewhere");
    }

    #[test]
    fn fresnel_numbers_of_figs_21_22() {
        // Normal incidence from air: ((n − 1)/(n + 1))² ≈ 0.02 for n = 4/3.
        let r0 = reflectivity(90.0, N_AIR, N_WATER);
        assert!((r0 - (1.0f64 / 7.0).powi(2)).abs() < 1e-12 && (r0 - 0.0204).abs() < 1e-4);
        // Air to water: R grows to 1 at grazing incidence.
        assert!((reflectivity(0.0, N_AIR, N_WATER) - 1.0).abs() < 1e-9);
        // Water to air: total internal reflection from 48.6° from the normal,
        // 41.4° from the surface (the notes print 41.1°).
        let c = critical_angle(N_WATER, N_AIR).unwrap().to_degrees();
        assert!((c - 48.59).abs() < 0.01, "{c}");
        assert_eq!(reflectivity(41.3, N_WATER, N_AIR), 1.0);
        assert!(reflectivity(41.5, N_WATER, N_AIR) < 1.0);
        assert!((reflectivity(90.0, N_WATER, N_AIR) - r0).abs() < 1e-12);
    }
}
