//! Shards and their assembly: a tile of a frame rendered as a pure function
//! of scene, frame, tile, seed and version; a frame put together from its
//! tiles after every hash is checked, with the exposure and tone map of a
//! single-process render.

use std::path::{Path, PathBuf};

use natura::core::{Image, Progress};
use natura::render::{
    Rendered, SceneDesc, StageTimes, World, auto_exposure, render_world, scene_renderer_prepared,
};

use crate::cache;
use crate::check::{Problems, check_lines};
use crate::error::{CliError, Result};
use crate::limits::{MAX_SCENE_BYTES, MAX_TILES, read_capped};
use crate::manifest::{
    TileLine, VERSION, frame_dir, platform, sha256_hex, tile_file, tile_sha256, tile_stem,
};
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
    /// Loads and validates a scene file of at most [`MAX_SCENE_BYTES`].
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = read_capped(path, MAX_SCENE_BYTES, "scene file")?;
        let name = path.display().to_string();
        let text = String::from_utf8(bytes)
            .map_err(|_| CliError::Other(format!("{name}: scene file is not UTF-8 text")))?;
        let desc = SceneDesc::from_toml_str(&text, &name)?;
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
/// reference that assembled frames equal byte for byte. Its stages are
/// reported to `progress`.
pub fn render_frame(
    scene: &Scene,
    frame: u32,
    out: &Path,
    progress: &dyn Progress,
) -> Result<PathBuf> {
    let still = scene.desc.at_frame(frame)?;
    let world = World::build(&still, progress)?;
    let rendered = render_world(&world, progress)?;
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
/// `first..=last`, so that no tile computes either. Its stages are reported
/// to `progress`.
pub fn prepare(
    scene: &Scene,
    cache_dir: &Path,
    first: u32,
    last: u32,
    progress: &dyn Progress,
) -> Result<Prepared> {
    let (eroded, source) = cache::eroded(cache_dir, &scene.desc, progress)?;
    let mut out = Prepared {
        world: (cache::path(cache_dir, &scene.desc)?, source),
        frames: Vec::new(),
    };
    for frame in first..=last {
        let still = scene.desc.at_frame(frame)?;
        let world = World::from_eroded(&still, eroded.clone(), progress)?;
        let (_, source) = cache::frame(cache_dir, &still, &world, progress)?;
        out.frames
            .push((frame, cache::frame_path(cache_dir, &still)?, source));
    }
    Ok(out)
}

/// Renders tile `tile` of `tiles` of frame `frame` into `out`: the tile's
/// EXR and its manifest line. Returns the manifest line. Its stages are
/// reported to `progress`.
pub fn render_tile(
    scene: &Scene,
    frame: u32,
    tile: u32,
    tiles: u32,
    out: &Path,
    cache_dir: &Path,
    progress: &dyn Progress,
) -> Result<TileLine> {
    let still = scene.desc.at_frame(frame)?;
    let r = &still.render;
    let rect = tiles::rect(r.width, r.height, tile, tiles)?;
    let (eroded, _) = cache::eroded(cache_dir, &scene.desc, progress)?;
    let world = World::from_eroded(&still, eroded, progress)?;
    let (prep, _) = cache::frame(cache_dir, &still, &world, progress)?;
    let renderer = scene_renderer_prepared(&world, prep, &mut StageTimes::default(), progress)?;
    let image = renderer.render_region(rect.x, rect.y, rect.width, rect.height, progress)?;

    let dir = frame_dir(out, frame);
    std::fs::create_dir_all(&dir).map_err(|e| crate::error::io(&dir, e))?;
    let stem = tile_stem(tile, tiles);
    let exr = dir.join(format!("{stem}.exr"));
    image.save_exr(&exr)?;
    let bytes = read_capped(&exr, exr_limit(rect.width, rect.height), "tile EXR")?;
    let sha256 = tile_sha256(&scene.sha256, frame, tile, tiles, &bytes);
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
        file: tile_file(frame, tile, tiles),
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

/// Largest EXR file of a `width × height` tile: its three `f32` channels
/// uncompressed, twice over, and a megabyte for its header and tables.
fn exr_limit(width: u32, height: u32) -> u64 {
    u64::from(width) * u64::from(height) * 12 * 2 + (1 << 20)
}

/// Checks every tile of frame `frame` under `out` (all present, one scene,
/// one version, one tiling, each where its index says, every EXR matching
/// its SHA-256, which binds it to its scene, frame and index) and writes the
/// frame's EXR and PNG. Every problem found is reported (at most
/// [`MAX_PROBLEMS`](crate::limits::MAX_PROBLEMS) lines), each naming its
/// tile index.
pub fn assemble(out: &Path, frame: u32) -> Result<PathBuf> {
    let dir = frame_dir(out, frame);
    let entries = std::fs::read_dir(&dir).map_err(|e| crate::error::io(&dir, e))?;
    let f = format!("frame {frame}");
    let mut problems = Problems::default();
    let mut lines = Vec::new();
    for e in entries.filter_map(|e| e.ok()) {
        let p = e.path();
        if p.extension().is_none_or(|x| x != "json") {
            continue;
        }
        if lines.len() == MAX_TILES as usize {
            return Err(CliError::Assemble(vec![format!(
                "{f}: more than {MAX_TILES} manifest files in {}, the most tiles a frame has",
                dir.display()
            )]));
        }
        let l = TileLine::read(&p)?;
        let stem = tile_stem(l.tile, l.tiles);
        if p.file_stem().is_none_or(|s| *s != *stem) {
            problems.push(format!(
                "{f}, tile {} of {}: its manifest line is in {}, not in {stem}.json",
                l.tile,
                l.tiles,
                p.display()
            ));
        }
        lines.push(l);
    }
    let Some(plan) = check_lines(lines, frame, &mut problems) else {
        if problems.is_empty() {
            problems.push(format!("{f}: no tiles in {}", dir.display()));
        }
        return Err(CliError::Assemble(problems.into_lines()));
    };
    let (first, n) = (&plan.first, plan.first.tiles);
    let mut image = Image::new(
        first.frame_width as usize,
        first.frame_height as usize,
        Default::default(),
    )?;
    for (i, l) in &plan.by_index {
        let t = format!("{f}, tile {i} of {n}");
        let path = out.join(&l.file);
        let bytes = match read_capped(&path, exr_limit(l.width, l.height), "tile EXR") {
            Ok(b) => b,
            Err(e) => {
                problems.push(format!("{t}: missing or unreadable EXR file: {e}"));
                continue;
            }
        };
        if tile_sha256(&l.scene_sha256, l.frame, l.tile, l.tiles, &bytes) != l.sha256 {
            problems.push(format!(
                "{t}: {} does not match its SHA-256 (tampered, corrupt, or another tile's)",
                path.display()
            ));
            continue;
        }
        match decode_exr(&bytes, &path) {
            Ok(tile) if (tile.width(), tile.height()) == (l.width as usize, l.height as usize) => {
                if let Some((x, y)) = tile.first_non_finite() {
                    problems.push(format!("{t}: pixel ({x}, {y}) is not a finite number"));
                } else if problems.is_empty() {
                    paste(&mut image, &tile, l.x as usize, l.y as usize);
                }
            }
            Ok(_) => problems.push(format!("{t}: EXR size differs from its manifest line")),
            Err(e) => problems.push(format!("{t}: {e}")),
        }
    }
    if !problems.is_empty() {
        return Err(CliError::Assemble(problems.into_lines()));
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

/// The linear colour of an EXR file's bytes (already read and checked).
fn decode_exr(bytes: &[u8], path: &Path) -> Result<Image> {
    let exr = natura::core::io::exr::read_exr_from(std::io::Cursor::new(bytes), path)?;
    let (w, h) = (exr.width, exr.height);
    let (Some(r), Some(g), Some(b)) = (exr.channel("R"), exr.channel("G"), exr.channel("B")) else {
        return Err(CliError::Other(format!(
            "{}: a tile EXR needs channels R, G and B",
            path.display()
        )));
    };
    if [r.len(), g.len(), b.len()] != [w * h; 3] {
        return Err(CliError::Other(format!(
            "{}: channel sizes differ from {w} × {h}",
            path.display()
        )));
    }
    Ok(Image::from_fn(w, h, |x, y| {
        let k = y * w + x;
        natura::core::glam::Vec3::new(r[k], g[k], b[k])
    })?)
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
