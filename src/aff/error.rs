//! AFF errors: a parse error located in one of the scene's files (often an
//! included one), shown as `FILE:LINE:COLUMN: message`.

use thiserror::Error;

use crate::nff::{ParseError, ParseErrorKind};

/// A problem in an AFF scene: what went wrong, in which file, where.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}:{}:{}: {}", error.line, error.column, error.kind)]
pub struct AffError {
    /// The file, named as in [`super::SourceFile::name`].
    pub file: String,
    /// The line, column and kind.
    pub error: ParseError,
}

impl AffError {
    /// True if loading was cancelled rather than refused.
    pub fn is_cancelled(&self) -> bool {
        self.error.kind == ParseErrorKind::Cancelled
    }
}

/// Why reading a file stopped: a problem in it, or one in a file it includes (which
/// already names its own file).
#[derive(Debug)]
pub(super) enum Failure {
    /// In the file being read.
    Here(ParseError),
    /// In a file it includes.
    Nested(AffError),
}

impl From<ParseError> for Failure {
    fn from(e: ParseError) -> Failure {
        Failure::Here(e)
    }
}

/// What a reader of one file returns.
pub(super) type Read = Result<(), Failure>;
