//! Flow directions, flow accumulation (D8 and multiple-flow-direction),
//! drainage-network extraction, Strahler order and the topographic wetness
//! index. Depressions are handled first (see [`super::flow`]) so flow reaches
//! the grid edge, as the "rain-water flow" moisture map of TerEdit needs
//! (Deussen et al. 1998, §4.2).

use natura_core::{Grid2, HeightField};

use super::flow::{D8, Depressions, FlowGraph};
use crate::error::{Result, invalid};

/// ESRI-style D8 codes by neighbour `(dx, dy)`, with north = +y:
/// E = 1, SE = 2, S = 4, SW = 8, W = 16, NW = 32, N = 64, NE = 128; 0 = outlet.
fn d8_code(dx: i64, dy: i64) -> u8 {
    match (dx, dy) {
        (1, 0) => 1,
        (1, -1) => 2,
        (0, -1) => 4,
        (-1, -1) => 8,
        (-1, 0) => 16,
        (-1, 1) => 32,
        (0, 1) => 64,
        (1, 1) => 128,
        _ => 0,
    }
}

/// D8 flow direction of every cell as ESRI codes (north = +y; 0 for edge outlets).
/// Depressions are routed (`Route`) or filled (`Fill`) first, or kept.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated. A NaN or infinite height is
/// [`TerrainError::Core`](crate::TerrainError::Core) naming the cell.
pub fn d8_directions(hf: &HeightField, depressions: Depressions) -> Result<Grid2<u8>> {
    let (g, _) = graph(hf, depressions)?;
    let nx = hf.nx();
    Ok(Grid2::from_fn(nx, hf.ny(), |x, y| {
        let i = y * nx + x;
        let r = g.receiver[i] as usize;
        d8_code((r % nx) as i64 - x as i64, (r / nx) as i64 - y as i64)
    })?)
}

fn graph(hf: &HeightField, depressions: Depressions) -> Result<(FlowGraph, Vec<f32>)> {
    hf.check_finite()?;
    let mut h = hf.heights().as_slice().to_vec();
    let g = FlowGraph::build(&mut h, hf.nx(), hf.ny(), depressions)?;
    Ok((g, h))
}

/// D8 flow accumulation: drainage area of every cell, m² (the cell itself included).
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated. A NaN or infinite height is
/// [`TerrainError::Core`](crate::TerrainError::Core) naming the cell.
pub fn flow_accumulation_d8(hf: &HeightField, depressions: Depressions) -> Result<Grid2<f32>> {
    let (g, _) = graph(hf, depressions)?;
    let a = f32::powi(hf.cell_size(), 2);
    Ok(Grid2::from_vec(
        hf.nx(),
        hf.ny(),
        g.area().into_iter().map(|c| c * a).collect(),
    )?)
}

/// Multiple-flow-direction accumulation (Freeman 1991; Quinn et al. 1991):
/// each cell passes its area to all lower neighbours in proportion to
/// `slope^exponent` (Freeman recommends 1.1). Depressions are filled first;
/// edge cells are outlets. Area in m².
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated. A NaN or infinite height is
/// [`TerrainError::Core`](crate::TerrainError::Core) naming the cell; an exponent outside (0, 100] is
/// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter).
pub fn flow_accumulation_mfd(hf: &HeightField, exponent: f64) -> Result<Grid2<f32>> {
    if !(exponent.is_finite() && exponent > 0.0 && exponent <= 100.0) {
        return Err(invalid("exponent", exponent, "must lie in (0, 100]"));
    }
    let (_, h) = graph(hf, Depressions::Fill)?;
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut order: Vec<u32> = (0..(nx * ny) as u32).collect();
    // Highest first, ties by index: a total order, so the parallel sort
    // gives the serial one's order.
    let higher = |a: &u32, b: &u32| h[*b as usize].total_cmp(&h[*a as usize]).then(a.cmp(b));
    #[cfg(feature = "parallel")]
    {
        use rayon::slice::ParallelSliceMut;
        order.par_sort_unstable_by(higher);
    }
    #[cfg(not(feature = "parallel"))]
    order.sort_unstable_by(higher);
    // The split of a cell's area depends on the heights alone: the weights
    // (a power each) are computed for a block of cells at once, in
    // parallel, and the areas then pass down the block in order, with the
    // same arithmetic as one cell at a time.
    let weights = |i: usize| {
        let (x, y) = (i % nx, i / nx);
        let mut w = [0.0f64; 8];
        let mut total = 0.0;
        if x == 0 || y == 0 || x == nx - 1 || y == ny - 1 {
            return (w, total);
        }
        for (k, &(dx, dy, d)) in D8.iter().enumerate() {
            let j = (i as i64 + i64::from(dy) * nx as i64 + i64::from(dx)) as usize;
            let s = f64::from(h[i] - h[j]) / f64::from(d);
            if s > 0.0 {
                w[k] = s.powf(exponent);
                total += w[k];
            }
        }
        (w, total)
    };
    let mut acc = vec![1.0f64; nx * ny];
    for block in order.chunks(1 << 15) {
        let split = crate::bands::run(block.chunks(1 << 11).collect(), |part: &[u32]| {
            part.iter()
                .map(|&i| weights(i as usize))
                .collect::<Vec<_>>()
        });
        for (&i, (w, total)) in block.iter().zip(split.iter().flatten()) {
            let i = i as usize;
            if *total > 0.0 {
                let a = acc[i];
                for (k, &(dx, dy, _)) in D8.iter().enumerate() {
                    if w[k] > 0.0 {
                        let j = (i as i64 + i64::from(dy) * nx as i64 + i64::from(dx)) as usize;
                        acc[j] += a * w[k] / *total;
                    }
                }
            }
        }
    }
    let cell = f64::from(hf.cell_size()).powi(2);
    Ok(Grid2::from_vec(
        nx,
        ny,
        acc.into_iter().map(|a| (a * cell) as f32).collect(),
    )?)
}

/// Channel mask: cells whose drainage area is at least `threshold_m2`.
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) unless the
/// threshold is finite and positive, and [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
pub fn channel_network(area: &Grid2<f32>, threshold_m2: f32) -> Result<Grid2<bool>> {
    if !(threshold_m2.is_finite() && threshold_m2 > 0.0) {
        return Err(invalid(
            "threshold_m2",
            threshold_m2,
            "must be finite and > 0",
        ));
    }
    Ok(area.map(|&a| a >= threshold_m2))
}

/// Strahler stream order of the D8 channel network (cells with drainage area
/// ≥ `threshold_m2`; 0 off the network). Depressions are routed first.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
pub fn strahler_order(hf: &HeightField, threshold_m2: f32) -> Result<Grid2<u8>> {
    if !(threshold_m2.is_finite() && threshold_m2 > 0.0) {
        return Err(invalid(
            "threshold_m2",
            threshold_m2,
            "must be finite and > 0",
        ));
    }
    let (g, _) = graph(hf, Depressions::Route)?;
    let cell = f32::powi(hf.cell_size(), 2);
    let area = g.area();
    let n = area.len();
    let mut order = vec![0u8; n];
    let mut max_in = vec![0u8; n];
    let mut count_max = vec![0u8; n];
    for &i in g.stack.iter().rev() {
        let i = i as usize;
        if area[i] * cell < threshold_m2 {
            continue;
        }
        order[i] = match count_max[i] {
            0 => 1,
            1 => max_in[i],
            _ => max_in[i].saturating_add(1),
        };
        let r = g.receiver[i] as usize;
        if r != i {
            if order[i] > max_in[r] {
                max_in[r] = order[i];
                count_max[r] = 1;
            } else if order[i] == max_in[r] {
                count_max[r] = count_max[r].saturating_add(1);
            }
        }
    }
    Ok(Grid2::from_vec(hf.nx(), hf.ny(), order)?)
}

/// Topographic wetness index `ln(a / tan β)` (Beven & Kirkby 1979), with `a`
/// the drainage area per unit contour width (area / cell size) and `β` the
/// local slope, floored at `tan β = 10⁻³` so flats stay finite.
///
/// # Errors
///
/// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if `area` is not the field's size, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if the grid cannot be allocated.
pub fn wetness_index(hf: &HeightField, area: &Grid2<f32>) -> Result<Grid2<f32>> {
    crate::error::same_size("area", area, hf.nx(), hf.ny())?;
    let c = hf.cell_size();
    Ok(Grid2::from_fn(hf.nx(), hf.ny(), |x, y| {
        let tan = hf.gradient_at_sample(x, y).length().max(1e-3);
        (area[(x, y)] / c / tan).max(1e-6).ln()
    })?)
}

/// The exponent of the multiple-flow-direction routing under [`wetness`]:
/// 1.1, the value Freeman 1991 recommends.
pub const WETNESS_MFD_EXPONENT: f64 = 1.1;

/// The wetness of a terrain in `[0, 1]`: the topographic wetness index
/// `ln(a / tan β)` of Beven & Kirkby 1979 ([`wetness_index`]) over the
/// multiple-flow-direction drainage area of Freeman 1991
/// ([`flow_accumulation_mfd`] with exponent [`WETNESS_MFD_EXPONENT`]),
/// rescaled linearly so the driest sample of the field is 0 and the wettest
/// 1 (0.5 everywhere if the index is the same everywhere). The rescaling is
/// natura's own: it stands in for the soil-humidity map of Deussen et al.
/// 1998, §4.2, whose species preferences are relative to their terrain.
///
/// This is natura's one wetness model: the materials a scene is shaded with
/// and the ecosystem its forest grows from read the same map.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is
/// too small for the flow graph, and [`TerrainError::Core`](crate::TerrainError::Core)
/// naming the first NaN or infinite height, or if a grid cannot be allocated.
pub fn wetness(hf: &HeightField) -> Result<Grid2<f32>> {
    let area = flow_accumulation_mfd(hf, WETNESS_MFD_EXPONENT)?;
    let twi = wetness_index(hf, &area)?;
    let (lo, hi) = (twi.min(), twi.max());
    let span = hi - lo;
    Ok(twi.map(|&v| if span > 0.0 { (v - lo) / span } else { 0.5 }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The blocked, parallel accumulation against the plain one: each cell
    /// in height order passing its area to its lower neighbours by their
    /// slopes' powers, one at a time. The same bits, over more than one
    /// block of cells.
    #[test]
    fn mfd_in_blocks_is_the_cell_by_cell_accumulation() {
        let (nx, ny) = (230, 190);
        let s = crate::Seed(5);
        let hf = HeightField::from_fn(nx, ny, 3.0, |i, j| {
            let (x, y) = (i as f32, j as f32);
            40.0 * (x / 37.0).sin() * (y / 23.0).cos()
                + 0.05 * (x + y)
                + 5.0 * s.uniform2(i as i64, j as i64) as f32
        })
        .unwrap();
        let fast = flow_accumulation_mfd(&hf, 1.1).unwrap();
        let (_, h) = graph(&hf, Depressions::Fill).unwrap();
        let mut order: Vec<usize> = (0..nx * ny).collect();
        order.sort_by(|&a, &b| h[b].total_cmp(&h[a]).then(a.cmp(&b)));
        let mut acc = vec![1.0f64; nx * ny];
        for &i in &order {
            let (x, y) = (i % nx, i / nx);
            if x == 0 || y == 0 || x == nx - 1 || y == ny - 1 {
                continue;
            }
            let nb =
                |dx: i32, dy: i32| (i as i64 + i64::from(dy) * nx as i64 + i64::from(dx)) as usize;
            let mut w = [0.0f64; 8];
            let mut total = 0.0;
            for (k, &(dx, dy, d)) in D8.iter().enumerate() {
                let sl = f64::from(h[i] - h[nb(dx, dy)]) / f64::from(d);
                if sl > 0.0 {
                    w[k] = sl.powf(1.1);
                    total += w[k];
                }
            }
            if total > 0.0 {
                let a = acc[i];
                for (k, &(dx, dy, _)) in D8.iter().enumerate() {
                    if w[k] > 0.0 {
                        acc[nb(dx, dy)] += a * w[k] / total;
                    }
                }
            }
        }
        let cell = 9.0f64;
        for (k, &a) in acc.iter().enumerate() {
            let want = (a * cell) as f32;
            assert_eq!(fast.as_slice()[k].to_bits(), want.to_bits(), "cell {k}");
        }
        assert!(fast.as_slice().iter().any(|&a| a > 1000.0 * 9.0));
    }

    #[test]
    fn plane_accumulates_downhill() {
        // A plane tilted toward -x: every column drains west; D8 and MFD agree on totals.
        let hf = HeightField::from_fn(16, 10, 1.0, |i, _| i as f32).unwrap();
        let d8 = flow_accumulation_d8(&hf, Depressions::Fill).unwrap();
        assert_eq!(d8[(1, 5)], 14.0);
        let mfd = flow_accumulation_mfd(&hf, 1.1).unwrap();
        // Everything ends on the edge outlets: their areas sum to the whole grid.
        let edge: f32 = (0..10)
            .flat_map(|y| (0..16).map(move |x| (x, y)))
            .filter(|&(x, y)| x == 0 || y == 0 || x == 15 || y == 9)
            .map(|p| mfd[p])
            .sum();
        assert!((edge - 160.0).abs() < 1e-3, "{edge}");
        assert!(mfd[(0, 5)] > mfd[(15, 5)]);
        let dirs = d8_directions(&hf, Depressions::Fill).unwrap();
        assert_eq!(dirs[(5, 5)], 16);
        let so = strahler_order(&hf, 3.0).unwrap();
        assert_eq!(so[(1, 5)], 1);
        let w = wetness_index(&hf, &d8).unwrap();
        assert!(w[(1, 5)] > w[(14, 5)]);
        assert!(channel_network(&d8, 0.0).is_err());
    }

    #[test]
    fn wetness_is_the_rescaled_index_over_mfd_area() {
        // A valley along y: wettest in its floor, driest on the ridges.
        let hf = HeightField::from_fn(33, 25, 10.0, |i, j| {
            (i as f32 - 16.0).abs() * 3.0 + j as f32 * 0.5
        })
        .unwrap();
        let w = wetness(&hf).unwrap();
        let twi = wetness_index(&hf, &flow_accumulation_mfd(&hf, 1.1).unwrap()).unwrap();
        let (lo, hi) = (twi.min(), twi.max());
        for (a, b) in w.as_slice().iter().zip(twi.as_slice()) {
            assert_eq!(*a, (b - lo) / (hi - lo));
        }
        assert_eq!((w.min(), w.max()), (0.0, 1.0));
        assert!(w[(16, 12)] > w[(4, 12)]);
        // A flat field: the routing across its flats still orders it.
        let flat = HeightField::flat(8, 8, 1.0, 3.0).unwrap();
        let f = wetness(&flat).unwrap();
        assert!(f.as_slice().iter().all(|v| (0.0..=1.0).contains(v)));
        let mut nan = flat.clone();
        nan.heights_mut()[(2, 2)] = f32::NAN;
        assert!(wetness(&nan).is_err());
    }

    #[test]
    fn strahler_confluence() {
        // Two valleys meeting: a V along x draining to y = 0.
        let hf = HeightField::from_fn(21, 21, 1.0, |i, j| {
            (i as f32 - 10.0).abs() * 2.0
                + j as f32 * 0.5
                + if (i as i32 - 5).abs() < 1 || (i as i32 - 15).abs() < 1 {
                    -1.0
                } else {
                    0.0
                }
        })
        .unwrap();
        let so = strahler_order(&hf, 2.0).unwrap();
        assert!(so.as_slice().iter().copied().max().unwrap() >= 2);
    }
}
