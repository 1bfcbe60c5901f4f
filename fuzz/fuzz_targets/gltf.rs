//! Fuzz target: glTF or GLB bytes (written to a file, as the importer reads files) -> import ->
//! compile -> evaluate every textured material at a few texture coordinates. Must never panic,
//! hang or allocate without bound.
#![no_main]

use libfuzzer_sys::fuzz_target;
use quasar::importers::{ImportOptions, import_gltf};

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("quasar-fuzz-gltf-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("input.gltf");
    if std::fs::write(&path, data).is_err() {
        return;
    }
    if let Ok(desc) = import_gltf(&path, &ImportOptions::default()) {
        for m in &desc.materials {
            for uv in [glam::Vec2::ZERO, glam::Vec2::new(-3.7, 1e7), glam::Vec2::new(0.5, f32::NAN)] {
                if let Some(p) = m.textures.params_at(&desc.textures, uv) {
                    let _ = quasar::importers::pbr_material(&p);
                }
            }
        }
        let _ = quasar::core::scene::Scene::compile(&desc);
    }
});
