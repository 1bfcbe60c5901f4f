//! OBJ/MTL import: meshes, normals, the MTL -> material mapping, emission, and malformed input
//! reported with file and line.

mod common;

use common::{Files, assert_at};
use glam::Vec3;
use quasar_importers::{ImportErrorKind, ImportOptions, ObjMaterials, SceneDesc, import_obj, import_scene};
use quasar_materials::spectrum::Spectrum;
use quasar_materials::{ConductorFresnel, Ior, Material};

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

fn obj(files: &[(&str, &str)]) -> (Files, Result<SceneDesc, quasar_importers::ImportError>) {
    let f = Files::new();
    for (n, t) in files {
        f.write(n, t);
    }
    let r = f.import(files[0].0);
    (f, r)
}

fn ok(files: &[(&str, &str)]) -> SceneDesc {
    obj(files).1.unwrap_or_else(|e| panic!("{e}"))
}

fn err(files: &[(&str, &str)]) -> String {
    match obj(files).1 {
        Ok(_) => panic!("should fail: {files:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn obj_without_mtl_gets_default_grey() {
    let s = ok(&[("tri.obj", TRI)]);
    assert_eq!(s.meshes.len(), 1);
    let m = &s.meshes[0];
    assert_eq!(m.name, "tri.obj:unnamed_object:default");
    assert_eq!(m.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(m.indices, vec![[0, 1, 2]]);
    assert!(m.normals.is_none());
    assert!(m.emission.is_none());
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.materials[0].material, Material::Diffuse { reflectance: Spectrum::Constant(0.8), two_sided: true });
    assert!(s.lights.is_empty());
    // usemtl without any mtllib: grey, but the name is kept
    let s = ok(&[("tri.obj", &format!("o Thing\nusemtl paint\n{TRI}"))]);
    assert_eq!(s.meshes[0].name, "tri.obj:Thing:paint");
    assert_eq!(s.materials[0].name, "paint");
}

#[test]
fn polygons_negative_indices_and_normals() {
    let text = "o Quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 2\nf -4//-1 -3//-1 -2//-1 -1//-1\n\
                o Mixed\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 5//1 6 7\n\
                o Pentagon\nf 1 2 3 4 5\n";
    let s = ok(&[("q.obj", text)]);
    assert_eq!(s.meshes.len(), 3);
    let q = &s.meshes[0];
    assert_eq!(q.name, "q.obj:Quad:default");
    assert_eq!(q.indices.len(), 2);
    assert_eq!(q.positions.len(), 4);
    assert!(q.normals.as_ref().unwrap().iter().all(|n| *n == Vec3::Z), "vn used and normalised");
    assert!(s.meshes[1].normals.is_none(), "vertices without vn: flat");
    assert_eq!(s.meshes[2].indices.len(), 3);
    // all meshes share the one default material
    assert_eq!(s.materials.len(), 1);
}

#[test]
fn units_scale_applies_to_obj() {
    let f = Files::new();
    let p = f.write("tri.obj", TRI);
    let s = import_scene(&p, &ImportOptions { units_scale: Some(0.01), ..Default::default() }).unwrap();
    assert_eq!(s.meshes[0].positions[1], Vec3::new(0.01, 0.0, 0.0));
}

const MTL: &str = "# materials
newmtl paint
Kd 0.6 0.5 0.4
Ks 0.5 0.5 0.5
Ns 250

newmtl chrome
Kd 0 0 0
Ks 0.9 0.9 0.9
Ns 98

newmtl mirror
Ks 0.95
illum 3

newmtl glass
Kd 0.1 0.1 0.1
Ni 1.52
d 0.2
Ns 1000

newmtl glass2
illum 7

newmtl tr_glass
Tr 0.5
Tf 0.2 0.8 0.4

newmtl lamp
Kd 0.2 0.2 0.2
Ke 4 3 2

newmtl empty
";

fn mtl_scene() -> SceneDesc {
    let mut o = String::from("mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for name in ["paint", "chrome", "mirror", "glass", "glass2", "tr_glass", "lamp", "empty"] {
        o.push_str(&format!("o {name}_obj\nusemtl {name}\nf 1 2 3\n"));
    }
    ok(&[("scene.obj", &o), ("lib.mtl", MTL)])
}

#[test]
fn mtl_mapping() {
    let s = mtl_scene();
    let mat = |n: &str| &s.materials.iter().find(|m| m.name == n).unwrap().material;
    assert_eq!(
        mat("paint"),
        &Material::Diffuse { reflectance: Spectrum::rgb_reflectance([0.6, 0.5, 0.4]).unwrap(), two_sided: true },
        "Kd + Ks blend keeps the dominant diffuse lobe"
    );
    match mat("chrome") {
        Material::Conductor { alpha, fresnel: ConductorFresnel::Constant(r), two_sided: true } => {
            assert!((alpha - (2.0f32 / 100.0).sqrt()).abs() < 1e-6, "alpha = sqrt(2/(Ns+2))");
            assert_eq!(r, &Spectrum::rgb_reflectance([0.9, 0.9, 0.9]).unwrap());
        }
        m => panic!("{m:?}"),
    }
    assert!(
        matches!(mat("mirror"), Material::Conductor { alpha, .. } if *alpha == 0.0),
        "no Ns: smooth; one-value Ks expands to grey"
    );
    assert_eq!(mat("glass"), &Material::Dielectric { ior: Ior::Constant(1.52), alpha: 0.0, transmittance: None });
    assert_eq!(mat("glass2"), &Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.0, transmittance: None });
    // `Tf` tints the transmitted light (issue 52's coloured glass, for MTL)
    let tint = Some(Spectrum::rgb_reflectance([0.2, 0.8, 0.4]).unwrap());
    assert_eq!(mat("tr_glass"), &Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.0, transmittance: tint });
    assert_eq!(
        mat("empty"),
        &Material::Diffuse { reflectance: Spectrum::rgb_reflectance([0.8; 3]).unwrap(), two_sided: true }
    );
    let lamp = s.meshes.iter().find(|m| m.name == "scene.obj:lamp_obj:lamp").unwrap();
    let e = lamp.emission.as_ref().unwrap();
    assert_eq!((e.scale, e.two_sided), (1.0, false));
    assert!(matches!(e.spectrum, Spectrum::RgbIlluminant { rgb, .. } if rgb == [4.0, 3.0, 2.0]));
    assert!(s.meshes.iter().filter(|m| m.emission.is_some()).count() == 1);
    // materials record where they were defined
    let glass = s.materials.iter().find(|m| m.name == "glass").unwrap();
    assert!(glass.source.file.ends_with("lib.mtl"));
    assert_eq!(glass.source.line, Some(16));
}

#[test]
fn several_material_libraries_and_materials_per_object() {
    let o = "mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\no Box\nusemtl red\nf 1 2 3\nusemtl blue\nf 2 4 3\nusemtl red\nf 1 3 2\n";
    let s = ok(&[("m.obj", o), ("a.mtl", "newmtl red\nKd 1 0 0\n"), ("b.mtl", "newmtl blue\nKd 0 0 1\n")]);
    let names: Vec<&str> = s.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["m.obj:Box:red", "m.obj:Box:blue", "m.obj:Box:red"]);
    assert_eq!(s.materials.len(), 2);
    assert_eq!(s.meshes[0].material, s.meshes[2].material);
    // a library file name with a space
    let o = "mtllib my lib.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let s = ok(&[("m.obj", o), ("my lib.mtl", "newmtl red\nKd 1 0 0\n")]);
    assert_eq!(s.materials[0].name, "red");
}

#[test]
fn names_only_mode_skips_libraries() {
    let f = Files::new();
    let p = f.write("m.obj", &format!("mtllib missing.mtl\nusemtl red\n{TRI}"));
    let s = import_obj(&p, &ImportOptions::default(), ObjMaterials::NamesOnly).unwrap();
    assert_eq!(s.materials[0].name, "red");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // reading the libraries, the missing one is a warning
    let s = import_obj(&p, &ImportOptions::default(), ObjMaterials::FromMtl).unwrap();
    assert!(s.warnings.iter().any(|w| w.contains("`missing.mtl` not found")), "{:?}", s.warnings);
}

#[test]
fn malformed_obj_names_file_and_line() {
    for (text, line, needle) in [
        ("v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n", 3, "`zero` is not a number"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", 4, "out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4, "out of range"),
        ("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", 2, "not a finite number"),
        ("v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n", 2, "not a finite number"),
        ("v 0 0 0\nv 1 0 1e39\nv 0 1 0\nf 1 2 3\n", 2, "not a finite number"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\n\n# c\nf 1 2\n", 6, "at least 3"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//2 2//1 3//1\n", 5, "normal index 2 is out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n", 4, "not an integer"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl\nf 1 2 3\n", 4, "needs a material name"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0\nf 1 2 3\n", 4, "`vn` expects 3"),
        ("v 0 0 0\nv 1 0 0 0\nv 0 1 0\nf 1 2 3\n", 2, "weight"),
    ] {
        let e = err(&[("bad.obj", text)]);
        assert_at(&format!("{e}:"), "bad.obj", line, &[needle]);
    }
    let e = err(&[("empty.obj", "# nothing\nv 0 0 0\n")]);
    assert!(e.contains("empty.obj: OBJ file has no faces"), "{e}");
}

#[test]
fn mtl_problems_name_the_right_file_and_line() {
    let o = |lib: &str, mat: &str| format!("\nmtllib {lib}\nusemtl {mat}\n{TRI}");
    // missing library: a warning naming the mtllib line of the OBJ, and grey materials (issue
    // 52: it was fatal, where Blender and tinyobjloader warn)
    let d = ok(&[("m.obj", &o("nope.mtl", "a"))]);
    let w = d.warnings.join("\n");
    assert!(w.contains("m.obj:2: material library `nope.mtl` not found") && w.contains("grey diffuse"), "{w}");
    assert_eq!(d.materials.len(), 1);
    assert!(matches!(d.materials[0].material, quasar_materials::Material::Diffuse { .. }), "{:?}", d.materials[0]);
    // unknown material: the usemtl line, with a suggestion
    let e = err(&[("m.obj", &o("a.mtl", "rde")), ("a.mtl", "newmtl red\nKd 1 0 0\n")]);
    assert_at(&e, "m.obj", 3, &["material `rde` is not defined", "a.mtl", "did you mean `red`?"]);
    // malformed MTL statement
    let e = err(&[("m.obj", &o("a.mtl", "red")), ("a.mtl", "newmtl red\n\nKd 1 0\n")]);
    assert_at(&e, "a.mtl", 3, &["`Kd` expects r g b", "(included from", "m.obj:2"]);
    let e = err(&[("m.obj", &o("a.mtl", "red")), ("a.mtl", "newmtl red\nNs abc\n")]);
    assert_at(&e, "a.mtl", 2, &["`abc` is not a number"]);
    // invalid values: the line of the key
    let e = err(&[("m.obj", &o("a.mtl", "red")), ("a.mtl", "newmtl red\nKd 1.5 0 0\n")]);
    assert_at(&e, "a.mtl", 2, &["material `red`", "Kd", "[0, 1]"]);
    let e = err(&[("m.obj", &o("a.mtl", "red")), ("a.mtl", "newmtl red\nKd 0.5 0.5 0.5\nKe -1 0 0\n")]);
    assert_at(&e, "a.mtl", 3, &["Ke"]);
    let e = err(&[("m.obj", &o("a.mtl", "red")), ("a.mtl", "newmtl red\nNs -3\n")]);
    assert_at(&e, "a.mtl", 2, &["Ns"]);
    let e = err(&[("m.obj", &o("a.mtl", "red")), ("a.mtl", "newmtl red\nKd spectral r.rfl\n")]);
    assert_at(&e, "a.mtl", 2, &["not supported"]);
    // textures are ignored, whatever their options
    let s =
        ok(&[("m.obj", &o("a.mtl", "red")), ("a.mtl", "newmtl red\nKd 1 0 0\nmap_Kd -s 1 1 1 tex.png\nmap_d\nbump\n")]);
    assert_eq!(s.materials.len(), 1);
}

#[test]
fn oversized_files_are_refused_before_reading() {
    let f = Files::new();
    let p = f.path("huge.obj");
    let file = std::fs::File::create(&p).unwrap();
    // sparse: no disk space is used
    if file.set_len(quasar_importers::MAX_OBJ_BYTES + 1).is_err() {
        return;
    }
    let e = import_scene(&p, &ImportOptions::default()).unwrap_err();
    assert_eq!(e.kind, ImportErrorKind::TooLarge);
    assert!(e.to_string().contains("huge.obj"), "{e}");
}

#[test]
fn binary_garbage_is_an_error_with_a_line() {
    let f = Files::new();
    let p = f.path("g.obj");
    std::fs::write(&p, b"v 0 0 0\nv 1 0 0\n\xff\xd8\xff\xe0 JFIF\n").unwrap();
    let e = import_scene(&p, &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("g.obj:3: line is not valid UTF-8"), "{e}");
}

#[test]
fn byte_order_marks_are_skipped() {
    let o = format!("\u{feff}mtllib a.mtl\nusemtl red\n{TRI}");
    let s = ok(&[("m.obj", &o), ("a.mtl", "\u{feff}newmtl red\nKd 1 0 0\n")]);
    assert_eq!(s.meshes[0].positions.len(), 3);
    assert_eq!(
        s.materials[0].material,
        Material::Diffuse { reflectance: Spectrum::rgb_reflectance([1.0, 0.0, 0.0]).unwrap(), two_sided: true }
    );
}

/// Trailing `#` comments, as in Morgan McGuire's CornellBox-Original.mtl (`Ka 0.63 0.065 0.05
/// # Red`) and CAD exports (`v 1 2 3 # comment`), are accepted in OBJ and MTL statements; a `#`
/// inside a word (a material name) is kept (issue 18).
#[test]
fn trailing_comments_are_accepted() {
    let obj_text = "mtllib m.mtl # the library\n\
                    v 0 0 0 # origin\nv 1 0 0\t# x\nv 0 1 0 #y\nvn 0 0 1 # up\n\
                    usemtl red # the red one\nf 1//1 2//1 3//1 # a triangle\n\
                    usemtl paint#2\nf 1 2 3\n";
    let mtl_text = "newmtl red # wall\nKd 0.63 0.065 0.05 # Red\nKa 0 0 0 #\n\
                    newmtl paint#2\nKd 0.5 0.5 0.5\n";
    let s = ok(&[("c.obj", obj_text), ("m.mtl", mtl_text)]);
    assert_eq!(s.meshes.len(), 2);
    assert_eq!(s.meshes[0].positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(s.meshes[0].normals.as_deref(), Some(&[Vec3::Z; 3][..]));
    let names: Vec<&str> = s.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["red", "paint#2"]);
    let Material::Diffuse { reflectance: Spectrum::RgbReflectance(r), .. } = &s.materials[0].material else {
        panic!("{:?}", s.materials[0].material)
    };
    assert_eq!(r.rgb, [0.63, 0.065, 0.05]);
    // a comment is not a value: a vertex with two coordinates and a comment is still an error
    assert!(err(&[("bad.obj", "v 1 2 # 3\n")]).contains("bad.obj:1"));
}

/// Statements the importer does not use are named in one warning per keyword with the first line
/// and the count (an OBJ line `hello world` was silently accepted; issue 18); grouping and
/// smoothing statements stay silent.
#[test]
fn ignored_statements_are_warned_about() {
    let text = format!("hello world\no thing\ng group\ns 1\n{TRI}hello again\ncurv 0 1 1 2\nusemap none\n");
    let s = ok(&[("w.obj", &text)]);
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(s.warnings.len(), 3, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("w.obj:1: statement `hello` ignored (not an OBJ keyword; 2 such statements"));
    assert!(s.warnings[1].contains("w.obj:10: statement `curv` ignored (free-form geometry"));
    assert!(s.warnings[2].contains("w.obj:11: statement `usemap`"));
    assert!(ok(&[("t.obj", TRI)]).warnings.is_empty());
}

/// OBJ files have no camera: the importer frames the model, through the opening of an open box
/// (issue 18: McGuire's Cornell box rendered edge-on from the fixed default camera). The two
/// shipped Cornell models are open at -Z (millimetres, the Cornell data's orientation) and at +Z.
#[test]
fn obj_models_get_a_framing_camera_on_their_open_side() {
    let models = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/models/");
    for (file, side) in [("cornell-box-mm.obj", -1.0f32), ("cornell-box-original.obj", 1.0)] {
        let s = import_scene(std::path::Path::new(&format!("{models}{file}")), &ImportOptions::default()).unwrap();
        let (lo, hi) = s
            .meshes
            .iter()
            .flat_map(|m| &m.positions)
            .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let c = &s.camera;
        assert!((c.target - 0.5 * (lo + hi)).length() < 1e-3 * (hi - lo).length(), "{file}: {c:?}");
        let rel = c.position - c.target;
        assert!(rel.z * side > 0.0 && rel.x.abs() < 1e-3 * rel.length(), "{file}: looks from {rel}");
        // the whole box is in view: the camera is outside its bounding sphere
        assert!(rel.length() > 0.5 * (hi - lo).length(), "{file}");
        assert!(s.warnings.is_empty(), "{file}: {:?}", s.warnings);
    }
}
