//! [`ImportError`]: every importer error names the file and the place in it
//! (`path:line:col: message`), including semantic errors found after parsing.

use std::fmt;
use std::path::{Path, PathBuf};

/// A place in a file: the file, and the 1-based line and column when known.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ErrorPlace {
    /// The file the error is in.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// 1-based column (in characters), when known.
    pub column: Option<usize>,
}

impl ErrorPlace {
    /// A place naming only the file (errors about the whole file: missing, unreadable, too large).
    pub fn file(file: impl Into<PathBuf>) -> Self {
        Self { file: file.into(), line: None, column: None }
    }

    /// A place naming the file and a 1-based line.
    pub fn line(file: impl Into<PathBuf>, line: usize) -> Self {
        Self { file: file.into(), line: Some(line), column: None }
    }

    /// A place naming the file, a 1-based line and a 1-based column.
    pub fn line_col(file: impl Into<PathBuf>, line: usize, column: usize) -> Self {
        Self { file: file.into(), line: Some(line), column: Some(column) }
    }

    /// The place of byte offset `offset` in `source` (the text of `file`).
    pub fn at_offset(file: impl Into<PathBuf>, source: &str, offset: usize) -> Self {
        let (line, column) = line_col(source, offset);
        Self::line_col(file, line, column)
    }
}

impl fmt::Display for ErrorPlace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(col) = self.column {
                write!(f, ":{col}")?;
            }
        }
        Ok(())
    }
}

/// 1-based line and column (in characters) of byte `offset` in `source`; offsets past the end or
/// inside a character are clamped to the nearest valid position before them.
pub fn line_col(source: &str, offset: usize) -> (usize, usize) {
    let mut off = offset.min(source.len());
    while !source.is_char_boundary(off) {
        off -= 1;
    }
    let before = &source[..off];
    let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

/// What kind of problem an [`ImportError`] reports (for callers that react differently).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImportErrorKind {
    /// The file could not be read (missing, permission, not UTF-8, ...).
    Io,
    /// The file is not syntactically valid (TOML syntax, malformed OBJ statement, ...).
    Syntax,
    /// A key that the format does not define.
    UnknownKey,
    /// A value of the wrong type, out of range, not finite, or otherwise invalid.
    InvalidValue,
    /// A name that refers to nothing (unknown material, override matching nothing, ...).
    UnresolvedReference,
    /// A file referenced from this file (mesh, CSV, MTL) does not exist or cannot be read.
    MissingFile,
    /// No importer handles the file's extension, or the feature is not supported yet.
    Unsupported,
    /// The input exceeds a resource limit (file size, element counts, tessellation level).
    TooLarge,
}

/// An import error. Its `Display` is always `path:line:col: message` (line and column when known)
/// followed by `(included from ...)` notes when the file was reached through includes.
#[derive(Debug, thiserror::Error)]
#[error("{place}: {message}{}", IncludeChain(&self.included_from))]
pub struct ImportError {
    /// The file and place of the problem.
    pub place: ErrorPlace,
    /// The kind of problem.
    pub kind: ImportErrorKind,
    /// Human-readable description (no file name: that is in `place`).
    pub message: String,
    /// The places of the include statements through which the file was reached, innermost first.
    pub included_from: Vec<ErrorPlace>,
    /// The underlying I/O error, if any.
    #[source]
    pub source: Option<std::io::Error>,
}

struct IncludeChain<'a>(&'a [ErrorPlace]);

impl fmt::Display for IncludeChain<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for p in self.0 {
            write!(f, " (included from {p})")?;
        }
        Ok(())
    }
}

impl ImportError {
    /// A new error of `kind` at `place`.
    pub fn new(kind: ImportErrorKind, place: ErrorPlace, message: impl Into<String>) -> Self {
        Self { place, kind, message: message.into(), included_from: Vec::new(), source: None }
    }

    /// An I/O error about `file` as a whole (a missing file is [`ImportErrorKind::MissingFile`]).
    pub fn io(file: &Path, what: &str, err: std::io::Error) -> Self {
        let kind =
            if err.kind() == std::io::ErrorKind::NotFound { ImportErrorKind::MissingFile } else { ImportErrorKind::Io };
        let message = format!("{what}: {err}");
        Self { place: ErrorPlace::file(file), kind, message, included_from: Vec::new(), source: Some(err) }
    }

    /// Records that the failing file was reached through an include statement at `place`.
    pub fn included_from(mut self, place: ErrorPlace) -> Self {
        self.included_from.push(place);
        self
    }
}

/// Edit distance between two strings (by characters): insertions, deletions, substitutions and
/// transpositions of adjacent characters each cost 1 (optimal string alignment distance).
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let w = b.len() + 1;
    let mut d = vec![0usize; (a.len() + 1) * w];
    for (j, x) in d.iter_mut().enumerate().take(w) {
        *x = j;
    }
    for i in 1..=a.len() {
        d[i * w] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[(i - 1) * w + j] + 1).min(d[i * w + j - 1] + 1).min(d[(i - 1) * w + j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[(i - 2) * w + j - 2] + 1);
            }
            d[i * w + j] = v;
        }
    }
    d[a.len() * w + b.len()]
}

/// The candidate closest to `word` by edit distance (case-insensitive), if it is close enough to
/// be a plausible typo: distance at most max(1, len/3), or the same word ignoring case.
pub(crate) fn suggest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    // Do not spend quadratic time on hostile, very long words.
    if word.len() > 256 {
        return None;
    }
    let lw = word.to_lowercase();
    let limit = (word.chars().count() / 3).max(1);
    candidates
        .into_iter()
        .filter(|c| c.len() <= 256)
        .map(|c| (edit_distance(&lw, &c.to_lowercase()), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// "; did you mean `x`?" when a close candidate exists, else "".
pub fn did_you_mean<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    suggest(word, candidates).map(|s| format!("; did you mean `{s}`?")).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_file_line_and_column() {
        let e = ImportError::new(ImportErrorKind::Syntax, ErrorPlace::line_col("a/scene.toml", 7, 3), "bad");
        assert_eq!(e.to_string(), "a/scene.toml:7:3: bad");
        let e = ImportError::new(ImportErrorKind::Syntax, ErrorPlace::line("m.obj", 12), "bad face");
        assert_eq!(e.to_string(), "m.obj:12: bad face");
        let e = e.included_from(ErrorPlace::line_col("scene.toml", 4, 1));
        assert_eq!(e.to_string(), "m.obj:12: bad face (included from scene.toml:4:1)");
        let e = ImportError::new(ImportErrorKind::Io, ErrorPlace::file("x.obj"), "gone");
        assert_eq!(e.to_string(), "x.obj: gone");
    }

    #[test]
    fn line_col_counts_lines_and_chars() {
        let s = "ab\ncäd\nx";
        assert_eq!(line_col(s, 0), (1, 1));
        assert_eq!(line_col(s, 2), (1, 3));
        assert_eq!(line_col(s, 3), (2, 1));
        assert_eq!(line_col(s, 6), (2, 3)); // after 'c' and 'ä' (2 bytes)
        assert_eq!(line_col(s, 5), (2, 2)); // inside 'ä': clamped back
        assert_eq!(line_col(s, 999), (3, 2));
    }

    #[test]
    fn suggestions() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("gery", "grey"), 1);
        let keys = ["position", "target", "up", "fov_deg", "fov_axis"];
        assert_eq!(suggest("fov_dg", keys), Some("fov_deg"));
        assert_eq!(suggest("Target", keys), Some("target"));
        assert_eq!(suggest("zzzzzz", keys), None);
        assert_eq!(did_you_mean("positon", keys), "; did you mean `position`?");
    }
}
