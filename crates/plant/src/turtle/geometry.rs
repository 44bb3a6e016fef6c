//! What the turtle draws: segments (struct-of-arrays, chained into
//! generalized cylinders), polygons and surface instances.

use super::{TurtleFrame, TurtleState};
use glam::{DVec3, Vec3};

/// The most vertices a polygon may have. Its triangulation (ear clipping in
/// its plane) takes time quadratic in the vertices, cubic for a tangled
/// outline, so the turtle and the mesher refuse longer ones with an error.
pub const MAX_POLYGON_VERTICES: usize = 1024;

/// A polygon recorded between `{` and `}`.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// Vertices in order (consecutive duplicates removed).
    pub vertices: Vec<Vec3>,
    /// Colour index.
    pub colour: u32,
    /// Path length from the base where the polygon starts.
    pub distance: f32,
}

impl Polygon {
    pub(crate) fn push_vertex(&mut self, p: DVec3) {
        let p = p.as_vec3();
        if self.vertices.last() != Some(&p) {
            self.vertices.push(p);
        }
    }
}

/// A predefined surface placed by `~X`, `@o` or `@O`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceInstance {
    /// The surface's name (`L` leaf, `P` petal, `O` sphere, `o` disc, `K` flower, or a registered one).
    pub name: char,
    /// The turtle's frame where it is placed.
    pub frame: TurtleFrame,
    /// Scale along `H` (radius for spheres and discs).
    pub length: f64,
    /// Scale along `L`.
    pub width: f64,
    /// Colour index.
    pub colour: u32,
    /// Path length from the base.
    pub distance: f32,
}

/// Geometry produced by the turtle.
///
/// Segments are stored as struct-of-arrays; `prev[k]` is the segment that
/// segment `k` continues (same branch, no gap), so consecutive segments form
/// one generalized cylinder with smooth joints.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    /// Segment start points.
    pub start: Vec<Vec3>,
    /// Segment end points.
    pub end: Vec<Vec3>,
    /// Turtle `U` along each segment (orients the cross-section).
    pub up: Vec<Vec3>,
    /// Width (diameter) at the start.
    pub width0: Vec<f32>,
    /// Width (diameter) at the end.
    pub width1: Vec<f32>,
    /// Path length from the base to the start of the segment.
    pub dist0: Vec<f32>,
    /// Path length from the base to the end.
    pub dist1: Vec<f32>,
    /// Colour index.
    pub colour: Vec<u32>,
    /// The segment this one continues, or `u32::MAX`.
    pub prev: Vec<u32>,
    /// Polygons.
    pub polygons: Vec<Polygon>,
    /// Predefined surfaces.
    pub surfaces: Vec<SurfaceInstance>,
}

impl Geometry {
    /// Number of segments.
    #[must_use]
    pub fn segment_count(&self) -> usize {
        self.start.len()
    }

    pub(crate) fn push_segment(&mut self, start: DVec3, st: &TurtleState, d0: f64, w0: f64) -> u32 {
        let k = self.start.len() as u32;
        self.start.push(start.as_vec3());
        self.end.push(st.frame.p.as_vec3());
        self.up.push(st.frame.u.as_vec3());
        self.width0.push(w0 as f32);
        self.width1.push(st.width as f32);
        self.dist0.push(d0 as f32);
        self.dist1.push(st.distance as f32);
        self.colour.push(st.colour);
        self.prev.push(st.last_seg);
        k
    }

    /// Appends `other`'s segments, polygons and surfaces (a second plant in
    /// the same picture, as a climber on its tree); the links of `other`'s
    /// segments to the segments they continue are shifted past this
    /// geometry's, so each still continues its own.
    pub fn append(&mut self, other: &Geometry) {
        let shift = self.start.len() as u32;
        self.start.extend_from_slice(&other.start);
        self.end.extend_from_slice(&other.end);
        self.up.extend_from_slice(&other.up);
        self.width0.extend_from_slice(&other.width0);
        self.width1.extend_from_slice(&other.width1);
        self.dist0.extend_from_slice(&other.dist0);
        self.dist1.extend_from_slice(&other.dist1);
        self.colour.extend_from_slice(&other.colour);
        self.prev.extend(
            other
                .prev
                .iter()
                .map(|&k| if k == u32::MAX { k } else { k + shift }),
        );
        self.polygons.extend(other.polygons.iter().cloned());
        self.surfaces.extend(other.surfaces.iter().cloned());
    }

    /// The largest path length from the base (for wind weights), at least a tiny positive number.
    #[must_use]
    pub fn max_distance(&self) -> f32 {
        let a = self.dist1.iter().copied().fold(0.0f32, f32::max);
        let b = self.polygons.iter().map(|p| p.distance).fold(a, f32::max);
        let c = self.surfaces.iter().map(|s| s.distance).fold(b, f32::max);
        c.max(1e-6)
    }

    /// The bounding box of every point drawn, or `None` if nothing was drawn.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let pts = self
            .start
            .iter()
            .chain(&self.end)
            .chain(self.polygons.iter().flat_map(|p| &p.vertices))
            .copied()
            .chain(self.surfaces.iter().map(|s| s.frame.p.as_vec3()));
        let mut b: Option<(Vec3, Vec3)> = None;
        for p in pts {
            b = Some(match b {
                None => (p, p),
                Some((lo, hi)) => (lo.min(p), hi.max(p)),
            });
        }
        b
    }
}
