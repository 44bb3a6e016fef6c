//! Pictures of a texture on its own: on a sphere, on a plane, and as water
//! (natura-core's `Image::contact_sheet` lays several out). These are what the examples write; they are
//! simple fixed renderers, not a scene description, drawn with natura-core's
//! preview loop ([`natura_core::preview::shade_pixels`]: [`SUPERSAMPLE`]²
//! samples a pixel resolved by the camera's pixel filter, rows in
//! parallel, the same bits on any number of threads).

use glam::DVec3;
use natura_core::{Image, Progress, preview};

use crate::error::{Result, TextureError, positive};
use crate::footprint::Footprint;
use crate::normal::bump;
use crate::texture::{SolidTexture, TextureKind};
use crate::view::View;

/// The light of the swatches: upper left, slightly in front.
const LIGHT: DVec3 = DVec3::new(-0.5, -0.55, 0.67);
/// Samples a swatch's pixel takes along each axis (resolved by the
/// camera's pixel filter, natura-core's `PixelFilter::camera`).
pub const SUPERSAMPLE: u32 = 3;
/// The dark blue behind densities (clouds, rings) and around spheres.
const BACKDROP: DVec3 = DVec3::new(0.02, 0.035, 0.08);

fn check_size(size: u32) -> Result<()> {
    if size == 0 || size > natura_core::camera::MAX_RESOLUTION {
        return Err(TextureError::InvalidSize {
            name: "size",
            value: size as usize,
            reason: format!(
                "must be between 1 and {}",
                natura_core::camera::MAX_RESOLUTION
            ),
        });
    }
    Ok(())
}

/// How a sample looks under the swatch light with surface normal `n`.
fn look(texture: &dyn SolidTexture, p: DVec3, n: DVec3, fp: Footprint, emissive: bool) -> DVec3 {
    let l = LIGHT.normalize();
    let s = texture.sample(p, fp);
    match texture.kind() {
        TextureKind::Colour if emissive => s.colour,
        TextureKind::Colour => s.colour * (0.15 + 0.85 * n.dot(l).max(0.0)),
        TextureKind::Density => {
            let lit = s.colour * (0.25 + 0.75 * n.dot(l).max(0.0));
            BACKDROP.lerp(lit, s.opacity)
        }
        TextureKind::Height | TextureKind::ColourAndHeight => {
            let nb = bump(n, texture.height_gradient(p, fp));
            s.colour * (0.15 + 0.85 * nb.dot(l).max(0.0))
        }
    }
}

/// The texture on the unit sphere, seen orthographically in a `size ×
/// size` image ([`SUPERSAMPLE`]² samples a pixel, each with the pixel's
/// footprint), lit from the upper left; densities are shown over a dark blue backdrop. Emissive
/// textures (fire) are shown unlit when `emissive` is set.
///
/// # Errors
/// [`TextureError::InvalidSize`] for a zero or oversize `size`.
pub fn sphere(
    texture: &dyn SolidTexture,
    size: u32,
    emissive: bool,
    progress: &dyn Progress,
) -> Result<Image> {
    // The hemisphere facing the viewer, who looks along +y with z up.
    sphere_from(texture, size, emissive, DVec3::NEG_Y, progress)
}

/// The texture on the unit sphere as [`sphere`] draws it, seen from the
/// direction `eye` (from the centre towards the viewer; [`sphere`] is
/// `eye = −y`): a texture whose feature sits at a pole (the cyclone's eye)
/// can be seen from above it. The image's up is the projection of +z (of +y
/// when looking along the z axis).
///
/// # Errors
/// [`TextureError::InvalidSize`] for a zero or oversize `size`;
/// [`TextureError::InvalidParameter`] naming `eye` if it is zero or not finite.
pub fn sphere_from(
    texture: &dyn SolidTexture,
    size: u32,
    emissive: bool,
    eye: DVec3,
    progress: &dyn Progress,
) -> Result<Image> {
    check_size(size)?;
    let toward = eye
        .try_normalize()
        .ok_or_else(|| crate::error::invalid("eye", eye, "must be finite and non-zero"))?;
    let hint = if toward.z.abs() > 0.999 {
        DVec3::Y
    } else {
        DVec3::Z
    };
    let right = hint.cross(toward).normalize();
    let up = toward.cross(right);
    let px = 2.2 / f64::from(size);
    let fp = Footprint::new(px).unwrap_or(Footprint::POINT);
    let image =
        preview::shade_pixels(size, size, SUPERSAMPLE, texture.name(), progress, |x, y| {
            let (u, v) = (x * px - 1.1, 1.1 - y * px);
            let r2 = u * u + v * v;
            let c = if r2 < 1.0 {
                let n = right * u + up * v + toward * (1.0 - r2).sqrt();
                look(texture, n, n, fp, emissive)
            } else {
                BACKDROP
            };
            c.as_vec3()
        })?;
    Ok(image)
}

/// Which plane a [`plane`] swatch shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Plane {
    /// The horizontal plane `z = 0.37`, seen from above.
    Horizontal,
    /// The vertical plane `y = 0.37` from `z = 0` up, seen from −y (for fire).
    Vertical,
}

/// The texture on a plane square of side `extent` (texture units), seen
/// straight on in a `size × size` image.
///
/// # Errors
/// [`TextureError::InvalidSize`] for a bad `size`, or an invalid `extent`.
pub fn plane(
    texture: &dyn SolidTexture,
    size: u32,
    extent: f64,
    which: Plane,
    emissive: bool,
    progress: &dyn Progress,
) -> Result<Image> {
    check_size(size)?;
    positive("extent", extent)?;
    let px = extent / f64::from(size);
    let fp = Footprint::new(px).unwrap_or(Footprint::POINT);
    let image =
        preview::shade_pixels(size, size, SUPERSAMPLE, texture.name(), progress, |x, y| {
            let (a, b) = (x * px - 0.5 * extent, 0.5 * extent - y * px);
            let (p, n) = match which {
                Plane::Horizontal => (DVec3::new(a, b, 0.37), DVec3::Z),
                Plane::Vertical => (DVec3::new(a, 0.37, b + 0.5 * extent), DVec3::NEG_Y),
            };
            look(texture, p, n, fp, emissive).as_vec3()
        })?;
    Ok(image)
}

/// A height texture as water: a mirror-like plane (`z = 0` displaced by
/// the texture's height, `scale` world units per texture unit) seen in
/// perspective from `eye_height` above it, reflecting a sky gradient and a
/// low sun with Fresnel's law (Schlick, water's index 1.33).
///
/// # Errors
/// [`TextureError`] for a bad resolution or scale.
pub fn water(
    texture: &dyn SolidTexture,
    width: u32,
    height: u32,
    scale: f64,
    progress: &dyn Progress,
) -> Result<Image> {
    positive("scale", scale)?;
    let eye = DVec3::new(0.0, 0.0, 1.5);
    let view = View::look_at(
        eye,
        DVec3::new(0.0, 20.0, 0.0),
        DVec3::Z,
        0.7,
        width,
        height,
    )?;
    let sun = DVec3::new(0.25, 1.0, 0.18).normalize();
    let sky = |d: DVec3| {
        let h = d.z.max(0.0);
        let base = DVec3::new(0.75, 0.82, 0.9).lerp(DVec3::new(0.18, 0.32, 0.62), h.powf(0.6));
        base + DVec3::new(1.0, 0.9, 0.7) * (d.dot(sun).max(0.0).powi(4000) * 12.0)
    };
    let alpha = view.pixel_angle();
    let image = preview::shade_pixels(
        width,
        height,
        SUPERSAMPLE,
        texture.name(),
        progress,
        |x, y| {
            let d = view.direction(x, y);
            let c = if d.z >= -1e-4 {
                sky(d)
            } else {
                let t = -eye.z / d.z;
                let p = eye + d * t;
                let fp = Footprint::new(t * alpha / scale).unwrap_or(Footprint::POINT);
                let g = texture.height_gradient(p / scale, fp);
                let n = bump(DVec3::Z, g);
                let r = d - n * (2.0 * d.dot(n));
                let cos = (-d.dot(n)).clamp(0.0, 1.0);
                let f = 0.02 + 0.98 * (1.0 - cos).powi(5);
                let deep = DVec3::new(0.01, 0.04, 0.05);
                deep.lerp(sky(DVec3::new(r.x, r.y, r.z.abs())), f)
            };
            c.as_vec3()
        },
    )?;
    Ok(image)
}
