//! Stam's *Stable Fluids* figures (Stam 1999) that the smoke examples do
//! not show: the periodic 2-D "liquid texture" a user stirs (Fig. 4a–d),
//! and 3-D gas carrying a texture map (Fig. 4e–j).
//!
//! ```text
//! cargo run --release --example figures_stam                 # every figure
//! cargo run --release --example figures_stam -- --quick      # small, for CI
//! ```
//!
//! Writes into `--out` (default `./figures_stam/`); docs/figures.md sets
//! each beside the source's caption. The 2-D fluid lies in the vertical
//! x–z plane (natura-fluid's convention); the pictures show it face on.

mod common;

use std::f32::consts::TAU;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure, enlarge};
use common::{Exit, Run, outln};
use natura::core::glam::{DVec3, Vec3};
use natura::core::{Grid2, Grid3, Image};
use natura::fluid::export::render_smoke_volume;
use natura::fluid::grid::Dims;
use natura::fluid::shape::Shape;
use natura::fluid::stable::{
    BoundedFluid, ForceSource, PeriodicFluid, StableParams, Substance, SubstanceId,
};
use natura::noise::{CurlNoise, Fbm, Field, Perlin, Spectral, VectorField};

/// Stam's *Stable Fluids* figures (Stam 1999) not shown by the smoke
/// examples: the periodic liquid texture a user stirs, and 3-D gas
/// carrying a texture map.
#[derive(Parser)]
#[command(name = "figures_stam", version)]
struct Cli {
    /// Small and fast (CI): a coarser grid, a shorter run
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_stam")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Fig. 4a-d: a periodic liquid texture stirred by a user, and one frame tiled 2 × 2
    LiquidTexture,
    /// Fig. 4e-j: 3-D gas billowing under a noise force, carrying a fractal and a striped texture
    Gas,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[Fig::LiquidTexture, Fig::Gas];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::LiquidTexture => &["stam_fig04a-d_liquid_texture.png", "stam_fig04_tiled.png"],
            Fig::Gas => &["stam_fig04e-j_gas.png"],
        }
    }
}

type R<T> = Result<T, Exit>;

fn main() -> ExitCode {
    common::run(run)
}

fn run() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let q = cli.quick;
    figures::make(&out, &cli.only, |fig| match fig {
        Fig::LiquidTexture => liquid_texture(q),
        Fig::Gas => Ok(vec![gas(q)?]),
    })
}

/// Sets of advected texture coordinates, reset in turn (Stam 1999, §4,
/// after Max et al.: "three sets of texture coordinates are periodically
/// reset to their initial values"; the source gives neither the period nor
/// the weights).
const SETS: usize = 3;

/// One set of texture coordinates on the torus, carried as the cosine and
/// sine of their phase along x and along z, so each is periodic and
/// advects without a seam; the phase comes back by `atan2`.
#[derive(Clone, Copy, Debug)]
struct CoordinateSet {
    /// cos 2πx/L, sin 2πx/L, cos 2πz/L, sin 2πz/L.
    ids: [SubstanceId; 4],
}

/// The liquid texture: a periodic fluid of `n × n` cells on a unit
/// square, dye, and [`SETS`] coordinate sets.
struct LiquidTexture {
    fluid: PeriodicFluid,
    dye: SubstanceId,
    sets: [CoordinateSet; SETS],
    /// Seconds between resets of one set.
    period: f32,
    time: f32,
}

impl LiquidTexture {
    fn new(n: usize) -> R<Self> {
        let params = StableParams {
            viscosity: 2e-5,
            ..StableParams::default()
        };
        let mut fluid = PeriodicFluid::new(Dims::plane(n, n)?, 1.0 / n as f32, params)?;
        let dye = fluid.add_substance(Substance {
            dissipation: 0.15,
            ..Substance::passive("dye")
        })?;
        let mut sets = Vec::new();
        for s in 0..SETS {
            let mut ids = Vec::new();
            for c in ["cos x", "sin x", "cos z", "sin z"] {
                ids.push(fluid.add_substance(Substance::passive(&format!("set {s} {c}")))?);
            }
            sets.push(CoordinateSet {
                ids: [ids[0], ids[1], ids[2], ids[3]],
            });
        }
        let mut tex = Self {
            fluid,
            dye,
            sets: [sets[0], sets[1], sets[2]],
            period: 1.5,
            time: 0.0,
        };
        for s in 0..SETS {
            tex.reset(s)?;
        }
        Ok(tex)
    }

    /// Puts set `s` back at the identity map.
    fn reset(&mut self, s: usize) -> R<()> {
        let n = self.fluid.dims().n();
        let h = self.fluid.h();
        for (c, id) in self.sets[s].ids.into_iter().enumerate() {
            let g = self.fluid.substance_mut(id)?;
            for k in 0..n[2] {
                for i in 0..n[0] {
                    let along = if c < 2 { i } else { k };
                    let phase = TAU * (along as f32 + 0.5) * h;
                    g[(i, 0, k)] = if c % 2 == 0 { phase.cos() } else { phase.sin() };
                }
            }
        }
        Ok(())
    }

    /// How far set `s` is through its life, in `[0, 1)`: the sets are a
    /// third of a period apart.
    fn age(&self, s: usize) -> f32 {
        (self.time / self.period + s as f32 / SETS as f32).fract()
    }

    /// The blend weights of the sets: a triangle over each set's life, zero
    /// when it is reset (so a reset never shows), normalised to sum to 1.
    fn weights(&self) -> [f32; SETS] {
        let mut w = [0.0; SETS];
        for (s, v) in w.iter_mut().enumerate() {
            *v = 1.0 - (2.0 * self.age(s) - 1.0).abs();
        }
        let sum: f32 = w.iter().sum();
        w.map(|v| v / sum)
    }

    /// One step of `dt` with the user's stroke: the pointer at `p` moving
    /// with velocity `v` pushes the fluid around it and drops dye.
    fn step(&mut self, dt: f32, p: [f32; 2], v: [f32; 2]) -> R<()> {
        let n = self.fluid.dims().n();
        let h = self.fluid.h();
        let radius = 0.06f32;
        let mut push = vec![0.0f32; n[0] * n[2]];
        for k in 0..n[2] {
            for i in 0..n[0] {
                let dx = torus_delta((i as f32 + 0.5) * h - p[0]);
                let dz = torus_delta((k as f32 + 0.5) * h - p[1]);
                push[k * n[0] + i] = (-(dx * dx + dz * dz) / (radius * radius)).exp();
            }
        }
        let gain = 8.0;
        let f = self.fluid.force_mut();
        for k in 0..n[2] {
            for i in 0..n[0] {
                let w = push[k * n[0] + i];
                f[0][(i, 0, k)] += gain * w * v[0];
                f[2][(i, 0, k)] += gain * w * v[1];
            }
        }
        let dye = self.fluid.substance_mut(self.dye)?;
        for k in 0..n[2] {
            for i in 0..n[0] {
                let d = &mut dye[(i, 0, k)];
                *d = (*d + 3.0 * dt * push[k * n[0] + i]).min(1.0);
            }
        }
        let before: Vec<f32> = (0..SETS).map(|s| self.age(s)).collect();
        self.fluid.step(dt)?;
        self.time += dt;
        for (s, a) in before.into_iter().enumerate() {
            if self.age(s) < a {
                self.reset(s)?;
            }
        }
        Ok(())
    }

    /// The picture at `size × size` pixels: the blended textures under the
    /// dye, sampled bilinearly on the torus.
    fn picture(&self, size: usize) -> R<Image> {
        let w = self.weights();
        let sets: Vec<[&Grid3<f32>; 4]> = self
            .sets
            .iter()
            .map(|set| {
                Ok([
                    self.fluid.substance(set.ids[0])?,
                    self.fluid.substance(set.ids[1])?,
                    self.fluid.substance(set.ids[2])?,
                    self.fluid.substance(set.ids[3])?,
                ])
            })
            .collect::<R<_>>()?;
        let dye = self.fluid.substance(self.dye)?;
        Ok(Image::from_grid(Grid2::from_fn(size, size, |px, py| {
            // Row 0 is the top of the picture: z = 1.
            let x = (px as f32 + 0.5) / size as f32;
            let z = 1.0 - (py as f32 + 0.5) / size as f32;
            let mut c = Vec3::ZERO;
            for (set, &ws) in sets.iter().zip(&w) {
                let u = phase(torus_sample(set[0], x, z), torus_sample(set[1], x, z));
                let v = phase(torus_sample(set[2], x, z), torus_sample(set[3], x, z));
                c += ws * pattern(u, v);
            }
            let d = torus_sample(dye, x, z).clamp(0.0, 1.0);
            c.lerp(Vec3::new(0.95, 0.55, 0.1), 0.85 * d)
        })?))
    }
}

/// The shortest signed difference on the unit torus.
fn torus_delta(d: f32) -> f32 {
    d - d.round()
}

/// The texture coordinate in `[0, 1)` whose phase has cosine `c` and sine `s`.
fn phase(c: f32, s: f32) -> f32 {
    (s.atan2(c) / TAU).rem_euclid(1.0)
}

/// A field of a 2-D periodic grid (`ny = 1`) at `(x, z)` in the unit
/// square, bilinear with wrap-around (cell centres at `(i + ½)/n`).
fn torus_sample(g: &Grid3<f32>, x: f32, z: f32) -> f32 {
    let (nx, _, nz) = g.dims();
    let fx = x * nx as f32 - 0.5;
    let fz = z * nz as f32 - 0.5;
    let (x0, z0) = (fx.floor(), fz.floor());
    let (tx, tz) = (fx - x0, fz - z0);
    let wrap = |v: f32, n: usize| (v as isize).rem_euclid(n as isize) as usize;
    let (i0, i1) = (wrap(x0, nx), wrap(x0 + 1.0, nx));
    let (k0, k1) = (wrap(z0, nz), wrap(z0 + 1.0, nz));
    let a = g[(i0, 0, k0)] + tx * (g[(i1, 0, k0)] - g[(i0, 0, k0)]);
    let b = g[(i0, 0, k1)] + tx * (g[(i1, 0, k1)] - g[(i0, 0, k1)]);
    a + tz * (b - a)
}

/// The texture the liquid carries, tileable on the unit square: an 8 × 8
/// checkerboard of two blues with lighter grout lines.
fn pattern(u: f32, v: f32) -> Vec3 {
    let (su, sv) = (8.0 * u, 8.0 * v);
    let odd = (su.floor() as i32 + sv.floor() as i32) & 1 == 1;
    let base = if odd {
        Vec3::new(0.05, 0.18, 0.45)
    } else {
        Vec3::new(0.35, 0.62, 0.85)
    };
    let edge = (su - su.round()).abs().min((sv - sv.round()).abs());
    base.lerp(Vec3::splat(0.95), (1.0 - edge / 0.06).clamp(0.0, 1.0))
}

/// The user's pointer at time `t` (s): a figure-eight across the square,
/// wrapping over its edges, and its velocity.
fn pointer(t: f32) -> ([f32; 2], [f32; 2]) {
    let w = 0.9;
    let p = [
        (0.5 + 0.42 * (w * t).sin()).rem_euclid(1.0),
        (0.5 + 0.3 * (2.0 * w * t).sin() + 0.1 * t).rem_euclid(1.0),
    ];
    let v = [
        0.42 * w * (w * t).cos(),
        0.6 * w * (2.0 * w * t).cos() + 0.1,
    ];
    (p, v)
}

/// Fig. 4a–d: four moments of the stirred texture, and the last tiled
/// 2 × 2 (it tiles: the domain is a torus).
fn liquid_texture(quick: bool) -> R<Vec<Image>> {
    // The source's interactive solver ran at 100² (the back cover).
    let (n, size) = if quick { (48, 144) } else { (100, 400) };
    let mut tex = LiquidTexture::new(n)?;
    let dt = 0.02;
    let every = if quick { 25 } else { 100 };
    let mut shots = Vec::new();
    for s in 1..=4 * every {
        let (p, v) = pointer(s as f32 * dt);
        tex.step(dt, p, v)?;
        if s % every == 0 {
            shots.push(tex.picture(size)?);
        }
    }
    outln(format_args!(
        "  Fig. 4: {n}² cells, {} steps of {dt} s, max |∇·u| {:.2e} /s",
        4 * every,
        tex.fluid.max_divergence()
    ))?;
    let last = shots
        .last()
        .ok_or_else(|| Exit::new(2, "no frames"))?
        .box_downsample(2)?;
    let tiled = Image::contact_sheet(
        &[last.clone(), last.clone(), last.clone(), last],
        2,
        0,
        Vec3::ONE,
    )?;
    Ok(vec![Image::contact_sheet(&shots, 2, 6, Vec3::ONE)?, tiled])
}

// ------------------------------------------------------------- Fig. 4e–j

/// The noise force per unit density (m/s²): the source's "noise term
/// proportional to the amount of density", whose factor is a user's
/// parameter it does not give.
const NOISE_FORCE: f32 = 20.0;

/// The noise force's field: curl noise (divergence-free, so the projection
/// keeps all of it), 3 lattice cells a metre, drifting down through the
/// gas at 0.4 m/s so the billows keep changing.
fn noise_force(noise: &CurlNoise<Perlin>, p: Vec3, t: f32) -> Vec3 {
    let q = p.as_dvec3() * 3.0 + DVec3::new(0.0, 0.0, 1.2 * f64::from(t));
    (noise.eval3(q) / noise.bound()).as_vec3()
}

/// The texture map a gas carries (Stam 1999, §5: "a fractal texture map"
/// in Fig. 4e–i, "evenly spaced lines" in Fig. 4j), as a factor in
/// `[0, 1]` of the carried coordinates.
#[derive(Clone, Copy, Debug)]
enum Carried {
    Fractal,
    Lines,
}

/// Fig. 4e–j's gas: the source's largest grid, 30³ cells, over a closed
/// 1 m box (none of its sessions is given). A ball of gas placed over the
/// floor, a force region in it pushes it up as the animator's forces
/// did, and the noise force stirs it where it is dense. Three passive
/// substances carry the texture coordinates, starting at each cell's
/// centre.
struct Gas {
    fluid: BoundedFluid,
    smoke: SubstanceId,
    coords: [SubstanceId; 3],
    noise: CurlNoise<Perlin>,
    strength: f32,
    time: f32,
}

impl Gas {
    fn new(n: usize, strength: f32) -> R<Self> {
        let h = 1.0 / n as f32;
        let mut fluid = BoundedFluid::new(Dims::new(n, n, n)?, h, StableParams::default())?;
        let smoke = fluid.add_substance(Substance::passive("smoke"))?;
        let mut coords = [smoke; 3];
        for (a, c) in coords.iter_mut().enumerate() {
            *c = fluid.add_substance(Substance::passive(["u", "v", "w"][a]))?;
            let g = fluid.substance_mut(*c)?;
            for k in 0..n {
                for j in 0..n {
                    for i in 0..n {
                        g[(i, j, k)] = ([i, j, k][a] as f32 + 0.5) * h;
                    }
                }
            }
        }
        // The animator's density: a ball of gas over the floor's centre.
        let centre = Vec3::new(0.5, 0.5, 0.3);
        let g = fluid.substance_mut(smoke)?;
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let p = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * h;
                    g[(i, j, k)] = (1.0 - (p - centre).length() / 0.24).clamp(0.0, 0.5) * 2.0;
                }
            }
        }
        fluid.add_force_source(ForceSource {
            shape: Shape::Sphere {
                centre: Vec3::new(0.5, 0.5, 0.25),
                radius: 0.15,
            },
            acceleration: Vec3::new(0.0, 0.0, 3.0),
        })?;
        Ok(Self {
            fluid,
            smoke,
            coords,
            noise: CurlNoise::new(Perlin::new(4)),
            strength,
            time: 0.0,
        })
    }

    fn step(&mut self, dt: f32) -> R<()> {
        let h = self.fluid.h();
        let rho = self.fluid.substance(self.smoke)?.clone();
        let (nx, ny, nz) = rho.dims();
        let (noise, strength, t) = (&self.noise, self.strength, self.time);
        let f = self.fluid.force_mut();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let r = rho[(i, j, k)];
                    if r > 0.0 {
                        let p = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * h;
                        let v = noise_force(noise, p, t) * (strength * r.min(1.0));
                        for a in 0..3 {
                            f[a][(i, j, k)] = v[a];
                        }
                    }
                }
            }
        }
        self.fluid.step(dt)?;
        self.time += dt;
        Ok(())
    }

    /// The density times the carried texture, `ρ·(0.25 + 0.75·T)`.
    fn textured(&self, carried: Carried) -> R<Grid3<f32>> {
        let rho = self.fluid.substance(self.smoke)?;
        let [u, v, w] = self.coords.map(|c| self.fluid.substance(c));
        let (u, v, w) = (u?, v?, w?);
        let fbm = Fbm::new(Perlin::new(9), Spectral::default().with_octaves(4.0))?;
        let b = fbm.bound();
        let (nx, ny, nz) = rho.dims();
        Ok(Grid3::from_fn(nx, ny, nz, |i, j, k| {
            let c = DVec3::new(
                f64::from(u[(i, j, k)]),
                f64::from(v[(i, j, k)]),
                f64::from(w[(i, j, k)]),
            );
            let t = match carried {
                Carried::Fractal => (0.5 + 0.8 * fbm.eval3(c * 4.0) / b).clamp(0.0, 1.0) as f32,
                Carried::Lines => (0.5 + 0.5 * (c.z * std::f64::consts::TAU / 0.15).cos()) as f32,
            };
            rho[(i, j, k)] * (0.25 + 0.75 * t)
        })?)
    }

    /// The density's second moment about the vertical axis through the
    /// source (`Σ ρ r²`, r horizontal, m²) over its total.
    fn spread(&self) -> R<f64> {
        let rho = self.fluid.substance(self.smoke)?;
        let h = f64::from(self.fluid.h());
        let (nx, ny, nz) = rho.dims();
        let (mut m, mut m2) = (0.0f64, 0.0f64);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let (x, y) = ((i as f64 + 0.5) * h - 0.5, (j as f64 + 0.5) * h - 0.5);
                    let r = f64::from(rho[(i, j, k)]);
                    m += r;
                    m2 += r * (x * x + y * y);
                }
            }
        }
        Ok(m2 / m.max(1e-12))
    }
}

/// Fig. 4e–j: the gas at four times carrying the fractal texture (top)
/// and the lines (bottom), seen from the side with self-shadowing from a
/// fixed directional light, as the source's renderer did.
fn gas(quick: bool) -> R<Image> {
    let n = if quick { 16 } else { 30 };
    let mut g = Gas::new(n, NOISE_FORCE)?;
    let dt = 0.02;
    let (steps, every) = if quick { (60, 15) } else { (160, 40) };
    let light = Vec3::new(-0.5, -0.5, 1.0).normalize();
    let (mut top, mut bottom) = (Vec::new(), Vec::new());
    let h = g.fluid.h();
    let shoot = |d: &Grid3<f32>| render_smoke_volume(d, h, 5.0, 0.9, light, 1, Vec3::splat(0.05));
    for s in 1..=steps {
        g.step(dt)?;
        if s % every == 0 {
            top.push(shoot(&g.textured(Carried::Fractal)?)?);
            bottom.push(shoot(&g.textured(Carried::Lines)?)?);
        }
    }
    outln(format_args!(
        "  Fig. 4e–j: {n}³ cells, {steps} steps of {dt} s, the density's spread {:.3} m²",
        g.spread()?
    ))?;
    let shots = top
        .iter()
        .chain(&bottom)
        .map(|i| enlarge(i, 6))
        .collect::<R<Vec<_>>>()?;
    Ok(Image::contact_sheet(&shots, top.len(), 6, Vec3::ONE)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_force_makes_the_gas_billow_and_the_texture_moves_with_it() {
        // Fig. 4e–j: the noise term "produced nice billowing motions". The
        // same gas without it spreads less about its axis; and the carried
        // coordinates left their cells.
        let run = |strength: f32| {
            let mut g = Gas::new(16, strength).unwrap();
            for _ in 0..60 {
                g.step(0.02).unwrap();
            }
            g
        };
        let (billowing, plain) = (run(NOISE_FORCE), run(0.0));
        let (a, b) = (billowing.spread().unwrap(), plain.spread().unwrap());
        assert!(a > 1.3 * b, "spread {a} against {b}");
        let w = billowing.fluid.substance(billowing.coords[2]).unwrap();
        let moved = (0..16)
            .filter(|&k| (w[(8, 8, k)] - (k as f32 + 0.5) / 16.0).abs() > 0.03)
            .count();
        assert!(
            moved > 3,
            "{moved} cells on the axis carry moved coordinates"
        );
    }

    #[test]
    fn at_rest_the_coordinates_are_the_identity_and_the_weights_sum_to_one() {
        let tex = LiquidTexture::new(16).unwrap();
        for (i, k) in [(0, 0), (3, 9), (15, 15)] {
            let (x, z) = ((i as f32 + 0.5) / 16.0, (k as f32 + 0.5) / 16.0);
            for set in &tex.sets {
                let g = |c: usize| tex.fluid.substance(set.ids[c]).unwrap()[(i, 0, k)];
                assert!((phase(g(0), g(1)) - x).abs() < 1e-5);
                assert!((phase(g(2), g(3)) - z).abs() < 1e-5);
            }
        }
        let w = tex.weights();
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6 && w.iter().all(|&v| v >= 0.0));
    }

    #[test]
    fn the_stirred_texture_tiles_without_a_seam() {
        // The jump across the picture's wrap-around edges is no larger than
        // between neighbouring pixels inside it.
        let mut tex = LiquidTexture::new(32).unwrap();
        for s in 1..=60 {
            let (p, v) = pointer(s as f32 * 0.02);
            tex.step(0.02, p, v).unwrap();
        }
        let img = tex.picture(96).unwrap();
        let px = |x: usize, y: usize| img.get(x, y).unwrap();
        let (mut seam, mut inner) = (0.0, 0.0);
        for y in 0..96 {
            seam += (px(95, y) - px(0, y)).abs().element_sum();
            inner += (px(47, y) - px(48, y)).abs().element_sum();
        }
        let (mut seam_v, mut inner_v) = (0.0, 0.0);
        for x in 0..96 {
            seam_v += (px(x, 95) - px(x, 0)).abs().element_sum();
            inner_v += (px(x, 47) - px(x, 48)).abs().element_sum();
        }
        assert!(
            seam < 2.0 * inner + 1.0 && seam_v < 2.0 * inner_v + 1.0,
            "{seam} {inner} {seam_v} {inner_v}"
        );
        // The stirring moved the texture: it is no longer the identity.
        let rest = LiquidTexture::new(32).unwrap().picture(96).unwrap();
        let moved = (0..96 * 96)
            .filter(|&i| {
                (img.get(i % 96, i / 96).unwrap() - rest.get(i % 96, i / 96).unwrap()).length()
                    > 0.1
            })
            .count();
        assert!(moved > 96 * 96 / 10, "{moved}");
    }

    #[test]
    fn a_step_of_many_cells_stays_bounded_and_divergence_free() {
        // Stam's claim: stable for any time step. A swirl moving 10 cells a
        // step neither gains energy nor leaves a divergence (central
        // differences, which the modified wavenumbers project exactly).
        let n = 32;
        let mut f = PeriodicFluid::new(
            Dims::plane(n, n).unwrap(),
            1.0 / n as f32,
            StableParams {
                variant: natura::fluid::fft::FftVariant::ModifiedWavenumber,
                ..StableParams::default()
            },
        )
        .unwrap();
        for k in 0..n {
            for i in 0..n {
                let (x, z) = ((i as f32 + 0.5) / n as f32, (k as f32 + 0.5) / n as f32);
                f.velocity_mut()[0][(i, 0, k)] = (TAU * z).sin();
                f.velocity_mut()[2][(i, 0, k)] = (TAU * x).sin() + 0.5 * (2.0 * TAU * z).cos();
            }
        }
        f.project();
        let e0 = f.kinetic_energy();
        let dt = 10.0 / n as f32 / 1.5;
        for _ in 0..5 {
            f.step(dt).unwrap();
        }
        assert!(
            f.kinetic_energy() <= e0 * (1.0 + 1e-6),
            "{} > {e0}",
            f.kinetic_energy()
        );
        assert!(f.max_divergence() < 1e-3, "{}", f.max_divergence());
    }

    #[test]
    fn the_pointer_wraps_onto_the_square() {
        for s in 0..500 {
            let (p, v) = pointer(s as f32 * 0.02);
            assert!(p.iter().all(|c| (0.0..1.0).contains(c)) && v.iter().all(|c| c.is_finite()));
        }
    }
}
