//! quasar-importers: the plain-data [`SceneDesc`] and the importers that produce it.
//!
//! [`import_scene`] picks the importer by file extension from the table in [`registry`]:
//! `.toml` (the native scene format, see `docs/scene-format.md`), `.obj` (Wavefront OBJ/MTL) and
//! `.gltf`/`.glb` (glTF 2.0, see `docs/gltf.md`).
//! Every error is an [`ImportError`] whose message starts with `file:line:col:`.
#![warn(missing_docs)]

pub mod bsdf_file;
pub mod env_map;
pub mod error;
mod glob;
pub mod gltf;
pub mod obj;
mod obj_lint;
pub mod pbr;
pub mod photometric;
pub mod registry;
pub mod scene_desc;
pub mod texture_desc;
pub mod toml_scene;
mod transform;

pub use error::{ErrorPlace, ImportError, ImportErrorKind, did_you_mean};
pub use glob::glob_match;
pub use gltf::{GltfImporter, import_gltf};
pub use obj::{ObjImporter, ObjMaterials, import_obj};
pub use obj_lint::{MAX_OBJ_BYTES, MAX_OBJ_TRIANGLES, MAX_SMALL_FILE_BYTES};
pub use pbr::{PbrParams, pbr_material, pbr_material_at};
pub use registry::{IMPORTERS, ImportOptions, Importer, import_scene, importer_for, supported_extensions};
pub use scene_desc::*;
pub use toml_scene::{TomlSceneImporter, import_toml_scene, parse_toml_scene};
