//! The one table of AFF's keywords and the function that reads each: NFF's that
//! AFF keeps, then AFF's own. The parser dispatches through it and the error for
//! an unknown keyword lists it.

use super::error::Read;
use super::parser::{loc, FileParser};
use crate::nff::{parse_f32, ParseError, ParseErrorKind, Token};

/// Reads one entity whose keyword has just been taken.
type Reader = fn(&mut FileParser<'_, '_, '_>, &Token<'_>) -> Read;

/// Every keyword with its reader, NFF's first (the order of the list in messages).
const KEYWORDS: &[(&str, Reader)] = &[
    ("v", |p, t| p.nff_entity(t)),
    ("b", |p, t| p.nff_entity(t)),
    ("l", |p, t| p.nff_entity(t)),
    ("f", |p, t| p.nff_entity(t)),
    ("s", |p, t| p.nff_entity(t)),
    ("c", |p, t| p.nff_entity(t)),
    ("p", |p, t| p.nff_entity(t)),
    ("pp", |p, t| p.nff_entity(t)),
    ("la", |p, t| p.named_light(t)),
    ("fm", |p, t| p.fill_material(t)),
    ("am", |p, t| p.ambient(t)),
    ("a", |p, t| p.animation_span(t)),
    ("i", |p, t| p.include(t)),
    ("d", |p, t| p.detail_level(t)),
    ("m", |p, t| p.mesh(t)),
    ("tt", |p, t| p.textured_triangle(t, false)),
    ("ttp", |p, t| p.textured_triangle(t, true)),
    ("tpa", |p, t| p.animated_triangle(t)),
    ("xs", |p, t| p.static_transform(t)),
    ("x", |p, t| p.animated_transform(t)),
    ("k", |p, t| p.keyframes(t)),
];

/// The reader of keyword `text`: one of the table's, or a run of `}` (each closes a
/// transform block, as the original reads them one character at a time).
pub(super) fn find(text: &[u8]) -> Option<Reader> {
    if !text.is_empty() && text.iter().all(|&b| b == b'}') {
        return Some(|p, t| p.close_blocks(t));
    }
    KEYWORDS
        .iter()
        .find(|(name, _)| name.as_bytes() == text)
        .map(|&(_, read)| read)
}

/// The error for `tok`, which is no keyword.
pub(super) fn unknown(tok: &Token) -> ParseError {
    let names: Vec<&str> = KEYWORDS.iter().map(|(name, _)| *name).collect();
    let expected = format!("a keyword ({}, or '}}')", names.join(", "));
    let kind = if parse_f32(tok.text).is_some() {
        ParseErrorKind::Expected {
            expected,
            found: format!("the number {}", tok.quoted()),
        }
    } else {
        ParseErrorKind::UnknownKeyword {
            word: tok.quoted(),
            other: None,
        }
    };
    let (line, column) = loc(tok);
    ParseError::new(line, column, kind)
}
