//! `Image`: a linear-light RGB `f32` image, and PNG/EXR input and output.

use std::path::Path;

use glam::Vec3;

use crate::colour::{Ramp, ToneMap, exposure, from_srgb8, srgb_decode, to_srgb8};
use crate::error::{CoreError, Result};
use crate::grid2::Grid2;
use crate::io::exr::{read_exr, write_exr};
use crate::io::{WriteError, write_atomic};

/// A linear RGB image with `f32` channels (scene-referred until tone-mapped).
///
/// Pixel `(x, y)` has `x` to the right and `y` downward, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pixels: Grid2<Vec3>,
}

impl Image {
    /// A `width × height` image filled with `colour`; refuses zero or oversize dimensions.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    pub fn new(width: usize, height: usize, colour: Vec3) -> Result<Self> {
        Ok(Self {
            pixels: Grid2::new(width, height, colour)?,
        })
    }

    /// An image whose pixel `(x, y)` is `f(x, y)`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    pub fn from_fn(
        width: usize,
        height: usize,
        f: impl FnMut(usize, usize) -> Vec3,
    ) -> Result<Self> {
        Ok(Self {
            pixels: Grid2::from_fn(width, height, f)?,
        })
    }

    /// Wraps a grid of linear colours.
    #[must_use]
    pub fn from_grid(pixels: Grid2<Vec3>) -> Self {
        Self { pixels }
    }

    /// Maps a scalar field through a false-colour `ramp`, with `[lo, hi]` spanning the ramp.
    #[must_use]
    pub fn false_colour(field: &Grid2<f32>, ramp: Ramp, lo: f32, hi: f32) -> Self {
        Self {
            pixels: field.map(|&v| ramp.map(v, lo, hi)),
        }
    }

    /// Maps a scalar field through `ramp` using the field's own min and max.
    #[must_use]
    pub fn false_colour_auto(field: &Grid2<f32>, ramp: Ramp) -> Self {
        let (lo, hi) = field.min_max();
        Self::false_colour(field, ramp, lo, hi)
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> usize {
        self.pixels.width()
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> usize {
        self.pixels.height()
    }

    /// The pixels as a grid.
    #[must_use]
    pub fn pixels(&self) -> &Grid2<Vec3> {
        &self.pixels
    }

    /// The pixels as a grid, mutably.
    pub fn pixels_mut(&mut self) -> &mut Grid2<Vec3> {
        &mut self.pixels
    }

    /// Consumes the image, returning its pixel grid.
    #[must_use]
    pub fn into_grid(self) -> Grid2<Vec3> {
        self.pixels
    }

    /// Pixel `(x, y)`, or `None` outside.
    #[must_use]
    pub fn get(&self, x: usize, y: usize) -> Option<Vec3> {
        self.pixels.get(x, y).copied()
    }

    /// Sets pixel `(x, y)`; returns `false` (changing nothing) outside.
    pub fn set(&mut self, x: usize, y: usize, c: Vec3) -> bool {
        self.pixels.set(x, y, c).is_some()
    }

    /// The image shrunk by an integer `factor` with a box filter (see
    /// [`Grid2::box_downsample`]).
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`] if `factor` is zero or larger
    /// than either side.
    pub fn box_downsample(&self, factor: usize) -> Result<Image> {
        Ok(Image {
            pixels: self.pixels.box_downsample(factor)?,
        })
    }

    /// The image box-filtered by the smallest integer factor that brings
    /// both sides to at most `max_side` pixels (itself when they already are).
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`] if `max_side` is zero or the
    /// factor needed exceeds the shorter side.
    pub fn fit_within(&self, max_side: usize) -> Result<Image> {
        if max_side == 0 {
            return Err(CoreError::InvalidParameter {
                name: "max_side",
                value: "0".into(),
                reason: "must be at least 1",
            });
        }
        let factor = self.width().max(self.height()).div_ceil(max_side).max(1);
        self.box_downsample(factor)
    }

    /// Lays `images` out in a grid of `columns` columns separated by `gap`
    /// pixels of `background`, each cell the size of the largest image and
    /// each image centred in its cell (a contact sheet).
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`] for no images or zero
    /// columns, and the errors of [`Image::new`] for a sheet too large.
    pub fn contact_sheet(
        images: &[Image],
        columns: usize,
        gap: usize,
        background: Vec3,
    ) -> Result<Image> {
        if images.is_empty() {
            return Err(CoreError::InvalidParameter {
                name: "images",
                value: "0 images".into(),
                reason: "a contact sheet needs at least one image",
            });
        }
        if columns == 0 {
            return Err(CoreError::InvalidParameter {
                name: "columns",
                value: "0".into(),
                reason: "must be at least 1",
            });
        }
        let cw = images.iter().map(Image::width).max().unwrap_or(1);
        let ch = images.iter().map(Image::height).max().unwrap_or(1);
        let cols = columns.min(images.len());
        let rows = images.len().div_ceil(cols);
        let w = cols * cw + (cols + 1) * gap;
        let h = rows * ch + (rows + 1) * gap;
        let mut sheet = Image::new(w, h, background)?;
        for (k, img) in images.iter().enumerate() {
            let (cx, cy) = (k % cols, k / cols);
            let x0 = gap + cx * (cw + gap) + (cw - img.width()) / 2;
            let y0 = gap + cy * (ch + gap) + (ch - img.height()) / 2;
            for y in 0..img.height() {
                for x in 0..img.width() {
                    sheet.set(x0 + x, y0 + y, img.pixels[(x, y)]);
                }
            }
        }
        Ok(sheet)
    }

    /// Returns `exposure(c, ev)` tone-mapped by `op`: display-referred linear values in `[0, 1]`.
    #[must_use]
    pub fn tone_mapped(&self, ev: f32, op: ToneMap) -> Image {
        Image {
            pixels: self.pixels.map(|&c| op.apply(exposure(c, ev))),
        }
    }

    /// The first pixel with a NaN or infinite channel, if any.
    #[must_use]
    pub fn first_non_finite(&self) -> Option<(usize, usize)> {
        self.pixels.find(|c| !c.is_finite()).map(|(x, y, _)| (x, y))
    }

    /// 8-bit sRGB bytes, `RGBRGB…` row by row (values clipped to `[0, 1]`).
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels
            .as_slice()
            .iter()
            .flat_map(|&c| to_srgb8(c))
            .collect()
    }

    /// Writes an 8-bit sRGB PNG, atomically.
    ///
    /// Values are treated as display-referred linear light: clipped to `[0, 1]`
    /// and sRGB-encoded. Tone-map HDR images first ([`Image::tone_mapped`]).
    /// An image with a NaN or infinite pixel is refused (naming the pixel)
    /// rather than written with a silently invented colour.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be written (a missing or
    /// read-only folder, a directory in the way), and [`CoreError::Format`](crate::CoreError::Format)
    /// if the encoder refuses the data. Nothing is left half-written.
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<()> {
        self.save_png_impl(path.as_ref())
    }

    /// The body of [`Self::save_png`]: not generic, so it is compiled once, here, and not again in
    /// every crate that calls it.
    fn save_png_impl(&self, path: &Path) -> Result<()> {
        if let Some((x, y)) = self.first_non_finite() {
            return Err(CoreError::format(
                path,
                format!("pixel ({x}, {y}) is not finite; refusing to write"),
            ));
        }
        let bytes = self.to_srgb8();
        let (w, h) = (self.width() as u32, self.height() as u32);
        write_atomic(path, |out| {
            encode_png(out, &bytes, w, h, image::ExtendedColorType::Rgb8)
        })
    }

    /// Writes a linear `f32` RGB OpenEXR file (channels R, G, B), atomically.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be written (a missing or
    /// read-only folder, a directory in the way), and [`CoreError::Format`](crate::CoreError::Format)
    /// if the encoder refuses the data. Nothing is left half-written.
    pub fn save_exr(&self, path: impl AsRef<Path>) -> Result<()> {
        let px = self.pixels.as_slice();
        let r: Vec<f32> = px.iter().map(|c| c.x).collect();
        let g: Vec<f32> = px.iter().map(|c| c.y).collect();
        let b: Vec<f32> = px.iter().map(|c| c.z).collect();
        write_exr(
            path,
            self.width(),
            self.height(),
            &[("R", &r), ("G", &g), ("B", &b)],
            &[],
        )
    }

    /// Reads the R, G, B channels of an EXR file as linear colour (a single
    /// `Y` channel is read as grey).
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be read, and
    /// [`CoreError::Format`](crate::CoreError::Format) if it is truncated, corrupt or of an
    /// unsupported layout, or if its size exceeds the memory cap. An EXR without R, G, B or Y channels is a format error.
    pub fn load_exr(path: impl AsRef<Path>) -> Result<Image> {
        Self::load_exr_impl(path.as_ref())
    }

    /// The body of [`Self::load_exr`]: not generic, so it is compiled once, here, and not again in
    /// every crate that calls it.
    fn load_exr_impl(path: &Path) -> Result<Image> {
        let exr = read_exr(path)?;
        let (w, h) = (exr.width, exr.height);
        let pixels = match (
            exr.channel("R"),
            exr.channel("G"),
            exr.channel("B"),
            exr.channel("Y"),
        ) {
            (Some(r), Some(g), Some(b), _) => Grid2::from_fn(w, h, |x, y| {
                Vec3::new(r[y * w + x], g[y * w + x], b[y * w + x])
            })?,
            (_, _, _, Some(l)) => Grid2::from_fn(w, h, |x, y| Vec3::splat(l[y * w + x]))?,
            _ => {
                return Err(CoreError::format(
                    path,
                    "EXR has neither R, G, B nor Y channels",
                ));
            }
        };
        Ok(Image { pixels })
    }

    /// Reads an 8- or 16-bit PNG (grey or RGB, alpha ignored) and decodes sRGB to linear.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Io`](crate::CoreError::Io) naming the file if it cannot be read, and
    /// [`CoreError::Format`](crate::CoreError::Format) if it is truncated, corrupt or of an
    /// unsupported layout, or if its size exceeds the memory cap.
    pub fn load_png(path: impl AsRef<Path>) -> Result<Image> {
        Self::load_png_impl(path.as_ref())
    }

    /// The body of [`Self::load_png`]: not generic, so it is compiled once, here, and not again in
    /// every crate that calls it.
    fn load_png_impl(path: &Path) -> Result<Image> {
        let img = decode_png(path)?;
        let (w, h) = (img.width() as usize, img.height() as usize);
        let pixels = match img {
            image::DynamicImage::ImageRgb8(_)
            | image::DynamicImage::ImageRgba8(_)
            | image::DynamicImage::ImageLuma8(_)
            | image::DynamicImage::ImageLumaA8(_) => {
                let rgb = img.to_rgb8();
                Grid2::from_fn(w, h, |x, y| from_srgb8(rgb.get_pixel(x as u32, y as u32).0))?
            }
            _ => {
                let rgb = img.to_rgb16();
                Grid2::from_fn(w, h, |x, y| {
                    let p = rgb.get_pixel(x as u32, y as u32).0;
                    let d = |v: u16| srgb_decode(f32::from(v) / 65535.0);
                    Vec3::new(d(p[0]), d(p[1]), d(p[2]))
                })?
            }
        };
        Ok(Image { pixels })
    }
}

/// Encodes raw pixel bytes as PNG into `out` (helper for atomic writers).
pub(crate) fn encode_png(
    out: &mut impl std::io::Write,
    bytes: &[u8],
    w: u32,
    h: u32,
    colour: image::ExtendedColorType,
) -> std::result::Result<(), WriteError> {
    use image::ImageEncoder;
    image::codecs::png::PngEncoder::new(out)
        .write_image(bytes, w, h, colour)
        .map_err(|e| match e {
            image::ImageError::IoError(e) => WriteError::Io(e),
            other => WriteError::Encode(other.to_string()),
        })
}

/// Decodes a PNG file with size limits, turning decoder errors (and panics on
/// hostile input) into [`CoreError::Format`] naming the file.
pub(crate) fn decode_png(path: &Path) -> Result<image::DynamicImage> {
    let bytes = crate::io::read_file(path)?;
    let bad = |m: String| CoreError::format(path, m);
    let result = std::panic::catch_unwind(|| {
        let mut reader =
            image::ImageReader::with_format(std::io::Cursor::new(&bytes), image::ImageFormat::Png);
        let mut limits = image::Limits::default();
        limits.max_alloc = Some(crate::MAX_GRID_BYTES);
        reader.limits(limits);
        reader.decode()
    });
    match result {
        Err(_) => Err(bad("corrupt PNG (decoder failed)".into())),
        Ok(Err(e)) => Err(bad(format!("not a readable PNG: {e}"))),
        Ok(Ok(img)) => Ok(img),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("natura-core-image-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn test_image() -> Image {
        Image::from_fn(17, 9, |x, y| {
            Vec3::new(x as f32 / 16.0, y as f32 / 8.0, 0.25)
        })
        .unwrap()
    }

    #[test]
    fn exr_round_trip_is_exact() {
        let img =
            Image::from_fn(13, 7, |x, y| Vec3::new(x as f32 * 1.5e3, -(y as f32), 1e-7)).unwrap();
        let p = scratch("rt.exr");
        img.save_exr(&p).unwrap();
        assert_eq!(Image::load_exr(&p).unwrap(), img);
    }

    #[test]
    fn png_round_trip_within_quantisation() {
        let img = test_image();
        let p = scratch("rt.png");
        img.save_png(&p).unwrap();
        let back = Image::load_png(&p).unwrap();
        assert_eq!(back.to_srgb8(), img.to_srgb8());
    }

    #[test]
    fn png_refuses_nan() {
        let mut img = test_image();
        img.set(3, 4, Vec3::new(f32::NAN, 0.0, 0.0));
        let err = img.save_png(scratch("nan.png")).unwrap_err();
        assert!(err.to_string().contains("(3, 4)"), "{err}");
    }

    #[test]
    fn contact_sheet_places_each_image_in_its_cell() {
        let red = Image::new(3, 2, Vec3::X).unwrap();
        let green = Image::new(1, 1, Vec3::Y).unwrap();
        let sheet = Image::contact_sheet(&[red.clone(), green, red], 2, 1, Vec3::ZERO).unwrap();
        // Two columns of 3 × 2 cells with 1-pixel gaps: 9 × 7.
        assert_eq!((sheet.width(), sheet.height()), (9, 7));
        assert_eq!(sheet.get(1, 1), Some(Vec3::X));
        assert_eq!(sheet.get(0, 0), Some(Vec3::ZERO));
        // The 1 × 1 image sits at the centre of the second cell.
        assert_eq!(sheet.get(5 + 1, 1), Some(Vec3::Y));
        assert_eq!(sheet.get(5, 1), Some(Vec3::ZERO));
        assert_eq!(sheet.get(1, 4), Some(Vec3::X));
        assert!(Image::contact_sheet(&[], 2, 1, Vec3::ZERO).is_err());
        assert!(Image::contact_sheet(&[sheet], 0, 1, Vec3::ZERO).is_err());
    }

    #[test]
    fn fit_within_shrinks_by_the_smallest_factor() {
        let img = Image::new(1000, 300, Vec3::ONE).unwrap();
        let small = img.fit_within(512).unwrap();
        assert_eq!((small.width(), small.height()), (500, 150));
        assert_eq!(img.fit_within(1000).unwrap(), img);
        assert!(img.fit_within(0).is_err());
    }

    #[test]
    fn tone_mapping_bounds() {
        let img = Image::new(4, 4, Vec3::splat(50.0)).unwrap();
        let t = img.tone_mapped(0.0, ToneMap::AcesFilmic);
        assert!(t.pixels().as_slice().iter().all(|c| c.max_element() <= 1.0));
    }
}
