//! The flow graph's edges: D8 steepest-descent receivers (O'Callaghan &
//! Mark 1984) with their distances, the roots (outlets and pits) and each
//! cell's donor mask, the neighbour tables they share.

use natura_core::simd::Simd;

use crate::bands;

/// Neighbour offsets in the fixed tie-break order, with distances in cells.
pub(crate) const D8: [(i32, i32, f32); 8] = [
    (1, 0, 1.0),
    (-1, 0, 1.0),
    (0, 1, 1.0),
    (0, -1, 1.0),
    (1, 1, std::f32::consts::SQRT_2),
    (-1, 1, std::f32::consts::SQRT_2),
    (1, -1, std::f32::consts::SQRT_2),
    (-1, -1, std::f32::consts::SQRT_2),
];

/// The eight neighbours in increasing index order (raster order of the 3 × 3
/// block): bit `k` of a donor mask stands for the neighbour at `NB[k]`.
const NB: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// Index offsets of [`NB`] on a grid `nx` wide.
#[inline]
pub(super) fn nb_offsets(nx: usize) -> [isize; 8] {
    NB.map(|(dx, dy)| dy * nx as isize + dx)
}

/// The bit of neighbour `d` in the donor mask of cell `r` (8-neighbours).
#[inline]
pub(super) fn nb_bit(r: usize, d: usize, nx: usize) -> u8 {
    let dx = (d % nx) as isize - (r % nx) as isize;
    let dy = (d / nx) as isize - (r / nx) as isize;
    let idx = (dy + 1) * 3 + (dx + 1);
    debug_assert!((0..9).contains(&idx) && idx != 4, "not a neighbour");
    1u8 << (idx - isize::from(idx > 4))
}

/// Distance in cells between neighbours `i` and `j` (1 or √2).
pub(super) fn cell_distance(i: usize, j: usize, nx: usize) -> f32 {
    let (dx, dy) = (
        (i % nx) as i64 - (j % nx) as i64,
        (i / nx) as i64 - (j / nx) as i64,
    );
    if dx != 0 && dy != 0 {
        std::f32::consts::SQRT_2
    } else {
        1.0
    }
}

/// D8 steepest-descent receivers and distances (cells); edge cells are outlets.
#[cfg(test)]
pub(super) fn d8_receivers(h: &[f32], nx: usize, ny: usize) -> (Vec<u32>, Vec<f32>) {
    let (mut rec, mut dist) = (Vec::new(), Vec::new());
    d8_receivers_into(Simd::best(), h, nx, ny, &mut rec, &mut dist);
    (rec, dist)
}

/// D8 steepest-descent receivers and distances (cells) into reusable buffers
/// (resized to `nx × ny`); edge cells are outlets. The interior of each row
/// goes through [`d8_row`] at the instruction set `simd`.
pub(crate) fn d8_receivers_into(
    simd: Simd,
    h: &[f32],
    nx: usize,
    ny: usize,
    rec: &mut Vec<u32>,
    dist: &mut Vec<f32>,
) {
    let n = nx * ny;
    rec.resize(n, 0);
    dist.resize(n, 0.0);
    // Receivers and distances of each band of rows in one task.
    let chunk = nx * bands::BAND_ROWS;
    let jobs: Vec<_> = rec
        .chunks_mut(chunk.max(1))
        .zip(dist.chunks_mut(chunk.max(1)))
        .enumerate()
        .collect();
    bands::run(jobs, |(b, (r, d))| {
        let y0 = b * bands::BAND_ROWS;
        for (y, (row, drow)) in (y0..).zip(r.chunks_mut(nx).zip(d.chunks_mut(nx))) {
            let i0 = y * nx;
            if y == 0 || y == ny - 1 || nx < 3 {
                // Edge cells are outlets.
                for (x, v) in row.iter_mut().enumerate() {
                    *v = (i0 + x) as u32;
                }
                drow.fill(0.0);
            } else {
                row[0] = i0 as u32;
                row[nx - 1] = (i0 + nx - 1) as u32;
                drow[0] = 0.0;
                drow[nx - 1] = 0.0;
                d8_row(
                    simd,
                    h,
                    i0 + 1,
                    nx,
                    &mut row[1..nx - 1],
                    &mut drow[1..nx - 1],
                );
            }
        }
    });
}

natura_core::simd::multiversion! {
/// D8 steepest descent for the interior cells `i0..i0 + out.len()` of one
/// row (all eight neighbours exist), with the distance to the receiver
/// (cells; 0 for a pit) into `dist`: the same divisions and comparisons, in
/// the order of [`D8`], as a per-cell loop (dividing by an axial distance of
/// 1 is the identity), written over row slices so it vectorises.
fn d8_row<'a>(simd: Simd, h: &'a [f32], i0: usize, nx: usize, out: &'a mut [u32], dist: &'a mut [f32]) {
    let m = out.len();
    let dist = &mut dist[..m];
    let at = |o: usize| &h[o..o + m];
    let c = at(i0);
    let (e, w, n, s) = (at(i0 + 1), at(i0 - 1), at(i0 + nx), at(i0 - nx));
    let (ne, nw, se, sw) = (at(i0 + nx + 1), at(i0 + nx - 1), at(i0 - nx + 1), at(i0 - nx - 1));
    let r2 = std::f32::consts::SQRT_2;
    let nx32 = nx as u32;
    for x in 0..m {
        let hi = c[x];
        let i = (i0 + x) as u32;
        let mut slope = 0.0f32;
        let mut best = i;
        let mut bd = 0.0f32;
        let mut step = |s: f32, j: u32, d: f32| {
            if s > slope {
                slope = s;
                best = j;
                bd = d;
            }
        };
        step(hi - e[x], i + 1, 1.0);
        step(hi - w[x], i - 1, 1.0);
        step(hi - n[x], i + nx32, 1.0);
        step(hi - s[x], i - nx32, 1.0);
        step((hi - ne[x]) / r2, i + nx32 + 1, r2);
        step((hi - nw[x]) / r2, i + nx32 - 1, r2);
        step((hi - se[x]) / r2, i - nx32 + 1, r2);
        step((hi - sw[x]) / r2, i - nx32 - 1, r2);
        out[x] = best;
        dist[x] = bd;
    }
}
}

/// Cells that are their own receiver (outlets and pits), in increasing order.
pub(super) fn find_roots(rec: &[u32], nx: usize, ny: usize, roots: &mut Vec<u32>) {
    let bands = bands::reduce_bands(ny, |y0, y1| {
        (y0 * nx..y1 * nx)
            .filter(|&i| rec[i] as usize == i)
            .map(|i| i as u32)
            .collect::<Vec<u32>>()
    });
    roots.clear();
    for b in bands {
        roots.extend_from_slice(&b);
    }
}

/// Donor masks of every cell: bit `k` set when the neighbour at [`NB`]`[k]`
/// has this cell as its receiver. Pure per cell, in parallel over bands.
pub(super) fn donor_masks_into(simd: Simd, rec: &[u32], nx: usize, ny: usize, masks: &mut Vec<u8>) {
    masks.resize(nx * ny, 0);
    bands::map_bands(nx, ny, [masks.as_mut_slice()], |y0, y1, [m]| {
        for y in y0..y1 {
            let row = &mut m[(y - y0) * nx..(y - y0 + 1) * nx];
            let general = |x: usize| {
                let i = y * nx + x;
                let mut bits = 0u8;
                for (k, &(dx, dy)) in NB.iter().enumerate() {
                    let (xj, yj) = (x as isize + dx, y as isize + dy);
                    if xj >= 0 && yj >= 0 && (xj as usize) < nx && (yj as usize) < ny {
                        let j = yj as usize * nx + xj as usize;
                        if rec[j] as usize == i {
                            bits |= 1 << k;
                        }
                    }
                }
                bits
            };
            if y == 0 || y + 1 == ny || nx < 3 {
                for (x, v) in row.iter_mut().enumerate() {
                    *v = general(x);
                }
            } else {
                row[0] = general(0);
                row[nx - 1] = general(nx - 1);
                let rows = [
                    &rec[(y - 1) * nx..y * nx],
                    &rec[y * nx..(y + 1) * nx],
                    &rec[(y + 1) * nx..(y + 2) * nx],
                ];
                masks_row(simd, rows, (y * nx) as u32, &mut row[1..nx - 1]);
            }
        }
    });
}

natura_core::simd::multiversion! {
/// Donor masks of the interior cells `1..nx − 1` of a row whose first cell
/// has index `i0`, from the receivers of the rows below, at and above it.
fn masks_row<'a>(simd: Simd, rows: [&'a [u32]; 3], i0: u32, out: &'a mut [u8]) {
    let m = out.len();
    let [dn, md, up] = rows;
    let (d0, d1, d2) = (&dn[..m], &dn[1..m + 1], &dn[2..m + 2]);
    let (m0, m2) = (&md[..m], &md[2..m + 2]);
    let (u0, u1, u2) = (&up[..m], &up[1..m + 1], &up[2..m + 2]);
    for x in 0..m {
        let i = i0 + 1 + x as u32;
        out[x] = u8::from(d0[x] == i)
            | u8::from(d1[x] == i) << 1
            | u8::from(d2[x] == i) << 2
            | u8::from(m0[x] == i) << 3
            | u8::from(m2[x] == i) << 4
            | u8::from(u0[x] == i) << 5
            | u8::from(u1[x] == i) << 6
            | u8::from(u2[x] == i) << 7;
    }
}
}
