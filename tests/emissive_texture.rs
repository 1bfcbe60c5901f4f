//! Textured emission (issue 50, item 3): a panel whose glTF `emissiveTexture` is a 2 x 2
//! checkerboard shows the checkerboard, and lights a floor as the same panel built of two
//! emitting and two black squares does: `pt` on both agree, and the bidirectional methods on the
//! textured panel converge to `pt` (its light samples and photons follow the texture); a mostly
//! black texture spends its light samples on its lit texels.

mod common;

use common::{assert_converges_from, bidir_ov, layer, pt_ov, render_file};
use quasar_importers::gltf::writer::{BinStorage, GltfWriter, Prim};

/// A `size` x `size` PNG: white where `lit(x, y)`, black elsewhere.
fn png(size: u32, lit: impl Fn(u32, u32) -> bool) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(size, size, |x, y| {
        if lit(x, y) { image::Rgba([255; 4]) } else { image::Rgba([0, 0, 0, 255]) }
    });
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png).unwrap();
    png.into_inner()
}

/// A 2 x 2 PNG: white where x == y, black elsewhere.
fn checkerboard() -> Vec<u8> {
    png(2, |x, y| x == y)
}

/// A quad in the plane y = `y` over x in [x0, x1], z in [z0, z1], facing -y, with uvs
/// u = x + 0.5, v = z + 0.5.
fn quad(w: &mut GltfWriter, y: f32, [x0, x1, z0, z1]: [f32; 4], material: usize, up: bool) -> Prim {
    let position = w.positions(&[[x0, y, z0], [x1, y, z0], [x1, y, z1], [x0, y, z1]]);
    let uv = Some(w.uvs(&[[x0 + 0.5, z0 + 0.5], [x1 + 0.5, z0 + 0.5], [x1 + 0.5, z1 + 0.5], [x0 + 0.5, z1 + 0.5]]));
    let order: [u32; 6] = if up { [0, 2, 1, 0, 3, 2] } else { [0, 1, 2, 0, 2, 3] };
    let indices = Some(w.indices(&order));
    Prim { position, uv, indices, material: Some(material), ..Default::default() }
}

/// The panel (1 m square at y = 1, emitting downwards) over a white floor: textured, or as four
/// squares of which the two on the diagonal x == z emit, untextured.
fn panel_scene(textured: bool) -> String {
    if textured {
        return textured_panel_scene(&checkerboard());
    }
    let quads = [(0.0f32, 0.0f32), (0.5, 0.0), (0.0, 0.5), (0.5, 0.5)].map(|(x, z)| ([x - 0.5, x, z - 0.5, z], x == z));
    squares_panel_scene(&quads)
}

/// The floor under a 1 m panel at y = 1 whose emission follows the PNG `image`.
fn textured_panel_scene(image: &[u8]) -> String {
    let (mut w, mut prims, black) = floor_scene();
    let img = w.image(image, "image/png");
    GltfWriter::push(&mut w.samplers, r#"{"magFilter":9728,"minFilter":9728,"wrapS":33071,"wrapT":33071}"#);
    GltfWriter::push(&mut w.textures, &format!(r#"{{"source":{img},"sampler":0}}"#));
    let m = GltfWriter::push(
        &mut w.materials,
        &format!(r#"{{"name":"panel",{black},"emissiveFactor":[1,1,1],"emissiveTexture":{{"index":0}}}}"#),
    );
    prims.push(quad(&mut w, 1.0, [-0.5, 0.5, -0.5, 0.5], m, false));
    finish(w, &prims)
}

/// The floor under untextured quads at y = 1 ([x0, x1, z0, z1], emitting or black).
fn squares_panel_scene(quads: &[([f32; 4], bool)]) -> String {
    let (mut w, mut prims, black) = floor_scene();
    let lit = GltfWriter::push(&mut w.materials, &format!(r#"{{"name":"lit",{black},"emissiveFactor":[1,1,1]}}"#));
    let dark = GltfWriter::push(&mut w.materials, &format!(r#"{{"name":"dark",{black}}}"#));
    for &(extent, emits) in quads {
        prims.push(quad(&mut w, 1.0, extent, if emits { lit } else { dark }, false));
    }
    finish(w, &prims)
}

/// A writer holding the white floor (4 m square at y = 0), its primitives and a black
/// material's JSON.
fn floor_scene() -> (GltfWriter, Vec<Prim>, &'static str) {
    let mut w = GltfWriter::new();
    let floor_mat = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"floor","pbrMetallicRoughness":{"baseColorFactor":[0.8,0.8,0.8,1],"metallicFactor":0}}"#,
    );
    let black = r#""pbrMetallicRoughness":{"baseColorFactor":[0,0,0,1],"metallicFactor":0}"#;
    let prims = vec![quad(&mut w, 0.0, [-2.0, 2.0, -2.0, 2.0], floor_mat, true)];
    (w, prims, black)
}

/// The glTF text of one mesh of `prims` under one node.
fn finish(mut w: GltfWriter, prims: &[Prim]) -> String {
    let mesh = w.mesh("scene", prims);
    let n = GltfWriter::push(&mut w.nodes, &format!(r#"{{"mesh":{mesh}}}"#));
    w.roots.push(n);
    w.to_gltf(&BinStorage::DataUri).0
}

const FLOOR_VIEW: &str = "[render]\nwidth = 24\nheight = 18\n[camera]\nposition = [0, 0.6, 2.2]\n\
    target = [0, 0, 0]\nfov_deg = 50\n[[include]]\nfile = \"panel.gltf\"\n";

#[test]
fn the_panel_shows_its_checkerboard() {
    let toml = "[render]\nwidth = 16\nheight = 16\n[camera]\nposition = [0, 0.2, 0]\ntarget = [0, 1, 0]\n\
                up = [0, 0, -1]\nfov_deg = 40\n[[include]]\nfile = \"panel.gltf\"\n";
    let scene = common::write_scene(toml, &[("panel.gltf", &panel_scene(true))]);
    let img = render_file(&scene.path, &pt_ov(16, 16, 1024, 1));
    let y = img.image.channel(quasar::film::LUMINANCE).unwrap();
    let px = |x: usize, yy: usize| y[yy * 16 + x];
    let q = [px(4, 4), px(11, 4), px(4, 11), px(11, 11)];
    // diagonal quadrants equal and bright, the others black
    let (bright, dark) = if q[0] > q[1] { ([q[0], q[3]], [q[1], q[2]]) } else { ([q[1], q[2]], [q[0], q[3]]) };
    // (the luminance of 1024 samples of four wavelengths each varies by about 1%)
    assert!(bright.iter().all(|&b| b > 0.0) && (bright[0] - bright[1]).abs() < 0.03 * bright[0], "{q:?}");
    assert!(dark.iter().all(|&d| d == 0.0), "{q:?}");
    // the bright squares have the luminance of the untextured emission (emissiveFactor 1)
    let plain = common::write_scene(toml, &[("panel.gltf", &panel_scene(false))]);
    let p = render_file(&plain.path, &pt_ov(16, 16, 1024, 1));
    let py = p.image.channel(quasar::film::LUMINANCE).unwrap();
    let lit = if q[0] > q[1] { py[4 * 16 + 4] } else { py[4 * 16 + 11] };
    assert!((lit - bright[0]).abs() < 0.03 * lit, "{lit} vs {bright:?}");
}

#[test]
fn the_textured_panel_lights_the_floor_as_its_squares_do() {
    let textured = common::write_scene(FLOOR_VIEW, &[("panel.gltf", &panel_scene(true))]);
    let squares = common::write_scene(FLOOR_VIEW, &[("panel.gltf", &panel_scene(false))]);
    let reference = render_file(&squares.path, &pt_ov(24, 18, 4096, 3));
    let pt = render_file(&textured.path, &pt_ov(24, 18, 4096, 4));
    assert_converges_from(4, "pt, textured panel", &pt, &reference, &[layer("direct"), layer("indirect")]);
    for method in ["vismap", "adaptive+quasi"] {
        let img = render_file(&textured.path, &bidir_ov(24, 18, method, 256, 20_000, 5));
        assert_converges_from(8, method, &img, &reference, &[layer("direct"), layer("indirect")]);
    }
}

/// A mostly black emissive texture (one lit 4 x 4 patch of 32 x 32 texels, 1/64 of the panel)
/// lights the floor as the same patch built as an untextured square does, and its light
/// samples start on the patch (`core/emission_grid.rs`): the floor's noise at equal samples is
/// within 1.5x of the square's (1.08x measured), where uniform points on the panel (1 in 64 on
/// the patch) made it 42x.
#[test]
fn a_mostly_black_emissive_texture_samples_its_lit_texels() {
    // texels x in [4, 8), rows y in [20, 24): u = x + 0.5 in [0.125, 0.25), v = z + 0.5 in
    // [0.625, 0.75) (glTF's v runs down the image)
    let image = png(32, |x, y| (4..8).contains(&x) && (20..24).contains(&y));
    let textured = common::write_scene(FLOOR_VIEW, &[("panel.gltf", &textured_panel_scene(&image))]);
    let (x0, x1, z0, z1) = (-0.375, -0.25, 0.125, 0.25);
    let squares = squares_panel_scene(&[
        ([x0, x1, z0, z1], true),
        ([-0.5, x0, -0.5, 0.5], false),
        ([x1, 0.5, -0.5, 0.5], false),
        ([x0, x1, -0.5, z0], false),
        ([x0, x1, z1, 0.5], false),
    ]);
    let squares = common::write_scene(FLOOR_VIEW, &[("panel.gltf", &squares)]);
    let reference = render_file(&squares.path, &pt_ov(24, 18, 1024, 6));
    let pt = render_file(&textured.path, &pt_ov(24, 18, 1024, 7));
    assert_converges_from(4, "pt, mostly black texture", &pt, &reference, &[layer("direct"), layer("indirect")]);
    let (m_tex, se_tex) = common::mean_and_error(&pt.image);
    let (m_sq, se_sq) = common::mean_and_error(&reference.image);
    eprintln!("floor: textured {m_tex:.5e} +- {se_tex:.2e}, square {m_sq:.5e} +- {se_sq:.2e}");
    assert!(se_tex < 1.5 * se_sq, "textured panel's error {se_tex:.3e} vs the square's {se_sq:.3e}");
}
