//! A top-down picture of an ecosystem: every plant's circle of influence,
//! coloured by species, over the hill-shaded terrain (as in Deussen et al.
//! 1998, Fig. 4 and 6, which draw the plants as circles), drawn with
//! natura-core's preview loops ([`natura_core::preview`]).

use glam::{Vec2, Vec3};
use natura_core::filter::PixelFilter;
use natura_core::{Grid2, Image, preview};

use super::sim::Ecosystem;
use crate::error::{PlantError, Result};

/// A distinct colour for species `k` (linear RGB).
#[must_use]
pub fn species_colour(k: usize) -> Vec3 {
    const C: [[f32; 3]; 8] = [
        [0.05, 0.30, 0.05],
        [0.35, 0.55, 0.10],
        [0.05, 0.25, 0.55],
        [0.70, 0.75, 0.20],
        [0.55, 0.20, 0.05],
        [0.45, 0.10, 0.45],
        [0.10, 0.50, 0.45],
        [0.80, 0.45, 0.10],
    ];
    Vec3::from(C[k % C.len()])
}

/// Samples a pixel of [`top_view`] takes along each axis.
const SUPERSAMPLE: usize = 3;

/// Renders the ecosystem from above, `width` pixels wide (height from the
/// terrain's aspect): the ground shaded by its light, and each plant a disc
/// of its crown's radius in its species' colour, smallest first, drawn on
/// 3 × 3 samples a pixel and resolved by the camera's pixel
/// filter (natura-core's `PixelFilter::camera`).
///
/// # Errors
///
/// [`PlantError::InvalidParameter`] if `width` is 0 or above 16384; [`PlantError::Core`] if
/// the height (from the terrain's aspect) is over natura-core's
/// [`MAX_RESOLUTION`](natura_core::camera::MAX_RESOLUTION) or the image
/// cannot be allocated.
pub fn top_view(eco: &Ecosystem, width: usize) -> Result<Image> {
    if width == 0 || width > 16384 {
        return Err(PlantError::InvalidParameter {
            name: "width",
            value: width.to_string(),
            reason: "between 1 and 16384 pixels".into(),
        });
    }
    let site = eco.site();
    let (ex, ey) = site.extent();
    let height = ((width as f32 * ey / ex).round() as usize).max(1);
    let px = ex / width as f32;
    // The ground and the crowns are drawn on SUPERSAMPLE² samples a pixel,
    // then resolved by the camera's pixel filter, so a crown's edge is
    // antialiased and a crown smaller than a pixel is a soft dot.
    let s = SUPERSAMPLE;
    let h32 = u32::try_from(height).unwrap_or(u32::MAX);
    preview::check_size(width as u32, h32, s as u32)?;
    let sp = px / s as f32;
    let mut frame = Grid2::from_fn(width * s, height * s, |i, j| {
        // Row 0 at the top is the terrain's far (+y) edge.
        let (wx, wy) = ((i as f32 + 0.5) * sp, ey - (j as f32 + 0.5) * sp);
        let (i, j) = site.nearest(wx, wy);
        let shade = 0.25 + 0.6 * site.light[(i, j)];
        Vec3::new(0.55, 0.5, 0.42) * shade
    })?;
    // Small plants first, so crowns of trees lie on top of the meadow.
    let mut order: Vec<usize> = (0..eco.plants().len()).collect();
    order.sort_by(|&a, &b| {
        eco.plants()[a]
            .radius
            .total_cmp(&eco.plants()[b].radius)
            .then(a.cmp(&b))
    });
    for p in order.iter().map(|&i| &eco.plants()[i]) {
        let c = species_colour(p.species as usize);
        let centre = Vec2::new(p.x / sp, (ey - p.y) / sp);
        // At least half a pixel, so the smallest plants still show.
        let r = (p.radius / px).max(0.5) * s as f32;
        for (x, y) in preview::disc_pixels(centre, r, width * s, height * s) {
            let base = frame[(x, y)];
            frame[(x, y)] = base * 0.25 + c * 0.75;
        }
    }
    Ok(PixelFilter::camera().resolve(&frame, s)?)
}
