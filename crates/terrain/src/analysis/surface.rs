//! Slope and curvature from second-order central differences (Evans 1980,
//! Wood 1991 forms), one-sided at the edges.

use natura_core::{Grid2, HeightField};

use crate::bands;
use crate::error::Result;

/// Slope angle at every sample, radians in `[0, π/2)` (central differences).
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
pub fn slope(hf: &HeightField) -> Result<Grid2<f32>> {
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut g = Grid2::new(nx, ny, 0.0f32)?;
    bands::map_bands(nx, ny, [g.as_mut_slice()], |y0, y1, [o]| {
        for y in y0..y1 {
            for x in 0..nx {
                o[(y - y0) * nx + x] = hf.slope_at_sample(x, y);
            }
        }
    });
    Ok(g)
}

/// Curvatures of the surface, 1/m.
#[derive(Clone, Debug, PartialEq)]
pub struct Curvature {
    /// Profile curvature (along the steepest slope). Positive: concave up
    /// (flow decelerates, deposition, valley floors); negative: convex (ridges, knick points).
    pub profile: Grid2<f32>,
    /// Plan (contour) curvature. Positive: contours bend so that flow diverges (spurs);
    /// negative: flow converges (hollows, channels).
    pub plan: Grid2<f32>,
    /// Laplacian `z_xx + z_yy` (the quantity diffusion acts on). Positive: concave up.
    pub laplacian: Grid2<f32>,
}

/// Profile, plan and Laplacian curvature at every sample. Needs at least 3 × 3 samples.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
pub fn curvature(hf: &HeightField) -> Result<Curvature> {
    crate::error::min_size("curvature", hf.nx(), hf.ny(), 3, 3)?;
    let (nx, ny) = (hf.nx(), hf.ny());
    let h = hf.heights();
    let c = f64::from(hf.cell_size());
    let mut profile = Grid2::new(nx, ny, 0.0f32)?;
    let mut plan = Grid2::new(nx, ny, 0.0f32)?;
    let mut lap = Grid2::new(nx, ny, 0.0f32)?;
    bands::map_bands(
        nx,
        ny,
        [
            profile.as_mut_slice(),
            plan.as_mut_slice(),
            lap.as_mut_slice(),
        ],
        |y0, y1, [po, pl, la]| {
            for y in y0..y1 {
                let yc = y.clamp(1, ny - 2);
                for x in 0..nx {
                    let xc = x.clamp(1, nx - 2);
                    let z = |dx: i64, dy: i64| {
                        f64::from(h[((xc as i64 + dx) as usize, (yc as i64 + dy) as usize)])
                    };
                    let zx = (z(1, 0) - z(-1, 0)) / (2.0 * c);
                    let zy = (z(0, 1) - z(0, -1)) / (2.0 * c);
                    let zxx = (z(1, 0) - 2.0 * z(0, 0) + z(-1, 0)) / (c * c);
                    let zyy = (z(0, 1) - 2.0 * z(0, 0) + z(0, -1)) / (c * c);
                    let zxy = (z(1, 1) - z(-1, 1) - z(1, -1) + z(-1, -1)) / (4.0 * c * c);
                    let p = zx * zx + zy * zy;
                    let r = (y - y0) * nx + x;
                    if p > 1e-20 {
                        po[r] = ((zxx * zx * zx + 2.0 * zxy * zx * zy + zyy * zy * zy)
                            / (p * (1.0 + p).powf(1.5))) as f32;
                        pl[r] = ((zxx * zy * zy - 2.0 * zxy * zx * zy + zyy * zx * zx)
                            / p.powf(1.5)) as f32;
                    }
                    la[r] = (zxx + zyy) as f32;
                }
            }
        },
    );
    Ok(Curvature {
        profile,
        plan,
        laplacian: lap,
    })
}

/// Area of the surface, m²: each cell split into two triangles on its
/// `(+1, +1)` diagonal (the usual height-field triangulation, Musgrave et
/// al. 1989, §5), their areas summed in `f64`. A flat field's area is its
/// horizontal extent; roughness only adds to it. Needs at least 2 × 2
/// samples.
///
/// ```
/// use natura_terrain::{HeightField, analysis::surface_area};
/// // A plane rising 1 m per metre along x: area √2 times the 4 m × 3 m extent.
/// let hf = HeightField::from_fn(5, 4, 1.0, |i, _| i as f32)?;
/// assert!((surface_area(&hf)? - 12.0 * 2f64.sqrt()).abs() < 1e-9);
/// # Ok::<(), natura_terrain::TerrainError>(())
/// ```
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) for fewer
/// than 2 × 2 samples and [`TerrainError::Core`](crate::TerrainError::Core)
/// for a height that is not finite.
pub fn surface_area(hf: &HeightField) -> Result<f64> {
    crate::error::min_size("surface_area", hf.nx(), hf.ny(), 2, 2)?;
    hf.check_finite()?;
    let p = |i: usize, j: usize| hf.point(i, j).as_dvec3();
    let tri = |a: glam::DVec3, b: glam::DVec3, c: glam::DVec3| 0.5 * (b - a).cross(c - a).length();
    let mut area = 0.0;
    for j in 0..hf.ny() - 1 {
        for i in 0..hf.nx() - 1 {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            area += tri(a, b, c) + tri(a, c, d);
        }
    }
    Ok(area)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paraboloid_curvatures() {
        // z = x²/100: Laplacian 0.02 everywhere; along x (the slope) profile curvature > 0.
        let hf =
            HeightField::from_fn(21, 21, 1.0, |i, _| (i as f32 - 10.0).powi(2) / 100.0).unwrap();
        let c = curvature(&hf).unwrap();
        assert!((c.laplacian[(5, 5)] - 0.02).abs() < 1e-6);
        let p = -0.1f64; // zx at x = -5
        let want = 0.02 / (1.0 + p * p).powf(1.5);
        assert!((f64::from(c.profile[(5, 5)]) - want).abs() < 1e-5);
        assert!(c.plan[(5, 5)].abs() < 1e-6);
        let s = slope(&hf).unwrap();
        assert!((s[(5, 5)] - 0.1f32.atan()).abs() < 1e-5);
    }
}
