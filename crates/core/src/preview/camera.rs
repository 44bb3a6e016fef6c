//! Preview cameras: a look-at camera with its framing of a bounding box, and
//! the projector the rasterizer draws through.

use glam::Vec3;

use super::PixelRays;
use crate::camera::{OrthographicCamera, PinholeCamera, Ray};
use crate::check::{Checked, ParamError};
use crate::error::Result;

/// How a [`PreviewCamera`] projects.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum PreviewProjection {
    /// Parallel projection; `height` is the visible height in metres.
    Orthographic {
        /// Visible height in metres.
        height: f32,
    },
    /// Pinhole projection with the vertical field of view in degrees.
    Perspective {
        /// Vertical field of view in degrees, in (0, 180).
        fov_y_deg: f32,
    },
}

/// A camera looking from `eye` at `target`, `up` pointing up in the picture.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PreviewCamera {
    /// Position of the eye.
    pub eye: Vec3,
    /// Point looked at (the centre of the picture).
    pub target: Vec3,
    /// Direction that appears upward (need not be ⟂ to the view).
    pub up: Vec3,
    /// The projection.
    pub projection: PreviewProjection,
}

impl PreviewCamera {
    /// Returns a camera looking along `view_dir` that frames the box
    /// `lo..hi` with a small margin in a picture of the given aspect ratio
    /// (width / height), with z up in the picture (y up if looking along z).
    /// For a perspective camera pass the field of view; `None` gives an
    /// orthographic one.
    ///
    /// ```
    /// use natura_core::glam::Vec3;
    /// use natura_core::preview::{PreviewCamera, PreviewProjection};
    /// let cam = PreviewCamera::framing(Vec3::ZERO, Vec3::ONE, Vec3::Y, None, 1.0)?;
    /// assert!((cam.target - Vec3::splat(0.5)).length() < 1e-6);
    /// let PreviewProjection::Orthographic { height } = cam.projection else { panic!() };
    /// assert!(height > 1.0 && height < 1.2); // the unit box plus a margin
    /// # Ok::<(), natura_core::check::ParamError>(())
    /// ```
    ///
    /// # Errors
    ///
    /// A [`ParamError`] naming `bounds` for a non-finite box, `view_dir` for a
    /// zero or non-finite direction, `aspect` for a non-positive aspect, or
    /// the camera's field ([`PreviewCamera::validate`]) for a field of view
    /// outside (0, 180).
    pub fn framing(
        lo: Vec3,
        hi: Vec3,
        view_dir: Vec3,
        fov_y_deg: Option<f32>,
        aspect: f32,
    ) -> Checked<Self> {
        if !lo.is_finite() || !hi.is_finite() {
            let v = format!("{lo}..{hi}");
            return Err(ParamError::new("bounds", v, "must be finite"));
        }
        let f = view_dir
            .try_normalize()
            .ok_or_else(|| ParamError::new("view_dir", view_dir, "must be finite and non-zero"))?;
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(ParamError::new("aspect", aspect, "must be finite and > 0"));
        }
        let up = if f.cross(Vec3::Z).length() > 1e-3 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let r = f.cross(up).normalize();
        let u = r.cross(f);
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-3);
        let (mut r0, mut r1, mut u0, mut u1) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for k in 0..8 {
            let c = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            ) - centre;
            r0 = r0.min(c.dot(r));
            r1 = r1.max(c.dot(r));
            u0 = u0.min(c.dot(u));
            u1 = u1.max(c.dot(u));
        }
        let target = centre + r * (0.5 * (r0 + r1)) + u * (0.5 * (u0 + u1));
        let (eye, projection) = match fov_y_deg {
            None => {
                let h = ((u1 - u0).max((r1 - r0) / aspect) * 1.06).max(1e-3);
                let eye = target - f * (4.0 * radius);
                (eye, PreviewProjection::Orthographic { height: h })
            }
            Some(fov) => {
                let half = 0.5 * fov.to_radians();
                let half = half.min((half.tan() * aspect).atan());
                let eye = target - f * (1.08 * radius / half.sin());
                (eye, PreviewProjection::Perspective { fov_y_deg: fov })
            }
        };
        let cam = Self {
            eye,
            target,
            up,
            projection,
        };
        cam.validate()?;
        Ok(cam)
    }

    /// Checks the camera can project.
    ///
    /// # Errors
    ///
    /// A [`ParamError`] naming the field: `PreviewCamera::target` (eye and
    /// target not finite and distinct), `PreviewCamera::up` (not finite or
    /// parallel to the view), `PreviewCamera::projection.height` or
    /// `PreviewCamera::projection.fov_y_deg`.
    pub fn validate(&self) -> Checked<()> {
        let f = self.target - self.eye;
        if !self.eye.is_finite() || !self.target.is_finite() || f.length() < 1e-9 {
            return Err(ParamError::new(
                "PreviewCamera::target",
                format!("eye {} target {}", self.eye, self.target),
                "eye and target must be finite and distinct",
            ));
        }
        if !self.up.is_finite() || f.normalize().cross(self.up).length() < 1e-6 {
            return Err(ParamError::new(
                "PreviewCamera::up",
                self.up,
                "must be finite and not parallel to the view",
            ));
        }
        match self.projection {
            PreviewProjection::Orthographic { height } if !(height.is_finite() && height > 0.0) => {
                Err(ParamError::new(
                    "PreviewCamera::projection.height",
                    height,
                    "must be finite and > 0",
                ))
            }
            PreviewProjection::Perspective { fov_y_deg }
                if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) =>
            {
                Err(ParamError::new(
                    "PreviewCamera::projection.fov_y_deg",
                    fov_y_deg,
                    "must lie in (0, 180)",
                ))
            }
            _ => Ok(()),
        }
    }
}

/// A [`PreviewCamera`] set up for a picture of given size: natura-core's
/// [`OrthographicCamera`] or [`PinholeCamera`] does the projection, and the
/// projector adds the depth key the [`Raster`](super::Raster) compares and
/// the perspective near plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projector {
    eye: Vec3,
    forward: Vec3,
    projection: Projection,
    near: f32,
}

/// The projection of a [`Projector`].
#[derive(Clone, Copy, Debug, PartialEq)]
enum Projection {
    Orthographic(OrthographicCamera),
    Perspective(PinholeCamera),
}

impl Projector {
    /// Returns the projector of `camera` onto a `width × height` picture.
    /// The near plane of a perspective camera lies at `1e-4` of the
    /// eye–target distance.
    ///
    /// ```
    /// use natura_core::glam::Vec3;
    /// use natura_core::preview::{PreviewCamera, PreviewProjection, Projector};
    /// let camera = PreviewCamera {
    ///     eye: Vec3::new(0.0, -5.0, 0.0),
    ///     target: Vec3::ZERO,
    ///     up: Vec3::Z,
    ///     projection: PreviewProjection::Perspective { fov_y_deg: 60.0 },
    /// };
    /// let p = Projector::new(&camera, 64, 48)?;
    /// let [x, y, key] = p.project(Vec3::ZERO).expect("the target is in view");
    /// assert!((x - 32.0).abs() < 1e-4 && (y - 24.0).abs() < 1e-4);
    /// assert!((key - 0.2).abs() < 1e-6); // 1 / distance along the view
    /// assert!(p.project(Vec3::new(0.0, -6.0, 0.0)).is_none()); // behind the eye
    /// # Ok::<(), natura_core::CoreError>(())
    /// ```
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
    /// if the camera fails [`PreviewCamera::validate`] or natura-core's
    /// camera refuses it (a size of zero or over
    /// [`MAX_RESOLUTION`](crate::camera::MAX_RESOLUTION), a field of view
    /// that rounds to 180°).
    pub fn new(camera: &PreviewCamera, width: u32, height: u32) -> Result<Self> {
        camera.validate()?;
        let c = camera;
        let projection = match c.projection {
            PreviewProjection::Orthographic { height: view } => Projection::Orthographic(
                OrthographicCamera::look_at(c.eye, c.target, c.up, view, width, height)?,
            ),
            PreviewProjection::Perspective { fov_y_deg } => {
                Projection::Perspective(PinholeCamera::look_at(
                    c.eye,
                    c.target,
                    c.up,
                    fov_y_deg.to_radians(),
                    width,
                    height,
                )?)
            }
        };
        let forward = match &projection {
            Projection::Orthographic(o) => o.direction(),
            Projection::Perspective(p) => p.direction(),
        };
        Ok(Self {
            eye: c.eye,
            forward,
            projection,
            near: 1e-4 * (c.target - c.eye).length(),
        })
    }

    /// Screen x, y (continuous pixel coordinates) and the depth key (larger
    /// is nearer, affine in screen space: `−z` for an orthographic camera,
    /// `1/z` for a perspective one, `z` the distance along the view), or
    /// `None` behind the near plane (perspective), behind the screen
    /// (orthographic) or for a non-finite point.
    #[inline]
    #[must_use]
    pub fn project(&self, p: Vec3) -> Option<[f32; 3]> {
        let z = (p - self.eye).dot(self.forward);
        let (q, key) = match &self.projection {
            Projection::Perspective(c) => {
                if z < self.near {
                    return None;
                }
                (c.project(p)?, 1.0 / z)
            }
            Projection::Orthographic(c) => (c.project(p)?, -z),
        };
        Some([q.x, q.y, key])
    }

    /// The depth key of a point (as in [`Projector::project`]), without
    /// the checks.
    #[inline]
    #[must_use]
    pub fn depth_key(&self, p: Vec3) -> f32 {
        let z = (p - self.eye).dot(self.forward);
        match self.projection {
            Projection::Perspective(_) => 1.0 / z,
            Projection::Orthographic(_) => -z,
        }
    }

    /// Unit vector from `p` towards the viewer.
    #[inline]
    #[must_use]
    pub fn to_viewer(&self, p: Vec3) -> Vec3 {
        match self.projection {
            Projection::Perspective(_) => (self.eye - p).normalize_or(-self.forward),
            Projection::Orthographic(_) => -self.forward,
        }
    }
}

impl PixelRays for Projector {
    fn resolution(&self) -> glam::UVec2 {
        match &self.projection {
            Projection::Orthographic(c) => c.resolution(),
            Projection::Perspective(c) => c.resolution(),
        }
    }

    fn ray_at(&self, px: f32, py: f32) -> Ray {
        match &self.projection {
            Projection::Orthographic(c) => c.ray_at(px, py),
            Projection::Perspective(c) => c.ray_at(px, py),
        }
    }
}
