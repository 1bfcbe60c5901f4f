//! glTF scenes rendered end to end: .glb and .gltf give identical images, a 1 cd point light gives
//! the photometrically right luminance, and base-colour textures reach the shading.

mod common;

use quasar::render::job::{JobOverrides, render_desc};
use quasar_importers::gltf::writer::{BinStorage, GltfWriter, Prim};
use quasar_importers::photometric::LUMINANCE_PER_Y;
use quasar_importers::{ImportOptions, import_scene};

/// A 20 m white (or textured) floor at y = 0 with uvs, a camera looking straight down from
/// `cam_h` and a point light of `cd` candela 1 m above the origin.
fn floor_scene(cd: f32, cam_h: f32, texture: Option<&[u8]>) -> GltfWriter {
    let mut w = GltfWriter::new();
    w.use_extension("KHR_lights_punctual", false);
    let mat = match texture {
        Some(png) => {
            let img = w.image(png, "image/png");
            GltfWriter::push(&mut w.samplers, r#"{"magFilter":9728,"wrapS":33071,"wrapT":33071}"#);
            GltfWriter::push(&mut w.textures, &format!(r#"{{"source":{img},"sampler":0}}"#));
            GltfWriter::push(
                &mut w.materials,
                r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0}}"#,
            )
        }
        None => GltfWriter::push(&mut w.materials, r#"{"pbrMetallicRoughness":{"metallicFactor":0}}"#),
    };
    let position = w.positions(&[[-10.0, 0.0, 10.0], [10.0, 0.0, 10.0], [10.0, 0.0, -10.0], [-10.0, 0.0, -10.0]]);
    let uv = Some(w.uvs(&[[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]));
    let indices = Some(w.indices(&[0, 1, 2, 0, 2, 3]));
    let m = w.mesh("floor", &[Prim { position, uv, indices, material: Some(mat), ..Default::default() }]);
    GltfWriter::push(&mut w.cameras, r#"{"type":"perspective","perspective":{"yfov":0.17,"znear":0.01}}"#);
    GltfWriter::push(&mut w.lights, &format!(r#"{{"type":"point","intensity":{cd}}}"#));
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let nodes = [
        format!(r#"{{"mesh":{m}}}"#),
        format!(r#"{{"camera":0,"translation":[0,{cam_h},0],"rotation":[{},0,0,{s}]}}"#, -s),
        r#"{"translation":[0,1,0],"extensions":{"KHR_lights_punctual":{"light":0}}}"#.to_owned(),
    ];
    for n in nodes {
        let i = GltfWriter::push(&mut w.nodes, &n);
        w.roots.push(i);
    }
    w
}

fn overrides(size: u32, spp: u32) -> JobOverrides {
    JobOverrides {
        width: Some(size),
        height: Some(size),
        spp: Some(spp),
        method: Some("pt".into()),
        threads: Some(2),
        ..Default::default()
    }
}

fn render(path: &std::path::Path, ov: &JobOverrides) -> quasar::output::ExrImage {
    let desc = import_scene(path, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    render_desc(&desc, ov, false).unwrap_or_else(|e| panic!("{e:#}")).image
}

#[test]
fn glb_and_gltf_render_identically() {
    let dir = tempfile::tempdir().unwrap();
    let w = floor_scene(5.0, 0.6, None);
    let a = dir.path().join("a.gltf");
    std::fs::write(&a, w.to_gltf(&BinStorage::DataUri).0).unwrap();
    let b = dir.path().join("b.glb");
    std::fs::write(&b, w.to_glb()).unwrap();
    let ov = overrides(12, 4);
    let (ia, ib) = (render(&a, &ov), render(&b, &ov));
    let (ya, yb) = (ia.channel(quasar::film::LUMINANCE).unwrap(), ib.channel(quasar::film::LUMINANCE).unwrap());
    assert!(ya.iter().any(|&v| v > 0.0), "the floor is lit");
    assert_eq!(ya, yb, "bit-identical");
}

#[test]
fn one_candela_gives_the_photometric_luminance() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cd.glb");
    std::fs::write(&p, floor_scene(1.0, 0.5, None).to_glb()).unwrap();
    let img = render(&p, &overrides(8, 4));
    let y = common::mean(img.channel(quasar::film::LUMINANCE).unwrap());
    // 1 cd at 1 m: 1 lx on a white Lambertian floor -> 1/pi cd/m^2
    let lv = y * f64::from(LUMINANCE_PER_Y);
    let want = 1.0 / std::f64::consts::PI;
    assert!((lv / want - 1.0).abs() < 0.02, "luminance {lv} cd/m^2, expected {want}");
}

#[test]
fn base_colour_texture_is_shaded() {
    // left half red, right half blue (nearest filtering, clamped)
    let img = image::RgbaImage::from_fn(2, 1, |x, _| {
        if x == 0 { image::Rgba([255, 0, 0, 255]) } else { image::Rgba([0, 0, 255, 255]) }
    });
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("tex.glb");
    // a camera high enough to see the floor's central 1.7 m, whose texture splits at x = 0
    std::fs::write(&p, floor_scene(50.0, 10.0, Some(png.get_ref())).to_glb()).unwrap();
    let out = render(&p, &overrides(8, 2));
    let (r, b) = (out.channel("R").unwrap(), out.channel("B").unwrap());
    let at = |x: usize, y: usize| (r[y * 8 + x], b[y * 8 + x]);
    for y in 0..8 {
        let (lr, lb) = at(1, y);
        let (rr, rb) = at(6, y);
        assert!(lr > 3.0 * lb.max(1e-12), "left is red: {lr} {lb}");
        assert!(rb > 3.0 * rr.max(1e-12), "right is blue: {rr} {rb}");
    }
}

/// A floor (normal +y, u along +x, v decreasing towards -z) with a constant normal map `rgb`.
fn normal_mapped_floor_normal(rgb: [u8; 3]) -> glam::Vec3 {
    let img = image::RgbaImage::from_pixel(2, 2, image::Rgba([rgb[0], rgb[1], rgb[2], 255]));
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let mut w = floor_scene(1.0, 1.0, None);
    let i = w.image(png.get_ref(), "image/png");
    let t = GltfWriter::push(&mut w.textures, &format!(r#"{{"source":{i}}}"#));
    w.materials[0] = format!(r#"{{"pbrMetallicRoughness":{{"metallicFactor":0}},"normalTexture":{{"index":{t}}}}}"#);
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("n.glb");
    std::fs::write(&p, w.to_glb()).unwrap();
    let desc = import_scene(&p, &ImportOptions::default()).unwrap();
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let scene = quasar::core::scene::Scene::compile(&desc).unwrap();
    let ray = quasar::core::geometry::Ray::new(glam::Vec3::new(0.3, 2.0, 0.2), -glam::Vec3::Y); // (-0, -1, -0): an exactly axis-parallel ray
    let si = scene.intersect(&ray).expect("hits the floor");
    assert!((si.ng - glam::Vec3::Y).length() < 1e-5);
    si.ns
}

#[test]
fn normal_maps_tilt_the_shading_normal() {
    // flat map: unchanged
    let n = normal_mapped_floor_normal([128, 128, 255]);
    assert!((n - glam::Vec3::Y).length() < 0.01, "{n}");
    // +X of the map = the direction of increasing u (+x)
    let n = normal_mapped_floor_normal([255, 128, 128]);
    assert!((n - glam::Vec3::X).length() < 0.02, "{n}");
    // +Y of the map = "up" in the image = decreasing v (-z here)
    let n = normal_mapped_floor_normal([128, 255, 128]);
    assert!((n + glam::Vec3::Z).length() < 0.02, "{n}");
    // halfway: 45 degrees towards +x
    let n = normal_mapped_floor_normal([218, 128, 218]);
    assert!((n - glam::Vec3::new(1.0, 0.0, 0.0).lerp(glam::Vec3::Y, 0.5).normalize()).length() < 0.02, "{n}");
}

/// The scene of [`floor_scene`] with a 2 m floor (the camera sees its central 1.7 m) carrying
/// COLOR_0 vertex colours `corners` (in the order of its four vertices: -x+z, +x+z, +x-z,
/// -x-z), which multiply its white base colour (issue 52: they were ignored with a warning).
fn coloured_floor(corners: [[f32; 3]; 4]) -> (tempfile::TempDir, std::path::PathBuf) {
    let mut w = floor_scene(50.0, 10.0, None);
    let position = w.positions(&[[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]]);
    let colors = w.normals(&corners);
    let indices = w.indices(&[0, 1, 2, 0, 2, 3]);
    w.meshes[0] = format!(
        r#"{{"name":"floor","primitives":[{{"attributes":{{"POSITION":{position},"COLOR_0":{colors}}},"indices":{indices},"material":0}}]}}"#
    );
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("colours.glb");
    std::fs::write(&p, w.to_glb()).unwrap();
    (dir, p)
}

#[test]
fn vertex_colours_multiply_the_base_colour() {
    let white = render(&coloured_floor([[1.0; 3]; 4]).1, &overrides(8, 4));
    let grey = render(&coloured_floor([[0.5; 3]; 4]).1, &overrides(8, 4));
    // direct light only, the same paths: grey vertex colours halve the image
    let ratio = common::mean(grey.channel(quasar::film::LUMINANCE).unwrap())
        / common::mean(white.channel(quasar::film::LUMINANCE).unwrap());
    assert!((ratio - 0.5).abs() < 0.01, "grey 0.5 vertex colours: {ratio} of the white floor");
    // red towards -x, blue towards +x, interpolated across the floor
    let (_dir, path) = coloured_floor([[1.0, 0.1, 0.1], [0.1, 0.1, 1.0], [0.1, 0.1, 1.0], [1.0, 0.1, 0.1]]);
    let out = render(&path, &overrides(8, 16));
    let (r, b) = (out.channel("R").unwrap(), out.channel("B").unwrap());
    for y in 0..8 {
        let (l, rt) = (y * 8, y * 8 + 7);
        assert!(
            r[l] > 2.0 * r[rt] && b[rt] > 2.0 * b[l],
            "row {y}: left ({}, {}), right ({}, {})",
            r[l],
            b[l],
            r[rt],
            b[rt]
        );
    }
}
