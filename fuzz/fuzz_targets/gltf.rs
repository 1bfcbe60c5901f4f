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
    if let Ok(desc) = import_gltf(&path, &ImportOptions::default())
        && let Ok(scene) = quasar::core::scene::Scene::compile(&desc)
    {
        for t in scene.material_textures.iter().flatten() {
            for uv in [glam::Vec2::ZERO, glam::Vec2::new(-3.7, 1e7), glam::Vec2::new(0.5, f32::NAN)] {
                let _ = quasar::materials::pbr_material(&t.params_at(&scene.textures, uv));
                let _ = t.normal_at(&scene.textures, uv);
            }
        }
    }
});
