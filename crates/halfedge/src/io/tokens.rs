//! The tokenizer of the text formats read by hand (OFF, ASCII STL): tokens are runs of
//! bytes that are not ASCII white space, each with its line number.
//!
//! It works on bytes, not on `str`: bytes that are not UTF-8 (a Latin-1 name or comment)
//! are fine wherever a token is skipped, and a token that is parsed as a number and is not
//! UTF-8 is a malformed number like any other. Lines end at `\n`, `\r\n` or a lone `\r`;
//! a UTF-8 byte order mark at the start is skipped; with `comments`, `#` starts a comment
//! that runs to the end of its line.

/// One token and the line it is on (numbered from 1).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token<'a> {
    /// The token's bytes.
    pub(crate) text: &'a [u8],
    /// Its line, numbered from 1.
    pub(crate) line: usize,
}

impl Token<'_> {
    /// The token as text for messages (lossy, at most 40 characters).
    pub(crate) fn shown(&self) -> String {
        shown(self.text)
    }

    /// The token as an `f64` (Rust's syntax: `1`, `-1.5e3`, `inf`, `nan`), or `None`.
    pub(crate) fn f64(&self) -> Option<f64> {
        std::str::from_utf8(self.text).ok()?.parse().ok()
    }

    /// The token as an integer (`+` or `-` sign allowed), or `None`.
    pub(crate) fn i64(&self) -> Option<i64> {
        std::str::from_utf8(self.text).ok()?.parse().ok()
    }

    /// The token as a count (no sign), or `None`.
    pub(crate) fn u64(&self) -> Option<u64> {
        if self.text.first() == Some(&b'+') {
            return None;
        }
        std::str::from_utf8(self.text).ok()?.parse().ok()
    }

    /// True when the token is `word`, ignoring ASCII case.
    pub(crate) fn is(&self, word: &str) -> bool {
        self.text.eq_ignore_ascii_case(word.as_bytes())
    }
}

/// Bytes as text for messages: lossy, cut after 40 characters.
pub(crate) fn shown(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    if text.chars().count() > 40 {
        let cut: String = text.chars().take(40).collect();
        format!("{cut}…")
    } else {
        text.into_owned()
    }
}

/// The tokens of a text, in order.
#[derive(Clone)]
pub(crate) struct Tokens<'a> {
    bytes: &'a [u8],
    /// The next byte to look at.
    pos: usize,
    /// The line of `pos`.
    line: usize,
    /// `#` starts a comment.
    comments: bool,
}

impl<'a> Tokens<'a> {
    pub(crate) fn new(bytes: &'a [u8], comments: bool) -> Self {
        let pos = if bytes.starts_with(b"\xEF\xBB\xBF") {
            3
        } else {
            0
        };
        Self {
            bytes,
            pos,
            line: 1,
            comments,
        }
    }

    /// The line of the next byte (after the last token returned): for errors at the end
    /// of the file.
    pub(crate) fn line(&self) -> usize {
        self.line
    }

    /// The number of bytes not read yet.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// Skips white space and comments; with `stop_at_line_end`, stops before a line end.
    /// Returns true when it stopped before a line end.
    fn skip(&mut self, stop_at_line_end: bool) -> bool {
        while let Some(&b) = self.bytes.get(self.pos) {
            match b {
                b'\n' | b'\r' => {
                    if stop_at_line_end {
                        return true;
                    }
                    self.pos += 1;
                    // `\r\n` is one line end: the `\n` counts it.
                    if !(b == b'\r' && self.bytes.get(self.pos) == Some(&b'\n')) {
                        self.line += 1;
                    }
                }
                b' ' | b'\t' | 0x0b | 0x0c => self.pos += 1,
                b'#' if self.comments => {
                    while let Some(&c) = self.bytes.get(self.pos) {
                        if c == b'\n' || c == b'\r' {
                            break;
                        }
                        self.pos += 1;
                    }
                }
                _ => return false,
            }
        }
        false
    }

    /// The token starting at `pos` (which is not white space), consumed.
    fn take(&mut self) -> Option<Token<'a>> {
        let start = self.pos;
        while let Some(&b) = self.bytes.get(self.pos) {
            if b.is_ascii_whitespace() || b == 0x0b || (b == b'#' && self.comments) {
                break;
            }
            self.pos += 1;
        }
        (self.pos > start).then(|| Token {
            text: &self.bytes[start..self.pos],
            line: self.line,
        })
    }

    /// The next token, or `None` at the end of the file.
    pub(crate) fn next_token(&mut self) -> Option<Token<'a>> {
        self.skip(false);
        self.take()
    }

    /// The next token without consuming it.
    pub(crate) fn peek(&self) -> Option<Token<'a>> {
        self.clone().next_token()
    }

    /// The next token if it is on the current line, consumed.
    pub(crate) fn next_on_line(&mut self) -> Option<Token<'a>> {
        if self.skip(true) {
            return None;
        }
        self.take()
    }

    /// Skips the tokens left on the current line; returns how many there were and the
    /// first of them.
    pub(crate) fn skip_line(&mut self) -> (usize, Option<Token<'a>>) {
        let mut count = 0;
        let mut first = None;
        while let Some(token) = self.next_on_line() {
            first = first.or(Some(token));
            count += 1;
        }
        (count, first)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(bytes: &[u8], comments: bool) -> Vec<(String, usize)> {
        let mut t = Tokens::new(bytes, comments);
        std::iter::from_fn(|| t.next_token())
            .map(|t| (t.shown(), t.line))
            .collect()
    }

    #[test]
    fn tokens_and_their_lines() {
        let text = b"\xEF\xBB\xBFOFF # c\xe9\r\n 3\t1 0\r\r\n\n# x\n1.5e3 nan\x0b-2\n";
        assert_eq!(
            all(text, true),
            [
                ("OFF".into(), 1),
                ("3".into(), 2),
                ("1".into(), 2),
                ("0".into(), 2),
                ("1.5e3".into(), 6),
                ("nan".into(), 6),
                ("-2".into(), 6),
            ]
        );
        // Without comments, `#` is part of tokens.
        assert_eq!(all(b"a#b c", false).len(), 2);
        assert_eq!(all(b"a#b c", true).len(), 1);
    }

    #[test]
    fn lines_and_numbers() {
        let mut t = Tokens::new(b"3 0 1 2 255 0 0\n4 5\n", false);
        let count = t.next_token().unwrap();
        assert_eq!(count.u64(), Some(3));
        for _ in 0..3 {
            t.next_token().unwrap();
        }
        let (n, first) = t.skip_line();
        assert_eq!((n, first.unwrap().shown()), (3, "255".into()));
        assert_eq!(t.skip_line().0, 0, "the line end is not crossed twice");
        assert_eq!(t.next_token().unwrap().line, 2);
        assert_eq!(t.peek().unwrap().i64(), Some(5));
        assert!(t.next_on_line().is_some());
        assert!(t.next_on_line().is_none());
        assert!(t.next_token().is_none());
        let n = Token {
            text: b"+3",
            line: 1,
        };
        assert_eq!((n.u64(), n.i64()), (None, Some(3)));
        let latin1 = Token {
            text: b"1\xe9",
            line: 1,
        };
        assert_eq!(latin1.f64(), None);
        assert_eq!(latin1.shown(), "1\u{fffd}");
    }
}
