//! Reading an asset a scene names: a plain file, or an entry of a `.usdz` package written in
//! USD's package-relative form `pkg.usdz[tex/albedo.png]` (what the USD resolver gives for a
//! texture inside a package). Package entries are read with the ZIP reader; the declared size
//! is checked against the caller's limit before anything is read or inflated, and the read
//! stops at the limit whatever the header says. Nested packages (`a.usdz[b.usdz[c.png]]`) are
//! refused.

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::error::ImportErrorKind;

/// Why an asset could not be read: the kind and a message (the caller adds the place).
pub type AssetError = (ImportErrorKind, String);

/// `path` split into its package file and the entry inside it, when it is package-relative
/// (`pkg.usdz[entry]`, split at the first `[`); None for a plain path.
pub fn package_entry(path: &Path) -> Option<(PathBuf, String)> {
    let s = path.to_str()?;
    let (package, inner) = openusd::ar::split_package_relative_path_outer(s)?;
    Some((PathBuf::from(package), inner))
}

/// The file name of the asset at `path` (of the entry, for a package entry).
pub fn file_name(path: &Path) -> Option<String> {
    let name = match package_entry(path) {
        Some((_, entry)) => Path::new(&entry).file_name()?.to_string_lossy().into_owned(),
        None => path.file_name()?.to_string_lossy().into_owned(),
    };
    Some(name)
}

/// The bytes of the asset at `path` (a file or a package entry), refusing more than `limit`.
pub fn read_asset(path: &Path, limit: u64) -> Result<Vec<u8>, AssetError> {
    let too_large = |len: u64| (ImportErrorKind::TooLarge, format!("{len} bytes is more than the limit of {limit}"));
    let Some((package, entry)) = package_entry(path) else {
        let len = std::fs::metadata(path).map_err(io_error)?.len();
        if len > limit {
            return Err(too_large(len));
        }
        return std::fs::read(path).map_err(io_error);
    };
    if entry.contains('[') {
        return Err((ImportErrorKind::Unsupported, "assets inside nested packages are not read".into()));
    }
    let file = std::fs::File::open(&package).map_err(io_error)?;
    let mut zip = zip::ZipArchive::new(file).map_err(|e| {
        (ImportErrorKind::Syntax, format!("package {} is not a readable ZIP archive: {e}", package.display()))
    })?;
    let mut f = zip.by_name(&entry).map_err(|e| {
        let kind = match e {
            zip::result::ZipError::FileNotFound => ImportErrorKind::MissingFile,
            _ => ImportErrorKind::Syntax,
        };
        (kind, format!("entry `{entry}` of package {}: {e}", package.display()))
    })?;
    if f.size() > limit {
        return Err(too_large(f.size()));
    }
    let mut bytes = Vec::with_capacity(f.size() as usize);
    (&mut f)
        .take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| (ImportErrorKind::Syntax, format!("entry `{entry}` of package {}: {e}", package.display())))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

fn io_error(e: std::io::Error) -> AssetError {
    let kind =
        if e.kind() == std::io::ErrorKind::NotFound { ImportErrorKind::MissingFile } else { ImportErrorKind::Io };
    (kind, e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn package(dir: &Path, entries: &[(&str, &[u8])], method: zip::CompressionMethod) -> PathBuf {
        let p = dir.join("pkg.usdz");
        let mut z = zip::ZipWriter::new(std::fs::File::create(&p).unwrap());
        for (name, bytes) in entries {
            z.start_file(*name, zip::write::SimpleFileOptions::default().compression_method(method)).unwrap();
            z.write_all(bytes).unwrap();
        }
        z.finish().unwrap();
        p
    }

    #[test]
    fn package_entries_and_plain_files_read_alike() {
        let dir = tempfile::tempdir().unwrap();
        let pkg = package(
            dir.path(),
            &[("scene.usda", b"#usda 1.0\n"), ("tex/a.png", b"png bytes")],
            zip::CompressionMethod::Stored,
        );
        let entry = PathBuf::from(format!("{}[tex/a.png]", pkg.display()));
        assert_eq!(package_entry(&entry), Some((pkg.clone(), "tex/a.png".into())));
        assert_eq!(file_name(&entry).as_deref(), Some("a.png"));
        assert_eq!(read_asset(&entry, 100).unwrap(), b"png bytes");
        assert_eq!(read_asset(&entry, 4).unwrap_err().0, ImportErrorKind::TooLarge);
        let missing = PathBuf::from(format!("{}[tex/b.png]", pkg.display()));
        let e = read_asset(&missing, 100).unwrap_err();
        assert!(e.0 == ImportErrorKind::MissingFile && e.1.contains("tex/b.png"), "{e:?}");
        let nested = PathBuf::from(format!("{}[in.usdz[c.png]]", pkg.display()));
        assert_eq!(read_asset(&nested, 100).unwrap_err().0, ImportErrorKind::Unsupported);
        let plain = dir.path().join("plain.png");
        std::fs::write(&plain, b"12345").unwrap();
        assert_eq!(package_entry(&plain), None);
        assert_eq!(read_asset(&plain, 5).unwrap(), b"12345");
        assert_eq!(read_asset(&plain, 4).unwrap_err().0, ImportErrorKind::TooLarge);
        assert_eq!(read_asset(&dir.path().join("none.png"), 5).unwrap_err().0, ImportErrorKind::MissingFile);
    }

    /// A deflated entry that inflates past the limit is stopped at the limit, not inflated whole.
    #[test]
    fn inflation_stops_at_the_limit() {
        let dir = tempfile::tempdir().unwrap();
        let big = vec![0u8; 1 << 20];
        let pkg = package(dir.path(), &[("bomb.png", &big)], zip::CompressionMethod::Deflated);
        let entry = PathBuf::from(format!("{}[bomb.png]", pkg.display()));
        assert_eq!(read_asset(&entry, 1000).unwrap_err().0, ImportErrorKind::TooLarge);
        assert_eq!(read_asset(&entry, 1 << 20).unwrap().len(), 1 << 20);
        let junk = dir.path().join("junk.usdz");
        std::fs::write(&junk, b"not a zip").unwrap();
        let e = read_asset(&PathBuf::from(format!("{}[a.png]", junk.display())), 10).unwrap_err();
        assert_eq!(e.0, ImportErrorKind::Syntax);
    }
}
