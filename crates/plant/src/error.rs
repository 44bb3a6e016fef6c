//! The error type of `natura-plant`.

use natura_core::CoreError;
use std::fmt;

/// A position in L-system text: 1-based line and column (in characters).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    /// Line, counted from 1.
    pub line: u32,
    /// Column in characters, counted from 1.
    pub col: u32,
}

impl Span {
    /// Returns the span at `line`, `col`.
    #[must_use]
    pub const fn new(line: u32, col: u32) -> Self {
        Self { line, col }
    }
}

impl fmt::Display for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.col)
    }
}

/// Everything that can go wrong in `natura-plant`.
///
/// Errors about L-system text name the line and column, as a compiler's do;
/// errors raised while a production is applied also name the production (its
/// label, or its line when it has none).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlantError {
    /// The L-system text does not parse.
    #[error("{span}: syntax error: {message}")]
    Syntax {
        /// Where the problem was found.
        span: Span,
        /// What was expected or found.
        message: String,
    },
    /// A name (variable, function, array, macro, surface) is used but never defined.
    #[error("{span}: undefined {what} `{name}`")]
    Undefined {
        /// Where the name is used.
        span: Span,
        /// What kind of name (`"variable"`, `"function"`, `"array"`, …).
        what: &'static str,
        /// The name itself.
        name: String,
    },
    /// An expression failed while a production (or the axiom) was evaluated:
    /// a division by zero, a NaN or infinite result, an array index out of range.
    #[error("{span}: in {production}: {message}")]
    Eval {
        /// Where the failing operation is in the text.
        span: Span,
        /// The production (`"production p3"`, `"production at line 7"`, `"the axiom"`).
        production: String,
        /// What went wrong.
        message: String,
    },
    /// The string grew past the configured limit on modules or parameters.
    #[error(
        "runaway growth at step {step}: {modules} modules and {params} parameters exceed the limit of {max_modules} modules / {max_params} parameters ({bytes} bytes)"
    )]
    Growth {
        /// The derivation step at which the limit was reached (1-based; 0 for
        /// the axiom and the interpretation rules).
        step: u32,
        /// Modules the string would hold.
        modules: usize,
        /// Parameters the string would hold.
        params: usize,
        /// The module limit in force.
        max_modules: usize,
        /// The parameter limit in force.
        max_params: usize,
        /// Approximate memory the string would need, in bytes.
        bytes: usize,
    },
    /// A derivation did more work than [`crate::Limits::max_work`] allows.
    #[error(
        "work limit reached at step {step}: {work} units of work (modules read and written, 64 per step) exceed the limit `max_work` = {max_work}"
    )]
    Work {
        /// The derivation step that would pass the limit (1-based).
        step: u32,
        /// The work the derivation would have done after that step's start.
        work: u64,
        /// The limit in force.
        max_work: u64,
    },
    /// Decomposition or interpretation rules recursed deeper than the maximum depth.
    #[error("{span}: {production} recursed deeper than the maximum depth {depth}")]
    Depth {
        /// Where the production starts.
        span: Span,
        /// The production that recursed.
        production: String,
        /// The maximum depth in force.
        depth: u32,
    },
    /// The string cannot be interpreted (unbalanced brackets, a polygon left open, …).
    #[error("interpretation of module {index} (`{module}`): {message}")]
    Interpret {
        /// Index of the module in the string.
        index: usize,
        /// The module's symbol.
        module: String,
        /// What went wrong.
        message: String,
    },
    /// The environment of an open L-system answered badly (unknown address, too many values, NaN).
    #[error("environment: {message}")]
    Environment {
        /// What was wrong with the reply.
        message: String,
    },
    /// A parameter is NaN, infinite or outside its valid range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as it appears in the API.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// The valid range, in words.
        reason: String,
    },
    /// A file's bytes are malformed (a truncated or corrupt glTF binary, …).
    #[error("malformed {what}: {message}")]
    Format {
        /// What kind of data (`"glTF binary"`).
        what: &'static str,
        /// What is wrong with it.
        message: String,
    },
    /// An error from `natura-core` (file I/O, images).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// An error from `natura-terrain` (analysis of the ecosystem's terrain).
    #[error(transparent)]
    Terrain(#[from] natura_terrain::TerrainError),
}

natura_core::from_param_error!(PlantError::InvalidParameter, expected: reason);

impl PlantError {
    /// Returns a syntax error at `span`.
    pub(crate) fn syntax(span: Span, message: impl Into<String>) -> Self {
        Self::Syntax {
            span,
            message: message.into(),
        }
    }

    /// Returns the line and column the error points at, if it concerns L-system text.
    #[must_use]
    pub fn span(&self) -> Option<Span> {
        match self {
            Self::Syntax { span, .. }
            | Self::Undefined { span, .. }
            | Self::Eval { span, .. }
            | Self::Depth { span, .. } => Some(*span),
            _ => None,
        }
    }
}

/// Shorthand for results of this crate.
pub type Result<T, E = PlantError> = std::result::Result<T, E>;
