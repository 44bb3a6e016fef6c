//! Row-parallel filling of images and grids (natura-core's preview row
//! loop): every renderer of the crate computes each row independently, so
//! results do not depend on the number of threads.

use glam::Vec3;
use natura_core::{Grid2, Image, Progress};

use crate::error::Result;

pub use natura_core::preview::fill_rows;

/// Fills a `width × height` image row by row with `row(y, pixels)` (rows in
/// parallel with the `parallel` feature), reporting one unit per row to
/// `progress` under `stage`.
///
/// # Errors
/// A zero or oversize image ([`natura_core::CoreError`]).
pub fn render_rows(
    width: u32,
    height: u32,
    stage: &str,
    progress: &dyn Progress,
    row: impl Fn(u32, &mut [Vec3]) + Sync,
) -> Result<Image> {
    let mut grid = Grid2::new(width as usize, height as usize, Vec3::ZERO)?;
    fill_rows(&mut grid, stage, progress, |y, r| row(y as u32, r));
    Ok(Image::from_grid(grid))
}
