//! Scattering media inside transmitting surfaces (issue 49, docs/architecture.md §5): the
//! white furnace of a medium of albedo 1 and the light an index-matched absorbing sphere takes
//! out of a uniform sky (both analytic), every method converging to `pt` through a scattering
//! diffuser, numerical extremes, and the scene file's errors.

mod common;

use common::{
    assert_bidirectional_methods_converge, assert_converges_from, layer, mean_and_error, pt_ov, quick_ov, render_file,
    slab, sphere_on_floor_scene, write_scene,
};

/// A sphere of material MATERIAL (radius R m, at the origin) seen from z = D through a field of
/// view FOV degrees, under a uniform environment of radiance 1.
const SPHERE_IN_SKY: &str = r#"
[render]
width = 32
height = 32
[camera]
position = [0, 0, D]
target = [0, 0, 0]
fov_deg = FOV
[materials.m]
MATERIAL
[[shape]]
type = "sphere"
center = [0, 0, 0]
radius = R
subdivisions = 5
material = "m"
[[light]]
type = "environment"
"#;

fn sphere_in_sky(material: &str, r: f32, d: f32, fov: f32) -> common::TempScene {
    let toml = SPHERE_IN_SKY
        .replace("MATERIAL", material)
        .replace("= R", &format!("= {r}"))
        .replace("D]", &format!("{d}]"))
        .replace("FOV", &fov.to_string());
    write_scene(&toml, &[])
}

/// A medium of albedo 1 (sigma_s = 100/m, no absorption) in a sphere under a uniform sky scatters
/// light but neither adds nor removes any: every pixel's expected radiance is the sky's, for an
/// index-matched or a refracting boundary, forward or backward scattering, and every method.
#[test]
fn a_medium_of_albedo_one_is_a_white_furnace_for_every_method() {
    for (ior, g) in [(1.0f32, 0.6f32), (1.5, -0.5), (1.5, 0.0)] {
        let material = format!("type = \"dielectric\"\nior = {ior}\nscattering = 100\nphase_g = {g}\n");
        let scene = sphere_in_sky(&material, 0.1, 1.0, 16.0);
        for method in ["pt", "vismap", "adaptive", "quasi", "adaptive+quasi"] {
            let img = render_file(&scene.path, &quick_ov(method)).image;
            let (mean, se) = mean_and_error(&img);
            eprintln!("furnace ior {ior} g {g} {method}: {mean:.5} +- {se:.5}");
            assert!(se < 0.01, "{method}: stderr {se}");
            assert!((mean - 1.0).abs() < 4.0 * se, "{method} ior {ior} g {g}: {mean} +- {se}, the sky's 1");
        }
    }
}

/// An index-matched sphere (n = 1) of radius R absorbing sigma_a = 1/R under a sky of radiance 1,
/// seen from far away (rays parallel within 2e-3): a ray at distance b from the centre crosses
/// 2 sqrt(R² - b²) of it, so the light it takes out of the image, integrated over the image
/// plane, is pi R² (1 - <T>), <T> = 2 (1 - e^(-2 s R) (1 + 2 s R)) / (4 s² R²) = 0.2970 at s R = 1.
/// `pt` and a bidirectional method give it within four standard errors, and so does the same
/// sphere scattering as well as absorbing, against its albedo-1 furnace twin: not analytic, so
/// only the absorbing case is checked against the formula.
#[test]
fn an_absorbing_sphere_takes_the_analytic_light_out_of_a_uniform_sky() {
    let (r, d, fov) = (0.1f64, 50.0f64, 0.4f64);
    let scene = sphere_in_sky("type = \"dielectric\"\nior = 1.0\nabsorption = 10\n", r as f32, d as f32, fov as f32);
    let sr = 1.0f64;
    let mean_t = 2.0 * (1.0 - (-2.0 * sr).exp() * (1.0 + 2.0 * sr)) / (4.0 * sr * sr);
    let want = std::f64::consts::PI * r * r * (1.0 - mean_t);
    // the image plane's area at the sphere's centre
    let side = 2.0 * d * (fov.to_radians() / 2.0).tan();
    for method in ["pt", "adaptive+quasi"] {
        let img = render_file(&scene.path, &quick_ov(method)).image;
        let (mean, se) = mean_and_error(&img);
        let (deficit, deficit_se) = ((1.0 - mean) * side * side, se * side * side);
        eprintln!("{method}: {deficit:.6} +- {deficit_se:.6} m², analytic {want:.6}");
        assert!(
            (deficit - want).abs() < 4.0 * deficit_se + 2e-3 * want,
            "{method}: {deficit} +- {deficit_se} m² of sky taken out, analytic {want}"
        );
    }
}

/// A scattering, absorbing diffuser slab over a floor under a small lamp, and a milky sphere:
/// its shadow and the light it spreads come from photons that scatter in the medium and from
/// camera paths that scatter there (continued as `pt`). Every bidirectional method, and
/// `direct` against `pt`'s emission and direct layers, converge to `pt`.
#[test]
fn every_method_converges_to_pt_through_a_scattering_diffuser() {
    let scene = sphere_on_floor_scene(
        "type = \"dielectric\"\nior = 1.4\nalpha = 0.1\n\
         scattering = { wavelengths = [400, 700], values = [40, 20] }\nphase_g = 0.5\nabsorption = 1",
    );
    let reference = render_file(&scene.path, &pt_ov(40, 30, 4096, 101));
    let mut direct = pt_ov(40, 30, 1024, 12);
    direct.method = Some("direct".into());
    let direct = render_file(&scene.path, &direct);
    assert_converges_from(8, "direct", &direct, &reference, &[layer("emission"), layer("direct")]);
    assert_bidirectional_methods_converge(&scene.path, &reference);
}

/// Numerical extremes (issue 49 item 5): sigma_s from 1e-6 to 1e6 1/m at albedo 1, and
/// g = +-0.999, in a 2 cm slab under the sky: finite images, no hang (a path scatters at most
/// [`quasar::core::medium::MAX_MEDIUM_SCATTERS`] times), and a nearly clear medium giving the
/// clear slab's luminance.
#[test]
fn extreme_scattering_stays_finite() {
    for (scattering, g) in [("1e-6", 0.0f32), ("1e6", 0.0), ("300", 0.999), ("300", -0.999), ("1e6", 0.999)] {
        let toml = format!(
            "[render]\nwidth = 8\nheight = 8\n[camera]\nposition = [0, 0, 10]\ntarget = [0, 0, 0]\nfov_deg = 2\n\
             [materials.m]\ntype = \"dielectric\"\nior = 1.5\nscattering = {scattering}\nphase_g = {g}\n{}\
             [[light]]\ntype = \"environment\"\n",
            slab("m", 0.01)
        );
        let scene = write_scene(&toml, &[]);
        for method in ["pt", "direct", "adaptive+quasi"] {
            let img = render_file(&scene.path, &quick_ov(method)).image;
            assert!(
                img.channels.iter().all(|c| c.values.iter().all(|v| v.is_finite())),
                "{method} sigma_s {scattering} g {g}"
            );
            let (mean, se) = mean_and_error(&img);
            // albedo 1 neither adds light nor (beyond the cap on scattering events) removes it
            assert!(mean <= 1.0 + 4.0 * se + 1e-3, "{method} sigma_s {scattering} g {g}: {mean} +- {se}");
            if scattering == "1e-6" && method != "direct" {
                assert!((mean - 1.0).abs() < 4.0 * se + 1e-4, "{method}: the clear slab, {mean} +- {se}");
            }
        }
    }
}

/// The scene file's errors name the material and the key.
#[test]
fn scattering_keys_are_checked() {
    for (keys, wants) in [
        ("phase_g = 0.5", "`phase_g` goes with `scattering`"),
        ("scattering = 10\nphase_g = 1.5", "phase_g"),
        ("scattering = -1", "scattering"),
    ] {
        let toml = format!(
            "[camera]\nposition = [0, 0, 1]\ntarget = [0, 0, 0]\n[materials.cloudy]\ntype = \"dielectric\"\nior = 1.5\n{keys}\n"
        );
        let scene = write_scene(&toml, &[]);
        let err = quasar::render::job::load_scene(&scene.path).unwrap_err().to_string();
        assert!(err.contains(wants) && err.contains("cloudy"), "{keys:?}: {err}");
    }
}
