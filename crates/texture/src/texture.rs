//! The seam every texture plugs into: [`SolidTexture`], a function of a 3-D
//! point that returns a [`Sample`].

use glam::DVec3;

use crate::footprint::Footprint;

/// What a texture's [`Sample`] carries, so a renderer knows how to show it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureKind {
    /// A surface colour (opacity 1, no displacement).
    Colour,
    /// A density or opacity in `[0, 1]` with a colour (clouds, rings).
    Density,
    /// A displacement along the surface normal (bump or displacement map).
    Height,
    /// A surface colour and a displacement (a planet, a moon).
    ColourAndHeight,
}

/// Converts a colour as the sources write it to linear RGB.
///
/// Musgrave's listings give their colours (sky blue, the flame's black-body
/// ramp, the terran land spline, …) as the values a display shows, i.e.
/// sRGB-encoded; natura's renderers work in linear light. Every texture
/// computes in the listing's terms and returns linear RGB through this
/// function (the IEC 61966-2-1 sRGB decoding per channel), so an image
/// encoded back to sRGB shows the listing's colours.
#[must_use]
pub fn display_to_linear(c: DVec3) -> DVec3 {
    let f = |v: f64| {
        let v = v.clamp(0.0, 1.0);
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    DVec3::new(f(c.x), f(c.y), f(c.z))
}

/// A texture's value at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Linear RGB colour, each channel in `[0, 1]` (see [`display_to_linear`]).
    pub colour: DVec3,
    /// Opacity (cloud or ring density) in `[0, 1]`; 1 for opaque surfaces.
    pub opacity: f64,
    /// Displacement along the surface normal, in texture units (0 if none).
    pub height: f64,
}

impl Sample {
    /// An opaque colour without displacement.
    #[must_use]
    pub const fn colour(colour: DVec3) -> Self {
        Self {
            colour,
            opacity: 1.0,
            height: 0.0,
        }
    }

    /// A density with its colour.
    #[must_use]
    pub const fn density(colour: DVec3, density: f64) -> Self {
        Self {
            colour,
            opacity: density,
            height: 0.0,
        }
    }

    /// A displacement on a neutral grey surface.
    #[must_use]
    pub const fn height(height: f64) -> Self {
        Self {
            colour: DVec3::splat(0.5),
            opacity: 1.0,
            height,
        }
    }

    /// Whether every field is finite and colour and opacity are in `[0, 1]`.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.colour.cmpge(DVec3::ZERO).all()
            && self.colour.cmple(DVec3::ONE).all()
            && (0.0..=1.0).contains(&self.opacity)
            && self.height.is_finite()
    }
}

/// A procedural solid texture: a pure function of a point in texture space
/// (`f64`), filtered to a pixel [`Footprint`].
///
/// Implementors are `Send + Sync` and deterministic: the same point and
/// footprint give the same bits on every call, thread and run. Every valid
/// [`Sample`] has finite fields and colour and opacity in `[0, 1]` for finite
/// input; a non-finite point gives unspecified (possibly NaN) values, never a
/// panic.
pub trait SolidTexture: Send + Sync {
    /// The texture's name, as the examples label it.
    fn name(&self) -> &'static str;

    /// What the samples carry.
    fn kind(&self) -> TextureKind;

    /// The texture at `p` (texture space), filtered to `fp`.
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample;

    /// The gradient of [`Sample::height`] at `p`, for bump and displacement
    /// normals. The default is a central difference over half the footprint
    /// (at least 10⁻⁵ texture units); textures with an analytic gradient
    /// override it.
    fn height_gradient(&self, p: DVec3, fp: Footprint) -> DVec3 {
        let h = (0.5 * fp.width()).max(1e-5);
        crate::normal::gradient_fd(|q| self.sample(q, fp).height, p, h)
    }
}

impl<T: SolidTexture + ?Sized> SolidTexture for &T {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn kind(&self) -> TextureKind {
        (**self).kind()
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        (**self).sample(p, fp)
    }
    fn height_gradient(&self, p: DVec3, fp: Footprint) -> DVec3 {
        (**self).height_gradient(p, fp)
    }
}

impl<T: SolidTexture + ?Sized> SolidTexture for Box<T> {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn kind(&self) -> TextureKind {
        (**self).kind()
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        (**self).sample(p, fp)
    }
    fn height_gradient(&self, p: DVec3, fp: Footprint) -> DVec3 {
        (**self).height_gradient(p, fp)
    }
}
