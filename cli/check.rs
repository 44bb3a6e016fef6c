//! The checks of an assembly that need only the manifest lines: one scene,
//! one version, one platform, one tiling, each tile where its index says and
//! once, none missing. Problems are listed with their tile indices, missing
//! tiles as ranges, at most [`MAX_PROBLEMS`] lines.

use std::collections::{BTreeMap, BTreeSet};

use crate::limits::MAX_PROBLEMS;
use crate::manifest::{TileLine, VERSION};
use crate::tiles;

/// A list of problems that keeps the first [`MAX_PROBLEMS`] and counts the
/// rest.
#[derive(Debug, Default)]
pub struct Problems {
    list: Vec<String>,
    more: usize,
}

impl Problems {
    /// Adds a problem.
    pub fn push(&mut self, p: String) {
        if self.list.len() < MAX_PROBLEMS {
            self.list.push(p);
        } else {
            self.more += 1;
        }
    }

    /// Whether none was found.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The problems, with a last line counting those left out.
    pub fn into_lines(mut self) -> Vec<String> {
        if self.more > 0 {
            self.list.push(format!("… and {} more problems", self.more));
        }
        self.list
    }
}

/// `indices` (sorted) as ranges: `3`, `5 to 9`, joined by commas, at most
/// 20 ranges and then how many indices are left.
pub fn ranges(indices: &[u32]) -> String {
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for &i in indices {
        match runs.last_mut() {
            Some((_, b)) if b.checked_add(1) == Some(i) => *b = i,
            _ => runs.push((i, i)),
        }
    }
    let shown = runs.len().min(20);
    let mut parts: Vec<String> = runs[..shown]
        .iter()
        .map(|&(a, b)| {
            if a == b {
                a.to_string()
            } else {
                format!("{a} to {b}")
            }
        })
        .collect();
    let rest: u64 = runs[shown..]
        .iter()
        .map(|&(a, b)| u64::from(b - a) + 1)
        .sum();
    if rest > 0 {
        parts.push(format!("and {rest} more"));
    }
    parts.join(", ")
}

/// The tiles of a frame that passed the checks: the reference tile the
/// others were held to, and every tile by index.
#[derive(Debug)]
pub struct Plan {
    /// The reference tile (most common scene and platform; ties: lowest index).
    pub first: TileLine,
    /// Every tile, by index.
    pub by_index: BTreeMap<u32, TileLine>,
}

/// Checks the manifest lines of frame `frame` (read from files named as
/// given). Returns the plan, and the problems found (empty when the frame
/// can be assembled from its EXR files); `None` when there are no tiles.
pub fn check_lines(mut lines: Vec<TileLine>, frame: u32, problems: &mut Problems) -> Option<Plan> {
    let f = format!("frame {frame}");
    lines.sort_by_key(|l| l.tile);
    // The reference the others are held to: the most common scene and
    // platform among the tiles (ties: the lowest tile's).
    let common = |key: fn(&TileLine) -> &str| -> Option<String> {
        let mut count: BTreeMap<&str, usize> = BTreeMap::new();
        for l in &lines {
            *count.entry(key(l)).or_default() += 1;
        }
        let most = *count.values().max()?;
        lines
            .iter()
            .map(key)
            .find(|k| count[k] == most)
            .map(str::to_owned)
    };
    let (scene, platform) = (common(|l| &l.scene_sha256)?, common(|l| &l.platform)?);
    let first = lines
        .iter()
        .find(|l| l.scene_sha256 == scene && l.platform == platform)?
        .clone();
    let counts: BTreeSet<u32> = lines.iter().map(|l| l.tiles).collect();
    if counts.len() > 1 {
        problems.push(format!(
            "{f}: tiles of different tilings ({counts:?} tiles); remove the stale ones"
        ));
        return None;
    }
    let n = first.tiles;
    let grid = tiles::grid(first.frame_width, first.frame_height, n).ok();
    let mut by_index: BTreeMap<u32, TileLine> = BTreeMap::new();
    for l in lines {
        let t = format!("{f}, tile {} of {n}", l.tile);
        if l.natura != VERSION {
            problems.push(format!(
                "{t}: rendered by natura {}, this is natura {VERSION}",
                l.natura
            ));
        }
        if l.platform != first.platform {
            problems.push(format!(
                "{t}: rendered on {}, tile {} on {}: shards of a frame must run one build",
                l.platform, first.tile, first.platform
            ));
        }
        if l.scene_sha256 != first.scene_sha256 || l.seed != first.seed {
            problems.push(format!(
                "{t}: rendered from another scene (scene SHA-256 {}…, tile {} has {}…)",
                &l.scene_sha256[..12],
                first.tile,
                &first.scene_sha256[..12]
            ));
        }
        if l.frame != frame
            || (l.frame_width, l.frame_height, l.exposure_ev, l.tone_map)
                != (
                    first.frame_width,
                    first.frame_height,
                    first.exposure_ev,
                    first.tone_map,
                )
        {
            problems.push(format!(
                "{t}: frame, size or exposure differ from tile {}'s",
                first.tile
            ));
        }
        let rect =
            grid.map(|(c, r)| tiles::cell(first.frame_width, first.frame_height, c, r, l.tile));
        if rect.is_none_or(|r| (r.x, r.y, r.width, r.height) != (l.x, l.y, l.width, l.height)) {
            problems.push(format!("{t}: its rectangle is not tile {} of {n}", l.tile));
        }
        if by_index.contains_key(&l.tile) {
            problems.push(format!("{t}: two manifest lines claim this tile"));
            continue;
        }
        by_index.insert(l.tile, l);
    }
    let missing: Vec<u32> = (0..n).filter(|i| !by_index.contains_key(i)).collect();
    match missing.len() {
        0 => {}
        1 => problems.push(format!(
            "{f}, tile {} of {n}: missing (no manifest line)",
            missing[0]
        )),
        k => problems.push(format!(
            "{f}, tiles {} of {n}: missing ({k} tiles without a manifest line)",
            ranges(&missing)
        )),
    }
    Some(Plan { first, by_index })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_tiles_are_listed_as_ranges() {
        assert_eq!(ranges(&[3]), "3");
        assert_eq!(ranges(&[1, 3, 4, 5, 9]), "1, 3 to 5, 9");
        let many: Vec<u32> = (0..100).map(|i| i * 2).collect();
        let r = ranges(&many);
        assert!(r.ends_with("and 80 more") && r.len() < 200, "{r}");
        let all: Vec<u32> = (0..u32::MAX).step_by(1 << 16).collect();
        assert!(ranges(&all).len() < 200);
        let mut p = Problems::default();
        for i in 0..1000 {
            p.push(format!("problem {i}"));
        }
        let lines = p.into_lines();
        assert_eq!(lines.len(), MAX_PROBLEMS + 1);
        assert_eq!(lines[MAX_PROBLEMS], "… and 950 more problems");
    }

    fn line(tile: u32, tiles: u32) -> String {
        format!(
            r#"{{"natura":"{VERSION}","platform":"x86_64-linux","scene_sha256":"{h}","seed":7,"frame":0,"tile":{tile},"tiles":{tiles},"x":0,"y":0,"width":1,"height":1,"frame_width":64,"frame_height":36,"exposure_ev":null,"tone_map":"aces_filmic","file":"tiles/frame_0000/tile_{tile:04}_of_{tiles:04}.exr","sha256":"{h}"}}"#,
            h = "a".repeat(64)
        )
    }

    #[test]
    fn a_well_formed_line_parses() {
        let l = TileLine::parse(line(0, 1).as_bytes(), "t.json").unwrap();
        assert_eq!((l.tile, l.tiles), (0, 1));
    }

    proptest::proptest! {
        /// The fuzz target `manifest` in small: mutated manifest lines parse
        /// or fail with an error naming the file, and the checks of any set
        /// of them list a bounded number of problems.
        #[test]
        fn mutated_lines_never_panic(
            tiles in proptest::prop_oneof![1u32..5, 60_000u32..70_000, proptest::num::u32::ANY],
            at in 0usize..400,
            byte in proptest::num::u8::ANY,
            cut in 0usize..400,
        ) {
            let mut bytes = line(tiles.saturating_sub(1) % tiles.max(1), tiles).into_bytes();
            if at < bytes.len() {
                bytes[at] = byte;
            }
            bytes.truncate(cut.max(1).min(bytes.len()));
            let mut lines = Vec::new();
            match TileLine::parse(&bytes, "t.json") {
                Ok(l) => lines.push(l),
                Err(e) => proptest::prop_assert!(e.to_string().contains("t.json")),
            }
            let mut problems = Problems::default();
            let _ = check_lines(lines, 0, &mut problems);
            proptest::prop_assert!(problems.into_lines().len() <= MAX_PROBLEMS + 1);
        }
    }
}
