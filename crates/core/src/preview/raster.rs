//! Triangle rasterization into a supersampled frame with a z-buffer.

use glam::{Vec2, Vec3};

use super::check_size;
use crate::check::{Checked, ParamError};
use crate::error::Result;
use crate::filter::PixelFilter;
use crate::image::Image;

/// One sample a triangle covers, handed to the shading callback of
/// [`Raster::triangle`] once it has passed the depth test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    /// Sample column in the supersampled frame.
    pub x: usize,
    /// Sample row in the supersampled frame.
    pub y: usize,
    /// Barycentric weights of the triangle's three vertices at the sample
    /// centre (they sum to one).
    pub weights: [f32; 3],
    /// The interpolated depth key (larger is nearer).
    pub depth: f32,
}

impl Fragment {
    /// Interpolates per-vertex values with the barycentric weights,
    /// `v₀·w₀ + v₁·w₁ + v₂·w₂` (an interpolated normal, a Gouraud colour).
    #[inline]
    #[must_use]
    pub fn mix(&self, v: [Vec3; 3]) -> Vec3 {
        let [w0, w1, w2] = self.weights;
        v[0] * w0 + v[1] * w1 + v[2] * w2
    }
}

/// The signed edge function of the line `a → b` at `(x, y)`: twice the
/// signed area of the triangle `a, b, (x, y)` in screen space.
#[inline]
fn edge(a: [f32; 3], b: [f32; 3], x: f32, y: f32) -> f32 {
    (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])
}

/// The edge function evaluated the same way whichever way round the edge
/// is given (endpoints in a fixed order, the sign flipped to match), so two
/// triangles sharing an edge see exactly opposite values.
#[inline]
fn shared_edge(a: [f32; 3], b: [f32; 3], x: f32, y: f32) -> f32 {
    if (a[0], a[1]) <= (b[0], b[1]) {
        edge(a, b, x, y)
    } else {
        -edge(b, a, x, y)
    }
}

/// Whether a sample exactly on the edge `a → b` of a triangle whose area has
/// sign `sign` belongs to it: the tie rule that gives each sample on an
/// edge shared by two triangles to exactly one of them.
#[inline]
fn owns_edge(a: [f32; 3], b: [f32; 3], sign: f32) -> bool {
    let (dx, dy) = (sign * (b[0] - a[0]), sign * (b[1] - a[1]));
    dy > 0.0 || (dy == 0.0 && dx < 0.0)
}

/// A supersampled frame being drawn: a colour and a depth key per sample.
///
/// Triangles are given in screen space (continuous coordinates of the
/// *sample* grid, which is `supersample` times finer than the picture, and a
/// depth key, larger nearer, that is affine in screen space, as
/// [`Projector::project`](super::Projector::project) gives). A sample is
/// covered when its centre lies inside the triangle by the signs of the
/// three edge functions (Pineda 1988, "A Parallel Algorithm for Polygon
/// Rasterization"), each evaluated the same way by both triangles sharing
/// the edge, with a tie rule for centres exactly on an edge (decided by the
/// edge's direction, which the two triangles see opposite ways), so
/// triangles sharing an edge cover each sample once. The nearest triangle wins
/// (ties keep the first), so the picture does not depend on the drawing
/// order except where two surfaces have equal depth.
///
/// ```
/// use natura_core::glam::Vec3;
/// use natura_core::preview::Raster;
/// let mut r = Raster::new(4, 4, 1, Vec3::ZERO)?;
/// // A triangle over the lower-left half of the picture.
/// let n = r.triangle([[0.0, 0.0, 1.0], [0.0, 4.0, 1.0], [4.0, 4.0, 1.0]], |_| Vec3::ONE)?;
/// assert_eq!(n, 10); // the centres on or below the diagonal, each once
/// let img = r.resolve()?;
/// assert_eq!(img.get(0, 3), Some(Vec3::ONE));
/// assert_eq!(img.get(3, 0), Some(Vec3::ZERO));
/// # Ok::<(), natura_core::CoreError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Raster {
    supersample: usize,
    w: usize,
    h: usize,
    depth: Vec<f32>,
    colour: crate::Grid2<Vec3>,
}

impl Raster {
    /// Returns an empty `width × height` picture with `supersample ×
    /// supersample` samples per pixel, every sample `background` and
    /// infinitely far.
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
    /// naming `width`, `height` or `supersample` ([`check_size`]).
    pub fn new(width: u32, height: u32, supersample: u32, background: Vec3) -> Result<Self> {
        check_size(width, height, supersample)?;
        let s = supersample as usize;
        let (w, h) = (width as usize * s, height as usize * s);
        // The sample grid's size through the grid's own allocation check.
        let colour = crate::Grid2::new(w, h, background)?;
        Ok(Self {
            supersample: s,
            w,
            h,
            depth: vec![f32::NEG_INFINITY; w * h],
            colour,
        })
    }

    /// The sample grid's size, `(width · s, height · s)`: the resolution to
    /// project the triangles onto.
    #[must_use]
    pub fn samples(&self) -> (u32, u32) {
        (self.w as u32, self.h as u32)
    }

    /// The colour and depth key of sample `(x, y)`, or `None` outside the
    /// frame. The depth key of a sample no triangle covers is −∞.
    #[must_use]
    pub fn sample(&self, x: usize, y: usize) -> Option<(Vec3, f32)> {
        (x < self.w && y < self.h).then(|| (self.colour[(x, y)], self.depth[y * self.w + x]))
    }

    /// Draws one triangle `v` (screen x, y and depth key per vertex): every
    /// covered sample nearer than what it holds takes the depth key and the
    /// colour `shade(fragment)`. Returns the number of samples written.
    /// Triangles of zero area (or whose area is not a number) draw nothing.
    ///
    /// # Errors
    ///
    /// A [`ParamError`] naming `vertices` if a coordinate is not finite.
    pub fn triangle(
        &mut self,
        v: [[f32; 3]; 3],
        mut shade: impl FnMut(&Fragment) -> Vec3,
    ) -> Checked<usize> {
        if v.iter().flatten().any(|c| !c.is_finite()) {
            let text = format!("{v:?}");
            return Err(ParamError::new("vertices", text, "must be finite"));
        }
        let area = edge(v[0], v[1], v[2][0], v[2][1]);
        if area.is_nan() || area.abs() <= 1e-12 {
            return Ok(0);
        }
        let Some((x0, x1, y0, y1)) = self.bounds(v) else {
            return Ok(0);
        };
        let sign = area.signum();
        let own = [
            owns_edge(v[1], v[2], sign),
            owns_edge(v[2], v[0], sign),
            owns_edge(v[0], v[1], sign),
        ];
        let inside = |e: f32, own: bool| e > 0.0 || (e == 0.0 && own);
        let inv = 1.0 / area;
        let mut written = 0;
        for y in y0..y1 {
            let py = y as f32 + 0.5;
            for x in x0..x1 {
                let px = x as f32 + 0.5;
                let e = [
                    sign * shared_edge(v[1], v[2], px, py),
                    sign * shared_edge(v[2], v[0], px, py),
                    sign * shared_edge(v[0], v[1], px, py),
                ];
                if !(inside(e[0], own[0]) && inside(e[1], own[1]) && inside(e[2], own[2])) {
                    continue;
                }
                let w0 = edge(v[1], v[2], px, py) * inv;
                let w1 = edge(v[2], v[0], px, py) * inv;
                let w2 = 1.0 - w0 - w1;
                let key = w0 * v[0][2] + w1 * v[1][2] + w2 * v[2][2];
                let k = y * self.w + x;
                if key > self.depth[k] {
                    self.depth[k] = key;
                    let f = Fragment {
                        x,
                        y,
                        weights: [w0, w1, w2],
                        depth: key,
                    };
                    self.colour.as_mut_slice()[k] = shade(&f);
                    written += 1;
                }
            }
        }
        Ok(written)
    }

    /// The samples `x0..x1, y0..y1` the triangle's bounding box touches,
    /// clipped to the frame, or `None` if it misses the frame.
    fn bounds(&self, v: [[f32; 3]; 3]) -> Option<(usize, usize, usize, usize)> {
        let lo = |i: usize| {
            v.iter()
                .map(|p| p[i])
                .fold(f32::MAX, f32::min)
                .floor()
                .max(0.0)
        };
        let hi = |i: usize, n: usize| {
            v.iter()
                .map(|p| p[i])
                .fold(f32::MIN, f32::max)
                .ceil()
                .min(n as f32)
        };
        let (x0, x1, y0, y1) = (lo(0), hi(0, self.w), lo(1), hi(1, self.h));
        (x0 < x1 && y0 < y1).then_some((x0 as usize, x1 as usize, y0 as usize, y1 as usize))
    }

    /// The picture: each pixel resolved from the samples by the camera's
    /// pixel filter ([`PixelFilter::camera`]).
    ///
    /// # Errors
    ///
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) only if the image
    /// cannot be allocated.
    pub fn resolve(&self) -> Result<Image> {
        self.resolve_with(PixelFilter::camera())
    }

    /// The picture resolved by `filter` ([`PixelFilter::BOX`]: each pixel
    /// the mean of its `s × s` samples, summed row by row).
    ///
    /// # Errors
    ///
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) only if the image
    /// cannot be allocated.
    pub fn resolve_with(&self, filter: PixelFilter) -> Result<Image> {
        filter.resolve(&self.colour, self.supersample)
    }
}

/// The pixels `(x, y)` of a `width × height` picture whose centres lie in
/// the disc of radius `radius` about `centre` (continuous pixel
/// coordinates, boundary included), row by row.
///
/// ```
/// use natura_core::glam::Vec2;
/// let px: Vec<_> = natura_core::preview::disc_pixels(Vec2::new(2.0, 2.0), 0.75, 8, 8).collect();
/// assert_eq!(px, [(1, 1), (2, 1), (1, 2), (2, 2)]);
/// ```
pub fn disc_pixels(
    centre: Vec2,
    radius: f32,
    width: usize,
    height: usize,
) -> impl Iterator<Item = (usize, usize)> {
    let (cx, cy, r) = (centre.x, centre.y, radius);
    let (x0, x1) = (
        (cx - r).floor().max(0.0) as usize,
        ((cx + r).ceil() as usize).min(width),
    );
    let (y0, y1) = (
        (cy - r).floor().max(0.0) as usize,
        ((cy + r).ceil() as usize).min(height),
    );
    (y0..y1).flat_map(move |y| {
        (x0..x1).filter_map(move |x| {
            let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
            (dx * dx + dy * dy <= r * r).then_some((x, y))
        })
    })
}
