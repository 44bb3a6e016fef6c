//! Triangle meshes of turtle geometry, and their export (glTF 2.0 binary, OBJ).
//!
//! [`PlantMesh::from_geometry`] turns the turtle's [`Geometry`] into one
//! indexed triangle mesh with two materials:
//!
//! - **bark**: every chain of segments becomes one generalized cylinder
//!   (Prusinkiewicz et al. 2001, §3; Prusinkiewicz & Lindenmayer 1990, §5.1):
//!   a ring of vertices at each end of each segment, *shared* between a
//!   segment and the one that continues it, so joints are smooth. A joint's
//!   ring lies in the plane that bisects the two segments and is widened
//!   along the bend (a mitre), so the tube keeps its width around corners;
//!   its reference direction is parallel-transported along the chain, so the
//!   tube does not twist. Each chain is closed by a flat cap at both ends.
//! - **leaf**: polygons drawn between `{` and `}` (ear-clipped in their
//!   plane) and the predefined surfaces `~L` (leaf), `~P` (petal), `~K`
//!   (a flower of five petals), `@o` (disc) and `@O` (sphere).
//!
//! Widths: a segment's ring radius is half the turtle's width (diameter) at
//! each end; at a joint the continuing segment's start width is used, so a
//! width change by `!` between two chained segments becomes a taper of the
//! earlier segment and the surface stays closed.
//!
//! Every vertex has a position, a unit normal, texture coordinates and a
//! wind weight, stored as struct-of-arrays. Bark `u` runs once around the
//! stem (0 to 1, the seam duplicated) and `v` is the path length from the
//! plant's base in metres, so a bark texture tiles at a fixed scale; leaf
//! `u` runs across the leaf and `v` along it, both 0 to 1.
//!
//! **Wind weight**: the path length from the base along the organ's
//! ancestry (the turtle's distance), divided by the plant's greatest path
//! length. It is 0 at the base of the trunk and 1 at the farthest tip, never
//! decreases from a segment to the one it continues or from a stem to its
//! branches, and a leaf takes the weight of the point where it is attached,
//! so a vertex shader can bend the plant by `weight²·wind` without tearing
//! leaves from their stems.

mod cylinder;
mod glb;
mod obj;
mod surface;
#[cfg(test)]
mod tests;

pub use glb::{Glb, glb_bytes, save_glb, save_glb_instanced};
pub use obj::save_obj;

use crate::error::{PlantError, Result};
use crate::turtle::Geometry;
use glam::{Quat, Vec2, Vec3};

/// The material of a group of triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Material {
    /// Stems and branches (generalized cylinders).
    Bark,
    /// Leaves, petals and other surfaces (polygons and predefined surfaces).
    Leaf,
}

impl Material {
    /// The material's name in exported files (`"bark"`, `"leaf"`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Bark => "bark",
            Self::Leaf => "leaf",
        }
    }

    /// The default base colour (linear RGB) used by the exporters and the preview.
    #[must_use]
    pub fn base_colour(self) -> Vec3 {
        match self {
            Self::Bark => Vec3::new(0.23, 0.14, 0.08),
            Self::Leaf => Vec3::new(0.12, 0.36, 0.07),
        }
    }
}

/// A contiguous range of [`PlantMesh::indices`] drawn with one material.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Primitive {
    /// The material.
    pub material: Material,
    /// First index (a multiple of 3).
    pub first: u32,
    /// Number of indices (a multiple of 3).
    pub count: u32,
}

/// Settings of [`PlantMesh::from_geometry`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MeshParams {
    /// Vertices around a stem (3 to 64); also the slices of spheres and discs.
    pub radial_segments: u32,
    /// Close each chain of segments with a flat cap at both ends.
    pub caps: bool,
    /// Rows of vertices along a leaf or petal surface (2 to 64).
    pub leaf_rows: u32,
    /// Emit every leaf triangle twice, front and back with opposite normals
    /// (for formats and renderers without double-sided materials; glTF's leaf
    /// material is double-sided anyway).
    pub double_sided_leaves: bool,
}

impl Default for MeshParams {
    /// 8 radial segments, caps, 5 leaf rows, single-sided leaves.
    fn default() -> Self {
        Self {
            radial_segments: 8,
            caps: true,
            leaf_rows: 5,
            double_sided_leaves: false,
        }
    }
}

impl MeshParams {
    /// Checks the counts are in range.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field out of range.
    pub fn validate(&self) -> Result<()> {
        use natura_core::check::count;
        count(
            "MeshParams::radial_segments",
            self.radial_segments as usize,
            3,
            64,
            "must lie in 3..=64",
        )?;
        count(
            "MeshParams::leaf_rows",
            self.leaf_rows as usize,
            2,
            64,
            "must lie in 2..=64",
        )?;
        Ok(())
    }
}

/// A placement of a mesh: scale, then rotation, then translation (z up, metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Translation.
    pub translation: Vec3,
    /// Rotation (unit quaternion).
    pub rotation: Quat,
    /// Scale along the mesh's own axes (positive).
    pub scale: Vec3,
}

impl Default for Instance {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        }
    }
}

impl Instance {
    /// Returns the instance at `translation`, turned by `yaw` radians about z, scaled uniformly by `scale`.
    #[must_use]
    pub fn new(translation: Vec3, yaw: f32, scale: f32) -> Self {
        Self {
            translation,
            rotation: Quat::from_rotation_z(yaw),
            scale: Vec3::splat(scale),
        }
    }

    /// Maps a point of the mesh into the scene.
    #[must_use]
    #[inline]
    pub fn transform_point(&self, p: Vec3) -> Vec3 {
        self.translation + self.rotation * (self.scale * p)
    }

    /// Maps a normal of the mesh into the scene (unit length).
    #[must_use]
    #[inline]
    pub fn transform_normal(&self, n: Vec3) -> Vec3 {
        (self.rotation * (n / self.scale)).normalize_or_zero()
    }

    /// Checks the values are finite, the rotation unit and the scale positive.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        use natura_core::check;
        check::finite3("Instance::translation", self.translation.as_dvec3())?;
        let q = self.rotation;
        if !q.is_finite() || (q.length() - 1.0).abs() > 1e-4 {
            return Err(invalid(
                "Instance::rotation",
                format!("{q:?}"),
                "must be a finite unit quaternion",
            ));
        }
        if !self.scale.is_finite() || self.scale.min_element() <= 0.0 {
            return Err(invalid(
                "Instance::scale",
                self.scale,
                "every component must be finite and > 0",
            ));
        }
        Ok(())
    }
}

/// An indexed triangle mesh of a plant, struct-of-arrays: vertex `i` is
/// `positions[i]`, `normals[i]`, `uvs[i]`, `wind[i]`.
///
/// Triangles are counter-clockwise seen from the side their normals point to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlantMesh {
    /// Vertex positions (z up, metres).
    pub positions: Vec<Vec3>,
    /// Unit vertex normals.
    pub normals: Vec<Vec3>,
    /// Texture coordinates (see the [module docs](self)).
    pub uvs: Vec<Vec2>,
    /// Wind weight in `[0, 1]` (see the [module docs](self)).
    pub wind: Vec<f32>,
    /// Triangle vertex indices, three per triangle.
    pub indices: Vec<u32>,
    /// Index ranges per material, in order, covering `indices`.
    pub primitives: Vec<Primitive>,
}

/// Vertex and index counts of a mesh, known before it is built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshCounts {
    /// Bark vertices.
    pub bark_vertices: usize,
    /// Bark indices.
    pub bark_indices: usize,
    /// Leaf vertices.
    pub leaf_vertices: usize,
    /// Leaf indices.
    pub leaf_indices: usize,
}

impl PlantMesh {
    /// Meshes turtle geometry (see the [module docs](self)).
    ///
    /// Every array is allocated once at its final size (the counts are known
    /// in closed form beforehand), so meshing does no allocation per segment.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] if `params` does not validate, if
    /// `geometry`'s segment arrays differ in length, a segment continues a
    /// later or missing one, a coordinate or width is not finite (or a width
    /// negative), a surface name is not one of `L P K o O`, or the mesh would
    /// exceed 2³² vertices.
    pub fn from_geometry(geometry: &Geometry, params: &MeshParams) -> Result<Self> {
        params.validate()?;
        check_geometry(geometry)?;
        let chains = cylinder::Chains::new(geometry);
        let counts = counts_of(geometry, &chains, params)?;
        let nv = counts.bark_vertices + counts.leaf_vertices;
        let ni = counts.bark_indices + counts.leaf_indices;
        let mut m = Self {
            positions: Vec::with_capacity(nv),
            normals: Vec::with_capacity(nv),
            uvs: Vec::with_capacity(nv),
            wind: Vec::with_capacity(nv),
            indices: Vec::with_capacity(ni),
            primitives: Vec::with_capacity(2),
        };
        let inv_max = 1.0 / geometry.max_distance();
        cylinder::build(geometry, &chains, params, inv_max, &mut m);
        debug_assert_eq!(m.positions.len(), counts.bark_vertices);
        debug_assert_eq!(m.indices.len(), counts.bark_indices);
        surface::build(geometry, params, inv_max, &mut m);
        debug_assert_eq!(m.positions.len(), nv);
        debug_assert_eq!(m.indices.len(), ni);
        let nb = counts.bark_indices as u32;
        if nb > 0 {
            m.primitives.push(Primitive {
                material: Material::Bark,
                first: 0,
                count: nb,
            });
        }
        if ni as u32 > nb {
            m.primitives.push(Primitive {
                material: Material::Leaf,
                first: nb,
                count: ni as u32 - nb,
            });
        }
        Ok(m)
    }

    /// The vertex and index counts [`PlantMesh::from_geometry`] will produce, in closed form.
    ///
    /// # Errors
    ///
    /// As [`PlantMesh::from_geometry`].
    pub fn counts(geometry: &Geometry, params: &MeshParams) -> Result<MeshCounts> {
        params.validate()?;
        check_geometry(geometry)?;
        counts_of(geometry, &cylinder::Chains::new(geometry), params)
    }

    /// Number of vertices.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The bounding box of the vertices, or `None` for an empty mesh.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }

    /// Checks the mesh is consistent (its fields are public, so a caller may
    /// have edited it): equal attribute lengths, whole triangles, indices of
    /// existing vertices, primitives covering the indices in order, finite
    /// values, unit normals and wind weights in `[0, 1]`.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming `mesh` and what is wrong.
    pub fn check(&self) -> Result<()> {
        let n = self.positions.len();
        if self.normals.len() != n || self.uvs.len() != n || self.wind.len() != n {
            return Err(invalid(
                "mesh",
                format!(
                    "{n} positions, {} normals, {} uvs, {} wind weights",
                    self.normals.len(),
                    self.uvs.len(),
                    self.wind.len()
                ),
                "needs one of each attribute per vertex",
            ));
        }
        if n > u32::MAX as usize || !self.indices.len().is_multiple_of(3) {
            return Err(invalid(
                "mesh",
                format!("{n} vertices, {} indices", self.indices.len()),
                "needs fewer than 2^32 vertices and three indices per triangle",
            ));
        }
        if let Some(&i) = self.indices.iter().find(|&&i| i as usize >= n) {
            return Err(invalid(
                "mesh",
                format!("index {i} of {n} vertices"),
                "indices must name existing vertices",
            ));
        }
        let mut at = 0u64;
        for p in &self.primitives {
            if u64::from(p.first) != at || p.count % 3 != 0 {
                return Err(invalid(
                    "mesh",
                    format!("primitive {p:?}"),
                    "primitives must cover the indices in order, whole triangles each",
                ));
            }
            at += u64::from(p.count);
        }
        if at != self.indices.len() as u64 {
            return Err(invalid(
                "mesh",
                format!("primitives cover {at} of {} indices", self.indices.len()),
                "primitives must cover every index",
            ));
        }
        if let Some(i) = (0..n).find(|&i| {
            !self.positions[i].is_finite()
                || !self.uvs[i].is_finite()
                || !(0.0..=1.0).contains(&self.wind[i])
                || !self.normals[i].is_finite()
                || (self.normals[i].length() - 1.0).abs() >= 1e-3
        }) {
            return Err(invalid(
                "mesh",
                format!(
                    "vertex {i}: {} {} {} {}",
                    self.positions[i], self.normals[i], self.uvs[i], self.wind[i]
                ),
                "positions and uvs must be finite, normals unit, wind in [0, 1]",
            ));
        }
        Ok(())
    }

    /// The triangles of one material as index triples.
    pub fn triangles(&self, material: Material) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.primitives
            .iter()
            .filter(move |p| p.material == material)
            .flat_map(move |p| {
                self.indices[p.first as usize..(p.first + p.count) as usize]
                    .chunks_exact(3)
                    .map(|t| [t[0], t[1], t[2]])
            })
    }
}

pub(crate) fn invalid(
    name: &'static str,
    value: impl std::fmt::Display,
    reason: &str,
) -> PlantError {
    PlantError::InvalidParameter {
        name,
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

/// Checks the public fields of `g` hang together.
fn check_geometry(g: &Geometry) -> Result<()> {
    let n = g.start.len();
    let lens = [
        g.end.len(),
        g.up.len(),
        g.width0.len(),
        g.width1.len(),
        g.dist0.len(),
        g.dist1.len(),
        g.colour.len(),
        g.prev.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(invalid(
            "geometry",
            format!("{n} segment starts, other arrays {lens:?}"),
            "every segment array must have one entry per segment",
        ));
    }
    for k in 0..n {
        let p = g.prev[k];
        if p != u32::MAX && p as usize >= k {
            return Err(invalid(
                "geometry.prev",
                format!("segment {k} continues {p}"),
                "a segment may continue only an earlier segment",
            ));
        }
        let ok = g.start[k].is_finite()
            && g.end[k].is_finite()
            && g.up[k].is_finite()
            && g.width0[k].is_finite()
            && g.width0[k] >= 0.0
            && g.width1[k].is_finite()
            && g.width1[k] >= 0.0
            && g.dist0[k].is_finite()
            && g.dist1[k].is_finite();
        if !ok {
            return Err(invalid(
                "geometry",
                format!("segment {k}"),
                "points, widths and distances must be finite, widths ≥ 0",
            ));
        }
    }
    for (k, poly) in g.polygons.iter().enumerate() {
        if !poly.distance.is_finite() || poly.vertices.iter().any(|v| !v.is_finite()) {
            return Err(invalid(
                "geometry.polygons",
                format!("polygon {k}"),
                "vertices and distance must be finite",
            ));
        }
        if poly.vertices.len() > crate::turtle::MAX_POLYGON_VERTICES {
            return Err(invalid(
                "geometry.polygons",
                format!("polygon {k} of {} vertices", poly.vertices.len()),
                &format!(
                    "a polygon may have at most {} vertices",
                    crate::turtle::MAX_POLYGON_VERTICES
                ),
            ));
        }
    }
    for (k, s) in g.surfaces.iter().enumerate() {
        let f = &s.frame;
        let ok = f.p.is_finite()
            && f.h.is_finite()
            && f.l.is_finite()
            && f.u.is_finite()
            && s.length.is_finite()
            && s.width.is_finite()
            && s.distance.is_finite();
        if !ok {
            return Err(invalid(
                "geometry.surfaces",
                format!("surface {k}"),
                "frame, size and distance must be finite",
            ));
        }
        if !surface::KNOWN.contains(&s.name) {
            return Err(invalid(
                "geometry.surfaces",
                format!("surface {k} `~{}`", s.name),
                "predefined surfaces are L (leaf), P (petal), K (flower), o (disc) and O (sphere)",
            ));
        }
    }
    if !(g.max_distance().is_finite()) {
        return Err(invalid(
            "geometry",
            g.max_distance(),
            "path lengths must be finite",
        ));
    }
    Ok(())
}

fn counts_of(g: &Geometry, chains: &cylinder::Chains, p: &MeshParams) -> Result<MeshCounts> {
    let (bv, bi) = cylinder::counts(chains, p);
    let (lv, li) = surface::counts(g, p);
    let c = MeshCounts {
        bark_vertices: bv,
        bark_indices: bi,
        leaf_vertices: lv,
        leaf_indices: li,
    };
    if (bv as u64 + lv as u64) > u64::from(u32::MAX)
        || (bi as u64 + li as u64) > u64::from(u32::MAX)
    {
        return Err(invalid(
            "geometry",
            format!("{} vertices, {} indices", bv + lv, bi + li),
            "a mesh holds at most 2^32 vertices and indices",
        ));
    }
    Ok(c)
}
