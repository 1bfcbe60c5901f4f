//! The one way quasar writes an output file: to a hidden temporary file beside it (same folder,
//! so the rename cannot cross file systems; named per process), which is renamed over the
//! target only once it is complete. The target is therefore either its old content or the
//! complete new file, never a truncated one, and a failed write leaves nothing behind.

use std::path::{Path, PathBuf};

/// The temporary path beside `path`: `.NAME.tmpPID`.
fn temp_path(path: &Path) -> PathBuf {
    let name = path.file_name().map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp{}", std::process::id()))
}

/// A failed atomic write: the target file and what went wrong (a missing folder, permissions,
/// a full disk).
#[derive(Debug, thiserror::Error)]
#[error("{}: {msg}", path.display())]
pub struct WriteError {
    /// The file that was to be written.
    pub path: PathBuf,
    /// What went wrong.
    pub msg: String,
}

/// Writes `path` atomically: `write` creates the file at the temporary path it is given, which
/// then replaces `path`.
pub fn write_atomic(path: &Path, write: impl FnOnce(&Path) -> Result<(), String>) -> Result<(), WriteError> {
    let tmp = temp_path(path);
    let result = write(&tmp).and_then(|()| std::fs::rename(&tmp, path).map_err(|e| e.to_string()));
    if let Err(msg) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(WriteError { path: path.to_path_buf(), msg });
    }
    Ok(())
}

/// [`write_atomic`] of `bytes`, synced to disk before the rename (checkpoints must survive a
/// crash right after they are written).
pub fn write_atomic_bytes(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    use std::io::Write;
    write_atomic(path, |tmp| {
        let mut f = std::fs::File::create(tmp).map_err(|e| e.to_string())?;
        f.write_all(bytes).map_err(|e| e.to_string())?;
        f.sync_all().map_err(|e| e.to_string())
    })
}

/// [`write_atomic`] of an 8-bit RGB image as PNG.
pub fn write_png_atomic(path: &Path, img: &image::RgbImage) -> Result<(), WriteError> {
    write_atomic(path, |tmp| img.save_with_format(tmp, image::ImageFormat::Png).map_err(|e| e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_atomic_bytes(&p, b"old").unwrap();
        let e = write_atomic(&p, |tmp| {
            std::fs::write(tmp, "half").unwrap();
            Err("disk full".into())
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("a.txt") && e.contains("disk full"), "{e}");
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let e = write_atomic_bytes(&dir.path().join("missing/b.txt"), b"x").unwrap_err().to_string();
        assert!(e.contains("missing/b.txt"), "{e}");
    }
}
