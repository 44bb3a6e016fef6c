//! The glTF 2.0 binary container (GLB): a 12-byte header, a JSON chunk and
//! an optional binary chunk, each 4-byte aligned (Khronos, *glTF 2.0
//! Specification*, §4.4 "GLB File Format Specification"). What the JSON
//! says (meshes, accessors, materials) is the writer's business; this module
//! only frames and checks the chunks, for every natura crate that writes or
//! reads `.glb` files.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{CoreError, Result};
use crate::io::{WriteError, write_atomic};

const MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// The two chunks of a `.glb` file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Glb<'a> {
    /// The JSON chunk (UTF-8; a reader sees it without its trailing padding).
    pub json: &'a str,
    /// The binary chunk, if any.
    pub bin: Option<&'a [u8]>,
}

impl<'a> Glb<'a> {
    /// The file's bytes: the header, the JSON chunk padded with spaces and
    /// the binary chunk padded with zeros to multiples of 4 bytes.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::TooLarge`] if the file would reach 4 GiB (its
    /// lengths are 32-bit).
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        let pad = |n: usize| n.div_ceil(4) * 4;
        let json_len = pad(self.json.len());
        let bin_len = self.bin.map_or(0, |b| pad(b.len()));
        let total = 12 + 8 + json_len + self.bin.map_or(0, |_| 8 + bin_len);
        if total > u32::MAX as usize {
            return Err(CoreError::TooLarge {
                dims: "a glTF binary file".into(),
                bytes: total as u128,
                cap: u64::from(u32::MAX),
            });
        }
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
        out.extend_from_slice(self.json.as_bytes());
        out.resize(20 + json_len, b' ');
        if let Some(bin) = self.bin {
            out.extend_from_slice(&(bin_len as u32).to_le_bytes());
            out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
            out.extend_from_slice(bin);
            out.resize(total, 0);
        }
        Ok(out)
    }

    /// Writes the file atomically (a temporary name, then a rename).
    ///
    /// # Errors
    ///
    /// The errors of [`Glb::to_bytes`], and [`CoreError::Io`] naming the file
    /// if it cannot be written.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<()> {
        let bytes = self.to_bytes()?;
        write_atomic(path, |w| w.write_all(&bytes).map_err(WriteError::Io))
    }

    /// Splits `bytes` into the JSON and binary chunks, checking the magic,
    /// the version, the declared length against the real one and each
    /// chunk's length, type and 4-byte alignment (chunks after `BIN` are
    /// skipped, as the specification asks of readers, §4.4.3.1).
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Format`] saying what is wrong; never panics on
    /// any input.
    pub fn parse(bytes: &'a [u8]) -> Result<Self> {
        let bad = |m: String| CoreError::Format {
            path: PathBuf::from("(glTF binary)"),
            problem: m,
        };
        let u32_at = |o: usize| -> Option<u32> {
            bytes
                .get(o..o.checked_add(4)?)
                .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        };
        if bytes.len() < 20 {
            return Err(bad(format!("{} bytes, shorter than a header", bytes.len())));
        }
        if &bytes[0..4] != MAGIC {
            return Err(bad("the magic is not `glTF`".into()));
        }
        let version = u32_at(4).unwrap_or(0);
        if version != 2 {
            return Err(bad(format!("version {version}, expected 2")));
        }
        let total = u32_at(8).unwrap_or(0) as usize;
        if total != bytes.len() {
            return Err(bad(format!(
                "header says {total} bytes, the data holds {}",
                bytes.len()
            )));
        }
        let chunk = |at: usize| -> Result<(u32, &'a [u8], usize)> {
            let len = u32_at(at).ok_or_else(|| bad(format!("chunk header at {at} is cut off")))?;
            let ty =
                u32_at(at + 4).ok_or_else(|| bad(format!("chunk header at {at} is cut off")))?;
            let start = at + 8;
            let end = start
                .checked_add(len as usize)
                .filter(|&e| e <= bytes.len())
                .ok_or_else(|| bad(format!("chunk at {at} of {len} bytes runs past the end")))?;
            if len % 4 != 0 {
                return Err(bad(format!(
                    "chunk at {at}: length {len} is not a multiple of 4"
                )));
            }
            Ok((ty, &bytes[start..end], end))
        };
        let (ty, json, next) = chunk(12)?;
        if ty != CHUNK_JSON {
            return Err(bad(format!("first chunk has type {ty:#x}, expected JSON")));
        }
        let json = std::str::from_utf8(json)
            .map_err(|e| bad(format!("JSON chunk is not UTF-8: {e}")))?
            .trim_end_matches([' ', '\0']);
        let bin = if next < bytes.len() {
            let (ty, bin, end) = chunk(next)?;
            if ty != CHUNK_BIN {
                return Err(bad(format!("second chunk has type {ty:#x}, expected BIN")));
            }
            // Later chunks of other types are allowed and skipped, but each
            // must still fit the file.
            let mut at = end;
            while at < bytes.len() {
                at = chunk(at)?.2;
            }
            Some(bin)
        } else {
            None
        };
        Ok(Self { json, bin })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_pads_to_four_bytes() {
        let g = Glb {
            json: "{\"asset\":{}}",
            bin: Some(&[1, 2, 3, 4, 5]),
        };
        let bytes = g.to_bytes().unwrap();
        assert_eq!(bytes.len() % 4, 0);
        assert_eq!(bytes.len(), 12 + 8 + 12 + 8 + 8);
        let back = Glb::parse(&bytes).unwrap();
        assert_eq!(back.json, g.json);
        assert_eq!(back.bin, Some(&[1, 2, 3, 4, 5, 0, 0, 0][..]));
        let no_bin = Glb {
            json: "{}",
            bin: None,
        };
        let b = no_bin.to_bytes().unwrap();
        assert_eq!(Glb::parse(&b).unwrap(), no_bin);
    }

    #[test]
    fn every_truncation_is_an_error() {
        let bytes = Glb {
            json: "{\"a\":1}",
            bin: Some(&[9; 16]),
        }
        .to_bytes()
        .unwrap();
        for n in 0..bytes.len() {
            assert!(Glb::parse(&bytes[..n]).is_err(), "truncated to {n}");
        }
    }
}
