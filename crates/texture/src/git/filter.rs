//! The GIT image filter (Musgrave 1998, "An Impressionistic Image
//! Processing Filter"): a picture enlarged and repainted in brush strokes
//! laid across its lightness gradient, each stroke blurring the picture
//! along itself while adding fractal colour juxtaposition whose spread is
//! the principal components of the colours around it.

use glam::{DMat3, DVec2, DVec3, Vec3};
use natura_core::colour::srgb_encode_rgb;
use natura_core::preview::fill_rows;
use natura_core::{Grid2, Image, Progress};
use natura_noise::VectorField;

use super::ColourEllipsoid;
use crate::error::{Result, invalid, non_negative, positive};
use crate::fractals::{spectral_gain, vfbm};
use crate::multicolor::fold;
use crate::texture::display_to_linear;

/// Parameters of [`git_filter`]. Lengths are in pixels of the input
/// picture.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct GitFilterParams {
    /// Seed of the juxtaposed colour.
    pub seed: u64,
    /// How many output pixels each input pixel becomes along each side,
    /// 1–8 (4; the source enlarges "by a factor of four to eight" to make
    /// room for the added detail).
    pub expand: usize,
    /// Radius of the square neighbourhood whose colours' principal
    /// components shape the juxtaposition, 1–32 (2: 5 × 5 pixels).
    pub window: usize,
    /// Length of a brush stroke, in (0, 32] (5).
    pub stroke_length: f64,
    /// Width of the colour streaks within a stroke, the first wavelength
    /// of their fBm across it, in (0, 8] (0.6).
    pub stroke_width: f64,
    /// Strength of the juxtaposed colour, in standard deviations of the
    /// neighbourhood's colours along each principal axis, in [0, 4] (0.8).
    pub juxtaposition: f64,
    /// Octaves of the juxtaposition's vector fBm, in [1, 8] (3).
    pub octaves: f64,
}

impl Default for GitFilterParams {
    fn default() -> Self {
        Self {
            seed: 0,
            expand: 4,
            window: 2,
            stroke_length: 5.0,
            stroke_width: 0.6,
            juxtaposition: 0.8,
            octaves: 3.0,
        }
    }
}

impl GitFilterParams {
    /// Checks every parameter against the ranges its field documents.
    ///
    /// # Errors
    /// [`TextureError::InvalidParameter`](crate::TextureError::InvalidParameter)
    /// naming the first parameter out of its range or not finite.
    pub fn validate(&self) -> Result<()> {
        if !(1..=8).contains(&self.expand) {
            return Err(invalid("expand", self.expand, "must be in 1..=8"));
        }
        if !(1..=32).contains(&self.window) {
            return Err(invalid("window", self.window, "must be in 1..=32"));
        }
        let up_to = |name, v: f64, hi: f64| {
            positive(name, v)?;
            if v > hi {
                return Err(invalid(name, v, "is above its largest value"));
            }
            Ok(())
        };
        up_to("stroke_length", self.stroke_length, 32.0)?;
        up_to("stroke_width", self.stroke_width, 8.0)?;
        non_negative("juxtaposition", self.juxtaposition)?;
        if self.juxtaposition > 4.0 {
            return Err(invalid(
                "juxtaposition",
                self.juxtaposition,
                "must be at most 4",
            ));
        }
        if !(1.0..=8.0).contains(&self.octaves) {
            return Err(invalid("octaves", self.octaves, "must be in [1, 8]"));
        }
        Ok(())
    }
}

/// Repaints `image` in GIT brush strokes (Musgrave 1998, "An
/// Impressionistic Image Processing Filter"), returning a picture
/// [`GitFilterParams::expand`] times larger along each side.
///
/// The picture is taken as displayed (its linear values sRGB-encoded, each
/// channel shown within `[0, 1]` as a display shows it), and:
///
/// 1. around each pixel, the mean and covariance of the colours in its
///    neighbourhood give a [`ColourEllipsoid`] (the Hotelling transform of
///    the source; its matrix is taken as the covariance's symmetric square
///    root, so it interpolates smoothly between pixels);
/// 2. the lightness gradient's structure tensor (Sobel derivatives,
///    smoothed over 2 pixels) orients the strokes across the gradient:
///    a picture fading from dark below to light above gets horizontal
///    strokes, as in the source, and so do flat areas;
/// 3. each output pixel is the mean of the picture along its stroke (a
///    line-integral convolution over `stroke_length`, after Cabral and
///    Leedom 1993, which the source cites), plus the stroke's juxtaposed
///    colour: vector fBm across the stroke, averaged along it the same way
///    so it streaks, scaled to unit variance and taken through the
///    neighbourhood's ellipsoid times `juxtaposition`;
/// 4. colours leaving the RGB cube are reflected back into it, as for the
///    solid texture.
///
/// The source leaves the strokes' model open ("we never spent much time on
/// the model for the brush strokes"); the above is natura's. Rows run in
/// parallel, each alone, so the result does not depend on the number of
/// threads.
///
/// ```
/// use natura_core::{Image, NoProgress};
/// use natura_texture::git::{GitFilterParams, git_filter};
/// use natura_texture::glam::Vec3;
/// // A picture dark below and light above.
/// let image = Image::from_fn(16, 12, |_, y| Vec3::splat(0.8 - y as f32 * 0.05))?;
/// let p = GitFilterParams { expand: 2, ..GitFilterParams::default() };
/// let out = git_filter(&image, &p, &NoProgress)?;
/// assert_eq!((out.width(), out.height()), (32, 24));
/// # Ok::<(), natura_texture::TextureError>(())
/// ```
///
/// # Errors
/// [`GitFilterParams::validate`]'s; `image` as an invalid parameter when a
/// pixel is NaN or infinite; an output too large to allocate
/// ([`natura_core::CoreError::TooLarge`]).
pub fn git_filter(
    image: &Image,
    params: &GitFilterParams,
    progress: &dyn Progress,
) -> Result<Image> {
    params.validate()?;
    if let Some((x, y)) = image.first_non_finite() {
        return Err(invalid(
            "image",
            format!("pixel ({x}, {y})"),
            "must be finite",
        ));
    }
    let (w, h) = (image.width(), image.height());
    let e = params.expand;
    // The output's size is checked before any work.
    let mut out = Grid2::new(w * e, h * e, Vec3::ZERO)?;
    let display: Vec<DVec3> = image
        .pixels()
        .as_slice()
        .iter()
        .map(|&c| srgb_encode_rgb(c.clamp(Vec3::ZERO, Vec3::ONE)).as_dvec3())
        .collect();
    let spread = neighbourhood_spreads(&display, w, h, params.window);
    let tensor = structure_tensor(&display, w, h);

    // The juxtaposition's streaks: vector fBm on the output grid, averaged
    // along the strokes, then scaled to unit variance.
    let fbm = vfbm(
        params.seed,
        "git filter",
        spectral_gain(0.5, 2.0, params.octaves),
    )?;
    let inv = 1.0 / (e as f64 * params.stroke_width);
    let mut noise = Grid2::new(w * e, h * e, Vec3::ZERO)?;
    fill_rows(&mut noise, "GIT filter: colour", progress, |y, row| {
        for (x, v) in row.iter_mut().enumerate() {
            let p = DVec3::new(x as f64 * inv, y as f64 * inv, 0.5);
            *v = fbm.eval3(p).as_vec3();
        }
    });
    let field = Field {
        display: &display,
        spread: &spread,
        tensor: &tensor,
        noise: &noise,
        w,
        h,
        e,
    };
    let steps = (params.stroke_length * 0.5 * e as f64).round().max(1.0) as usize;
    // A Hann window over the stroke.
    let hann: Vec<f64> = (0..=steps)
        .map(|k| 0.5 + 0.5 * (std::f64::consts::PI * k as f64 / (steps + 1) as f64).cos())
        .collect();
    let mut strokes = Grid2::new(w * e, h * e, [Vec3::ZERO; 2])?;
    fill_rows(&mut strokes, "GIT filter: strokes", progress, |y, row| {
        for (x, s) in row.iter_mut().enumerate() {
            let (c, n) = field.stroke(x, y, &hann);
            *s = [c.as_vec3(), n.as_vec3()];
        }
    });
    // Unit variance per component, summed in row order.
    let mut sum2 = DVec3::ZERO;
    for s in strokes.as_slice() {
        let n = s[1].as_dvec3();
        sum2 += n * n;
    }
    let count = (w * e * h * e) as f64;
    let scale =
        DVec3::splat(params.juxtaposition) / (sum2 / count).max(DVec3::splat(1e-300)).sqrt();
    fill_rows(&mut out, "GIT filter: paint", progress, |y, row| {
        for (x, px) in row.iter_mut().enumerate() {
            let [c, n] = strokes[(x, y)];
            let u = field.input_at(x, y);
            let s = field.spread_at(u);
            let v = c.as_dvec3() + s * (n.as_dvec3() * scale);
            *px = display_to_linear(DVec3::new(fold(v.x), fold(v.y), fold(v.z))).as_vec3();
        }
    });
    Ok(Image::from_grid(out))
}

/// The per-pixel inputs of the strokes.
struct Field<'a> {
    display: &'a [DVec3],
    spread: &'a [DMat3],
    /// Structure tensor `(Jxx, Jxy, Jyy)` per input pixel.
    tensor: &'a [DVec3],
    noise: &'a Grid2<Vec3>,
    w: usize,
    h: usize,
    e: usize,
}

impl Field<'_> {
    /// The input coordinate (pixel centres at integers) of output pixel `(x, y)`.
    fn input_at(&self, x: usize, y: usize) -> DVec2 {
        let e = self.e as f64;
        DVec2::new((x as f64 + 0.5) / e - 0.5, (y as f64 + 0.5) / e - 0.5)
    }

    /// Bilinear weights and the four pixels around input coordinate `u`,
    /// clamped to the picture.
    fn corners(&self, u: DVec2) -> [(usize, f64); 4] {
        let x = u.x.clamp(0.0, (self.w - 1) as f64);
        let y = u.y.clamp(0.0, (self.h - 1) as f64);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.w - 1), (y0 + 1).min(self.h - 1));
        let (fx, fy) = (x - x0 as f64, y - y0 as f64);
        [
            (y0 * self.w + x0, (1.0 - fx) * (1.0 - fy)),
            (y0 * self.w + x1, fx * (1.0 - fy)),
            (y1 * self.w + x0, (1.0 - fx) * fy),
            (y1 * self.w + x1, fx * fy),
        ]
    }

    #[cfg(test)]
    fn colour_at(&self, u: DVec2) -> DVec3 {
        self.corners(u)
            .iter()
            .map(|&(i, f)| self.display[i] * f)
            .sum()
    }

    fn spread_at(&self, u: DVec2) -> DMat3 {
        self.corners(u)
            .iter()
            .fold(DMat3::ZERO, |m, &(i, f)| m + self.spread[i] * f)
    }

    /// The stroke's direction at `u`: across the lightness gradient.
    #[cfg(test)]
    fn direction_at(&self, u: DVec2) -> DVec2 {
        self.direction_of(&self.corners(u))
    }

    /// The stroke's direction from the tensor interpolated over `corners`:
    /// the gradient's orientation φ is half the angle of
    /// `(Jxx − Jyy, 2Jxy)`, taken by the half-angle formulas (φ in
    /// (−π/2, π/2], as `atan2` would give it), and the stroke runs at φ + π/2.
    fn direction_of(&self, corners: &[(usize, f64); 4]) -> DVec2 {
        let j: DVec3 = corners.iter().map(|&(i, f)| self.tensor[i] * f).sum();
        let (a, b) = (j.x - j.z, 2.0 * j.y);
        let r = (a * a + b * b).sqrt();
        if r == 0.0 {
            return DVec2::Y;
        }
        // cos φ = √((r + a)/2r), sin φ = ±√((r − a)/2r), the larger first
        // and the other from sin 2φ = b/r without cancellation.
        let (sin, cos) = if a >= 0.0 {
            let c = ((r + a) / (2.0 * r)).sqrt();
            (b / (2.0 * r * c), c)
        } else {
            let s = b.signum() * ((r - a) / (2.0 * r)).sqrt();
            (s, b / (2.0 * r * s))
        };
        DVec2::new(-sin, cos)
    }

    /// The noise of the output grid at output coordinate `q`, bilinear.
    fn noise_at(&self, q: DVec2) -> DVec3 {
        let (w, h) = self.noise.dims();
        self.noise
            .sample_bilinear(
                q.x.clamp(0.0, (w - 1) as f64) as f32,
                q.y.clamp(0.0, (h - 1) as f64) as f32,
                natura_core::Boundary::Clamp,
            )
            .as_dvec3()
    }

    /// The picture's colour and the streaked noise averaged along the
    /// stroke through output pixel `(x, y)`: `hann.len() − 1` steps of one
    /// output pixel each way, step `k` weighted by `hann[k]`.
    fn stroke(&self, x: usize, y: usize, hann: &[f64]) -> (DVec3, DVec3) {
        let e = self.e as f64;
        let start = self.input_at(x, y);
        let (mut colour, mut noise, mut weight) = (DVec3::ZERO, DVec3::ZERO, 0.0);
        // Adds the step at `u` with weight `f`; returns the stroke's
        // direction there (one interpolation of the picture for both).
        let mut add = |u: DVec2, f: f64| {
            let corners = self.corners(u);
            let c: DVec3 = corners.iter().map(|&(i, w)| self.display[i] * w).sum();
            colour += c * f;
            noise += self.noise_at((u + 0.5) * e - 0.5) * f;
            weight += f;
            self.direction_of(&corners)
        };
        let first = add(start, hann[0]);
        for sign in [1.0, -1.0] {
            let (mut u, mut d) = (start, first * sign);
            for &f in &hann[1..] {
                u += d / e;
                let next = add(u, f);
                // Orientations are axial: keep walking the same way.
                d = if next.dot(d) < 0.0 { -next } else { next };
            }
        }
        (colour / weight, noise / weight)
    }
}

/// Per pixel, the symmetric square root of the covariance of the colours
/// within `r` pixels (a square window clipped to the picture), from
/// summed-area tables of the colours and their products.
fn neighbourhood_spreads(c: &[DVec3], w: usize, h: usize, r: usize) -> Vec<DMat3> {
    // Sums of (r, g, b) and of (rr, gg, bb) and (rg, rb, gb).
    let mut table = vec![[DVec3::ZERO; 3]; (w + 1) * (h + 1)];
    for y in 0..h {
        let mut row = [DVec3::ZERO; 3];
        for x in 0..w {
            let v = c[y * w + x];
            row[0] += v;
            row[1] += v * v;
            row[2] += DVec3::new(v.x * v.y, v.x * v.z, v.y * v.z);
            let above = table[y * (w + 1) + x + 1];
            table[(y + 1) * (w + 1) + x + 1] = [0, 1, 2].map(|k| above[k] + row[k]);
        }
    }
    let at = |x: usize, y: usize| table[y * (w + 1) + x];
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let (x0, x1) = (x.saturating_sub(r), (x + r + 1).min(w));
            let (y0, y1) = (y.saturating_sub(r), (y + r + 1).min(h));
            let n = ((x1 - x0) * (y1 - y0)) as f64;
            let (a, b, cc, d) = (at(x1, y1), at(x0, y1), at(x1, y0), at(x0, y0));
            let s = [0, 1, 2].map(|k| (a[k] - b[k] - cc[k] + d[k]) / n);
            let m = s[0];
            let (sq, cross) = (
                s[1] - m * m,
                s[2] - DVec3::new(m.x * m.y, m.x * m.z, m.y * m.z),
            );
            let cov = DMat3::from_cols(
                DVec3::new(sq.x, cross.x, cross.y),
                DVec3::new(cross.x, sq.y, cross.z),
                DVec3::new(cross.y, cross.z, sq.z),
            );
            let el = ColourEllipsoid::of_covariance(m, cov);
            // A·diag(σ)·Aᵀ: the symmetric square root.
            el.spread() * DMat3::from_cols(el.axes[0], el.axes[1], el.axes[2]).transpose()
        })
        .collect()
}

/// The structure tensor `(Jxx, Jxy, Jyy)` of the display lightness (Rec.
/// 709 weights on the display values): Sobel derivatives, their products
/// smoothed by a Gaussian of σ = 2 pixels, plus 10⁻⁹ on `Jyy` so that a
/// flat area counts as lit from above and gets horizontal strokes.
fn structure_tensor(c: &[DVec3], w: usize, h: usize) -> Vec<DVec3> {
    let lum: Vec<f64> = c
        .iter()
        .map(|v| v.dot(DVec3::new(0.2126, 0.7152, 0.0722)))
        .collect();
    let at = |x: isize, y: isize| {
        let x = x.clamp(0, w as isize - 1) as usize;
        let y = y.clamp(0, h as isize - 1) as usize;
        lum[y * w + x]
    };
    let raw: Vec<DVec3> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            let gx = (at(x + 1, y - 1) + 2.0 * at(x + 1, y) + at(x + 1, y + 1))
                - (at(x - 1, y - 1) + 2.0 * at(x - 1, y) + at(x - 1, y + 1));
            let gy = (at(x - 1, y + 1) + 2.0 * at(x, y + 1) + at(x + 1, y + 1))
                - (at(x - 1, y - 1) + 2.0 * at(x, y - 1) + at(x + 1, y - 1));
            DVec3::new(gx * gx, gx * gy, gy * gy)
        })
        .collect();
    let kernel: Vec<f64> = (-6i32..=6)
        .map(|k| (-(f64::from(k) * f64::from(k)) / (2.0 * 2.0 * 2.0)).exp())
        .collect();
    let total: f64 = kernel.iter().sum();
    let blur = |src: &[DVec3], dx: isize, dy: isize| -> Vec<DVec3> {
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as isize, (i / w) as isize);
                kernel
                    .iter()
                    .enumerate()
                    .map(|(k, &f)| {
                        let o = k as isize - 6;
                        let xx = (x + o * dx).clamp(0, w as isize - 1) as usize;
                        let yy = (y + o * dy).clamp(0, h as isize - 1) as usize;
                        src[yy * w + xx] * f
                    })
                    .sum::<DVec3>()
                    / total
            })
            .collect()
    };
    blur(&blur(&raw, 1, 0), 0, 1)
        .into_iter()
        .map(|j| j + DVec3::new(0.0, 0.0, 1e-9))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::NoProgress;

    fn filter(image: &Image, p: GitFilterParams) -> Image {
        git_filter(image, &p, &NoProgress).unwrap()
    }

    /// `run` on the strokes' inputs over a `w × h` picture of colours
    /// `display` and tensors `tensor`, enlarged `e` times, with no spread
    /// and no noise.
    fn with_field<R>(
        display: &[DVec3],
        tensor: &[DVec3],
        (w, h, e): (usize, usize, usize),
        run: impl FnOnce(&Field<'_>) -> R,
    ) -> R {
        let spread = vec![DMat3::ZERO; w * h];
        let noise = Grid2::new(w * e, h * e, Vec3::ZERO).unwrap();
        run(&Field {
            display,
            spread: &spread,
            tensor,
            noise: &noise,
            w,
            h,
            e,
        })
    }

    fn encoded(image: &Image, x: usize, y: usize) -> DVec3 {
        srgb_encode_rgb(image.get(x, y).unwrap()).as_dvec3()
    }

    #[test]
    fn a_flat_picture_stays_flat_and_gets_horizontal_strokes() {
        let grey = Vec3::splat(0.2);
        let image = Image::new(12, 10, grey).unwrap();
        let out = filter(&image, GitFilterParams::default());
        assert_eq!((out.width(), out.height()), (48, 40));
        // No colour variation around any pixel: no juxtaposition at all.
        for c in out.pixels().as_slice() {
            assert!((*c - grey).abs().max_element() < 1e-4, "{c:?}");
        }
        let display = vec![DVec3::splat(0.5); 12 * 10];
        let t = structure_tensor(&display, 12, 10);
        let d = with_field(&display, &t, (12, 10, 4), |f| {
            f.direction_at(DVec2::new(5.0, 5.0))
        });
        assert!(d.x.abs() > 0.999, "{d:?}");
    }

    #[test]
    fn the_half_angle_direction_is_the_trigonometric_one() {
        // The stroke at φ + π/2 for φ = ½·atan2(2Jxy, Jxx − Jyy), over
        // tensors of every orientation, signed zeros included.
        let mut tensors = vec![DVec3::new(1.0, 0.0, 2.0), DVec3::new(1.0, -0.0, 2.0)];
        for k in 0..500 {
            let t = f64::from(k);
            let (a, b) = ((t * 0.37).sin(), (t * 0.71).cos());
            tensors.push(DVec3::new(
                a * a + 0.1 * b.abs(),
                a * b,
                b * b * (1.0 + 0.3 * a),
            ));
        }
        for j in tensors {
            let got = with_field(&[DVec3::ZERO], &[j], (1, 1, 1), |f| {
                f.direction_at(DVec2::ZERO)
            });
            // The tensor as interpolated: a sum from zero (so −0 is +0).
            let j = DVec3::ZERO + j;
            let phi = 0.5 * (2.0 * j.y).atan2(j.x - j.z);
            let want = DVec2::new(-phi.sin(), phi.cos());
            assert!((got - want).length() < 1e-12, "{j}: {got} against {want}");
        }
    }

    #[test]
    fn strokes_run_across_the_gradient() {
        // Light increasing to the right: strokes vertical.
        let image = Image::from_fn(24, 24, |x, _| Vec3::splat(x as f32 / 24.0)).unwrap();
        let display: Vec<DVec3> = image
            .pixels()
            .as_slice()
            .iter()
            .map(|&c| srgb_encode_rgb(c).as_dvec3())
            .collect();
        let t = structure_tensor(&display, 24, 24);
        with_field(&display, &t, (24, 24, 4), |f| {
            let d = f.direction_at(DVec2::new(12.0, 12.0));
            assert!(d.y.abs() > 0.999, "{d:?}");
            // Averaging along a vertical stroke keeps a horizontal ramp: the
            // stroke blurs along itself only.
            let hann = [1.0; 9];
            let (c, _) = f.stroke(48, 48, &hann);
            assert!(
                (c - f.colour_at(f.input_at(48, 48))).length() < 1e-9,
                "{c:?}"
            );
        });
    }

    #[test]
    fn the_juxtaposition_follows_the_neighbourhoods_principal_axis() {
        // A picture whose colours vary only from blue to yellow: the added
        // colour must vary along that axis alone.
        let axis = DVec3::new(1.0, 1.0, -1.0).normalize();
        let image = Image::from_fn(32, 32, |x, y| {
            let t = (((x * 7 + y * 13) % 11) as f64 / 10.0 - 0.5) * 0.3;
            let d = DVec3::splat(0.5) + axis * t;
            crate::texture::display_to_linear(d).as_vec3()
        })
        .unwrap();
        let out = filter(&image, GitFilterParams::default());
        let (mut along, mut across) = (0.0, 0.0);
        let mean = DVec3::splat(0.5);
        for y in 20..100 {
            for x in 20..100 {
                let d = encoded(&out, x, y) - mean;
                along += d.dot(axis).abs();
                across += d.cross(axis).length();
            }
        }
        assert!(along > 20.0 * across, "along {along}, across {across}");
    }

    #[test]
    fn the_result_does_not_depend_on_the_thread_count() {
        let image = Image::from_fn(20, 14, |x, y| {
            Vec3::new(x as f32 / 20.0, y as f32 / 14.0, ((x * y) % 5) as f32 / 5.0)
        })
        .unwrap();
        let p = GitFilterParams::default();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| filter(&image, p));
        let many = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap()
            .install(|| filter(&image, p));
        assert_eq!(one.pixels().as_slice(), many.pixels().as_slice());
        // And a different seed paints different strokes.
        let other = filter(&image, GitFilterParams { seed: 9, ..p });
        assert_ne!(one.pixels().as_slice(), other.pixels().as_slice());
    }

    #[test]
    fn bad_input_is_refused_by_name() {
        let image = Image::new(4, 4, Vec3::splat(0.5)).unwrap();
        let name = |p: GitFilterParams| match git_filter(&image, &p, &NoProgress) {
            Err(crate::TextureError::InvalidParameter { name, .. }) => name,
            other => panic!("{other:?}"),
        };
        let d = GitFilterParams::default();
        assert_eq!(name(GitFilterParams { expand: 0, ..d }), "expand");
        assert_eq!(name(GitFilterParams { expand: 9, ..d }), "expand");
        assert_eq!(name(GitFilterParams { window: 0, ..d }), "window");
        assert_eq!(
            name(GitFilterParams {
                stroke_length: f64::NAN,
                ..d
            }),
            "stroke_length"
        );
        assert_eq!(
            name(GitFilterParams {
                stroke_length: 33.0,
                ..d
            }),
            "stroke_length"
        );
        assert_eq!(
            name(GitFilterParams {
                stroke_width: 0.0,
                ..d
            }),
            "stroke_width"
        );
        assert_eq!(
            name(GitFilterParams {
                juxtaposition: -1.0,
                ..d
            }),
            "juxtaposition"
        );
        assert_eq!(
            name(GitFilterParams {
                juxtaposition: 5.0,
                ..d
            }),
            "juxtaposition"
        );
        assert_eq!(name(GitFilterParams { octaves: 0.5, ..d }), "octaves");
        let mut bad = image.clone();
        assert!(bad.set(1, 2, Vec3::new(0.0, f32::NAN, 0.0)));
        match git_filter(&bad, &d, &NoProgress) {
            Err(crate::TextureError::InvalidParameter { name: "image", .. }) => {}
            other => panic!("{other:?}"),
        }
    }
}
