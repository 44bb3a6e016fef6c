//! The planet's surface sampled onto the six faces of a cube sphere and onto
//! an equirectangular (latitude–longitude) map, with EXR export.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use natura_core::io::{check_writable, exr::write_exr};
use natura_core::{Grid2, MAX_GRID_BYTES, NoProgress, Progress};

use super::{Planet, Surface};
use crate::error::{Result, TextureError};
use crate::footprint::Footprint;
use crate::row_fill::fill_rows;

/// A face of the cube sphere, named by its outward axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Face {
    /// +x.
    PosX,
    /// −x.
    NegX,
    /// +y.
    PosY,
    /// −y.
    NegY,
    /// +z (north pole).
    PosZ,
    /// −z (south pole).
    NegZ,
}

impl Face {
    /// All six, in file order.
    pub const ALL: [Face; 6] = [
        Face::PosX,
        Face::NegX,
        Face::PosY,
        Face::NegY,
        Face::PosZ,
        Face::NegZ,
    ];

    /// The short name used in file names (`px`, `nx`, …).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Face::PosX => "px",
            Face::NegX => "nx",
            Face::PosY => "py",
            Face::NegY => "ny",
            Face::PosZ => "pz",
            Face::NegZ => "nz",
        }
    }

    /// `(normal, right, up)`: the face's outward axis and the directions of
    /// increasing column and decreasing row in its image. The side faces
    /// have z up and are seen from outside; the poles continue them (+z's
    /// bottom edge is +x's top edge, −z's top edge is +x's bottom edge).
    #[must_use]
    pub const fn frame(self) -> [[i64; 3]; 3] {
        match self {
            Face::PosX => [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
            Face::NegX => [[-1, 0, 0], [0, -1, 0], [0, 0, 1]],
            Face::PosY => [[0, 1, 0], [-1, 0, 0], [0, 0, 1]],
            Face::NegY => [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
            Face::PosZ => [[0, 0, 1], [0, 1, 0], [-1, 0, 0]],
            Face::NegZ => [[0, 0, -1], [0, 1, 0], [1, 0, 0]],
        }
    }

    /// The integer cube point of sample `(i, j)` on a face of `n` samples
    /// per side: each coordinate in `−(n−1) ..= n−1` (step 2), the face's
    /// own axis at `±(n−1)`. Samples shared by two or three faces (edges and
    /// corners) get the same integers from every face.
    #[must_use]
    pub fn lattice(self, n: usize, i: usize, j: usize) -> [i64; 3] {
        let k = n as i64 - 1;
        let s = 2 * i as i64 - k;
        let t = k - 2 * j as i64;
        let [nrm, right, up] = self.frame();
        core::array::from_fn(|a| nrm[a] * k + right[a] * s + up[a] * t)
    }
}

/// The equal-angle warp of one cube coordinate `c/k ∈ [−1, 1]`:
/// `tan(π/4·c/k)`, exactly `±1` at the cube's edges and odd in `c`, so the
/// same integer gives the same bits on every face.
fn warp(c: i64, k: i64) -> f64 {
    if c.abs() == k {
        return c.signum() as f64;
    }
    let a = (c.unsigned_abs() as f64) / (k as f64);
    let w = libm::tan(std::f64::consts::FRAC_PI_4 * a);
    if c < 0 { -w } else { w }
}

/// The unit direction of integer cube point `q` on a cube of half-side `k`.
#[must_use]
pub fn cube_direction(q: [i64; 3], k: i64) -> DVec3 {
    DVec3::new(warp(q[0], k), warp(q[1], k), warp(q[2], k)).normalize()
}

/// One face: height above sea level (metres) and unlit surface colour.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeFace {
    /// Which face.
    pub face: Face,
    /// Height above `R`, metres.
    pub height: Grid2<f32>,
    /// Surface colour (albedo), linear RGB.
    pub colour: Grid2<Vec3>,
}

/// The surface on six `n × n` faces.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeMap {
    /// Samples per face side.
    pub size: usize,
    /// The faces, in [`Face::ALL`] order.
    pub faces: Vec<CubeFace>,
}

/// The surface on an equirectangular map: column `i` at longitude
/// `−π + 2π(i + ½)/w`, row `j` at latitude `π/2 − π(j + ½)/h`.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceMap {
    /// Height above `R`, metres.
    pub height: Grid2<f32>,
    /// Surface colour (albedo), linear RGB.
    pub colour: Grid2<Vec3>,
}

/// Refuses a map size that is too small or needs more memory than the cap.
fn check_size(name: &'static str, value: usize, min: usize, samples: u128) -> Result<()> {
    let bytes = samples * 16;
    if value < min {
        return Err(TextureError::InvalidSize {
            name,
            value,
            reason: format!("must be at least {min}"),
        });
    }
    if bytes > u128::from(MAX_GRID_BYTES) {
        return Err(TextureError::InvalidSize {
            name,
            value,
            reason: format!("needs {bytes} bytes, over the cap of {MAX_GRID_BYTES}"),
        });
    }
    Ok(())
}

impl Planet {
    /// The surface height (metres above `R`) and unlit colour in the unit
    /// direction `dir`, for a footprint of `footprint_m` metres.
    #[must_use]
    pub fn surface_sample(&self, dir: DVec3, footprint_m: f64) -> (f32, Vec3) {
        match &self.surface {
            Surface::Terrain(relief) => {
                let fp = relief.footprint(footprint_m);
                let b = relief.bump(dir, fp);
                let height = relief.height_of(b);
                let c = match &self.biomes {
                    Some(biomes) => {
                        let chaos = relief.chaos_above_sea(b);
                        if chaos > 0.0 {
                            let fp = Footprint::new(footprint_m / self.radius())
                                .unwrap_or(Footprint::POINT);
                            let temp = biomes.temperature(dir.z, height);
                            biomes.land(temp, biomes.moisture(dir, fp), height, 0.0, 0.0)
                        } else {
                            let temp = biomes.temperature(dir.z, 0.0);
                            biomes.sea(temp, -chaos * relief.metres_per_chaos())
                        }
                    }
                    None => {
                        let t = relief.terran();
                        let mottle = t.mottle(relief.texture_point(dir), fp);
                        t.shade(b, dir.z.abs(), mottle).colour
                    }
                };
                (height as f32, c.as_vec3())
            }
            Surface::Textured(tex) => {
                let fp = Footprint::new(footprint_m / self.radius()).unwrap_or(Footprint::POINT);
                let s = tex.sample(dir, fp);
                ((s.height * self.radius()) as f32, s.colour.as_vec3())
            }
        }
    }

    /// Samples the surface onto six `size × size` cube faces (equal-angle
    /// cube sphere). Every sample shared by neighbouring faces — the edges
    /// and the eight corners — is computed from the same integer cube point
    /// and the same footprint (the face's sample spacing at its centre), so
    /// it is bit-identical on each face.
    ///
    /// # Errors
    /// [`TextureError::InvalidSize`] for `size < 2` or a map over the memory cap.
    pub fn cube_map(&self, size: usize, progress: &dyn Progress) -> Result<CubeMap> {
        CubeMap::check_size(size)?;
        let k = size as i64 - 1;
        let footprint = self.radius() * std::f64::consts::FRAC_PI_2 / k as f64;
        let mut faces = Vec::with_capacity(6);
        for face in Face::ALL {
            let mut both = Grid2::new(size, size, (0.0f32, Vec3::ZERO))?;
            fill_rows(&mut both, face.name(), progress, |j, row| {
                for (i, cell) in row.iter_mut().enumerate() {
                    let dir = cube_direction(face.lattice(size, i, j), k);
                    *cell = self.surface_sample(dir, footprint);
                }
            });
            faces.push(CubeFace {
                face,
                height: both.map(|c| c.0),
                colour: both.map(|c| c.1),
            });
        }
        Ok(CubeMap { size, faces })
    }

    /// Samples the surface onto a `width × height` equirectangular map.
    ///
    /// # Errors
    /// [`TextureError::InvalidSize`] for a zero size or a map over the memory cap.
    pub fn equirect(
        &self,
        width: usize,
        height: usize,
        progress: &dyn Progress,
    ) -> Result<SurfaceMap> {
        check_size(
            "width",
            width,
            1,
            (width as u128).saturating_mul(height as u128),
        )?;
        check_size(
            "height",
            height,
            1,
            (width as u128).saturating_mul(height as u128),
        )?;
        let footprint = self.radius() * std::f64::consts::PI / height as f64;
        let mut both = Grid2::new(width, height, (0.0f32, Vec3::ZERO))?;
        fill_rows(&mut both, "equirectangular", progress, |j, row| {
            let lat = std::f64::consts::FRAC_PI_2
                - std::f64::consts::PI * (j as f64 + 0.5) / height as f64;
            for (i, cell) in row.iter_mut().enumerate() {
                let lon =
                    -std::f64::consts::PI + std::f64::consts::TAU * (i as f64 + 0.5) / width as f64;
                *cell = self.surface_sample(super::views::direction(lat, lon), footprint);
            }
        });
        Ok(SurfaceMap {
            height: both.map(|c| c.0),
            colour: both.map(|c| c.1),
        })
    }

    /// [`cube_map`](Self::cube_map) without progress reports.
    ///
    /// # Errors
    /// As [`cube_map`](Self::cube_map).
    pub fn cube_map_quiet(&self, size: usize) -> Result<CubeMap> {
        self.cube_map(size, &NoProgress)
    }
}

/// Splits a colour grid into R, G, B channel vectors.
fn channels(c: &Grid2<Vec3>) -> [Vec<f32>; 3] {
    let s = c.as_slice();
    [
        s.iter().map(|v| v.x).collect(),
        s.iter().map(|v| v.y).collect(),
        s.iter().map(|v| v.z).collect(),
    ]
}

/// Writes a height grid (channel `Y`) and a colour grid (`R`, `G`, `B`).
fn write_pair(
    height_path: &Path,
    colour_path: &Path,
    height: &Grid2<f32>,
    colour: &Grid2<Vec3>,
    attributes: &[(&str, &str)],
) -> Result<()> {
    let (w, h) = height.dims();
    write_exr(height_path, w, h, &[("Y", height.as_slice())], attributes)?;
    let [r, g, b] = channels(colour);
    write_exr(
        colour_path,
        w,
        h,
        &[("R", &r), ("G", &g), ("B", &b)],
        attributes,
    )?;
    Ok(())
}

impl CubeMap {
    /// Checks a face size before any work: what
    /// [`Planet::cube_map`](crate::planet::Planet::cube_map) accepts.
    ///
    /// # Errors
    /// [`TextureError::InvalidSize`](crate::TextureError::InvalidSize) for
    /// `size < 2` or six faces over the memory cap.
    pub fn check_size(size: usize) -> Result<()> {
        let samples = (size as u128)
            .saturating_mul(size as u128)
            .saturating_mul(6);
        check_size("face_size", size, 2, samples)
    }

    /// The files [`write_exr`](Self::write_exr) writes into `dir`:
    /// `{name}_{face}_height.exr` and `{name}_{face}_colour.exr` per face.
    #[must_use]
    pub fn paths(dir: &Path, name: &str) -> Vec<PathBuf> {
        Face::ALL
            .iter()
            .flat_map(|f| {
                [
                    dir.join(format!("{name}_{}_height.exr", f.name())),
                    dir.join(format!("{name}_{}_colour.exr", f.name())),
                ]
            })
            .collect()
    }

    /// Writes every face as two linear `f32` EXR files (height in metres as
    /// channel `Y`; colour as `R`, `G`, `B`), each atomically, after checking
    /// that every file can be created. Returns the paths written.
    ///
    /// # Errors
    /// [`TextureError::Core`] naming the first file that cannot be written.
    pub fn write_exr(&self, dir: &Path, name: &str) -> Result<Vec<PathBuf>> {
        let paths = Self::paths(dir, name);
        for p in &paths {
            check_writable(p)?;
        }
        for (face, pair) in self.faces.iter().zip(paths.chunks(2)) {
            write_pair(
                &pair[0],
                &pair[1],
                &face.height,
                &face.colour,
                &[
                    ("face", face.face.name()),
                    ("projection", "equal-angle cube sphere"),
                ],
            )?;
        }
        Ok(paths)
    }
}

impl SurfaceMap {
    /// Writes the map as `{name}_height.exr` and `{name}_colour.exr` in
    /// `dir`, after checking both can be created. Returns the paths.
    ///
    /// # Errors
    /// [`TextureError::Core`] naming the first file that cannot be written.
    pub fn write_exr(&self, dir: &Path, name: &str) -> Result<[PathBuf; 2]> {
        let paths = [
            dir.join(format!("{name}_height.exr")),
            dir.join(format!("{name}_colour.exr")),
        ];
        for p in &paths {
            check_writable(p)?;
        }
        write_pair(
            &paths[0],
            &paths[1],
            &self.height,
            &self.colour,
            &[("projection", "equirectangular")],
        )?;
        Ok(paths)
    }
}
