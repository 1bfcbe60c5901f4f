//! Fuzz target: OBJ bytes (written to a file, as the importer reads files) -> import with its
//! default materials -> compile. Must never panic, hang or allocate without bound.
#![no_main]

use libfuzzer_sys::fuzz_target;
use quasar::importers::{ImportOptions, ObjMaterials, import_obj};

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("quasar-fuzz-obj-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("input.obj");
    if std::fs::write(&path, data).is_err() {
        return;
    }
    if let Ok(desc) = import_obj(&path, &ImportOptions::default(), ObjMaterials::FromMtl) {
        let _ = quasar::core::scene::Scene::compile(&desc);
    }
});
