//! Reading the small text files of a scene (TOML scenes, MTL libraries, spectrum CSVs, BSDF
//! tables) with a size limit, so hostile input cannot exhaust memory.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};

/// Largest scene, MTL, CSV or BSDF-table text file accepted (bytes).
pub const MAX_SMALL_FILE_BYTES: u64 = 64 << 20;

/// Reads a small text file (scene, MTL, CSV, BSDF table) of at most [`MAX_SMALL_FILE_BYTES`],
/// past a UTF-8 byte order mark; errors name `file` (and the line of invalid UTF-8).
pub fn read_small_text(file: &Path, what: &str) -> Result<String, ImportError> {
    let f = File::open(file).map_err(|e| ImportError::io(file, &format!("cannot open {what}"), e))?;
    let len = f.metadata().map(|m| m.len()).unwrap_or(0);
    if len > MAX_SMALL_FILE_BYTES {
        return Err(ImportError::new(
            ImportErrorKind::TooLarge,
            ErrorPlace::file(file),
            format!("{what} is {len} bytes, more than the limit of {MAX_SMALL_FILE_BYTES}"),
        ));
    }
    let mut bytes = Vec::new();
    f.take(MAX_SMALL_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| ImportError::io(file, &format!("cannot read {what}"), e))?;
    if bytes.len() as u64 > MAX_SMALL_FILE_BYTES {
        return Err(ImportError::new(
            ImportErrorKind::TooLarge,
            ErrorPlace::file(file),
            format!("{what} is more than the limit of {MAX_SMALL_FILE_BYTES} bytes"),
        ));
    }
    let mut text = String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        ImportError::new(ImportErrorKind::Syntax, ErrorPlace::line(file, line), "not valid UTF-8")
    })?;
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}
