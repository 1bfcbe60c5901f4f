//! The importer table: every supported scene format, chosen by file extension.
//!
//! Adding a format means writing one [`Importer`] and adding one row to [`IMPORTERS`].

use std::path::Path;

use crate::error::ImportError;
use crate::gltf::GltfImporter;
use crate::importer::{Formats, ImportOptions, Importer};
use crate::obj::ObjImporter;
use crate::scene_desc::SceneDesc;
use crate::toml_scene::{self, TomlSceneImporter};
use crate::usd::UsdImporter;

/// The table of importers, searched in order by [`importer_for`].
pub static IMPORTERS: &[&dyn Importer] = &[&TomlSceneImporter, &ObjImporter, &GltfImporter, &UsdImporter];

/// Every format of [`IMPORTERS`].
pub fn formats() -> Formats<'static> {
    Formats(IMPORTERS)
}

/// The importer registered for the extension of `path` (case-insensitive), if any.
pub fn importer_for(path: &Path) -> Option<&'static dyn Importer> {
    formats().for_path(path)
}

/// All extensions that some importer handles, in table order.
pub fn supported_extensions() -> Vec<&'static str> {
    formats().extensions()
}

/// Imports the scene file at `path` with the importer registered for its extension.
/// A medium whose surfaces leave gaps is reported in [`SceneDesc::warnings`]
/// ([`crate::medium_boundary`]).
pub fn import_scene(path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    formats().import(path, opts).map(with_boundary_warnings)
}

/// `desc` with a warning for every medium whose surfaces do not close.
fn with_boundary_warnings(mut desc: SceneDesc) -> SceneDesc {
    let open = crate::medium_boundary::open_medium_boundaries(&desc);
    desc.warnings.extend(open);
    desc
}

/// Imports TOML scene text as if it were the file `path` (for messages and to resolve relative
/// file names against `path`'s directory); its includes may be of any format.
pub fn parse_toml_scene(text: &str, path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    toml_scene::parse_toml_scene(text, path, opts, formats()).map(with_boundary_warnings)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ImportErrorKind;
    use crate::importer::ImportOptions;

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
