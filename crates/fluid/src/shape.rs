//! Solid shapes, obstacles and source regions, voxelised onto the grid.

use glam::{Quat, Vec3};

use crate::error::{FluidError, Result};
use natura_core::Grid3;

use crate::grid::{CellKind, Dims};

/// A solid region given by its signed distance (negative inside), in metres.
///
/// With the `serde` feature it reads and writes as a table tagged by `kind`
/// (`sphere`, `cuboid`, `oriented_box`, `ellipsoid`), the rotation as
/// `[x, y, z, w]`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)
)]
pub enum Shape {
    /// A ball.
    Sphere {
        /// Centre (m).
        centre: Vec3,
        /// Radius (m).
        radius: f32,
    },
    /// An axis-aligned box.
    Cuboid {
        /// Minimum corner (m).
        min: Vec3,
        /// Maximum corner (m).
        max: Vec3,
    },
    /// A box of half extents `half` rotated by `rotation` about `centre`.
    OrientedBox {
        /// Centre (m).
        centre: Vec3,
        /// Half extents along the box's own axes (m).
        half: Vec3,
        /// Orientation (a unit quaternion).
        rotation: Quat,
    },
    /// An ellipsoid of semi-axes `radii` rotated by `rotation` about
    /// `centre` (the moving ellipsoid of Foster & Fedkiw 2001, Figs. 5–6).
    ///
    /// Its [`sdf`](Shape::sdf) is the first-order distance
    /// `f/|∇f|` of `f = |q/r| − 1` (q the point in the ellipsoid's frame): exact
    /// on the surface with the true sign everywhere, and within a factor
    /// `max r / min r` of the distance away from it.
    Ellipsoid {
        /// Centre (m).
        centre: Vec3,
        /// Semi-axes along the ellipsoid's own axes (m).
        radii: Vec3,
        /// Orientation (a unit quaternion).
        rotation: Quat,
    },
}

/// The first-order signed distance `f/|∇f|` to the ellipsoid `|q/r| = 1`,
/// `q` in the ellipsoid's frame: `f = |q/r| − 1`, `∇f = (q/r²)/|q/r|`.
fn ellipsoid_sdf(q: Vec3, r: Vec3) -> f32 {
    let k0 = (q / r).length();
    let k1 = (q / (r * r)).length();
    if k1 > 0.0 {
        k0 * (k0 - 1.0) / k1
    } else {
        // The centre: as deep as the smallest semi-axis.
        -r.min_element()
    }
}

impl Shape {
    /// Signed distance from `p` (m): negative inside.
    #[must_use]
    pub fn sdf(&self, p: Vec3) -> f32 {
        fn box_sdf(q: Vec3, half: Vec3) -> f32 {
            let d = q.abs() - half;
            d.max(Vec3::ZERO).length() + d.max_element().min(0.0)
        }
        match *self {
            Shape::Sphere { centre, radius } => (p - centre).length() - radius,
            Shape::Cuboid { min, max } => box_sdf(p - 0.5 * (min + max), 0.5 * (max - min)),
            Shape::OrientedBox {
                centre,
                half,
                rotation,
            } => box_sdf(rotation.inverse() * (p - centre), half),
            Shape::Ellipsoid {
                centre,
                radii,
                rotation,
            } => ellipsoid_sdf(rotation.inverse() * (p - centre), radii),
        }
    }

    /// The shape's reference centre (m).
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        match *self {
            Shape::Sphere { centre, .. }
            | Shape::OrientedBox { centre, .. }
            | Shape::Ellipsoid { centre, .. } => centre,
            Shape::Cuboid { min, max } => 0.5 * (min + max),
        }
    }

    /// An axis-aligned bounding box `(min, max)`.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match *self {
            Shape::Sphere { centre, radius } => {
                (centre - Vec3::splat(radius), centre + Vec3::splat(radius))
            }
            Shape::Cuboid { min, max } => (min, max),
            Shape::OrientedBox {
                centre,
                half,
                rotation,
            } => {
                let m = glam::Mat3::from_quat(rotation);
                let e = m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z;
                (centre - e, centre + e)
            }
            Shape::Ellipsoid {
                centre,
                radii,
                rotation,
            } => {
                // Exact: the support of the ellipsoid along each world axis.
                let m = glam::Mat3::from_quat(rotation);
                let row = |a: usize| Vec3::new(m.x_axis[a], m.y_axis[a], m.z_axis[a]);
                let e = Vec3::new(
                    (row(0) * radii).length(),
                    (row(1) * radii).length(),
                    (row(2) * radii).length(),
                );
                (centre - e, centre + e)
            }
        }
    }

    /// The shape moved by `dx` and rotated by `angle_axis` (radians along the axis) about its centre.
    #[must_use]
    pub fn moved(&self, dx: Vec3, angle_axis: Vec3) -> Shape {
        let rot = if angle_axis.length_squared() > 0.0 {
            Quat::from_scaled_axis(angle_axis)
        } else {
            Quat::IDENTITY
        };
        match *self {
            Shape::Sphere { centre, radius } => Shape::Sphere {
                centre: centre + dx,
                radius,
            },
            Shape::Cuboid { min, max } if angle_axis == Vec3::ZERO => Shape::Cuboid {
                min: min + dx,
                max: max + dx,
            },
            Shape::Cuboid { min, max } => Shape::OrientedBox {
                centre: 0.5 * (min + max) + dx,
                half: 0.5 * (max - min),
                rotation: rot,
            },
            Shape::OrientedBox {
                centre,
                half,
                rotation,
            } => Shape::OrientedBox {
                centre: centre + dx,
                half,
                rotation: (rot * rotation).normalize(),
            },
            Shape::Ellipsoid {
                centre,
                radii,
                rotation,
            } => Shape::Ellipsoid {
                centre: centre + dx,
                radii,
                rotation: (rot * rotation).normalize(),
            },
        }
    }

    /// Checks the parameters are finite and positive where they must be.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::InvalidParameter`] naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        let bad = |reason: &'static str| FluidError::InvalidParameter {
            name: "shape",
            value: format!("{self:?}"),
            reason,
        };
        let ok = match *self {
            Shape::Sphere { centre, radius } => {
                centre.is_finite() && radius.is_finite() && radius > 0.0
            }
            Shape::Cuboid { min, max } => {
                min.is_finite() && max.is_finite() && max.cmpgt(min).all()
            }
            Shape::OrientedBox {
                centre,
                half: size,
                rotation,
            }
            | Shape::Ellipsoid {
                centre,
                radii: size,
                rotation,
            } => {
                centre.is_finite()
                    && size.is_finite()
                    && size.cmpgt(Vec3::ZERO).all()
                    && rotation.is_finite()
                    && (rotation.length() - 1.0).abs() < 1e-3
            }
        };
        if ok {
            Ok(())
        } else {
            Err(bad(
                "must be finite with positive size (an oriented box's or ellipsoid's rotation a unit quaternion)",
            ))
        }
    }

    /// Checks that the shape lies within the domain `[0, n·h]` on every
    /// non-flat axis; on a flat axis it must cover the single cell's centre.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::OutsideGrid`] if the shape lies outside the grid.
    pub fn check_inside(&self, dims: Dims, h: f32, what: &'static str) -> Result<()> {
        self.validate()?;
        let (lo, hi) = self.bounds();
        let n = dims.n();
        let tol = 1e-4 * h;
        for a in 0..3 {
            let ext = n[a] as f32 * h;
            let inside = if n[a] == 1 {
                lo[a] <= 0.5 * h && hi[a] >= 0.5 * h
            } else {
                lo[a] >= -tol && hi[a] <= ext + tol
            };
            if !inside {
                return Err(FluidError::OutsideGrid {
                    what,
                    detail: format!(
                        "axis {} spans [{}, {}] m but the grid covers [0, {}] m",
                        ["x", "y", "z"][a],
                        lo[a],
                        hi[a],
                        ext
                    ),
                });
            }
        }
        Ok(())
    }
}

/// A solid obstacle moving rigidly: translation `velocity` plus rotation
/// `angular_velocity` (rad/s) about its centre. Its cells are occupied; their
/// faces carry the obstacle's velocity (Fedkiw et al. 2001, §4).
///
/// With the `serde` feature every field but `shape` may be left out (a
/// fixed obstacle with no temperature of its own).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Obstacle {
    /// The occupied region at the current time.
    pub shape: Shape,
    /// Linear velocity (m/s).
    #[cfg_attr(feature = "serde", serde(default))]
    pub velocity: Vec3,
    /// Angular velocity (rad/s) about the shape's centre.
    #[cfg_attr(feature = "serde", serde(default))]
    pub angular_velocity: Vec3,
    /// Temperature imposed on occupied cells (smoke), if any (Fedkiw et al. 2001, §4).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub temperature: Option<f32>,
}

impl Obstacle {
    /// A static obstacle.
    #[must_use]
    pub fn fixed(shape: Shape) -> Self {
        Self {
            shape,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            temperature: None,
        }
    }

    /// Velocity of the solid at `p` (m/s).
    #[must_use]
    pub fn velocity_at(&self, p: Vec3) -> Vec3 {
        self.velocity + self.angular_velocity.cross(p - self.shape.centre())
    }

    /// Whether it moves at all.
    #[must_use]
    pub fn is_moving(&self) -> bool {
        self.velocity != Vec3::ZERO || self.angular_velocity != Vec3::ZERO
    }

    /// Advances the shape by `dt` seconds.
    pub fn advance(&mut self, dt: f32) {
        if self.is_moving() {
            self.shape = self
                .shape
                .moved(self.velocity * dt, self.angular_velocity * dt);
        }
    }

    pub(crate) fn validate(&self) -> Result<()> {
        self.shape.validate()?;
        if !(self.velocity.is_finite() && self.angular_velocity.is_finite()) {
            return Err(FluidError::InvalidParameter {
                name: "obstacle velocity",
                value: format!("{:?} / {:?}", self.velocity, self.angular_velocity),
                reason: "must be finite",
            });
        }
        if let Some(t) = self.temperature {
            crate::error::finite("obstacle temperature", f64::from(t))?;
        }
        Ok(())
    }
}

/// The obstacles of a grid solver and what follows from them: which
/// obstacle owns each cell (`u16::MAX` for none) and the cell kinds.
#[derive(Clone, Debug)]
pub(crate) struct Obstacles {
    pub(crate) list: Vec<Obstacle>,
    pub(crate) owner: Vec<u16>,
    pub(crate) kinds: Grid3<CellKind>,
}

impl Obstacles {
    /// No obstacles: every cell is fluid.
    pub(crate) fn new(dims: Dims) -> Result<Self> {
        Ok(Self {
            list: Vec::new(),
            owner: vec![u16::MAX; dims.cells()],
            kinds: Grid3::new(dims.nx, dims.ny, dims.nz, CellKind::Fluid)?,
        })
    }

    /// Adds an obstacle, which must be valid and lie inside the grid.
    pub(crate) fn add(&mut self, o: Obstacle, dims: Dims, h: f32) -> Result<()> {
        o.validate()?;
        o.shape.check_inside(dims, h, "obstacle")?;
        if self.list.len() >= usize::from(u16::MAX) {
            return Err(FluidError::InvalidParameter {
                name: "obstacles",
                value: self.list.len().to_string(),
                reason: "at most 65535 obstacles",
            });
        }
        self.list.push(o);
        self.revoxelise(dims, h);
        Ok(())
    }

    /// Moves the moving obstacles on by `dt`; returns whether any moved (the
    /// cells were then revoxelised).
    pub(crate) fn advance(&mut self, dt: f32, dims: Dims, h: f32) -> bool {
        if !self.list.iter().any(Obstacle::is_moving) {
            return false;
        }
        self.list.iter_mut().for_each(|o| o.advance(dt));
        self.revoxelise(dims, h);
        true
    }

    fn revoxelise(&mut self, dims: Dims, h: f32) {
        self.owner = voxelise(&self.list, dims, h);
        for (k, &o) in self.kinds.as_mut_slice().iter_mut().zip(&self.owner) {
            *k = if o == u16::MAX {
                CellKind::Fluid
            } else {
                CellKind::Solid
            };
        }
    }
}

/// For each cell, the index of the first obstacle whose shape contains the
/// cell centre, or `u16::MAX`.
pub(crate) fn voxelise(obstacles: &[Obstacle], dims: Dims, h: f32) -> Vec<u16> {
    let n = dims.n();
    let mut out = vec![u16::MAX; dims.cells()];
    for (oi, o) in obstacles.iter().enumerate() {
        let (lo, hi) = o.shape.bounds();
        let r = |a: usize| {
            let a0 = ((lo[a] / h - 0.5).floor().max(0.0) as usize).min(n[a] - 1);
            let a1 = ((hi[a] / h - 0.5).ceil().max(0.0) as usize).min(n[a] - 1);
            a0..=a1
        };
        for k in r(2) {
            for j in r(1) {
                for i in r(0) {
                    let c = dims.idx(i, j, k);
                    if out[c] == u16::MAX
                        && o.shape.sdf(crate::grid::cell_centre([i, j, k], h)) < 0.0
                    {
                        out[c] = oi as u16;
                    }
                }
            }
        }
    }
    out
}

/// Velocity of the solid owning face `f` of component `a` (0 if none): the
/// obstacle of the cell on either side of the face.
pub(crate) fn solid_face_velocity<'a>(
    dims: Dims,
    h: f32,
    owner: &'a [u16],
    obstacles: &'a [Obstacle],
) -> impl Fn(usize, [usize; 3]) -> f32 + Sync + 'a {
    move |a, f| {
        let cell = |c: [usize; 3]| owner[dims.idx(c[0], c[1], c[2])];
        let mut o = if f[a] < dims.n()[a] {
            cell(f)
        } else {
            u16::MAX
        };
        if o == u16::MAX && f[a] > 0 {
            let mut c = f;
            c[a] -= 1;
            o = cell(c);
        }
        if o == u16::MAX {
            return 0.0;
        }
        obstacles[usize::from(o)].velocity_at(crate::grid::face_position(a, f, h))[a]
    }
}
