//! The manifest line of a tile: who rendered it from what, where it sits in
//! the frame, and the SHA-256 of its EXR file. One JSON line per tile, in a
//! file of its own beside the tile, so concurrent shards never share a file.

use std::path::{Path, PathBuf};

use natura::core::ToneMap;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::{CliError, Result};

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
    /// SHA-256 of the EXR file.
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

impl TileLine {
    /// Writes the line (JSON and a newline) to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        let mut text = serde_json::to_string(self).map_err(|e| CliError::Other(e.to_string()))?;
        text.push('\n');
        Ok(natura::core::io::write_bytes_atomic(path, text.as_bytes())?)
    }

    /// Reads a manifest line, naming the file in any error.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = natura::core::io::read_file_at_most(path, 1 << 16)?;
        let text = String::from_utf8(bytes).map_err(|_| {
            CliError::Other(format!("{}: manifest line is not UTF-8", path.display()))
        })?;
        serde_json::from_str(text.trim_end()).map_err(|e| {
            CliError::Other(format!("{}: unreadable manifest line: {e}", path.display()))
        })
    }
}
