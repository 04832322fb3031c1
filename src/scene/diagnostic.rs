//! Scene errors that point at the file, line and column of the offending value.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use codespan_reporting::diagnostic::{Diagnostic as Report, Label};
use codespan_reporting::files::SimpleFiles;
use codespan_reporting::term;

/// One problem found in a scene file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// What is wrong, as a sentence without a final period.
    pub message: String,
    /// The bytes of the file the problem is about, when there is such a place.
    pub span: Option<Range<usize>>,
    /// A short label printed under the offending value.
    pub label: String,
    /// What to change, when there is a clear fix.
    pub hint: Option<String>,
    /// Other values that take part in the problem, each with its label (the frame
    /// count is `duration` and `fps` together, for example).
    pub also: Vec<(Range<usize>, String)>,
}

impl Diagnostic {
    /// Creates a diagnostic about the value at `span`.
    pub fn at(span: Range<usize>, message: impl Into<String>) -> Self {
        Diagnostic {
            message: message.into(),
            span: Some(span),
            label: String::new(),
            hint: None,
            also: Vec::new(),
        }
    }

    /// Creates a diagnostic about the file as a whole.
    pub fn whole_file(message: impl Into<String>) -> Self {
        Diagnostic {
            message: message.into(),
            span: None,
            label: String::new(),
            hint: None,
            also: Vec::new(),
        }
    }

    /// Adds a label under the offending value.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }

    /// Adds a hint saying what to change.
    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    /// Points at another value that takes part in the problem, with its own label.
    pub fn also(mut self, span: Range<usize>, label: impl Into<String>) -> Self {
        self.also.push((span, label.into()));
        self
    }
}

/// Every problem found in one scene file, with the text needed to show where.
#[derive(Clone, Debug)]
pub struct SceneError {
    /// The scene file's path as the user gave it.
    pub path: PathBuf,
    /// The text of the file.
    pub text: String,
    /// The `--set KEY=VALUE` arguments, in order; spans can point into them too (see
    /// [`Sources`]).
    pub overrides: Vec<String>,
    /// The problems, in the order they appear in the file, then in the overrides.
    pub diagnostics: Vec<Diagnostic>,
}

/// The texts that spans point into, laid end to end in one address space: the scene
/// file at `0..file_len`, then each `--set` argument, each one byte after the end of
/// the text before it. A span therefore names both a text and a place in it.
#[derive(Clone, Copy, Debug)]
pub struct Sources<'a> {
    /// The length of the scene file's text in bytes.
    pub file_len: usize,
    /// The `--set` arguments, in order.
    pub overrides: &'a [String],
}

impl Sources<'_> {
    /// Returns the offset at which override `i` starts.
    pub fn base(&self, i: usize) -> usize {
        self.file_len
            + 1
            + self.overrides[..i]
                .iter()
                .map(|o| o.len() + 1)
                .sum::<usize>()
    }

    /// Returns which text a span points into (`None` for the scene file, `Some(i)` for
    /// override `i`) and the span relative to that text.
    pub fn locate(&self, span: &Range<usize>) -> (Option<usize>, Range<usize>) {
        for i in (0..self.overrides.len()).rev() {
            let base = self.base(i);
            if span.start >= base {
                return (Some(i), span.start - base..span.end.saturating_sub(base));
            }
        }
        (None, span.clone())
    }
}

impl SceneError {
    /// Creates an error for `path`, sorting the diagnostics by position in the file. A
    /// diagnostic about the whole file stays after every one reported before it (first,
    /// when none was): a count of the problems left unlisted ("38 more pairs …") reads
    /// after the ones it follows.
    pub fn new(path: &Path, text: &str, diagnostics: Vec<Diagnostic>) -> Self {
        let mut at = 0;
        let mut keyed: Vec<(usize, Diagnostic)> = diagnostics
            .into_iter()
            .map(|d| {
                if let Some(span) = &d.span {
                    at = at.max(span.start);
                }
                // A located one sorts by its own place, a whole-file one after those
                // before it.
                let at = d.span.as_ref().map_or(at, |s| s.start);
                (at, d)
            })
            .collect();
        // A stable sort: a whole-file diagnostic stays after the one it follows.
        keyed.sort_by_key(|(at, _)| *at);
        let diagnostics = keyed.into_iter().map(|(_, d)| d).collect();
        SceneError {
            path: path.to_path_buf(),
            text: text.to_string(),
            overrides: Vec::new(),
            diagnostics,
        }
    }

    /// Records the `--set` arguments that spans beyond the file point into.
    pub fn with_overrides(mut self, overrides: &[String]) -> Self {
        self.overrides = overrides.to_vec();
        self
    }

    /// Returns `line:column` (both counted from 1) of a byte offset in the file.
    pub fn line_column(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = &self.text[..floor_char_boundary(&self.text, offset)];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        (line, column)
    }

    /// Renders every diagnostic like a compiler does: the file, line and column, the
    /// offending line with a caret under the bad value, and the hint. A problem in a
    /// `--set` argument is shown in that argument, named `--set #N`.
    pub fn render(&self) -> String {
        let name = self.path.display().to_string();
        let sources = Sources {
            file_len: self.text.len(),
            overrides: &self.overrides,
        };
        let mut files = SimpleFiles::new();
        let file_id = files.add(name.clone(), self.text.as_str());
        let override_ids: Vec<usize> = self
            .overrides
            .iter()
            .enumerate()
            .map(|(i, o)| files.add(format!("--set #{}", i + 1), o.as_str()))
            .collect();
        let config = term::Config::default();
        let mut out = String::new();
        for d in &self.diagnostics {
            let mut report = Report::error().with_message(&d.message);
            // Each span names its text (the file or an override) and a place in it.
            let place = |span: &Range<usize>| {
                let (source, local) = sources.locate(span);
                let (id, text) = match source {
                    Some(i) => (override_ids[i], self.overrides[i].as_str()),
                    None => (file_id, self.text.as_str()),
                };
                let start = floor_char_boundary(text, local.start);
                let end = floor_char_boundary(text, local.end.max(local.start));
                (id, start..end)
            };
            let mut labels = Vec::new();
            if let Some(span) = &d.span {
                let (id, range) = place(span);
                labels.push(Label::primary(id, range).with_message(d.label.clone()));
            }
            for (span, label) in &d.also {
                let (id, range) = place(span);
                labels.push(Label::secondary(id, range).with_message(label.clone()));
            }
            report = report.with_labels(labels);
            if let Some(hint) = &d.hint {
                report = report.with_notes(vec![format!("hint: {hint}")]);
            }
            match term::emit_into_string(&config, &files, &report) {
                Ok(text) => out.push_str(&text),
                Err(_) => out.push_str(&format!("error: {}: {}\n", name, d.message)),
            }
        }
        let n = self.diagnostics.len();
        out.push_str(&format!(
            "error: {name}: {n} problem{} found; nothing was written\n",
            if n == 1 { "" } else { "s" }
        ));
        out
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render())
    }
}

impl std::error::Error for SceneError {}

/// Returns the largest char boundary at or below `i`.
fn floor_char_boundary(s: &str, i: usize) -> usize {
    let mut i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}
