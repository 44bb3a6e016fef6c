//! The batch path of [`GridDensity::sample`](super::GridDensity::sample):
//! the same trilinear interpolation ([`super::trilinear`]) over `f32` lanes,
//! compiled for the CPU's widest SIMD level by natura-simd's
//! `multiversion!`. The lattice coordinates, weights and voxel indices are
//! computed a chunk at a time in vectorisable loops, the eight corners read
//! one lane at a time, and the blends vectorised again. A point whose eight
//! corners are not all inside the grid (or whose coordinates are NaN) takes
//! the point path. Every step is the point path's own arithmetic (no fused
//! multiply-adds, exactly rounded `floor`), so each level gives its bits.

use glam::Vec3;
use natura_core::simd::{Simd, multiversion};

use super::trilinear;

/// Points per chunk (stack scratch, zeroed per chunk: the march fetches 16
/// at a time).
const CHUNK: usize = 16;

/// Where a grid's voxels are: what the kernel needs of a
/// [`GridDensity`](super::GridDensity).
#[derive(Clone, Copy, Debug)]
pub(super) struct Layout {
    pub origin: Vec3,
    pub inv_cell: f32,
    /// The grid's dimensions as `f32` (exact: each is below `2²⁴`).
    pub dims: [f32; 3],
    /// Voxels per row and per slice.
    pub sy: i32,
    pub sz: i32,
}

impl Layout {
    /// Whether the lanes can index the grid with `i32` and compare
    /// coordinates with exact `f32` dimensions.
    pub(super) fn fits(nx: usize, ny: usize, nz: usize) -> bool {
        let small = |n: usize| n < (1 << 24);
        small(nx) && small(ny) && small(nz) && nx * ny * nz < i32::MAX as usize
    }
}

/// The grid's trilinear samples at `(x[i], y[i], z[i])` into `out` (equal
/// lengths), bit for bit as the point path; `point` is that path, used for
/// the points whose corners are not all inside; `simd` the level of the
/// kernels.
#[allow(clippy::too_many_arguments)]
pub(super) fn samples(
    simd: Simd,
    layout: &Layout,
    voxels: &[f32],
    x: &[f32],
    y: &[f32],
    z: &[f32],
    out: &mut [f32],
    point: impl Fn(Vec3) -> f32,
) {
    for s in (0..out.len()).step_by(CHUNK) {
        let e = (s + CHUNK).min(out.len());
        let (x, y, z, out) = (&x[s..e], &y[s..e], &z[s..e], &mut out[s..e]);
        let mut index = [0i32; CHUNK];
        let mut t = [[0.0f32; CHUNK]; 3];
        let n = out.len();
        locate(simd, layout, x, y, z, &mut index[..n], &mut t);
        // The corners, one lane at a time (a lane outside reads nothing).
        let mut c = [[0.0f32; CHUNK]; 8];
        let (sy, sz) = (layout.sy as usize, layout.sz as usize);
        for (l, &i) in index[..n].iter().enumerate() {
            if i < 0 {
                continue;
            }
            let i = i as usize;
            let pair = |k: usize| voxels.get(k..k + 2).map_or([0.0; 2], |v| [v[0], v[1]]);
            [c[0][l], c[1][l]] = pair(i);
            [c[2][l], c[3][l]] = pair(i + sy);
            [c[4][l], c[5][l]] = pair(i + sz);
            [c[6][l], c[7][l]] = pair(i + sy + sz);
        }
        blend(simd, &c, &t, out);
        for (l, &i) in index[..n].iter().enumerate() {
            if i < 0 {
                out[l] = point(Vec3::new(x[l], y[l], z[l]));
            }
        }
    }
}

multiversion! {
    /// Each lane's lattice weights `t` and the index of its lowest corner,
    /// or −1 where its eight corners are not all inside the grid.
    fn locate<'a>(
        simd: Simd,
        layout: &'a Layout,
        x: &'a [f32],
        y: &'a [f32],
        z: &'a [f32],
        index: &'a mut [i32],
        t: &'a mut [[f32; CHUNK]; 3],
    ) {
        let (o, s) = (layout.origin, layout.inv_cell);
        let [nx, ny, nz] = layout.dims;
        let n = index.len().min(x.len()).min(y.len()).min(z.len());
        for l in 0..n {
            // The point path's `(p − origin)·(1/cell) − ½`, axis by axis.
            let (qx, qy, qz) = ((x[l] - o.x) * s - 0.5, (y[l] - o.y) * s - 0.5, (z[l] - o.z) * s - 0.5);
            let (fx, fy, fz) = (qx.floor(), qy.floor(), qz.floor());
            t[0][l] = qx - fx;
            t[1][l] = qy - fy;
            t[2][l] = qz - fz;
            // False for NaN coordinates.
            let inside = fx >= 0.0
                && fy >= 0.0
                && fz >= 0.0
                && fx + 1.0 < nx
                && fy + 1.0 < ny
                && fz + 1.0 < nz;
            let i = (fz as i32).wrapping_mul(layout.sz)
                .wrapping_add((fy as i32).wrapping_mul(layout.sy))
                .wrapping_add(fx as i32);
            index[l] = if inside { i } else { -1 };
        }
    }
}

multiversion! {
    /// The trilinear blend of each lane's corners `c` with weights `t`.
    fn blend<'a>(
        simd: Simd,
        c: &'a [[f32; CHUNK]; 8],
        t: &'a [[f32; CHUNK]; 3],
        out: &'a mut [f32],
    ) {
        let n = out.len().min(CHUNK);
        for l in 0..n {
            out[l] = trilinear(
                [c[0][l], c[1][l], c[2][l], c[3][l], c[4][l], c[5][l], c[6][l], c[7][l]],
                Vec3::new(t[0][l], t[1][l], t[2][l]),
            );
        }
    }
}
