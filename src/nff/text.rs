//! What the parser is given before it reads a token: a UTF-8 byte-order mark at the
//! start (Windows editors write one) is skipped, and a file that is not text at all
//! (an image or a program passed as the scene) is refused as such, at its first
//! control byte, instead of as an unknown keyword full of invisible characters.

use super::error::{ParseError, ParseErrorKind};

/// The UTF-8 encoding of U+FEFF, the byte-order mark.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// Bytes scanned at once: the test over a block has no early exit, so it vectorizes.
const BLOCK: usize = 4096;

/// `src` without a leading byte-order mark, or an error at the first byte that no
/// text file holds (a control character other than tab, line feed, vertical tab,
/// form feed and carriage return). Line and column count from after the mark, as an
/// editor shows them.
pub(crate) fn scene_text(src: &[u8]) -> Result<&[u8], ParseError> {
    let text = src.strip_prefix(UTF8_BOM).unwrap_or(src);
    for (k, block) in text.chunks(BLOCK).enumerate() {
        if block.iter().fold(false, |any, &b| any | is_binary(b)) {
            let at = k * BLOCK + block.iter().position(|&b| is_binary(b)).expect("found above");
            return Err(binary_at(text, at, src.len() - text.len()));
        }
    }
    Ok(text)
}

/// True for the control bytes that text files do not contain: below 0x20 but for tab,
/// line feed, vertical tab, form feed and carriage return (0x09 to 0x0d), and 0x7f.
/// Written without branches (0x0e..0x1f is one unsigned comparison), so the block
/// scan compiles to a few byte-vector instructions per 16 bytes.
#[inline(always)]
fn is_binary(b: u8) -> bool {
    (b < 0x09) | (b.wrapping_sub(0x0e) < 0x20 - 0x0e) | (b == 0x7f)
}

/// The error for a control byte at offset `at` of `text`, which starts `skipped`
/// bytes into the file.
fn binary_at(text: &[u8], at: usize, skipped: usize) -> ParseError {
    let before = &text[..at];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    ParseError::new(
        u32::try_from(line).unwrap_or(u32::MAX),
        u32::try_from(at - line_start + 1).unwrap_or(u32::MAX),
        ParseErrorKind::Invalid(format!(
            "not a text scene: binary data at byte offset {} (0x{:02x})",
            skipped + at,
            text[at]
        )),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_leading_byte_order_mark_is_skipped() {
        assert_eq!(scene_text(b"\xEF\xBB\xBFs 0 0 0 1\n").unwrap(), b"s 0 0 0 1\n");
        // Only at the start: elsewhere it is an ordinary (non-ASCII) token.
        assert_eq!(scene_text(b"s \xEF\xBB\xBF").unwrap(), b"s \xEF\xBB\xBF");
    }

    #[test]
    fn control_bytes_are_binary_and_located() {
        // A PNG's signature: 0x89 P N G \r \n 0x1a \n, then a length with zero bytes.
        let e = scene_text(b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR").unwrap_err();
        assert_eq!((e.line, e.column), (2, 1));
        assert_eq!(
            e.kind.to_string(),
            "not a text scene: binary data at byte offset 6 (0x1a)"
        );
        // Past the first block, after a byte-order mark: offsets count the mark.
        let mut long = b"\xEF\xBB\xBF".to_vec();
        long.extend(std::iter::repeat_n(b'#', 5000));
        long.extend(b"\n  \0");
        let e = scene_text(&long).unwrap_err();
        assert_eq!((e.line, e.column), (2, 3));
        assert!(
            e.kind.to_string().contains("at byte offset 5006 (0x00)"),
            "{}",
            e.kind
        );
    }

    #[test]
    fn text_whitespace_and_non_ascii_are_not_binary() {
        let ok = b"# caf\xc3\xa9 \xe9\r\n\tv\x0b\x0cs 0 0 0 1\n";
        assert_eq!(scene_text(ok).unwrap(), ok);
    }

    #[test]
    fn binary_bytes_are_exactly_the_controls_text_lacks() {
        for b in 0..=255u8 {
            let control = b < 0x20 && !matches!(b, b'\t' | b'\n' | 0x0b | 0x0c | b'\r');
            assert_eq!(is_binary(b), control || b == 0x7f, "byte {b:#04x}");
        }
    }
}
