//! Large files parsed in pieces, one per thread, then joined into the scene a single
//! pass would give.
//!
//! A piece starts at the beginning of a line whose first token is one of the
//! keywords no entity takes as an operand (`s c p pp pl aabb f l`: the keyword
//! table's `starts_piece`), so the token stream splits cleanly and the parser stands
//! between two entities there. Only NFF files are split (P3F files are small but for
//! their meshes, which do not split). A piece
//! after the first parses with no view, no material and no limits of its own in play:
//! its objects before its first `f` take a placeholder material, resolved when the
//! pieces are joined. Anything that would make the join differ from one pass — an
//! error in any piece (the single pass then finds it and reports it), a `v` block
//! after the first piece, objects before any `f` in the whole file, or counts past the
//! limits — makes [`parse_in_parallel`] give up and leave the file to one pass.

use std::sync::atomic::AtomicBool;

use rayon::prelude::*;

use super::keywords::starts_piece;
use super::lexer::Lexer;
use super::limits::Limits;
use super::parser::{Parser, INHERITED_MATERIAL};
use super::Format;
use crate::scene::Scene;

/// Files below this size are parsed in one pass (a few milliseconds).
pub(super) const PARALLEL_BYTES: usize = 1 << 20;
/// The least bytes per piece.
const MIN_PIECE: usize = 256 << 10;
/// Lines looked at, from a piece's ideal start, for one that can begin it.
const SEARCH_LINES: usize = 1024;

/// The scene of `src` parsed in pieces on the current rayon pool, or `None` when the
/// file is small, the pool has one thread, or a piece could differ from one pass.
pub(super) fn parse_in_parallel(src: &[u8], limits: &Limits, cancel: Option<&AtomicBool>) -> Option<Scene> {
    let pieces = rayon::current_num_threads().min(src.len() / MIN_PIECE);
    if src.len() < PARALLEL_BYTES || pieces < 2 {
        return None;
    }
    parse_pieces_with(src, limits, &piece_starts(src, pieces), cancel)
}

/// Up to `pieces - 1` places to split `src` at, each the byte offset of a line start
/// and that line's number, in increasing order, near `i * len / pieces`.
pub(super) fn piece_starts(src: &[u8], pieces: usize) -> Vec<(usize, u32)> {
    let mut starts = Vec::new();
    let (mut counted_to, mut line) = (0usize, 1u32);
    for i in 1..pieces {
        let from = (i * src.len() / pieces).max(counted_to);
        let Some(at) = line_start_for_piece(src, from) else {
            continue;
        };
        line += src[counted_to..at].iter().filter(|&&b| b == b'\n').count() as u32;
        counted_to = at;
        starts.push((at, line));
    }
    starts
}

/// The first line starting after byte `from` whose first token can begin a piece.
fn line_start_for_piece(src: &[u8], from: usize) -> Option<usize> {
    let mut at = from + src[from..].iter().position(|&b| b == b'\n')? + 1;
    for _ in 0..SEARCH_LINES {
        let rest = &src[at..];
        let indent = rest.iter().take_while(|&&b| matches!(b, b' ' | b'\t')).count();
        let token = &rest[indent..];
        let word = token.iter().take_while(|&&b| !is_delimiter(b)).count();
        if starts_piece(&token[..word], Format::Nff) {
            return Some(at);
        }
        at += rest.iter().position(|&b| b == b'\n')? + 1;
    }
    None
}

/// Bytes that end a token (the lexer's whitespace and `#`).
fn is_delimiter(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c | b'#')
}

/// [`parse_pieces_with`] that cannot be cancelled.
#[cfg(test)]
pub(super) fn parse_pieces(src: &[u8], limits: &Limits, starts: &[(usize, u32)]) -> Option<Scene> {
    parse_pieces_with(src, limits, starts, None)
}

/// `src` parsed in pieces starting at `starts` (see [`piece_starts`]) and joined, or
/// `None` where the join could differ from one pass, or once `cancel` is raised
/// (each piece polls it).
fn parse_pieces_with(
    src: &[u8],
    limits: &Limits,
    starts: &[(usize, u32)],
    cancel: Option<&AtomicBool>,
) -> Option<Scene> {
    let bounds: Vec<(usize, usize, u32)> = std::iter::once((0, 1))
        .chain(starts.iter().copied())
        .zip(starts.iter().map(|&(at, _)| at).chain([src.len()]))
        .map(|((start, line), end)| (start, end, line))
        .collect();
    let parsed: Vec<Parser> = bounds
        .par_iter()
        .enumerate()
        .map(|(i, &(start, end, line))| {
            let lexer = Lexer::starting_at(&src[..end], start, line);
            let mut p = Parser::new(lexer, Format::Nff, limits, i > 0);
            p.cancel = cancel;
            p.run().ok().map(|()| p)
        })
        .collect::<Option<_>>()?;
    let mut parsed = parsed.into_iter();
    let mut whole = parsed.next()?;
    for piece in parsed {
        join(&mut whole, piece)?;
    }
    if whole.entities == 0 {
        return None;
    }
    let s = &whole.scene;
    let vertices = s.polygon_vertices.len() + s.patch_vertices.len();
    if s.primitive_count() > limits.max_primitives
        || vertices > limits.max_vertices
        || s.lights.len() > limits.max_lights
    {
        return None;
    }
    let end = whole.lexer.end_location();
    Some(whole.finish(end))
}

/// Appends the next piece's scene to `whole`'s, as if one parser had gone on: its
/// material indices shifted past `whole`'s table (its first material merged with
/// `whole`'s last when equal, as consecutive `f` lines are), its placeholder material
/// resolved, its vertex ranges shifted, its warnings kept in order under the cap.
fn join<'a>(whole: &mut Parser<'a>, piece: Parser<'a>) -> Option<()> {
    if piece.saw_view {
        return None;
    }
    let mut p = piece.scene;
    let background = p.background;
    let warnings = std::mem::take(&mut p.warnings);
    let p_materials = std::mem::take(&mut p.materials);
    let w = &mut whole.scene;
    let shared = !p_materials.is_empty() && w.materials.last() == p_materials.first();
    let base = (w.materials.len() - usize::from(shared)) as u32;
    let inherited = whole.material;
    let mut unresolved = false;
    let mut material = |m: u32| {
        if m != INHERITED_MATERIAL {
            return m + base;
        }
        unresolved |= inherited.is_none();
        inherited.unwrap_or(0)
    };
    w.append(p, &mut material);
    if unresolved {
        return None;
    }
    w.materials
        .extend(p_materials.into_iter().skip(usize::from(shared)));
    if piece.saw_background {
        w.background = background;
    }
    if let Some(m) = piece.material {
        whole.material = Some(m + base);
    }
    for warning in warnings {
        whole.warn((warning.line, warning.column), warning.message);
    }
    whole.warnings_left_out += piece.warnings_left_out;
    whole.entities += piece.entities;
    whole.lexer = piece.lexer;
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gen::{generate, SpdScene};
    use crate::nff::parser::parse_in_one_pass;
    use crate::nff::{parse_bytes_with, write_nff};

    /// Every entity kind, materials repeated across lines, lights with and without a
    /// colour, polygons and patches over several lines, comments, a second
    /// background, and skipped (warned) degenerate objects.
    const RICH: &str = "# a scene
v
from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 64 48
b 0.1 0.2 0.3
l 1 2 3
l 1 2 3 0.5 0.5 0.5
f 1 0 0 1 0 1 0 1
s 0 0 0 1
s 1 1 1 0
f 1 0 0 1 0 1 0 1
c 0 0 0 1 0 1 0 0.5   # a comment
c 0 0 0 1 0 0 0 0.5
p 3
0 0 0
1 0 0
0 1 0
f 0 1 0 1 0 1 0 1
pp 3
0 0 0 0 0 1
1 0 0 0 0 1
0 1 0 0 0 1
p 3
0 0 0
1 0 0
2 0 0
  pl 0 0 0 1 0 0 0 1 0
l 4 5 6
b 0.5 0.5 0.5
f 0 1 0 1 0 1 0 1
aabb -1 1 -2 2 -3 3
s 2 2 2 0.5
f 0 0 1 1 0 1 0 1
s 3 3 3 0.5 # end
";

    fn one_pass(src: &[u8]) -> Scene {
        parse_in_one_pass(src, Format::Nff, &Limits::default()).unwrap()
    }

    /// Line starts of `src` that can begin a piece, with their line numbers.
    fn eligible(src: &[u8]) -> Vec<(usize, u32)> {
        let mut out = Vec::new();
        let mut line = 1;
        for (i, &b) in src.iter().enumerate() {
            if b == b'\n' {
                line += 1;
                if line_start_for_piece(src, i) == Some(i + 1) {
                    out.push((i + 1, line));
                }
            }
        }
        out
    }

    #[test]
    fn every_split_and_pair_of_splits_gives_the_one_pass_scene() {
        let src = RICH.as_bytes();
        let want = one_pass(src);
        assert!(!want.warnings.is_empty());
        let starts = eligible(src);
        assert!(starts.len() >= 15, "{starts:?}");
        for (k, &a) in starts.iter().enumerate() {
            assert_eq!(
                parse_pieces(src, &Limits::default(), &[a]),
                Some(want.clone()),
                "at {a:?}"
            );
            for &b in &starts[k + 1..] {
                assert_eq!(
                    parse_pieces(src, &Limits::default(), &[a, b]),
                    Some(want.clone()),
                    "at {a:?} {b:?}"
                );
            }
        }
    }

    #[test]
    fn generated_scenes_split_anywhere_give_the_one_pass_scene() {
        for (which, size) in [
            (SpdScene::Rings, 2),
            (SpdScene::Gears, 1),
            (SpdScene::Tree, 6),
            (SpdScene::Teapot, 2),
        ] {
            let mut text = Vec::new();
            write_nff(&generate(which, size).unwrap(), &mut text).unwrap();
            let want = one_pass(&text);
            let starts = eligible(&text);
            assert!(starts.len() > 100, "{which:?}: {} starts", starts.len());
            for &a in starts.iter().step_by(7) {
                assert_eq!(
                    parse_pieces(&text, &Limits::default(), &[a]).as_ref(),
                    Some(&want),
                    "{which:?} at {a:?}"
                );
            }
            for pieces in 2..=8 {
                let at = piece_starts(&text, pieces);
                assert!(!at.is_empty());
                assert_eq!(
                    parse_pieces(&text, &Limits::default(), &at).as_ref(),
                    Some(&want),
                    "{which:?} {pieces} pieces"
                );
            }
        }
    }

    #[test]
    fn the_spd_files_in_pieces_give_the_one_pass_scene() {
        let Some(dir) = crate::test_skip::shared("scenes/spd") else {
            return;
        };
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let text = std::fs::read(&path).unwrap();
            let want = one_pass(&text);
            for pieces in [2, 3, 5] {
                let at = piece_starts(&text, pieces);
                assert_eq!(at.len(), pieces - 1, "{}", path.display());
                assert_eq!(
                    parse_pieces(&text, &Limits::default(), &at).as_ref(),
                    Some(&want),
                    "{}",
                    path.display()
                );
            }
        }
    }

    #[test]
    fn pieces_that_could_differ_leave_the_file_to_one_pass() {
        let split = |src: &str, line: u32| {
            let src = src.as_bytes();
            let at = eligible(src)
                .into_iter()
                .find(|&(_, l)| l == line)
                .expect("an eligible line");
            parse_pieces(src, &Limits::default(), &[at])
        };
        let view = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n";
        // A view in a later piece (the second replaces the first, with a warning).
        assert_eq!(
            split(&format!("{view}f 1 1 1 1 0 1 0 1\ns 0 0 0 1\n{view}"), 3),
            None
        );
        // Objects before any `f` in the whole file (a default material, a warning)
        // starting a later piece; after the first piece has met one, the join holds.
        let before_f = format!("{view}s 0 0 0 1\ns 1 1 1 1\n");
        assert_eq!(split(&before_f, 2), None);
        assert_eq!(split(&before_f, 3), Some(one_pass(before_f.as_bytes())));
        // An error in either piece.
        assert_eq!(
            split(&format!("{view}f 1 1 1 1 0 1 0 1\ns 0 0 0 x\ns 1 1 1 1\n"), 3),
            None
        );
        assert_eq!(
            split(&format!("{view}f 1 1 1 1 0 1 0 1\ns 0 0 0 1\ns 1 1 1\n"), 3),
            None
        );
        // Past a limit only together.
        let src = format!("{view}f 1 1 1 1 0 1 0 1\ns 0 0 0 1\ns 1 1 1 1\n");
        let at = eligible(src.as_bytes())[1];
        let two = Limits {
            max_primitives: 2,
            ..Limits::default()
        };
        let one = Limits {
            max_primitives: 1,
            ..Limits::default()
        };
        assert!(parse_pieces(src.as_bytes(), &two, &[at]).is_some());
        assert_eq!(parse_pieces(src.as_bytes(), &one, &[at]), None);
        assert!(parse_bytes_with(src.as_bytes(), &one).is_err());
    }

    #[test]
    fn warnings_past_the_cap_are_counted_across_pieces() {
        use crate::limits::MAX_WARNINGS;
        let mut src = String::from(
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\nf 1 1 1 1 0 1 0 1\n",
        );
        for _ in 0..MAX_WARNINGS + 300 {
            src.push_str("s 0 0 0 0\n");
        }
        let want = one_pass(src.as_bytes());
        assert_eq!(want.warnings.len(), MAX_WARNINGS + 1);
        for line in [3, 500, 1002, 1200] {
            let at = eligible(src.as_bytes())
                .into_iter()
                .find(|&(_, l)| l == line)
                .unwrap();
            assert_eq!(
                parse_pieces(src.as_bytes(), &Limits::default(), &[at]).as_ref(),
                Some(&want),
                "line {line}"
            );
        }
    }
}
