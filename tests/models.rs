//! Model files as users get them from other tools (`scenes/models/`: OBJ in millimetres without
//! materials or light, OBJ/MTL with trailing comments and an `Ke` light, glTF without lights or
//! cameras) render unedited: exit 0, at most the warnings named here, a framed model (most of
//! the image sees it) and a readable preview (issue 18: they rendered black or edge-on).

use std::path::Path;
use std::process::Command;

/// Renders `file` at 48x36 with a preview; returns stderr, the EXR and the preview's pixels.
fn render(file: &Path) -> (String, quasar::output::ExrImage, Vec<u8>) {
    let dir = tempfile::tempdir().unwrap();
    let (exr, png) = (dir.path().join("m.exr"), dir.path().join("m.png"));
    let o = Command::new(env!("CARGO_BIN_EXE_quasar"))
        .args(["render", "--quiet", "--spp", "8", "--width", "48", "--height", "36"])
        .arg(file)
        .arg("-o")
        .arg(&exr)
        .arg("--preview")
        .arg(&png)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{}: {stderr}", file.display());
    let img = quasar::output::read_exr(&exr).unwrap();
    let preview = image::open(&png).unwrap().to_rgb8().into_raw();
    (stderr, img, preview)
}

#[test]
fn shipped_models_render_unedited_and_framed() {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/models");
    // (file, the warnings it may give)
    let cases: [(&str, &[&str]); 4] = [
        ("cornell-box-mm.obj", &["has no light; it is lit by a uniform white environment"]),
        ("cornell-box-original.obj", &[]),
        // issue 50: KHR_materials_clearcoat required (refused before), a mostly black emissive
        // texture as the only light (it lit the model as its mean colour before)
        ("coated-paint-and-lamp.gltf", &[]),
        // issue 50: sheen and transmission required, sheen textures, volume attenuation, signs
        // that differ only by KHR_materials_emissive_strength
        ("velvet-glass-and-signs.gltf", &[]),
    ];
    for (file, allowed) in cases {
        let (stderr, img, preview) = render(&models.join(file));
        for line in stderr.lines() {
            assert!(allowed.iter().any(|a| line.contains(a)), "{file}: unexpected output {line}");
        }
        for a in allowed {
            assert!(stderr.contains(a), "{file}: expected the warning {a}: {stderr}");
        }
        let depth = img.channel("depth.Z").unwrap();
        let hit = depth.iter().filter(|d| d.is_finite()).count() as f64 / depth.len() as f64;
        assert!(hit > 0.3, "{file}: the model covers only {:.0}% of the image", 100.0 * hit);
        let mean = preview.iter().map(|&v| f64::from(v)).sum::<f64>() / preview.len() as f64;
        assert!((25.0..230.0).contains(&mean), "{file}: preview mean {mean:.1} of 255");
        assert!(img.channel(quasar::film::LUMINANCE).unwrap().iter().all(|y| y.is_finite()));
    }
}
