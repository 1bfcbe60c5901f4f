//! quasar-importers: the plain-data [`SceneDesc`] and the importers that produce it.
//!
//! [`import_scene`] picks the importer by file extension from the table in [`registry`]:
//! `.toml` (the native scene format, see `docs/scene-format.md`), `.obj` (Wavefront OBJ/MTL),
//! `.gltf`/`.glb` (glTF 2.0, see `docs/gltf.md`) and `.usd`/`.usda`/`.usdc`/`.usdz` (USD, see
//! `docs/usd.md`).
//! Every error is an [`ImportError`] whose message starts with `file:line:col:`.
#![warn(missing_docs)]

pub mod asset;
pub mod bsdf_file;
pub mod env_map;
pub mod error;
pub mod framing;
mod glob;
pub mod gltf;
pub mod importer;
pub mod medium_boundary;
pub mod names;
pub mod obj;
mod obj_keywords;
mod obj_lint;
mod obj_text;
pub mod photometric;
pub mod photometry;
pub mod registry;
pub mod scene_desc;
pub mod sensor_desc;
pub mod small_text;
pub mod source;
mod tessellation;
pub mod texture_decode;
pub mod texture_desc;
pub mod toml_reader;
pub mod toml_scene;
mod transform;
pub mod usd;

pub use error::{ErrorPlace, ImportError, ImportErrorKind, did_you_mean};
pub use glob::glob_match;
pub use gltf::{GltfImporter, import_gltf};
pub use importer::{Formats, ImportOptions, Importer};
pub use obj::{ObjImporter, ObjMaterials, import_obj};
pub use obj_lint::{MAX_OBJ_BYTES, MAX_OBJ_TRIANGLES};
pub use registry::{IMPORTERS, formats, import_scene, importer_for, parse_toml_scene, supported_extensions};
pub use scene_desc::*;
pub use sensor_desc::{SensorDesc, SensorLayout, SensorQuantity};
pub use small_text::MAX_SMALL_FILE_BYTES;
pub use toml_scene::TomlSceneImporter;
pub use usd::reader_guard::{UsdReaderGuard, set_usd_reader_guard};
pub use usd::{UsdImporter, import_usd};
