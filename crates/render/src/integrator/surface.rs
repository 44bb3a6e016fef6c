//! The traced surface: water levels, the sea plane and the procedural
//! detail kept off the water.

use super::*;

impl Renderer<'_> {
    /// The water level of the cell `(i, j)` of the surface: its lowest corner.
    pub(super) fn cell_level(&self, cell: glam::UVec2) -> f32 {
        let s = self.world.surface.heights();
        let (i, j) = (cell.x as usize, cell.y as usize);
        let (i1, j1) = ((i + 1).min(s.width() - 1), (j + 1).min(s.height() - 1));
        s[(i, j)].min(s[(i1, j)]).min(s[(i, j1)]).min(s[(i1, j1)])
    }

    /// Height of the traced surface (terrain, lakes and sea) below `p`.
    pub(super) fn surface_height(&self, p: Vec3) -> f32 {
        let inv = 1.0 / self.world.terrain.cell_size();
        self.world
            .surface
            .heights()
            .sample_bilinear(p.x * inv, p.y * inv, Boundary::Clamp)
    }

    /// Depth of water at a surface point, if it is wet (lake or sea).
    pub(super) fn water_depth(&self, p: Vec3) -> Option<f32> {
        self.world.water_level?;
        let w = self.world;
        let inv = 1.0 / w.terrain.cell_size();
        let s = w
            .surface
            .heights()
            .sample_bilinear(p.x * inv, p.y * inv, Boundary::Clamp);
        let g = w
            .terrain
            .heights()
            .sample_bilinear(p.x * inv, p.y * inv, Boundary::Clamp);
        let depth = s - g;
        (depth > 0.02).then_some(depth)
    }

    /// Distance to the sea plane along `d` from `o`, if the ray goes down onto it.
    pub(super) fn sea_t(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let level = self.world.water_level?;
        (o.z > level && d.z < 0.0)
            .then(|| (level - o.z) / d.z)
            .filter(|t| t.is_finite() && *t > 0.0)
    }
}

/// The traced surface of a world: its water surface plus the scene's
/// procedural detail (the first octave at the cell's wavelength), kept off
/// the lakes and the sea by a mask that is 0 on every wet sample and its
/// neighbours and 1 elsewhere. Without detail (disabled, or amplitude or
/// octaves 0) the surface is the height field alone and is traced exactly as
/// before.
pub(super) fn detail_surface(world: &World) -> Result<DetailSurface<'_>> {
    let d = &world.scene.detail;
    let on = d.enabled && d.amplitude_m > 0.0 && d.octaves > 0;
    let detail = Detail::new(&DetailParams {
        amplitude_m: if on { d.amplitude_m as f32 } else { 0.0 },
        h: d.h as f32,
        lacunarity: d.lacunarity as f32,
        octaves: if on { d.octaves } else { 0 },
        wavelength_m: world.terrain.cell_size(),
        seed: Seed(world.scene.seed.wrapping_add(d.seed_offset))
            .derive("detail")
            .0,
    })?;
    let mask = if on && world.water_level.is_some() {
        let (s, g) = (world.surface.heights(), world.terrain.heights());
        let (nx, ny) = (s.width(), s.height());
        let wet = |i: usize, j: usize| s[(i, j)] > g[(i, j)];
        Some(natura_core::Grid2::from_fn(nx, ny, |i, j| {
            let near_water = (i.saturating_sub(1)..=(i + 1).min(nx - 1))
                .any(|a| (j.saturating_sub(1)..=(j + 1).min(ny - 1)).any(|b| wet(a, b)));
            if near_water { 0.0f32 } else { 1.0 }
        })?)
    } else {
        None
    };
    Ok(DetailSurface::new(&world.surface, detail, mask)?)
}
