//! Diagnostics of the scene language: an error with its place, rendered by
//! `codespan-reporting` as `file:line:col`, the source line, a caret and what was expected.

use crate::LoadError;
use codespan_reporting::diagnostic::{Diagnostic, Label};
use codespan_reporting::files::{Files, SimpleFiles};
use codespan_reporting::term::{self, Chars, Config};
use std::ops::Range;
use std::path::PathBuf;

/// Index of a source file in [`Sources`].
pub(crate) type FileId = usize;

/// Every file read while loading one scene (the main file and its includes).
#[derive(Default)]
pub(crate) struct Sources {
    files: SimpleFiles<String, String>,
    paths: Vec<PathBuf>,
}

impl Sources {
    /// Registers a file; `name` is how diagnostics show it.
    pub(crate) fn add(&mut self, name: String, path: PathBuf, text: String) -> FileId {
        self.paths.push(path);
        self.files.add(name, text)
    }

    /// True for a file named `*.scn`, or the main file: one whose lines an error may
    /// quote.
    pub(crate) fn is_scene_file(&self, id: FileId) -> bool {
        id == 0 || self.paths.get(id).and_then(|p| p.extension()).is_some_and(|e| e.eq_ignore_ascii_case("scn"))
    }

    /// The text of a file.
    pub(crate) fn text(&self, id: FileId) -> &str {
        self.files.get(id).map(|f| f.source().as_str()).unwrap_or("")
    }

    /// The path of a file.
    pub(crate) fn path(&self, id: FileId) -> PathBuf {
        self.paths.get(id).cloned().unwrap_or_default()
    }

    /// How diagnostics name a file.
    pub(crate) fn name(&self, id: FileId) -> String {
        self.files.name(id).map(|n| n.to_string()).unwrap_or_default()
    }

    /// The 1-based line of a byte offset (1 if the offset is out of range).
    pub(crate) fn line(&self, id: FileId, offset: usize) -> usize {
        self.files.location(id, offset).map_or(1, |l| l.line_number)
    }

    /// `name:line:col` of a byte offset, for notes that mention another place.
    pub(crate) fn place(&self, id: FileId, offset: usize) -> String {
        let name = self.files.name(id).map(|n| n.to_string()).unwrap_or_default();
        match self.files.location(id, offset) {
            Ok(l) => format!("{name}:{}:{}", l.line_number, l.column_number),
            Err(_) => name,
        }
    }
}

/// One error: a primary place with an optional label, secondary places, notes.
#[derive(Debug)]
pub(crate) struct Diag {
    file: FileId,
    span: Range<usize>,
    message: String,
    label: String,
    secondary: Vec<(FileId, Range<usize>, String)>,
    notes: Vec<String>,
}

impl Diag {
    /// An error at `span` of `file`.
    pub(crate) fn new(file: FileId, span: Range<usize>, message: impl Into<String>) -> Self {
        Self { file, span, message: message.into(), label: String::new(), secondary: vec![], notes: vec![] }
    }

    /// The text printed beside the caret (usually what was expected).
    pub(crate) fn label(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }

    /// Points at a second place (the first definition of a duplicate, say).
    pub(crate) fn also(mut self, file: FileId, span: Range<usize>, label: impl Into<String>) -> Self {
        self.secondary.push((file, span, label.into()));
        self
    }

    /// A note printed under the source excerpt.
    pub(crate) fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    /// Renders the error with its source line and caret into a [`LoadError::Scene`].
    /// An error inside an included file that is not a `.scn` shows its place only: the
    /// file may be anything an include names (`/etc/passwd`), and neither its lines nor
    /// its words (which messages quote) belong in an error (issue 43).
    pub(crate) fn into_error(self, sources: &Sources) -> LoadError {
        if self.file != 0 && !sources.is_scene_file(self.file) {
            let (line, column) =
                sources.files.location(self.file, self.span.start).map_or((0, 0), |l| (l.line_number, l.column_number));
            let path = sources.path(self.file);
            let message = format!(
                "line {line}, column {column} is not the scene language (an included file that is not a `.scn` \
                 is not quoted)"
            );
            let mut rendered = format!("{}:{line}:{column}: error: {message}", sources.name(self.file));
            for n in &self.notes {
                rendered.push_str(&format!("\n  = {n}"));
            }
            return LoadError::Scene { path, line, column, message, rendered };
        }
        let mut labels = vec![Label::primary(self.file, self.span.clone()).with_message(self.label.clone())];
        for (f, s, l) in &self.secondary {
            labels.push(Label::secondary(*f, s.clone()).with_message(l.clone()));
        }
        let diagnostic =
            Diagnostic::error().with_message(self.message.clone()).with_labels(labels).with_notes(self.notes.clone());
        let config = Config { chars: Chars::ascii(), ..Config::default() };
        let (line, column) = match sources.files.location(self.file, self.span.start) {
            Ok(l) => (l.line_number, l.column_number),
            Err(_) => (0, 0),
        };
        let path = sources.path(self.file);
        let rendered = match term::emit_into_string(&config, &sources.files, &diagnostic) {
            Ok(s) => s.trim_end().to_string(),
            // Only reachable if a span fell outside its file: still say where and what.
            Err(_) => format!("{}:{line}:{column}: error: {}", path.display(), self.message),
        };
        LoadError::Scene { path, line, column, message: self.message, rendered }
    }
}

/// The candidate closest to `word` by edit distance, if it is close enough to be a typo
/// (at most one edit per three characters, and at least one).
pub(crate) fn did_you_mean<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (word.chars().count() / 3).max(1);
    candidates.into_iter().map(|c| (edit_distance(word, c), c)).filter(|&(d, _)| d <= limit).min().map(|(_, c)| c)
}

/// Levenshtein distance over characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_catch_typos_only() {
        assert_eq!(did_you_mean("centre", ["center", "radius"]), Some("center"));
        assert_eq!(did_you_mean("radus", ["center", "radius"]), Some("radius"));
        assert_eq!(did_you_mean("xyz", ["center", "radius"]), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
