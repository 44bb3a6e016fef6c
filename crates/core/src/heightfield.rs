//! `HeightField`: a regular grid of altitudes in metres with a horizontal cell size.
//!
//! Conventions: z up, metres. Sample `(i, j)` of the
//! grid sits at world position `(i·cell_size, j·cell_size, h[i, j])`, so the
//! field covers `[0, (nx − 1)·cell_size] × [0, (ny − 1)·cell_size]`. This is
//! Musgrave's "regular height field" (Musgrave et al. 1989, §2).
//!
//! Files (PNG, EXR, raw) store rows in **map order**: the first row in the
//! file is the row of largest y (north up), as DEM tools and image viewers
//! expect. Reading and writing flip rows accordingly; round trips are exact.

use std::io::Write;
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::check::positive;
use crate::error::{CoreError, Result};
use crate::grid2::{Grid2, checked_len};
use crate::io::exr::{read_exr, write_exr};
use crate::io::{WriteError, read_file_at_most, write_atomic};
use crate::sample::Boundary;

/// An axis-aligned box in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box's extent along each axis.
    #[must_use]
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    /// The centre of the box.
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Whether `p` lies inside or on the box.
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// Key of the tEXt chunk / EXR attribute holding the height range of a 16-bit PNG.
const RANGE_KEY: &str = "natura:height_range_m";
/// Key of the attribute holding the cell size.
const CELL_KEY: &str = "natura:cell_size_m";

/// A height field: altitudes in metres on a regular grid with square cells.
///
/// Constructors refuse NaN or infinite heights (naming the first bad cell)
/// and a cell size that is not finite and positive. [`HeightField::heights_mut`]
/// hands out the grid for in-place algorithms (erosion); consumers that need
/// finiteness re-check with [`HeightField::check_finite`].
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    heights: Grid2<f32>,
    cell_size: f32,
}

impl HeightField {
    /// Wraps a grid of heights (metres) with `cell_size` metres between samples.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if `cell_size` is not
    /// finite and positive.
    pub fn new(heights: Grid2<f32>, cell_size: f32) -> Result<Self> {
        positive("cell_size", f64::from(cell_size))?;
        heights.check_finite()?;
        Ok(Self { heights, cell_size })
    }

    /// A field of `nx × ny` samples whose height at sample `(i, j)` is `f(i, j)`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if `cell_size` is not finite and positive.
    pub fn from_fn(
        nx: usize,
        ny: usize,
        cell_size: f32,
        f: impl FnMut(usize, usize) -> f32,
    ) -> Result<Self> {
        Self::new(Grid2::from_fn(nx, ny, f)?, cell_size)
    }

    /// A flat field at height `h`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if `cell_size` is not finite and positive.
    pub fn flat(nx: usize, ny: usize, cell_size: f32, h: f32) -> Result<Self> {
        Self::new(Grid2::new(nx, ny, h)?, cell_size)
    }

    /// The heights, metres.
    #[inline]
    #[must_use]
    pub fn heights(&self) -> &Grid2<f32> {
        &self.heights
    }

    /// The heights, mutably (keep them finite; see [`HeightField::check_finite`]).
    #[inline]
    pub fn heights_mut(&mut self) -> &mut Grid2<f32> {
        &mut self.heights
    }

    /// Consumes the field, returning its heights.
    #[must_use]
    pub fn into_heights(self) -> Grid2<f32> {
        self.heights
    }

    /// Horizontal distance between neighbouring samples, metres.
    #[inline]
    #[must_use]
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Samples along x.
    #[inline]
    #[must_use]
    pub fn nx(&self) -> usize {
        self.heights.width()
    }

    /// Samples along y.
    #[inline]
    #[must_use]
    pub fn ny(&self) -> usize {
        self.heights.height()
    }

    /// World extent `((nx − 1)·cell, (ny − 1)·cell)`, metres.
    #[must_use]
    pub fn extent(&self) -> Vec2 {
        Vec2::new((self.nx() - 1) as f32, (self.ny() - 1) as f32) * self.cell_size
    }

    /// The height of sample `(i, j)`; `None` outside the grid.
    #[inline]
    #[must_use]
    pub fn get(&self, i: usize, j: usize) -> Option<f32> {
        self.heights.get(i, j).copied()
    }

    /// World position of sample `(i, j)`.
    ///
    /// # Panics
    ///
    /// Panics if `i ≥ nx` or `j ≥ ny` (an index bug in the caller); use
    /// [`try_point`](Self::try_point) for indices that come from user data.
    #[inline]
    #[must_use]
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        Vec3::new(
            i as f32 * self.cell_size,
            j as f32 * self.cell_size,
            self.heights[(i, j)],
        )
    }

    /// World position of sample `(i, j)`, or `None` outside the grid.
    #[inline]
    #[must_use]
    pub fn try_point(&self, i: usize, j: usize) -> Option<Vec3> {
        self.get(i, j)
            .map(|z| Vec3::new(i as f32 * self.cell_size, j as f32 * self.cell_size, z))
    }

    /// Bilinearly interpolated height at world `(x, y)`; `None` outside the field or for NaN.
    #[must_use]
    pub fn height_at(&self, x: f32, y: f32) -> Option<f32> {
        let e = self.extent();
        if !(x >= 0.0 && y >= 0.0 && x <= e.x && y <= e.y) {
            return None;
        }
        Some(self.sample(x, y, Boundary::Clamp))
    }

    /// Bilinearly interpolated height at world `(x, y)` with `boundary` outside the field.
    #[must_use]
    pub fn sample(&self, x: f32, y: f32, boundary: Boundary<f32>) -> f32 {
        let inv = 1.0 / self.cell_size;
        self.heights.sample_bilinear(x * inv, y * inv, boundary)
    }

    /// Height gradient `(∂h/∂x, ∂h/∂y)` at sample `(i, j)` by central differences
    /// (one-sided on the border; zero along an axis with a single sample).
    #[must_use]
    pub fn gradient_at_sample(&self, i: usize, j: usize) -> Vec2 {
        let (nx, ny) = self.heights.dims();
        let h = &self.heights;
        let d = |lo: usize, hi: usize, v: f32, w: f32| {
            if hi > lo {
                (w - v) / ((hi - lo) as f32 * self.cell_size)
            } else {
                0.0
            }
        };
        let (x0, x1) = (i.saturating_sub(1), (i + 1).min(nx - 1));
        let (y0, y1) = (j.saturating_sub(1), (j + 1).min(ny - 1));
        Vec2::new(
            d(x0, x1, h[(x0, j)], h[(x1, j)]),
            d(y0, y1, h[(i, y0)], h[(i, y1)]),
        )
    }

    /// Unit surface normal at sample `(i, j)` from central differences, `(−∂h/∂x, −∂h/∂y, 1)` normalised.
    #[must_use]
    pub fn normal_at_sample(&self, i: usize, j: usize) -> Vec3 {
        let g = self.gradient_at_sample(i, j);
        Vec3::new(-g.x, -g.y, 1.0).normalize()
    }

    /// Gradient at world `(x, y)`: the central-difference gradients of the four
    /// surrounding samples, bilinearly interpolated. `None` outside the field.
    #[must_use]
    pub fn gradient_at(&self, x: f32, y: f32) -> Option<Vec2> {
        self.height_at(x, y)?;
        let fx = x / self.cell_size;
        let fy = y / self.cell_size;
        let i0 = (fx.floor() as usize).min(self.nx() - 1);
        let j0 = (fy.floor() as usize).min(self.ny() - 1);
        let i1 = (i0 + 1).min(self.nx() - 1);
        let j1 = (j0 + 1).min(self.ny() - 1);
        let (tx, ty) = (fx - i0 as f32, fy - j0 as f32);
        let g = |i, j| self.gradient_at_sample(i, j);
        let a = g(i0, j0).lerp(g(i1, j0), tx);
        let b = g(i0, j1).lerp(g(i1, j1), tx);
        Some(a.lerp(b, ty))
    }

    /// Unit surface normal at world `(x, y)` (see [`HeightField::gradient_at`]).
    #[must_use]
    pub fn normal_at(&self, x: f32, y: f32) -> Option<Vec3> {
        self.gradient_at(x, y)
            .map(|g| Vec3::new(-g.x, -g.y, 1.0).normalize())
    }

    /// Slope angle from horizontal at world `(x, y)`, radians in `[0, π/2)`.
    #[must_use]
    pub fn slope_at(&self, x: f32, y: f32) -> Option<f32> {
        self.gradient_at(x, y).map(|g| g.length().atan())
    }

    /// Slope angle at sample `(i, j)`, radians.
    #[must_use]
    pub fn slope_at_sample(&self, i: usize, j: usize) -> f32 {
        self.gradient_at_sample(i, j).length().atan()
    }

    /// `(lowest, highest)` height.
    #[must_use]
    pub fn min_max(&self) -> (f32, f32) {
        self.heights.min_max()
    }

    /// The world-space bounding box of the surface.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        let (lo, hi) = self.min_max();
        let e = self.extent();
        Aabb {
            min: Vec3::new(0.0, 0.0, lo),
            max: Vec3::new(e.x, e.y, hi),
        }
    }

    /// Fails with [`CoreError::NonFinite`] naming the first NaN or infinite height.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::NonFinite`](crate::CoreError::NonFinite) naming the first NaN or infinite value.
    pub fn check_finite(&self) -> Result<()> {
        self.heights.check_finite()
    }

    /// Lambertian hill shade `max(0, n·sun)` at every sample, for a unit `sun`
    /// direction (toward the sun, z up). Refuses a non-finite or zero `sun`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) naming `sun` if it is zero or
    /// not finite.
    pub fn hillshade(&self, sun: Vec3) -> Result<Grid2<f32>> {
        let s = sun.try_normalize().ok_or(CoreError::InvalidParameter {
            name: "sun",
            value: format!("{sun}"),
            reason: "must be a finite non-zero direction",
        })?;
        Grid2::from_fn(self.nx(), self.ny(), |i, j| {
            self.normal_at_sample(i, j).dot(s).max(0.0)
        })
    }

    // ---------------------------------------------------------------- raw --

    /// Writes heights as raw little-endian `f32`, rows in map order, atomically.
    /// The file has no header: keep the dimensions and cell size elsewhere.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be written (a missing or
    /// read-only folder, a directory in the way), and [`CoreError::Format`](crate::CoreError::Format)
    /// if the encoder refuses the data. Nothing is left half-written.
    pub fn save_raw(&self, path: impl AsRef<Path>) -> Result<()> {
        let bytes: Vec<u8> = map_rows(&self.heights)
            .flat_map(|r| r.iter().flat_map(|v| v.to_le_bytes()))
            .collect();
        write_atomic(path, |w| w.write_all(&bytes).map_err(WriteError::Io))
    }

    /// Reads raw little-endian `f32` heights of `nx × ny` samples (rows in map order).
    ///
    /// A file of the wrong length, or with a NaN or infinite value, is refused
    /// with an error naming the file. Raw files carry no checksum, so a flipped
    /// bit inside a valid float cannot be detected.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be read, and
    /// [`CoreError::Format`](crate::CoreError::Format) if it is truncated, corrupt or of an
    /// unsupported layout, or if its size exceeds the memory cap. A file of the wrong length for the stated size, a
    /// NaN or infinite height, and a bad cell size are errors too.
    pub fn load_raw(path: impl AsRef<Path>, nx: usize, ny: usize, cell_size: f32) -> Result<Self> {
        let path = path.as_ref();
        let len = checked_len::<f32>(&[nx, ny])?;
        // Never read more than one byte past the expected size, so an endless
        // stream (a pipe, /dev/zero) is refused instead of read without end.
        let bytes = read_file_at_most(path, len as u64 * 4 + 1)?;
        Self::from_raw_bytes(&bytes, path, nx, ny, cell_size)
    }

    /// As [`HeightField::load_raw`], from the file's bytes (`name` labels errors).
    ///
    /// # Errors
    ///
    /// As [`HeightField::load_raw`].
    pub fn from_raw_bytes(
        bytes: &[u8],
        name: &Path,
        nx: usize,
        ny: usize,
        cell_size: f32,
    ) -> Result<Self> {
        let path = name;
        let len = checked_len::<f32>(&[nx, ny])?;
        if bytes.len() != len * 4 {
            return Err(CoreError::format(
                path,
                if bytes.len() > len * 4 {
                    format!(
                        "expected {} bytes for {nx} × {ny} f32 heights, found more",
                        len * 4
                    )
                } else {
                    format!(
                        "expected {} bytes for {nx} × {ny} f32 heights, found {}",
                        len * 4,
                        bytes.len()
                    )
                },
            ));
        }
        let values: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        from_map_rows(path, nx, ny, values, cell_size)
    }

    // ---------------------------------------------------------------- exr --

    /// Writes heights as a single-channel (`Y`) 32-bit float EXR, rows in map
    /// order, with the cell size as an attribute, atomically. Round trips are bit-exact.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be written (a missing or
    /// read-only folder, a directory in the way), and [`CoreError::Format`](crate::CoreError::Format)
    /// if the encoder refuses the data. Nothing is left half-written.
    pub fn save_exr(&self, path: impl AsRef<Path>) -> Result<()> {
        let values: Vec<f32> = map_rows(&self.heights).flatten().copied().collect();
        let cell = self.cell_size.to_string();
        write_exr(
            path,
            self.nx(),
            self.ny(),
            &[("Y", &values)],
            &[(CELL_KEY, &cell)],
        )
    }

    /// Reads a height EXR. The height channel is `Y`, `Z`, `R`, `H` or
    /// `height`, or the only channel. `cell_size` overrides the file's
    /// attribute; without either, the call fails.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be read, and
    /// [`CoreError::Format`](crate::CoreError::Format) if it is truncated, corrupt or of an
    /// unsupported layout, or if its size exceeds the memory cap. A NaN or infinite height and a missing cell size are errors too.
    pub fn load_exr(path: impl AsRef<Path>, cell_size: Option<f32>) -> Result<Self> {
        let path = path.as_ref();
        let exr = read_exr(path)?;
        let data = ["Y", "Z", "R", "H", "height"]
            .iter()
            .find_map(|n| exr.channel(n))
            .or_else(|| (exr.channels.len() == 1).then(|| exr.channels[0].1.as_slice()))
            .ok_or_else(|| {
                let names: Vec<_> = exr.channels.iter().map(|(n, _)| n.as_str()).collect();
                CoreError::format(
                    path,
                    format!("no height channel among {names:?} (expected Y, Z, R, H or height)"),
                )
            })?;
        let cell = resolve_cell_size(path, cell_size, exr.attribute(CELL_KEY))?;
        from_map_rows(path, exr.width, exr.height, data.to_vec(), cell)
    }

    // ---------------------------------------------------------------- png --

    /// Writes a 16-bit greyscale PNG mapping heights `range.0 → 0` and `range.1 → 65535`,
    /// rows in map order, atomically. The range and cell size are stored in
    /// tEXt chunks so [`HeightField::load_png16`] can recover them.
    ///
    /// A height outside `range` is an error naming the cell (never clipped);
    /// use [`HeightField::min_max`] for a range that fits.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be written (a missing or
    /// read-only folder, a directory in the way), and [`CoreError::Format`](crate::CoreError::Format)
    /// if the encoder refuses the data. Nothing is left half-written.
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if the height range is empty or not finite.
    pub fn save_png16(&self, path: impl AsRef<Path>, range: (f32, f32)) -> Result<()> {
        let path = path.as_ref();
        let (lo, hi) = range;
        if !(lo.is_finite() && hi.is_finite() && hi > lo) {
            return Err(CoreError::InvalidParameter {
                name: "range",
                value: format!("({lo}, {hi})"),
                reason: "must be finite with range.1 > range.0",
            });
        }
        if let Some((x, y, &v)) = self.heights.find(|&v| v < lo || v > hi) {
            return Err(CoreError::InvalidParameter {
                name: "range",
                value: format!("({lo}, {hi})"),
                reason: if v < lo {
                    "a height lies below range.0"
                } else {
                    "a height lies above range.1"
                },
            })
            .map_err(|e| CoreError::format(path, format!("{e}: cell ({x}, {y}) = {v}")));
        }
        let scale = 65535.0 / f64::from(hi - lo);
        let mut bytes = Vec::with_capacity(self.heights.len() * 2);
        for row in map_rows(&self.heights) {
            for &v in row {
                let q = ((f64::from(v) - f64::from(lo)) * scale)
                    .round()
                    .clamp(0.0, 65535.0) as u16;
                bytes.extend_from_slice(&q.to_be_bytes());
            }
        }
        let (w, h) = (self.nx() as u32, self.ny() as u32);
        let range_text = format!("{lo} {hi}");
        let cell_text = self.cell_size.to_string();
        write_atomic(path, |out| {
            let enc_err = |e: png::EncodingError| match e {
                png::EncodingError::IoError(e) => WriteError::Io(e),
                other => WriteError::Encode(other.to_string()),
            };
            let mut enc = png::Encoder::new(out, w, h);
            enc.set_color(png::ColorType::Grayscale);
            enc.set_depth(png::BitDepth::Sixteen);
            enc.add_text_chunk(RANGE_KEY.into(), range_text)
                .map_err(enc_err)?;
            enc.add_text_chunk(CELL_KEY.into(), cell_text)
                .map_err(enc_err)?;
            let mut writer = enc.write_header().map_err(enc_err)?;
            writer.write_image_data(&bytes).map_err(enc_err)?;
            writer.finish().map_err(enc_err)
        })
    }

    /// Reads an 8- or 16-bit greyscale PNG height map.
    ///
    /// `range` maps grey 0 → `range.0` and full white → `range.1` metres; if
    /// `None`, the range stored by [`HeightField::save_png16`] is used, and a
    /// file without one is an error. `cell_size` likewise overrides the stored
    /// value. Colour PNGs are refused (convert to greyscale first).
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be read, and
    /// [`CoreError::Format`](crate::CoreError::Format) if it is truncated, corrupt or of an
    /// unsupported layout, or if its size exceeds the memory cap. A PNG that is not 16-bit greyscale, an empty height
    /// range and a missing cell size are errors too.
    pub fn load_png16(
        path: impl AsRef<Path>,
        cell_size: Option<f32>,
        range: Option<(f32, f32)>,
    ) -> Result<Self> {
        let path = path.as_ref();
        let file = std::fs::File::open(path).map_err(|e| CoreError::io(path, e))?;
        Self::read_png16(std::io::BufReader::new(file), path, cell_size, range)
    }

    /// As [`HeightField::load_png16`], from any buffered, seekable reader
    /// (`name` labels errors).
    ///
    /// # Errors
    ///
    /// As [`HeightField::load_png16`].
    pub fn read_png16(
        reader: impl std::io::BufRead + std::io::Seek,
        name: &Path,
        cell_size: Option<f32>,
        range: Option<(f32, f32)>,
    ) -> Result<Self> {
        let path = name;
        let bad = |m: String| CoreError::format(path, m);
        // The decoder may allocate no more than the image itself needs plus
        // its chunks; the image's size is checked against the cap from the
        // header, before any pixel memory exists.
        let limits = png::Limits {
            bytes: usize::try_from(crate::MAX_GRID_BYTES).unwrap_or(usize::MAX),
        };
        let mut dec = png::Decoder::new_with_limits(reader, limits);
        dec.set_transformations(png::Transformations::IDENTITY);
        let mut reader = dec
            .read_info()
            .map_err(|e| bad(format!("not a readable PNG: {e}")))?;
        let info = reader.info();
        let (w, h, colour, depth) = (
            info.width as usize,
            info.height as usize,
            info.color_type,
            info.bit_depth,
        );
        checked_len::<f32>(&[w, h]).map_err(|e| bad(format!("PNG header: {e}")))?;
        let texts: Vec<(String, String)> = info
            .uncompressed_latin1_text
            .iter()
            .map(|t| (t.keyword.clone(), t.text.clone()))
            .collect();
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| bad("PNG too large".into()))?;
        let mut buf = vec![0u8; size];
        reader
            .next_frame(&mut buf)
            .map_err(|e| bad(format!("corrupt or truncated PNG: {e}")))?;
        reader
            .finish()
            .map_err(|e| bad(format!("corrupt or truncated PNG: {e}")))?;
        let decoded = (w, h, colour, depth, texts, buf);
        let (w, h, colour, depth, texts, buf) = decoded;
        if colour != png::ColorType::Grayscale {
            return Err(bad(format!(
                "expected a greyscale height map, found colour type {colour:?}"
            )));
        }
        let text = |k: &str| {
            texts
                .iter()
                .find(|(key, _)| key == k)
                .map(|(_, v)| v.as_str())
        };
        let (lo, hi) = match range {
            Some(r) => r,
            None => {
                let t = text(RANGE_KEY)
                    .ok_or_else(|| bad("no height range given and the file stores none".into()))?;
                let mut it = t.split_whitespace().map(str::parse::<f32>);
                match (it.next(), it.next()) {
                    (Some(Ok(a)), Some(Ok(b))) => (a, b),
                    _ => return Err(bad(format!("unreadable stored height range `{t}`"))),
                }
            }
        };
        if !(lo.is_finite() && hi.is_finite() && hi > lo) {
            return Err(bad(format!(
                "height range ({lo}, {hi}) must be finite with max > min"
            )));
        }
        let cell = resolve_cell_size(path, cell_size, text(CELL_KEY))?;
        let n = checked_len::<f32>(&[w, h])?;
        let values: Vec<f32> = match depth {
            png::BitDepth::Sixteen => buf[..n * 2]
                .chunks_exact(2)
                .map(|c| f32::from(u16::from_be_bytes([c[0], c[1]])) / 65535.0)
                .collect(),
            png::BitDepth::Eight => buf[..n].iter().map(|&v| f32::from(v) / 255.0).collect(),
            other => {
                return Err(bad(format!(
                    "unsupported bit depth {other:?} (need 8 or 16)"
                )));
            }
        };
        let span = f64::from(hi) - f64::from(lo);
        let values = values
            .into_iter()
            .map(|t| (f64::from(lo) + f64::from(t) * span) as f32)
            .collect();
        from_map_rows(path, w, h, values, cell)
    }

    /// Loads a height map by extension: `.png` (see [`HeightField::load_png16`]),
    /// `.exr`; raw files need their dimensions, so use [`HeightField::load_raw`].
    ///
    /// # Errors
    ///
    /// As the loader chosen by the file's extension ([`HeightField::load_png16`],
    /// [`HeightField::load_exr`], [`HeightField::load_raw`]); an unknown extension is
    /// [`CoreError::Format`](crate::CoreError::Format).
    pub fn load(
        path: impl AsRef<Path>,
        cell_size: Option<f32>,
        range: Option<(f32, f32)>,
    ) -> Result<Self> {
        let path = path.as_ref();
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Self::load_png16(path, cell_size, range),
            Some("exr") => Self::load_exr(path, cell_size),
            _ => Err(CoreError::format(
                path,
                "unknown height-map extension (expected .png or .exr)",
            )),
        }
    }
}

/// Rows in map order (largest y first).
fn map_rows(g: &Grid2<f32>) -> impl Iterator<Item = &[f32]> {
    (0..g.height()).rev().map(move |j| g.row(j))
}

/// Builds a field from values whose rows are in map order, refusing NaN/inf.
fn from_map_rows(
    path: &Path,
    nx: usize,
    ny: usize,
    values: Vec<f32>,
    cell: f32,
) -> Result<HeightField> {
    let file = Grid2::from_vec(nx, ny, values)?;
    let grid = Grid2::from_fn(nx, ny, |i, j| file[(i, ny - 1 - j)])?;
    positive("cell_size", f64::from(cell))?;
    if let Some((x, y, &v)) = grid.find(|v| !v.is_finite()) {
        return Err(CoreError::format(
            path,
            format!("non-finite height {v} at cell ({x}, {y})"),
        ));
    }
    HeightField::new(grid, cell)
}

fn resolve_cell_size(path: &Path, given: Option<f32>, stored: Option<&str>) -> Result<f32> {
    match (given, stored) {
        (Some(c), _) => Ok(c),
        (None, Some(s)) => s
            .trim()
            .parse::<f32>()
            .map_err(|_| CoreError::format(path, format!("unreadable stored cell size `{s}`"))),
        (None, None) => Err(CoreError::format(
            path,
            "no cell size given and the file stores none",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("natura-core-hf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// A bumpy, asymmetric field so that any row flip or transpose shows.
    pub(crate) fn bumpy(nx: usize, ny: usize) -> HeightField {
        HeightField::from_fn(nx, ny, 2.5, |i, j| {
            (i as f32 * 0.37).sin() * 120.0 + (j as f32 * 0.21).cos() * 80.0 + i as f32 * 0.5
                - j as f32 * 3.0
                + 1000.0
        })
        .unwrap()
    }

    #[test]
    fn construction_refuses_nan_and_bad_cells() {
        let mut g = Grid2::new(4, 3, 0.0f32).unwrap();
        g[(2, 1)] = f32::INFINITY;
        let err = HeightField::new(g, 1.0).unwrap_err();
        assert!(
            matches!(err, CoreError::NonFinite { x: 2, y: 1, .. }),
            "{err}"
        );
        for c in [0.0, -1.0, f32::NAN] {
            assert!(HeightField::flat(2, 2, c, 0.0).is_err());
        }
    }

    #[test]
    fn geometry() {
        let hf = HeightField::from_fn(11, 6, 2.0, |i, j| 3.0 * i as f32 - 1.0 * j as f32).unwrap();
        assert_eq!(hf.extent(), Vec2::new(20.0, 10.0));
        let b = hf.bounds();
        assert_eq!(b.min, Vec3::new(0.0, 0.0, -5.0));
        assert_eq!(b.max, Vec3::new(20.0, 10.0, 30.0));
        // h = 1.5 x − 0.5 y in world units: bilinear is exact, gradient is constant.
        assert_relative_eq!(
            hf.height_at(7.3, 4.1).unwrap(),
            1.5 * 7.3 - 0.5 * 4.1,
            epsilon = 1e-4
        );
        assert_eq!(hf.height_at(-0.1, 1.0), None);
        assert_eq!(hf.height_at(f32::NAN, 1.0), None);
        let g = hf.gradient_at(13.0, 3.0).unwrap();
        assert_relative_eq!(g.x, 1.5, epsilon = 1e-5);
        assert_relative_eq!(g.y, -0.5, epsilon = 1e-5);
        let n = hf.normal_at(5.0, 5.0).unwrap();
        assert_relative_eq!(n, Vec3::new(-1.5, 0.5, 1.0).normalize(), epsilon = 1e-5);
        assert_relative_eq!(
            hf.slope_at(1.0, 1.0).unwrap(),
            (1.5f32.hypot(0.5)).atan(),
            epsilon = 1e-5
        );
        let shade = hf.hillshade(Vec3::Z).unwrap();
        assert_relative_eq!(shade[(5, 3)], n.z, epsilon = 1e-5);
        assert!(hf.hillshade(Vec3::ZERO).is_err());
    }

    #[test]
    fn raw_round_trip_is_exact() {
        let hf = bumpy(23, 17);
        let p = scratch("rt.raw");
        hf.save_raw(&p).unwrap();
        assert_eq!(HeightField::load_raw(&p, 23, 17, 2.5).unwrap(), hf);
        let err = HeightField::load_raw(&p, 17, 23 + 1, 2.5).unwrap_err();
        assert!(
            err.to_string().contains("rt.raw") && err.to_string().contains("expected"),
            "{err}"
        );
    }

    #[test]
    fn raw_file_order_is_map_order() {
        let hf = HeightField::from_fn(2, 2, 1.0, |i, j| (i + 10 * j) as f32).unwrap();
        let p = scratch("order.raw");
        hf.save_raw(&p).unwrap();
        let b = std::fs::read(&p).unwrap();
        let first = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        assert_eq!(
            first, 10.0,
            "the first stored row is the one with the largest y"
        );
    }

    #[test]
    fn exr_round_trip_is_bit_exact() {
        let mut hf = bumpy(31, 19);
        hf.heights_mut()[(3, 4)] = -0.0;
        hf.heights_mut()[(5, 6)] = f32::MIN_POSITIVE / 3.0; // subnormal
        let p = scratch("rt.exr");
        hf.save_exr(&p).unwrap();
        let back = HeightField::load_exr(&p, None).unwrap();
        assert_eq!(back.cell_size(), hf.cell_size());
        for (a, b) in back
            .heights()
            .as_slice()
            .iter()
            .zip(hf.heights().as_slice())
        {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }

    #[test]
    fn png16_round_trip_within_one_step() {
        let hf = bumpy(29, 21);
        let (lo, hi) = hf.min_max();
        let p = scratch("rt.png");
        hf.save_png16(&p, (lo, hi)).unwrap();
        let back = HeightField::load_png16(&p, None, None).unwrap();
        assert_eq!(back.cell_size(), hf.cell_size());
        let step = (hi - lo) / 65535.0;
        for (a, b) in back
            .heights()
            .as_slice()
            .iter()
            .zip(hf.heights().as_slice())
        {
            assert!((a - b).abs() <= step, "{a} vs {b}, step {step}");
        }
        // A range that does not cover the data is refused, naming a cell.
        let err = hf.save_png16(&p, (lo + 10.0, hi)).unwrap_err();
        assert!(err.to_string().contains("cell ("), "{err}");
        assert!(hf.save_png16(&p, (5.0, 5.0)).is_err());
    }

    #[test]
    fn png_without_range_needs_one() {
        let img = crate::Image::new(4, 4, Vec3::splat(0.5)).unwrap();
        let p = scratch("colour.png");
        img.save_png(&p).unwrap();
        let err = HeightField::load_png16(&p, Some(1.0), Some((0.0, 1.0))).unwrap_err();
        assert!(err.to_string().contains("greyscale"), "{err}");
    }

    #[test]
    fn missing_file_is_named() {
        let err = HeightField::load_exr("/no/such/file.exr", Some(1.0)).unwrap_err();
        assert!(err.to_string().contains("/no/such/file.exr"));
        let err = HeightField::load("x.tiff", Some(1.0), None).unwrap_err();
        assert!(err.to_string().contains("extension"));
    }
}
