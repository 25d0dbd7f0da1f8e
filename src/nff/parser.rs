//! Turns NFF or P3F tokens into a [`Scene`]: the token-level machinery (numbers,
//! counts, warnings, limits) and the dispatch through the keyword table
//! (`keywords.rs`). The keywords themselves are read in `entities.rs` (NFF's, most
//! shared with P3F) and `p3f.rs` (P3F's own), one function per keyword, each quoting
//! its syntax.

use std::sync::atomic::{AtomicBool, Ordering};

use super::chunks;
use super::error::{ParseError, ParseErrorKind};
use super::keywords;
use super::lexer::{Lexer, Token};
use super::limits::Limits;
use super::text;
use super::Format;
use crate::limits::MAX_WARNINGS;
use crate::math::Vec3;
use crate::scene::{AngleSpan, Dialect, Material, Scene, Warning};

/// Parses NFF text into a scene. Errors carry the line and column of the offending token.
///
/// ```
/// let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 64 48\n\
///                                f 1 0 0 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
/// assert_eq!(scene.spheres.len(), 1);
/// assert_eq!((scene.view.width, scene.view.height), (64, 48));
/// ```
pub fn parse(src: &str) -> Result<Scene, ParseError> {
    parse_bytes(src.as_bytes())
}

/// Parses NFF from raw bytes (which need not be UTF-8: a non-ASCII token is reported
/// as an error), within the default [`Limits`].
pub fn parse_bytes(src: &[u8]) -> Result<Scene, ParseError> {
    parse_bytes_with(src, &Limits::default())
}

/// Parses NFF from raw bytes, refusing a file that describes more than `limits` allow
/// (at the first primitive, vertex or light past the limit). Files of a megabyte or
/// more are parsed in pieces on the current rayon pool's threads when they split
/// cleanly (see `chunks.rs`); the scene, warnings and errors are the same either way.
/// A leading UTF-8 byte-order mark is skipped and binary data refused (see `text.rs`).
pub fn parse_bytes_with(src: &[u8], limits: &Limits) -> Result<Scene, ParseError> {
    parse_format(src, Format::Nff, limits)
}

/// Parses a scene in `format` from raw bytes within `limits` (see
/// [`parse_bytes_with`]; P3F files are always parsed in one pass). A file without a
/// single entity is an error, and so is [`Format::Aff`]: an AFF file includes others
/// and is animated, so it is read by [`crate::aff`] (or [`crate::load`]).
pub fn parse_format(src: &[u8], format: Format, limits: &Limits) -> Result<Scene, ParseError> {
    parse_with(src, format, limits, None)
}

/// [`parse_format`] that gives up with [`ParseErrorKind::Cancelled`] soon after
/// `cancel` is raised (it is polled between entities; one entity, a mesh say, is
/// read whole).
pub fn parse_format_cancellable(
    src: &[u8],
    format: Format,
    limits: &Limits,
    cancel: &AtomicBool,
) -> Result<Scene, ParseError> {
    parse_with(src, format, limits, Some(cancel))
}

fn parse_with(
    src: &[u8],
    format: Format,
    limits: &Limits,
    cancel: Option<&AtomicBool>,
) -> Result<Scene, ParseError> {
    let src = text::scene_text(src)?;
    let parallel = match format {
        Format::Nff => chunks::parse_in_parallel(src, limits, cancel),
        Format::P3f => None,
        Format::Aff => {
            return Err(invalid(
                (1, 1),
                "AFF scenes are read by nffrt::aff or nffrt::load, which follow their includes",
            ))
        }
    };
    match parallel {
        Some(scene) => Ok(scene),
        None => parse_in_one_pass_with(src, format, limits, cancel),
    }
}

/// [`parse_format`] on the calling thread, token after token.
#[cfg(test)]
pub(super) fn parse_in_one_pass(src: &[u8], format: Format, limits: &Limits) -> Result<Scene, ParseError> {
    parse_in_one_pass_with(src, format, limits, None)
}

/// [`parse_format`] on the calling thread, token after token, polling `cancel`
/// between entities.
fn parse_in_one_pass_with(
    src: &[u8],
    format: Format,
    limits: &Limits,
    cancel: Option<&AtomicBool>,
) -> Result<Scene, ParseError> {
    let mut p = Parser::new(Lexer::new(src), format, limits, false);
    p.cancel = cancel;
    p.run()?;
    let end = p.lexer.end_location();
    if p.entities == 0 {
        return Err(err(
            end,
            ParseErrorKind::Invalid(
                "empty scene: the file holds no entity (no camera, light or object)".into(),
            ),
        ));
    }
    Ok(p.finish(end))
}

/// The material index primitives get, in a piece of a file parsed on its own, before
/// the piece's first `f`: the material then current in the pieces before it.
pub(super) const INHERITED_MATERIAL: u32 = u32::MAX;

pub(super) struct Parser<'a> {
    pub(super) lexer: Lexer<'a>,
    /// The language being read.
    pub(super) format: Format,
    pub(super) scene: Scene,
    /// Entities read so far.
    pub(super) entities: usize,
    /// A keyword only the 2024/25 P3F dialect has was read.
    pub(super) saw_p3f_2025: bool,
    /// Index of the current material, `None` before the first `f`.
    pub(super) material: Option<u32>,
    /// A piece of a file after its first: objects before any `f` take
    /// [`INHERITED_MATERIAL`] (no default material, no warning).
    pub(super) inherits_material: bool,
    pub(super) saw_view: bool,
    pub(super) saw_background: bool,
    pub(super) limits: Limits,
    /// Warnings past [`MAX_WARNINGS`], counted instead of kept.
    pub(super) warnings_left_out: usize,
    /// Raised by the caller to stop early (polled every [`CANCEL_POLL`] entities).
    pub(super) cancel: Option<&'a AtomicBool>,
}

/// Entities read between two looks at the cancellation flag.
const CANCEL_POLL: usize = 256;

/// A 1-based location.
pub(super) type Loc = (u32, u32);

pub(super) fn loc(t: &Token) -> Loc {
    (t.line, t.column)
}

pub(super) fn err(at: Loc, kind: ParseErrorKind) -> ParseError {
    ParseError::new(at.0, at.1, kind)
}

pub(super) fn invalid(at: Loc, msg: impl Into<String>) -> ParseError {
    err(at, ParseErrorKind::Invalid(msg.into()))
}

impl<'a> Parser<'a> {
    /// A parser of `lexer`'s tokens into an empty scene.
    pub(super) fn new(lexer: Lexer<'a>, format: Format, limits: &Limits, inherits_material: bool) -> Self {
        Parser {
            lexer,
            format,
            scene: Scene::default(),
            entities: 0,
            saw_p3f_2025: false,
            material: None,
            inherits_material,
            saw_view: false,
            saw_background: false,
            limits: *limits,
            warnings_left_out: 0,
            cancel: None,
        }
    }

    /// Parses every token (the warning for a missing view comes in
    /// [`Parser::finish`]).
    pub(super) fn run(&mut self) -> Result<(), ParseError> {
        while let Some(tok) = self.lexer.next() {
            if self.entities.is_multiple_of(CANCEL_POLL)
                && self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
            {
                return Err(err(loc(&tok), ParseErrorKind::Cancelled));
            }
            let Some(keyword) = keywords::find(tok.text, self.format) else {
                let kind = if parse_f32(tok.text).is_some() {
                    ParseErrorKind::Expected {
                        expected: format!("a keyword ({})", keywords::list(self.format)),
                        found: format!("the number {}", tok.quoted()),
                    }
                } else {
                    ParseErrorKind::UnknownKeyword {
                        word: tok.quoted(),
                        other: keywords::other_format_with(tok.text, self.format),
                    }
                };
                return Err(err(loc(&tok), kind));
            };
            (keyword.read)(self, &tok)?;
            self.entities += 1;
        }
        Ok(())
    }

    /// The scene, with the file's closing warnings: a missing view, and how many
    /// warnings were left out (reported at `end`, the end of the file).
    pub(super) fn finish(mut self, end: Loc) -> Scene {
        if self.format == Format::P3f {
            self.scene.dialect = if self.saw_p3f_2025 {
                Dialect::P3f2025
            } else {
                Dialect::P3f2019
            };
        }
        if !self.saw_view {
            let block = match self.format {
                Format::Nff | Format::Aff => "'v' block",
                Format::P3f => {
                    self.scene.view.angle_span = AngleSpan::ImageEdges;
                    "'v' or 'camera' block"
                }
            };
            self.warn(
                (1, 1),
                format!(
                    "no {block}: using the default camera (from 0 0 10, at 0 0 0, up 0 1 0, angle 45, 512x512)"
                ),
            );
        }
        if self.warnings_left_out > 0 {
            let n = self.warnings_left_out;
            self.scene.warnings.push(Warning {
                line: end.0,
                column: end.1,
                message: format!("... and {n} more warnings"),
            });
        }
        self.scene
    }

    /// Refuses the primitive at `at` if the scene already holds the most allowed.
    pub(super) fn admit_primitive(&self, at: Loc) -> Result<(), ParseError> {
        let max = self.limits.max_primitives;
        if self.scene.primitive_count() >= max {
            return Err(invalid(
                at,
                format!("more than {max} primitives (the limit; nffrt's --max-primitives raises it)"),
            ));
        }
        Ok(())
    }

    /// Refuses another polygon, patch or mesh vertex (of the entity at `kw`) past the
    /// limit, reporting it at the vertex's first token.
    pub(super) fn admit_vertex(&self, kw: &Token) -> Result<(), ParseError> {
        let max = self.limits.max_vertices;
        let s = &self.scene;
        if s.polygon_vertices.len() + s.patch_vertices.len() + s.mesh_vertices.len() >= max {
            let at = self.lexer.clone().next().map_or(loc(kw), |t| loc(&t));
            return Err(invalid(
                at,
                format!(
                    "more than {max} polygon, patch and mesh vertices (the limit; nffrt's --max-vertices raises it)"
                ),
            ));
        }
        Ok(())
    }

    /// Refuses the light at `kw` if the scene already holds the most allowed.
    pub(super) fn admit_light(&self, kw: &Token) -> Result<(), ParseError> {
        let max = self.limits.max_lights;
        if self.scene.lights.len() >= max {
            return Err(invalid(
                loc(kw),
                format!("more than {max} lights (the limit; nffrt's --max-lights raises it)"),
            ));
        }
        Ok(())
    }

    pub(super) fn warn(&mut self, at: Loc, message: String) {
        if self.scene.warnings.len() >= MAX_WARNINGS {
            self.warnings_left_out += 1;
            return;
        }
        self.scene.warnings.push(Warning {
            line: at.0,
            column: at.1,
            message,
        });
    }

    pub(super) fn expected(&self, tok: Option<Token>, expected: &str) -> ParseError {
        let (at, found) = match tok {
            Some(t) => (loc(&t), t.quoted()),
            None => (self.lexer.end_location(), "end of file".to_string()),
        };
        err(
            at,
            ParseErrorKind::Expected {
                expected: expected.to_string(),
                found,
            },
        )
    }

    /// Reads one finite number; `what` names it in the error message.
    pub(super) fn number(&mut self, what: &str) -> Result<f32, ParseError> {
        let tok = self.lexer.next();
        match tok.as_ref().and_then(|t| parse_f32(t.text)) {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(self.expected(tok, &format!("a finite number ({what})"))),
            None => Err(self.expected(tok, &format!("a number ({what})"))),
        }
    }

    pub(super) fn vec3(&mut self, what: &str) -> Result<Vec3, ParseError> {
        Ok(Vec3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }

    /// Reads a non-negative integer count.
    pub(super) fn count(&mut self, what: &str) -> Result<(u32, Loc), ParseError> {
        let tok = self.lexer.next();
        let Some(t) = tok else {
            return Err(self.expected(None, &format!("a count ({what})")));
        };
        if t.text.is_empty() || !t.text.iter().all(u8::is_ascii_digit) {
            return Err(self.expected(tok, &format!("a non-negative whole number ({what})")));
        }
        match std::str::from_utf8(t.text)
            .ok()
            .and_then(|s| s.parse::<u32>().ok())
        {
            Some(n) => Ok((n, loc(&t))),
            None => Err(invalid(loc(&t), format!("{what} {} is too large", t.quoted()))),
        }
    }

    /// The material index for a new object, falling back (once, with a warning) to
    /// [`Material::DEFAULT`] before the first `f`.
    pub(super) fn current_material(&mut self, at: Loc) -> u32 {
        if let Some(m) = self.material {
            return m;
        }
        if self.inherits_material {
            return INHERITED_MATERIAL;
        }
        self.warn(
            at,
            "object before any 'f': using the default material (f 1 1 1 1 0 1 0 1)".into(),
        );
        self.scene.materials.push(Material::DEFAULT);
        let m = (self.scene.materials.len() - 1) as u32;
        self.material = Some(m);
        m
    }
}

/// Parses a C-style float (`1`, `-0.5`, `.5`, `1E-3`). Returns `None` for anything
/// else, including Rust-only spellings such as `inf` and `nan` (which would parse but
/// are rejected later as non-finite anyway). `fast_float2` reads the bytes as
/// `str::parse` would (same syntax, correctly rounded), without first validating them
/// as UTF-8 and faster: 52 MB of triangles parse in 110 instead of 131 ms.
#[inline]
pub(crate) fn parse_f32(text: &[u8]) -> Option<f32> {
    let first = *text.first()?;
    if !(first.is_ascii_digit() || matches!(first, b'-' | b'+' | b'.')) {
        return None;
    }
    fast_float2::parse::<f32, _>(text).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    const VIEW: &str = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 64 48\n";

    fn parse_err(src: &str) -> ParseError {
        parse(src).expect_err("should fail")
    }

    #[test]
    fn parses_every_keyword() {
        let src = format!(
            "{VIEW}b 0.1 0.2 0.3\nl 1 2 3\nl 1 2 3 0.5 0.5 0.5\nf 1 0 0 1 0 1 0 1\n\
             s 0 0 0 1\nc 0 0 0 1 0 1 0 0.5\np 3 0 0 0 1 0 0 0 1 0\n\
             pp 3 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\npl 0 0 0 1 0 0 0 1 0\naabb -1 1 -2 2 -3 3\n"
        );
        let s = parse(&src).unwrap();
        assert_eq!(s.background, Vec3::new(0.1, 0.2, 0.3));
        assert_eq!(s.lights.len(), 2);
        assert_eq!(s.lights[0].color, None);
        assert_eq!(s.lights[1].color, Some(Vec3::splat(0.5)));
        assert_eq!(
            (
                s.spheres.len(),
                s.cones.len(),
                s.polygons.len(),
                s.patches.len(),
                s.planes.len(),
                s.boxes.len()
            ),
            (1, 1, 1, 1, 1, 1)
        );
        assert_eq!(s.boxes[0].min, Vec3::new(-1.0, -2.0, -3.0));
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    }

    #[test]
    fn unknown_keyword_names_line_and_column() {
        let e = parse_err(&format!("{VIEW}\n  zz 1 2 3"));
        assert_eq!((e.line, e.column), (3, 3));
        assert!(e.to_string().contains("unknown keyword \"zz\""), "{e}");
    }

    #[test]
    fn a_keyword_of_the_other_language_gets_a_hint() {
        let p3f = "camera\n  eye 0 0 5\n";
        let e = parse_format(
            format!("accel bvh\n{p3f}").as_bytes(),
            Format::Nff,
            &Limits::default(),
        )
        .unwrap_err();
        assert_eq!(
            e.kind.to_string(),
            r#"unknown keyword "accel"; "accel" is a P3F keyword: is this a P3F file? (--format p3f)"#
        );
        let e = parse_format(b"aabb 0 1 0 1 0 1\n", Format::P3f, &Limits::default()).unwrap_err();
        assert_eq!(
            e.kind.to_string(),
            r#"unknown keyword "aabb"; "aabb" is an NFF keyword: is this an NFF file? (--format nff)"#
        );
        // A word of neither language gets no hint.
        let e = parse_err(&format!("{VIEW}\nzz 1 2 3"));
        assert_eq!(e.kind.to_string(), r#"unknown keyword "zz""#);
    }

    #[test]
    fn truncated_sphere_reports_end_of_file() {
        let e = parse_err(&format!("{VIEW}f 1 1 1 1 0 1 0 1\ns 1 2"));
        assert!(e.to_string().contains("end of file"), "{e}");
        assert_eq!(e.line, 3);
    }

    /// `parse_f32` as the standard library would read the token (the parser used
    /// `str::parse` before `fast_float2`).
    fn std_f32(text: &[u8]) -> Option<f32> {
        let first = *text.first()?;
        if !(first.is_ascii_digit() || matches!(first, b'-' | b'+' | b'.')) {
            return None;
        }
        std::str::from_utf8(text).ok()?.parse::<f32>().ok()
    }

    #[test]
    fn numbers_read_as_the_standard_library_reads_them() {
        // Every token of up to six characters over the characters of a number, and
        // some others.
        let alphabet = b"05+-.eE1ix";
        let mut tokens: Vec<Vec<u8>> = vec![Vec::new()];
        let mut all = Vec::new();
        for _ in 0..6 {
            tokens = tokens
                .iter()
                .flat_map(|t| alphabet.iter().map(move |&c| [t.as_slice(), &[c]].concat()))
                .collect();
            all.extend(tokens.iter().cloned());
        }
        // Long mantissas and exponents near the ends of the range: rounding.
        let mut state = 0x853c_49e6_748f_ea9b_u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let digits = 1 + state % 30;
            let mantissa: String = (0..digits)
                .map(|k| char::from(b'0' + ((state >> (k % 50)) % 10) as u8))
                .collect();
            let point = (state >> 20) % (digits + 1);
            let exponent = ((state >> 32) % 100) as i64 - 55;
            let sign = if state & (1 << 40) != 0 { "-" } else { "" };
            let (a, b) = mantissa.split_at(point as usize);
            all.push(format!("{sign}{a}.{b}e{exponent}").into_bytes());
        }
        all.extend(
            [
                "inf",
                "nan",
                "-inf",
                "+nan",
                "1e39",
                "-1e-46",
                "3.4028236e38",
                "1.4e-45",
                "0x10",
                "1_0",
                " 1",
                "1 ",
            ]
            .map(|t| t.as_bytes().to_vec()),
        );
        let mut numbers = 0;
        for t in &all {
            let (got, want) = (parse_f32(t), std_f32(t));
            assert_eq!(
                got.map(f32::to_bits),
                want.map(f32::to_bits),
                "{:?}",
                String::from_utf8_lossy(t)
            );
            numbers += usize::from(want.is_some());
        }
        assert!(
            numbers > 100_000,
            "{numbers} of {} tokens were numbers",
            all.len()
        );
    }

    #[test]
    fn non_finite_numbers_are_refused() {
        for bad in ["nan", "inf", "1e39", "-infinity"] {
            let e = parse_err(&format!("{VIEW}s 0 0 {bad} 1"));
            assert!(e.to_string().contains("number"), "{bad}: {e}");
        }
    }

    #[test]
    fn huge_count_fails_without_allocating() {
        let e = parse_err(&format!("{VIEW}p 4000000000 1 2 3"));
        assert!(e.to_string().contains("end of file"), "{e}");
        let e = parse_err(&format!("{VIEW}p 99999999999"));
        assert!(e.to_string().contains("too large"), "{e}");
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        for cam in [
            "v from 0 0 0 at 0 0 0 up 0 1 0 angle 40",
            "v from 0 0 5 at 0 0 0 up 0 0 1 angle 40",
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 180",
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 0",
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 40000 10",
            "v from 0 0 5 at 0 0 0 up 0 1 0",
        ] {
            assert!(matches!(parse_err(cam).kind, ParseErrorKind::Invalid(_)), "{cam}");
        }
    }

    #[test]
    fn default_material_and_degenerate_geometry_warn_with_lines() {
        let s = parse(&format!("{VIEW}s 0 0 0 1\ns 0 0 0 0\np 3 0 0 0 1 1 1 2 2 2\n")).unwrap();
        assert_eq!(s.spheres.len(), 1);
        assert!(s.polygons.is_empty() && s.polygon_vertices.is_empty());
        let lines: Vec<u32> = s.warnings.iter().map(|w| w.line).collect();
        assert_eq!(lines, vec![2, 3, 4]);
        assert_eq!(s.materials, vec![Material::DEFAULT]);
    }

    #[test]
    fn bad_angle_is_reported_at_its_value() {
        let e = parse_err("v from 0 0 5 at 0 0 0 up 0 1 0\n  angle -5");
        assert_eq!((e.line, e.column), (2, 9));
    }

    #[test]
    fn cameras_that_overflow_f32_are_refused() {
        for cam in [
            "v from 0 0 3e38 at 0 0 -3e38 up 0 1 0 angle 40",
            "v from 0 0 3e19 at 0 0 0 up 0 1 0 angle 40",
            "v from 0 0 5 at 0 0 0 up 3e38 3e38 0 angle 40",
        ] {
            assert!(matches!(parse_err(cam).kind, ParseErrorKind::Invalid(_)), "{cam}");
        }
    }

    #[test]
    fn light_colour_is_optional_even_before_a_keyword() {
        let s = parse(&format!("{VIEW}l 1 2 3\nl 4 5 6 1 1 1 l 7 8 9")).unwrap();
        let colors: Vec<_> = s.lights.iter().map(|l| l.color.is_some()).collect();
        assert_eq!(colors, vec![false, true, false]);
    }
}
