//! The importer table: every supported scene format, chosen by file extension.
//!
//! Adding a format means writing one [`Importer`] and adding one row to [`IMPORTERS`].

use std::path::Path;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::gltf::GltfImporter;
use crate::obj::ObjImporter;
use crate::scene_desc::SceneDesc;
use crate::toml_scene::TomlSceneImporter;

/// Options shared by all importers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportOptions {
    /// Extra factor applied to every length after the file's own units are converted to metres
    /// (`None` = 1). Must be finite and > 0.
    pub units_scale: Option<f32>,
    /// Let glTF files refer to external files by absolute paths or by relative paths that leave
    /// the glTF file's folder (refused by default; CLI `--allow-external-paths`).
    pub allow_external_paths: bool,
}

impl ImportOptions {
    /// The validated extra scale (1 when unset).
    pub fn scale(&self, file: &Path) -> Result<f32, ImportError> {
        match self.units_scale {
            None => Ok(1.0),
            Some(s) if s.is_finite() && s > 0.0 => Ok(s),
            Some(s) => Err(ImportError::new(
                ImportErrorKind::InvalidValue,
                ErrorPlace::file(file),
                format!("units scale must be finite and > 0, got {s}"),
            )),
        }
    }
}

/// A scene file format.
pub trait Importer: Sync {
    /// The lower-case file extensions (without the dot) this importer handles.
    fn extensions(&self) -> &[&str];

    /// Reads the file at `path` into a [`SceneDesc`] (lengths in metres, times `opts.units_scale`).
    fn import(&self, path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError>;
}

/// The table of importers, searched in order by [`importer_for`].
pub static IMPORTERS: &[&dyn Importer] = &[&TomlSceneImporter, &ObjImporter, &GltfImporter];

/// The importer registered for the extension of `path` (case-insensitive), if any.
pub fn importer_for(path: &Path) -> Option<&'static dyn Importer> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    IMPORTERS.iter().copied().find(|imp| imp.extensions().contains(&ext.as_str()))
}

/// All extensions that some importer handles, in table order.
pub fn supported_extensions() -> Vec<&'static str> {
    IMPORTERS.iter().flat_map(|imp| imp.extensions().iter().copied()).collect()
}

/// Imports the scene file at `path` with the importer registered for its extension.
pub fn import_scene(path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    match importer_for(path) {
        Some(imp) => imp.import(path, opts),
        None => Err(ImportError::new(
            ImportErrorKind::Unsupported,
            ErrorPlace::file(path),
            format!(
                "unsupported scene format (extension {:?}); supported extensions: {}",
                path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default(),
                supported_extensions().iter().map(|e| format!(".{e}")).collect::<Vec<_>>().join(", ")
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chooses_by_extension_case_insensitively() {
        assert!(importer_for(Path::new("a/b.toml")).unwrap().extensions().contains(&"toml"));
        assert!(importer_for(Path::new("b.OBJ")).unwrap().extensions().contains(&"obj"));
        assert!(importer_for(Path::new("b.xyz")).is_none());
        assert!(importer_for(Path::new("noext")).is_none());
        let e = import_scene(Path::new("dir/model.fbx"), &ImportOptions::default()).unwrap_err();
        assert_eq!(e.kind, ImportErrorKind::Unsupported);
        let s = e.to_string();
        assert!(s.starts_with("dir/model.fbx: unsupported"), "{s}");
        assert!(s.contains(".toml") && s.contains(".obj") && s.contains(".glb"), "{s}");
        assert!(importer_for(Path::new("a.GLTF")).unwrap().extensions().contains(&"gltf"));
    }

    #[test]
    fn units_scale_is_validated() {
        let p = Path::new("x.toml");
        assert_eq!(ImportOptions::default().scale(p).unwrap(), 1.0);
        assert_eq!(ImportOptions { units_scale: Some(0.5), ..Default::default() }.scale(p).unwrap(), 0.5);
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(ImportOptions { units_scale: Some(bad), ..Default::default() }.scale(p).is_err());
        }
    }
}
