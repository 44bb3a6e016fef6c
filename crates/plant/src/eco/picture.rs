//! A top-down picture of an ecosystem: every plant's circle of influence,
//! coloured by species, over the hill-shaded terrain (as in Deussen et al.
//! 1998, Fig. 4 and 6, which draw the plants as circles).

use glam::Vec3;
use natura_core::Image;

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

/// Renders the ecosystem from above, `width` pixels wide (height from the terrain's aspect).
///
/// # Errors
///
/// [`PlantError::InvalidParameter`] if `width` is 0 or above 16384; [`PlantError::Core`] if
/// the image cannot be allocated.
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
    let mut img = Image::from_fn(width, height, |x, y| {
        // Row 0 at the top is the terrain's far (+y) edge.
        let wx = (x as f32 + 0.5) * px;
        let wy = ey - (y as f32 + 0.5) * px;
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
        let (cx, cy) = (p.x / px, (ey - p.y) / px);
        let r = (p.radius / px).max(0.5);
        let (x0, x1) = (
            (cx - r).floor().max(0.0) as usize,
            ((cx + r).ceil() as usize).min(width),
        );
        let (y0, y1) = (
            (cy - r).floor().max(0.0) as usize,
            ((cy + r).ceil() as usize).min(height),
        );
        for y in y0..y1 {
            for x in x0..x1 {
                let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                if dx * dx + dy * dy <= r * r {
                    let base = img.get(x, y).unwrap_or(c);
                    img.set(x, y, base * 0.25 + c * 0.75);
                }
            }
        }
    }
    Ok(img)
}
