//! The command-line tool's error: every failure names what went wrong and,
//! where it helps, what to do.

use natura::core::CoreError;
use natura::render::RenderError;

/// Everything that can stop a `natura` command.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad command-line arguments (exit status 2).
    #[error("{0}\n(run `natura --help` for usage)")]
    Usage(String),
    /// Standard output was closed by its reader (a broken pipe): the
    /// command ends quietly.
    #[error("standard output closed")]
    Closed,
    /// A scene, world or image error from the libraries.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A file error from natura-core.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// A cache file that cannot be used as it is.
    #[error("cache {path}: {reason}; delete it to recompute it")]
    Cache {
        /// The cache file.
        path: String,
        /// Why it is refused.
        reason: String,
    },
    /// Shards that do not make a frame (missing, tampered, mismatched).
    #[error("{}", .0.join("\n"))]
    Assemble(Vec<String>),
    /// Any other problem, stated in full.
    #[error("{0}")]
    Other(String),
}

impl CliError {
    /// A usage error.
    pub fn usage(m: impl Into<String>) -> Self {
        CliError::Usage(m.into())
    }
}

/// Shorthand for the tool's results.
pub type Result<T, E = CliError> = std::result::Result<T, E>;

/// An OS error on `path`, naming it.
pub fn io(path: &std::path::Path, source: std::io::Error) -> CliError {
    CliError::Core(CoreError::Io {
        path: path.into(),
        source,
    })
}
