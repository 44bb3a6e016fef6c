//! The manifest line of a tile: who rendered it from what, where it sits in
//! the frame, and the tile's SHA-256, which binds its EXR file to its place:
//! the scene's hash, the frame, the tile's index and the tile count. One JSON
//! line per tile, in a file of its own beside the tile, so concurrent shards
//! never share a file. Every field is checked when the line is read.

use std::path::{Path, PathBuf};

use natura::core::ToneMap;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::{CliError, Result};
use crate::limits::{MAX_MANIFEST_BYTES, MAX_TILES};

/// The version every shard, cache and assembly must agree on.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// One tile's manifest line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TileLine {
    /// natura version that rendered the tile.
    pub natura: String,
    /// Architecture and operating system of the shard's binary (the
    /// platforms' math libraries may round differently).
    pub platform: String,
    /// SHA-256 of the scene (its canonical TOML, all frames).
    pub scene_sha256: String,
    /// The scene's seed.
    pub seed: u64,
    /// Frame number.
    pub frame: u32,
    /// Tile index.
    pub tile: u32,
    /// Tiles in the frame.
    pub tiles: u32,
    /// Left column of the tile in the frame.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Tile width, pixels.
    pub width: u32,
    /// Tile height, pixels.
    pub height: u32,
    /// Frame width, pixels.
    pub frame_width: u32,
    /// Frame height, pixels.
    pub frame_height: u32,
    /// The scene's fixed exposure, if any (absent: automatic, from the whole frame).
    pub exposure_ev: Option<f32>,
    /// The scene's tone map.
    pub tone_map: ToneMap,
    /// The tile's EXR file, relative to the output directory.
    pub file: String,
    /// SHA-256 of the tile: of its place (see [`tile_sha256`]) and its EXR
    /// file.
    pub sha256: String,
}

/// The platform this binary was built for, `arch-os`.
pub fn platform() -> String {
    format!("{}-{}", std::env::consts::ARCH, std::env::consts::OS)
}

/// Lower-case hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Lower-case hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The directory of frame `frame`'s tiles under `out`.
pub fn frame_dir(out: &Path, frame: u32) -> PathBuf {
    out.join("tiles").join(format!("frame_{frame:04}"))
}

/// File stem of tile `tile` of `tiles`.
pub fn tile_stem(tile: u32, tiles: u32) -> String {
    format!("tile_{tile:04}_of_{tiles:04}")
}

/// Most frames of a scene (`animation.frames`), so the largest frame number
/// is one less.
pub const MAX_FRAMES: u32 = 1_000_000;

/// Largest frame side, pixels (`render.width`, `render.height`).
pub const MAX_SIDE: u32 = 16_384;

/// The SHA-256 of tile `tile` of `tiles` of frame `frame` of the scene with
/// hash `scene_sha256`, whose EXR file holds `exr`: a hash over a header
/// naming the tile's place, then the file. A tile copied to another index,
/// frame or scene no longer matches its hash.
pub fn tile_sha256(scene_sha256: &str, frame: u32, tile: u32, tiles: u32, exr: &[u8]) -> String {
    let mut h = Sha256::new();
    h.update(
        format!("natura tile\nscene {scene_sha256}\nframe {frame}\ntile {tile} of {tiles}\n\n")
            .as_bytes(),
    );
    h.update(exr);
    hex(&h.finalize())
}

/// The EXR file of tile `tile` of `tiles` of frame `frame`, relative to the
/// output directory.
pub fn tile_file(frame: u32, tile: u32, tiles: u32) -> String {
    format!("tiles/frame_{frame:04}/{}.exr", tile_stem(tile, tiles))
}

/// `text` as a quoted string for a message, cut to 80 characters.
pub fn shown(text: &str) -> String {
    let mut cut: String = text.chars().take(80).collect();
    if cut.len() < text.len() {
        cut.push('…');
    }
    format!("{cut:?}")
}

fn is_sha256(s: &str) -> bool {
    s.len() == 64
        && s.bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

fn is_label(s: &str) -> bool {
    (1..=64).contains(&s.len()) && s.chars().all(|c| c.is_ascii_graphic())
}

impl TileLine {
    /// Writes the line (JSON and a newline) to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        let mut text = serde_json::to_string(self).map_err(|e| CliError::Other(e.to_string()))?;
        text.push('\n');
        Ok(natura::core::io::write_bytes_atomic(path, text.as_bytes())?)
    }

    /// Reads a manifest line of at most [`MAX_MANIFEST_BYTES`], naming the
    /// file in any error.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = crate::limits::read_capped(path, MAX_MANIFEST_BYTES, "tile manifest")?;
        Self::parse(&bytes, &path.display().to_string())
    }

    /// Parses and checks a manifest line (the bytes of file `name`): JSON of
    /// exactly the fields of a [`TileLine`], each within its range
    /// ([`TileLine::check`]).
    pub fn parse(bytes: &[u8], name: &str) -> Result<Self> {
        if bytes.len() as u64 > MAX_MANIFEST_BYTES {
            return Err(CliError::Other(format!(
                "{name}: tile manifest of {} bytes is larger than the most natura reads, \
                 {MAX_MANIFEST_BYTES} bytes",
                bytes.len()
            )));
        }
        let text = std::str::from_utf8(bytes)
            .map_err(|_| CliError::Other(format!("{name}: manifest line is not UTF-8")))?;
        let line: Self = serde_json::from_str(text.trim_end())
            .map_err(|e| CliError::Other(format!("{name}: unreadable manifest line: {e}")))?;
        line.check(name)?;
        Ok(line)
    }

    /// Checks every field against its range: labels of 1 to 64 printable
    /// ASCII characters, hashes of 64 lower-case hex digits, a frame below
    /// [`MAX_FRAMES`], 1 to [`MAX_TILES`] tiles and an index below them, a
    /// frame of 1 to [`MAX_SIDE`] pixels a side holding a non-empty tile
    /// rectangle, a finite exposure, and the tile's own EXR file name.
    pub fn check(&self, name: &str) -> Result<()> {
        let bad = |field: &str, value: String, expected: &str| {
            Err(CliError::Other(format!(
                "{name}: manifest field `{field}` = {value}: expected {expected}"
            )))
        };
        for (field, v) in [("natura", &self.natura), ("platform", &self.platform)] {
            if !is_label(v) {
                return bad(field, shown(v), "1 to 64 printable ASCII characters");
            }
        }
        for (field, v) in [
            ("scene_sha256", &self.scene_sha256),
            ("sha256", &self.sha256),
        ] {
            if !is_sha256(v) {
                return bad(field, shown(v), "a SHA-256 of 64 lower-case hex digits");
            }
        }
        if self.frame >= MAX_FRAMES {
            return bad(
                "frame",
                self.frame.to_string(),
                &format!("0 to {}", MAX_FRAMES - 1),
            );
        }
        if !(1..=MAX_TILES).contains(&self.tiles) {
            return bad(
                "tiles",
                self.tiles.to_string(),
                &format!("1 to {MAX_TILES}"),
            );
        }
        if self.tile >= self.tiles {
            return bad(
                "tile",
                self.tile.to_string(),
                &format!("0 to {} (tiles = {})", self.tiles - 1, self.tiles),
            );
        }
        for (field, v) in [
            ("frame_width", self.frame_width),
            ("frame_height", self.frame_height),
        ] {
            if !(1..=MAX_SIDE).contains(&v) {
                return bad(field, v.to_string(), &format!("1 to {MAX_SIDE} pixels"));
            }
        }
        for (field, at, len, side, side_name) in [
            ("width", self.x, self.width, self.frame_width, "frame_width"),
            (
                "height",
                self.y,
                self.height,
                self.frame_height,
                "frame_height",
            ),
        ] {
            if len == 0 || u64::from(at) + u64::from(len) > u64::from(side) {
                return bad(
                    field,
                    len.to_string(),
                    &format!(
                        "1 to {} pixels (the tile starts at {at} of {side_name} = {side})",
                        u64::from(side).saturating_sub(u64::from(at))
                    ),
                );
            }
        }
        if let Some(ev) = self.exposure_ev
            && !ev.is_finite()
        {
            return bad("exposure_ev", ev.to_string(), "a finite number");
        }
        let file = tile_file(self.frame, self.tile, self.tiles);
        if self.file != file {
            return bad(
                "file",
                shown(&self.file),
                &format!("{file:?}, this tile's own file"),
            );
        }
        Ok(())
    }
}
