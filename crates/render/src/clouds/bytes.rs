//! A [`CloudSky`] as bytes, so that the tiles of a frame rendered in
//! separate processes share one preparation of its clouds.
//!
//! Layout (little-endian): the magic `natura cloud sky`, a format number
//! (`u32`), the eye (3 × `f32`) and the layer's middle height; the dome's
//! first azimuth and elevation, inverse cell size, wrap flag (`u32`), width
//! and height (`u64`) and its cells (5 × `f32` each, row by row); the shadow
//! map's origin (2 × `f32`), inverse cell size, base height, sun slope
//! (2 × `f32`), width and height (`u64`) and its transmittances; then the
//! checksum of every byte before it (`u64`, natura-core's
//! [`checksum`](natura_core::io::checksum)). Nothing may follow. Floats
//! are stored as their bits, so a round trip is exact.
//!
//! The checksum is there because a flipped bit in a float is a valid float:
//! without it a damaged file gave another sky without a word. Format 1
//! (before the checksum) is still read.

use std::path::Path;

use glam::{Vec2, Vec3};
use natura_core::io::checksum;
use natura_core::{CoreError, Grid2};

use super::{CloudSky, Dome, ShadowMap};
use crate::error::Result;

const MAGIC: &[u8; 16] = b"natura cloud sky";
/// The format written; [`FORMAT_UNCHECKED`] is read as well.
const FORMAT: u32 = 2;
/// The format before the checksum, read without one.
const FORMAT_UNCHECKED: u32 = 1;

impl CloudSky {
    /// The clouds as bytes (see [`Self::from_bytes`]); a round trip gives
    /// the same lookups bit for bit.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let (d, s) = (&self.dome, &self.shadow);
        let mut out = Vec::with_capacity(
            128 + 4 * (5 * d.cells.as_slice().len() + s.transmittance.as_slice().len()),
        );
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT.to_le_bytes());
        let mut f = |v: &[f32]| {
            for x in v {
                out.extend_from_slice(&x.to_bits().to_le_bytes());
            }
        };
        f(&self.eye.to_array());
        f(&[self.mid, d.az0, d.el0, d.inv_cell]);
        out.extend_from_slice(&u32::from(d.wrap).to_le_bytes());
        out.extend_from_slice(&(d.cells.width() as u64).to_le_bytes());
        out.extend_from_slice(&(d.cells.height() as u64).to_le_bytes());
        for c in d.cells.as_slice() {
            for x in c {
                out.extend_from_slice(&x.to_bits().to_le_bytes());
            }
        }
        for x in [
            s.origin.x, s.origin.y, s.inv_cell, s.base, s.slope.x, s.slope.y,
        ] {
            out.extend_from_slice(&x.to_bits().to_le_bytes());
        }
        out.extend_from_slice(&(s.transmittance.width() as u64).to_le_bytes());
        out.extend_from_slice(&(s.transmittance.height() as u64).to_le_bytes());
        for x in s.transmittance.as_slice() {
            out.extend_from_slice(&x.to_bits().to_le_bytes());
        }
        let sum = checksum(out.iter().copied());
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Reads clouds written by [`Self::to_bytes`]; `source` names where the
    /// bytes came from in errors.
    ///
    /// # Errors
    ///
    /// [`RenderError::Core`](crate::RenderError::Core) with
    /// [`CoreError::Format`] if the bytes are not a cloud sky of this format
    /// (wrong magic or format number, truncated, trailing bytes, sizes over
    /// the grid cap, a checksum that does not match the bytes, non-finite
    /// values or transmittances outside [0, 1]).
    pub fn from_bytes(bytes: &[u8], source: &Path) -> Result<Self> {
        let bad = |problem: String| {
            crate::RenderError::Core(CoreError::Format {
                path: source.to_path_buf(),
                problem: format!("cloud sky: {problem}"),
            })
        };
        let mut r = Reader { bytes, at: 0 };
        if r.take(MAGIC.len()) != Some(MAGIC.as_slice()) {
            return Err(bad("not a natura cloud sky".into()));
        }
        let truncated = || bad("truncated".into());
        let format = r.u32().ok_or_else(truncated)?;
        if format != FORMAT && format != FORMAT_UNCHECKED {
            return Err(bad(format!(
                "format {format}, this build reads {FORMAT_UNCHECKED} and {FORMAT}"
            )));
        }
        let mut head = [0f32; 7];
        for h in &mut head {
            *h = r.f32().ok_or_else(truncated)?;
        }
        let wrap = match r.u32().ok_or_else(truncated)? {
            0 => false,
            1 => true,
            w => return Err(bad(format!("wrap flag {w} is neither 0 nor 1"))),
        };
        let (nx, ny) = r.dims().ok_or_else(truncated)?;
        let cells = r
            .grid(nx, ny, |r| {
                let mut c = [0f32; 5];
                for x in &mut c {
                    *x = r.f32()?;
                }
                Some(c)
            })
            .map_err(|e| e.map_or_else(truncated, |e| bad(e.to_string())))?;
        let mut tail = [0f32; 6];
        for t in &mut tail {
            *t = r.f32().ok_or_else(truncated)?;
        }
        let (sx, sy) = r.dims().ok_or_else(truncated)?;
        let transmittance = r
            .grid(sx, sy, Reader::f32)
            .map_err(|e| e.map_or_else(truncated, |e| bad(e.to_string())))?;
        if format == FORMAT {
            let end = r.at;
            let stored = r.take(8).ok_or_else(truncated)?;
            let stored = u64::from_le_bytes(stored.try_into().map_err(|_| truncated())?);
            if r.at == bytes.len() && stored != checksum(bytes[..end].iter().copied()) {
                return Err(bad("checksum does not match: the file is damaged".into()));
            }
        }
        if r.at != bytes.len() {
            return Err(bad(format!(
                "{} bytes after the {}",
                bytes.len() - r.at,
                if format == FORMAT {
                    "checksum"
                } else {
                    "shadow map"
                }
            )));
        }
        if nx < 2 || ny < 2 {
            return Err(bad(format!("dome of {nx} × {ny} cells (at least 2 × 2)")));
        }
        let finite = head.iter().chain(&tail).all(|x| x.is_finite())
            && cells.as_slice().iter().flatten().all(|x| x.is_finite());
        let unit = |x: &f32| (0.0..=1.0).contains(x);
        let in_unit = transmittance.as_slice().iter().all(unit)
            && cells.as_slice().iter().all(|c| unit(&c[3]) && unit(&c[4]));
        if !finite || !in_unit || head[6] <= 0.0 || tail[2] <= 0.0 {
            return Err(bad(
                "non-finite values, cell sizes or transmittances outside [0, 1]".into(),
            ));
        }
        Ok(Self {
            eye: Vec3::new(head[0], head[1], head[2]),
            mid: head[3],
            dome: Dome {
                az0: head[4],
                el0: head[5],
                inv_cell: head[6],
                wrap,
                cells,
            },
            shadow: ShadowMap {
                origin: Vec2::new(tail[0], tail[1]),
                inv_cell: tail[2],
                base: tail[3],
                slope: Vec2::new(tail[4], tail[5]),
                transmittance,
            },
        })
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Option<&[u8]> {
        let end = self.at.checked_add(n)?;
        let s = self.bytes.get(self.at..end)?;
        self.at = end;
        Some(s)
    }

    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }

    fn f32(&mut self) -> Option<f32> {
        self.u32().map(f32::from_bits)
    }

    fn dims(&mut self) -> Option<(u64, u64)> {
        let a = u64::from_le_bytes(self.take(8)?.try_into().ok()?);
        let b = u64::from_le_bytes(self.take(8)?.try_into().ok()?);
        Some((a, b))
    }

    /// A `nx × ny` grid read cell by cell: `Err(None)` if the bytes run
    /// out, `Err(Some(e))` if the size is refused.
    fn grid<T>(
        &mut self,
        nx: u64,
        ny: u64,
        mut cell: impl FnMut(&mut Self) -> Option<T>,
    ) -> std::result::Result<Grid2<T>, Option<CoreError>> {
        let (nx, ny) = (
            usize::try_from(nx).map_err(|_| None)?,
            usize::try_from(ny).map_err(|_| None)?,
        );
        let n = natura_core::checked_len::<T>(&[nx, ny]).map_err(Some)?;
        // Refuse a size the remaining bytes cannot hold before allocating.
        if n.saturating_mul(size_of::<T>()) > self.bytes.len() - self.at {
            return Err(None);
        }
        let mut data = Vec::with_capacity(n);
        for _ in 0..n {
            data.push(cell(self).ok_or(None)?);
        }
        Grid2::from_vec(nx, ny, data).map_err(Some)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small sky with every field distinct.
    fn sky() -> CloudSky {
        let cells = Grid2::from_fn(4, 3, |i, j| {
            let v = (i + 4 * j) as f32;
            [0.1 * v, 0.2 * v, 0.3 * v, 0.05 * v, 1.0 - 0.05 * v]
        })
        .unwrap();
        let transmittance = Grid2::from_fn(3, 2, |i, j| 0.1 * (i + 3 * j) as f32).unwrap();
        CloudSky {
            eye: Vec3::new(1.0, 2.0, 3.0),
            mid: 1500.0,
            dome: Dome {
                az0: -3.1,
                el0: -0.1,
                inv_cell: 12.5,
                wrap: true,
                cells,
            },
            shadow: ShadowMap {
                origin: Vec2::new(-50.0, 20.0),
                inv_cell: 0.01,
                base: 900.0,
                slope: Vec2::new(0.3, -0.2),
                transmittance,
            },
        }
    }

    fn read(bytes: &[u8]) -> Result<CloudSky> {
        CloudSky::from_bytes(bytes, Path::new("sky"))
    }

    #[test]
    fn every_damaged_byte_and_every_cut_is_refused() {
        let bytes = sky().to_bytes();
        assert_eq!(read(&bytes).unwrap().to_bytes(), bytes, "exact round trip");
        for at in 0..bytes.len() {
            for bit in 0..8 {
                let mut b = bytes.clone();
                b[at] ^= 1 << bit;
                let e = read(&b).err();
                assert!(
                    e.is_some_and(|e| e.to_string().contains("cloud sky")),
                    "bit {bit} of byte {at} flipped was read"
                );
            }
            assert!(read(&bytes[..at]).is_err(), "cut at {at}");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(
            read(&longer)
                .unwrap_err()
                .to_string()
                .contains("after the checksum")
        );
    }

    #[test]
    fn a_value_damaged_under_a_matching_checksum_is_still_refused() {
        let mut bytes = sky().to_bytes();
        let n = bytes.len() - 8;
        // The first dome cell follows the magic, format, 7 floats, wrap flag and two sizes.
        bytes[68..72].copy_from_slice(&f32::NAN.to_bits().to_le_bytes());
        let sum = checksum(bytes[..n].iter().copied());
        bytes[n..].copy_from_slice(&sum.to_le_bytes());
        let e = read(&bytes).unwrap_err().to_string();
        assert!(e.contains("non-finite"), "{e}");
    }

    #[test]
    fn the_format_before_the_checksum_is_still_read() {
        let sky = sky();
        let bytes = sky.to_bytes();
        let mut old = bytes[..bytes.len() - 8].to_vec();
        old[16..20].copy_from_slice(&FORMAT_UNCHECKED.to_le_bytes());
        assert_eq!(read(&old).unwrap().to_bytes(), bytes);
        // A later format is named.
        let mut new = bytes.clone();
        new[16..20].copy_from_slice(&7u32.to_le_bytes());
        let e = read(&new).unwrap_err().to_string();
        assert!(e.contains("format 7"), "{e}");
    }
}
