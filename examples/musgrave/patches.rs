//! Musgrave's terrain-model plates as rendered patches: the patch whose
//! fractal dimension goes from 2 to 3 (Pl. 2.3), statistics by altitude
//! with "Spirit Lake" (Pl. 2.4–2.5), the ridge by position (Pl. 2.6),
//! Terrain() (Pl. 2.8) and "Hell" (Pl. 2.9). Each composes one of
//! natura-noise's (or natura-texture's) models into a height field and
//! draws it with flat Lambert facets from the front and above, as the
//! planar-to-space-filling patch of Pl. 2.2 is drawn.

use std::sync::Arc;

use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::core::preview::{PreviewCamera, PreviewProjection, Projector, Raster, facing, lambert};
use natura::core::{HeightField, Image};
use natura::noise::{
    Driven, DrivenKind, Fade, Field, HeteroTerrain, HeteroTerrainParams, Param, Perlin, Ridged,
    Spectral, StatsByAltitude, StatsByAltitudeParams,
};
use natura::texture::Footprint;
use natura::texture::earth::{Ridge, RidgeParams};

use super::R;

/// How a facet looks: its albedo under the sun and the light it emits.
pub(crate) struct Facet {
    pub albedo: Vec3,
    pub emission: Vec3,
}

/// A height field as triangles, two per cell.
pub(crate) fn field_mesh(hf: &HeightField) -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let (nx, ny) = (hf.nx(), hf.ny());
    let pos = (0..nx * ny).map(|k| hf.point(k % nx, k / nx)).collect();
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let v = |a: usize, b: usize| b * nx + a;
            tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    (pos, tris)
}

/// The patch seen from the front and above (`size` pixels, 2 × 2 samples
/// a pixel, a 20° lens), each facet flat-shaded by the sun from the front
/// left, `look` giving its albedo and emission from its centre and
/// normal, over `background`.
pub(crate) fn render_patch(
    hf: &HeightField,
    size: (u32, u32),
    background: Vec3,
    look: &dyn Fn(Vec3, Vec3) -> Facet,
) -> R<Image> {
    let (lo, hi) = hf.heights().min_max();
    let (pos, tris) = field_mesh(hf);
    let extent = Vec3::new(hf.nx() as f32, hf.ny() as f32, 0.0) * hf.cell_size();
    let mut cam = PreviewCamera::framing(
        Vec3::new(0.0, 0.0, lo),
        Vec3::new(extent.x, extent.y, hi),
        Vec3::new(0.0, 1.0, -0.85),
        Some(30.0),
        size.0 as f32 / size.1 as f32,
    )?;
    cam.projection = PreviewProjection::Perspective { fov_y_deg: 20.0 };
    let mut frame = Raster::new(size.0, size.1, 2, background)?;
    let (w, h) = frame.samples();
    let view = Projector::new(&cam, w, h)?;
    let screen: Vec<Option<[f32; 3]>> = pos.iter().map(|&p| view.project(p)).collect();
    let light = Vec3::new(-0.5, -0.6, 0.62).normalize();
    for t in &tris {
        let [a, b, c] = *t;
        let (Some(pa), Some(pb), Some(pc)) = (screen[a], screen[b], screen[c]) else {
            continue;
        };
        let centre = (pos[a] + pos[b] + pos[c]) / 3.0;
        let nrm = (pos[b] - pos[a]).cross(pos[c] - pos[a]).normalize_or_zero();
        let f = look(centre, nrm);
        let col = f.albedo * lambert(facing(nrm, view.to_viewer(centre)), light, 0.2) + f.emission;
        frame.triangle([pa, pb, pc], |_| col)?;
    }
    Ok(frame.resolve()?)
}

/// A patch of `n` × `n/2` samples over x in (0, 1] (x = (i + 1)/n) and y in
/// (0, ½], the field `f` at `span` lattice units per patch width, its
/// heights rescaled to run from 0 to `relief` patch widths.
fn unit_patch(f: &dyn Field, n: usize, span: f64, relief: f64) -> R<HeightField> {
    let ny = n / 2;
    let raw: Vec<f64> = (0..n * ny)
        .map(|k| {
            let p = DVec2::new(((k % n) + 1) as f64, ((k / n) + 1) as f64) / n as f64;
            f.eval2(p * span)
        })
        .collect();
    rescaled(&raw, (n, ny), 1.0 / n as f32, relief)
}

/// `raw` (row by row, `n` × `ny`) rescaled to heights in `[0, relief]`,
/// samples `cell` apart.
pub(crate) fn rescaled(
    raw: &[f64],
    (n, ny): (usize, usize),
    cell: f32,
    relief: f64,
) -> R<HeightField> {
    let (lo, hi) = raw
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let scale = if hi > lo { relief / (hi - lo) } else { 0.0 };
    Ok(HeightField::from_fn(n, ny, cell, |i, j| {
        ((raw[j * n + i] - lo) * scale) as f32
    })?)
}

/// `hf` filled flat up to the height below which a fraction `q` of its
/// samples lie (a lake, a lava sea): `(filled, that level)`.
fn filled(hf: &HeightField, q: f64) -> R<(HeightField, f32)> {
    let mut v = hf.heights().as_slice().to_vec();
    v.sort_by(f32::total_cmp);
    let level = v[((v.len() - 1) as f64 * q).round() as usize];
    let out = HeightField::from_fn(hf.nx(), hf.ny(), hf.cell_size(), |i, j| {
        hf.heights()[(i, j)].max(level)
    })?;
    Ok((out, level))
}

/// Land by altitude `z` (0 … `relief`) and slope (normal's z): meadow
/// low and gentle, bare rock high or steep, snow on the highest gentle
/// ground.
fn land(z: f32, relief: f32, up: f32) -> Vec3 {
    let a = (z / relief).clamp(0.0, 1.0);
    let meadow = Vec3::new(0.34, 0.42, 0.20);
    let rock = Vec3::new(0.50, 0.44, 0.38);
    let snow = Vec3::new(0.85, 0.87, 0.90);
    let steep = ((0.8 - up.abs()) / 0.2).clamp(0.0, 1.0);
    let rocky = (((a - 0.45) / 0.3).clamp(0.0, 1.0)).max(steep);
    let base = meadow.lerp(rock, rocky);
    let snowy = ((a - 0.8) / 0.1).clamp(0.0, 1.0) * (1.0 - steep);
    base.lerp(snow, snowy)
}

const SKY: Vec3 = Vec3::new(0.55, 0.66, 0.82);

/// The relief of the terrain plates, in patch widths.
const RELIEF: f32 = 0.12;

/// H across Pl. 2.3's patch: 1 at the left edge (D = 2, planar) down to 0
/// at the right (D = 3, space filling): `H = 1 − x`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DimensionAcross;

impl Field for DimensionAcross {
    fn eval2(&self, p: DVec2) -> f64 {
        1.0 - p.x.clamp(0.0, 1.0)
    }
    fn eval3(&self, p: DVec3) -> f64 {
        1.0 - p.x.clamp(0.0, 1.0)
    }
    fn bound(&self) -> f64 {
        1.0
    }
    fn lipschitz2(&self) -> f64 {
        1.0
    }
    fn lipschitz3(&self) -> f64 {
        1.0
    }
}

/// Pl. 2.3's fBm: Plate 2.2's spectrum (`spectral`) with H = 1 − x.
pub(crate) fn plate_2_3_fbm(seed: u64, spectral: Spectral) -> R<Driven<Perlin>> {
    let basis = Perlin::with_fade(seed, Fade::Cubic);
    Ok(Driven::new(basis, spectral, DrivenKind::Fbm)?
        .with_h(Param::Field(Arc::new(DimensionAcross))))
}

/// Pl. 2.3: fractal dimension from 2 (left) to 3 (right), in one stone
/// colour as Pl. 2.2.
pub(crate) fn dimension_2_to_3(seed: u64, spectral: Spectral, quick: bool) -> R<Image> {
    let n = if quick { 96 } else { 512 };
    let fbm = plate_2_3_fbm(seed, spectral)?;
    let hf = unit_patch(&fbm, n, 1.0, 0.1)?;
    let size = if quick { (320, 200) } else { (1200, 750) };
    let stone = Vec3::new(0.72, 0.62, 0.50);
    render_patch(&hf, size, SKY, &|_, _| Facet {
        albedo: stone,
        emission: Vec3::ZERO,
    })
}

/// Water of the lakes: dark blue, a little sky in it.
const WATER: Vec3 = Vec3::new(0.10, 0.20, 0.32);

/// The fraction of Spirit Lake's patch under water.
pub(crate) const LAKE_FRACTION: f64 = 0.18;

/// Pl. 2.4–2.5's terrain: statistics by altitude (natura-noise's
/// defaults), 4 lattice units across, with a lake filled to the height
/// below which [`LAKE_FRACTION`] of it lies: `(ground, lake level)`.
pub(crate) fn spirit_lake_field(seed: u64, n: usize) -> R<(HeightField, f32)> {
    let f = StatsByAltitude::new(Perlin::new(seed), StatsByAltitudeParams::default())?;
    filled(&unit_patch(&f, n, 4.0, RELIEF as f64)?, LAKE_FRACTION)
}

/// Pl. 2.4–2.5: statistics by altitude, smooth lowlands and rough peaks,
/// with "Spirit Lake" in its valley.
pub(crate) fn spirit_lake(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 96 } else { 512 };
    let (hf, level) = spirit_lake_field(seed, n)?;
    let size = if quick { (320, 200) } else { (1200, 750) };
    render_patch(&hf, size, SKY, &|c, nrm| Facet {
        albedo: if c.z <= level + 1e-6 {
            WATER
        } else {
            land(c.z, RELIEF, nrm.z)
        },
        emission: Vec3::ZERO,
    })
}

/// Pl. 2.6: the ridge by position (natura-texture's `Ridge`: statistics by
/// altitude times a tent across x, its line bent by 1/f³ noise), one
/// crest across a unit patch.
pub(crate) fn ridge(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 96 } else { 512 };
    let ridge = Ridge::new(RidgeParams {
        seed,
        ..RidgeParams::default()
    })?;
    let ny = n / 2;
    // The crest runs along y: the tent is across x, over one period.
    let raw: Vec<f64> = (0..n * ny)
        .map(|k| {
            let p = DVec3::new(
                ((k % n) + 1) as f64 / n as f64,
                ((k / n) + 1) as f64 / n as f64,
                0.0,
            );
            ridge.height(p, Footprint::POINT)
        })
        .collect();
    let hf = rescaled(&raw, (n, ny), 1.0 / n as f32, RELIEF as f64)?;
    let size = if quick { (320, 200) } else { (1200, 750) };
    render_patch(&hf, size, SKY, &|c, nrm| Facet {
        albedo: land(c.z, RELIEF, nrm.z),
        emission: Vec3::ZERO,
    })
}

/// Pl. 2.8: Terrain(), natura-noise's heterogeneous terrain with its
/// defaults, 4 lattice units across, coloured by altitude and slope.
pub(crate) fn terrain(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 96 } else { 512 };
    let f = HeteroTerrain::new(Perlin::new(seed), HeteroTerrainParams::default())?;
    let hf = unit_patch(&f, n, 4.0, RELIEF as f64)?;
    let size = if quick { (320, 200) } else { (1200, 750) };
    render_patch(&hf, size, SKY, &|c, nrm| Facet {
        albedo: land(c.z, RELIEF, nrm.z),
        emission: Vec3::ZERO,
    })
}

/// The fraction of "Hell"'s patch flooded by lava.
pub(crate) const LAVA_FRACTION: f64 = 0.22;

/// Pl. 2.9's terrain: heterogeneous terrain of the ridged basis, 4 lattice
/// units across, its lowest [`LAVA_FRACTION`] filled flat with lava:
/// `(ground, lava level)`.
pub(crate) fn hell_field(seed: u64, n: usize) -> R<(HeightField, f32)> {
    let f = HeteroTerrain::new(Ridged(Perlin::new(seed)), HeteroTerrainParams::default())?;
    filled(&unit_patch(&f, n, 4.0, RELIEF as f64)?, LAVA_FRACTION)
}

/// Pl. 2.9: "Hell": ridged heterogeneous terrain, dark scorched rock over
/// glowing lava, under a sky lit red from below.
pub(crate) fn hell(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 96 } else { 512 };
    let (hf, level) = hell_field(seed, n)?;
    let size = if quick { (320, 200) } else { (1200, 750) };
    let rock = Vec3::new(0.10, 0.06, 0.05);
    let lava = Vec3::new(1.0, 0.30, 0.03);
    render_patch(&hf, size, Vec3::new(0.07, 0.015, 0.008), &|c, _| {
        if c.z <= level + 1e-6 {
            Facet {
                albedo: Vec3::ZERO,
                emission: lava,
            }
        } else {
            // The rock just above the lava glows with its light.
            let glow = (1.0 - (c.z - level) / (0.15 * RELIEF)).clamp(0.0, 1.0);
            Facet {
                albedo: rock,
                emission: lava * 0.35 * glow * glow,
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dimension_runs_from_planar_to_space_filling() {
        assert_eq!(DimensionAcross.eval2(DVec2::new(0.0, 0.3)), 1.0);
        assert_eq!(DimensionAcross.eval2(DVec2::new(1.0, 0.3)), 0.0);
        assert!((DimensionAcross.eval2(DVec2::new(0.25, 0.0)) - 0.75).abs() < 1e-15);
    }

    #[test]
    fn the_lake_and_the_lava_fill_their_fraction_flat() {
        for (hf, level, q) in [
            {
                let (h, l) = spirit_lake_field(7, 64).unwrap();
                (h, l, LAKE_FRACTION)
            },
            {
                let (h, l) = hell_field(7, 64).unwrap();
                (h, l, LAVA_FRACTION)
            },
        ] {
            let v = hf.heights().as_slice();
            let flat = v.iter().filter(|&&z| z == level).count() as f64 / v.len() as f64;
            assert!((flat - q).abs() < 0.02, "{flat} against {q}");
            assert!(v.iter().all(|&z| z >= level));
            let (lo, hi) = hf.heights().min_max();
            assert_eq!(lo, level);
            assert!((hi - RELIEF).abs() < 1e-6, "{hi}");
        }
    }

    #[test]
    fn statistics_by_altitude_are_rougher_high_than_low() {
        // Pl. 2.4: the valleys smooth, the peaks rough: the mean slope of
        // the highest fifth of the land exceeds that of the lowest fifth.
        let (hf, level) = spirit_lake_field(3, 256).unwrap();
        let (nx, ny) = (hf.nx(), hf.ny());
        let h = hf.heights();
        let mut cells: Vec<(f32, f32)> = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let z = h[(i, j)];
                if z > level {
                    let s = (h[(i + 1, j)] - z).abs() + (h[(i, j + 1)] - z).abs();
                    cells.push((z, s));
                }
            }
        }
        cells.sort_by(|a, b| a.0.total_cmp(&b.0));
        let fifth = cells.len() / 5;
        let mean = |c: &[(f32, f32)]| c.iter().map(|e| e.1).sum::<f32>() / c.len() as f32;
        let (low, high) = (mean(&cells[..fifth]), mean(&cells[cells.len() - fifth..]));
        assert!(high > 1.5 * low, "slope high {high} low {low}");
    }
}
