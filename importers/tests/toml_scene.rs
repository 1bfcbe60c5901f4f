//! The TOML scene format: every supported feature imports to the expected `SceneDesc`.

mod common;

use common::{BASE, Files, ok};
use glam::Vec3;
use quasar_importers::{
    FovAxis, ImportOptions, LightDesc, MeshDesc, ParamValue, RenderSettings, SceneDesc, import_scene, parse_toml_scene,
};
use quasar_materials::spectrum::{Spectrum, StandardIlluminant};
use quasar_materials::{ConductorFresnel, Ior, Material};

/// The value of `[render]` key `key` as the importer kept it.
fn param<'a>(r: &'a RenderSettings, key: &str) -> Option<&'a ParamValue> {
    r.params.iter().find(|p| p.key == key).map(|p| &p.value)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() <= 1e-5 * (1.0 + b.length())
}

fn bounds(m: &MeshDesc) -> (Vec3, Vec3) {
    m.positions.iter().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}

fn geometric_normals(m: &MeshDesc) -> Vec<Vec3> {
    m.indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            (b - a).cross(c - a).normalize()
        })
        .collect()
}

fn material<'a>(s: &'a SceneDesc, name: &str) -> &'a Material {
    &s.materials.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("no material {name}")).material
}

fn mesh<'a>(s: &'a SceneDesc, name: &str) -> &'a MeshDesc {
    s.meshes.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("no mesh {name}: {:?}", names(s)))
}

fn names(s: &SceneDesc) -> Vec<&str> {
    s.meshes.iter().map(|m| m.name.as_str()).collect()
}

#[test]
fn render_and_camera_settings() {
    let s = ok(
        &format!(
            r#"
[render]
width = 320
height = 200
spp = 16
time = 2.5
seed = 42
max_depth = 7
method = "pt"
{}
"#,
            BASE.replace("fov_deg = 40", "fov_deg = 55\nfov_axis = \"x\"\nup = [0, 0, 1]")
                .replace("position = [0, 0, 5]", "position = [0, 5, 0]")
        ),
        &[],
    );
    let r = &s.render;
    assert_eq!((r.width, r.height, r.spp, r.time_s, r.seed), (320, 200, 16, Some(2.5), 42));
    assert_eq!(param(r, "max_depth"), Some(&ParamValue::Int(7)));
    assert_eq!(r.method, "pt");
    assert_eq!(s.camera.fov_deg, 55.0);
    assert_eq!(s.camera.fov_axis, FovAxis::X);
    assert_eq!(s.camera.up, Vec3::Z);
    assert_eq!(s.camera.position, Vec3::new(0.0, 5.0, 0.0));
    assert!(s.source.ends_with("scene.toml"));
    // the bidirectional methods' settings; `radius` is a length in the scene's units
    let s = ok(
        &format!(
            "units = \"cm\"\n[render]\nmethod = \"adaptive+quasi\"\niterations = 12\nphotons_per_iteration = 5000\n\
             max_gather_depth = 3\ncone_deg = 20\nradius = 2\nalpha = 0.5\ntarget_error = 0.02\n{BASE}"
        ),
        &[],
    );
    // the method parameters are kept as written (validated by the renderer's method table), with
    // the file's unit for lengths and the place of each key
    let r = &s.render;
    assert_eq!(param(r, "iterations"), Some(&ParamValue::Int(12)));
    assert_eq!(param(r, "photons_per_iteration"), Some(&ParamValue::Int(5000)));
    assert_eq!(param(r, "max_gather_depth"), Some(&ParamValue::Int(3)));
    assert_eq!(param(r, "cone_deg"), Some(&ParamValue::Int(20)));
    assert_eq!(param(r, "alpha"), Some(&ParamValue::Float(0.5)));
    assert_eq!(param(r, "radius"), Some(&ParamValue::Int(2)));
    assert_eq!(param(r, "gather_depth"), None);
    assert!((r.unit - 0.01).abs() < 1e-9);
    let place = &r.params.iter().find(|p| p.key == "cone_deg").unwrap().place;
    assert!(place.to_string().contains(":7:"), "{place}");
    assert_eq!(s.render.target_error, Some(0.02f32 as f64));
    // defaults
    let s = ok(BASE, &[]);
    assert_eq!(s.render, quasar_importers::RenderSettings::default());
    assert_eq!(s.camera.fov_axis, FovAxis::Y);
    assert_eq!(s.camera.up, Vec3::Y);
}

#[test]
fn units_scale_every_length() {
    let toml = r#"
units = "cm"
[camera]
position = [0, 0, 500]
target = [0, 0, 0]
[materials.m]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "sphere"
center = [100, 0, 0]
radius = 50
material = "m"
transform = { translate = [0, 200, 0] }
[[light]]
type = "point"
position = [0, 300, 0]
"#;
    let s = ok(toml, &[]);
    assert!(close(s.camera.position, Vec3::new(0.0, 0.0, 5.0)));
    let (lo, hi) = bounds(&s.meshes[0]);
    let c = (lo + hi) / 2.0;
    assert!(close(c, Vec3::new(1.0, 2.0, 0.0)), "{c}");
    assert!(((hi.x - lo.x) / 2.0 - 0.5).abs() < 0.01);
    match &s.lights[0] {
        LightDesc::Point { position, .. } => assert!(close(*position, Vec3::new(0.0, 3.0, 0.0))),
        l => panic!("{l:?}"),
    }
    for (u, f) in [("m", 1.0), ("mm", 0.001), ("in", 0.0254), ("ft", 0.3048)] {
        let s = ok(&toml.replace("\"cm\"", &format!("\"{u}\"")), &[]);
        assert!(close(s.camera.position, Vec3::new(0.0, 0.0, 500.0 * f)), "{u}");
    }
    // ImportOptions::units_scale multiplies on top
    let f = Files::new();
    let p = f.write("scene.toml", toml);
    let s = import_scene(&p, &ImportOptions { units_scale: Some(2.0), ..Default::default() }).unwrap();
    assert!(close(s.camera.position, Vec3::new(0.0, 0.0, 10.0)));
    let (lo, hi) = bounds(&s.meshes[0]);
    assert!(close((lo + hi) / 2.0, Vec3::new(2.0, 4.0, 0.0)));
}

#[test]
fn every_spectrum_form() {
    let csv = "# measured\nwavelength_nm,value\n400, 0.1\n500;0.5 # comment\n\n600\t0.9\n";
    let toml = format!(
        r#"{BASE}
[materials.number]
type = "diffuse"
reflectance = 0.25
[materials.constant]
type = "diffuse"
reflectance = {{ constant = 0.5 }}
[materials.table]
type = "diffuse"
reflectance = {{ wavelengths = [400, 500, 700], values = [0.1, 0.2, 0.3] }}
[materials.rgb]
type = "diffuse"
reflectance = {{ rgb = [0.8, 0.2, 0.1] }}
[materials.csv]
type = "diffuse"
reflectance = {{ file = "spectra/r.csv" }}
[[light]]
type = "environment"
spectrum = {{ blackbody = 3000 }}
[[light]]
type = "environment"
spectrum = {{ illuminant = "D65" }}
[[light]]
type = "environment"
spectrum = {{ illuminant = "A" }}
[[light]]
type = "environment"
spectrum = {{ rgb = [2, 1, 0.5] }}
"#
    );
    let s = ok(&toml, &[("spectra/r.csv", csv)]);
    let refl = |n: &str| match material(&s, n) {
        Material::Diffuse { reflectance, .. } => reflectance.clone(),
        m => panic!("{m:?}"),
    };
    assert_eq!(refl("number"), Spectrum::Constant(0.25));
    assert_eq!(refl("constant"), Spectrum::Constant(0.5));
    assert_eq!(
        refl("table"),
        Spectrum::PiecewiseLinear { lambda: vec![400.0, 500.0, 700.0], values: vec![0.1, 0.2, 0.3] }
    );
    assert_eq!(refl("rgb"), Spectrum::rgb_reflectance([0.8, 0.2, 0.1]).unwrap());
    assert_eq!(
        refl("csv"),
        Spectrum::PiecewiseLinear { lambda: vec![400.0, 500.0, 600.0], values: vec![0.1, 0.5, 0.9] }
    );
    let spectra: Vec<&Spectrum> = s
        .lights
        .iter()
        .map(|l| match l {
            LightDesc::Environment { spectrum, .. } => spectrum,
            l => panic!("{l:?}"),
        })
        .collect();
    assert_eq!(spectra[0], &Spectrum::Constant(1.0));
    assert!(matches!(spectra[1], Spectrum::Blackbody { kelvin, .. } if *kelvin == 3000.0));
    assert!(matches!(spectra[2], Spectrum::Illuminant { illuminant: StandardIlluminant::D65, .. }));
    assert!(matches!(spectra[3], Spectrum::Illuminant { illuminant: StandardIlluminant::A, .. }));
    // emission context: rgb is a light colour, not a reflectance (values > 1 allowed)
    assert!(matches!(spectra[4], Spectrum::RgbIlluminant { rgb, .. } if *rgb == [2.0, 1.0, 0.5]));
}

#[test]
fn every_material_type() {
    let toml = format!(
        r#"{BASE}
[materials.one_sided]
type = "diffuse"
reflectance = 0.3
two_sided = false
[materials.mirror]
type = "conductor"
fresnel = {{ rgb = [0.9, 0.8, 0.5] }}
[materials.rough_nk]
type = "conductor"
roughness = 0.5
eta = {{ wavelengths = [400, 700], values = [1.2, 0.3] }}
k = {{ constant = 3.0 }}
two_sided = false
[materials.aluminium]
type = "conductor"
metal = "Al"
alpha = 0.05
[materials.glass]
type = "dielectric"
ior = 1.5
[materials.bk7]
type = "dielectric"
ior = "BK7"
alpha = 0.1
transmittance = {{ rgb = [0.2, 0.5, 0.9] }}
[materials.cauchy]
type = "dielectric"
ior = {{ cauchy = [1.5, 0.0042] }}
[materials.sellmeier]
type = "dielectric"
ior = {{ sellmeier = {{ b = [1.03961212, 0.231792344, 1.01046945], c = [0.00600069867, 0.0200179144, 103.560653] }} }}
"#
    );
    let s = ok(&toml, &[]);
    assert_eq!(material(&s, "grey"), &Material::Diffuse { reflectance: Spectrum::Constant(0.5), two_sided: true });
    assert_eq!(
        material(&s, "one_sided"),
        &Material::Diffuse { reflectance: Spectrum::Constant(0.3), two_sided: false }
    );
    assert_eq!(
        material(&s, "mirror"),
        &Material::Conductor {
            alpha: 0.0,
            fresnel: ConductorFresnel::Constant(Spectrum::rgb_reflectance([0.9, 0.8, 0.5]).unwrap()),
            two_sided: true
        }
    );
    match material(&s, "rough_nk") {
        Material::Conductor { alpha, fresnel: ConductorFresnel::Complex { k, .. }, two_sided } => {
            assert_eq!(*alpha, 0.25, "alpha = roughness^2");
            assert_eq!(k, &Spectrum::Constant(3.0));
            assert!(!two_sided);
        }
        m => panic!("{m:?}"),
    }
    assert_eq!(
        material(&s, "aluminium"),
        &Material::Conductor { alpha: 0.05, fresnel: ConductorFresnel::named("Al").unwrap(), two_sided: true }
    );
    assert_eq!(
        material(&s, "glass"),
        &Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.0, transmittance: None }
    );
    let tint = Some(Spectrum::rgb_reflectance([0.2, 0.5, 0.9]).unwrap());
    assert_eq!(
        material(&s, "bk7"),
        &Material::Dielectric { ior: Ior::named("BK7").unwrap(), alpha: 0.1, transmittance: tint }
    );
    assert_eq!(
        material(&s, "cauchy"),
        &Material::Dielectric { ior: Ior::Cauchy { a: 1.5, b: 0.0042 }, alpha: 0.0, transmittance: None }
    );
    assert!(matches!(material(&s, "sellmeier"), Material::Dielectric { ior: Ior::Sellmeier { .. }, .. }));
    // materials keep file order; each has its source line
    let order: Vec<&str> = s.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(&order[..3], ["grey", "one_sided", "mirror"]);
    let glass = s.materials.iter().find(|m| m.name == "glass").unwrap();
    assert_eq!(glass.source.line, Some(common::line_of(&toml, "[materials.glass]")));
}

#[test]
fn quads_both_parametrisations() {
    let toml = r#"
[materials.m]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "quad"
corner = [-1, 0, 1]
edge1 = [2, 0, 0]
edge2 = [0, 0, -2]
material = "m"
[[shape]]
type = "quad"
name = "ceiling"
center = [0, 2, 0]
size = [4, 2]
normal = [0, -1, 0]
material = "m"
[[shape]]
type = "quad"
center = [0, 0, -3]
size = [1, 1]
material = "m"
"#;
    let s = ok(toml, &[]);
    let floor = mesh(&s, "shape[0]:quad");
    assert_eq!(floor.indices.len(), 2);
    assert!(geometric_normals(floor).iter().all(|n| close(*n, Vec3::Y)));
    let ceiling = mesh(&s, "ceiling");
    assert!(geometric_normals(ceiling).iter().all(|n| close(*n, Vec3::NEG_Y)));
    let (lo, hi) = bounds(ceiling);
    assert!(close(lo, Vec3::new(-2.0, 2.0, -1.0)) && close(hi, Vec3::new(2.0, 2.0, 1.0)), "{lo} {hi}");
    let wall = mesh(&s, "shape[2]:quad");
    assert!(geometric_normals(wall).iter().all(|n| close(*n, Vec3::Z)), "default normal +Z");
    assert!(floor.normals.is_none());
    assert_eq!(floor.source.line, Some(common::line_of(toml, "[[shape]]")));
}

#[test]
fn spheres_and_disks_with_transforms() {
    let toml = r#"
[materials.m]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "sphere"
radius = 1
subdivisions = 2
material = "m"
transform = { scale = [2, 1, 1], rotate_deg = [0, 0, 90], translate = [0, 0, -5] }
[[shape]]
type = "disk"
center = [0, 1, 0]
radius = 0.5
normal = [0, -1, 0]
segments = 32
material = "m"
[[shape]]
type = "disk"
radius = 1
material = "m"
transform = { rotate = { axis = [1, 0, 0], angle_deg = -90 } }
"#;
    let s = ok(toml, &[]);
    let sph = mesh(&s, "shape[0]:sphere");
    assert_eq!(sph.indices.len(), 320);
    // scaled 2x along x, then rotated 90 deg about z: the long axis is y
    let (lo, hi) = bounds(sph);
    assert!((hi.y - lo.y - 4.0).abs() < 0.1 && (hi.x - lo.x - 2.0).abs() < 0.1, "{lo} {hi}");
    assert!(close((lo + hi) / 2.0, Vec3::new(0.0, 0.0, -5.0)));
    // normals stay unit, point outward and follow the inverse transpose
    let c = Vec3::new(0.0, 0.0, -5.0);
    for (p, n) in sph.positions.iter().zip(sph.normals.as_ref().unwrap()) {
        assert!((n.length() - 1.0).abs() < 1e-5);
        assert!(n.dot(*p - c) > 0.0);
        // ellipsoid x^2/1 + y^2/4 + z^2 = 1 (after rotation): gradient (x, y/4, z)
        let q = *p - c;
        let g = Vec3::new(q.x, q.y / 4.0, q.z).normalize();
        assert!(n.dot(g) > 0.99, "{n} vs {g}");
    }
    for n in geometric_normals(sph) {
        assert!(n.is_finite());
    }
    let d = mesh(&s, "shape[1]:disk");
    assert_eq!(d.indices.len(), 32);
    assert!(geometric_normals(d).iter().all(|n| close(*n, Vec3::NEG_Y)));
    let d2 = mesh(&s, "shape[2]:disk");
    assert_eq!(d2.indices.len(), quasar_importers::toml_scene::DEFAULT_DISK_SEGMENTS as usize);
    // +Z rotated by -90 deg about x faces +Y
    assert!(geometric_normals(d2).iter().all(|n| close(*n, Vec3::Y)), "{:?}", geometric_normals(d2)[0]);
}

#[test]
fn emission_flip_normals_and_implicit_black_material() {
    let toml = r#"
[materials.wall]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "sphere"
radius = 1
material = "wall"
flip_normals = true
emission = { spectrum = { constant = 1.0 }, scale = 2.5 }
[[shape]]
type = "quad"
corner = [0, 0, 0]
edge1 = [1, 0, 0]
edge2 = [0, 1, 0]
emission = { spectrum = { blackbody = 4000 }, two_sided = true }
"#;
    let s = ok(toml, &[]);
    let sph = &s.meshes[0];
    let e = sph.emission.as_ref().unwrap();
    assert_eq!((e.scale, e.two_sided), (2.5, false));
    for (t, n) in sph.indices.iter().zip(geometric_normals(sph)) {
        let p = sph.positions[t[0] as usize];
        assert!(n.dot(p) < 0.0, "flipped sphere faces inward");
    }
    assert!(sph.normals.as_ref().unwrap().iter().zip(&sph.positions).all(|(n, p)| n.dot(*p) < 0.0));
    let lamp = &s.meshes[1];
    assert!(lamp.emission.as_ref().unwrap().two_sided);
    assert_eq!(lamp.emission.as_ref().unwrap().scale, 1.0);
    assert_eq!(
        s.materials[lamp.material].material,
        Material::Diffuse { reflectance: Spectrum::Constant(0.0), two_sided: true }
    );
}

#[test]
fn every_light_type() {
    let toml = r#"
[[light]]
type = "point"
position = [1, 2, 3]
spectrum = { illuminant = "A" }
scale = 100
[[light]]
type = "spot"
position = [0, 4, 0]
target = [0, 0, 0]
cone_deg = 30
falloff_start_deg = 20
[[light]]
type = "spot"
position = [0, 4, 0]
direction = [0, -1, 0]
cone_deg = 45
[[light]]
type = "directional"
direction = [0, -1, -1]
scale = 3
[[light]]
type = "environment"
scale = 0.5
"#;
    let s = ok(toml, &[]);
    assert_eq!(s.lights.len(), 5);
    assert!(
        matches!(&s.lights[0], LightDesc::Point { position, scale, .. } if *position == Vec3::new(1.0, 2.0, 3.0) && *scale == 100.0)
    );
    match &s.lights[1] {
        LightDesc::Spot { direction, cone_deg, falloff_start_deg, scale, spectrum, .. } => {
            assert!(close(direction.normalize(), Vec3::NEG_Y));
            assert_eq!((*cone_deg, *falloff_start_deg, *scale), (30.0, 20.0, 1.0));
            assert_eq!(spectrum, &Spectrum::Constant(1.0));
        }
        l => panic!("{l:?}"),
    }
    assert!(matches!(&s.lights[2], LightDesc::Spot { falloff_start_deg, .. } if *falloff_start_deg == 45.0));
    assert!(matches!(&s.lights[3], LightDesc::Directional { scale, .. } if *scale == 3.0));
    assert!(matches!(&s.lights[4], LightDesc::Environment { scale, .. } if *scale == 0.5));
    assert!(s.meshes.is_empty());
}

const CUBE_OBJ: &str = "mtllib cube.mtl
o Cube
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
usemtl red
f 1 4 3 2
f 5 6 7 8
usemtl glass_clear
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
";

const CUBE_MTL: &str = "newmtl red
Kd 0.8 0.1 0.1
newmtl glass_clear
Kd 0 0 0
d 0.1
Ni 1.45
";

#[test]
fn mesh_shapes_and_includes_with_units_transform_and_materials() {
    let toml = r#"
units = "cm"
[materials.white]
type = "diffuse"
reflectance = 0.8
[materials.lamp]
type = "diffuse"
reflectance = 0
[[shape]]
type = "mesh"
file = "models/cube.obj"
units = "m"
material = "lamp"
emission = { spectrum = 1, scale = 5 }
transform = { translate = [0, 300, 0] }
[[include]]
file = "models/cube.obj"
transform = { translate = [100, 0, 0], scale = 2 }
[[include]]
file = "models/cube.obj"
units = "mm"
material = "white"
"#;
    let s = ok(toml, &[("models/cube.obj", CUBE_OBJ), ("models/cube.mtl", CUBE_MTL)]);
    assert_eq!(s.meshes.len(), 6);
    // shape mesh: OBJ in metres, translated 3 m up, one material for everything, emissive
    for m in &s.meshes[..2] {
        assert_eq!(s.materials[m.material].name, "lamp");
        assert_eq!(m.emission.as_ref().unwrap().scale, 5.0);
    }
    let (lo, hi) = bounds(&s.meshes[0]);
    assert!(close(lo, Vec3::new(-1.0, 2.0, -1.0)) && close(hi, Vec3::new(1.0, 4.0, 1.0)), "{lo} {hi}");
    // include without material: OBJ in scene units (cm), scaled 2x, translated 1 m; MTL materials
    // are added with the file name as prefix
    let inc = &s.meshes[2..4];
    assert_eq!(inc[0].name, "cube.obj:Cube:red");
    assert_eq!(s.materials[inc[0].material].name, "cube.obj:red");
    assert!(
        matches!(s.materials[inc[1].material].material, Material::Dielectric { ior: Ior::Constant(n), .. } if n == 1.45)
    );
    let (lo, hi) = bounds(&inc[1]);
    assert!(close(lo, Vec3::new(0.98, -0.02, -0.02)) && close(hi, Vec3::new(1.02, 0.02, 0.02)), "{lo} {hi}");
    assert!(inc[0].emission.is_none());
    // include with material and units = mm
    for m in &s.meshes[4..] {
        assert_eq!(s.materials[m.material].name, "white");
    }
    let (lo, hi) = bounds(&s.meshes[4]);
    assert!(close(lo, Vec3::splat(-0.001)) && close(hi, Vec3::splat(0.001)));
    // quads were triangulated with consistent outward winding
    assert_eq!(s.meshes[2].indices.len() + s.meshes[3].indices.len(), 12);
}

#[test]
fn overrides_match_mesh_and_material_names_with_globs() {
    let toml = r#"
[materials.white]
type = "diffuse"
reflectance = 0.8
[materials.chrome]
type = "conductor"
metal = "Ag"
[materials.frosted]
type = "dielectric"
ior = 1.5
alpha = 0.3
[[include]]
file = "cube.obj"
[[override]]
match = "glass_*"
material = "frosted"
[[override]]
match = "cube.obj:C?be:red"
material = "chrome"
"#;
    let s = ok(toml, &[("cube.obj", CUBE_OBJ), ("cube.mtl", CUBE_MTL)]);
    assert_eq!(s.materials[s.meshes[0].material].name, "chrome");
    assert_eq!(s.materials[s.meshes[1].material].name, "frosted");
    // the OBJ's materials also match when the include assigns one material to everything
    let toml2 = toml.replace("file = \"cube.obj\"", "file = \"cube.obj\"\nmaterial = \"white\"");
    let s = ok(&toml2, &[("cube.obj", CUBE_OBJ)]); // no MTL needed: its materials are replaced
    assert_eq!(s.materials[s.meshes[1].material].name, "frosted");
}

#[test]
fn overrides_can_give_imported_meshes_an_emission() {
    let toml = r#"
[[include]]
file = "cube.obj"
[[override]]
match = "glass_*"
emission = { spectrum = { blackbody = 3000 }, scale = 5 }
"#;
    let s = ok(toml, &[("cube.obj", CUBE_OBJ), ("cube.mtl", CUBE_MTL)]);
    assert!(s.meshes[0].emission.is_none());
    let e = s.meshes[1].emission.as_ref().expect("the override's emission");
    assert_eq!(e.scale, 5.0);
    // the material is kept when only the emission is given
    assert_eq!(s.materials[s.meshes[1].material].name, "cube.obj:glass_clear");
    let bare = "[[include]]\nfile = \"cube.obj\"\n[[override]]\nmatch = \"glass_*\"\n";
    let e = common::err(bare, &[("cube.obj", CUBE_OBJ), ("cube.mtl", CUBE_MTL)]);
    assert!(e.contains("material"), "{e}");
}

#[test]
fn include_of_a_toml_scene() {
    let inner = r#"
units = "mm"
[materials.m]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "sphere"
radius = 100
material = "m"
[[light]]
type = "point"
position = [0, 1000, 0]
"#;
    let outer = r#"
[[include]]
file = "parts/inner.toml"
transform = { translate = [5, 0, 0] }
"#;
    let s = ok(outer, &[("parts/inner.toml", inner)]);
    assert_eq!(s.materials[0].name, "inner.toml:m");
    let (lo, hi) = bounds(&s.meshes[0]);
    assert!(close((lo + hi) / 2.0, Vec3::new(5.0, 0.0, 0.0)) && (hi.x - lo.x - 0.2).abs() < 0.002);
    assert!(matches!(&s.lights[0], LightDesc::Point { position, .. } if close(*position, Vec3::new(5.0, 1.0, 0.0))));
}

#[test]
fn parse_from_text_resolves_files_relative_to_the_given_path() {
    let f = Files::new();
    f.write("c.csv", "400,0.5\n700,0.5\n");
    let text = format!("{BASE}\n[materials.c]\ntype = \"diffuse\"\nreflectance = {{ file = \"c.csv\" }}\n");
    let s = parse_toml_scene(&text, &f.path("virtual.toml"), &ImportOptions::default()).unwrap();
    assert_eq!(s.materials.len(), 2);
}

#[test]
fn the_shipped_example_scenes_import() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut n = 0;
    for entry in walk(&dir) {
        if entry.extension().is_some_and(|e| e == "toml") {
            let s = import_scene(&entry, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
            assert!(!s.meshes.is_empty() || !s.lights.is_empty());
            n += 1;
        }
    }
    assert!(n > 0 || !dir.exists());
}

fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() { out.extend(walk(&p)) } else { out.push(p) }
        }
    }
    out
}

#[test]
fn byte_order_mark_and_crlf_are_accepted() {
    let text = format!("\u{feff}{}", BASE.replace('\n', "\r\n"));
    let s = ok(&text, &[]);
    assert_eq!(s.meshes.len(), 1);
}

#[test]
fn the_example_in_the_format_reference_imports() {
    let doc = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/scene-format.md");
    let Ok(text) = std::fs::read_to_string(&doc) else { return };
    let start = text.find("```toml\n").expect("an example") + "```toml\n".len();
    let example = &text[start..start + text[start..].find("```").unwrap()];
    let plate = "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nv -5 1 -5\nf 1 4 3 2\nf 1 2 5\n";
    let stand = "mtllib stand.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl wood\nf 1 2 3\nusemtl steel_dark\nf 1 3 2\n";
    let mtl = "newmtl wood\nKd 0.5 0.3 0.1\nnewmtl steel_dark\nKd 0 0 0\nKs 0.6 0.6 0.6\nNs 50\n";
    let s = ok(example, &[("plate.obj", plate), ("stand.obj", stand), ("stand.mtl", mtl)]);
    assert_eq!(s.render.width, 640);
    assert_eq!(s.meshes.len(), 5);
    let steel = s.meshes.iter().find(|m| m.name.contains("steel_dark")).unwrap();
    assert_eq!(s.materials[steel.material].name, "brushed");
    let wood = s.meshes.iter().find(|m| m.name.contains(":wood")).unwrap();
    assert_eq!(s.materials[wood.material].name, "stand.obj:wood");
    assert!(s.meshes.iter().any(|m| m.emission.is_some()));
}
