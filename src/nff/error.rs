//! Parse errors: what went wrong and where.

use thiserror::Error;

use super::Format;

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
    /// A word where a keyword of the file's language must stand, and none of its
    /// keywords.
    #[error("unknown keyword {word}{}", other_language_hint(word, *other))]
    UnknownKeyword {
        /// The word, quoted.
        word: String,
        /// The other language, when the word is one of its keywords (a P3F file
        /// read as NFF, say).
        other: Option<Format>,
    },
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

impl ParseErrorKind {
    /// The message without the command line's hint of the other language (for a
    /// front end that says how to choose the format in its own words), and that
    /// language when the message has the hint.
    pub fn without_language_hint(&self) -> (String, Option<Format>) {
        match self {
            ParseErrorKind::UnknownKeyword { word, other } => (format!("unknown keyword {word}"), *other),
            kind => (kind.to_string(), None),
        }
    }
}

/// `; "accel" is a P3F keyword: is this a P3F file? (--format p3f)` when the word is a
/// keyword of `other`, else nothing.
fn other_language_hint(word: &str, other: Option<Format>) -> String {
    let (article, name, flag) = match other {
        None => return String::new(),
        Some(Format::Nff) => ("an", "NFF", "nff"),
        Some(Format::P3f) => ("a", "P3F", "p3f"),
        Some(Format::Aff) => ("an", "AFF", "aff"),
    };
    format!("; {word} is {article} {name} keyword: is this {article} {name} file? (--format {flag})")
}
