//! Words of an AFF/NFF file with their line numbers, and the typed reads the parser makes
//! of them (numbers, counts, names), each failing with a [`LoadError`] at the word's line.
//!
//! AFF is free-form: a command is a word followed by its numbers, which may run over
//! several lines (BART's `xs` and `fm` do). `#` and `%` start comments that run to the end
//! of the line (NFF uses `#`, BART's files both). `{` and `}` are words of their own even
//! when written against another word.

use crate::LoadError;
use std::path::Path;

/// One word and the 1-based line it is on.
#[derive(Clone, Copy, Debug)]
pub(super) struct Token<'a> {
    pub text: &'a str,
    pub line: usize,
}

/// The words of one file and a read position.
pub(super) struct Tokens<'a> {
    pub path: &'a Path,
    tokens: Vec<Token<'a>>,
    pos: usize,
}

impl<'a> Tokens<'a> {
    /// Splits `text` (the contents of `path`) into words.
    pub fn new(path: &'a Path, text: &'a str) -> Self {
        let mut tokens = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let code = raw.split(['#', '%']).next().unwrap_or("");
            for word in code.split_whitespace() {
                // `{`/`}` glued to a word: split them off, keeping the order.
                let mut rest = word;
                while let Some(at) = rest.find(['{', '}']) {
                    if at > 0 {
                        tokens.push(Token { text: &rest[..at], line });
                    }
                    tokens.push(Token { text: &rest[at..at + 1], line });
                    rest = &rest[at + 1..];
                }
                if !rest.is_empty() {
                    tokens.push(Token { text: rest, line });
                }
            }
        }
        Tokens { path, tokens, pos: 0 }
    }

    /// A parse error at `line` of this file.
    pub fn error(&self, line: usize, message: impl Into<String>) -> LoadError {
        LoadError::parse(self.path, Some(line), message)
    }

    /// The line of the next word, or of the last one at the end of the file.
    pub fn line(&self) -> usize {
        self.tokens.get(self.pos).or(self.tokens.last()).map_or(1, |t| t.line)
    }

    /// The next word, without taking it.
    pub fn peek(&self) -> Option<Token<'a>> {
        self.tokens.get(self.pos).copied()
    }

    /// Whether the next word is a number (optional trailing arguments end at a word).
    pub fn next_is_number(&self) -> bool {
        self.peek().is_some_and(|t| t.text.parse::<f32>().is_ok())
    }

    /// Takes the next word; at the end of the file, an error saying what was expected.
    pub fn word(&mut self, what: &str) -> Result<Token<'a>, LoadError> {
        match self.tokens.get(self.pos) {
            Some(t) => {
                self.pos += 1;
                Ok(*t)
            }
            None => Err(self.error(self.line(), format!("unexpected end of file: expected {what}"))),
        }
    }

    /// Takes the word `text` or fails naming `context`.
    pub fn expect(&mut self, text: &str, context: &str) -> Result<Token<'a>, LoadError> {
        let t = self.word(&format!("`{text}` {context}"))?;
        if t.text == text {
            Ok(t)
        } else {
            Err(self.error(t.line, format!("expected `{text}` {context}, found `{}`", t.text)))
        }
    }

    /// A finite number, described as `what` in messages.
    pub fn number(&mut self, what: &str) -> Result<f32, LoadError> {
        let t = self.word(&format!("a number ({what})"))?;
        match t.text.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.error(t.line, format!("{what}: `{}` is not a finite number", t.text))),
            Err(_) => Err(self.error(t.line, format!("expected a number ({what}), found `{}`", t.text))),
        }
    }

    /// Three numbers.
    pub fn vec3(&mut self, what: &str) -> Result<[f32; 3], LoadError> {
        Ok([self.number(what)?, self.number(what)?, self.number(what)?])
    }

    /// A non-negative integer (a count or an index).
    pub fn count(&mut self, what: &str) -> Result<usize, LoadError> {
        let t = self.word(&format!("a whole number ({what})"))?;
        t.text
            .parse::<u32>()
            .map(|n| n as usize)
            .map_err(|_| self.error(t.line, format!("expected a whole number ({what}), found `{}`", t.text)))
    }
}

/// How many elements to reserve for a claimed `count` of items of `words_each` words:
/// never more than the words left could hold, so a lying header allocates nothing big.
pub(super) fn reserve(tokens: &Tokens<'_>, count: usize, words_each: usize) -> usize {
    let left = tokens.tokens.len().saturating_sub(tokens.pos);
    count.min(left / words_each.max(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_comments_and_braces() {
        let t = Tokens::new(Path::new("t.aff"), "xs 1 2{\n# all\n% of it\n  p 3 % x\n}x{y}\n");
        let words: Vec<(&str, usize)> = t.tokens.iter().map(|t| (t.text, t.line)).collect();
        assert_eq!(
            words,
            [
                ("xs", 1),
                ("1", 1),
                ("2", 1),
                ("{", 1),
                ("p", 4),
                ("3", 4),
                ("}", 5),
                ("x", 5),
                ("{", 5),
                ("y", 5),
                ("}", 5)
            ]
        );
    }

    #[test]
    fn typed_reads_name_the_line() {
        let mut t = Tokens::new(Path::new("t.aff"), "1.5\nabc\n-3\n");
        assert_eq!(t.number("x").unwrap(), 1.5);
        let e = t.number("radius").unwrap_err().to_string();
        assert_eq!(e, "t.aff:2: expected a number (radius), found `abc`");
        let e = t.count("vertices").unwrap_err().to_string();
        assert_eq!(e, "t.aff:3: expected a whole number (vertices), found `-3`");
        let e = t.number("y").unwrap_err().to_string();
        assert_eq!(e, "t.aff:3: unexpected end of file: expected a number (y)");
        assert_eq!(reserve(&t, 1_000_000_000, 3), 0);
    }
}
