//! Shards and their assembly: a tile of a frame rendered as a pure function
//! of scene, frame, tile, seed and version; a frame put together from its
//! tiles after every hash is checked, with the exposure and tone map of a
//! single-process render.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use natura::core::{Image, NoProgress};
use natura::render::{
    Rendered, SceneDesc, StageTimes, World, auto_exposure, render_world, scene_renderer_prepared,
};

use crate::cache;
use crate::error::{CliError, Result};
use crate::manifest::{TileLine, VERSION, frame_dir, platform, sha256_hex, tile_stem};
use crate::tiles;

/// The scene as shards identify it: parsed, validated, and hashed in its
/// canonical TOML (so formatting and comments do not matter).
pub struct Scene {
    /// The scene, all frames.
    pub desc: SceneDesc,
    /// SHA-256 of its canonical TOML.
    pub sha256: String,
}

impl Scene {
    /// Loads and validates a scene file.
    pub fn load(path: &Path) -> Result<Self> {
        let desc = SceneDesc::load(path)?;
        desc.validate()?;
        let sha256 = sha256_hex(desc.to_toml_string()?.as_bytes());
        Ok(Self { desc, sha256 })
    }
}

/// The final files of frame `frame` in `out`: `(png, exr)`.
pub fn frame_files(out: &Path, frame: u32) -> (PathBuf, PathBuf) {
    (
        out.join(format!("frame_{frame:04}.png")),
        out.join(format!("frame_{frame:04}.exr")),
    )
}

/// Renders frame `frame` whole in this process (no tiles, no cache): the
/// reference that assembled frames equal byte for byte.
pub fn render_frame(scene: &Scene, frame: u32, out: &Path) -> Result<PathBuf> {
    let still = scene.desc.at_frame(frame)?;
    let world = World::build(&still, &NoProgress)?;
    let rendered = render_world(&world, &NoProgress)?;
    let (png, exr) = frame_files(out, frame);
    rendered.save(&png, &exr)?;
    Ok(png)
}

/// What [`prepare`] found or made.
pub struct Prepared {
    /// The world cache's file and whether it was computed.
    pub world: (PathBuf, cache::Source),
    /// Each frame's cache.
    pub frames: Vec<(u32, PathBuf, cache::Source)>,
}

/// Builds the eroded terrain of `scene` into `cache_dir` (or checks the
/// cache there), then the frame cache (clouds and forest) of frames
/// `first..=last`, so that no tile computes either.
pub fn prepare(scene: &Scene, cache_dir: &Path, first: u32, last: u32) -> Result<Prepared> {
    let (eroded, source) = cache::eroded(cache_dir, &scene.desc)?;
    let mut out = Prepared {
        world: (cache::path(cache_dir, &scene.desc)?, source),
        frames: Vec::new(),
    };
    for frame in first..=last {
        let still = scene.desc.at_frame(frame)?;
        let world = World::from_eroded(&still, eroded.clone(), &NoProgress)?;
        let (_, source) = cache::frame(cache_dir, &still, &world)?;
        out.frames
            .push((frame, cache::frame_path(cache_dir, &still)?, source));
    }
    Ok(out)
}

/// Renders tile `tile` of `tiles` of frame `frame` into `out`: the tile's
/// EXR and its manifest line. Returns the manifest line.
pub fn render_tile(
    scene: &Scene,
    frame: u32,
    tile: u32,
    tiles: u32,
    out: &Path,
    cache_dir: &Path,
) -> Result<TileLine> {
    let still = scene.desc.at_frame(frame)?;
    let r = &still.render;
    let rect = tiles::rect(r.width, r.height, tile, tiles)?;
    let (eroded, _) = cache::eroded(cache_dir, &scene.desc)?;
    let world = World::from_eroded(&still, eroded, &NoProgress)?;
    let (prep, _) = cache::frame(cache_dir, &still, &world)?;
    let renderer = scene_renderer_prepared(&world, prep, &mut StageTimes::default(), &NoProgress)?;
    let image = renderer.render_region(rect.x, rect.y, rect.width, rect.height, &NoProgress)?;

    let dir = frame_dir(out, frame);
    std::fs::create_dir_all(&dir).map_err(|e| crate::error::io(&dir, e))?;
    let stem = tile_stem(tile, tiles);
    let exr = dir.join(format!("{stem}.exr"));
    image.save_exr(&exr)?;
    let sha256 = sha256_hex(&natura::core::io::read_file(&exr)?);
    let line = TileLine {
        natura: VERSION.to_owned(),
        platform: platform(),
        scene_sha256: scene.sha256.clone(),
        seed: still.seed,
        frame,
        tile,
        tiles,
        x: rect.x,
        y: rect.y,
        width: rect.width,
        height: rect.height,
        frame_width: r.width,
        frame_height: r.height,
        exposure_ev: r.exposure_ev,
        tone_map: r.tone_map,
        file: exr
            .strip_prefix(out)
            .unwrap_or(&exr)
            .to_string_lossy()
            .replace('\\', "/"),
        sha256,
    };
    line.write(&dir.join(format!("{stem}.json")))?;
    Ok(line)
}

/// The frames that have tiles under `out`, in order.
pub fn frames_present(out: &Path) -> Result<Vec<u32>> {
    let dir = out.join("tiles");
    let entries = std::fs::read_dir(&dir).map_err(|e| crate::error::io(&dir, e))?;
    let mut frames: Vec<u32> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| e.file_name().to_str()?.strip_prefix("frame_")?.parse().ok())
        .collect();
    frames.sort_unstable();
    Ok(frames)
}

/// Checks every tile of frame `frame` under `out` (all present, one scene,
/// one version, one tiling, every EXR matching its SHA-256) and writes the
/// frame's EXR and PNG. Every problem found is reported, each naming its
/// tile index.
pub fn assemble(out: &Path, frame: u32) -> Result<PathBuf> {
    let dir = frame_dir(out, frame);
    let entries = std::fs::read_dir(&dir).map_err(|e| crate::error::io(&dir, e))?;
    let mut lines = Vec::new();
    for e in entries.filter_map(|e| e.ok()) {
        let p = e.path();
        if p.extension().is_some_and(|x| x == "json") {
            lines.push(TileLine::read(&p)?);
        }
    }
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
    let (scene, platform) = (
        common(|l| &l.scene_sha256).unwrap_or_default(),
        common(|l| &l.platform).unwrap_or_default(),
    );
    let Some(first) = lines
        .iter()
        .find(|l| l.scene_sha256 == scene && l.platform == platform)
        .cloned()
    else {
        return Err(CliError::Assemble(vec![format!(
            "{f}: no tiles in {}",
            dir.display()
        )]));
    };
    let mut problems = Vec::new();
    let counts: std::collections::BTreeSet<u32> = lines.iter().map(|l| l.tiles).collect();
    if counts.len() > 1 {
        return Err(CliError::Assemble(vec![format!(
            "{f}: tiles of different tilings ({counts:?} tiles) in {}; remove the stale ones",
            dir.display()
        )]));
    }
    let n = first.tiles;
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
                &l.scene_sha256[..l.scene_sha256.len().min(12)],
                first.tile,
                &first.scene_sha256[..first.scene_sha256.len().min(12)]
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
        match tiles::rect(l.frame_width, l.frame_height, l.tile, n) {
            Ok(r) if (r.x, r.y, r.width, r.height) == (l.x, l.y, l.width, l.height) => {}
            _ => problems.push(format!("{t}: its rectangle is not tile {} of {n}", l.tile)),
        }
        by_index.insert(l.tile, l);
    }
    for i in (0..n).filter(|i| !by_index.contains_key(i)) {
        problems.push(format!("{f}, tile {i} of {n}: missing (no manifest line)"));
    }
    let mut image = Image::new(
        first.frame_width as usize,
        first.frame_height as usize,
        Default::default(),
    )?;
    for (i, l) in &by_index {
        let t = format!("{f}, tile {i} of {n}");
        let path = out.join(&l.file);
        let Ok(bytes) = natura::core::io::read_file(&path) else {
            problems.push(format!("{t}: missing EXR file {}", path.display()));
            continue;
        };
        if sha256_hex(&bytes) != l.sha256 {
            problems.push(format!(
                "{t}: {} does not match its SHA-256 (tampered or corrupt)",
                path.display()
            ));
            continue;
        }
        match Image::load_exr(&path) {
            Ok(tile) if (tile.width(), tile.height()) == (l.width as usize, l.height as usize) => {
                if problems.is_empty() {
                    paste(&mut image, &tile, l.x as usize, l.y as usize);
                }
            }
            Ok(_) => problems.push(format!("{t}: EXR size differs from its manifest line")),
            Err(e) => problems.push(format!("{t}: {e}")),
        }
    }
    if !problems.is_empty() {
        return Err(CliError::Assemble(problems));
    }
    let exposure_ev = first.exposure_ev.unwrap_or_else(|| auto_exposure(&image));
    let rendered = Rendered {
        image,
        exposure_ev,
        tone_map: first.tone_map,
        times: StageTimes::default(),
        forest: None,
    };
    let (png, exr) = frame_files(out, frame);
    rendered.save(&png, &exr)?;
    Ok(png)
}

fn paste(frame: &mut Image, tile: &Image, x0: usize, y0: usize) {
    let w = frame.width();
    let src = tile.pixels().as_slice();
    let dst = frame.pixels_mut().as_mut_slice();
    for (r, row) in src.chunks_exact(tile.width()).enumerate() {
        let start = (y0 + r) * w + x0;
        dst[start..start + row.len()].copy_from_slice(row);
    }
}
