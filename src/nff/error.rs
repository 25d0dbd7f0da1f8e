//! Parse errors: what went wrong and where.

use thiserror::Error;

/// A fatal problem in an NFF file, with its 1-based line and column.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("line {line}, column {column}: {kind}")]
pub struct ParseError {
    /// 1-based line of the offending token (or of the end of the file).
    pub line: u32,
    /// 1-based column (in bytes) of the offending token.
    pub column: u32,
    /// What went wrong.
    pub kind: ParseErrorKind,
}

/// The kinds of parse error.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ParseErrorKind {
    /// A token of the wrong form, or the end of the file, where something was required.
    #[error("expected {expected}, found {found}")]
    Expected {
        /// What the grammar needed here.
        expected: String,
        /// The token found, quoted, or "end of file".
        found: String,
    },
    /// A keyword that NFF (and our extensions) does not define.
    #[error("unknown keyword {0}")]
    UnknownKeyword(String),
    /// Well-formed but unusable input (a degenerate camera, a resolution past the cap, ...).
    #[error("{0}")]
    Invalid(String),
    /// The caller's cancellation flag was raised ([`crate::nff::parse_format_cancellable`]).
    #[error("parsing cancelled")]
    Cancelled,
}

impl ParseError {
    /// Builds an error at a location.
    pub fn new(line: u32, column: u32, kind: ParseErrorKind) -> Self {
        ParseError { line, column, kind }
    }
}
