//! How a frame is cut into `N` tiles: a grid of `cols × rows = N` nearly
//! square rectangles, numbered row-major from the top-left.

use crate::error::{CliError, Result};
use crate::limits::MAX_TILES;

/// A pixel rectangle of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
}

/// Parses `I/N` (tile `I` of `N`, `0 ≤ I < N ≤` [`MAX_TILES`]); the
/// error says what was expected (the caller names the flag and value).
pub fn parse_tile(text: &str) -> std::result::Result<(u32, u32), String> {
    let bad = || format!("expected I/N with 0 ≤ I < N ≤ {MAX_TILES}, e.g. 3/16");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (u32, u32) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 {
        return Err("N = 0 tiles; N must be at least 1".into());
    }
    if n > MAX_TILES {
        return Err(format!("N = {n} tiles; N must be at most {MAX_TILES}"));
    }
    if i >= n {
        return Err(format!(
            "tile index {i} is out of range 0 to {} for N = {n}",
            n - 1
        ));
    }
    Ok((i, n))
}

/// The grid `(cols, rows)` for `n` tiles of a `width × height` frame: of the
/// factorisations `cols · rows = n` that give every tile at least one pixel,
/// the one whose tiles are closest to square.
pub fn grid(width: u32, height: u32, n: u32) -> Result<(u32, u32)> {
    let mut best: Option<(f64, u32, u32)> = None;
    for cols in (1..=n).filter(|c| n.is_multiple_of(*c)) {
        let rows = n / cols;
        if cols > width || rows > height {
            continue;
        }
        let aspect = (f64::from(width) / f64::from(cols)) / (f64::from(height) / f64::from(rows));
        let score = aspect.ln().abs();
        if best.is_none_or(|(s, _, _)| score < s) {
            best = Some((score, cols, rows));
        }
    }
    best.map(|(_, c, r)| (c, r)).ok_or_else(|| {
        CliError::usage(format!(
            "{n} tiles cannot cut a {width} × {height} frame into a grid of non-empty tiles"
        ))
    })
}

/// The rectangle of tile `index` of `n` in a `width × height` frame.
pub fn rect(width: u32, height: u32, index: u32, n: u32) -> Result<Rect> {
    if index >= n {
        return Err(CliError::usage(format!(
            "tile index {index} is out of range 0 to {} for N = {n}",
            n.saturating_sub(1)
        )));
    }
    let (cols, rows) = grid(width, height, n)?;
    Ok(cell(width, height, cols, rows, index))
}

/// The rectangle of cell `index` (row-major) of a `cols × rows` grid over a
/// `width × height` frame; `index < cols · rows`.
pub fn cell(width: u32, height: u32, cols: u32, rows: u32, index: u32) -> Rect {
    let (c, r) = (index % cols, index / cols);
    let cut =
        |k: u32, parts: u32, side: u32| (u64::from(k) * u64::from(side) / u64::from(parts)) as u32;
    let (x0, x1) = (cut(c, cols, width), cut(c + 1, cols, width));
    let (y0, y1) = (cut(r, rows, height), cut(r + 1, rows, height));
    Rect {
        x: x0,
        y: y0,
        width: x1 - x0,
        height: y1 - y0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_frame_exactly_once() {
        for (w, h) in [(64, 36), (7, 5), (1920, 1080), (1, 9)] {
            for n in [1, 2, 3, 4, 5, 7, 9, 16, 64] {
                let Ok(_) = grid(w, h, n) else { continue };
                let mut count = vec![0u8; (w * h) as usize];
                for i in 0..n {
                    let r = rect(w, h, i, n).unwrap();
                    assert!(r.width > 0 && r.height > 0, "{w}×{h} {i}/{n}");
                    for y in r.y..r.y + r.height {
                        for x in r.x..r.x + r.width {
                            count[(y * w + x) as usize] += 1;
                        }
                    }
                }
                assert!(count.iter().all(|&c| c == 1), "{w}×{h} n={n}");
            }
        }
    }

    #[test]
    fn bad_tiles_are_refused() {
        assert!(parse_tile("3/0").unwrap_err().contains("N = 0"));
        assert!(parse_tile("0/65537").unwrap_err().contains("at most 65536"));
        assert!(parse_tile("16/16").unwrap_err().contains("out of range"));
        assert!(parse_tile("x").is_err());
        assert_eq!(parse_tile("3/16").unwrap(), (3, 16));
        assert!(grid(2, 2, 5).is_err());
    }
}
