//! The example of docs/scene-format.md is the shipped scene `scenes/example/example.toml`, word
//! for word, and renders (issue 18: it referred to `plate.obj` and `stand.obj`, which did not
//! exist).

use std::path::Path;
use std::process::Command;

#[test]
fn the_scene_format_example_is_shipped_and_renders() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/scene-format.md")).unwrap();
    let block = doc.split("## Example\n\n```toml\n").nth(1).and_then(|t| t.split("```").next()).unwrap();
    let scene = root.join("scenes/example/example.toml");
    assert_eq!(block, std::fs::read_to_string(&scene).unwrap(), "docs/scene-format.md and {} differ", scene.display());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("example.exr");
    let o = Command::new(env!("CARGO_BIN_EXE_quasar"))
        .args(["render", "--quiet", "--width", "32", "--height", "24", "--spp", "2"])
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success() && o.stderr.is_empty(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = quasar::output::read_exr(&out).unwrap();
    assert!(img.channel(quasar::film::LUMINANCE).unwrap().iter().any(|&y| y > 0.0));
}
