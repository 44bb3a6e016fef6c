//! Scenes as TOML text: parsing with errors that name the file, line,
//! column and dotted key, loading from a file, and writing back.

use std::path::Path;

use serde::Deserialize;

use super::SceneDesc;
use crate::error::{RenderError, Result};

impl SceneDesc {
    /// Parses a scene from TOML text. `name` labels errors (e.g. the file name).
    ///
    /// Errors name the line, column and dotted key, e.g.
    /// `scene.toml:12:1: key 'sun.elevation': unknown field ...`.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] naming `name` with the line and column
    /// of malformed TOML, an unknown key or a value of the wrong type.
    pub fn from_toml_str(text: &str, name: &str) -> Result<Self> {
        // First pass, on the text as written: malformed TOML, unknown keys
        // and wrong types are reported with their line and column. The
        // terrain models' sub-tables fill what they leave out from the
        // models' defaults here, so this pass only checks.
        toml::from_str::<SceneDesc>(text).map_err(|e| toml_error(text, name, &e))?;
        // Second pass: the file's keys laid over the built-in scene, so a
        // key left out of a sub-table keeps the scene's default, not the
        // model's.
        let mut table = toml::Table::try_from(SceneDesc::default())
            .map_err(|e| RenderError::Scene(format!("the built-in scene: {e}")))?;
        let ours: toml::Table = toml::from_str(text).map_err(|e| toml_error(text, name, &e))?;
        overlay(&mut table, ours);
        SceneDesc::deserialize(toml::Value::Table(table))
            .map_err(|e| RenderError::Scene(format!("{name}: {}", e.message().trim())))
    }

    /// Reads and parses a scene file. A missing or unreadable file is an error naming it.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Scene`] naming the file if it cannot be read, the
    /// errors of [`SceneDesc::from_toml_str`], and those of
    /// [`SceneDesc::validate`].
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| {
            RenderError::Scene(format!("{}: cannot read scene file: {e}", path.display()))
        })?;
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
fn overlay(base: &mut toml::Table, top: toml::Table) {
    for (key, value) in top {
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(t)) => overlay(b, t),
            (_, v) => {
                base.insert(key, v);
            }
        }
    }
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
