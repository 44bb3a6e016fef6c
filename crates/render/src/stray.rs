//! Stray pixels: isolated bright pixels a viewer reads as specks (a sun
//! glint caught by one sample, a firefly of the sampling, a gap in a
//! surface). The test is local and scale-free: a pixel is stray when its
//! luminance exceeds [`STRAY_RATIO`] times the median luminance `m` of the
//! 5 × 5 pixels around it (itself included) while none of its eight
//! neighbours exceeds `STRAY_RATIO · m`. Real highlights larger than a
//! pixel (a glitter path, a lit ridge) have bright neighbours and are not
//! counted.
//!
//! The neighbours are held to the pixel's own background `m`, not each to
//! its own neighbourhood's median: a speck is bright against one
//! background, alone. Held each to its own median, a neighbour inside a
//! wide bright feature is "not bright" (its median is the feature), and
//! the feature's dimmer edge pixel, whose median is still the dark field
//! beside it, was counted as a speck although the neighbours beside it
//! are brighter than it: the edges of anti-aliased lines over a dark
//! field, the rims of lit shapes.
//!
//! What the test cannot tell from a speck: a real feature of a pixel's
//! size whose contrast is moderate. Under the camera's pixel filter
//! (natura-core's `PixelFilter::camera`, σ = 0.5 pixel) a lit square one
//! pixel wide keeps 0.48 of its light in its own pixel and lends 0.11 to
//! each side; over a background `b`, its pixel passes the ratio once its
//! excess over `b` exceeds 6.2 `b` and its neighbours only above 28 `b`,
//! so a feature between the two (a lit crown tip in shade, a faint star in
//! a dark sky, a floret's highlight) is counted. A wider blur does not
//! close the window but moves it: at σ = 1 pixel the square lights a
//! third of the 5 × 5 pixels, and their median rises with it (by a sixth
//! of its pixel's excess), so its pixel passes the ratio above 56 `b` and
//! its neighbours, at 0.63 of the pixel, never do: every such feature
//! brighter than that is counted, however bright. Only from σ ≈ 1.2
//! pixels, twice and more a camera's, is none (a star field drawn so is a
//! field of soft discs). A count of 0 is reached where the specks are the
//! sampling's (aliasing, fireflies), not where they are the scene's.

use natura_core::Image;
use natura_core::colour::luminance;

/// How many times brighter than its neighbourhood's median a stray pixel is.
pub const STRAY_RATIO: f32 = 4.0;

/// The pixels `(x, y)` of `image` that are stray (see the module docs), in
/// row order. `image` holds linear colours: best the picture as shown
/// (exposed and tone-mapped, or an 8-bit picture decoded to linear), whose
/// contrasts are the viewer's; the luminance is Rec. 709's. Pixels within
/// two of the border see the border pixels repeated in the median; a
/// border pixel's neighbours are those inside the picture.
#[must_use]
pub fn stray_pixels(image: &Image) -> Vec<(usize, usize)> {
    let (w, h) = (image.width(), image.height());
    if w == 0 || h == 0 {
        return Vec::new();
    }
    let px = image.pixels();
    let lum: Vec<f32> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| luminance(px[(x, y)]))
        .collect();
    let at = |x: isize, y: isize| {
        let (x, y) = (x.clamp(0, w as isize - 1), y.clamp(0, h as isize - 1));
        lum[y as usize * w + x as usize]
    };
    let median = |x: isize, y: isize| {
        let mut v = [0.0f32; 25];
        for (k, s) in v.iter_mut().enumerate() {
            *s = at(x + (k % 5) as isize - 2, y + (k / 5) as isize - 2);
        }
        v.sort_unstable_by(f32::total_cmp);
        v[12]
    };
    let mut out = Vec::new();
    for y in 0..h as isize {
        for x in 0..w as isize {
            let level = STRAY_RATIO * median(x, y);
            if at(x, y) <= level {
                continue;
            }
            let lonely = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (x + dx, y + dy)))
                .filter(|&(nx, ny)| (nx, ny) != (x, y))
                .filter(|&(nx, ny)| (0..w as isize).contains(&nx) && (0..h as isize).contains(&ny))
                .all(|(nx, ny)| at(nx, ny) <= level);
            if lonely {
                out.push((x as usize, y as usize));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn finds_a_lone_speck_but_not_a_blob_or_a_texture() {
        let grey = Vec3::splat(0.1);
        let mut img = Image::new(16, 12, grey).unwrap();
        assert!(stray_pixels(&img).is_empty());
        img.set(5, 4, Vec3::splat(0.5));
        assert_eq!(stray_pixels(&img), vec![(5, 4)]);
        // Just below the ratio: not stray.
        img.set(5, 4, Vec3::splat(0.39));
        assert!(stray_pixels(&img).is_empty());
        // Two bright pixels side by side are a feature, not a speck.
        img.set(5, 4, Vec3::splat(0.5));
        img.set(6, 4, Vec3::splat(0.5));
        assert!(stray_pixels(&img).is_empty());
        // A speck at the corner is found too.
        img.set(0, 0, Vec3::splat(1.0));
        assert_eq!(stray_pixels(&img), vec![(0, 0)]);
        // Stripes a pixel wide are texture: the median is the bright value.
        let cb = Image::from_fn(9, 9, |x, _| {
            if x % 2 == 0 {
                Vec3::ONE
            } else {
                Vec3::splat(0.01)
            }
        })
        .unwrap();
        assert!(stray_pixels(&cb).is_empty());
    }

    /// A lit square one pixel wide, `excess` times brighter than the
    /// background `b`, blurred by a Gaussian of `sigma` pixels, in the
    /// middle of a 15 × 15 picture; whether the detector counts it.
    fn blurred_square_is_counted(sigma: f32, excess: f32) -> bool {
        let b = 0.01;
        // The filter's weight on the square from a pixel `d` pixels off:
        // the Gaussian over the square's width (the midpoint rule).
        let w = |d: i32| -> f32 {
            (0..1000)
                .map(|k| {
                    let x = d as f32 - (k as f32 + 0.5) / 1000.0 + 0.5;
                    (-0.5 * (x / sigma).powi(2)).exp()
                })
                .sum::<f32>()
                / 1000.0
                / (sigma * std::f32::consts::TAU.sqrt())
        };
        let img = Image::from_fn(15, 15, |x, y| {
            let (dx, dy) = (x as i32 - 7, y as i32 - 7);
            Vec3::splat(b + excess * b * w(dx) * w(dy))
        })
        .unwrap();
        stray_pixels(&img).contains(&(7, 7))
    }

    #[test]
    fn a_wider_blur_moves_the_window_of_a_pixel_wide_feature() {
        // The camera's σ = 0.5: counted between 6.2 b and 28 b.
        assert!(!blurred_square_is_counted(0.5, 5.5));
        assert!(blurred_square_is_counted(0.5, 7.0));
        assert!(blurred_square_is_counted(0.5, 26.0));
        assert!(!blurred_square_is_counted(0.5, 30.0));
        // σ = 1: from 56 b on, however bright (the median rises with it).
        assert!(!blurred_square_is_counted(1.0, 50.0));
        assert!(blurred_square_is_counted(1.0, 60.0));
        assert!(blurred_square_is_counted(1.0, 1e4));
        // σ = 1.2: never.
        for excess in [3.0, 10.0, 30.0, 100.0, 1e3, 1e4] {
            assert!(!blurred_square_is_counted(1.2, excess), "{excess}");
        }
    }

    #[test]
    fn the_dim_edge_of_a_bright_shape_is_not_a_speck() {
        // A bright half-plane (x + y ≤ 11) over a dark field, and at (6, 6)
        // one edge pixel dimmer than the shape: its own median is the dark
        // field, and three of its neighbours are the shape. Held each to
        // its own median, those neighbours were "not bright" and the edge
        // pixel was counted.
        let dark = Vec3::splat(0.02);
        let mut img =
            Image::from_fn(13, 13, |x, y| if x + y <= 11 { Vec3::ONE } else { dark }).unwrap();
        img.set(6, 6, Vec3::splat(0.2));
        assert!(stray_pixels(&img).is_empty());
        // Alone in the dark field, the same pixel is a speck.
        let mut alone = Image::new(13, 13, dark).unwrap();
        alone.set(6, 6, Vec3::splat(0.2));
        assert_eq!(stray_pixels(&alone), vec![(6, 6)]);
    }
}
