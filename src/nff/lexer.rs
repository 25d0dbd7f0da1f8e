//! Splits NFF text into whitespace-separated tokens, each with its line and column.

/// One token: a run of non-whitespace bytes outside comments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Token<'a> {
    /// The token's bytes (not necessarily UTF-8).
    pub text: &'a [u8],
    /// 1-based line.
    pub line: u32,
    /// 1-based column, in bytes.
    pub column: u32,
}

impl Token<'_> {
    /// The token quoted for an error message, with non-printable bytes escaped
    /// and long tokens shortened.
    pub fn quoted(&self) -> String {
        const MAX: usize = 40;
        let shown = &self.text[..self.text.len().min(MAX)];
        let mut s = String::with_capacity(shown.len() + 2);
        s.push('"');
        for chunk in shown.utf8_chunks() {
            for c in chunk.valid().chars() {
                if c.is_control() {
                    s.extend(c.escape_default());
                } else {
                    s.push(c);
                }
            }
            for b in chunk.invalid() {
                s.push_str(&format!("\\x{b:02x}"));
            }
        }
        if self.text.len() > MAX {
            s.push_str("...");
        }
        s.push('"');
        s
    }
}

/// An iterator over the tokens of an NFF source.
#[derive(Clone, Debug)]
pub struct Lexer<'a> {
    src: &'a [u8],
    pos: usize,
    line: u32,
    line_start: usize,
}

impl<'a> Lexer<'a> {
    /// Starts lexing `src` from its beginning.
    pub fn new(src: &'a [u8]) -> Self {
        Lexer {
            src,
            pos: 0,
            line: 1,
            line_start: 0,
        }
    }

    /// Lexes `src` from byte `pos`, the start of line `line` (a piece of a file
    /// parsed on its own: locations stay those of the whole file).
    pub(super) fn starting_at(src: &'a [u8], pos: usize, line: u32) -> Self {
        Lexer {
            src,
            pos,
            line,
            line_start: pos,
        }
    }

    /// Line and column just past the last byte, for "unexpected end of file".
    pub fn end_location(&self) -> (u32, u32) {
        let mut line = self.line;
        let mut line_start = self.line_start;
        for (i, &b) in self.src.iter().enumerate().skip(self.pos) {
            if b == b'\n' {
                line += 1;
                line_start = i + 1;
            }
        }
        (line, (self.src.len() - line_start + 1) as u32)
    }
}

impl<'a> Iterator for Lexer<'a> {
    type Item = Token<'a>;

    #[inline]
    fn next(&mut self) -> Option<Token<'a>> {
        let src = self.src;
        // Skip whitespace and comments.
        loop {
            let &b = src.get(self.pos)?;
            match b {
                b'\n' => {
                    self.pos += 1;
                    self.line += 1;
                    self.line_start = self.pos;
                }
                b' ' | b'\t' | b'\r' | 0x0b | 0x0c => self.pos += 1,
                b'#' => {
                    while self.pos < src.len() && src[self.pos] != b'\n' {
                        self.pos += 1;
                    }
                }
                _ => break,
            }
        }
        let start = self.pos;
        while self.pos < src.len() {
            match src[self.pos] {
                b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c | b'#' => break,
                _ => self.pos += 1,
            }
        }
        Some(Token {
            text: &src[start..self.pos],
            line: self.line,
            column: (start - self.line_start + 1) as u32,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(src: &str) -> Vec<(String, u32, u32)> {
        Lexer::new(src.as_bytes())
            .map(|t| (String::from_utf8_lossy(t.text).into_owned(), t.line, t.column))
            .collect()
    }

    #[test]
    fn tokens_carry_line_and_column() {
        let got = texts("s 1 2\r\n\t3 # comment\n  .5");
        assert_eq!(
            got,
            vec![
                ("s".into(), 1, 1),
                ("1".into(), 1, 3),
                ("2".into(), 1, 5),
                ("3".into(), 2, 2),
                (".5".into(), 3, 3),
            ]
        );
    }

    #[test]
    fn comment_glued_to_a_token_ends_it() {
        assert_eq!(texts("12#x\n3").len(), 2);
    }

    #[test]
    fn end_location_points_past_the_last_byte() {
        let mut lx = Lexer::new(b"s 1\n2 ");
        while lx.next().is_some() {}
        assert_eq!(lx.end_location(), (2, 3));
    }

    #[test]
    fn quoting_escapes_binary() {
        let t = Token {
            text: b"a\xff\x01",
            line: 1,
            column: 1,
        };
        assert_eq!(t.quoted(), "\"a\\xff\\u{1}\"");
    }
}
