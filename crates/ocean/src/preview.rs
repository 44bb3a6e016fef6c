//! Pictures of a patch on its own: false-colour height, slope and foam
//! maps, and a shaded orthographic view of the tiling surface. These are
//! what the `ocean` example writes; they are fixed, simple renderers, not a
//! scene (natura-render places the ocean in a landscape).
//!
//! Every picture has north up: grid row `j` (y increasing northward) is
//! image row `ny − 1 − j`.

use glam::{Vec2, Vec3};
use natura_core::{Grid2, Image, NoProgress, Ramp, ToneMap, preview};

use crate::error::Result;
use crate::foam::Foam;
use crate::frame::Frame;
use crate::optics::WaterShader;
use crate::surface::{Surface, WaterSurface};

/// A grid as an image's rows: north (the last row) at the top.
fn north_up(g: &Grid2<f32>) -> Result<Grid2<f32>> {
    let (w, h) = g.dims();
    Ok(Grid2::from_fn(w, h, |i, r| g[(i, h - 1 - r)])?)
}

/// Height in a diverging ramp symmetric about zero (blue troughs, red crests).
///
/// # Errors
///
/// Returns [`OceanError::Core`](crate::OceanError::Core) only if the image
/// cannot be allocated.
pub fn height_image(frame: &Frame) -> Result<Image> {
    let (lo, hi) = frame.height().min_max();
    let m = lo.abs().max(hi.abs());
    Ok(Image::false_colour(
        &north_up(frame.height())?,
        Ramp::Coolwarm,
        -m,
        m,
    ))
}

/// The x-slope in grey over ±3 standard deviations, as in Tessendorf
/// (2001), *Simulating Ocean Water*, figure 7.
///
/// # Errors
///
/// Returns [`OceanError::Core`](crate::OceanError::Core) only if the image
/// cannot be allocated.
pub fn slope_image(frame: &Frame) -> Result<Image> {
    let s = frame.slope_x();
    let sd = (s.as_slice().iter().map(|v| v * v).sum::<f32>() / s.len() as f32).sqrt();
    Ok(Image::false_colour(
        &north_up(s)?,
        Ramp::Grey,
        -3.0 * sd,
        3.0 * sd,
    ))
}

/// Foam coverage from 0 (none) to 1 in the viridis ramp. Its dark end is a
/// deep blue, not black: over black (the magma ramp's end) the faintest
/// foam, a few thousandths of coverage left by an old whitecap, is one
/// 8-bit level above the open sea yet four times its luminance, and the
/// map reads as a field of specks where the sea is clear.
///
/// # Errors
///
/// Returns [`OceanError::Core`](crate::OceanError::Core) only if the image
/// cannot be allocated.
pub fn foam_image(foam: &Foam) -> Result<Image> {
    Ok(Image::false_colour(
        &north_up(foam.coverage())?,
        Ramp::Viridis,
        0.0,
        1.0,
    ))
}

/// An orthographic view straight down the grid, one pixel per sample,
/// shaded by [`WaterShader`] under a zenith-to-horizon sky gradient, with
/// foam blended over the water. Tone-mapped (ACES filmic) for display.
/// Drawn with natura-core's preview loop ([`natura_core::preview`]).
#[derive(Clone, Debug)]
pub struct TopView {
    /// Direction the camera looks (unit, pointing down into the water).
    /// Default: north and down at 55° from the vertical, so the Fresnel
    /// reflectance varies with the slope.
    pub view: Vec3,
    /// The water's shading; its sun sits behind the waves to the north by
    /// default, giving glitter.
    pub shader: WaterShader,
    /// Sky radiance straight up (linear RGB).
    pub zenith: Vec3,
    /// Sky radiance at the horizon (linear RGB).
    pub horizon: Vec3,
    /// Colour of fully developed foam (linear RGB).
    pub foam_colour: Vec3,
    /// Opacity of full foam cover (0–1).
    pub foam_opacity: f32,
}

impl Default for TopView {
    fn default() -> Self {
        Self {
            view: Vec3::new(0.0, 0.82, -0.57).normalize(),
            shader: WaterShader {
                sun_direction: Vec3::new(-0.55, 0.45, 0.7).normalize(),
                sun_irradiance: Vec3::new(0.5, 0.47, 0.42),
                slope_variance: 0.004,
                ..WaterShader::default()
            },
            zenith: Vec3::new(0.18, 0.36, 0.75),
            horizon: Vec3::new(0.75, 0.85, 0.95),
            foam_colour: Vec3::new(0.85, 0.88, 0.9),
            foam_opacity: 0.9,
        }
    }
}

/// Samples a pixel of [`TopView::render`] takes along each axis.
pub const SUPERSAMPLE: u32 = 2;

impl TopView {
    /// Sky radiance seen in direction `d` (z up): the horizon colour blended
    /// toward the zenith with the square root of the elevation's sine.
    #[must_use]
    pub fn sky(&self, d: Vec3) -> Vec3 {
        self.horizon.lerp(self.zenith, d.z.clamp(0.0, 1.0).sqrt())
    }

    /// Renders `n × n` pixels over `extent` metres of `surface` (which
    /// tiles, so any extent works), [`SUPERSAMPLE`]² samples a pixel
    /// resolved by the camera's pixel filter (natura-core's
    /// `PixelFilter::camera`).
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter)
    /// from [`WaterShader::validate`] and
    /// [`OceanError::Core`](crate::OceanError::Core) for a zero `n` or one
    /// over natura-core's [`MAX_RESOLUTION`](natura_core::camera::MAX_RESOLUTION).
    pub fn render(&self, surface: &Surface, n: usize, extent: Vec2) -> Result<Image> {
        self.shader.validate()?;
        let sky = |d: Vec3| self.sky(d);
        let cell = extent / n.max(1) as f32;
        let side = u32::try_from(n).unwrap_or(u32::MAX);
        let img =
            preview::shade_pixels(side, side, SUPERSAMPLE, "top view", &NoProgress, |x, y| {
                // Image row 0 is the grid's north edge.
                let p = Vec2::new(x as f32, n as f32 - y as f32) * cell;
                let c = self
                    .shader
                    .shade(self.view, surface.normal_at(p), 0.0, Some(&sky));
                let foam = surface.foam_at(p).clamp(0.0, 1.0) * self.foam_opacity;
                c.lerp(self.foam_colour, foam)
            })?;
        Ok(img.tone_mapped(0.0, ToneMap::AcesFilmic))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FoamParams, Ocean, OceanParams, Phillips, Seed};

    fn patch() -> (Ocean, Frame, Foam) {
        let params = OceanParams {
            nx: 32,
            ny: 32,
            lx: 50.0,
            ly: 50.0,
            choppiness: 1.0,
            ..OceanParams::default()
        };
        let spectrum = Phillips {
            wind_speed: 10.0,
            small_wave_length: 0.5,
            ..Phillips::default()
        };
        let ocean = Ocean::new(&params, &spectrum, Seed(3)).unwrap();
        let frame = ocean.evaluate(1.0).unwrap();
        let mut foam = Foam::for_frame(&frame, FoamParams::default()).unwrap();
        foam.update(&frame).unwrap();
        (ocean, frame, foam)
    }

    #[test]
    fn maps_put_north_at_the_top() {
        let (_, frame, _) = patch();
        let img = height_image(&frame).unwrap();
        let h = frame.height();
        let (lo, hi) = h.min_max();
        let m = lo.abs().max(hi.abs());
        // Image row 0 is grid row ny − 1.
        let want = Ramp::Coolwarm.map(h[(5, 31)], -m, m);
        assert_eq!(img.get(5, 0), Some(want));
    }

    #[test]
    fn top_view_is_finite_and_displayable() {
        let (ocean, frame, foam) = patch();
        let surface = Surface::new(&frame, Some(&foam)).unwrap();
        let ext = ocean.extent();
        let img = TopView::default().render(&surface, 24, ext).unwrap();
        assert!(img.first_non_finite().is_none());
        let px = img.pixels().as_slice();
        assert!(
            px.iter()
                .all(|c| c.min_element() >= 0.0 && c.max_element() <= 1.0)
        );
        // Slopes vary the Fresnel reflectance: the picture is not flat.
        let lum: Vec<f32> = px.iter().map(|c| c.x + c.y + c.z).collect();
        let (lo, hi) = lum
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(hi - lo > 0.01, "{lo} {hi}");
    }
}
