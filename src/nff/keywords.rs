//! The one table of scene keywords: which language has each, whether a large file may
//! be split before it, and the function that reads it. The parser dispatches through
//! it, the error for an unknown keyword lists it, and the parallel parser's split
//! points come from it: a keyword is added here once.

use super::error::ParseError;
use super::lexer::Token;
use super::parser::Parser;
use super::Format;

/// Reads one entity whose keyword has just been taken.
pub(super) type Reader = fn(&mut Parser<'_>, &Token<'_>) -> Result<(), ParseError>;

/// One keyword of NFF or P3F.
pub(super) struct Keyword {
    /// The keyword as written.
    pub name: &'static str,
    /// Read in NFF files.
    pub nff: bool,
    /// Read in P3F files.
    pub p3f: bool,
    /// No entity takes this keyword as an operand, so the token stream splits
    /// cleanly before a line that starts with it (see `chunks.rs`).
    pub starts_piece: bool,
    /// Its reader.
    pub read: Reader,
}

const fn kw(name: &'static str, nff: bool, p3f: bool, starts_piece: bool, read: Reader) -> Keyword {
    Keyword {
        name,
        nff,
        p3f,
        starts_piece,
        read,
    }
}

/// Every keyword, NFF's first (the order of the lists in error messages).
pub(super) const KEYWORDS: &[Keyword] = &[
    kw("v", true, true, false, |p, t| p.view(t)),
    kw("b", true, false, false, |p, t| p.background(t)),
    kw("l", true, true, true, |p, t| p.light(t)),
    kw("f", true, true, true, |p, t| p.fill(t)),
    kw("s", true, true, true, |p, t| p.sphere(t)),
    kw("c", true, true, true, |p, t| p.cone(t)),
    kw("p", true, true, true, |p, t| p.polygon(t)),
    kw("pp", true, true, true, |p, t| p.patch(t)),
    kw("pl", true, true, true, |p, t| p.plane(t)),
    kw("aabb", true, false, true, |p, t| p.aabb(t)),
    kw("bclr", false, true, false, |p, t| p.background(t)),
    kw("env", false, true, false, |p, t| p.environment(t)),
    kw("al", false, true, false, |p, t| p.area_light(t)),
    kw("box", false, true, false, |p, t| p.p3f_box(t)),
    kw("mesh", false, true, false, |p, t| p.mesh(t)),
    kw("npl", false, true, false, |p, t| p.normal_plane(t)),
    kw("camera", false, true, false, |p, t| p.camera(t)),
    kw("light", false, true, false, |p, t| p.p3f_light(t)),
    kw("mat", false, true, false, |p, t| p.fill(t)),
    kw("spp", false, true, false, |p, t| p.samples_per_pixel(t)),
    kw("accel", false, true, false, |p, t| p.accelerator(t)),
    kw("sm", false, true, false, |p, t| p.moving_sphere(t)),
    kw("shutter", false, true, false, |p, t| p.shutter(t)),
    kw("integrator", false, true, false, |p, t| p.integrator(t)),
];

impl Keyword {
    /// True if files in `format` use this keyword (none is AFF's: [`crate::aff`] has
    /// its own table, which takes NFF's entities from this one).
    pub fn in_format(&self, format: Format) -> bool {
        match format {
            Format::Nff => self.nff,
            Format::P3f => self.p3f,
            Format::Aff => false,
        }
    }
}

/// The keyword `text` names in `format`, if any.
#[inline]
pub(super) fn find(text: &[u8], format: Format) -> Option<&'static Keyword> {
    KEYWORDS
        .iter()
        .find(|k| k.name.as_bytes() == text && k.in_format(format))
}

/// The other language than `format`, if `text` is one of its keywords (for the hint
/// of an unknown keyword: a P3F file read as NFF, or the reverse).
pub(super) fn other_format_with(text: &[u8], format: Format) -> Option<Format> {
    let other = match format {
        Format::Nff => Format::P3f,
        Format::P3f | Format::Aff => Format::Nff,
    };
    find(text, other).map(|_| other)
}

/// The keywords of `format`, as listed in error messages: `v, b, l, ...`.
pub(super) fn list(format: Format) -> String {
    let names: Vec<&str> = KEYWORDS
        .iter()
        .filter(|k| k.in_format(format))
        .map(|k| k.name)
        .collect();
    names.join(", ")
}

/// True if a piece of a large `format` file may start at a line beginning with `text`.
pub(super) fn starts_piece(text: &[u8], format: Format) -> bool {
    find(text, format).is_some_and(|k| k.starts_piece)
}
