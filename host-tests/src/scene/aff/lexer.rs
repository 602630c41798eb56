//! Byte lexer for AFF text.
//!
//! Works on raw bytes (CRLF line ends and Latin-1 bytes in comments are
//! fine; nothing is decoded as UTF-8 except names). Whitespace is space,
//! tab, LF, CR, VT and FF. `{` and `}` are always tokens of their own, so
//! `xs … {` and `x NAME{` both lex. Tokens are borrowed slices of the file
//! (no allocation per token); the lexer tracks the 1-based line of each
//! token.

/// One whitespace-separated token and the line it starts on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token<'a> {
    /// The bytes of the token.
    pub text: &'a [u8],
    /// 1-based line.
    pub line: usize,
}

impl Token<'_> {
    /// The token as (lossy) text for messages.
    pub fn show(&self) -> String {
        String::from_utf8_lossy(self.text).into_owned()
    }
}

/// Cursor over one file's bytes.
pub(crate) struct Lexer<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

#[inline]
fn is_space(c: u8) -> bool {
    matches!(c, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `bytes` (line 1).
    pub fn new(bytes: &'a [u8]) -> Self {
        Self {
            bytes,
            pos: 0,
            line: 1,
        }
    }

    /// Current line (the line of the last token read, or of the end of file
    /// once everything is consumed).
    pub fn line(&self) -> usize {
        self.line
    }

    /// Number of lines in the file, once [`next_token`](Self::next_token)
    /// has returned `None` (a last line without newline counts).
    pub fn line_count_at_end(&self) -> usize {
        match self.bytes.last() {
            None => 0,
            Some(b'\n') => self.line - 1,
            Some(_) => self.line,
        }
    }

    fn skip_space(&mut self) {
        while let Some(&c) = self.bytes.get(self.pos) {
            if !is_space(c) {
                break;
            }
            if c == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }

    /// The next token, or `None` at end of file.
    pub fn next_token(&mut self) -> Option<Token<'a>> {
        self.skip_space();
        let start = self.pos;
        let first = *self.bytes.get(start)?;
        if first == b'{' || first == b'}' {
            self.pos += 1;
        } else {
            while let Some(&c) = self.bytes.get(self.pos) {
                if is_space(c) || c == b'{' || c == b'}' {
                    break;
                }
                self.pos += 1;
            }
        }
        Some(Token {
            text: &self.bytes[start..self.pos],
            line: self.line,
        })
    }

    /// The next token without consuming it.
    pub fn peek(&mut self) -> Option<Token<'a>> {
        let (pos, line) = (self.pos, self.line);
        let t = self.next_token();
        self.pos = pos;
        self.line = line;
        t
    }

    /// Skips the rest of the current line (a comment). Stops before the
    /// newline so line counting stays right.
    pub fn skip_line(&mut self) {
        while let Some(&c) = self.bytes.get(self.pos) {
            if c == b'\n' {
                break;
            }
            self.pos += 1;
        }
    }
}

/// Exact powers of ten up to 10^22 (all representable in f64).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Fast path for plain decimals (`[+-]digits[.digits]`, at most 15 digits,
/// no exponent): the mantissa (< 10^15 < 2^53) and 10^k (k ≤ 22) are exact
/// in f64, so one IEEE division gives the correctly rounded value — the
/// same as the full parser. `None` hands the token to the full parser.
fn parse_plain_decimal(text: &[u8]) -> Option<f64> {
    let (neg, digits) = match text.first()? {
        b'-' => (true, &text[1..]),
        b'+' => (false, &text[1..]),
        _ => (false, text),
    };
    let (mut mant, mut ndig, mut frac, mut dot) = (0u64, 0usize, 0usize, false);
    for &c in digits {
        match c {
            b'0'..=b'9' => {
                mant = mant * 10 + u64::from(c - b'0');
                ndig += 1;
                frac += usize::from(dot);
                if ndig > 15 {
                    return None;
                }
            }
            b'.' if !dot => dot = true,
            _ => return None,
        }
    }
    if ndig == 0 {
        return None;
    }
    let v = mant as f64 / POW10[frac];
    Some(if neg { -v } else { v })
}

/// Parses a C-style float (`3.`, `-2.18557e-07`, `1.85E-4`, `255`, `.5`).
/// Rejects anything else, including `nan` and `inf`.
pub(crate) fn parse_f64(text: &[u8]) -> Option<f64> {
    if let Some(v) = parse_plain_decimal(text) {
        return Some(v);
    }
    // Only the characters a C float literal can hold; this also rejects
    // `inf`/`nan`, which str::parse would accept.
    if text.is_empty()
        || !text
            .iter()
            .all(|c| matches!(c, b'0'..=b'9' | b'+' | b'-' | b'.' | b'e' | b'E'))
    {
        return None;
    }
    // ASCII only, so this cannot fail.
    let s = std::str::from_utf8(text).ok()?;
    let v: f64 = s.parse().ok()?;
    v.is_finite().then_some(v)
}

/// Parses a non-negative decimal integer.
pub(crate) fn parse_usize(text: &[u8]) -> Option<usize> {
    let digits = text.strip_prefix(b"+").unwrap_or(text);
    if digits.is_empty() || digits.len() > 18 || !digits.iter().all(u8::is_ascii_digit) {
        return None;
    }
    Some(
        digits
            .iter()
            .fold(0usize, |acc, &d| acc * 10 + usize::from(d - b'0')),
    )
}

/// Parses a (possibly negative) decimal integer.
pub(crate) fn parse_i64(text: &[u8]) -> Option<i64> {
    match text.strip_prefix(b"-") {
        Some(rest) => parse_usize(rest).map(|v| -(v as i64)),
        None => parse_usize(text).map(|v| v as i64),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_lines_braces_crlf_latin1() {
        let src = b"xs 1 2{\r\n% caf\xf6 }\r\n}x\n";
        let mut lx = Lexer::new(src);
        let mut out = Vec::new();
        while let Some(t) = lx.next_token() {
            if t.text.starts_with(b"%") {
                lx.skip_line();
                continue;
            }
            out.push((t.show(), t.line));
        }
        let want = [("xs", 1), ("1", 1), ("2", 1), ("{", 1), ("}", 3), ("x", 3)];
        let want: Vec<_> = want.iter().map(|(s, l)| (s.to_string(), *l)).collect();
        assert_eq!(out, want);
        assert_eq!(lx.line_count_at_end(), 3);
        let mut lx = Lexer::new(b"a\nb");
        while lx.next_token().is_some() {}
        assert_eq!(lx.line_count_at_end(), 2);
        let mut lx = Lexer::new(b"");
        assert!(lx.next_token().is_none());
        assert_eq!(lx.line_count_at_end(), 0);
    }

    #[test]
    fn numbers() {
        assert_eq!(parse_f64(b"3."), Some(3.0));
        assert_eq!(parse_f64(b"-2.18557e-07"), Some(-2.18557e-07));
        assert_eq!(parse_f64(b"1.85E-4"), Some(1.85e-4));
        assert_eq!(parse_f64(b".5"), Some(0.5));
        assert_eq!(parse_f64(b"-0.0"), Some(0.0));
        for bad in [&b"inf"[..], b"nan", b"1e999", b"", b"1,5", b"x", b"1.2.3"] {
            assert_eq!(parse_f64(bad), None, "{:?}", String::from_utf8_lossy(bad));
        }
        assert_eq!(parse_usize(b"65535"), Some(65535));
        assert_eq!(parse_usize(b"-1"), None);
        assert_eq!(parse_usize(b"4.0"), None);
        assert_eq!(parse_i64(b"-3"), Some(-3));
    }

    #[test]
    fn fast_path_agrees_with_std_parser() {
        let cases = [
            "0",
            "-0.0",
            "3.",
            ".5",
            "0.1",
            "0.3",
            "-31.77348",
            "0.000425",
            "123456789012345",
            "1234567890123456",
            "0.1234567890123456789",
            "4.6799998",
            "-2.18557e-07",
            "255",
            "1e5",
            "+7.25",
            "0.0000000000000000000001",
            "00000000000000001.5",
        ];
        for c in cases {
            let want: f64 = c.parse().unwrap();
            let got = parse_f64(c.as_bytes()).unwrap();
            assert_eq!(got.to_bits(), want.to_bits(), "{c}");
        }
        // Pseudo-random decimals of up to 15 digits.
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let digits = (x % 1_000_000_000_000_000) as i64;
            let frac = ((x >> 50) % 16) as usize;
            let s = format!("{digits:016}");
            let s = format!("{}.{}", &s[..16 - frac], &s[16 - frac..]);
            let s = if x & 1 == 1 { format!("-{s}") } else { s };
            let want: f64 = s.parse().unwrap();
            assert_eq!(
                parse_f64(s.as_bytes()).unwrap().to_bits(),
                want.to_bits(),
                "{s}"
            );
        }
    }
}
