//! `quasar info`: what a scene contains (meshes, triangles, materials, textures, cameras, lights,
//! bounds) and the scene analysis behind `auto`.

use std::fmt::Write as _;
use std::path::Path;

use quasar_importers::SceneDesc;

use crate::core::scene::Scene;
use crate::integrator::analysis::SceneAnalysis;

/// The report of the scene file `path`, imported as `desc` and compiled as `compiled`.
pub fn report(path: &Path, desc: &SceneDesc, compiled: &Scene) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "scene: {}", path.display());
    let _ = writeln!(s, "meshes: {}, triangles: {}", desc.meshes.len(), compiled.triangle_count());
    let _ = writeln!(s, "materials: {}", desc.materials.len());
    for m in &desc.materials {
        let tex = if m.textures.is_empty() { "" } else { " (textured)" };
        let _ = writeln!(s, "  {}: {:?}{tex}", m.name, m.material);
    }
    if !desc.textures.is_empty() {
        let t: Vec<String> = desc.textures.iter().map(|t| format!("{} {}x{}", t.name, t.width, t.height)).collect();
        let _ = writeln!(s, "textures: {}", t.join(", "));
    }
    if !desc.cameras.is_empty() {
        let c: Vec<&str> = desc.cameras.iter().map(|c| c.name.as_str()).collect();
        let _ =
            writeln!(s, "cameras in the file: {} (the scene camera looks from {})", c.join(", "), desc.camera.position);
    }
    let _ = writeln!(
        s,
        "lights: {} ({} emissive triangles)",
        compiled.lights.len(),
        compiled.lights.len() - desc.lights.len()
    );
    let _ = writeln!(s, "bounding sphere: centre {:?}, radius {}", compiled.center, compiled.radius);
    s + &SceneAnalysis::of(compiled).report()
}
