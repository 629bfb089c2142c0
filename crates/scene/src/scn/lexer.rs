//! Tokens of the scene language: names, numbers, strings and punctuation, each with the
//! byte span it came from, so every later error can point at the text.

use super::diag::{Diag, FileId};
use std::ops::Range;

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    /// A name or keyword: `[A-Za-z_][A-Za-z0-9_]*`. Keywords are recognised by the parser.
    Name(String),
    /// A number literal without fraction or exponent (`12`).
    Int(f64),
    /// A number literal with a fraction or exponent (`1.5`, `.5`, `2e-3`).
    Real(f64),
    /// A double-quoted string (`"bunny.ply"`); no escapes except `\"` and `\\`.
    Str(String),
    /// One of `{ } ( ) < > , + - * / =`.
    Punct(char),
    /// End of the file.
    Eof,
}

impl Tok {
    /// How the token reads in an error message ("found …").
    pub(crate) fn describe(&self) -> String {
        match self {
            Tok::Name(n) => format!("`{n}`"),
            Tok::Int(v) | Tok::Real(v) => format!("number `{v}`"),
            Tok::Str(s) => format!("string \"{s}\""),
            Tok::Punct(c) => format!("`{c}`"),
            Tok::Eof => "end of file".to_string(),
        }
    }
}

/// A token and where it is.
#[derive(Clone, Debug)]
pub(crate) struct Token {
    /// The token.
    pub tok: Tok,
    /// Byte range in its file.
    pub span: Range<usize>,
}

/// Splits `src` into tokens, skipping whitespace and `//` and `/* */` comments. The last
/// token is always [`Tok::Eof`].
pub(crate) fn tokenize(file: FileId, src: &str) -> Result<Vec<Token>, Diag> {
    let b = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let start = i;
        match c {
            b' ' | b'\t' | b'\r' | b'\n' => i += 1,
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                // Block comments do not nest (as in C, and as the seed uses them).
                match src[i + 2..].find("*/") {
                    Some(k) => i += 2 + k + 2,
                    None => {
                        return Err(
                            Diag::new(file, i..i + 2, "unterminated comment").label("this `/*` has no closing `*/`")
                        )
                    }
                }
            }
            b'{' | b'}' | b'(' | b')' | b'<' | b'>' | b',' | b'+' | b'-' | b'*' | b'/' | b'=' => {
                i += 1;
                out.push(Token { tok: Tok::Punct(c as char), span: start..i });
            }
            b'"' => {
                i += 1;
                let mut s = String::new();
                loop {
                    match b.get(i) {
                        None | Some(b'\n') => {
                            return Err(Diag::new(file, start..i, "unterminated string")
                                .label("expected a closing `\"` before the end of the line"))
                        }
                        Some(b'"') => {
                            i += 1;
                            break;
                        }
                        Some(b'\\') if matches!(b.get(i + 1), Some(b'"') | Some(b'\\')) => {
                            s.push(b[i + 1] as char);
                            i += 2;
                        }
                        Some(_) => {
                            // Advance one whole UTF-8 character.
                            let ch = src[i..].chars().next().unwrap_or('\u{fffd}');
                            s.push(ch);
                            i += ch.len_utf8().max(1);
                        }
                    }
                }
                out.push(Token { tok: Tok::Str(s), span: start..i });
            }
            b'0'..=b'9' | b'.' => {
                let mut real = false;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
                if i < b.len() && b[i] == b'.' {
                    real = true;
                    i += 1;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
                if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                    let mut j = i + 1;
                    if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                        j += 1;
                    }
                    if j < b.len() && b[j].is_ascii_digit() {
                        real = true;
                        i = j;
                        while i < b.len() && b[i].is_ascii_digit() {
                            i += 1;
                        }
                    }
                }
                let text = &src[start..i];
                let v: f64 = match text.parse() {
                    Ok(v) if text != "." => v,
                    _ => {
                        return Err(Diag::new(file, start..i, format!("malformed number `{text}`"))
                            .label("expected digits, as in `1`, `0.5` or `2e-3`"))
                    }
                };
                if !v.is_finite() {
                    return Err(Diag::new(file, start..i, format!("number `{text}` is out of range")));
                }
                if i < b.len() && (b[i].is_ascii_alphabetic() || b[i] == b'_') {
                    return Err(Diag::new(file, start..i + 1, format!("malformed number `{}`", &src[start..=i]))
                        .label("a number may not run into a name; add a space"));
                }
                out.push(Token { tok: if real { Tok::Real(v) } else { Tok::Int(v) }, span: start..i });
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                    i += 1;
                }
                out.push(Token { tok: Tok::Name(src[start..i].to_string()), span: start..i });
            }
            _ => {
                let ch = src[i..].chars().next().unwrap_or('\u{fffd}');
                let end = i + ch.len_utf8().max(1);
                return Err(Diag::new(file, start..end, format!("unexpected character `{}`", ch.escape_debug()))
                    .label("expected a name, a number, a string, or one of { } ( ) < > , + - * / ="));
            }
        }
    }
    out.push(Token { tok: Tok::Eof, span: b.len()..b.len() });
    Ok(out)
}
