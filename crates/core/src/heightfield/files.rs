//! Reading and writing height fields: raw little-endian `f32`, EXR and
//! 16-bit PNG, rows in map order (north up), every write atomic.

use std::io::Write;
use std::path::Path;

use super::{CELL_KEY, HeightField, RANGE_KEY};
use crate::check::positive;
use crate::error::{CoreError, Result};
use crate::grid2::{Grid2, checked_len};
use crate::io::exr::{read_exr, write_exr};
use crate::io::{WriteError, read_file_at_most, write_atomic};

/// The most deflate can compress: 1032 bytes out of every byte in.
const DEFLATE_MAX_RATIO: u64 = 1032;

impl HeightField {
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
        Self::load_exr_impl(path.as_ref(), cell_size)
    }

    /// The body of [`Self::load_exr`]: not generic, so it is compiled once, here, and not again in
    /// every crate that calls it.
    fn load_exr_impl(path: &Path, cell_size: Option<f32>) -> Result<Self> {
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
        self.save_png16_impl(path.as_ref(), range)
    }

    /// The body of [`Self::save_png16`]: not generic, so it is compiled once, here, and not again
    /// in every crate that calls it.
    fn save_png16_impl(&self, path: &Path, range: (f32, f32)) -> Result<()> {
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
        Self::load_png16_impl(path.as_ref(), cell_size, range)
    }

    /// The body of [`Self::load_png16`]: not generic, so it is compiled once, here, and not again
    /// in every crate that calls it.
    fn load_png16_impl(
        path: &Path,
        cell_size: Option<f32>,
        range: Option<(f32, f32)>,
    ) -> Result<Self> {
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
        let mut reader = reader;
        // The bytes the stream holds, to refuse a header whose pixels they
        // cannot hold before the pixels' buffer is allocated.
        // A stream that cannot seek (a pipe) is not measured: the decoder
        // then meets its end while it reads.
        let held = match (
            reader.stream_position(),
            reader.seek(std::io::SeekFrom::End(0)),
        ) {
            (Ok(start), Ok(end)) => {
                reader
                    .seek(std::io::SeekFrom::Start(start))
                    .map_err(|e| CoreError::io(path, e))?;
                end.saturating_sub(start)
            }
            _ => u64::MAX,
        };
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
        // Refused from the header, before the pixels' buffer exists: a
        // colour image's buffer (up to 8 bytes a pixel) could pass the check
        // above and still ask for tens of gigabytes. A greyscale buffer (at
        // most 2 bytes a pixel) is smaller than the grid just checked.
        if colour != png::ColorType::Grayscale {
            return Err(bad(format!(
                "expected a greyscale height map, found colour type {colour:?}"
            )));
        }
        let texts: Vec<(String, String)> = info
            .uncompressed_latin1_text
            .iter()
            .map(|t| (t.keyword.clone(), t.text.clone()))
            .collect();
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| bad("PNG too large".into()))?;
        // Deflate compresses at most 1032 to 1 (a length-258 match in two
        // bits), so a stream shorter than the pixels over 1032 is
        // truncated whatever it holds: refused before a buffer of the
        // header's size is allocated and filled (a 49-byte file claiming
        // four billion pixels asked for gigabytes).
        if (size as u64) / DEFLATE_MAX_RATIO > held {
            return Err(bad(format!(
                "truncated PNG: its {w} × {h} pixels need at least {} compressed bytes, the file holds {held}",
                (size as u64).div_ceil(DEFLATE_MAX_RATIO)
            )));
        }
        let mut buf = vec![0u8; size];
        reader
            .next_frame(&mut buf)
            .map_err(|e| bad(format!("corrupt or truncated PNG: {e}")))?;
        reader
            .finish()
            .map_err(|e| bad(format!("corrupt or truncated PNG: {e}")))?;
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
