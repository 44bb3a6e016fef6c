//! Pictures and volume files from simulation fields: slices, projections,
//! a simple self-shadowed smoke rendering, raw and EXR volumes.
//!
//! Images follow natura's conventions: linear RGB [`Image`]s, row 0 at the
//! top, so for the vertical x–z plane image row 0 is the highest z.

use std::io::Write;
use std::path::Path;

use glam::Vec3;
use natura_core::io::{WriteError, write_atomic};
use natura_core::{Grid2, Grid3, Image, Ramp};

use crate::error::{FluidError, Result};
use crate::grid::CellKind;

/// Which plane an image shows: the two axes other than `normal`.
fn plane_axes(normal: usize) -> Result<(usize, usize)> {
    match normal {
        0 => Ok((1, 2)),
        1 => Ok((0, 2)),
        2 => Ok((0, 1)),
        _ => Err(FluidError::InvalidParameter {
            name: "axis",
            value: normal.to_string(),
            reason: "must be 0 (x), 1 (y) or 2 (z)",
        }),
    }
}

/// Returns the slice of `g` at `index` across axis `normal` as a 2-D grid
/// (columns along the first remaining axis, rows along the second, row 0 at
/// its low end).
///
/// # Errors
///
/// Returns [`FluidError::InvalidParameter`] for an axis other than 0, 1 or 2
/// and [`FluidError::OutsideGrid`] if `index` lies outside the grid.
pub fn slice(g: &Grid3<f32>, normal: usize, index: usize) -> Result<Grid2<f32>> {
    let (a, b) = plane_axes(normal)?;
    let n = [g.nx(), g.ny(), g.nz()];
    if index >= n[normal] {
        return Err(FluidError::OutsideGrid {
            what: "slice",
            detail: format!("index {index} on an axis of {} cells", n[normal]),
        });
    }
    Ok(Grid2::from_fn(n[a], n[b], |i, j| {
        let mut c = [0; 3];
        c[a] = i;
        c[b] = j;
        c[normal] = index;
        g[(c[0], c[1], c[2])]
    })?)
}

/// Integrates `g` along axis `normal` (sum × `h`): the optical depth seen
/// looking along that axis when `g` is an extinction coefficient.
///
/// # Errors
///
/// Returns [`FluidError::Core`] if a result grid cannot be allocated.
pub fn projection(g: &Grid3<f32>, normal: usize, h: f32) -> Result<Grid2<f32>> {
    let (a, b) = plane_axes(normal)?;
    let n = [g.nx(), g.ny(), g.nz()];
    Ok(Grid2::from_fn(n[a], n[b], |i, j| {
        let mut c = [0; 3];
        c[a] = i;
        c[b] = j;
        let mut s = 0.0;
        for t in 0..n[normal] {
            c[normal] = t;
            s += g[(c[0], c[1], c[2])];
        }
        s * h
    })?)
}

/// Maps a 2-D field to an image through `ramp` over `[lo, hi]`, flipping
/// rows so that the field's high second axis is at the top.
#[must_use]
pub fn field_image(f: &Grid2<f32>, ramp: Ramp, lo: f32, hi: f32) -> Image {
    let (w, hgt) = f.dims();
    Image::from_grid(
        Grid2::from_fn(w, hgt, |i, r| ramp.map(f[(i, hgt - 1 - r)], lo, hi))
            .expect("same size as a valid grid"),
    )
}

/// Renders smoke seen along axis `normal`: transmittance `exp(−σ ∫ρ)` over
/// a background, lit smoke colour `colour` weighted by absorbed light, and
/// solid cells (`kinds`, any cell along the ray) drawn in grey. Rows flipped so +z is up.
///
/// # Errors
///
/// Returns [`FluidError::Core`] if a result grid cannot be allocated.
pub fn smoke_image(
    density: &Grid3<f32>,
    kinds: Option<&Grid3<CellKind>>,
    normal: usize,
    h: f32,
    extinction: f32,
    colour: Vec3,
    background: Vec3,
) -> Result<Image> {
    let tau = projection(density, normal, h)?;
    let (a, b) = plane_axes(normal)?;
    let (w, hgt) = tau.dims();
    let solid = kinds.map(|k| {
        let n = [k.nx(), k.ny(), k.nz()];
        Grid2::from_fn(n[a], n[b], |i, j| {
            let mut c = [0; 3];
            c[a] = i;
            c[b] = j;
            (0..n[normal]).any(|t| {
                c[normal] = t;
                k[(c[0], c[1], c[2])] == CellKind::Solid
            })
        })
    });
    let solid = match solid {
        Some(s) => Some(s?),
        None => None,
    };
    Ok(Image::from_grid(Grid2::from_fn(w, hgt, |i, r| {
        let j = hgt - 1 - r;
        if solid.as_ref().is_some_and(|s| s[(i, j)]) {
            return Vec3::splat(0.35);
        }
        let t = (-extinction * tau[(i, j)]).exp();
        background * t + colour * (1.0 - t)
    })?))
}

/// Renders a 3-D smoke density with single-scattered light from direction
/// `light` (unit, pointing toward the light) and self-shadowing, seen along
/// axis `normal` from its low side — a CPU version of the paper's two-pass
/// slice renderer (Fedkiw et al. 2001, §5.1) with the per-voxel transmittance
/// `exp(−C_ext ρ h)` (an erratum: Fedkiw et al. 2001, §5.1 prints it without ρ).
///
/// # Errors
///
/// Returns [`FluidError::InvalidParameter`] for an axis other than 0, 1 or 2,
/// and [`FluidError::Core`] if a result grid cannot be allocated.
pub fn render_smoke_volume(
    density: &Grid3<f32>,
    h: f32,
    extinction: f32,
    albedo: f32,
    light: Vec3,
    normal: usize,
    background: Vec3,
) -> Result<Image> {
    render_volume(
        density, None, h, extinction, albedo, light, normal, background,
    )
}

/// [`render_smoke_volume`] with solid cells (`solid[(i, j, k)]` true): they
/// stop the eye's rays and the light's (casting shadows into the smoke)
/// and are drawn in `solid_colour` times the light that reaches them
/// through the smoke, with a quarter of it as ambient light.
///
/// # Errors
///
/// As [`render_smoke_volume`], and [`FluidError::InvalidParameter`] if
/// `solid` and `density` differ in size.
#[allow(clippy::too_many_arguments)]
pub fn render_smoke_volume_with_solids(
    density: &Grid3<f32>,
    solid: &Grid3<bool>,
    solid_colour: Vec3,
    h: f32,
    extinction: f32,
    albedo: f32,
    light: Vec3,
    normal: usize,
    background: Vec3,
) -> Result<Image> {
    if solid.dims() != density.dims() {
        return Err(FluidError::InvalidParameter {
            name: "solid",
            value: format!("{:?}", solid.dims()),
            reason: "must have the density's dimensions",
        });
    }
    render_volume(
        density,
        Some((solid, solid_colour)),
        h,
        extinction,
        albedo,
        light,
        normal,
        background,
    )
}

#[allow(clippy::too_many_arguments)]
fn render_volume(
    density: &Grid3<f32>,
    solid: Option<(&Grid3<bool>, Vec3)>,
    h: f32,
    extinction: f32,
    albedo: f32,
    light: Vec3,
    normal: usize,
    background: Vec3,
) -> Result<Image> {
    let blocked = |i: usize, j: usize, k: usize| solid.is_some_and(|(s, _)| s[(i, j, k)]);
    let (a, b) = plane_axes(normal)?;
    let (nx, ny, nz) = density.dims();
    let n = [nx, ny, nz];
    // Pass 1: light transmittance reaching each voxel, marching toward the light
    // one cell at a time along the light's dominant direction (nearest sampling).
    let l = light.normalize_or_zero();
    let step = l / l.abs().max_element().max(1e-6);
    let mut shadow = Grid3::new(nx, ny, nz, 1.0f32)?;
    let dl = h * step.length();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let mut p = Vec3::new(i as f32, j as f32, k as f32) + step;
                let mut tau = 0.0;
                while p.x >= -0.5
                    && p.y >= -0.5
                    && p.z >= -0.5
                    && p.x < nx as f32 - 0.5
                    && p.y < ny as f32 - 0.5
                    && p.z < nz as f32 - 0.5
                {
                    let q = p.round();
                    let (qi, qj, qk) = (q.x as usize, q.y as usize, q.z as usize);
                    if blocked(qi, qj, qk) {
                        tau = f32::INFINITY;
                        break;
                    }
                    tau += density[(qi, qj, qk)];
                    p += step;
                }
                shadow[(i, j, k)] = (-extinction * tau * dl).exp();
            }
        }
    }
    // Pass 2: composite front to back along `normal`.
    Ok(Image::from_grid(Grid2::from_fn(n[a], n[b], |i, r| {
        let jb = n[b] - 1 - r;
        let mut c = [0; 3];
        c[a] = i;
        c[b] = jb;
        let mut t_ray = 1.0f32;
        let mut lsum = 0.0f32;
        for s in 0..n[normal] {
            c[normal] = s;
            if let Some((solids, colour)) = solid
                && solids[(c[0], c[1], c[2])]
            {
                let lit = 0.25 + 0.75 * shadow[(c[0], c[1], c[2])];
                return colour * (lit * t_ray) + Vec3::splat(lsum);
            }
            let t_vox = (-extinction * density[(c[0], c[1], c[2])] * h).exp();
            lsum += albedo * shadow[(c[0], c[1], c[2])] * (1.0 - t_vox) * t_ray;
            t_ray *= t_vox;
        }
        background * t_ray + Vec3::splat(lsum)
    })?))
}

/// Writes `g` as raw little-endian `f32` (x fastest, then y, then z),
/// atomically, plus a sidecar `<path>.txt` giving the size and cell size.
///
/// # Errors
///
/// Returns [`FluidError::Core`] naming the file if it cannot be written (written
/// atomically: nothing is left half-written).
pub fn write_raw_volume(path: impl AsRef<Path>, g: &Grid3<f32>, h: f32) -> Result<()> {
    write_raw_volume_impl(path.as_ref(), g, h)
}

/// The body of [`write_raw_volume`]: not generic, so it is compiled once, here, and not again in
/// every crate that calls it.
fn write_raw_volume_impl(path: &Path, g: &Grid3<f32>, h: f32) -> Result<()> {
    write_atomic(path, |w| {
        for v in g.as_slice() {
            w.write_all(&v.to_le_bytes())?;
        }
        Ok::<(), WriteError>(())
    })?;
    let (nx, ny, nz) = g.dims();
    let meta = format!(
        "format = \"f32le\"\nnx = {nx}\nny = {ny}\nnz = {nz}\ncell_size_m = {h}\norder = \"x fastest, then y, then z (up)\"\n"
    );
    let mut side = path.as_os_str().to_owned();
    side.push(".txt");
    natura_core::io::write_bytes_atomic(Path::new(&side), meta.as_bytes())?;
    Ok(())
}

/// Writes `g` as a single-channel (`Y`) float EXR of `nx × (ny·nz)` pixels:
/// the z-slices stacked top to bottom, with attributes `nx`, `ny`, `nz` and
/// `cell_size_m`.
///
/// # Errors
///
/// Returns [`FluidError::Core`] naming the file if it cannot be written (written
/// atomically: nothing is left half-written).
pub fn write_exr_volume(path: impl AsRef<Path>, g: &Grid3<f32>, h: f32) -> Result<()> {
    write_exr_volume_impl(path.as_ref(), g, h)
}

/// The body of [`write_exr_volume`]: not generic, so it is compiled once, here, and not again in
/// every crate that calls it.
fn write_exr_volume_impl(path: &Path, g: &Grid3<f32>, h: f32) -> Result<()> {
    let (nx, ny, nz) = g.dims();
    let (sx, sy, sz, hs) = (
        nx.to_string(),
        ny.to_string(),
        nz.to_string(),
        h.to_string(),
    );
    natura_core::io::exr::write_exr(
        path,
        nx,
        ny * nz,
        &[("Y", g.as_slice())],
        &[("nx", &sx), ("ny", &sy), ("nz", &sz), ("cell_size_m", &hs)],
    )?;
    Ok(())
}
