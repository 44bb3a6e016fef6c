//! The stated limits of the `natura` binary, and the one way it reads a
//! file: its size checked against a limit before a byte is read.

use std::path::Path;

use crate::error::{CliError, Result};

/// Most tiles per frame (`--tile I/N`, `--tiles N`, a manifest's `tiles`).
pub const MAX_TILES: u32 = 65_536;

/// Most render tasks of a farm job (frames × tiles): Slurm's largest
/// `MaxArraySize` is 4 000 001, so array indices stay below 4 000 000.
pub const MAX_TASKS: u64 = 4_000_000;

/// Largest scene file read, bytes.
pub const MAX_SCENE_BYTES: u64 = 4 << 20;

/// Largest tile manifest file read, bytes.
pub const MAX_MANIFEST_BYTES: u64 = 64 << 10;

/// Most problems an assembly lists before it says how many more there are.
pub const MAX_PROBLEMS: usize = 50;

/// Reads `path` whole if it holds at most `limit` bytes; a larger file (or
/// one that grows past the limit while it is read) is an error naming the
/// file, `what` it is and the limit.
pub fn read_capped(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>> {
    let too_big = |size: u64| {
        CliError::Other(format!(
            "{}: {what} of {size} bytes is larger than the most natura reads, {limit} bytes",
            path.display()
        ))
    };
    let meta = std::fs::metadata(path).map_err(|e| crate::error::io(path, e))?;
    if meta.is_file() && meta.len() > limit {
        return Err(too_big(meta.len()));
    }
    // One byte more than the limit tells a file that grew from one that fits.
    let bytes = natura::core::io::read_file_at_most(path, limit.saturating_add(1))?;
    if bytes.len() as u64 > limit {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_over_their_limit_are_refused_by_name() {
        let dir = std::env::temp_dir().join(format!("natura-cli-limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("big.json");
        std::fs::write(&f, vec![b' '; 101]).unwrap();
        let e = read_capped(&f, 100, "tile manifest")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("big.json") && e.contains("101 bytes") && e.contains("100 bytes"),
            "{e}"
        );
        assert_eq!(read_capped(&f, 101, "x").unwrap().len(), 101);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
