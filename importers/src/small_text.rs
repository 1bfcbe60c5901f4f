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
    read_text(file, what, false)
}

/// [`read_small_text`] for formats older than UTF-8 (IES LM-63, EULUMDAT): a file that is not
/// valid UTF-8 is read as Latin-1 (ISO 8859-1, every byte the code point of its value), the
/// encoding manufacturers' tools write their labels in (a degree sign 0xB0 in `[LUMINAIRE]`).
/// The numbers these formats hold are ASCII, so only text fields can differ (Windows-1252's
/// punctuation at 0x80-0x9F reads as Latin-1's control characters there).
pub fn read_legacy_text(file: &Path, what: &str) -> Result<String, ImportError> {
    read_text(file, what, true)
}

fn read_text(file: &Path, what: &str, latin1: bool) -> Result<String, ImportError> {
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
    let mut text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) if latin1 => e.into_bytes().iter().map(|&b| char::from(b)).collect(),
        Err(e) => {
            let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
            return Err(ImportError::new(ImportErrorKind::Syntax, ErrorPlace::line(file, line), "not valid UTF-8"));
        }
    };
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}
