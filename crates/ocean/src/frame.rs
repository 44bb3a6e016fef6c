//! The fields of an ocean patch at one time, and what follows from them:
//! normals, the Jacobian of the choppy map, its eigen-decomposition and
//! folding (Tessendorf 2001, eqs. 20, 29-36, §3.3 and §3.7).

use glam::{Vec2, Vec3};
use natura_core::Grid2;
use natura_core::fft::Complex;

use crate::error::{OceanError, Result};
use crate::fft::SOURCES;
use crate::patch::Ocean;

/// Per-worker scratch of the FFT passes.
#[derive(Clone, Debug)]
pub(crate) struct Slot {
    pub(crate) rows: Vec<Complex<f32>>,
    pub(crate) scratch: Vec<Complex<f32>>,
    /// One group of columns of each source (padded).
    pub(crate) col: Vec<Complex<f32>>,
}

/// Buffers reused from frame to frame.
#[derive(Clone, Debug)]
pub(crate) struct Workspace {
    pub(crate) cols: [Vec<Complex<f32>>; SOURCES],
    pub(crate) slots: Vec<Slot>,
}

/// The eight real fields of a [`Frame`], in storage order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FrameField {
    /// Height h, metres.
    Height = 0,
    /// Slope ∂h/∂x.
    SlopeX = 1,
    /// Slope ∂h/∂y.
    SlopeY = 2,
    /// Horizontal displacement d_x, metres.
    DispX = 3,
    /// Horizontal displacement d_y, metres.
    DispY = 4,
    /// J_xx = 1 + ∂d_x/∂x.
    Jxx = 5,
    /// J_yy = 1 + ∂d_y/∂y.
    Jyy = 6,
    /// J_xy = ∂d_x/∂y.
    Jxy = 7,
}

impl FrameField {
    /// All fields in storage order.
    pub const ALL: [FrameField; 8] = [
        FrameField::Height,
        FrameField::SlopeX,
        FrameField::SlopeY,
        FrameField::DispX,
        FrameField::DispY,
        FrameField::Jxx,
        FrameField::Jyy,
        FrameField::Jxy,
    ];

    /// Returns a short name (`"height"`, `"slope_x"`, …), used as EXR channel names.
    #[must_use]
    pub fn name(self) -> &'static str {
        [
            "height", "slope_x", "slope_y", "disp_x", "disp_y", "jxx", "jyy", "jxy",
        ][self as usize]
    }
}

const HEIGHT: usize = FrameField::Height as usize;
const SLOPE_X: usize = FrameField::SlopeX as usize;
const SLOPE_Y: usize = FrameField::SlopeY as usize;
const DISP_X: usize = FrameField::DispX as usize;
const DISP_Y: usize = FrameField::DispY as usize;
const JXX: usize = FrameField::Jxx as usize;
const JYY: usize = FrameField::Jyy as usize;
const JXY: usize = FrameField::Jxy as usize;

/// Every field of an ocean patch at one time, on the rest (Lagrangian) grid:
/// sample (i, j) belongs to the water particle whose rest position is
/// (i·Δx, j·Δy) and which is now at (i·Δx + d_x, j·Δy + d_y, h).
///
/// Made by [`Frame::new`] for one [`Ocean`] and refilled by
/// [`Ocean::evaluate_into`] without allocating.
///
/// | field | meaning | source |
/// |---|---|---|
/// | [`height`](Frame::height) | h, metres | eq. 19 |
/// | [`slope_x`](Frame::slope_x), [`slope_y`](Frame::slope_y) | ∇h by FFT | eq. 20 |
/// | [`disp_x`](Frame::disp_x), [`disp_y`](Frame::disp_y) | choppy displacement d | eq. 29, sign-corrected |
/// | [`jxx`](Frame::jxx), [`jyy`](Frame::jyy), [`jxy`](Frame::jxy) | ∂X/∂x of X = x + d | eq. 30 |
#[derive(Clone, Debug)]
pub struct Frame {
    pub(crate) fields: [Grid2<f32>; 8],
    pub(crate) work: Workspace,
    pub(crate) time: f64,
    lx: f64,
    ly: f64,
}

impl Frame {
    /// Allocates a frame (fields and FFT scratch) for `ocean`, all zero.
    ///
    /// With the `parallel` feature the scratch is split for the current
    /// rayon pool's thread count; using the frame in a larger pool uses at
    /// most that many threads. Results never depend on it.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::Core`](crate::OceanError::Core) if the grids exceed natura-core's memory cap.
    pub fn new(ocean: &Ocean) -> Result<Self> {
        let p = ocean.params();
        let (nx, ny) = (p.nx, p.ny);
        let grid = Grid2::new(nx, ny, 0.0f32)?;
        let zero = Complex::new(0.0f32, 0.0);
        let plane = crate::fft::plane_len(nx, ny);
        #[cfg(feature = "parallel")]
        let workers = rayon::current_num_threads().clamp(1, 64);
        #[cfg(not(feature = "parallel"))]
        let workers = 1;
        let scratch = ocean
            .col_fft
            .get_inplace_scratch_len()
            .max(ocean.row_fft.get_inplace_scratch_len());
        let slot = Slot {
            rows: vec![zero; crate::fft::row_buffer_len(nx)],
            scratch: vec![zero; scratch],
            col: vec![zero; crate::fft::group_buffer_len(nx, ny)],
        };
        Ok(Self {
            fields: std::array::from_fn(|_| grid.clone()),
            work: Workspace {
                cols: std::array::from_fn(|_| vec![zero; plane]),
                slots: vec![slot; workers],
            },
            time: 0.0,
            lx: p.lx,
            ly: p.ly,
        })
    }

    pub(crate) fn check_matches(&self, ocean: &Ocean) -> Result<()> {
        let p = ocean.params();
        let (w, h) = self.fields[0].dims();
        let expected_cols = crate::fft::plane_len(p.nx, p.ny);
        if (w, h) != (p.nx, p.ny) || self.work.cols[0].len() != expected_cols {
            return Err(OceanError::SizeMismatch {
                expected: format!("a frame of {} × {}", p.nx, p.ny),
                actual: format!("{w} × {h}"),
            });
        }
        Ok(())
    }

    /// Returns the time the frame was evaluated at, seconds.
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Returns the number of samples (N, M).
    #[must_use]
    pub fn dims(&self) -> (usize, usize) {
        self.fields[0].dims()
    }

    /// Returns the patch size (Lx, Ly), metres.
    #[must_use]
    pub fn extent(&self) -> Vec2 {
        Vec2::new(self.lx as f32, self.ly as f32)
    }

    /// Returns the sample spacing (Δx, Δy), metres.
    #[must_use]
    pub fn cell_size(&self) -> Vec2 {
        let (nx, ny) = self.dims();
        Vec2::new((self.lx / nx as f64) as f32, (self.ly / ny as f64) as f32)
    }

    /// Returns field `f`.
    #[must_use]
    pub fn field(&self, f: FrameField) -> &Grid2<f32> {
        &self.fields[f as usize]
    }

    /// Returns the height h (metres, z up, mean 0).
    #[must_use]
    pub fn height(&self) -> &Grid2<f32> {
        &self.fields[HEIGHT]
    }
    /// Returns the slope ∂h/∂x, computed by FFT (eq. 20; preferred over finite differences, §3.3).
    #[must_use]
    pub fn slope_x(&self) -> &Grid2<f32> {
        &self.fields[SLOPE_X]
    }
    /// Returns the slope ∂h/∂y.
    #[must_use]
    pub fn slope_y(&self) -> &Grid2<f32> {
        &self.fields[SLOPE_Y]
    }
    /// Returns the horizontal displacement d_x (metres); 0 without choppiness.
    #[must_use]
    pub fn disp_x(&self) -> &Grid2<f32> {
        &self.fields[DISP_X]
    }
    /// Returns the horizontal displacement d_y (metres).
    #[must_use]
    pub fn disp_y(&self) -> &Grid2<f32> {
        &self.fields[DISP_Y]
    }
    /// Returns J_xx = 1 + ∂d_x/∂x (eq. 30).
    #[must_use]
    pub fn jxx(&self) -> &Grid2<f32> {
        &self.fields[JXX]
    }
    /// Returns J_yy = 1 + ∂d_y/∂y.
    #[must_use]
    pub fn jyy(&self) -> &Grid2<f32> {
        &self.fields[JYY]
    }
    /// Returns J_xy = ∂d_x/∂y = ∂d_y/∂x (equal because d is a gradient field).
    #[must_use]
    pub fn jxy(&self) -> &Grid2<f32> {
        &self.fields[JXY]
    }

    /// Returns the displaced surface point of sample (i, j):
    /// (i·Δx + d_x, j·Δy + d_y, h).
    #[must_use]
    pub fn position(&self, i: usize, j: usize) -> Vec3 {
        let c = self.cell_size();
        let k = self.fields[0].index(i, j);
        Vec3::new(
            i as f32 * c.x + self.fields[DISP_X].as_slice()[k],
            j as f32 * c.y + self.fields[DISP_Y].as_slice()[k],
            self.fields[HEIGHT].as_slice()[k],
        )
    }

    /// Returns the Jacobian determinant J = J_xx J_yy − J_xy² of sample (i, j)
    /// (eq. 30); J < 0 where the surface folds over itself (§3.7).
    #[must_use]
    pub fn jacobian(&self, i: usize, j: usize) -> f32 {
        let k = self.fields[0].index(i, j);
        let (a, b, c) = (
            self.fields[JXX].as_slice()[k],
            self.fields[JYY].as_slice()[k],
            self.fields[JXY].as_slice()[k],
        );
        a * b - c * c
    }

    /// Returns the grid of Jacobian determinants J.
    #[must_use]
    pub fn jacobian_grid(&self) -> Grid2<f32> {
        let mut g = self.fields[JXX].clone();
        for ((o, &b), &c) in g
            .as_mut_slice()
            .iter_mut()
            .zip(self.fields[JYY].as_slice())
            .zip(self.fields[JXY].as_slice())
        {
            *o = *o * b - c * c;
        }
        g
    }

    /// Returns the eigen-decomposition of the Jacobian at sample (i, j) (eqs. 31-34).
    #[must_use]
    pub fn eigen(&self, i: usize, j: usize) -> JacobianEigen {
        let k = self.fields[0].index(i, j);
        JacobianEigen::new(
            self.fields[JXX].as_slice()[k],
            self.fields[JYY].as_slice()[k],
            self.fields[JXY].as_slice()[k],
        )
    }

    /// Returns whether sample (i, j) is folded (J < 0).
    #[must_use]
    pub fn is_folded(&self, i: usize, j: usize) -> bool {
        self.jacobian(i, j) < 0.0
    }

    /// Returns the unit surface normal (z up) of sample (i, j), for the
    /// choppy surface: the cross product of the tangents
    /// ∂P/∂x = (J_xx, J_xy, ε_x) and ∂P/∂y = (J_xy, J_yy, ε_y), i.e.
    /// (J_xy ε_y − J_yy ε_x, J_xy ε_x − J_xx ε_y, J).
    ///
    /// Without choppiness it is eq. 36's (−ε_x, −ε_y, 1)/√(1 + ε²); the
    /// source gives no normal for the displaced surface (derived here from ∂P/∂x × ∂P/∂y).
    /// Where the surface folds (J < 0) the normal points down, as the
    /// folded sheet does; [`Frame::normal_up`] flips it up instead.
    #[must_use]
    pub fn normal(&self, i: usize, j: usize) -> Vec3 {
        let k = self.fields[0].index(i, j);
        normal_from(
            self.fields[SLOPE_X].as_slice()[k],
            self.fields[SLOPE_Y].as_slice()[k],
            self.fields[JXX].as_slice()[k],
            self.fields[JYY].as_slice()[k],
            self.fields[JXY].as_slice()[k],
        )
    }

    /// Returns [`Frame::normal`] flipped, if needed, to point up (z ≥ 0).
    #[must_use]
    pub fn normal_up(&self, i: usize, j: usize) -> Vec3 {
        let n = self.normal(i, j);
        if n.z < 0.0 { -n } else { n }
    }

    /// Returns the grid of upward normals.
    #[must_use]
    pub fn normals(&self) -> Grid2<Vec3> {
        let (nx, ny) = self.dims();
        let mut g = Grid2::new(nx, ny, Vec3::Z).expect("frame dimensions are valid");
        for j in 0..ny {
            for (i, n) in g.row_mut(j).iter_mut().enumerate() {
                *n = self.normal_up(i, j);
            }
        }
        g
    }

    /// Returns the height variance (1/NM) Σ h², m².
    #[must_use]
    pub fn height_variance(&self) -> f64 {
        let h = self.fields[HEIGHT].as_slice();
        h.iter().map(|&v| f64::from(v) * f64::from(v)).sum::<f64>() / h.len() as f64
    }
}

/// Returns the unit normal from slopes and Jacobian terms (see [`Frame::normal`]).
#[inline]
#[must_use]
pub fn normal_from(ex: f32, ey: f32, jxx: f32, jyy: f32, jxy: f32) -> Vec3 {
    let n = Vec3::new(
        jxy * ey - jyy * ex,
        jxy * ex - jxx * ey,
        jxx * jyy - jxy * jxy,
    );
    let l = n.length();
    if l > 0.0 { n / l } else { Vec3::Z }
}

/// The eigen-decomposition of the symmetric 2 × 2 Jacobian (Tessendorf 2001,
/// eqs. 31-34): J_ab = J₋ ê₋ₐ ê₋ᵦ + J₊ ê₊ₐ ê₊ᵦ with J₋ ≤ J₊.
///
/// Folding means J₋ < 0 while J₊ > 0; ê₋ is the horizontal direction along
/// which the surface folds (§3.7; slides "Choppy waves").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JacobianEigen {
    /// The smaller eigenvalue J₋.
    pub j_minus: f32,
    /// The larger eigenvalue J₊.
    pub j_plus: f32,
    /// Unit eigenvector of J₋.
    pub e_minus: Vec2,
    /// Unit eigenvector of J₊ (orthogonal to `e_minus`).
    pub e_plus: Vec2,
}

impl JacobianEigen {
    /// Decomposes [[`jxx`, `jxy`], [`jxy`, `jyy`]].
    ///
    /// Eq. 32 for the eigenvalues; eqs. 33-34 give ê± = (1, q±)/√(1+q±²),
    /// q± = (J± − J_xx)/J_xy, which is singular when J_xy = 0; the matrix is
    /// then diagonal and the eigenvectors are the axes.
    /// Here ê₊ is computed in whichever of the two equivalent forms is
    /// better conditioned, and ê₋ is its perpendicular.
    #[must_use]
    pub fn new(jxx: f32, jyy: f32, jxy: f32) -> Self {
        let (a, b, c) = (f64::from(jxx), f64::from(jyy), f64::from(jxy));
        let mean = 0.5 * (a + b);
        let r = (0.25 * (a - b) * (a - b) + c * c).sqrt();
        let (jm, jp) = (mean - r, mean + r);
        let e_plus = if c == 0.0 {
            if a >= b {
                glam::DVec2::X
            } else {
                glam::DVec2::Y
            }
        } else if a >= b {
            // (J₊ − J_yy, J_xy) is the same eigenvector as (1, q₊) and does
            // not cancel when J_xx ≥ J_yy.
            glam::DVec2::new(jp - b, c).normalize()
        } else {
            glam::DVec2::new(c, jp - a).normalize()
        };
        let e_minus = glam::DVec2::new(-e_plus.y, e_plus.x);
        Self {
            j_minus: jm as f32,
            j_plus: jp as f32,
            e_minus: e_minus.as_vec2(),
            e_plus: e_plus.as_vec2(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn eigen_decomposition_reconstructs(a in -3.0f32..3.0, b in -3.0f32..3.0, c in -3.0f32..3.0) {
            let e = JacobianEigen::new(a, b, c);
            prop_assert!(e.j_minus <= e.j_plus);
            prop_assert!((e.e_minus.length() - 1.0).abs() < 1e-5);
            prop_assert!(e.e_minus.dot(e.e_plus).abs() < 1e-5);
            // J ê = λ ê for both.
            for (l, v) in [(e.j_minus, e.e_minus), (e.j_plus, e.e_plus)] {
                let jv = Vec2::new(a * v.x + c * v.y, c * v.x + b * v.y);
                prop_assert!((jv - l * v).length() < 1e-4 * (1.0 + a.abs() + b.abs() + c.abs()));
            }
            // det = J₋ J₊ and trace = J₋ + J₊.
            prop_assert!((e.j_minus * e.j_plus - (a * b - c * c)).abs() < 1e-4 * (1.0 + (a * b).abs() + c * c));
            prop_assert!((e.j_minus + e.j_plus - (a + b)).abs() < 1e-4 * (1.0 + a.abs() + b.abs()));
            // Folding (J < 0) coincides with J₋ < 0 < J₊.
            if a * b - c * c < -1e-3 { prop_assert!(e.j_minus < 0.0 && e.j_plus > 0.0); }
        }
    }

    #[test]
    fn diagonal_branch_uses_the_axes() {
        let e = JacobianEigen::new(2.0, -1.0, 0.0);
        assert_eq!((e.j_minus, e.j_plus), (-1.0, 2.0));
        assert!(e.e_plus.abs_diff_eq(Vec2::X, 1e-7));
        assert!(e.e_minus.abs().abs_diff_eq(Vec2::Y, 1e-7));
        let e = JacobianEigen::new(1.0, 1.0, 0.0);
        assert_eq!((e.j_minus, e.j_plus), (1.0, 1.0));
    }

    #[test]
    fn normal_without_chop_is_eq_36() {
        let (ex, ey) = (0.3f32, -0.2f32);
        let n = normal_from(ex, ey, 1.0, 1.0, 0.0);
        let want = Vec3::new(-ex, -ey, 1.0) / (1.0 + ex * ex + ey * ey).sqrt();
        assert!(n.abs_diff_eq(want, 1e-6));
        // Perpendicular to the tangents (1, 0, ε_x) and (0, 1, ε_y).
        assert!(n.dot(Vec3::new(1.0, 0.0, ex)).abs() < 1e-6);
        assert!(n.dot(Vec3::new(0.0, 1.0, ey)).abs() < 1e-6);
    }
}
