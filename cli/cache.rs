//! The world cache: the eroded terrain of a scene, shared by every tile and
//! frame of a job, stored under the content hash of what determines it
//! (natura's version, the seed, the terrain and erosion sections).
//!
//! File layout: a text header (magic, version, key, sizes, the payload's
//! SHA-256) then the terrain, deposition and wetness grids as little-endian
//! `f32`. A cache of another version, key or size, or whose payload does not
//! match its hash, is refused with an error naming the file; it is never
//! used and never silently replaced.

use std::path::{Path, PathBuf};

use natura::core::{Grid2, HeightField, NoProgress};
use natura::render::{ErodedTerrain, ErosionDesc, SceneDesc, TerrainDesc, World};
use serde::Serialize;
use sha2::{Digest, Sha256};

use crate::error::{CliError, Result};
use crate::manifest::{VERSION, hex};

const MAGIC: &str = "natura world cache";

/// What the eroded terrain is a function of.
#[derive(Serialize)]
struct Key<'a> {
    natura: &'a str,
    seed: u64,
    terrain: &'a TerrainDesc,
    erosion: &'a ErosionDesc,
}

/// The content hash of the eroded terrain of `scene` (hex SHA-256).
pub fn key(scene: &SceneDesc) -> Result<String> {
    let json = serde_json::to_string(&Key {
        natura: VERSION,
        seed: scene.seed,
        terrain: &scene.terrain,
        erosion: &scene.erosion,
    })
    .map_err(|e| CliError::Other(e.to_string()))?;
    Ok(hex(&Sha256::digest(json.as_bytes())))
}

/// The cache file of `scene` in `dir`.
pub fn path(dir: &Path, scene: &SceneDesc) -> Result<PathBuf> {
    Ok(dir.join(format!("world_{}.bin", &key(scene)?[..32])))
}

/// Whether the eroded terrain came from the cache or was computed (and stored).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Read from a valid cache file.
    Cached,
    /// Computed and written to the cache.
    Computed,
}

/// The eroded terrain of `scene`: from its cache file in `dir` when present,
/// else computed and stored there (atomically).
pub fn eroded(dir: &Path, scene: &SceneDesc) -> Result<(ErodedTerrain, Source)> {
    let file = path(dir, scene)?;
    let key = key(scene)?;
    if file.exists() {
        return Ok((read(&file, &key)?, Source::Cached));
    }
    let eroded = World::build_eroded(scene, &NoProgress)?;
    std::fs::create_dir_all(dir).map_err(|e| crate::error::io(dir, e))?;
    write(&file, &key, &eroded)?;
    Ok((eroded, Source::Computed))
}

fn payload(e: &ErodedTerrain) -> Vec<u8> {
    let grids = [e.terrain.heights(), &e.deposition, &e.wetness];
    let mut out = Vec::with_capacity(grids.iter().map(|g| g.as_slice().len() * 4).sum());
    for g in grids {
        for v in g.as_slice() {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

fn write(file: &Path, key: &str, e: &ErodedTerrain) -> Result<()> {
    let body = payload(e);
    let (nx, ny) = (e.terrain.nx(), e.terrain.ny());
    let header = format!(
        "{MAGIC}\nnatura {VERSION}\nkey {key}\nsize {nx} {ny} {:08x}\npayload {}\n\n",
        e.terrain.cell_size().to_bits(),
        hex(&Sha256::digest(&body))
    );
    let mut bytes = header.into_bytes();
    bytes.extend_from_slice(&body);
    Ok(natura::core::io::write_bytes_atomic(file, &bytes)?)
}

fn read(file: &Path, key: &str) -> Result<ErodedTerrain> {
    let refuse = |reason: String| CliError::Cache {
        path: file.display().to_string(),
        reason,
    };
    let limit = 3 * natura::core::MAX_GRID_BYTES + 4096;
    let bytes = natura::core::io::read_file_at_most(file, limit)?;
    let end = bytes
        .windows(2)
        .take(4096)
        .position(|w| w == b"\n\n")
        .ok_or_else(|| refuse("no header (not a world cache, or truncated)".into()))?;
    let header =
        std::str::from_utf8(&bytes[..end]).map_err(|_| refuse("header is not text".into()))?;
    let body = &bytes[end + 2..];
    let lines: Vec<&str> = header.lines().collect();
    let field = |i: usize, name: &str| -> Result<&str> {
        lines
            .get(i)
            .and_then(|l| l.strip_prefix(name))
            .and_then(|l| l.strip_prefix(' '))
            .ok_or_else(|| refuse(format!("header line {} should start with `{name}`", i + 1)))
    };
    if lines.first() != Some(&MAGIC) {
        return Err(refuse("not a natura world cache".into()));
    }
    let version = field(1, "natura")?;
    if version != VERSION {
        return Err(refuse(format!(
            "written by natura {version}, this is natura {VERSION}"
        )));
    }
    if field(2, "key")? != key {
        return Err(refuse(
            "its content hash is not this scene's terrain".into(),
        ));
    }
    let size: Vec<&str> = field(3, "size")?.split(' ').collect();
    let bad_size = || refuse("unreadable size line".into());
    let [nx, ny, cell] = size[..] else {
        return Err(bad_size());
    };
    let nx: usize = nx.parse().map_err(|_| bad_size())?;
    let ny: usize = ny.parse().map_err(|_| bad_size())?;
    let cell = f32::from_bits(u32::from_str_radix(cell, 16).map_err(|_| bad_size())?);
    if hex(&Sha256::digest(body)) != field(4, "payload")? {
        return Err(refuse(
            "the data does not match its SHA-256 (corrupt or truncated)".into(),
        ));
    }
    let n = natura::core::checked_len::<f32>(&[nx, ny])?;
    if body.len() != 3 * 4 * n {
        return Err(refuse(format!(
            "{} data bytes for {nx} × {ny} grids",
            body.len()
        )));
    }
    let grid = |k: usize| -> Result<Grid2<f32>> {
        let v = body[k * 4 * n..(k + 1) * 4 * n]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        Ok(Grid2::from_vec(nx, ny, v)?)
    };
    Ok(ErodedTerrain {
        terrain: HeightField::new(grid(0)?, cell)?,
        deposition: grid(1)?,
        wetness: grid(2)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ErodedTerrain {
        let g = |k: f32| Grid2::from_fn(5, 3, |i, j| k * (i as f32) - j as f32).unwrap();
        ErodedTerrain {
            terrain: HeightField::new(g(1.5), 30.0).unwrap(),
            deposition: g(0.25),
            wetness: g(-0.5),
        }
    }

    #[test]
    fn round_trip_is_exact_and_damage_is_refused() {
        let dir = std::env::temp_dir().join(format!("natura-cli-cache-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("w.bin");
        write(&file, "abc", &sample()).unwrap();
        assert_eq!(read(&file, "abc").unwrap(), sample());
        let e = read(&file, "abd").unwrap_err().to_string();
        assert!(e.contains("not this scene's terrain"), "{e}");
        let bytes = std::fs::read(&file).unwrap();
        std::fs::write(&file, &bytes[..bytes.len() - 4]).unwrap();
        let e = read(&file, "abc").unwrap_err().to_string();
        assert!(
            e.contains("corrupt or truncated") && e.contains("delete it"),
            "{e}"
        );
        std::fs::write(&file, b"hello").unwrap();
        assert!(read(&file, "abc").is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
