//! The one way quasar writes an output file: to a hidden temporary file beside it (same folder,
//! so the rename cannot cross file systems; named per process), which is renamed over the
//! target only once it is complete. The target is therefore either its old content or the
//! complete new file, never a truncated one, and a failed write leaves nothing behind.
//!
//! What the target path names decides how (`OutputTarget`): a new path or a regular file is
//! replaced by the rename (through a symbolic link: the file it points to, the link stays); a
//! character device (`/dev/null`) or a named pipe is written through, as a device or a pipe
//! expects, from a complete temporary in the system's temporary folder, and is never replaced by
//! a regular file; a folder, a block device or a socket is refused. [`check_writable`] tries the
//! same before a render, so that an unwritable output fails before the work, not after it.

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

/// What an output path names, and so how it is written (module documentation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum OutputTarget {
    /// A regular file, existing or not: written beside it and renamed over it. The path is the
    /// file itself (a symbolic link resolved).
    File(PathBuf),
    /// A character device or a named pipe: written through, never replaced.
    Stream,
}

impl OutputTarget {
    /// Classifies `path`; refuses a folder, a block device and a socket with the reason.
    pub fn of(path: &Path) -> Result<Self, String> {
        let meta = match std::fs::metadata(path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Self::File(path.to_path_buf())),
            Err(e) => return Err(e.to_string()),
            Ok(m) => m,
        };
        if meta.is_file() {
            let file = if path.is_symlink() {
                std::fs::canonicalize(path).map_err(|e| e.to_string())?
            } else {
                path.to_path_buf()
            };
            return Ok(Self::File(file));
        }
        if meta.is_dir() {
            return Err("is a folder, not a file".into());
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            let t = meta.file_type();
            if t.is_char_device() || t.is_fifo() {
                return Ok(Self::Stream);
            }
        }
        Err("is neither a regular file, nor a character device (such as /dev/null), nor a pipe; quasar does not write to it".into())
    }
}

/// Checks before a render that `path` can be written as [`write_atomic`] will write it: the
/// target is a kind quasar writes, and its temporary can be created beside it (for a new or
/// regular file) or the device opened for writing. A named pipe is not opened (that would wait
/// for its reader).
pub fn check_writable(path: &Path) -> Result<(), WriteError> {
    let err = |msg: String| WriteError { path: path.to_path_buf(), msg };
    match OutputTarget::of(path).map_err(err)? {
        OutputTarget::File(file) => {
            let tmp = temp_path(&file);
            let dir = file.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            if !dir.is_dir() {
                return Err(err(format!("the directory {} does not exist", dir.display())));
            }
            std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&tmp)
                .map_err(|e| err(format!("cannot create a file in {}: {e}", dir.display())))?;
            let _ = std::fs::remove_file(&tmp);
            Ok(())
        }
        OutputTarget::Stream => {
            #[cfg(unix)]
            {
                use std::os::unix::fs::FileTypeExt;
                if std::fs::metadata(path).is_ok_and(|m| m.file_type().is_fifo()) {
                    return Ok(());
                }
            }
            std::fs::OpenOptions::new().write(true).open(path).map(drop).map_err(|e| err(e.to_string()))
        }
    }
}

/// Writes `path` atomically: `write` creates the file at the temporary path it is given, which
/// then replaces `path` (or, for a device or a pipe, is copied into it: module documentation).
pub fn write_atomic(path: &Path, write: impl FnOnce(&Path) -> Result<(), String>) -> Result<(), WriteError> {
    let err = |msg: String| WriteError { path: path.to_path_buf(), msg };
    let (tmp, file) = match OutputTarget::of(path).map_err(err)? {
        OutputTarget::File(file) => (temp_path(&file), Some(file)),
        OutputTarget::Stream => {
            let name = format!("quasar-{}-{}", std::process::id(), path.display().to_string().replace('/', "_"));
            (std::env::temp_dir().join(name), None)
        }
    };
    let result = write(&tmp).and_then(|()| match &file {
        Some(file) => std::fs::rename(&tmp, file).map_err(|e| e.to_string()),
        None => copy_into_stream(&tmp, path),
    });
    if let Err(msg) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(err(msg));
    }
    if file.is_none() {
        let _ = std::fs::remove_file(&tmp);
    }
    Ok(())
}

/// Copies the complete file `tmp` into the device or pipe `stream` (opened without truncation
/// or creation, so that nothing else can be made of it).
fn copy_into_stream(tmp: &Path, stream: &Path) -> Result<(), String> {
    use std::io::Write;
    let mut from = std::fs::File::open(tmp).map_err(|e| e.to_string())?;
    let mut to = std::fs::OpenOptions::new().write(true).open(stream).map_err(|e| e.to_string())?;
    std::io::copy(&mut from, &mut to).map_err(|e| e.to_string())?;
    to.flush().map_err(|e| e.to_string())
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

    #[cfg(unix)]
    fn is_char_device(p: &str) -> bool {
        use std::os::unix::fs::FileTypeExt;
        std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_char_device())
    }

    /// `/dev/null` is written through and stays a device; `/dev/full` fails with the device's
    /// own error and stays a device (the landed writer renamed a regular file over both).
    #[cfg(unix)]
    #[test]
    fn devices_are_written_through_never_replaced() {
        if !is_char_device("/dev/null") || !is_char_device("/dev/full") {
            return; // a machine without the devices has nothing to protect
        }
        assert_eq!(OutputTarget::of(Path::new("/dev/null")), Ok(OutputTarget::Stream));
        write_atomic_bytes(Path::new("/dev/null"), b"discarded").unwrap();
        check_writable(Path::new("/dev/null")).unwrap();
        assert!(is_char_device("/dev/null"));
        let e = write_atomic_bytes(Path::new("/dev/full"), &[0; 1 << 16]).unwrap_err().to_string();
        assert!(e.starts_with("/dev/full: ") && e.to_lowercase().contains("space"), "{e}");
        assert!(is_char_device("/dev/full"));
    }

    /// A folder is refused before anything is written; a missing folder is named; a symbolic
    /// link keeps pointing at the file it names, which gets the new content.
    #[test]
    fn folders_are_refused_and_links_followed() {
        let dir = tempfile::tempdir().unwrap();
        let e = check_writable(dir.path()).unwrap_err().to_string();
        assert!(e.contains("is a folder"), "{e}");
        assert!(write_atomic_bytes(dir.path(), b"x").unwrap_err().to_string().contains("is a folder"));
        let e = check_writable(&dir.path().join("missing/a.exr")).unwrap_err().to_string();
        assert!(e.contains("the directory") && e.contains("missing") && e.contains("does not exist"), "{e}");
        let file = dir.path().join("real.txt");
        write_atomic_bytes(&file, b"old").unwrap();
        check_writable(&file).unwrap();
        #[cfg(unix)]
        {
            let link = dir.path().join("link.txt");
            std::os::unix::fs::symlink(&file, &link).unwrap();
            write_atomic_bytes(&link, b"new").unwrap();
            assert!(link.is_symlink());
            assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        }
        // nothing but the files themselves is left behind
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert!(names.iter().all(|n| !n.to_string_lossy().contains(".tmp")), "{names:?}");
    }
}
