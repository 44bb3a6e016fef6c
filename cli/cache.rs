//! The job's caches, each stored under the content hash of what determines
//! it, so every tile re-uses them and a stale one is never picked up:
//!
//! * the world cache: the eroded terrain of a scene, shared by every tile and
//!   frame (its key: natura's version, the seed, the terrain and erosion
//!   sections);
//! * the frame cache: what the tiles of one frame share — its clouds as its
//!   renderer sees them and the population its forest's ecosystem grows
//!   (its key: natura's version and the frame's whole scene).
//!
//! File layout: a text header (magic, version, key, sizes, the payload's
//! SHA-256) then the payload: the terrain, deposition and wetness grids as
//! little-endian `f32`, or the frame's cloud-sky bytes and plants. A cache of
//! another kind, version, key or size, or whose payload does not match its
//! hash, is refused with an error naming the file; it is never used and
//! never silently replaced.

use std::path::{Path, PathBuf};

use natura::core::{Grid2, HeightField, Progress};
use natura::plant::eco::Plant;
use natura::render::clouds::CloudSky;
use natura::render::{ErodedTerrain, ErosionDesc, FramePrep, SceneDesc, TerrainDesc, World};
use serde::Serialize;
use sha2::{Digest, Sha256};

use crate::error::{CliError, Result};
use crate::manifest::{VERSION, hex};

const MAGIC: &str = "natura world cache";

/// The meaning of a world cache's contents, part of its key: raised when
/// what the cache holds changes within one version of natura (2: the
/// wetness is natura-terrain's topographic wetness index of the final
/// terrain), so a cache of another meaning is never found and reused.
const WORLD_FORMAT: u32 = 2;

/// What the eroded terrain is a function of.
#[derive(Serialize)]
struct Key<'a> {
    natura: &'a str,
    format: u32,
    seed: u64,
    terrain: &'a TerrainDesc,
    erosion: &'a ErosionDesc,
}

/// The content hash of the eroded terrain of `scene` (hex SHA-256).
pub fn key(scene: &SceneDesc) -> Result<String> {
    let json = serde_json::to_string(&Key {
        natura: VERSION,
        format: WORLD_FORMAT,
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
/// else computed (its stages reported to `progress`) and stored there
/// (atomically).
pub fn eroded(
    dir: &Path,
    scene: &SceneDesc,
    progress: &dyn Progress,
) -> Result<(ErodedTerrain, Source)> {
    let file = path(dir, scene)?;
    let key = key(scene)?;
    if file.exists() {
        return Ok((read(&file, &key)?, Source::Cached));
    }
    let eroded = World::build_eroded(scene, progress)?;
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
    let size = format!(
        "{} {} {:08x}",
        e.terrain.nx(),
        e.terrain.ny(),
        e.terrain.cell_size().to_bits()
    );
    store(file, TERRAIN, key, &size, &payload(e))
}

fn read(file: &Path, key: &str) -> Result<ErodedTerrain> {
    let refuse = |reason: String| CliError::Cache {
        path: file.display().to_string(),
        reason,
    };
    let limit = 3 * natura::core::MAX_GRID_BYTES + 4096;
    let (size, body) = load(file, TERRAIN, key, limit)?;
    let size: Vec<&str> = size.split(' ').collect();
    let bad_size = || refuse("unreadable size line".into());
    let [nx, ny, cell] = size[..] else {
        return Err(bad_size());
    };
    let nx: usize = nx.parse().map_err(|_| bad_size())?;
    let ny: usize = ny.parse().map_err(|_| bad_size())?;
    let cell = f32::from_bits(u32::from_str_radix(cell, 16).map_err(|_| bad_size())?);
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

/// What a cache file holds: its magic line and what its key hashes.
struct Kind {
    magic: &'static str,
    what: &'static str,
}

const TERRAIN: Kind = Kind {
    magic: MAGIC,
    what: "this scene's terrain",
};

const FRAME: Kind = Kind {
    magic: "natura frame cache",
    what: "this frame's scene",
};

/// Writes a cache file atomically: a text header (magic, version, key,
/// `size`, the payload's SHA-256) and the payload.
fn store(file: &Path, kind: Kind, key: &str, size: &str, body: &[u8]) -> Result<()> {
    let header = format!(
        "{}\nnatura {VERSION}\nkey {key}\nsize {size}\npayload {}\n\n",
        kind.magic,
        hex(&Sha256::digest(body))
    );
    let mut bytes = header.into_bytes();
    bytes.extend_from_slice(body);
    Ok(natura::core::io::write_bytes_atomic(file, &bytes)?)
}

/// Reads a cache file written by [`store`] of at most `limit` bytes (a
/// larger one is refused before it is read), refusing another kind,
/// version or key and a payload that does not match its hash. Returns the
/// size line and the payload.
fn load(file: &Path, kind: Kind, key: &str, limit: u64) -> Result<(String, Vec<u8>)> {
    let bytes = crate::limits::read_capped(file, limit, kind.magic)?;
    parse(bytes, &kind, key, &file.display().to_string())
}

/// The frame cache held in `bytes` (a whole file, named `name` in errors)
/// whose key must be `key`: its header checked, then its payload decoded.
/// (Used by the tests and the `frame_cache` fuzz target.)
#[allow(dead_code)]
pub fn parse_frame_cache(bytes: Vec<u8>, key: &str, name: &str) -> Result<FramePrep> {
    let (_, body) = parse(bytes, &FRAME, key, name)?;
    frame_from_bytes(&body, Path::new(name))
}

/// The size line and payload of cache file bytes `bytes` (see [`load`]).
fn parse(mut bytes: Vec<u8>, kind: &Kind, key: &str, name: &str) -> Result<(String, Vec<u8>)> {
    let refuse = |reason: String| CliError::Cache {
        path: name.to_owned(),
        reason,
    };
    let end = bytes
        .windows(2)
        .take(4096)
        .position(|w| w == b"\n\n")
        .ok_or_else(|| refuse("no header (not a natura cache, or truncated)".into()))?;
    let body = bytes.split_off(end + 2);
    let header =
        std::str::from_utf8(&bytes[..end]).map_err(|_| refuse("header is not text".into()))?;
    let lines: Vec<&str> = header.lines().collect();
    let field = |i: usize, name: &str| -> Result<&str> {
        lines
            .get(i)
            .and_then(|l| l.strip_prefix(name))
            .and_then(|l| l.strip_prefix(' '))
            .ok_or_else(|| refuse(format!("header line {} should start with `{name}`", i + 1)))
    };
    if lines.first() != Some(&kind.magic) {
        return Err(refuse(format!("not a {}", kind.magic)));
    }
    let version = field(1, "natura")?;
    if version != VERSION {
        return Err(refuse(format!(
            "written by natura {}, this is natura {VERSION}",
            version
                .chars()
                .filter(|c| !c.is_control())
                .take(64)
                .collect::<String>()
        )));
    }
    if field(2, "key")? != key {
        return Err(refuse(format!(
            "its content hash is not that of {}",
            kind.what
        )));
    }
    let size = field(3, "size")?.to_owned();
    if hex(&Sha256::digest(&body)) != field(4, "payload")? {
        return Err(refuse(
            "the data does not match its SHA-256 (corrupt or truncated)".into(),
        ));
    }
    Ok((size, body))
}

/// The content hash of the preparation of frame scene `still` (hex
/// SHA-256): what the eye sees of the clouds and where the trees grow
/// depend on the whole still scene (camera, sun, atmosphere, terrain,
/// clouds, vegetation).
fn frame_key(still: &SceneDesc) -> Result<String> {
    let toml = still.to_toml_string()?;
    let mut h = Sha256::new();
    h.update(b"natura ");
    h.update(VERSION.as_bytes());
    h.update(b"\n");
    h.update(toml.as_bytes());
    Ok(hex(&h.finalize()))
}

/// The frame cache file of frame scene `still` in `dir`.
pub fn frame_path(dir: &Path, still: &SceneDesc) -> Result<PathBuf> {
    Ok(dir.join(format!("frame_{}.bin", &frame_key(still)?[..32])))
}

/// The preparation of `world` (built from frame scene `still`) that its
/// tiles share: from its cache file in `dir` when present, else prepared
/// (its stages reported to `progress`) and stored there (atomically).
pub fn frame(
    dir: &Path,
    still: &SceneDesc,
    world: &World,
    progress: &dyn Progress,
) -> Result<(FramePrep, Source)> {
    let file = frame_path(dir, still)?;
    let key = frame_key(still)?;
    if file.exists() {
        let limit = 6 * natura::core::MAX_GRID_BYTES + 4096;
        let (_, body) = load(&file, FRAME, &key, limit)?;
        let prep = frame_from_bytes(&body, &file)?;
        return Ok((prep, Source::Cached));
    }
    let prep = FramePrep::new(world, progress)?;
    let body = frame_bytes(&prep);
    std::fs::create_dir_all(dir).map_err(|e| crate::error::io(dir, e))?;
    store(&file, FRAME, &key, &body.len().to_string(), &body)?;
    Ok((prep, Source::Computed))
}

/// Bytes of a plant: position, radius and vigor (`f32`), id (`u64`),
/// species (`u16`), dominated (`u8`).
const PLANT_BYTES: usize = 4 * 4 + 8 + 2 + 1;

/// The payload of a frame cache: the clouds' byte count (`u64`, `u64::MAX`
/// for none) and bytes, then the plant count (`u64`, `u64::MAX` for none)
/// and the plants.
fn frame_bytes(prep: &FramePrep) -> Vec<u8> {
    let mut out = Vec::new();
    match &prep.clouds {
        Some(c) => {
            let b = c.to_bytes();
            out.extend_from_slice(&(b.len() as u64).to_le_bytes());
            out.extend_from_slice(&b);
        }
        None => out.extend_from_slice(&u64::MAX.to_le_bytes()),
    }
    match &prep.plants {
        Some(plants) => {
            out.extend_from_slice(&(plants.len() as u64).to_le_bytes());
            for p in plants {
                for x in [p.x, p.y, p.radius, p.vigor] {
                    out.extend_from_slice(&x.to_bits().to_le_bytes());
                }
                out.extend_from_slice(&p.id.to_le_bytes());
                out.extend_from_slice(&p.species.to_le_bytes());
                out.push(u8::from(p.dominated));
            }
        }
        None => out.extend_from_slice(&u64::MAX.to_le_bytes()),
    }
    out
}

/// The frame's preparation from a frame cache's payload `body` (the
/// layout [`frame_bytes`] writes).
///
/// # Errors
///
/// Refuses, naming `file`, a payload that is truncated or whose counts and
/// sizes disagree with its length.
pub(crate) fn frame_from_bytes(body: &[u8], file: &Path) -> Result<FramePrep> {
    let refuse = |reason: String| CliError::Cache {
        path: file.display().to_string(),
        reason,
    };
    let truncated = || refuse("truncated frame cache".into());
    let mut at = 0usize;
    let count = |at: &mut usize| -> Result<u64> {
        let b = body.get(*at..*at + 8).ok_or_else(truncated)?;
        *at += 8;
        Ok(u64::from_le_bytes(b.try_into().unwrap_or_default()))
    };
    let clouds = match count(&mut at)? {
        u64::MAX => None,
        n => {
            let end = usize::try_from(n)
                .ok()
                .and_then(|n| at.checked_add(n))
                .filter(|&e| e <= body.len())
                .ok_or_else(truncated)?;
            let sky =
                CloudSky::from_bytes(&body[at..end], file).map_err(|e| refuse(e.to_string()))?;
            at = end;
            Some(sky)
        }
    };
    let plants = match count(&mut at)? {
        u64::MAX => None,
        n => {
            let rest = &body[at..];
            if usize::try_from(n)
                .ok()
                .and_then(|n| n.checked_mul(PLANT_BYTES))
                != Some(rest.len())
            {
                return Err(refuse(format!(
                    "{} bytes for {n} plants of {PLANT_BYTES} bytes",
                    rest.len()
                )));
            }
            let f = |b: &[u8], k: usize| {
                f32::from_bits(u32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]))
            };
            let plants = rest
                .chunks_exact(PLANT_BYTES)
                .map(|b| -> Result<Plant> {
                    let mut id = [0u8; 8];
                    id.copy_from_slice(&b[16..24]);
                    let dominated = match b[26] {
                        0 => false,
                        1 => true,
                        d => return Err(refuse(format!("plant flag {d} is neither 0 nor 1"))),
                    };
                    Ok(Plant {
                        x: f(b, 0),
                        y: f(b, 4),
                        radius: f(b, 8),
                        vigor: f(b, 12),
                        id: u64::from_le_bytes(id),
                        species: u16::from_le_bytes([b[24], b[25]]),
                        dominated,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            at = body.len();
            Some(plants)
        }
    };
    if at != body.len() {
        return Err(refuse(format!(
            "{} bytes after the clouds",
            body.len() - at
        )));
    }
    Ok(FramePrep { clouds, plants })
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
        assert!(e.contains("that of this scene's terrain"), "{e}");
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

    #[test]
    fn frame_payloads_round_trip_and_damage_is_refused() {
        let plant = |k: u16| Plant {
            x: 1.5 * f32::from(k),
            y: 2.0,
            radius: 0.25,
            vigor: 0.75,
            id: (3 << 40) | u64::from(k),
            species: k % 3,
            dominated: k.is_multiple_of(2),
        };
        let prep = FramePrep {
            clouds: None,
            plants: Some((0..5).map(plant).collect()),
        };
        let file = Path::new("frame.bin");
        let bytes = frame_bytes(&prep);
        let back = frame_from_bytes(&bytes, file).unwrap();
        assert!(back.clouds.is_none());
        assert_eq!(back.plants, prep.plants);
        let none = frame_bytes(&FramePrep {
            clouds: None,
            plants: None,
        });
        assert!(frame_from_bytes(&none, file).unwrap().plants.is_none());
        let mut flag = bytes.clone();
        let last = flag.len() - 1;
        flag[last] = 7;
        let e = frame_from_bytes(&flag, file).unwrap_err().to_string();
        assert!(e.contains("neither 0 nor 1"), "{e}");
        let e = frame_from_bytes(&bytes[..bytes.len() - 3], file)
            .unwrap_err()
            .to_string();
        assert!(e.contains("plants of 27 bytes"), "{e}");
        let e = frame_from_bytes(&bytes[..5], file).unwrap_err().to_string();
        assert!(e.contains("truncated"), "{e}");
        // Clouds claimed but absent.
        let mut claimed = bytes.clone();
        claimed[..8].copy_from_slice(&1000u64.to_le_bytes());
        assert!(frame_from_bytes(&claimed, file).is_err());

        // A terrain cache is not a frame cache.
        let dir = std::env::temp_dir().join(format!("natura-cli-frame-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let w = dir.join("w.bin");
        write(&w, "abc", &sample()).unwrap();
        let e = load(&w, FRAME, "abc", 1 << 20).unwrap_err().to_string();
        assert!(e.contains("not a natura frame cache"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    proptest::proptest! {
        /// The fuzz target `frame_cache` in small: a frame cache with any
        /// byte changed or cut anywhere is refused with an error naming the
        /// file, or read; never a panic.
        #[test]
        fn damaged_frame_caches_never_panic(
            at in 0usize..400,
            byte in proptest::num::u8::ANY,
            cut in 0usize..400,
        ) {
            let plant = Plant { x: 1.0, y: 2.0, radius: 0.5, vigor: 1.0, id: 9, species: 1, dominated: true };
            let body = frame_bytes(&FramePrep { clouds: None, plants: Some(vec![plant; 3]) });
            let mut file = format!(
                "natura frame cache\nnatura {VERSION}\nkey k\nsize {}\npayload {}\n\n",
                body.len(),
                hex(&Sha256::digest(&body))
            )
            .into_bytes();
            file.extend_from_slice(&body);
            if at < file.len() {
                file[at] = byte;
            }
            file.truncate(cut.min(file.len()));
            if let Err(e) = parse_frame_cache(file, "k", "f.bin") {
                proptest::prop_assert!(e.to_string().contains("f.bin"));
            }
        }
    }
}
