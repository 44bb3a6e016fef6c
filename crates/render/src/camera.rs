//! The scene's camera: where the eye stands and where it looks (from the
//! scene's `[camera]` keys over the world's terrain), the natura-core camera
//! those give ([`PinholeCamera`] or [`PanoramicCamera`]), and the angle one
//! pixel subtends, which sets the footprint of the terrain's detail, the
//! textures' filtering and the cloud cache's resolution.

use glam::{Vec2, Vec3};
use natura_core::Boundary;
use natura_core::camera::{PanoramicCamera, PinholeCamera, Projection};
use natura_trace::Camera;

use crate::error::Result;
use crate::scene::CameraKind;
use crate::world::World;

impl World {
    /// The eye position the scene's camera description gives: above the terrain
    /// (or water) at `position_uv` by `height_above_ground_m`.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        let c = &self.scene.camera;
        let e = self.terrain.extent();
        let (x, y) = (c.position_uv[0] as f32 * e.x, c.position_uv[1] as f32 * e.y);
        let ground = self.surface.sample(x, y, Boundary::Clamp);
        Vec3::new(x, y, ground + c.height_above_ground_m as f32)
    }

    /// The horizontal view direction rotated up by the scene's pitch.
    #[must_use]
    pub fn view_direction(&self) -> Vec3 {
        let c = &self.scene.camera;
        let e = self.terrain.extent();
        let to = Vec2::new(
            (c.target_uv[0] - c.position_uv[0]) as f32 * e.x,
            (c.target_uv[1] - c.position_uv[1]) as f32 * e.y,
        )
        .normalize_or(Vec2::Y);
        let p = (c.pitch_deg as f32).to_radians();
        Vec3::new(to.x * p.cos(), to.y * p.cos(), p.sin())
    }
}

/// The angle a pixel subtends at the image's centre (radians): the
/// vertical field of view over the image's height.
pub(crate) fn pixel_angle(world: &World) -> f32 {
    let scene = &world.scene;
    (scene.camera.vfov_deg as f32).to_radians() / scene.render.height as f32
}

/// The camera of a scene.
#[derive(Clone, Copy, Debug)]
pub enum SceneCamera {
    /// A pinhole camera.
    Pinhole(PinholeCamera),
    /// A cylindrical or spherical panorama.
    Panoramic(PanoramicCamera),
}

impl SceneCamera {
    /// The camera of `world`'s scene: at the eye, looking along the view
    /// direction, with the scene's kind, fields of view and image size.
    ///
    /// # Errors
    ///
    /// [`RenderError::Core`](crate::RenderError::Core) for a degenerate
    /// view or field of view.
    pub fn of_world(world: &World) -> Result<Self> {
        let scene = &world.scene;
        let r = &scene.render;
        let eye = world.eye();
        let dir = world.view_direction();
        let c = &scene.camera;
        let camera = match c.kind {
            CameraKind::Pinhole => SceneCamera::Pinhole(PinholeCamera::look_at(
                eye,
                eye + dir,
                Vec3::Z,
                (c.vfov_deg as f32).to_radians(),
                r.width,
                r.height,
            )?),
            CameraKind::Cylindrical | CameraKind::Spherical => {
                SceneCamera::Panoramic(PanoramicCamera::new(
                    eye,
                    dir,
                    Vec3::Z,
                    (c.hfov_deg as f32).to_radians(),
                    (c.vfov_deg as f32).to_radians(),
                    if c.kind == CameraKind::Cylindrical {
                        Projection::Cylindrical
                    } else {
                        Projection::Spherical
                    },
                    r.width,
                    r.height,
                )?)
            }
        };
        Ok(camera)
    }

    /// The camera as a natura-trace [`Camera`] (primary rays per pixel).
    #[must_use]
    pub fn camera(&self) -> &dyn Camera {
        match self {
            SceneCamera::Pinhole(c) => c,
            SceneCamera::Panoramic(c) => c,
        }
    }
}
