//! Where a scene element came from (file, line, path inside the file), kept with the element
//! for error messages and `quasar info`.

use std::path::PathBuf;

/// Where a scene element came from, for error messages and `quasar info`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SourceLocation {
    /// The file.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// A path inside the file (TOML key path, JSON pointer, OBJ group), when known.
    pub item: Option<String>,
}

impl std::fmt::Display for SourceLocation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        if let Some(i) = &self.item {
            write!(f, " ({i})")?;
        }
        Ok(())
    }
}
