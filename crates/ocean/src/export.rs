//! Export of ocean maps as linear `f32` OpenEXR, for other tools, and a
//! writer for numbered frame sequences.
//!
//! [`write_maps`] stores, per sample of the rest grid: `height`, `disp.x`,
//! `disp.y` (metres; together the vector displacement of the rest point,
//! z up), `normal.x/y/z` (unit, upward), `jacobian`, the raw `slope_x/y`
//! and, when given, `foam`. Row j of the image is grid row j (y = j·Δy),
//! so image row 0 is the patch's southern edge. Text attributes record the
//! patch size, the time and the axis convention.

use std::path::{Path, PathBuf};

use natura_core::Image;
use natura_core::io::exr::write_exr;

use crate::error::{OceanError, Result};
use crate::foam::Foam;
use crate::frame::Frame;

/// Writes `frame` (and `foam`, which must match its size) as a
/// multi-channel EXR at `path`, atomically (temporary file, then rename).
///
/// # Errors
///
/// Returns [`OceanError::SizeMismatch`] if `foam` is not the frame's size, and
/// [`OceanError::Core`] if the file cannot be written.
pub fn write_maps(path: impl AsRef<Path>, frame: &Frame, foam: Option<&Foam>) -> Result<()> {
    write_maps_impl(path.as_ref(), frame, foam)
}

/// The body of [`write_maps`]: not generic, so it is compiled once, here, and not again in every
/// crate that calls it.
fn write_maps_impl(path: &Path, frame: &Frame, foam: Option<&Foam>) -> Result<()> {
    let (nx, ny) = frame.dims();
    if let Some(f) = foam
        && f.coverage().dims() != (nx, ny)
    {
        return Err(OceanError::SizeMismatch {
            expected: format!("foam of {nx} × {ny}"),
            actual: format!("{:?}", f.coverage().dims()),
        });
    }
    let normals = frame.normals();
    let split = |c: usize| -> Vec<f32> { normals.as_slice().iter().map(|n| n[c]).collect() };
    let (nxs, nys, nzs) = (split(0), split(1), split(2));
    let jac = frame.jacobian_grid();
    let mut channels: Vec<(&str, &[f32])> = vec![
        ("height", frame.height().as_slice()),
        ("disp.x", frame.disp_x().as_slice()),
        ("disp.y", frame.disp_y().as_slice()),
        ("normal.x", &nxs),
        ("normal.y", &nys),
        ("normal.z", &nzs),
        ("jacobian", jac.as_slice()),
        ("slope_x", frame.slope_x().as_slice()),
        ("slope_y", frame.slope_y().as_slice()),
    ];
    if let Some(f) = foam {
        channels.push(("foam", f.coverage().as_slice()));
    }
    let ext = frame.extent();
    let size = format!("{} {}", ext.x, ext.y);
    let time = format!("{}", frame.time());
    let attrs = [
        ("naturaOceanExtentM", size.as_str()),
        ("naturaOceanTimeS", time.as_str()),
        (
            "naturaOceanAxes",
            "x east, y north (row j = y), z up; metres",
        ),
    ];
    write_exr(path, nx, ny, &channels, &attrs)?;
    Ok(())
}

/// Writes numbered files `<dir>/<stem>_0000.<ext>`, `…_0001.<ext>`, … for an
/// animation: EXR maps of frames or PNG pictures.
#[derive(Clone, Debug)]
pub struct FrameSequence {
    dir: PathBuf,
    stem: String,
    next: usize,
    written: Vec<PathBuf>,
}

impl FrameSequence {
    /// Starts a sequence in the existing, writable directory `dir`; the
    /// check is done now, before any frame is computed.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`] if `dir` is not an existing directory, and
    /// [`OceanError::Core`] if it is not writable.
    pub fn new(dir: impl Into<PathBuf>, stem: &str) -> Result<Self> {
        let dir = dir.into();
        if stem.is_empty() || stem.contains(['/', '\\']) {
            return Err(crate::error::invalid(
                "stem",
                stem,
                "must be a non-empty file name",
            ));
        }
        natura_core::io::check_writable(dir.join(format!("{stem}_probe")))?;
        Ok(Self {
            dir,
            stem: stem.to_owned(),
            next: 0,
            written: Vec::new(),
        })
    }

    /// Returns the path of frame `index` with extension `ext`.
    #[must_use]
    pub fn path(&self, index: usize, ext: &str) -> PathBuf {
        self.dir.join(format!("{}_{index:04}.{ext}", self.stem))
    }

    /// Writes the next frame's maps as EXR (see [`write_maps`]); returns its path.
    ///
    /// # Errors
    ///
    /// As [`write_maps`].
    pub fn write_maps(&mut self, frame: &Frame, foam: Option<&Foam>) -> Result<PathBuf> {
        let p = self.path(self.next, "exr");
        write_maps(&p, frame, foam)?;
        Ok(self.advance(p))
    }

    /// Writes the next frame as an 8-bit sRGB PNG; returns its path.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::Core`] if the file cannot be written.
    pub fn write_png(&mut self, image: &Image) -> Result<PathBuf> {
        let p = self.path(self.next, "png");
        image.save_png(&p)?;
        Ok(self.advance(p))
    }

    fn advance(&mut self, p: PathBuf) -> PathBuf {
        self.next += 1;
        self.written.push(p.clone());
        p
    }

    /// Returns the files written so far, in order.
    #[must_use]
    pub fn written(&self) -> &[PathBuf] {
        &self.written
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FoamParams, Ocean, OceanParams, Phillips, Seed};
    use natura_core::io::exr::read_exr;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("natura-ocean-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn maps_round_trip_through_exr() {
        let p = OceanParams {
            nx: 32,
            ny: 16,
            lx: 50.0,
            ly: 25.0,
            choppiness: 1.0,
            ..OceanParams::default()
        };
        let o = Ocean::new(
            &p,
            &Phillips {
                wind_speed: 9.0,
                ..Phillips::default()
            },
            Seed(2),
        )
        .unwrap();
        let f = o.evaluate(1.25).unwrap();
        let mut foam = Foam::for_frame(&f, FoamParams::default()).unwrap();
        foam.update(&f).unwrap();
        let dir = scratch("exr");
        let mut seq = FrameSequence::new(&dir, "sea").unwrap();
        let path = seq.write_maps(&f, Some(&foam)).unwrap();
        assert_eq!(path, dir.join("sea_0000.exr"));
        let back = read_exr(&path).unwrap();
        assert_eq!((back.width, back.height), (32, 16));
        assert_eq!(back.channel("height").unwrap(), f.height().as_slice());
        assert_eq!(back.channel("disp.y").unwrap(), f.disp_y().as_slice());
        assert_eq!(back.channel("foam").unwrap(), foam.coverage().as_slice());
        let nz = back.channel("normal.z").unwrap();
        assert!((nz[17] - f.normal_up(17, 0).z).abs() < 1e-7);
        assert_eq!(back.attribute("naturaOceanTimeS"), Some("1.25"));
        let second = seq.write_maps(&f, None).unwrap();
        assert_eq!(second, dir.join("sea_0001.exr"));
        assert!(read_exr(&second).unwrap().channel("foam").is_none());
        assert_eq!(seq.written().len(), 2);
    }

    #[test]
    fn bad_destinations_are_refused_up_front() {
        assert!(FrameSequence::new("/nonexistent-natura-dir", "x").is_err());
        assert!(FrameSequence::new(scratch("bad"), "").is_err());
        assert!(FrameSequence::new(scratch("bad"), "a/b").is_err());
    }
}
