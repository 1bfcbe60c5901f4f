//! Reading the bytes a glTF file refers to: the GLB binary chunk, `data:` URIs and external files.
//!
//! External URIs are resolved relative to the glTF file's folder. Absolute paths, URI schemes
//! other than `data:` and relative paths that leave the folder (`..`, or a symbolic link pointing
//! out of it) are refused unless [`ImportOptions::allow_external_paths`] is set. Every read is
//! bounded by [`MAX_GLTF_BUFFER_BYTES`].

use std::io::Read;
use std::path::{Component, Path, PathBuf};

use base64::Engine;

use super::err;
use crate::error::{ImportError, ImportErrorKind};
use crate::importer::ImportOptions;

/// Largest glTF/GLB file and largest single buffer or image file accepted (bytes).
pub const MAX_GLTF_BUFFER_BYTES: u64 = 2 << 30;

/// Decodes `%XX` escapes of a URI path (glTF URIs are URI-encoded: `my%20file.bin`).
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Reads `file` whole, refusing more than [`MAX_GLTF_BUFFER_BYTES`].
pub(super) fn read_bounded(file: &Path, what: &str) -> Result<Vec<u8>, ImportError> {
    let f = std::fs::File::open(file).map_err(|e| ImportError::io(file, &format!("cannot open {what}"), e))?;
    let len = f.metadata().map(|m| m.len()).unwrap_or(0);
    if len > MAX_GLTF_BUFFER_BYTES {
        return Err(err(
            ImportErrorKind::TooLarge,
            file,
            "",
            format!("{what} is {len} bytes, more than the limit of {MAX_GLTF_BUFFER_BYTES}"),
        ));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    f.take(MAX_GLTF_BUFFER_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| ImportError::io(file, &format!("cannot read {what}"), e))?;
    if bytes.len() as u64 > MAX_GLTF_BUFFER_BYTES {
        return Err(err(
            ImportErrorKind::TooLarge,
            file,
            "",
            format!("{what} is larger than {MAX_GLTF_BUFFER_BYTES} bytes"),
        ));
    }
    Ok(bytes)
}

/// True when `rel` (a relative path) stays inside its base folder lexically.
fn stays_inside(rel: &Path) -> bool {
    let mut depth = 0i64;
    for c in rel.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir => {
                depth -= 1;
                if depth < 0 {
                    return false;
                }
            }
            Component::RootDir | Component::Prefix(_) => return false,
        }
    }
    true
}

/// Resolves a non-`data:` URI of `gltf` to a file path, applying the path policy.
pub(super) fn resolve_uri(gltf: &Path, uri: &str, pointer: &str, opts: &ImportOptions) -> Result<PathBuf, ImportError> {
    let invalid = |msg: String| err(ImportErrorKind::InvalidValue, gltf, pointer, msg);
    let decoded = percent_decode(uri).ok_or_else(|| invalid(format!("URI `{uri}` has an invalid %-escape")))?;
    let (scheme, rest) = match decoded.split_once(':') {
        // a one-letter "scheme" is a Windows drive letter
        Some((s, r)) if s.len() > 1 && s.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c)) => {
            (Some(s.to_ascii_lowercase()), r)
        }
        _ => (None, decoded.as_str()),
    };
    let escape_hint = "(use --allow-external-paths / ImportOptions::allow_external_paths to allow it)";
    let path_text = match scheme.as_deref() {
        None => decoded.as_str(),
        Some("file") if opts.allow_external_paths => rest.trim_start_matches("//"),
        Some(s) => {
            return Err(err(
                ImportErrorKind::Unsupported,
                gltf,
                pointer,
                format!("URI `{uri}`: scheme `{s}:` is not supported (only relative file paths and data: URIs)"),
            ));
        }
    };
    let rel = Path::new(path_text);
    let has_drive = path_text.len() >= 2 && path_text.as_bytes()[1] == b':';
    let dir = gltf.parent().unwrap_or(Path::new(""));
    if rel.is_absolute() || path_text.starts_with('/') || path_text.starts_with('\\') || has_drive {
        if !opts.allow_external_paths {
            return Err(err(
                ImportErrorKind::InvalidValue,
                gltf,
                pointer,
                format!(
                    "URI `{uri}` is an absolute path; only paths relative to the glTF file are allowed {escape_hint}"
                ),
            ));
        }
        return Ok(rel.to_path_buf());
    }
    let full = dir.join(rel);
    if !opts.allow_external_paths {
        let outside = !stays_inside(rel)
            || match (full.canonicalize(), dir.canonicalize()) {
                (Ok(f), Ok(d)) => !f.starts_with(d),
                _ => false,
            };
        if outside {
            return Err(err(
                ImportErrorKind::InvalidValue,
                gltf,
                pointer,
                format!("URI `{uri}` leaves the glTF file's folder {escape_hint}"),
            ));
        }
    }
    Ok(full)
}

/// Decodes a `data:[<mediatype>][;base64],<data>` URI; `None` when `uri` is not a data URI.
pub(super) fn data_uri(gltf: &Path, uri: &str, pointer: &str) -> Option<Result<Vec<u8>, ImportError>> {
    let rest = uri.strip_prefix("data:")?;
    let bad = |msg: &str| err(ImportErrorKind::InvalidValue, gltf, pointer, format!("data URI: {msg}"));
    let Some((head, payload)) = rest.split_once(',') else {
        return Some(Err(bad("missing `,` before the data")));
    };
    if !head.ends_with(";base64") {
        return Some(Err(bad("only base64-encoded data URIs are supported")));
    }
    if payload.len() as u64 / 4 * 3 > MAX_GLTF_BUFFER_BYTES {
        return Some(Err(err(ImportErrorKind::TooLarge, gltf, pointer, "data URI is too large")));
    }
    Some(base64::engine::general_purpose::STANDARD.decode(payload).map_err(|e| bad(&format!("invalid base64: {e}"))))
}

/// The bytes behind a URI (data URI or file), read with the path policy and size limit.
pub(super) fn uri_bytes(gltf: &Path, uri: &str, pointer: &str, opts: &ImportOptions) -> Result<Vec<u8>, ImportError> {
    if let Some(d) = data_uri(gltf, uri, pointer) {
        return d;
    }
    let file = resolve_uri(gltf, uri, pointer, opts)?;
    if !file.is_file() {
        return Err(err(
            ImportErrorKind::MissingFile,
            gltf,
            pointer,
            format!("cannot find `{uri}` (looked for {})", file.display()),
        ));
    }
    read_bounded(&file, "glTF buffer or image")
        .map_err(|e| err(e.kind, gltf, pointer, format!("`{uri}`: {}", e.message)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_inside_and_outside() {
        assert!(stays_inside(Path::new("a/b.bin")));
        assert!(stays_inside(Path::new("a/../b.bin")));
        assert!(!stays_inside(Path::new("../b.bin")));
        assert!(!stays_inside(Path::new("a/../../b.bin")));
        assert_eq!(percent_decode("my%20file.bin").as_deref(), Some("my file.bin"));
        assert_eq!(percent_decode("bad%2"), None);
        let g = Path::new("/tmp/x/scene.gltf");
        let o = ImportOptions::default();
        assert!(resolve_uri(g, "../y.bin", "/buffers/0", &o).unwrap_err().to_string().contains("leaves"));
        assert!(resolve_uri(g, "/etc/passwd", "/buffers/0", &o).unwrap_err().to_string().contains("absolute"));
        assert!(resolve_uri(g, "https://x/y.bin", "/buffers/0", &o).unwrap_err().to_string().contains("scheme"));
        assert!(resolve_uri(g, "C:/y.bin", "/buffers/0", &o).is_err());
        let allow = ImportOptions { allow_external_paths: true, ..Default::default() };
        assert_eq!(resolve_uri(g, "../y.bin", "/buffers/0", &allow).unwrap(), Path::new("/tmp/x/../y.bin"));
        assert_eq!(data_uri(g, "data:application/octet-stream;base64,AAEC", "/b").unwrap().unwrap(), vec![0, 1, 2]);
        assert!(data_uri(g, "data:text/plain,abc", "/b").unwrap().is_err());
        assert!(data_uri(g, "x.bin", "/b").is_none());
    }
}
