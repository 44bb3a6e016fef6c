//! A crown seen from afar as a turbid medium: the sunlight that reaches a
//! point inside it, on average over the leaves a pixel covers.
//!
//! Near the camera a shadow ray toward the sun decides whether a leaf is lit:
//! sunlight passes a crown's gaps in flecks a few centimetres across. Once
//! a pixel covers many leaves, one ray per sample picks one fleck or none,
//! and a pixel whose one sample found a fleck in the shade shows as a lone
//! bright speck. What the pixel should show is the mean: the fraction of
//! its leaves the sun reaches. A crown is then a turbid medium of leaves
//! (Ross 1981, *The Radiation Regime and Architecture of Plant Stands*,
//! ch. 3: the canopy's gap probability `exp(−G·u_L·s)` along a path of
//! length `s` through foliage of leaf area density `u_L` and projection
//! `G`), and the sun reaching a point is `exp(−κ·s)` with `s` the path
//! toward the sun inside the crowns it crosses.
//!
//! **The crown's shape.** Each prototype's crown is a stack of
//! [`BANDS`] cylinders over the height of its leaves, each of radius
//! `√2` times the root-mean-square distance of that band's leaf corners from
//! the trunk (the radius of a uniform disc with the same spread).
//!
//! **Its density.** One `κ` per prototype, fitted to the mesh itself: from
//! leaves across the crown, shadow rays at the scene's sun elevation (four
//! azimuths, as the trees stand at any yaw) through the crown's own
//! triangles give the fraction of leaf points the sun reaches; `κ` is the
//! value at which `exp(−κ·s)` over the same points has that mean. So the
//! medium lights a crown as much as its leaves do, and the light's place
//! follows the depth into the crown toward the sun.
//!
//! Trunks and branches are left out of the medium: the shadow of a trunk
//! at the distances where the medium is used is narrower than a pixel.

use glam::Vec3;

use super::bvh::Mesh;

/// Height bands of a crown's shape.
pub const BANDS: usize = 8;

/// Leaf points a crown's density is fitted on, at most.
const FIT_POINTS: usize = 1024;

/// A crown as a turbid medium, in its mesh's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct CrownMedium {
    /// Height of the lowest leaf, mesh units.
    z0: f32,
    /// Height of one band, mesh units.
    dz: f32,
    /// Radius of each band from the trunk's axis, mesh units.
    radius: [f32; BANDS],
    /// Extinction per mesh unit of path.
    kappa: f32,
    /// The size of one leaf, mesh units: the square root of the leaf
    /// triangles' mean area.
    leaf: f32,
}

impl CrownMedium {
    /// The medium of `mesh`'s leaves, its density fitted for a sun at
    /// elevation `sun_elevation` (radians); `None` for a mesh without
    /// leaves.
    #[must_use]
    pub fn of(mesh: &Mesh, sun_elevation: f32) -> Option<Self> {
        let leaves: Vec<&[Vec3; 3]> = mesh
            .tris
            .iter()
            .zip(&mesh.leaf)
            .filter_map(|(t, &l)| l.then_some(t))
            .collect();
        if leaves.is_empty() {
            return None;
        }
        let (z0, z1) = leaves
            .iter()
            .flat_map(|t| t.iter())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), p| {
                (a.min(p.z), b.max(p.z))
            });
        let dz = ((z1 - z0) / BANDS as f32).max(1e-6);
        let mut sum = [0.0f64; BANDS];
        let mut count = [0usize; BANDS];
        for p in leaves.iter().flat_map(|t| t.iter()) {
            let b = (((p.z - z0) / dz) as usize).min(BANDS - 1);
            sum[b] += f64::from(p.truncate().length_squared());
            count[b] += 1;
        }
        let mut radius = [0.0f32; BANDS];
        for b in 0..BANDS {
            if count[b] > 0 {
                radius[b] = (2.0 * sum[b] / count[b] as f64).sqrt() as f32;
            }
        }
        let area: f64 = leaves
            .iter()
            .map(|t| f64::from(0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()))
            .sum();
        let leaf = (area / leaves.len() as f64).sqrt() as f32;
        let mut medium = Self {
            z0,
            dz,
            radius,
            kappa: 0.0,
            leaf,
        };
        medium.kappa = medium.fit(mesh, &leaves, sun_elevation);
        Some(medium)
    }

    /// The `κ` at which `exp(−κ·s)` has, over leaf points spread across the
    /// crown and four sun azimuths, the mean of the mesh's own shadow rays.
    fn fit(&self, mesh: &Mesh, leaves: &[&[Vec3; 3]], sun_elevation: f32) -> f32 {
        let stride = leaves.len().div_ceil(FIT_POINTS).max(1);
        let (se, ce) = sun_elevation.sin_cos();
        let height = (self.dz * BANDS as f32).max(1e-6);
        let eps = 1e-3 * height;
        let mut lit = 0usize;
        let mut paths = Vec::new();
        for t in leaves.iter().step_by(stride) {
            let c = (t[0] + t[1] + t[2]) / 3.0;
            for k in 0..4 {
                let a = (k as f32 + 0.5) * std::f32::consts::FRAC_PI_2;
                let d = Vec3::new(ce * a.cos(), ce * a.sin(), se);
                lit += usize::from(!mesh.any(c, d, eps, f32::INFINITY));
                paths.push(self.path(c, d, eps));
            }
        }
        let target = lit as f64 / paths.len() as f64;
        let mean = |kappa: f64| {
            paths
                .iter()
                .map(|&s| (-kappa * f64::from(s)).exp())
                .sum::<f64>()
                / paths.len() as f64
        };
        // The mean falls from 1 at κ = 0 toward the share of points with no
        // path; bisect on a logarithmic scale between those ends.
        let (mut lo, mut hi) = (1e-4 / f64::from(height), 1e4 / f64::from(height));
        if mean(lo) <= target {
            return 0.0;
        }
        if mean(hi) >= target {
            return hi as f32;
        }
        for _ in 0..60 {
            let mid = (lo * hi).sqrt();
            if mean(mid) > target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (lo * hi).sqrt() as f32
    }

    /// The size of one leaf, mesh units.
    #[must_use]
    pub fn leaf_size(&self) -> f32 {
        self.leaf
    }

    /// Extinction per mesh unit.
    #[must_use]
    pub fn kappa(&self) -> f32 {
        self.kappa
    }

    /// The length, in units of the ray parameter, of `o + t·d` with
    /// `t > t_min` inside the crown (`o`, `d` in the mesh's frame).
    #[must_use]
    pub fn path(&self, o: Vec3, d: Vec3, t_min: f32) -> f32 {
        let a = d.x * d.x + d.y * d.y;
        let b = 2.0 * (o.x * d.x + o.y * d.y);
        let c0 = o.x * o.x + o.y * o.y;
        let mut total = 0.0;
        for (k, &r) in self.radius.iter().enumerate() {
            if r <= 0.0 {
                continue;
            }
            // The band's slab of heights.
            let (za, zb) = (
                self.z0 + k as f32 * self.dz,
                self.z0 + (k + 1) as f32 * self.dz,
            );
            let (mut lo, mut hi) = (t_min, f32::INFINITY);
            if d.z.abs() > 1e-12 {
                let (ta, tb) = ((za - o.z) / d.z, (zb - o.z) / d.z);
                lo = lo.max(ta.min(tb));
                hi = hi.min(ta.max(tb));
            } else if o.z < za || o.z >= zb {
                continue;
            }
            // The cylinder about the trunk's axis.
            let c = c0 - r * r;
            if a > 1e-12 {
                let disc = b * b - 4.0 * a * c;
                if disc <= 0.0 {
                    continue;
                }
                let q = disc.sqrt();
                lo = lo.max((-b - q) / (2.0 * a));
                hi = hi.min((-b + q) / (2.0 * a));
            } else if c > 0.0 {
                continue;
            }
            if hi > lo {
                total += hi - lo;
            }
        }
        total
    }

    /// The optical depth of `o + t·d` with `t > t_min` through the crown
    /// (`o`, `d` in the mesh's frame, `d` of any length).
    #[must_use]
    pub fn optical_depth(&self, o: Vec3, d: Vec3, t_min: f32) -> f32 {
        self.kappa * self.path(o, d, t_min) * d.length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A crown of leaves: small horizontal squares scattered through the
    /// cylinder of radius 1 and height 2 above z = 1, on a pseudo-random
    /// grid (leaf size `w`).
    fn crown(n: usize, w: f32) -> Mesh {
        let mut tris = Vec::new();
        let seed = natura_core::Seed(11);
        let mut k = 0i64;
        let mut next = || {
            k += 1;
            seed.uniform(&[k]) as f32
        };
        for _ in 0..n {
            let (r, a, z) = (
                next().sqrt(),
                next() * std::f32::consts::TAU,
                1.0 + 2.0 * next(),
            );
            let c = Vec3::new(r * a.cos(), r * a.sin(), z);
            let (u, v) = (Vec3::new(w, 0.0, 0.0), Vec3::new(0.0, w, 0.0));
            tris.push([c, c + u, c + v]);
            tris.push([c + u, c + u + v, c + v]);
        }
        let leaf = vec![true; tris.len()];
        Mesh::new(tris, leaf)
    }

    #[test]
    fn the_path_through_a_cylinder_is_its_chord() {
        let mut m = CrownMedium {
            z0: 0.0,
            dz: 1.0,
            radius: [1.0; BANDS],
            kappa: 0.5,
            leaf: 0.1,
        };
        // Horizontally through the axis at height 3: the diameter.
        let o = Vec3::new(-5.0, 0.0, 3.0);
        approx::assert_relative_eq!(m.path(o, Vec3::X, 0.0), 2.0, epsilon = 1e-5);
        // From the axis: the radius; beyond the far side: nothing.
        approx::assert_relative_eq!(
            m.path(Vec3::new(0.0, 0.0, 3.0), Vec3::X, 0.0),
            1.0,
            epsilon = 1e-5
        );
        assert_eq!(m.path(Vec3::new(2.0, 0.0, 3.0), Vec3::X, 0.0), 0.0);
        // Off the axis by 0.6: the chord 2·√(1 − 0.36) = 1.6.
        approx::assert_relative_eq!(
            m.path(Vec3::new(-5.0, 0.6, 3.0), Vec3::X, 0.0),
            1.6,
            epsilon = 1e-5
        );
        // Up the axis: the stack's height, 8; a slanted ray at 45° from the
        // axis leaves through the side after √2.
        approx::assert_relative_eq!(
            m.path(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 0.0),
            8.0,
            epsilon = 1e-5
        );
        let d = Vec3::new(1.0, 0.0, 1.0).normalize();
        approx::assert_relative_eq!(
            m.path(Vec3::new(0.0, 0.0, 2.0), d, 0.0),
            2f32.sqrt(),
            epsilon = 1e-5
        );
        // The depth scales with the direction's length (a scaled instance).
        approx::assert_relative_eq!(
            m.optical_depth(o, Vec3::X * 2.0, 0.0),
            0.5 * 1.0 * 2.0,
            epsilon = 1e-5
        );
        // An empty band is a gap.
        m.radius[3] = 0.0;
        approx::assert_relative_eq!(
            m.path(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 0.0),
            7.0,
            epsilon = 1e-5
        );
    }

    #[test]
    fn the_fitted_medium_lights_the_crown_as_its_leaves_do() {
        // A denser crown has a larger κ, and each reproduces the mean
        // visibility of its own leaves, which is checked here against the
        // mesh's rays at other azimuths than the fit's.
        let elevation = 0.3f32;
        let mut last = 0.0;
        for n in [200, 800, 3200] {
            let mesh = crown(n, 0.08);
            let m = CrownMedium::of(&mesh, elevation).unwrap();
            assert!(m.kappa() > last, "κ {} after {last}", m.kappa());
            last = m.kappa();
            let (se, ce) = elevation.sin_cos();
            let (mut rays, mut medium, mut count) = (0.0, 0.0, 0.0);
            for (t, _) in mesh.tris.iter().zip(0..).filter(|(_, i)| i % 2 == 0) {
                let c = (t[0] + t[1] + t[2]) / 3.0;
                for k in 0..8 {
                    let a = k as f32 * 0.785 + 0.1;
                    let d = Vec3::new(ce * a.cos(), ce * a.sin(), se);
                    rays += f64::from(u8::from(!mesh.any(c, d, 3e-3, f32::INFINITY)));
                    medium += f64::from((-m.optical_depth(c, d, 3e-3)).exp());
                    count += 1.0;
                }
            }
            let (rays, medium) = (rays / count, medium / count);
            assert!(
                (rays - medium).abs() < 0.03,
                "{n} leaves: rays {rays:.3}, medium {medium:.3}"
            );
        }
        // The leaf's size: the root of the triangles' mean area, w/√2.
        let m = CrownMedium::of(&crown(100, 0.08), elevation).unwrap();
        approx::assert_relative_eq!(m.leaf_size(), 0.08 / 2f32.sqrt(), max_relative = 1e-4);
    }

    #[test]
    fn a_mesh_without_leaves_has_no_medium() {
        let m = Mesh::new(vec![[Vec3::ZERO, Vec3::X, Vec3::Y]], vec![false]);
        assert!(CrownMedium::of(&m, 0.3).is_none());
    }
}
