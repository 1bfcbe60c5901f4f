//! Absorbing media inside transmitting surfaces (issue 49, docs/architecture.md §5): Beer-Lambert
//! attenuation of every path segment inside, for every method, against the analytic slab; the
//! medium stack of nested surfaces; every method converging to `pt` where photons cross the
//! medium; the importers' forms of the absorption.

mod common;

use common::{
    assert_bidirectional_methods_converge, mean_and_error, pt_ov, quick_ov, render_file, slab, sphere_on_floor_scene,
    write_scene,
};

/// A camera looking along -z at a glass slab between z = -D/2 and D/2 (two quads, normals
/// outward), under a uniform environment of radiance 1; MATERIALS and SHAPES are replaced.
const SLAB: &str = r#"
[render]
width = 32
height = 32
[camera]
position = [0, 0, 10]
target = [0, 0, 0]
fov_deg = 2
MATERIALS
SHAPES
[[light]]
type = "environment"
"#;

/// The luminance of the slab under the environment at normal incidence: the reflections and
/// transmissions of a plate of Fresnel reflectance R at each face and internal transmittance a,
/// L = R + (1 - R)^2 a / (1 - R a) (1 for a = 1).
fn slab_luminance(ior: f64, a: f64) -> f64 {
    let r = ((ior - 1.0) / (ior + 1.0)).powi(2);
    r + (1.0 - r).powi(2) * a / (1.0 - r * a)
}

/// A slab of glass (n = 1.5, 2 cm) with sigma_a = 50 / m transmits e^-1 inside; every method
/// gives the analytic luminance within four standard errors, and the clear slab gives 1.
#[test]
fn an_absorbing_slab_follows_beer_lambert_for_every_method() {
    for (absorption, a) in [("absorption = 50", (-1.0f64).exp()), ("", 1.0)] {
        let materials = format!("[materials.glass]\ntype = \"dielectric\"\nior = 1.5\n{absorption}\n");
        let scene = write_scene(&SLAB.replace("MATERIALS", &materials).replace("SHAPES", &slab("glass", 0.01)), &[]);
        let want = slab_luminance(1.5, a);
        for method in quasar::integrator::method::METHODS.iter().map(|m| m.name) {
            let img = render_file(&scene.path, &quick_ov(method)).image;
            let (mean, se) = mean_and_error(&img);
            eprintln!("{method} {absorption:?}: {mean:.5} +- {se:.5}, analytic {want:.5}");
            assert!(
                se > 0.0 && (mean - want).abs() < 4.0 * se + 1e-4 * want,
                "{method} {absorption:?}: {mean} +- {se}, analytic {want}"
            );
        }
    }
}

/// One body, two finishes: a slab whose front face is one material and whose back face another
/// (a light guide's polished and frosted faces), with equal absorption, bounds one medium
/// (`core::media` merges equal interiors) and follows Beer-Lambert for `pt` and the photons.
#[test]
fn faces_of_one_body_with_equal_media_bound_one_medium() {
    let two_faces = |front: &str, back: &str| {
        format!(
            "[materials.front]\ntype = \"dielectric\"\nior = 1.5\n{front}\n[materials.back]\ntype = \"dielectric\"\nior = 1.5\n{back}\n"
        )
    };
    let shapes = "[[shape]]\ntype = \"quad\"\ncenter = [0, 0, 0.01]\nsize = [4, 4]\nnormal = [0, 0, 1]\nmaterial = \"front\"\n\
                  [[shape]]\ntype = \"quad\"\ncenter = [0, 0, -0.01]\nsize = [4, 4]\nnormal = [0, 0, -1]\nmaterial = \"back\"\n";
    let scene = write_scene(
        &SLAB.replace("MATERIALS", &two_faces("absorption = 50", "absorption = 50")).replace("SHAPES", shapes),
        &[],
    );
    let want = slab_luminance(1.5, (-1.0f64).exp());
    for method in ["pt", "adaptive+quasi"] {
        let (mean, se) = mean_and_error(&render_file(&scene.path, &quick_ov(method)).image);
        assert!((mean - want).abs() < 4.0 * se + 1e-4 * want, "{method}: {mean} +- {se}, analytic {want}");
    }
}

/// The medium stack: a clear inner slab (index-matched, 1 cm) inside an absorbing one (4 cm,
/// sigma_a = 25 / m): the path is in the absorbing medium for 3 cm of the 4, before and after the
/// inner slab; an absorbing inner slab inside a clear one absorbs over its own 1 cm only. Also
/// the same absorption given as an internal transmittance at a thickness.
#[test]
fn nested_media_absorb_where_the_path_is() {
    let cases = [
        ("outer", "absorption = 25", "inner", "", (-0.75f64).exp()),
        ("outer", "", "inner", "absorption = 25", (-0.25f64).exp()),
        ("outer", "internal_transmittance = 0.5\nthickness = 0.01", "inner", "", 0.5f64.powi(3)),
    ];
    for (outer, outer_abs, inner, inner_abs, a) in cases {
        let materials = format!(
            "[materials.{outer}]\ntype = \"dielectric\"\nior = 1.5\n{outer_abs}\n[materials.{inner}]\ntype = \"dielectric\"\nior = 1.0\n{inner_abs}\n"
        );
        let shapes = slab(outer, 0.02) + &slab(inner, 0.005);
        let scene = write_scene(&SLAB.replace("MATERIALS", &materials).replace("SHAPES", &shapes), &[]);
        let img = render_file(&scene.path, &quick_ov("pt")).image;
        let (mean, se) = mean_and_error(&img);
        let want = slab_luminance(1.5, a);
        eprintln!("{outer_abs:?} / {inner_abs:?}: {mean:.5} +- {se:.5}, analytic {want:.5}");
        assert!(
            (mean - want).abs() < 4.0 * se + 1e-4 * want,
            "{outer_abs:?} / {inner_abs:?}: {mean} +- {se}, analytic {want}"
        );
    }
}

/// An absorbing glass sphere on a diffuse floor under a small area light: its shadow and caustic
/// come from photons and camera paths that cross the medium. Every bidirectional method
/// converges to `pt`.
#[test]
fn every_method_converges_to_pt_through_an_absorbing_sphere() {
    let scene = sphere_on_floor_scene(
        "type = \"dielectric\"\nior = 1.5\nalpha = 0.05\n\
         absorption = { wavelengths = [400, 550, 700], values = [20, 8, 2] }",
    );
    let reference = render_file(&scene.path, &pt_ov(40, 30, 4096, 101));
    assert_bidirectional_methods_converge(&scene.path, &reference);
}

/// Numerical extremes: sigma_a from 1e-6 to 1e6 1/m (and an internal transmittance of 0, the
/// largest coefficient) give finite images: the slab's analytic luminance within the noise, its
/// front reflection alone when it is opaque.
#[test]
fn extreme_absorption_stays_finite() {
    for (absorption, a) in [
        ("absorption = 1e-6", (-2e-8f64).exp()),
        ("absorption = 1e6", 0.0),
        ("internal_transmittance = 0\nthickness = 1e-3", 0.0),
    ] {
        let materials = format!("[materials.glass]\ntype = \"dielectric\"\nior = 1.5\n{absorption}\n");
        let scene = write_scene(&SLAB.replace("MATERIALS", &materials).replace("SHAPES", &slab("glass", 0.01)), &[]);
        for method in ["pt", "adaptive+quasi"] {
            let img = render_file(&scene.path, &quick_ov(method)).image;
            assert!(img.channels.iter().all(|c| c.values.iter().all(|v| v.is_finite())), "{method} {absorption:?}");
            let (mean, se) = mean_and_error(&img);
            let want = slab_luminance(1.5, a);
            assert!(
                (mean - want).abs() < 4.0 * se + 1e-4 * want,
                "{method} {absorption:?}: {mean} +- {se}, analytic {want}"
            );
        }
    }
}

/// `absorption = "PMMA"` is the measured absorption of `Absorption::named` (issue 49 item 4).
#[test]
fn a_named_absorption_is_the_measured_one() {
    let materials = "[materials.pmma]\ntype = \"dielectric\"\nior = \"PMMA\"\nabsorption = \"acrylic\"\n";
    let scene = write_scene(&SLAB.replace("MATERIALS", materials).replace("SHAPES", &slab("pmma", 0.01)), &[]);
    let desc = quasar::render::job::load_scene_with(&scene.path, &Default::default()).unwrap();
    let m = desc.materials.iter().find(|m| m.name == "pmma").unwrap();
    assert_eq!(m.absorption, quasar_materials::Absorption::named("PMMA"));
    assert!(m.absorption.is_some());
}

/// The shipped lightguide's rod absorbs as measured PMMA, and its diffusing variant includes
/// it with scattering in the same rod (docs/lightguide.md).
#[test]
fn the_shipped_lightguides_carry_their_media() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/lightguide");
    let pmma = quasar_materials::Absorption::named("PMMA");
    let clear = quasar::render::job::load_scene_with(&root.join("lightguide.toml"), &Default::default()).unwrap();
    let rod: Vec<_> = clear.materials.iter().filter(|m| m.name.starts_with("pmma_")).collect();
    assert_eq!(rod.len(), 3);
    assert!(rod.iter().all(|m| m.absorption == pmma && m.scattering.is_none()));
    let diffuser =
        quasar::render::job::load_scene_with(&root.join("lightguide-diffuser.toml"), &Default::default()).unwrap();
    for mesh in diffuser.meshes.iter().filter(|m| m.emission.is_none()) {
        let m = &diffuser.materials[mesh.material];
        if m.name.starts_with("diffuser_") {
            let s = m.scattering.as_ref().unwrap();
            assert_eq!((s.coefficient.value(600.0), s.g, &m.absorption), (10.0, 0.6, &pmma));
        } else {
            assert!(!m.name.contains("pmma"), "{} kept the clear rod's material", m.name);
        }
    }
}

/// glTF's `KHR_materials_volume` is the absorption of the transmissive material's inside: white
/// light turns into `attenuationColor` over `attenuationDistance` (world units, times --units).
#[test]
fn gltf_volume_attenuation_is_an_internal_transmittance() {
    use quasar_importers::gltf::writer::{GltfWriter, Prim};
    let mut w = GltfWriter::new();
    w.use_extension("KHR_materials_transmission", false);
    w.use_extension("KHR_materials_volume", false);
    let mat = GltfWriter::push(
        &mut w.materials,
        r#"{"pbrMetallicRoughness":{"metallicFactor":0},"extensions":{"KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_volume":{"thicknessFactor":0.1,"attenuationDistance":0.5,"attenuationColor":[0.5,0.8,1.0]}}}"#,
    );
    let position = w.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let indices = Some(w.indices(&[0, 1, 2]));
    let m = w.mesh("glass", &[Prim { position, indices, material: Some(mat), ..Default::default() }]);
    let node = GltfWriter::push(&mut w.nodes, &format!(r#"{{"mesh":{m}}}"#));
    w.roots.push(node);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("glass.glb");
    std::fs::write(&path, w.to_glb()).unwrap();
    let opts = quasar_importers::ImportOptions { units_scale: Some(0.01), ..Default::default() };
    let desc = quasar::render::job::load_scene_with(&path, &opts).unwrap();
    let Some(quasar_materials::Absorption::Transmittance { transmittance, thickness }) = &desc.materials[0].absorption
    else {
        panic!("{:?}", desc.materials[0].absorption);
    };
    assert!((thickness - 0.005).abs() < 1e-7, "{thickness}");
    // the colour of the transmittance (under D65, linear sRGB) is the attenuation colour
    let rgb = quasar_materials::spectrum::rgb_uplift::reflectance_rgb(|l| transmittance.value(l));
    for (got, want) in rgb.iter().zip([0.5, 0.8, 1.0]) {
        assert!((got - want).abs() < 0.01, "{rgb:?}");
    }
}
