//! Fournier–Fussell–Carpenter stochastic subdivision (Fournier et al. 1982): 1-D midpoint
//! displacement (the `fractal` procedure, Fournier et al. 1982, §3.2.3), fractal polylines and
//! stochastic interpolation (Fournier et al. 1982, §4.1.1), and grid subdivision of triangles,
//! quadrilaterals and the non-Markovian grid fill / diamond-square
//! (Fournier et al. 1982, §4.1.2) into a [`HeightField`] of any size.
//!
//! **Random numbers indexed by position.** Every computed point draws its
//! Gaussian from [`Seed::gaussian`] keyed by the point's *first appearance*
//! `(level, index)` in lowest terms, never by its array index (Fournier et al. 1982, §3.2.3
//! and §4.1.2). So a coarse run is exactly the subsampled fine run —
//! level-of-detail consistency, bit for bit — and adjacent tiles agree on
//! shared edges.
//!
//! **Errata corrected.** Fournier et al. 1982, §3.2.3 prints `ratio := 21-h`; it is the OCR of
//! `2↑−h`, so the per-level factor is `2^(−h)` (a `2^(1−h)` reading makes the
//! displacements *grow*). Fournier et al. 1982, §3.2.3 `2maxlevel` is `2^maxlevel`. Fournier et al.'s Pascal
//! keys `GAUSS` by the array position `fmid`, which changes with `maxlevel`,
//! contradicting Fig. 5's "same sample path at 17 and 257 points" (Fournier et al. 1982, §3.2.3);
//! we key by the resolution-independent dyadic position. Fig. 5's text says
//! h = 0.6, the caption h = 0.8: irrelevant to the algorithm.

use glam::DVec2;
use natura_core::{Grid2, HeightField, Seed};

use crate::bands;
use crate::error::{Result, TerrainError, invalid, non_negative};

/// The largest subdivision depth accepted (2^24 + 1 samples per side of 1-D curves).
pub const MAX_LEVELS: u32 = 24;

/// How the two endpoints (1-D) or the base-lattice corners (2-D) are chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum EndpointMode {
    /// Gaussian with standard deviation `scale`, as Fournier et al.'s printed `fractal` (Fournier et al. 1982, §3.2.3).
    Random,
    /// Fixed values, so segments join with C0 continuity (Fournier et al. 1982, §4.1.1).
    Fixed(f64, f64),
}

/// Parameters of FFC midpoint displacement (1-D and grid schemes).
///
/// The displacement standard deviation at subdivision level `ℓ ≥ 1` is
/// `scale · Π_{i=1..ℓ} 2^(−h_i)` (= `scale · 2^(−hℓ)` for a constant `h`),
/// times Saupe's factor `√(1 − 2^(2h−2))` when `variance_correction` is set.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MidpointParams {
    /// Hurst exponent `h ∈ (0, 1]` (Fournier et al.'s `h`; Musgrave et al. 1989, §3.1 gives H ≈ 0.8 for terrain).
    /// Larger values give smoother curves.
    pub h: f64,
    /// Optional per-level `h` (index 0 is level 1; the last value repeats), e.g.
    /// rugged at large scale and smooth at small, "as if valleys filled with
    /// sediment" (Fournier et al. 1982, §4.1.2). Overrides `h` when non-empty.
    pub h_schedule: Vec<f64>,
    /// The "roughness" factor: standard deviation of level 0, metres (Fournier et al. 1982, §3.2.3).
    pub scale: f64,
    /// Endpoint (corner) handling.
    pub endpoints: EndpointMode,
    /// Multiply every level's deviation by Saupe's `√(1 − 2^(2h−2))` so increments
    /// match fBm's variance (level-independent, so the ratio stays `2^(−h)`).
    pub variance_correction: bool,
}

impl Default for MidpointParams {
    fn default() -> Self {
        Self {
            h: 0.8,
            h_schedule: Vec::new(),
            scale: 100.0,
            endpoints: EndpointMode::Random,
            variance_correction: false,
        }
    }
}

impl MidpointParams {
    /// Checks every field: `h` (and each scheduled `h`) in `(0, 1]`, `scale` finite and ≥ 0,
    /// fixed endpoints finite.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`] naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        let check_h = |name, h: f64| {
            if h > 0.0 && h <= 1.0 {
                Ok(())
            } else {
                Err(invalid(name, h, "Hurst exponent must lie in (0, 1]"))
            }
        };
        check_h("MidpointParams::h", self.h)?;
        for &h in &self.h_schedule {
            check_h("MidpointParams::h_schedule", h)?;
        }
        non_negative("MidpointParams::scale", self.scale)?;
        if let EndpointMode::Fixed(a, b) = self.endpoints
            && !(a.is_finite() && b.is_finite())
        {
            return Err(invalid(
                "MidpointParams::endpoints",
                format!("({a}, {b})"),
                "must be finite",
            ));
        }
        Ok(())
    }

    /// `h` used at level `level ≥ 1`.
    #[must_use]
    pub fn h_at(&self, level: u32) -> f64 {
        if self.h_schedule.is_empty() {
            self.h
        } else {
            let i = (level.max(1) as usize - 1).min(self.h_schedule.len() - 1);
            self.h_schedule[i]
        }
    }

    /// Standard deviations of levels `0..=levels` (level 0 is the endpoints' `scale`).
    #[must_use]
    pub fn level_std(&self, levels: u32) -> Vec<f64> {
        let mut out = Vec::with_capacity(levels as usize + 1);
        out.push(self.scale);
        let mut s = self.scale;
        for l in 1..=levels {
            let h = self.h_at(l);
            s *= (-h).exp2();
            let corr = if self.variance_correction {
                (1.0 - (2.0 * h - 2.0).exp2()).max(0.0).sqrt()
            } else {
                1.0
            };
            out.push(s * corr);
        }
        out
    }
}

/// Fournier et al.'s 1-D `fractal` procedure: `2^levels + 1` samples of a midpoint-displacement
/// approximation of fBm on `[0, 1]` (Fournier et al. 1982, §3.2.3).
///
/// The value at dyadic position `k / 2^levels` depends only on `(seed, k / 2^levels)`,
/// so `midpoint_1d(p, L, s)[k] == midpoint_1d(p, L + m, s)[k << m]` bit for bit.
/// Uses `2^levels + 1` Gaussian draws with random endpoints, `2^levels − 1` with fixed ones.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`]
/// for a size the method cannot make, and [`TerrainError::Core`] if the field
/// cannot be allocated.
pub fn midpoint_1d(p: &MidpointParams, levels: u32, seed: Seed) -> Result<Vec<f64>> {
    p.validate()?;
    if levels > MAX_LEVELS {
        return Err(invalid(
            "levels",
            levels,
            format!("must be at most {MAX_LEVELS}"),
        ));
    }
    let n = (1usize << levels) + 1;
    let mut f = vec![0.0f64; n];
    let g = |level: u32, k: i64| seed.gaussian2(i64::from(level), k);
    let (a, b) = match p.endpoints {
        EndpointMode::Random => (g(0, 0) * p.scale, g(0, 1) * p.scale),
        EndpointMode::Fixed(a, b) => (a, b),
    };
    f[0] = a;
    f[n - 1] = b;
    let std = p.level_std(levels);
    for l in 1..=levels {
        let step = 1usize << (levels - l);
        let mut k = step;
        while k < n {
            let key = (k / step) as i64; // odd
            f[k] = (f[k - step] + f[k + step]) / 2.0 + g(l, key) * std[l as usize];
            k += 2 * step;
        }
    }
    Ok(f)
}

/// Subdivides the edge from `a` to `b` (identified by `ids`) `levels` times,
/// displacing each new midpoint along the normal of the segment being split
/// (Fournier et al. 1982, §4.1.1), with fixed (undisplaced) endpoints — Fournier et al.'s stochastic
/// interpolation (Fournier et al. 1982, §4.1.1). Returns the `2^levels − 1` interior points, from `a` to `b`.
///
/// Deviations are `level_std` times the original edge length, so `scale` is
/// relative roughness. The edge is always computed in canonical order
/// (smaller id first) so both polygons sharing it produce identical points.
fn subdivide_edge(
    a: DVec2,
    b: DVec2,
    ids: (u64, u64),
    std: &[f64],
    levels: u32,
    seed: Seed,
) -> Vec<DVec2> {
    let flip = ids.0 > ids.1;
    let (p, q, lo, hi) = if flip {
        (b, a, ids.1, ids.0)
    } else {
        (a, b, ids.0, ids.1)
    };
    let edge_seed = Seed(seed.hash(&[lo as i64, hi as i64]));
    let len = (q - p).length();
    let n = (1usize << levels) + 1;
    let mut pts = vec![DVec2::ZERO; n];
    pts[0] = p;
    pts[n - 1] = q;
    for l in 1..=levels {
        let step = 1usize << (levels - l);
        let mut k = step;
        while k < n {
            let (p0, p1) = (pts[k - step], pts[k + step]);
            let d = p1 - p0;
            let normal = DVec2::new(-d.y, d.x).normalize_or_zero();
            let gauss = edge_seed.gaussian2(i64::from(l), (k / step) as i64);
            pts[k] = (p0 + p1) * 0.5 + normal * (gauss * std[l as usize] * len);
            k += 2 * step;
        }
    }
    let mut inner: Vec<DVec2> = pts[1..n - 1].to_vec();
    if flip {
        inner.reverse();
    }
    inner
}

/// A fractal polyline through `vertices` (Fournier et al.'s stochastic interpolation,
/// Fournier et al. 1982, §4.1.1): each edge is subdivided `levels` times with midpoints
/// displaced along the local segment normal by `scale · 2^(−hℓ)` times the edge
/// length; the given vertices are kept exactly. With `closed`, the last vertex
/// joins the first. Vertex `i` is identified by `i` for seeding; use
/// [`fractal_polyline_ids`] to share edges between polylines.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`]
/// for a size the method cannot make, and [`TerrainError::Core`] if the field
/// cannot be allocated.
pub fn fractal_polyline(
    vertices: &[DVec2],
    closed: bool,
    p: &MidpointParams,
    levels: u32,
    seed: Seed,
) -> Result<Vec<DVec2>> {
    let ids: Vec<u64> = (0..vertices.len() as u64).collect();
    fractal_polyline_ids(vertices, &ids, closed, p, levels, seed)
}

/// [`fractal_polyline`] with explicit invariant vertex identifiers: two
/// polylines that share an edge (same pair of ids, either direction) produce
/// bit-identical points on it (external consistency, Fournier et al. 1982, §3.2.1).
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`]
/// for a size the method cannot make, and [`TerrainError::Core`] if the field
/// cannot be allocated.
pub fn fractal_polyline_ids(
    vertices: &[DVec2],
    ids: &[u64],
    closed: bool,
    p: &MidpointParams,
    levels: u32,
    seed: Seed,
) -> Result<Vec<DVec2>> {
    p.validate()?;
    if levels > 20 {
        return Err(invalid(
            "levels",
            levels,
            "must be at most 20 for polylines",
        ));
    }
    if vertices.len() < 2 {
        return Err(invalid(
            "vertices",
            vertices.len(),
            "a polyline needs at least 2 vertices",
        ));
    }
    if ids.len() != vertices.len() {
        return Err(TerrainError::SizeMismatch {
            what: "vertex ids",
            expected: format!("{} ids", vertices.len()),
            actual: format!("{} ids", ids.len()),
        });
    }
    if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
        return Err(invalid(
            "vertices",
            format!("vertex {i} = {}", vertices[i]),
            "must be finite",
        ));
    }
    let std = p.level_std(levels);
    let nseg = if closed {
        vertices.len()
    } else {
        vertices.len() - 1
    };
    let mut out = Vec::with_capacity(nseg << levels | 1);
    for s in 0..nseg {
        let (i, j) = (s, (s + 1) % vertices.len());
        out.push(vertices[i]);
        out.extend(subdivide_edge(
            vertices[i],
            vertices[j],
            (ids[i], ids[j]),
            &std,
            levels,
            seed,
        ));
    }
    if !closed {
        out.push(vertices[vertices.len() - 1]);
    }
    Ok(out)
}

/// Which FFC grid scheme [`subdivide`] uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SubdivisionScheme {
    /// Fractal triangles (Fournier et al. 1982, §4.1.2): each square of the current lattice is
    /// two triangles split on its `(+1, +1)` diagonal; every new point is an
    /// edge midpoint displaced from the mean of the edge's two endpoints
    /// ("wireframe" displacement, Musgrave et al. 1989, §2.1). Markovian; creases along edges.
    Triangle,
    /// Fournier et al.'s quadrilateral scheme (Fournier et al. 1982, §4.1.2): the four side midpoints by the 1-D
    /// step; for each pair of opposite midpoints, a displaced midpoint of the
    /// segment joining them; the centre is the mean of those two candidates.
    Quad,
    /// Fournier et al.'s non-Markovian grid fill (Fig. 16, Fournier et al. 1982, §4.1.2), i.e. Miller's
    /// diamond-square: centres from the 4 diagonal neighbours, then sides from
    /// the 4 axial neighbours; the edges of each base tile (a patch) use the
    /// 1-D rule, so tiles share edges exactly (Fournier et al. 1982, §4.1.2).
    DiamondSquare,
}

/// Parameters of grid subdivision ([`subdivide`]).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SubdivisionParams {
    /// The midpoint-displacement law (H, scale in metres, corners).
    pub midpoint: MidpointParams,
    /// The scheme.
    pub scheme: SubdivisionScheme,
    /// Subdivision depth: base-lattice corners are `2^levels` cells apart.
    /// `None` picks the smallest depth whose single tile covers the grid.
    pub levels: Option<u32>,
}

impl Default for SubdivisionParams {
    fn default() -> Self {
        Self {
            midpoint: MidpointParams::default(),
            scheme: SubdivisionScheme::DiamondSquare,
            levels: None,
        }
    }
}

impl SubdivisionParams {
    /// Validates the midpoint law and the depth (`levels ≤ 16`).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`] naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        self.midpoint.validate()?;
        if let Some(l) = self.levels
            && l > 16
        {
            return Err(invalid(
                "SubdivisionParams::levels",
                l,
                "must be at most 16 (65 537 cells per tile side)",
            ));
        }
        Ok(())
    }
}

/// Depth whose single tile covers `n` samples (`2^L + 1 ≥ n`).
fn auto_levels(n: usize) -> u32 {
    let mut l = 0;
    while (1usize << l) + 1 < n {
        l += 1;
    }
    l
}

/// Stochastic subdivision into an `nx × ny` height field with `cell_size` metres
/// between samples.
///
/// The lattice of base corners (spacing `2^L` cells, drawn at level 0) tiles
/// the plane; the grid is computed on the whole tiles covering it and cropped,
/// so any size works (no `2^n + 1` restriction). Sample `(i, j)` depends only
/// on `(seed, i / 2^L, j / 2^L)`, so a run with depth `L − k` and
/// `(nx − 1) / 2^k + 1` samples is exactly the fine run subsampled every `2^k`
/// cells. Parallel over rows within each level; bit-identical on any thread count.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`]
/// for a size the method cannot make, and [`TerrainError::Core`] if the field
/// cannot be allocated.
pub fn subdivide(
    nx: usize,
    ny: usize,
    cell_size: f32,
    p: &SubdivisionParams,
    seed: Seed,
) -> Result<HeightField> {
    p.validate()?;
    crate::error::min_size("subdivide", nx, ny, 1, 1)?;
    let levels = p.levels.unwrap_or_else(|| auto_levels(nx.max(ny)));
    let tile = 1usize << levels;
    let tx = (nx - 1).div_ceil(tile).max(1);
    let ty = (ny - 1).div_ceil(tile).max(1);
    let (w, h) = (tx * tile + 1, ty * tile + 1);
    let mut g = Grid2::new(w, h, 0.0f64)?;
    let std = p.midpoint.level_std(levels);
    let seed = seed.derive("ffc-subdivision");
    // Level 0: the base lattice corners.
    for by in 0..=ty {
        for bx in 0..=tx {
            let v = match p.midpoint.endpoints {
                EndpointMode::Random => seed.gaussian(&[0, bx as i64, by as i64, 0]) * std[0],
                EndpointMode::Fixed(a, _) => a,
            };
            g[(bx * tile, by * tile)] = v;
        }
    }
    for l in 1..=levels {
        let s = 1usize << (levels - l);
        let sd = std[l as usize];
        let gauss = |a: usize, b: usize, tag: i64| {
            seed.gaussian(&[i64::from(l), a as i64, b as i64, tag]) * sd
        };
        match p.scheme {
            SubdivisionScheme::Triangle => level_pass(&mut g, s, |g, a, b| {
                let (i, j) = (a * s, b * s);
                let (m, key) = match (a % 2, b % 2) {
                    (1, 0) => ((g[(i - s, j)] + g[(i + s, j)]) / 2.0, 0),
                    (0, 1) => ((g[(i, j - s)] + g[(i, j + s)]) / 2.0, 0),
                    (1, 1) => ((g[(i - s, j - s)] + g[(i + s, j + s)]) / 2.0, 0),
                    _ => return None,
                };
                Some(m + gauss(a, b, key))
            }),
            SubdivisionScheme::Quad => {
                level_pass(&mut g, s, |g, a, b| {
                    let (i, j) = (a * s, b * s);
                    match (a % 2, b % 2) {
                        (1, 0) => Some((g[(i - s, j)] + g[(i + s, j)]) / 2.0 + gauss(a, b, 0)),
                        (0, 1) => Some((g[(i, j - s)] + g[(i, j + s)]) / 2.0 + gauss(a, b, 0)),
                        _ => None,
                    }
                });
                level_pass(&mut g, s, |g, a, b| {
                    if a % 2 == 1 && b % 2 == 1 {
                        let (i, j) = (a * s, b * s);
                        let c1 = (g[(i - s, j)] + g[(i + s, j)]) / 2.0 + gauss(a, b, 1);
                        let c2 = (g[(i, j - s)] + g[(i, j + s)]) / 2.0 + gauss(a, b, 2);
                        Some((c1 + c2) / 2.0)
                    } else {
                        None
                    }
                });
            }
            SubdivisionScheme::DiamondSquare => {
                level_pass(&mut g, s, |g, a, b| {
                    if a % 2 == 1 && b % 2 == 1 {
                        let (i, j) = (a * s, b * s);
                        let m = (g[(i - s, j - s)]
                            + g[(i + s, j - s)]
                            + g[(i - s, j + s)]
                            + g[(i + s, j + s)])
                            / 4.0;
                        Some(m + gauss(a, b, 0))
                    } else {
                        None
                    }
                });
                level_pass(&mut g, s, |g, a, b| {
                    let (i, j) = (a * s, b * s);
                    // Tile edges are patch boundaries computed by the 1-D rule
                    // (Fournier et al. 1982, §4.1.2), so tiles share edges exactly and the result does
                    // not depend on how many tiles the grid spans.
                    let m = match (a % 2, b % 2) {
                        (1, 0) if j % tile == 0 => (g[(i - s, j)] + g[(i + s, j)]) / 2.0,
                        (0, 1) if i % tile == 0 => (g[(i, j - s)] + g[(i, j + s)]) / 2.0,
                        (1, 0) | (0, 1) => {
                            (g[(i - s, j)] + g[(i + s, j)] + g[(i, j - s)] + g[(i, j + s)]) / 4.0
                        }
                        _ => return None,
                    };
                    Some(m + gauss(a, b, 0))
                });
            }
        }
    }
    let heights = Grid2::from_fn(nx, ny, |i, j| g[(i, j)] as f32)?;
    Ok(HeightField::new(heights, cell_size)?)
}

/// One pass over the lattice points of spacing `s`: `f(g, a, b)` returns the new
/// value of point `(a·s, b·s)` or `None` to leave it. Reads see the grid as it
/// was before the pass (values are written after all rows are computed), so the
/// pass is order-independent and parallel over rows.
fn level_pass(
    g: &mut Grid2<f64>,
    s: usize,
    f: impl Fn(&Grid2<f64>, usize, usize) -> Option<f64> + Sync + Send,
) {
    let (w, h) = g.dims();
    let (na, nb) = ((w - 1) / s + 1, (h - 1) / s + 1);
    let rows: Vec<usize> = (0..nb).collect();
    let gr = &*g;
    let updates: Vec<Vec<(usize, f64)>> = bands::run(rows, |b| {
        (0..na)
            .filter_map(|a| f(gr, a, b).map(|v| (a, v)))
            .collect()
    });
    for (b, row) in updates.into_iter().enumerate() {
        for (a, v) in row {
            g[(a * s, b * s)] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_is_two_to_minus_h() {
        let p = MidpointParams {
            h: 0.5,
            scale: 2.0,
            ..Default::default()
        };
        let s = p.level_std(3);
        assert_eq!(s[0], 2.0);
        approx::assert_relative_eq!(s[1], 2.0 * 0.5f64.sqrt(), epsilon = 1e-15);
        approx::assert_relative_eq!(s[3], 2.0 * 0.125f64.sqrt(), epsilon = 1e-15);
    }

    #[test]
    fn one_d_lod_consistency() {
        let p = MidpointParams::default();
        let coarse = midpoint_1d(&p, 4, Seed(3)).unwrap();
        let fine = midpoint_1d(&p, 8, Seed(3)).unwrap();
        assert_eq!(coarse.len(), 17);
        assert_eq!(fine.len(), 257);
        for (k, &c) in coarse.iter().enumerate() {
            assert_eq!(c.to_bits(), fine[k * 16].to_bits());
        }
    }

    #[test]
    fn fixed_endpoints_are_kept() {
        let p = MidpointParams {
            endpoints: EndpointMode::Fixed(1.5, -2.0),
            ..Default::default()
        };
        let f = midpoint_1d(&p, 6, Seed(1)).unwrap();
        assert_eq!(f[0], 1.5);
        assert_eq!(f[64], -2.0);
    }

    #[test]
    fn polyline_keeps_vertices_and_shares_edges() {
        let p = MidpointParams {
            h: 0.7,
            scale: 0.1,
            ..Default::default()
        };
        let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        let out = fractal_polyline(&square, true, &p, 5, Seed(9)).unwrap();
        assert_eq!(out.len(), 4 * 32);
        for (i, v) in square.iter().enumerate() {
            assert_eq!(out[i * 32], *v);
        }
        // The same edge walked backwards by another polyline gives the same points reversed.
        let a =
            fractal_polyline_ids(&[DVec2::X, DVec2::ZERO], &[1, 0], false, &p, 5, Seed(9)).unwrap();
        let first_edge: Vec<_> = out[1..32].iter().rev().copied().collect();
        assert_eq!(&a[1..32], &first_edge[..]);
        // h = 1 and scale → 0 converges to the base polygon.
        let flat = fractal_polyline(
            &square,
            true,
            &MidpointParams {
                h: 1.0,
                scale: 0.0,
                ..Default::default()
            },
            4,
            Seed(9),
        )
        .unwrap();
        assert!(
            flat.iter()
                .all(|v| v.x.min(v.y) >= 0.0 && v.x.max(v.y) <= 1.0)
        );
    }

    #[test]
    fn grid_lod_consistency_every_scheme() {
        for scheme in [
            SubdivisionScheme::Triangle,
            SubdivisionScheme::Quad,
            SubdivisionScheme::DiamondSquare,
        ] {
            let mut p = SubdivisionParams {
                scheme,
                levels: Some(7),
                ..Default::default()
            };
            let fine = subdivide(200, 150, 1.0, &p, Seed(11)).unwrap();
            p.levels = Some(5);
            let coarse = subdivide(50, 38, 4.0, &p, Seed(11)).unwrap();
            for j in 0..38 {
                for i in 0..50 {
                    assert_eq!(
                        coarse.heights()[(i, j)].to_bits(),
                        fine.heights()[(4 * i, 4 * j)].to_bits(),
                        "{scheme:?} at ({i}, {j})"
                    );
                }
            }
        }
    }

    #[test]
    fn refuses_bad_params() {
        let mut p = SubdivisionParams::default();
        p.midpoint.h = 0.0;
        assert!(subdivide(9, 9, 1.0, &p, Seed(1)).is_err());
        p.midpoint.h = f64::NAN;
        assert!(subdivide(9, 9, 1.0, &p, Seed(1)).is_err());
        p.midpoint.h = 0.5;
        p.midpoint.scale = -1.0;
        assert!(subdivide(9, 9, 1.0, &p, Seed(1)).is_err());
        assert!(subdivide(0, 9, 1.0, &SubdivisionParams::default(), Seed(1)).is_err());
        assert!(subdivide(9, 9, f32::NAN, &SubdivisionParams::default(), Seed(1)).is_err());
    }
}
