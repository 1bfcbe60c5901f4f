//! Helpers for the importer integration tests: scene files in a temporary directory.
#![allow(dead_code)]

use std::path::PathBuf;

use quasar_importers::{ImportError, ImportOptions, SceneDesc, import_scene};

/// A temporary directory holding the files of one test.
pub struct Files {
    /// The directory (deleted on drop).
    pub dir: tempfile::TempDir,
}

impl Files {
    /// A fresh, empty directory.
    pub fn new() -> Self {
        Self { dir: tempfile::tempdir().unwrap() }
    }

    /// Writes `text` to `name` (sub-directories are created) and returns its path.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.dir.path().join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(&p, text).unwrap();
        p
    }

    /// The path of `name` in the directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// Imports `name` with default options.
    pub fn import(&self, name: &str) -> Result<SceneDesc, ImportError> {
        import_scene(&self.path(name), &ImportOptions::default())
    }
}

/// Writes `scene.toml` (plus `extra` files) and imports it.
pub fn scene(toml: &str, extra: &[(&str, &str)]) -> (Files, Result<SceneDesc, ImportError>) {
    let f = Files::new();
    for (n, t) in extra {
        f.write(n, t);
    }
    f.write("scene.toml", toml);
    let r = f.import("scene.toml");
    (f, r)
}

/// Imports `scene.toml` and panics with the message on failure.
pub fn ok(toml: &str, extra: &[(&str, &str)]) -> SceneDesc {
    match scene(toml, extra).1 {
        Ok(s) => s,
        Err(e) => panic!("import failed: {e}"),
    }
}

/// Imports `scene.toml`, expects an error, and returns its message.
pub fn err(toml: &str, extra: &[(&str, &str)]) -> String {
    match scene(toml, extra).1 {
        Ok(_) => panic!("import should have failed:\n{toml}"),
        Err(e) => e.to_string(),
    }
}

/// 1-based line of the first line of `text` containing `needle`.
pub fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap_or_else(|| panic!("{needle:?} not in text")) + 1
}

/// Asserts that `msg` names `file:line` (followed by `:` and a column or message) and contains
/// every string of `parts`.
pub fn assert_at(msg: &str, file: &str, line: usize, parts: &[&str]) {
    let at = format!("{file}:{line}:");
    assert!(msg.contains(&at), "error should name {at}\n  got: {msg}");
    for p in parts {
        assert!(msg.contains(p), "error should contain {p:?}\n  got: {msg}");
    }
}

/// A minimal valid scene (one grey sphere, an environment light) to which tests append.
pub const BASE: &str = r#"[camera]
position = [0, 0, 5]
target = [0, 0, 0]
fov_deg = 40

[materials.grey]
type = "diffuse"
reflectance = 0.5

[[shape]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "grey"

[[light]]
type = "environment"
spectrum = 1
"#;
