//! Scenes as TOML text: parsing with errors that name the file, line,
//! column and dotted key, loading from a file, and writing back.

use std::path::Path;

use serde::Deserialize;

use super::{AnimationKey, MAX_SCENE_FILE_BYTES, SceneDesc};
use crate::error::{RenderError, Result, fmt_f64};

impl SceneDesc {
    /// Parses a scene from TOML text. `name` labels errors (e.g. the file name).
    ///
    /// Errors name the line, column and dotted key, e.g.
    /// `scene.toml:12:1: key 'sun.elevation': unknown field ...`.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] naming `name` with the line and column
    /// of malformed TOML, an unknown key or a value of the wrong type;
    /// [`RenderError::Invalid`] naming the key of an array of the wrong
    /// length, or of a number too large for the key's 32-bit value.
    pub fn from_toml_str(text: &str, name: &str) -> Result<Self> {
        // The text as TOML: malformed TOML is reported with its line and
        // column.
        let ours: toml::Table = toml::from_str(text).map_err(|e| toml_error(text, name, &e))?;
        // Arrays of numbers have a fixed length: one of another length is
        // named by its key with the length it must have.
        check_lengths(&ours, &schema()?, "")?;
        // First pass, on the text as written: unknown keys and wrong types
        // are reported with their line and column. The terrain models'
        // sub-tables fill what they leave out from the models' defaults
        // here, so this pass only checks.
        toml::from_str::<SceneDesc>(text).map_err(|e| toml_error(text, name, &e))?;
        // Second pass: the file's keys laid over the built-in scene, so a
        // key left out of a sub-table keeps the scene's default, not the
        // model's.
        let mut table = toml::Table::try_from(SceneDesc::default())
            .map_err(|e| RenderError::Scene(format!("the built-in scene: {e}")))?;
        overlay(&mut table, ours.clone());
        let scene = SceneDesc::deserialize(toml::Value::Table(table))
            .map_err(|e| RenderError::Scene(format!("{name}: {}", e.message().trim())))?;
        // A finite number too large for a key held in 32 bits would be
        // read as infinite: named here with the number as written.
        let read = toml::Table::try_from(&scene)
            .map_err(|e| RenderError::Scene(format!("{name}: {e}")))?;
        check_narrowed(&ours, &read, "")?;
        Ok(scene)
    }

    /// Reads and parses a scene file. A missing or unreadable file is an error naming it.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] naming the file if it cannot be read,
    /// is not UTF-8 text or is larger than [`MAX_SCENE_FILE_BYTES`] (checked
    /// before it is read), the errors of [`SceneDesc::from_toml_str`], and those of
    /// [`SceneDesc::validate`].
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text = read_scene_file(path)?;
        let scene = Self::from_toml_str(&text, &path.display().to_string())?;
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as TOML text (every key written out).
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] if a value cannot be written as TOML
    /// (a NaN or infinite number).
    pub fn to_toml_string(&self) -> Result<String> {
        toml::to_string_pretty(self)
            .map_err(|e| RenderError::Scene(format!("cannot write scene as TOML: {e}")))
    }
}

/// Lays `top` over `base`: tables merge key by key, any other value replaces.
///
/// An enum-valued key is a table of one key, its variant (`phase = { cloud
/// = { diameter_um = 20.0 } }`): a table naming another variant replaces it
/// whole, since the two variants' tables cannot merge into one value.
fn overlay(base: &mut toml::Table, top: toml::Table) {
    for (key, value) in top {
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(t)) if !other_variant(b, &t) => {
                overlay(b, t);
            }
            (_, v) => {
                base.insert(key, v);
            }
        }
    }
}

/// Whether `top` names another variant than the one-key table `base` holds:
/// both have keys and share none.
fn other_variant(base: &toml::Table, top: &toml::Table) -> bool {
    base.len() == 1 && !top.is_empty() && !top.keys().any(|k| base.contains_key(k))
}

/// Turns a TOML error into one that names the file, line, column and dotted key.
fn toml_error(text: &str, name: &str, e: &toml::de::Error) -> RenderError {
    let message = e.message().trim().to_owned();
    let Some(span) = e.span() else {
        return RenderError::Scene(format!("{name}: {message}"));
    };
    let start = span.start.min(text.len());
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    let key = dotted_key(text, start);
    match key {
        Some(k) => RenderError::Scene(format!("{name}:{line}:{col}: key '{k}': {message}")),
        None => RenderError::Scene(format!("{name}:{line}:{col}: {message}")),
    }
}

/// The dotted key at byte `pos`: the `key = …` on that line, prefixed by the
/// last `[table]` header above it.
fn dotted_key(text: &str, pos: usize) -> Option<String> {
    let line_start = text[..pos].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    let line = text[line_start..line_end].trim();
    let header = |l: &str| -> Option<String> {
        let l = l.trim();
        (l.starts_with('[') && !l.starts_with("[[")).then(|| {
            l.trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_owned()
        })
    };
    if let Some(h) = header(line) {
        return Some(h);
    }
    let key = line.split('=').next()?.trim().trim_matches('"').to_owned();
    if key.is_empty() || line.starts_with('#') {
        return None;
    }
    let table = text[..line_start].lines().rev().find_map(header);
    Some(match table {
        Some(t) if !t.is_empty() => format!("{t}.{key}"),
        _ => key,
    })
}

/// Reads a scene file of at most [`MAX_SCENE_FILE_BYTES`]: its size is
/// checked before reading, and the read stops past the limit (a device or
/// a pipe has no size).
fn read_scene_file(path: &Path) -> Result<String> {
    use std::io::Read;
    let fail = |what: String| RenderError::Scene(format!("{}: {what}", path.display()));
    let file =
        std::fs::File::open(path).map_err(|e| fail(format!("cannot read scene file: {e}")))?;
    let too_large = |len: u64| {
        fail(format!(
            "the scene file is {len} bytes or more; a scene file holds at most \
             {MAX_SCENE_FILE_BYTES} bytes"
        ))
    };
    let len = file
        .metadata()
        .map_err(|e| fail(format!("cannot read scene file: {e}")))?
        .len();
    if len > MAX_SCENE_FILE_BYTES {
        return Err(too_large(len));
    }
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(format!("cannot read scene file: {e}")))?;
    if bytes.len() as u64 > MAX_SCENE_FILE_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| fail(format!("not UTF-8 text: {e}")))
}

/// The scene's shape as TOML: every key of the built-in scene, with an
/// animation key that sets every field, so each array's length is known.
fn schema() -> Result<toml::Table> {
    let mut s = SceneDesc::default();
    s.animation.keys.push(AnimationKey {
        frame: 0,
        position_uv: Some([0.0; 2]),
        target_uv: Some([0.0; 2]),
        height_above_ground_m: Some(0.0),
        pitch_deg: Some(0.0),
        sun_elevation_deg: Some(0.0),
        sun_azimuth_deg: Some(0.0),
    });
    toml::Table::try_from(s).map_err(|e| RenderError::Scene(format!("the built-in scene: {e}")))
}

/// `path.key`, or `key` at the top.
fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_owned()
    } else {
        format!("{path}.{key}")
    }
}

/// A value as the user wrote it, cut short if long.
fn written(v: &toml::Value) -> String {
    let s = v.to_string();
    if s.chars().count() > 80 {
        format!("{}…", s.chars().take(80).collect::<String>())
    } else {
        s
    }
}

/// Refuses an array of numbers whose length differs from the schema's,
/// naming its dotted key and the length it must have, and an array where
/// the schema has a table.
fn check_lengths(user: &toml::Table, schema: &toml::Table, path: &str) -> Result<()> {
    let number = |v: &toml::Value| matches!(v, toml::Value::Float(_) | toml::Value::Integer(_));
    for (key, value) in user {
        let name = join(path, key);
        match (value, schema.get(key)) {
            (toml::Value::Table(u), Some(toml::Value::Table(s))) => check_lengths(u, s, &name)?,
            // A section or a variant's parameters written as an array (serde
            // reads a struct from a sequence): refused here by its key, where
            // a surplus element was refused later without naming it.
            (toml::Value::Array(_), Some(toml::Value::Table(_))) => {
                return Err(RenderError::Invalid {
                    name,
                    value: written(value),
                    reason: "must be a table of keys (`{ key = value, … }`), not an array".into(),
                });
            }
            (toml::Value::Array(u), Some(toml::Value::Array(s))) => {
                if !s.is_empty() && s.iter().all(number) && u.len() != s.len() {
                    return Err(RenderError::Invalid {
                        name,
                        value: written(value),
                        reason: format!("must hold {} numbers, not {}", s.len(), u.len()),
                    });
                }
                if let Some(toml::Value::Table(s)) = s.first() {
                    for (i, u) in u.iter().enumerate() {
                        if let toml::Value::Table(u) = u {
                            check_lengths(u, s, &format!("{name}[{i}]"))?;
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Refuses a finite number of `user`'s that the scene `read` from it holds
/// as infinite (a key held in 32 bits), naming its key and the number.
fn check_narrowed(user: &toml::Table, read: &toml::Table, path: &str) -> Result<()> {
    for (key, value) in user {
        if let Some(r) = read.get(key) {
            narrowed(value, r, &join(path, key))?;
        }
    }
    Ok(())
}

fn narrowed(user: &toml::Value, read: &toml::Value, name: &str) -> Result<()> {
    match (user, read) {
        (toml::Value::Float(u), toml::Value::Float(r)) if u.is_finite() && !r.is_finite() => {
            Err(RenderError::Invalid {
                name: name.to_owned(),
                value: fmt_f64(*u),
                reason: format!(
                    "must lie in [{}, {}], the range of this key's 32-bit number",
                    fmt_f64(-f64::from(f32::MAX)),
                    fmt_f64(f64::from(f32::MAX))
                ),
            })
        }
        (toml::Value::Table(u), toml::Value::Table(r)) => check_narrowed(u, r, name),
        (toml::Value::Array(u), toml::Value::Array(r)) => {
            for (i, (u, r)) in u.iter().zip(r).enumerate() {
                narrowed(u, r, &format!("{name}[{i}]"))?;
            }
            Ok(())
        }
        _ => Ok(()),
    }
}
