//! glTF importer: geometry, transforms, materials, extensions, cameras, lights, textures,
//! TOML includes with overrides, and clear errors for malformed files. Every glTF file is written
//! by the test with `quasar_importers::gltf::writer`.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use quasar_importers::gltf::writer::{BinStorage, GltfWriter, Prim};
use quasar_importers::photometric::photometric_scale;
use quasar_importers::{ImportErrorKind, ImportOptions, LightDesc, SceneDesc, TextureRef, TextureWrap, import_scene};
use quasar_materials::{Ior, Material};

/// A unit right triangle in the z = 0 plane facing +z, as one primitive (positions, normals,
/// uvs, indices) with material `mat`.
fn triangle(w: &mut GltfWriter, mat: Option<usize>) -> Prim {
    let position = w.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let normal = Some(w.normals(&[[0.0, 0.0, 1.0]; 3]));
    let uv = Some(w.uvs(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]));
    let indices = Some(w.indices(&[0, 1, 2]));
    Prim { position, normal, uv, indices, material: mat, mode: None }
}

fn node(w: &mut GltfWriter, json: &str) -> usize {
    GltfWriter::push(&mut w.nodes, json)
}

struct Dir {
    dir: tempfile::TempDir,
}

impl Dir {
    fn new() -> Self {
        Self { dir: tempfile::tempdir().unwrap() }
    }
    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }
    fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let p = self.path(name);
        if let Some(d) = p.parent() {
            std::fs::create_dir_all(d).unwrap();
        }
        std::fs::write(&p, bytes).unwrap();
        p
    }
    /// Writes `w` as `name.gltf` with a data URI.
    fn gltf(&self, name: &str, w: &GltfWriter) -> PathBuf {
        self.write(&format!("{name}.gltf"), w.to_gltf(&BinStorage::DataUri).0)
    }
}

fn import(p: &Path) -> SceneDesc {
    import_scene(p, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn import_err(p: &Path) -> (ImportErrorKind, String) {
    let e = import_scene(p, &ImportOptions::default()).unwrap_err();
    (e.kind, e.to_string())
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn trs_matrix_and_hierarchy() {
    let mut w = GltfWriter::new();
    let p = triangle(&mut w, None);
    let m = w.mesh("tri", &[p]);
    // child: matrix = uniform scale 2 then translate (0, 0, 3) (column-major)
    let child =
        node(&mut w, &format!("{{\"name\":\"child\",\"mesh\":{m},\"matrix\":[2,0,0,0, 0,2,0,0, 0,0,2,0, 0,0,3,1]}}"));
    // parent: rotate 90 degrees about +z, translate x by 10
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let parent = node(
        &mut w,
        &format!("{{\"name\":\"parent\",\"children\":[{child}],\"translation\":[10,0,0],\"rotation\":[0,0,{s},{s}]}}"),
    );
    w.roots.push(parent);
    let d = Dir::new();
    let s = import(&d.gltf("h", &w));
    assert_eq!(s.meshes.len(), 1);
    let ps = &s.meshes[0].positions;
    // vertex (1,0,0): scale 2 -> (2,0,0), +z3 -> (2,0,3), rotate z 90 -> (0,2,3), +x10 -> (10,2,3)
    assert!(close(ps[0], Vec3::new(10.0, 0.0, 3.0)), "{ps:?}");
    assert!(close(ps[1], Vec3::new(10.0, 2.0, 3.0)), "{ps:?}");
    assert!(close(ps[2], Vec3::new(8.0, 0.0, 3.0)), "{ps:?}");
    let n = s.meshes[0].normals.as_ref().unwrap();
    assert!(close(n[0], Vec3::Z), "{n:?}");
    assert_eq!(s.meshes[0].uvs.as_ref().unwrap()[1], Vec2::new(1.0, 0.0));
    assert_eq!(s.meshes[0].name, "child:tri:default");

    // --units style extra scale applies to everything
    let opts = ImportOptions { units_scale: Some(0.5), ..Default::default() };
    let half = import_scene(&d.path("h.gltf"), &opts).unwrap();
    assert!(close(half.meshes[0].positions[1], Vec3::new(5.0, 1.0, 1.5)));
}

#[test]
fn multiple_primitives_materials_and_instances() {
    let mut w = GltfWriter::new();
    let red = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"red","pbrMetallicRoughness":{"baseColorFactor":[0.8,0.1,0.1,1],"metallicFactor":0,"roughnessFactor":0.5}}"#,
    );
    let gold = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"gold","pbrMetallicRoughness":{"baseColorFactor":[1,0.8,0.3,1],"metallicFactor":0.9,"roughnessFactor":0.3}}"#,
    );
    let a = triangle(&mut w, Some(red));
    let b = triangle(&mut w, Some(gold));
    let m = w.mesh("pair", &[a, b]);
    let n0 = node(&mut w, &format!("{{\"name\":\"left\",\"mesh\":{m}}}"));
    let n1 = node(&mut w, &format!("{{\"name\":\"right\",\"mesh\":{m},\"translation\":[5,0,0]}}"));
    w.roots.extend([n0, n1]);
    let d = Dir::new();
    let s = import(&d.gltf("m", &w));
    assert_eq!(s.meshes.len(), 4, "2 primitives x 2 instances");
    let names: Vec<&str> = s.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["left:pair:red", "left:pair:gold", "right:pair:red", "right:pair:gold"]);
    assert_eq!(s.materials.len(), 2);
    let mat = |name: &str| &s.materials[s.meshes.iter().find(|m| m.name == name).unwrap().material];
    assert_eq!(mat("right:pair:red").name, "red");
    assert!(matches!(mat("left:pair:red").material, Material::Diffuse { .. }));
    match &mat("left:pair:gold").material {
        Material::Conductor { alpha, .. } => assert!((alpha - 0.09).abs() < 1e-6, "alpha = roughness^2"),
        m => panic!("{m:?}"),
    }
    assert!(close(s.meshes[2].positions[1], Vec3::new(6.0, 0.0, 0.0)));
}

#[test]
fn gltf_glb_and_external_buffer_agree() {
    let mut w = GltfWriter::new();
    let p = triangle(&mut w, None);
    let m = w.mesh("tri", &[p]);
    let n = node(&mut w, &format!("{{\"mesh\":{m},\"translation\":[0,1,0]}}"));
    w.roots.push(n);
    let d = Dir::new();
    let a = import(&d.gltf("a", &w));
    let b = import(&d.write("b.glb", w.to_glb()));
    let (json, bin) = w.to_gltf(&BinStorage::External("sub/my%20data.bin".into()));
    d.write("sub/my data.bin", bin);
    let c = import(&d.write("c.gltf", json));
    for other in [&b, &c] {
        assert_eq!(a.meshes.len(), other.meshes.len());
        assert_eq!(a.meshes[0].positions, other.meshes[0].positions);
        assert_eq!(a.meshes[0].indices, other.meshes[0].indices);
        assert_eq!(a.materials[0].material, other.materials[0].material);
        assert_eq!(a.camera, other.camera);
    }
}

#[test]
fn transmission_ior_volume_specular_and_emission() {
    let mut w = GltfWriter::new();
    for e in [
        "KHR_materials_transmission",
        "KHR_materials_ior",
        "KHR_materials_volume",
        "KHR_materials_specular",
        "KHR_materials_emissive_strength",
    ] {
        w.use_extension(e, false);
    }
    let glass = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"glass","pbrMetallicRoughness":{"baseColorFactor":[0.2,0.9,0.3,1],"metallicFactor":0,"roughnessFactor":0.2},
            "extensions":{"KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_ior":{"ior":1.33},
            "KHR_materials_volume":{"thicknessFactor":0.1,"attenuationColor":[0.5,1,1],"attenuationDistance":0.2},
            "KHR_materials_specular":{"specularFactor":0.5}}}"#,
    );
    let lamp = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"lamp","emissiveFactor":[1,0.5,0.25],"doubleSided":true,
            "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":40}}}"#,
    );
    let a = triangle(&mut w, Some(glass));
    let b = triangle(&mut w, Some(lamp));
    let m = w.mesh("m", &[a, b]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let d = Dir::new();
    let s = import(&d.gltf("x", &w));
    // the one warning: a single triangle cannot close the medium its volume declares
    assert!(
        s.warnings.len() == 1 && s.warnings[0].contains("`glass` (absorption or scattering) is not closed"),
        "{:?}",
        s.warnings
    );
    // the base colour tints the transmitted light (issue 52: it was dropped, coloured glass clear)
    let tint = Some(quasar_materials::spectrum::Spectrum::rgb_reflectance([0.2, 0.9, 0.3]).unwrap());
    assert_eq!(
        s.materials[0].material,
        Material::Dielectric { ior: Ior::Constant(1.33), alpha: 0.2 * 0.2, transmittance: tint }
    );
    assert!(s.meshes[0].emission.is_none());
    let e = s.meshes[1].emission.as_ref().expect("emissive mesh is an area light");
    assert!(e.two_sided);
    assert_eq!(e.scale, photometric_scale(1.0));
    // luminance-normalised colour x strength: the red channel (max) carries 40
    let (lo, hi) = (e.spectrum.value(450.0), e.spectrum.value(650.0));
    assert!(hi > lo, "reddish emission: {lo} vs {hi}");
}

#[test]
fn punctual_lights_convert_photometric_units() {
    let mut w = GltfWriter::new();
    w.use_extension("KHR_lights_punctual", false);
    let lp = GltfWriter::push(&mut w.lights, r#"{"type":"point","intensity":100,"color":[1,1,1]}"#);
    let ls = GltfWriter::push(
        &mut w.lights,
        r#"{"type":"spot","intensity":50,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.5}}"#,
    );
    let ld = GltfWriter::push(&mut w.lights, r#"{"type":"directional","intensity":1000}"#);
    let p = triangle(&mut w, None);
    let m = w.mesh("floor", &[p]);
    let mut roots = vec![node(&mut w, &format!("{{\"mesh\":{m}}}"))];
    roots.push(node(
        &mut w,
        &format!("{{\"translation\":[0,3,0],\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":{lp}}}}}}}"),
    ));
    // spot rotated -90 degrees about x: its -z axis points down (-y)
    let s = std::f32::consts::FRAC_1_SQRT_2;
    roots.push(node(
        &mut w,
        &format!("{{\"rotation\":[{},0,0,{s}],\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":{ls}}}}}}}", -s),
    ));
    roots.push(node(&mut w, &format!("{{\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":{ld}}}}}}}")));
    w.roots.extend(roots);
    let d = Dir::new();
    let sc = import(&d.gltf("l", &w));
    assert_eq!(sc.lights.len(), 3);
    match &sc.lights[0] {
        LightDesc::Point { position, scale, .. } => {
            assert!(close(*position, Vec3::new(0.0, 3.0, 0.0)));
            assert!((scale / photometric_scale(100.0) - 1.0).abs() < 1e-6);
            // 100 cd = 100 / (683 * 106.857) W/(sr nm) per unit of the normalised spectrum
            assert!((scale - 100.0 / (683.0 * 106.857)).abs() < 1e-7);
        }
        l => panic!("{l:?}"),
    }
    match &sc.lights[1] {
        LightDesc::Spot { direction, cone_deg, falloff_start_deg, .. } => {
            assert!(close(direction.normalize(), -Vec3::Y), "{direction}");
            assert!((cone_deg - 0.5f32.to_degrees()).abs() < 1e-4);
            assert!((falloff_start_deg - 0.2f32.to_degrees()).abs() < 1e-4);
        }
        l => panic!("{l:?}"),
    }
    assert!(
        matches!(&sc.lights[2], LightDesc::Directional { direction, .. } if close(direction.normalize(), -Vec3::Z))
    );
}

#[test]
fn cameras_perspective_orthographic_and_framing() {
    let mut w = GltfWriter::new();
    let p = triangle(&mut w, None);
    let m = w.mesh("tri", &[p]);
    let c0 = GltfWriter::push(
        &mut w.cameras,
        r#"{"name":"Main","type":"perspective","perspective":{"yfov":0.5,"aspectRatio":2.0,"znear":0.1}}"#,
    );
    let c1 = GltfWriter::push(
        &mut w.cameras,
        r#"{"name":"Top","type":"orthographic","orthographic":{"xmag":2,"ymag":1,"znear":0.1,"zfar":100}}"#,
    );
    let mut roots = vec![node(&mut w, &format!("{{\"mesh\":{m}}}"))];
    // listed before the camera-0 node: cameras are still ordered by camera index
    roots.push(node(&mut w, &format!("{{\"camera\":{c1},\"translation\":[0,0,10]}}")));
    roots.push(node(&mut w, &format!("{{\"camera\":{c0},\"translation\":[0,0,5]}}")));
    w.roots.extend(roots);
    let d = Dir::new();
    let s = import(&d.gltf("c", &w));
    assert_eq!(s.cameras.len(), 2);
    assert_eq!(s.cameras[0].name, "Main");
    assert_eq!(s.camera, s.cameras[0].camera);
    assert!(close(s.camera.position, Vec3::new(0.0, 0.0, 5.0)));
    assert!(close((s.camera.target - s.camera.position).normalize(), -Vec3::Z));
    assert!((s.camera.fov_deg - 0.5f32.to_degrees()).abs() < 1e-4);
    assert_eq!((s.render.width, s.render.height), (960, 480), "aspectRatio sets the default width");
    assert!(s.warnings.iter().any(|w| w.contains("orthographic") && w.contains("Top")), "{:?}", s.warnings);
    // ortho fallback spans ymag = 1 at the scene centre distance (about 10 m): 2 atan(1/10)
    let top = &s.cameras[1].camera;
    assert!((top.fov_deg - 2.0 * (1.0f32 / 10.0).atan().to_degrees()).abs() < 0.5, "{}", top.fov_deg);

    // without cameras: a framing camera that looks at the centre of the bounds
    let mut w = GltfWriter::new();
    let p = triangle(&mut w, None);
    let m = w.mesh("tri", &[p]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let s = import(&d.gltf("f", &w));
    assert!(s.cameras.is_empty());
    assert!(close(s.camera.target, Vec3::new(0.5, 0.5, 0.0)));
    assert!((s.camera.position - s.camera.target).length() > 1.0);
}

/// PNG bytes of a w x h image from `f(x, y)`.
fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(f(x, y)));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

#[test]
fn textures_and_texture_transform() {
    let mut w = GltfWriter::new();
    w.use_extension("KHR_texture_transform", false);
    let img = w.image(&png(4, 2, |x, _| if x < 2 { [255, 0, 0, 255] } else { [0, 0, 255, 255] }), "image/png");
    GltfWriter::push(&mut w.samplers, r#"{"magFilter":9728,"wrapS":33071,"wrapT":10497}"#);
    let t = GltfWriter::push(&mut w.textures, &format!("{{\"source\":{img},\"sampler\":0}}"));
    let mat = GltfWriter::push(
        &mut w.materials,
        &format!(
            r#"{{"name":"tex","pbrMetallicRoughness":{{"baseColorTexture":{{"index":{t},
            "extensions":{{"KHR_texture_transform":{{"offset":[0.5,0],"scale":[2,1]}}}}}},"metallicFactor":0}}}}"#
        ),
    );
    let p = triangle(&mut w, Some(mat));
    let m = w.mesh("tri", &[p]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let d = Dir::new();
    let s = import(&d.gltf("t", &w));
    assert_eq!(s.textures.len(), 1);
    let tex = &s.textures[0];
    assert_eq!((tex.width, tex.height), (4, 2));
    assert!(tex.nearest);
    assert_eq!((tex.wrap_u, tex.wrap_v), (TextureWrap::ClampToEdge, TextureWrap::Repeat));
    assert_eq!((tex.texels[0], tex.texels[3]), ([255, 0, 0, 255], [0, 0, 255, 255]));
    let mt = &s.materials[0].textures;
    let r = mt.base_color.expect("base colour texture");
    // uv' = T R S uv with offset (0.5, 0), scale (2, 1): u' = 2 u + 0.5 (evaluated by
    // quasar::core::texture, tested there)
    assert_eq!(r.transform, [[2.0, 0.0, 0.5], [0.0, 1.0, 0.0]]);
    assert_eq!(mt.pbr.unwrap().metallic, 0.0);
}

/// A textured triangle: base colour (red) in `a.gltf`; a normal map (a colour no other texture
/// has) in `b.gltf`. Included together, each material's references point at its own file's
/// textures (the normal map's index was once left unshifted, sampling `a.gltf`'s image).
#[test]
fn toml_includes_shift_every_texture_index() {
    let d = Dir::new();
    let mut a = GltfWriter::new();
    let img = a.image(&png(2, 2, |_, _| [255, 0, 0, 255]), "image/png");
    let t = GltfWriter::push(&mut a.textures, &format!("{{\"source\":{img}}}"));
    let mat = GltfWriter::push(
        &mut a.materials,
        &format!(r#"{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":{t}}}}}}}"#),
    );
    let p = triangle(&mut a, Some(mat));
    let m = a.mesh("A", &[p]);
    let n = node(&mut a, &format!("{{\"mesh\":{m}}}"));
    a.roots.push(n);
    d.gltf("a", &a);
    let mut b = GltfWriter::new();
    let base = b.image(&png(2, 2, |_, _| [0, 255, 0, 255]), "image/png");
    let normal = b.image(&png(2, 2, |_, _| [200, 128, 255, 255]), "image/png");
    let tb = GltfWriter::push(&mut b.textures, &format!("{{\"source\":{base}}}"));
    let tn = GltfWriter::push(&mut b.textures, &format!("{{\"source\":{normal}}}"));
    let mat = GltfWriter::push(
        &mut b.materials,
        &format!(
            r#"{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":{tb}}}}},"normalTexture":{{"index":{tn}}}}}"#
        ),
    );
    let p = triangle(&mut b, Some(mat));
    let m = b.mesh("B", &[p]);
    let n = node(&mut b, &format!("{{\"mesh\":{m}}}"));
    b.roots.push(n);
    d.gltf("b", &b);
    let s = import(&d.write("s.toml", "[[include]]\nfile = \"a.gltf\"\n[[include]]\nfile = \"b.gltf\"\n"));
    assert_eq!(s.textures.len(), 3);
    let textures_of = |file: &str| {
        let m = s.materials.iter().find(|m| m.name.starts_with(file)).unwrap_or_else(|| panic!("{file}"));
        m.textures.clone()
    };
    let texel = |r: Option<TextureRef>| s.textures[r.expect("reference").texture].texels[0];
    assert_eq!(texel(textures_of("a.gltf").base_color), [255, 0, 0, 255]);
    let tb = textures_of("b.gltf");
    assert_eq!(texel(tb.base_color), [0, 255, 0, 255]);
    assert_eq!(texel(tb.normal), [200, 128, 255, 255]);
}

/// A PNG whose header claims `w` x `h` (decoders must refuse it before allocating).
fn png_header_only(w: u32, h: u32) -> Vec<u8> {
    fn crc32(data: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in data {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 != 0 { 0xedb8_8320 ^ (c >> 1) } else { c >> 1 };
            }
        }
        !c
    }
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend_from_slice(&13u32.to_be_bytes());
    out.extend_from_slice(&ihdr);
    out.extend_from_slice(&crc32(&ihdr).to_be_bytes());
    out
}

fn textured_quad(image_bytes: &[u8]) -> GltfWriter {
    let mut w = GltfWriter::new();
    let img = w.image(image_bytes, "image/png");
    let t = GltfWriter::push(&mut w.textures, &format!("{{\"source\":{img}}}"));
    let mat = GltfWriter::push(
        &mut w.materials,
        &format!(r#"{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":{t}}}}}}}"#),
    );
    let p = triangle(&mut w, Some(mat));
    let m = w.mesh("tri", &[p]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    w
}

#[test]
fn decompression_bombs_and_bad_images_are_refused() {
    let d = Dir::new();
    let (k, e) = import_err(&d.gltf("bomb", &textured_quad(&png_header_only(100_000, 100_000))));
    assert_eq!(k, ImportErrorKind::TooLarge, "{e}");
    assert!(e.contains("bomb.gltf") && e.contains("/images/0"), "{e}");
    // a textured material on a primitive without texture coordinates: a warning
    let mut w = textured_quad(&png(1, 1, |_, _| [255; 4]));
    let position = w.positions(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let m = w.mesh("no-uv", &[Prim { position, material: Some(0), ..Default::default() }]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let s = import(&d.gltf("nouv", &w));
    assert!(
        s.warnings.iter().any(|x| x.contains("/meshes/1/primitives/0") && x.contains("no TEXCOORD_0")),
        "{:?}",
        s.warnings
    );
    let (k, e) = import_err(&d.gltf("junk", &textured_quad(b"not an image at all")));
    assert_eq!(k, ImportErrorKind::Unsupported, "{e}");
    assert!(e.contains("/images/0"), "{e}");
}

fn simple() -> GltfWriter {
    let mut w = GltfWriter::new();
    let p = triangle(&mut w, None);
    let m = w.mesh("tri", &[p]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    w
}

#[test]
fn malformed_files_give_clear_errors() {
    let d = Dir::new();
    // bad JSON: line and column
    let p = d.write("bad.gltf", "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [ oops ]\n}");
    let (k, e) = import_err(&p);
    assert_eq!(k, ImportErrorKind::Syntax);
    assert!(e.starts_with(&format!("{}:3:", p.display())), "{e}");

    // accessor past the end of its buffer view
    let mut w = GltfWriter::new();
    let mut p = triangle(&mut w, None);
    // view 3 holds the 3 indices (12 bytes); this accessor claims 1000
    p.indices = Some(w.raw_accessor(r#"{"bufferView":3,"componentType":5125,"count":1000,"type":"SCALAR"}"#));
    let m = w.mesh("tri", &[p]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let (k, e) = import_err(&d.gltf("range", &w));
    assert_eq!(k, ImportErrorKind::InvalidValue, "{e}");
    assert!(e.contains("/meshes/0/primitives/0/indices") && e.contains("do not fit"), "{e}");

    // index beyond the vertex count
    let mut w = GltfWriter::new();
    let position = w.positions(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let indices = Some(w.indices(&[0, 1, 7]));
    let m = w.mesh("bad", &[Prim { position, indices, ..Default::default() }]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let (_, e) = import_err(&d.gltf("idx", &w));
    assert!(e.contains("/meshes/0/primitives/0/indices") && e.contains("only 3 vertices"), "{e}");

    // missing external buffer
    let (json, _) = simple().to_gltf(&BinStorage::External("gone.bin".into()));
    let (k, e) = import_err(&d.write("missing.gltf", json));
    assert_eq!(k, ImportErrorKind::MissingFile);
    assert!(e.contains("/buffers/0/uri") && e.contains("gone.bin"), "{e}");

    // paths escaping the folder, absolute paths; allowed with the flag
    let (json, bin) = simple().to_gltf(&BinStorage::External("../outside.bin".into()));
    d.write("outside.bin", &bin);
    let p = d.write("in/escape.gltf", json);
    let (k, e) = import_err(&p);
    assert_eq!(k, ImportErrorKind::InvalidValue);
    assert!(e.contains("leaves the glTF file's folder") && e.contains("--allow-external-paths"), "{e}");
    let allow = ImportOptions { allow_external_paths: true, ..Default::default() };
    assert_eq!(import_scene(&p, &allow).unwrap().meshes.len(), 1);
    let abs = d.path("outside.bin").display().to_string();
    let (json, _) = simple().to_gltf(&BinStorage::External(abs));
    let (_, e) = import_err(&d.write("abs.gltf", json));
    assert!(e.contains("absolute path"), "{e}");

    // required unsupported extension: error; used unsupported: warning
    let mut w = simple();
    w.use_extension("KHR_draco_mesh_compression", true);
    let (k, e) = import_err(&d.gltf("req", &w));
    assert_eq!(k, ImportErrorKind::Unsupported);
    assert!(e.contains("/extensionsRequired/0") && e.contains("KHR_draco_mesh_compression"), "{e}");
    let mut w = simple();
    w.use_extension("KHR_materials_iridescence", false);
    w.use_extension("EXT_meshopt_compression", false);
    let s = import(&d.gltf("used", &w));
    assert_eq!(s.warnings.len(), 1);
    assert!(s.warnings[0].contains("KHR_materials_iridescence, EXT_meshopt_compression"), "{:?}", s.warnings);

    // invalid references found by validation name a JSON pointer
    let mut w = simple();
    w.nodes[0] = "{\"mesh\":9}".into();
    let (_, e) = import_err(&d.gltf("ref", &w));
    assert!(e.contains("/nodes/0/mesh"), "{e}");

    // a huge accessor without bufferView (all zeros) is refused before anything is allocated
    let mut w = GltfWriter::new();
    let position =
        w.raw_accessor(r#"{"componentType":5126,"count":536870912,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}"#);
    let indices = Some(w.indices(&[0, 1, 2]));
    let m = w.mesh("zeros", &[Prim { position, indices, ..Default::default() }]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let (k, e) = import_err(&d.gltf("zeros", &w));
    assert_eq!(k, ImportErrorKind::InvalidValue, "{e}");
    assert!(e.contains("/accessors/0/bufferView"), "{e}");

    // a POSITION accessor that does not exist (the gltf crate's validation would index with it)
    let mut w = GltfWriter::new();
    let m = w.mesh("bad", &[Prim { position: 99, ..Default::default() }]);
    let n = node(&mut w, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(n);
    let (_, e) = import_err(&d.gltf("pos", &w));
    assert!(
        e.contains("/meshes/0/primitives/0/attributes/POSITION") && e.contains("accessor 99 does not exist"),
        "{e}"
    );

    // fields the gltf crate would unwrap: an image in a bufferView without mimeType, a camera
    // whose projection object does not match its type
    let mut w = textured_quad(&png(1, 1, |_, _| [255; 4]));
    w.images[0] = w.images[0].replace(",\"mimeType\":\"image/png\"", "");
    let (_, e) = import_err(&d.gltf("mime", &w));
    assert!(e.contains("/images/0") && e.contains("mimeType"), "{e}");
    let mut w = simple();
    GltfWriter::push(&mut w.cameras, r#"{"type":"orthographic","perspective":{"yfov":1,"znear":0.1}}"#);
    let (_, e) = import_err(&d.gltf("camtype", &w));
    assert!(e.contains("/cameras/0") && e.contains("projection"), "{e}");

    // GLB header whose length is shorter than the header
    let mut glb = simple().to_glb();
    glb[8..12].copy_from_slice(&4u32.to_le_bytes());
    let (_, e) = import_err(&d.write("hdr.glb", &glb));
    assert!(e.contains("hdr.glb") && e.contains("header's length 4"), "{e}");

    // truncated GLB
    let glb = simple().to_glb();
    let (k, e) = import_err(&d.write("cut.glb", &glb[..glb.len() - 7]));
    assert_eq!(k, ImportErrorKind::Syntax, "{e}");
    assert!(e.contains("cut.glb") && e.contains("GLB"), "{e}");

    // byteLength larger than the data
    let (json, bin) = simple().to_gltf(&BinStorage::External("short.bin".into()));
    d.write("short.bin", &bin[..bin.len() - 4]);
    let (_, e) = import_err(&d.write("short.gltf", json));
    assert!(e.contains("/buffers/0/byteLength"), "{e}");
}

#[test]
fn toml_include_overrides_and_camera_by_name() {
    let mut w = GltfWriter::new();
    let chrome = GltfWriter::push(&mut w.materials, r#"{"name":"Chrome","pbrMetallicRoughness":{"metallicFactor":1}}"#);
    let paint = GltfWriter::push(&mut w.materials, r#"{"name":"Paint","pbrMetallicRoughness":{"metallicFactor":0}}"#);
    let a = triangle(&mut w, Some(chrome));
    let b = triangle(&mut w, Some(paint));
    let m = w.mesh("Body", &[a, b]);
    let cam = GltfWriter::push(
        &mut w.cameras,
        r#"{"name":"Front","type":"perspective","perspective":{"yfov":0.7,"znear":0.1}}"#,
    );
    let c2 = GltfWriter::push(
        &mut w.cameras,
        r#"{"name":"Side","type":"perspective","perspective":{"yfov":0.3,"znear":0.1}}"#,
    );
    let mut roots = vec![node(&mut w, &format!("{{\"name\":\"Car\",\"mesh\":{m}}}"))];
    roots.push(node(&mut w, &format!("{{\"camera\":{cam},\"translation\":[0,0,4]}}")));
    roots.push(node(
        &mut w,
        &format!("{{\"camera\":{c2},\"translation\":[4,0,0],\"rotation\":[0,0.7071068,0,0.7071068]}}"),
    ));
    w.roots.extend(roots);
    let d = Dir::new();
    d.gltf("car", &w);
    let toml = |camera: &str| {
        format!(
            r#"
[materials.matte]
type = "diffuse"
reflectance = {{ constant = 0.5 }}

[[include]]
file = "car.gltf"
transform = {{ translate = [0, 0, 1] }}

[[override]]
match = "Paint"
material = "matte"
{camera}
"#
        )
    };
    let s = import(&d.write("a.toml", toml("")));
    let mesh = |name: &str| s.meshes.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("{name}"));
    assert_eq!(s.materials[mesh("Car:Body:Paint").material].name, "matte");
    assert_eq!(s.materials[mesh("Car:Body:Chrome").material].name, "car.gltf:Chrome");
    // default: the first included camera, moved by the include transform
    assert!(close(s.camera.position, Vec3::new(0.0, 0.0, 5.0)), "{:?}", s.camera);
    let s = import(&d.write("b.toml", toml("[camera]\nname = \"Side\"")));
    assert!(close(s.camera.position, Vec3::new(4.0, 0.0, 1.0)), "{:?}", s.camera);
    assert!((s.camera.fov_deg - 0.3f32.to_degrees()).abs() < 1e-4);
    let s = import(&d.write("c.toml", toml("[camera]\nindex = 1")));
    assert!(close(s.camera.position, Vec3::new(4.0, 0.0, 1.0)));
    let (k, e) = import_err(&d.write("d.toml", toml("[camera]\nname = \"Frnt\"")));
    assert_eq!(k, ImportErrorKind::UnresolvedReference);
    assert!(e.contains("Front, Side") && e.contains("did you mean `Front`"), "{e}");
    // glob override on mesh names
    let s = import(&d.write("e.toml", toml("").replace("match = \"Paint\"", "match = \"Car:Body:*\"")));
    assert!(s.meshes.iter().all(|m| s.materials[m.material].name == "matte"));
}

#[test]
fn shipped_showcase_imports_cleanly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/gltf-showcase");
    let s = import(&dir.join("showcase.gltf"));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let cams: Vec<&str> = s.cameras.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(cams, ["Main", "Top"]);
    assert_eq!((s.render.width, s.render.height), (853, 480), "16:9 aspect ratio");
    assert_eq!(s.lights.len(), 3);
    assert_eq!(s.textures.len(), 2);
    assert!(s.meshes.iter().any(|m| m.emission.is_some()), "emissive panel");
    assert!(s.materials.iter().any(|m| matches!(m.material, Material::Dielectric { .. })), "glass");
    assert_eq!(s.meshes.iter().filter(|m| m.name.contains(":GoldBall:")).count(), 2, "instanced");
    let t = import(&dir.join("showcase.toml"));
    assert_eq!(t.camera, s.cameras[1].camera, "the TOML picks the Top camera");
    let block = t.meshes.iter().find(|m| m.name == "Block:Block:RedPaint").unwrap();
    assert_eq!(t.materials[block.material].name, "copper");
}

/// Morph targets are applied at their default weights (the node's over the mesh's); skins and
/// animations, which are not used, give one warning each (issue 18: Khronos SimpleSkin and
/// SimpleMorph were read silently as if they had none); COLOR_0 vertex colours are read (issue
/// 52), as FLOAT VEC3 here and as normalised UNSIGNED_BYTE VEC4 below.
#[test]
fn morph_targets_apply_and_unused_features_warn() {
    let mut w = GltfWriter::new();
    let position = w.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let normal = w.normals(&[[0.0, 0.0, 1.0]; 3]);
    let shift = w.positions(&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
    let tilt = w.normals(&[[1.0, 0.0, 0.0]; 3]);
    let lift = w.positions(&[[0.0, 0.0, 4.0]; 3]);
    let colors = w.normals(&[[1.0, 0.0, 0.0]; 3]);
    let indices = w.indices(&[0, 1, 2]);
    let mesh = format!(
        r#"{{"name":"morph","weights":[0.5,0.0],"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal},"COLOR_0":{colors}}},"indices":{indices},"targets":[{{"POSITION":{shift},"NORMAL":{tilt}}},{{"POSITION":{lift}}}]}}]}}"#
    );
    let m = GltfWriter::push(&mut w.meshes, &mesh);
    let a = node(&mut w, &format!(r#"{{"name":"A","mesh":{m}}}"#));
    let b = node(&mut w, &format!(r#"{{"name":"B","mesh":{m},"weights":[0.0,0.25],"skin":0}}"#));
    let joint = node(&mut w, r#"{"name":"joint"}"#);
    w.roots.extend([a, b, joint]);
    GltfWriter::push(&mut w.skins, &format!(r#"{{"joints":[{joint}]}}"#));
    // an animation moving the joint: one key (time 0, translation 0), read from the first view
    let input =
        w.raw_accessor(r#"{"bufferView":0,"componentType":5126,"count":1,"type":"SCALAR","min":[0],"max":[0]}"#);
    let output = w.raw_accessor(r#"{"bufferView":0,"componentType":5126,"count":1,"type":"VEC3"}"#);
    GltfWriter::push(
        &mut w.animations,
        &format!(
            r#"{{"channels":[{{"sampler":0,"target":{{"node":{joint},"path":"translation"}}}}],"samplers":[{{"input":{input},"output":{output}}}]}}"#
        ),
    );
    let d = Dir::new();
    let s = import(&d.gltf("morph", &w));
    let by = |n: &str| s.meshes.iter().find(|m| m.name.starts_with(n)).unwrap();
    // A: mesh weights (0.5, 0): the third vertex moves up by 1, normals tilt towards +X
    let ma = by("A:");
    assert!(close(ma.positions[2], Vec3::new(0.0, 2.0, 0.0)), "{:?}", ma.positions);
    let na = ma.normals.as_ref().unwrap()[0];
    assert!(close(na, Vec3::new(0.5, 0.0, 1.0).normalize()), "{na}");
    // B: node weights (0, 0.25) override: everything lifted by 1 along z, normals untouched
    let mb = by("B:");
    assert!(close(mb.positions[1], Vec3::new(1.0, 0.0, 1.0)), "{:?}", mb.positions);
    assert!(close(mb.normals.as_ref().unwrap()[0], Vec3::Z));
    let warned = |needle: &str| s.warnings.iter().filter(|w| w.contains(needle)).count();
    assert_eq!(warned("the skin is ignored"), 1, "{:?}", s.warnings);
    assert_eq!(warned("COLOR_0"), 0, "{:?}", s.warnings);
    assert_eq!(ma.colors.as_deref(), Some(&[[1.0, 0.0, 0.0]; 3][..]));
    assert!(s.materials[ma.material].textures.pbr.is_some(), "vertex colours make the material per-point");
    assert_eq!(warned("1 animation(s) ignored"), 1, "{:?}", s.warnings);
}

/// COLOR_0 as normalised UNSIGNED_BYTE VEC4 (Blender's export): linear RGB in [0, 1], alpha
/// dropped; a primitive whose colours are all white keeps no colours (nothing to multiply).
#[test]
fn vertex_colours_in_bytes_and_white_ones() {
    let mut w = GltfWriter::new();
    let position = w.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let indices = w.indices(&[0, 1, 2]);
    let bytes = w.raw_bytes_accessor(&[255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0], "VEC4", 5121, true);
    let white = w.raw_bytes_accessor(&[255; 12], "VEC4", 5121, true);
    for (name, c) in [("coloured", bytes), ("white", white)] {
        let mesh = format!(
            r#"{{"name":"{name}","primitives":[{{"attributes":{{"POSITION":{position},"COLOR_0":{c}}},"indices":{indices}}}]}}"#
        );
        let m = GltfWriter::push(&mut w.meshes, &mesh);
        let n = node(&mut w, &format!(r#"{{"name":"{name}","mesh":{m}}}"#));
        w.roots.push(n);
    }
    let d = Dir::new();
    let s = import(&d.gltf("colours", &w));
    let by = |n: &str| s.meshes.iter().find(|m| m.name.starts_with(n)).unwrap();
    assert_eq!(by("coloured:").colors.as_deref(), Some(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]][..]));
    assert_eq!(by("white:").colors, None);
}

/// KHR_materials_clearcoat (issue 50): a factor >= 0.5 puts the base lobe under a coat of IOR
/// 1.5 and GGX alpha = clearcoatRoughnessFactor^2; a smaller factor leaves it uncoated; bad
/// factors and texture indices are errors naming the JSON pointer; the coat's normal map and
/// its scale are read; the extension may be required.
#[test]
fn clearcoat_makes_coated_materials() {
    let ext = |cc: &str| {
        format!(
            r#"{{"name":"paint","pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.1,0.1,1],"metallicFactor":0}},"extensions":{{"KHR_materials_clearcoat":{cc}}}}}"#
        )
    };
    let scene = |cc: &str, required: bool| {
        let mut w = GltfWriter::new();
        w.use_extension("KHR_materials_clearcoat", required);
        let img = w.image(&png(2, 2, |_, _| [128, 140, 255, 255]), "image/png");
        GltfWriter::push(&mut w.textures, &format!("{{\"source\":{img}}}"));
        let m = GltfWriter::push(&mut w.materials, &ext(cc));
        let p = triangle(&mut w, Some(m));
        let mesh = w.mesh("tri", &[p]);
        let n = node(&mut w, &format!("{{\"mesh\":{mesh}}}"));
        w.roots.push(n);
        w
    };
    let d = Dir::new();
    let s = import(&d.gltf("coat", &scene(r#"{"clearcoatFactor":1,"clearcoatRoughnessFactor":0.2}"#, true)));
    match &s.materials[0].material {
        Material::Coated { coating, base, two_sided } => {
            assert!((coating.ior - 1.5).abs() < 1e-6 && (coating.alpha - 0.04).abs() < 1e-6 && *two_sided);
            assert!(matches!(base.as_ref(), Material::Diffuse { .. }));
        }
        m => panic!("{m:?}"),
    }
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let thin = import(&d.gltf("thin", &scene(r#"{"clearcoatFactor":0.3}"#, false)));
    assert!(matches!(thin.materials[0].material, Material::Diffuse { .. }));
    let normal = import(
        &d.gltf("normal", &scene(r#"{"clearcoatFactor":1,"clearcoatNormalTexture":{"index":0,"scale":0.5}}"#, false)),
    );
    let t = &normal.materials[0].textures;
    assert_eq!((t.clearcoat_normal.map(|r| r.texture), t.clearcoat_normal_scale), (Some(0), 0.5));
    assert!(normal.warnings.is_empty(), "{:?}", normal.warnings);
    let (_, e) = import_err(
        &d.gltf("scale", &scene(r#"{"clearcoatFactor":1,"clearcoatNormalTexture":{"index":0,"scale":"x"}}"#, false)),
    );
    assert!(e.contains("/materials/0/extensions/KHR_materials_clearcoat/clearcoatNormalTexture/scale"), "{e}");
    let (_, e) = import_err(&d.gltf("bad", &scene(r#"{"clearcoatFactor":2}"#, false)));
    assert!(
        e.contains("/materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor") && e.contains("[0, 1]"),
        "{e}"
    );
    let (_, e) = import_err(&d.gltf("tex", &scene(r#"{"clearcoatFactor":1,"clearcoatTexture":{"index":7}}"#, false)));
    assert!(e.contains("/materials/0/extensions/KHR_materials_clearcoat/clearcoatTexture/index"), "{e}");
}

/// KHR_materials_sheen (issue 50): a non-black sheen colour puts the base under a sheen of
/// Charlie alpha sheenRoughnessFactor^2; its textures are referenced for per-hit evaluation;
/// bad factors and texture indices are errors at their JSON pointer; under a clear coat the
/// sheen is dropped with a warning.
#[test]
fn sheen_makes_sheen_materials() {
    let scene = |ext: &str| {
        let mut w = GltfWriter::new();
        w.use_extension("KHR_materials_sheen", false);
        w.use_extension("KHR_materials_clearcoat", false);
        let img = w.image(&png(2, 2, |x, _| [255 * x as u8, 128, 0, 64]), "image/png");
        GltfWriter::push(&mut w.textures, &format!("{{\"source\":{img}}}"));
        let m = GltfWriter::push(
            &mut w.materials,
            &format!(
                r#"{{"name":"velvet","pbrMetallicRoughness":{{"baseColorFactor":[0.2,0.05,0.3,1],"metallicFactor":0}},"extensions":{{{ext}}}}}"#
            ),
        );
        let p = triangle(&mut w, Some(m));
        let mesh = w.mesh("tri", &[p]);
        let n = node(&mut w, &format!("{{\"mesh\":{mesh}}}"));
        w.roots.push(n);
        w
    };
    let d = Dir::new();
    let s = import(&d.gltf(
        "sheen",
        &scene(r#""KHR_materials_sheen":{"sheenColorFactor":[1,0.8,0.9],"sheenRoughnessFactor":0.5,"sheenColorTexture":{"index":0},"sheenRoughnessTexture":{"index":0}}"#),
    ));
    match &s.materials[0].material {
        Material::Sheen { alpha, base, .. } => {
            assert!((alpha - 0.25).abs() < 1e-6);
            assert!(matches!(base.as_ref(), Material::Diffuse { .. }));
        }
        m => panic!("{m:?}"),
    }
    // the textures multiply the factors per hit (quasar::core::texture)
    let t = &s.materials[0].textures;
    assert_eq!((t.sheen_color.map(|r| r.texture), t.sheen_roughness.map(|r| r.texture)), (Some(0), Some(0)));
    assert_eq!(t.pbr.map(|p| p.sheen_color), Some([1.0, 0.8, 0.9]));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let (_, e) = import_err(&d.gltf(
        "tex",
        &scene(r#""KHR_materials_sheen":{"sheenColorFactor":[1,1,1],"sheenRoughnessTexture":{"index":3}}"#),
    ));
    assert!(e.contains("/materials/0/extensions/KHR_materials_sheen/sheenRoughnessTexture/index"), "{e}");
    let black = import(&d.gltf("black", &scene(r#""KHR_materials_sheen":{"sheenRoughnessFactor":0.5}"#)));
    assert!(matches!(black.materials[0].material, Material::Diffuse { .. }));
    let (_, e) = import_err(&d.gltf("bad", &scene(r#""KHR_materials_sheen":{"sheenColorFactor":[1,2,0]}"#)));
    assert!(e.contains("/materials/0/extensions/KHR_materials_sheen/sheenColorFactor"), "{e}");
    let both = import(&d.gltf(
        "both",
        &scene(r#""KHR_materials_sheen":{"sheenColorFactor":[1,1,1]},"KHR_materials_clearcoat":{"clearcoatFactor":1}"#),
    ));
    assert!(matches!(both.materials[0].material, Material::Coated { .. }));
    assert!(both.warnings.iter().any(|w| w.contains("sheen under a clear coat")), "{:?}", both.warnings);
}
