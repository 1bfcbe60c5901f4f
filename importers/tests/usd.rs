//! USD import checked against Pixar's own USD: `tests/usd/make_fixtures.py` authored the
//! fixtures with usd-core 26.11 and wrote what Pixar's API computes for them (world-space
//! points after the transform stacks, triangle counts after holes, camera fields, light
//! placement) to `tests/usd/expected.json`; the importer must agree.

use std::path::{Path, PathBuf};

use glam::Vec3;
use quasar_importers::photometric::photometric_scale;
use quasar_importers::{ImportOptions, LightDesc, MeshDesc, SceneDesc, import_scene};
use quasar_materials::Material;
use serde_json::Value;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/usd").join(name)
}

fn expected(file: &str) -> Value {
    let all: Value = serde_json::from_str(&std::fs::read_to_string(fixture("expected.json")).unwrap()).unwrap();
    all.as_array().unwrap().iter().find(|e| e["file"] == file).unwrap().clone()
}

fn import(name: &str) -> SceneDesc {
    import_scene(&fixture(name), &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn v3(v: &Value) -> Vec3 {
    let a = v.as_array().unwrap();
    Vec3::new(a[0].as_f64().unwrap() as f32, a[1].as_f64().unwrap() as f32, a[2].as_f64().unwrap() as f32)
}

/// Pixar's world point `p` in quasar's frame: Z up rotated to Y up, stage units to metres.
fn to_quasar(p: Vec3, z_up: bool, meters_per_unit: f32) -> Vec3 {
    let p = if z_up { Vec3::new(p.x, p.z, -p.y) } else { p };
    p * meters_per_unit
}

fn mesh<'a>(s: &'a SceneDesc, prim: &str) -> &'a MeshDesc {
    s.meshes
        .iter()
        .find(|m| m.name == prim)
        .unwrap_or_else(|| panic!("no mesh {prim} in {:?}", s.meshes.iter().map(|m| &m.name).collect::<Vec<_>>()))
}

/// Every mesh Pixar renders is imported with its world points (as a set: unwelded meshes
/// repeat them), triangle count and bound material (the material prim's path, as Pixar's
/// `ComputeBoundMaterial` gives it), and nothing else; a `materialBind` GeomSubset is a mesh of
/// its own, named by its prim path, with its triangles and material.
fn check_meshes(s: &SceneDesc, exp: &Value) {
    let z_up = exp["up_axis"] == "Z";
    let mpu = exp["meters_per_unit"].as_f64().unwrap() as f32;
    let want = exp["meshes"].as_object().unwrap();
    let material_of = |m: &MeshDesc| s.materials[m.material].source.item.clone().unwrap_or_default();
    let mut expected_parts = 0;
    for (prim, w) in want {
        let mut rest = w["triangles"].as_u64().unwrap();
        let subsets = w.get("subsets").and_then(Value::as_object).cloned().unwrap_or_default();
        for (sub, sw) in &subsets {
            let part = mesh(s, sub);
            let n = sw["triangles"].as_u64().unwrap();
            assert_eq!(part.indices.len() as u64, n, "{sub}");
            assert_eq!(material_of(part), sw["material"].as_str().unwrap(), "{sub}");
            rest -= n;
            expected_parts += 1;
        }
        let m = mesh(s, prim);
        expected_parts += 1;
        assert_eq!(m.indices.len() as u64, rest, "{prim}");
        if let Some(mat) = w["material"].as_str().filter(|m| !m.is_empty()) {
            assert_eq!(material_of(m), mat, "{prim}");
        }
        let pts: Vec<Vec3> =
            w["world_points"].as_array().unwrap().iter().map(|p| to_quasar(v3(p), z_up, mpu)).collect();
        let tol = 1e-5 * pts.iter().map(|p| p.length()).fold(1.0, f32::max);
        for p in &m.positions {
            assert!(pts.iter().any(|q| (*p - *q).length() < tol), "{prim}: {p} is not one of Pixar's {pts:?}");
        }
        for q in &pts {
            assert!(m.positions.iter().any(|p| (*p - *q).length() < tol), "{prim}: Pixar's point {q} is missing");
        }
    }
    let geometry = s.meshes.iter().filter(|m| m.emission.is_none() || want.contains_key(&m.name)).count();
    assert_eq!(geometry, expected_parts, "{:?}", s.meshes.iter().map(|m| &m.name).collect::<Vec<_>>());
}

#[test]
fn scene_meshes_transforms_cameras_and_materials_match_pixar() {
    let s = import("scene.usda");
    let exp = expected("scene.usda");
    check_meshes(&s, &exp);
    // invisible, proxy and inactive prims are not imported
    for skipped in ["/World/Hidden", "/World/Proxy", "/World/Inactive"] {
        assert!(s.meshes.iter().all(|m| m.name != skipped), "{skipped}");
    }
    // camera: position, forward and horizontal field of view as Pixar's Gf.Camera gives them
    let cam = &exp["cameras"]["/World/Cam"];
    assert_eq!(s.cameras.len(), 1);
    let c = &s.camera;
    assert!((c.position - v3(&cam["position"])).length() < 1e-4, "{c:?}");
    assert!(((c.target - c.position).normalize() - v3(&cam["forward"])).length() < 1e-5, "{c:?}");
    assert!((c.fov_deg - cam["horizontal_fov_deg"].as_f64().unwrap() as f32).abs() < 1e-3, "{}", c.fov_deg);
    assert_eq!((s.render.width, s.render.height), (((s.render.height as f32) * 1.5).round() as u32, s.render.height));
    // materials: Red is diffuse-like, Glass a dielectric of IOR 1.5, Lamp an area light
    let material = |prim: &str| &s.materials[mesh(&s, prim).material];
    assert_eq!(material("/World/Quad").name, "Red");
    assert!(matches!(material("/World/Holed").material, Material::Dielectric { .. }), "{:?}", material("/World/Holed"));
    let lamp = mesh(&s, "/World/LeftHanded").emission.as_ref().expect("emissiveColor makes an area light");
    assert!((lamp.scale - photometric_scale(1.0)).abs() < 1e-12);
    // the left-handed triangle faces the other way than its right-handed winding
    let lh = &exp["meshes"]["/World/LeftHanded"]["world_points"];
    let [a, b, c2] = [0, 1, 2].map(|i| v3(&lh[i]));
    let rh_normal = (b - a).cross(c2 - a);
    let m = mesh(&s, "/World/LeftHanded");
    let [p, q, r] = m.indices[0].map(|i| m.positions[i as usize]);
    assert!((q - p).cross(r - p).dot(rh_normal) < 0.0);
    // normals: face-varying, uniform and vertex normals all arrive, transformed (rotY 90: +Z -> +X)
    let quad = mesh(&s, "/World/Quad");
    assert!(quad.normals.as_ref().unwrap().iter().all(|n| (*n - Vec3::X).length() < 1e-5), "{:?}", quad.normals);
    assert_eq!(quad.uvs.as_ref().unwrap().len(), quad.positions.len());
    assert!(mesh(&s, "/World/Reset/Tri").normals.as_ref().unwrap().iter().all(|n| (*n - Vec3::Y).length() < 1e-5));
    assert!(
        s.warnings.iter().any(|w| w.contains("/World/LeftHanded") && w.contains("catmullClark")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn lights_match_pixar_placement_and_photometric_units() {
    let s = import("lights.usda");
    let exp = expected("lights.usda");
    check_meshes(&s, &exp);
    let lights = &exp["lights"];
    let pos = |prim: &str| to_quasar(v3(&lights[prim]["position"]), true, 0.01);
    let dir = |prim: &str| to_quasar(v3(&lights[prim]["axis_minus_z"]), true, 1.0);
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b.abs();
    // treatAsPoint sphere of radius 1 cm, 1000 nits: intensity L pi r^2
    let point = s.lights.iter().find_map(|l| match l {
        LightDesc::Point { position, scale, .. } => Some((*position, *scale)),
        _ => None,
    });
    let (p, i) = point.expect("a point light");
    assert!((p - pos("/L/Point")).length() < 1e-6, "{p}");
    assert!(close(i, photometric_scale(1000.0) * std::f32::consts::PI * 0.01 * 0.01), "{i}");
    // shaped point sphere: a spot with the cone angle and softness
    let spot = s.lights.iter().find_map(|l| match l {
        LightDesc::Spot { cone_deg, falloff_start_deg, direction, .. } => {
            Some((*cone_deg, *falloff_start_deg, *direction))
        }
        _ => None,
    });
    let (cone, start, d) = spot.expect("a spot light");
    assert!((cone - 30.0).abs() < 1e-5 && (start - 15.0).abs() < 1e-5 && (d - dir("/L/Spot")).length() < 1e-5);
    // distant light: illuminance in lux along the prim's -Z
    let sun = s.lights.iter().find_map(|l| match l {
        LightDesc::Directional { direction, scale, .. } => Some((*direction, *scale)),
        _ => None,
    });
    let (d, e) = sun.expect("a directional light");
    assert!((d - dir("/L/Sun")).length() < 1e-5, "{d}");
    assert!(close(e, photometric_scale(2000.0)));
    // dome: constant environment of 0.5 nits
    assert!(s.lights.iter().any(
        |l| matches!(l, LightDesc::Environment { scale, map: None, .. } if close(*scale, photometric_scale(0.5)))
    ));
    // rect: 100 nits x 2^1, 20 x 10 cm, facing the prim's -Z, not normalised
    let rect = mesh(&s, "/L/Rect");
    let e = rect.emission.as_ref().unwrap();
    assert!(close(e.scale, photometric_scale(200.0)) && !e.two_sided);
    let area = rect.area() as f32;
    assert!(close(area, 0.02), "{area}");
    let [a, b, c] = rect.indices[0].map(|i| rect.positions[i as usize]);
    assert!(((b - a).cross(c - a).normalize() - dir("/L/Rect")).length() < 1e-5);
    assert!((rect.positions.iter().sum::<Vec3>() / 4.0 - pos("/L/Rect")).length() < 1e-6);
    // disk: normalised, so luminance / area
    let disk = mesh(&s, "/L/Disk");
    let disk_area = disk.area() as f32;
    assert!(close(disk.emission.as_ref().unwrap().scale, photometric_scale(50.0) / disk_area));
    assert!(s.meshes.iter().any(|m| m.name == "/L/Sphere") && s.meshes.iter().any(|m| m.name == "/L/Cylinder"));
}

#[test]
fn references_payloads_and_variants_compose_like_pixar() {
    let s = import("composed.usdc");
    check_meshes(&s, &expected("composed.usdc"));
}

#[test]
fn bad_files_name_the_file_and_the_prim() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let broken = write("broken.usda", "#usda 1.0\ndef Mesh \"M\" {\n  int[] faceVertexCounts = [3\n}\n");
    let e = import_scene(&broken, &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("broken.usda"), "{e}");
    let bad_index = write(
        "index.usda",
        "#usda 1.0\ndef Mesh \"M\" {\n  point3f[] points = [(0,0,0), (1,0,0), (0,1,0)]\n  int[] faceVertexCounts = [3]\n  int[] faceVertexIndices = [0, 1, 7]\n}\n",
    );
    let e = import_scene(&bad_index, &ImportOptions::default()).unwrap_err().to_string();
    assert!(
        e.contains("index.usda") && e.contains("</M>") && e.contains("faceVertexIndices") && e.contains("7"),
        "{e}"
    );
    let empty = write("empty.usda", "#usda 1.0\ndef Xform \"X\" {\n}\n");
    assert!(import_scene(&empty, &ImportOptions::default()).unwrap_err().to_string().contains("no Mesh"));
}

/// A TOML scene includes a USD stage like a glTF file: `[[override]]` matches the prim path,
/// `[camera] name` picks a USD camera by its prim path.
#[test]
fn toml_scenes_include_usd_with_overrides_and_cameras() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    let usd = fixture("scene.usda");
    std::fs::write(
        &scene,
        format!(
            "[camera]\nname = \"/World/Cam\"\n[materials.copper]\ntype = \"conductor\"\nmetal = \"Cu\"\n\
             [[include]]\nfile = {:?}\n[[override]]\nmatch = \"/World/Qu*\"\nmaterial = \"copper\"\n",
            usd.display().to_string()
        ),
    )
    .unwrap();
    let opts = ImportOptions { allow_external_paths: true, ..Default::default() };
    let s = import_scene(&scene, &opts).unwrap_or_else(|e| panic!("{e}"));
    let quad = s.meshes.iter().find(|m| m.name.ends_with("/World/Quad")).expect("the quad");
    assert_eq!(s.materials[quad.material].name, "copper");
    let holed = s.meshes.iter().find(|m| m.name.ends_with("/World/Holed")).unwrap();
    assert_ne!(s.materials[holed.material].name, "copper");
    assert!((s.camera.position - Vec3::new(21.0, 2.0, 3.0)).length() < 1e-4, "{:?}", s.camera);
}

/// The shipped composed stage `scenes/usd/glass-plate.usda`: the referenced plate asset's
/// meshes under the referencing prim, the variant `finish = "narrow"` giving the top face
/// roughness sqrt(0.02) (GGX alpha 0.02, as Pixar composes it: the asset authors the roughness
/// only inside its variants), Z up rotated to quasar's Y up.
#[test]
fn shipped_composed_stage_applies_its_reference_and_variant() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/usd/glass-plate.usda");
    let s = import_scene(&path, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let top = mesh(&s, "/World/Plate/Top");
    match &s.materials[top.material].material {
        Material::Dielectric { alpha, .. } => assert!((alpha - 0.02).abs() < 1e-6, "alpha {alpha}"),
        m => panic!("top face: {m:?}"),
    }
    // the top face lies 0.021 m above the substrate (quasar +Y)
    assert!(top.positions.iter().all(|p| (p.y - 0.021).abs() < 1e-6), "{:?}", top.positions);
    assert_eq!(s.meshes.len(), 8, "substrate, 6 plate faces, lamp");
}

fn bounds(m: &MeshDesc) -> (Vec3, Vec3) {
    m.positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}

/// `shapes.usda`: every implicit shape spans Pixar's world bounds (each axis, authored and
/// default sizes; the tessellation keeps the true area, so round shapes bulge by < 0.5%), and
/// is closed and outward (positive enclosed volume) except the plane.
#[test]
fn implicit_shapes_match_pixar_bounds() {
    let s = import("shapes.usda");
    let exp = expected("shapes.usda");
    let shapes = exp["shapes"].as_object().unwrap();
    assert!(shapes.len() >= 17);
    for (prim, e) in shapes {
        let m = mesh(&s, prim);
        let (lo, hi) = bounds(m);
        let (want_lo, want_hi) = (v3(&e["min"]), v3(&e["max"]));
        let tol = 5e-3 * (want_hi - want_lo).max_element() + 1e-5;
        assert!(
            (lo - want_lo).abs().max_element() < tol && (hi - want_hi).abs().max_element() < tol,
            "{prim} ({}): bounds {lo}..{hi}, Pixar {want_lo}..{want_hi}",
            e["type"]
        );
        let volume: f32 = m
            .indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                (a - lo).dot((b - lo).cross(c - lo)) / 6.0
            })
            .sum();
        if e["type"] != "Plane" {
            assert!(volume > 0.0, "{prim}: faces inwards (volume {volume})");
        }
    }
    // the plane faces +axis
    let p = mesh(&s, "/World/PlaneX");
    let [a, b, c] = p.indices[0].map(|i| p.positions[i as usize]);
    assert!((b - a).cross(c - a).normalize().dot(Vec3::X) > 0.999);
}

/// `shapes.usda`'s PointInstancer: every visible instance's meshes at Pixar's world points
/// (`ComputeInstanceTransformsAtTime` with the prototype root's transform, the mesh's own below
/// it, the instancer's above), in instance order; the invisible id is skipped and the
/// prototypes are not drawn by themselves.
#[test]
fn point_instancer_instances_match_pixar() {
    let s = import("shapes.usda");
    let exp = expected("shapes.usda");
    let want = exp["instances"].as_array().unwrap();
    let got: Vec<&MeshDesc> = s.meshes.iter().filter(|m| m.name.starts_with("/World/Forest/")).collect();
    assert_eq!(got.len(), want.len(), "{:?}", got.iter().map(|m| &m.name).collect::<Vec<_>>());
    for (m, w) in got.iter().zip(want) {
        assert_eq!(m.name, w["mesh"].as_str().unwrap());
        let pts = w["world_points"].as_array().unwrap();
        assert_eq!(m.positions.len(), pts.len(), "{}", m.name);
        for (p, q) in m.positions.iter().zip(pts) {
            assert!((*p - v3(q)).length() < 1e-4, "{}: {p} vs Pixar {}", m.name, v3(q));
        }
    }
}

/// `--time-code`: the time-sampled translation is read at the earliest sample by default and
/// interpolated at 5.5 as Pixar does.
#[test]
fn time_code_selects_the_time_sample() {
    let exp = expected("shapes.usda");
    for (key, t) in [("earliest", None), ("5.5", Some(5.5))] {
        let opts = ImportOptions { time_code: t, ..Default::default() };
        let s = import_scene(&fixture("shapes.usda"), &opts).unwrap_or_else(|e| panic!("{e}"));
        let p = mesh(&s, "/World/Moving").positions[0];
        let want = v3(&exp["moving"][key]);
        assert!((p - want).length() < 1e-5, "time {key}: {p}, Pixar {want}");
    }
}

/// `textures.usda`: UsdUVTexture inputs become the material's textures: the base colour image
/// Pixar resolves (its file given by the Material's interface input) with its wrap modes and
/// `scale` as the factor, the st transform of UsdTransform2d (in quasar's v-down coordinates),
/// roughness (`r` of one image) and metallic (`g` of another) packed into glTF's G and B
/// channels, the standard-encoded normal map.
#[test]
fn uv_textures_match_pixar_resolution_and_pack_like_gltf() {
    use quasar_importers::texture_desc::TextureWrap;
    let s = import("textures.usda");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let exp = expected("textures.usda");
    let quad = mesh(&s, "/World/Quad");
    let m = &s.materials[quad.material];
    let pbr = m.textures.pbr.expect("textured material");
    let base = m.textures.base_color.expect("base colour texture");
    let albedo = &s.textures[base.texture];
    let e = &exp["textures"]["/World/Looks/Painted/Albedo"];
    assert_eq!(albedo.name, Path::new(e["file"].as_str().unwrap()).file_name().unwrap().to_str().unwrap());
    assert_eq!((albedo.width, albedo.height), (4, 2));
    assert_eq!(albedo.texels[0], [255, 0, 0, 255], "row 0 is the image's top");
    assert_eq!((e["wrapS"].as_str(), e["wrapT"].as_str()), (Some("clamp"), Some("mirror")));
    assert_eq!((albedo.wrap_u, albedo.wrap_v), (TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat));
    assert_eq!(pbr.base_color, [0.5; 3], "scale is the factor");
    // UsdTransform2d: st' = T R S st with S = (2, 1), R = 90 deg, T = (0.5, 0.25), in USD's v-up
    // st; quasar's uv = (s, 1 - t) on both sides
    let usd = |s: f32, t: f32| {
        let (u, v) = (2.0 * s, t);
        (-v + 0.5, u + 0.25)
    };
    for (s0, t0) in [(0.0, 0.0), (1.0, 0.0), (0.25, 0.75)] {
        let (s1, t1) = usd(s0, t0);
        let (u, v) = (s0, 1.0 - t0);
        let tr = base.transform;
        let got = (tr[0][0] * u + tr[0][1] * v + tr[0][2], tr[1][0] * u + tr[1][1] * v + tr[1][2]);
        assert!((got.0 - s1).abs() < 1e-5 && (got.1 - (1.0 - t1)).abs() < 1e-5, "st ({s0}, {t0}): {got:?}");
    }
    // roughness from rough.png's red, metallic from metal.png's green (scale 0.5: the factor)
    let mr = &s.textures[m.textures.metallic_roughness.expect("packed").texture];
    assert_eq!((mr.width, mr.height), (2, 2));
    assert_eq!(mr.texels.iter().map(|t| t[1]).collect::<Vec<_>>(), [200, 100, 50, 0]);
    assert!(mr.texels.iter().all(|t| t[2] == 77));
    assert_eq!(exp["textures"]["/World/Looks/Painted/Metal"]["scale"][1], 0.5);
    assert_eq!((pbr.roughness, pbr.metallic), (1.0, 0.5));
    let n = &s.textures[m.textures.normal.expect("normal map").texture];
    assert_eq!(n.texels[0], [128, 128, 255, 255]);
    assert_eq!(m.textures.normal_scale, 1.0);
}

/// `textures.usdz`: the same stage packaged with its images by Pixar's `UsdUtils`
/// (`CreateNewUsdzPackage`): Pixar resolves every texture to an entry of the package
/// (`textures.usdz[tex/albedo.png]`), and the importer reads those entries to the very texels,
/// materials and triangles the loose `textures.usda` gives.
#[test]
fn usdz_packages_read_their_images_from_the_package() {
    let loose = import("textures.usda");
    let packed = import("textures.usdz");
    assert!(packed.warnings.is_empty(), "{:?}", packed.warnings);
    let exp = expected("textures.usdz");
    for (prim, e) in exp["textures"].as_object().unwrap() {
        let file = e["file"].as_str().unwrap();
        assert!(file.starts_with("textures.usdz[tex/") && file.ends_with(']'), "{prim}: Pixar resolved {file}");
    }
    assert_eq!(packed.textures.len(), loose.textures.len());
    for (p, l) in packed.textures.iter().zip(&loose.textures) {
        assert_eq!((&p.name, p.width, p.height, &p.texels), (&l.name, l.width, l.height, &l.texels));
        assert_eq!((p.wrap_u, p.wrap_v), (l.wrap_u, l.wrap_v));
    }
    let (pm, lm) = (mesh(&packed, "/World/Quad"), mesh(&loose, "/World/Quad"));
    assert_eq!((&pm.positions, &pm.indices), (&lm.positions, &lm.indices));
    let (a, b) = (&packed.materials[pm.material].textures, &loose.materials[lm.material].textures);
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
}

/// A texture file that does not exist is an error naming the stage, the texture prim and the file.
#[test]
fn missing_texture_files_are_errors_naming_the_prim() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(fixture("textures.usda")).unwrap().replace("./tex/rough.png", "./tex/nothing.png");
    let p = dir.path().join("broken.usda");
    std::fs::write(&p, text).unwrap();
    for f in ["albedo.png", "metal.png", "normal.png"] {
        std::fs::create_dir_all(dir.path().join("tex")).unwrap();
        std::fs::copy(fixture("tex").join(f), dir.path().join("tex").join(f)).unwrap();
    }
    let e = import_scene(&p, &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("broken.usda") && e.contains("/World/Looks/Painted/Rough") && e.contains("nothing.png"), "{e}");
}

/// Real stages nobody here wrote: usd-wg/assets `test_assets/foundation/stage_composition`
/// (Apache-2.0, `tests/usd/usd-wg/SOURCE.md`): references, payloads and sublayers across
/// folders (and to missing files), inherits, specializes, overs, active and purpose. Each
/// imports to the gprims Pixar renders (visible, purpose default or render), each within
/// Pixar's world bounds; a stage whose arc points to a missing file still imports what exists,
/// as Pixar's does.
#[test]
fn usd_wg_composition_assets_import_like_pixar() {
    let root = fixture("usd-wg");
    let exp: Value = serde_json::from_str(&std::fs::read_to_string(root.join("expected.json")).unwrap()).unwrap();
    let stages = exp.as_object().unwrap();
    assert!(stages.len() >= 27);
    let mut failures = Vec::new();
    for (file, prims) in stages {
        let s = match import_scene(&root.join(file), &ImportOptions::default()) {
            Ok(s) => s,
            Err(e) => {
                failures.push(format!("{file}: {e}"));
                continue;
            }
        };
        let mut got: Vec<&str> = s.meshes.iter().map(|m| m.name.as_str()).collect();
        got.sort_unstable();
        let want: Vec<&str> = prims.as_object().unwrap().keys().map(String::as_str).collect();
        if got != want {
            failures.push(format!("{file}: meshes {got:?}, Pixar renders {want:?}"));
            continue;
        }
        for (prim, b) in prims.as_object().unwrap() {
            let (lo, hi) = bounds(mesh(&s, prim));
            let (wl, wh) = (v3(&b["min"]), v3(&b["max"]));
            if (lo - wl).abs().max_element() > 1e-5 || (hi - wh).abs().max_element() > 1e-5 {
                failures.push(format!("{file}: {prim}: bounds {lo}..{hi}, Pixar {wl}..{wh}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `DomeLight_1` `poleAxis` (UsdLux: the dome's own starting alignment, "scene" the stage's up
/// axis): pole Z turns the dome by 90 degrees about +X (latitude +pi/2 along +Z, latitude 0 and
/// longitude 0 along -Y), so a Z-up stage's `DomeLight_1` lights quasar's frame as a Y-up stage's
/// `DomeLight` does, pole Y in a Z-up stage as its `DomeLight`, and pole Z in a Y-up stage as a
/// `DomeLight` turned by rotateX 90; an unknown pole axis is an error naming the attribute.
#[test]
fn dome_light_1_pole_axis_sets_the_domes_starting_alignment() {
    let dir = tempfile::tempdir().unwrap();
    exr::prelude::write_rgb_file(dir.path().join("sky.exr"), 8, 4, |x, y| (x as f32, y as f32, 1.0f32)).unwrap();
    let frame = |up: &str, ty: &str, extra: &str| -> Result<glam::Mat3, String> {
        let stage = format!(
            "#usda 1.0\n(\n    metersPerUnit = 1\n    upAxis = \"{up}\"\n)\ndef {ty} \"Sky\"\n{{\n    asset inputs:texture:file = @./sky.exr@\n{extra}}}\n"
        );
        let p = dir.path().join("dome.usda");
        std::fs::write(&p, stage).unwrap();
        let desc = import_scene(&p, &ImportOptions::default()).map_err(|e| e.to_string())?;
        match desc.lights.first() {
            Some(LightDesc::Environment { map: Some(m), .. }) => Ok(m.frame),
            other => panic!("no textured environment: {other:?}"),
        }
    };
    let close = |a: glam::Mat3, b: glam::Mat3, what: &str| {
        assert!((a - b).to_cols_array().iter().all(|d| d.abs() < 1e-5), "{what}: {a} vs {b}");
    };
    let y_up_dome = frame("Y", "DomeLight", "").unwrap();
    close(frame("Z", "DomeLight_1", "").unwrap(), y_up_dome, "scene pole in a Z-up stage");
    close(frame("Y", "DomeLight_1", "").unwrap(), y_up_dome, "scene pole in a Y-up stage");
    close(
        frame("Z", "DomeLight_1", "    uniform token poleAxis = \"Y\"\n").unwrap(),
        frame("Z", "DomeLight", "").unwrap(),
        "pole Y in a Z-up stage",
    );
    let turned = "    float xformOp:rotateX = 90\n    uniform token[] xformOpOrder = [\"xformOp:rotateX\"]\n";
    close(
        frame("Y", "DomeLight_1", "    uniform token poleAxis = \"Z\"\n").unwrap(),
        frame("Y", "DomeLight", turned).unwrap(),
        "pole Z in a Y-up stage",
    );
    // the old DomeLight of a Z-up stage keeps its pole on the stage's +Y: tilted in quasar's frame
    let old = frame("Z", "DomeLight", "").unwrap();
    assert!((old.y_axis - Vec3::NEG_Z).length() < 1e-5, "{old}");
    let e = frame("Y", "DomeLight_1", "    uniform token poleAxis = \"X\"\n").unwrap_err();
    assert!(e.contains("poleAxis") && e.contains("/Sky"), "{e}");
}

/// Whole numbers written as integer literals, as Python and `usdcat` write them in time samples
/// (`float inputs:intensity.timeSamples = { 0: 10 }`, `color3f ... = { 0: (1, 1, 1) }`), read
/// as the declared float, as Pixar's USD does (issue 51: "expected a number, got Int64(10)").
#[test]
fn integer_literals_of_float_attributes_are_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let stage = |intensity: &str, colour: &str| {
        let text = format!(
            "#usda 1.0\n(\n    metersPerUnit = 1\n    upAxis = \"Y\"\n)\ndef Mesh \"M\" {{\n    point3f[] points = [(0,0,0), (1,0,0), (0,1,0)]\n    int[] faceVertexCounts = [3]\n    int[] faceVertexIndices = [0, 1, 2]\n}}\ndef SphereLight \"L\" {{\n    float inputs:intensity.timeSamples = {{ 0: {intensity} }}\n    color3f inputs:color.timeSamples = {{ 0: {colour} }}\n    float inputs:radius = 0.1\n}}\n"
        );
        let p = dir.path().join("lamp.usda");
        std::fs::write(&p, text).unwrap();
        let s = import_scene(&p, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let lamp = s.meshes.iter().find(|m| m.emission.is_some()).expect("the sphere light");
        let e = lamp.emission.clone().unwrap();
        (e.scale, e.spectrum.luminance())
    };
    assert_eq!(stage("10", "(1, 1, 1)"), stage("10.0", "(1.0, 1.0, 1.0)"));
}

/// A stage with native instancing imports to the same meshes as its flattened binary copy, and
/// to what Pixar draws from both (issue 51: the flattened `.usdc` gave the prototypes' meshes
/// once more, because its root `over` prim leaves the specifier unauthored).
#[test]
fn a_flattened_instanced_stage_imports_like_the_original() {
    let exp = expected("instanced.usda");
    let summary = |name: &str| {
        let s = import(name);
        let mut meshes: Vec<(String, usize)> = s.meshes.iter().map(|m| (m.name.clone(), m.indices.len())).collect();
        meshes.sort();
        meshes
    };
    let (usda, usdc) = (summary("instanced.usda"), summary("instanced_flat.usdc"));
    for (name, got) in [("instanced.usda", &usda), ("instanced_flat.usdc", &usdc)] {
        let want = &exp["drawn"][name];
        assert_eq!(got.len() as u64, want["meshes"].as_u64().unwrap(), "{name}: {got:?}");
        let tris: usize = got.iter().map(|m| m.1).sum();
        assert_eq!(tris as u64, want["triangles"].as_u64().unwrap(), "{name}: {got:?}");
    }
    let tris = |v: &[(String, usize)]| v.iter().map(|m| m.1).collect::<Vec<_>>();
    assert_eq!(tris(&usda), tris(&usdc));
}

/// The import says what it drew and skipped, with the reasons, and the time code it read, for
/// `quasar info` (issue 51, item 4).
#[test]
fn the_import_summary_counts_prims_drawn_and_skipped() {
    let s = import("scene.usda");
    let text = s.import_summary.join("\n");
    assert!(
        text.contains("1 inactive") && text.contains("1 invisible") && text.contains("1 purpose proxy or guide"),
        "{text}"
    );
    // as many as Pixar's traversal renders
    let pixar = expected("scene.usda")["meshes"].as_object().unwrap().len();
    assert!(text.contains(&format!("{pixar} meshes or shapes drawn")), "{text}");
    assert!(text.contains("USD time code: the earliest time sample"), "{text}");
    let flat = import("instanced_flat.usdc").import_summary.join("\n");
    assert!(flat.contains("1 not defined (an `over` or `class`)"), "{flat}");
}

/// Composition arcs besides references and payloads (issue 51, item 3), as Pixar composes them:
/// a class prim inherited by two prims (its child mesh drawn under each, a local opinion over
/// the inherited points in one), a prim specializing a class, and an animated asset referenced
/// with a layer offset (offset 10, scale 2) read at time code 30, the asset's time 10; the
/// classes themselves are not drawn.
#[test]
fn inherits_specializes_and_layer_offsets_compose_as_pixar_does() {
    let opts = ImportOptions { time_code: Some(30.0), ..Default::default() };
    let s = import_scene(&fixture("arcs.usda"), &opts).unwrap_or_else(|e| panic!("{e}"));
    check_meshes(&s, &expected("arcs.usda"));
}

/// Material bindings resolved as Pixar's `ComputeBoundMaterial` does for the render (`full`)
/// purpose (issue 51, item 3): a parent's strongerThanDescendants binding wins over its child's,
/// a full-purpose binding over an all-purpose one, a preview-purpose binding is not the render's,
/// and a collection binding reaches the meshes in the collection only (members with and without
/// MaterialBindingAPI, one below an included Xform), loses to a member's own direct binding and
/// beats its owner's direct binding, which a non-member gets.
#[test]
fn material_bindings_resolve_as_pixar_does_for_rendering() {
    check_meshes(&import("bindings.usda"), &expected("bindings.usda"));
}

/// A CAD-style camera (issue 51, item 3): a stage in millimetres with Z up, a 35 mm lens on a
/// 36 x 24 mm back, placed by a translation and a rotateXYZ: quasar's camera sits at Pixar's
/// position and looks along Pixar's forward with Pixar's up (turned to Y up and scaled to
/// metres), with Pixar's field of view and the back's aspect.
#[test]
fn millimetre_z_up_cameras_match_pixar() {
    let s = import("camera_mm.usda");
    let exp = expected("camera_mm.usda");
    check_meshes(&s, &exp);
    let cam = &exp["cameras"]["/World/Cam"];
    let c = &s.camera;
    let want = to_quasar(v3(&cam["position"]), true, 0.001);
    assert!((c.position - want).length() < 1e-5, "{c:?} vs {want}");
    let forward = to_quasar(v3(&cam["forward"]), true, 1.0);
    assert!(((c.target - c.position).normalize() - forward).length() < 1e-5, "{c:?} vs {forward}");
    assert!((c.fov_deg - cam["horizontal_fov_deg"].as_f64().unwrap() as f32).abs() < 1e-3, "{}", c.fov_deg);
    // no roll: the image's up is the camera's +Y
    let up = to_quasar(v3(&cam["up"]), true, 1.0);
    let image_up = c.up - c.up.dot(forward) * forward;
    assert!((image_up.normalize() - up).length() < 1e-4, "{c:?} vs up {up}");
    assert_eq!(s.render.width * 2, s.render.height * 3);
}

/// `MeshLightAPI` (issue 51, item 3): a mesh with it is drawn as Pixar draws it and is an area
/// light of its own shape, of luminance `intensity` x 2^`exposure` nits in its `color`, divided
/// by its area with `normalize` (5 x 2 / 2 m^2 here); the plain mesh beside it emits nothing.
#[test]
fn mesh_lights_emit_from_their_mesh() {
    let s = import("meshlight.usda");
    check_meshes(&s, &expected("meshlight.usda"));
    let e = mesh(&s, "/World/Panel").emission.as_ref().expect("the MeshLightAPI mesh emits");
    assert!((e.scale - photometric_scale(10.0) / 2.0).abs() < 1e-6 * e.scale, "{}", e.scale);
    assert!(!e.two_sided);
    let orange = quasar_materials::spectrum::Spectrum::rgb_illuminant([1.0, 0.5, 0.25]).unwrap();
    assert_eq!(e.spectrum, orange);
    assert!(mesh(&s, "/World/Plain").emission.is_none());
}

/// A tetrahedron bound to a UsdPreviewSurface glass whose Material prim carries the medium
/// attributes `MEDIUM`.
fn medium_stage(medium: &str) -> String {
    format!(
        r#"#usda 1.0
(
    metersPerUnit = 1
)
def Xform "W"
{{
    def Material "Milk"
    {{
        {medium}
        token outputs:surface.connect = </W/Milk/S.outputs:surface>
        def Shader "S"
        {{
            uniform token info:id = "UsdPreviewSurface"
            float inputs:opacity = 0
            float inputs:ior = 1.4
            token outputs:surface
        }}
    }}
    def Mesh "M" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {{
        uniform token subdivisionScheme = "none"
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
        int[] faceVertexCounts = [3, 3, 3, 3]
        int[] faceVertexIndices = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]
        rel material:binding = </W/Milk>
    }}
}}
"#
    )
}

/// The medium of a USD material (docs/usd.md): `quasar:absorption`, or
/// `quasar:internalTransmittance` at `quasar:thickness` (metres), and `quasar:scattering` with
/// `quasar:phaseG`, read from the Material prim; contradictory or invalid values are errors
/// naming the prim and the attribute.
#[test]
fn material_prims_carry_their_medium() {
    let dir = tempfile::tempdir().unwrap();
    let load = |medium: &str| {
        let p = dir.path().join("medium.usda");
        std::fs::write(&p, medium_stage(medium)).unwrap();
        import_scene(&p, &ImportOptions::default())
    };
    let s =
        load("float quasar:absorption = 2.5\n        float quasar:scattering = 40\n        float quasar:phaseG = 0.7")
            .unwrap();
    let m = s.materials.iter().find(|m| m.name == "Milk").unwrap();
    assert_eq!(
        m.absorption,
        Some(quasar_materials::Absorption::Coefficient(quasar_materials::spectrum::Spectrum::Constant(2.5)))
    );
    let sc = m.scattering.as_ref().unwrap();
    assert_eq!((sc.coefficient.value(550.0), sc.g), (40.0, 0.7));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let s =
        load("color3f quasar:internalTransmittance = (0.5, 0.5, 0.5)\n        float quasar:thickness = 0.01").unwrap();
    let Some(quasar_materials::Absorption::Transmittance { thickness, .. }) = &s.materials[0].absorption else {
        panic!("{:?}", s.materials[0].absorption)
    };
    assert_eq!(*thickness, 0.01);
    assert!(load("").unwrap().materials[0].absorption.is_none());
    for (bad, wants) in [
        ("float quasar:phaseG = 0.5", "quasar:phaseG"),
        ("float quasar:scattering = 10\n        float quasar:phaseG = 2", "phase_g"),
        ("float quasar:absorption = 1\n        float quasar:thickness = 0.01", "not both"),
        ("float quasar:thickness = 0.01", "go together"),
        ("float quasar:absorption = -1", "absorption"),
    ] {
        let e = load(bad).unwrap_err().to_string();
        assert!(e.contains("medium.usda") && e.contains("</W/Milk>") && e.contains(wants), "{bad:?}: {e}");
    }
    // docs/usd.md lists every attribute read
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/usd.md")).unwrap();
    for attr in
        ["quasar:absorption", "quasar:internalTransmittance", "quasar:thickness", "quasar:scattering", "quasar:phaseG"]
    {
        assert!(doc.contains(&format!("`{attr}`")) || doc.contains(&format!(" {attr}`")), "docs/usd.md lacks {attr}");
    }
}

/// UsdPreviewSurface `clearcoat` >= 0.5 coats the surface (issue 50), with GGX alpha =
/// `clearcoatRoughness`²; the schema's defaults (no coat) leave it a diffuse.
#[test]
fn preview_surface_clearcoat_makes_a_coated_material() {
    let stage = |coat: &str| {
        format!(
            r#"#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Y"
)
def Material "Paint"
{{
    token outputs:surface.connect = </Paint/Surface.outputs:surface>
    def Shader "Surface"
    {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.6, 0.05, 0.04)
        {coat}
        token outputs:surface
    }}
}}
def Mesh "Panel" (
    prepend apiSchemas = ["MaterialBindingAPI"]
)
{{
    int[] faceVertexCounts = [3]
    int[] faceVertexIndices = [0, 1, 2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    rel material:binding = </Paint>
}}
"#
        )
    };
    let dir = tempfile::tempdir().unwrap();
    let read = |name: &str, coat: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, stage(coat)).unwrap();
        quasar_importers::import_scene(&path, &Default::default()).unwrap()
    };
    let s = read("coat.usda", "float inputs:clearcoat = 1\n        float inputs:clearcoatRoughness = 0.3");
    match &s.materials[s.meshes[0].material].material {
        quasar_materials::Material::Coated { coating, base, .. } => {
            assert!((coating.alpha - 0.09).abs() < 1e-6 && (coating.ior - 1.5).abs() < 1e-6);
            assert!(matches!(base.as_ref(), quasar_materials::Material::Diffuse { .. }));
        }
        m => panic!("{m:?}"),
    }
    let plain = read("plain.usda", "");
    assert!(matches!(plain.materials[plain.meshes[0].material].material, quasar_materials::Material::Diffuse { .. }));
}
