//! Coated and sheen materials in the renderer (issue 50): every method converges to `pt` on a
//! lacquered sphere over a diffuse and over a metal base and on a velvet (sheen) sphere, and
//! such scenes stay finite at the parameters' extremes. Plain `vismap` gathers photons on whatever its first non-specular vertex is: on a
//! coat of alpha 0.04 that is a narrow lobe, whose photon estimate is heavy-tailed (its indirect
//! layer read 12% low at 256 iterations, 8.5% at 1024, with standard errors that did not show
//! it: the noise the adaptive and quasi-specular methods exist to remove); it is checked on a
//! broad coat (alpha 0.25) and the three methods that pass narrow lobes on the narrow one.

mod common;

use common::{assert_converges_from, assert_methods_converge, layer, pt_ov, render_file, sphere_on_floor_scene};

const ALL: [&str; 4] = ["vismap", "adaptive", "quasi", "adaptive+quasi"];

fn direct_and_bidirectional_converge(sphere: &str, methods: &[&str]) {
    let scene = sphere_on_floor_scene(sphere);
    let reference = render_file(&scene.path, &pt_ov(40, 30, 4096, 201));
    let mut direct = pt_ov(40, 30, 1024, 22);
    direct.method = Some("direct".into());
    let direct = render_file(&scene.path, &direct);
    assert_converges_from(8, "direct", &direct, &reference, &[layer("emission"), layer("direct")]);
    assert_methods_converge(&scene.path, &reference, methods);
}

#[test]
fn every_method_converges_on_a_coat_over_diffuse() {
    let base = "base = { type = \"diffuse\", reflectance = { rgb = [0.7, 0.1, 0.05] } }";
    direct_and_bidirectional_converge(&format!("type = \"coated\"\nroughness = 0.5\n{base}"), &ALL);
    direct_and_bidirectional_converge(&format!("type = \"coated\"\nroughness = 0.2\n{base}"), &ALL[1..]);
}

#[test]
fn every_method_converges_on_an_absorbing_coat_over_metal() {
    direct_and_bidirectional_converge(
        "type = \"coated\"\nior = 1.6\nabsorption = { wavelengths = [400, 700], values = [2000, 200] }\n\
         thickness = 0.0002\nbase = { type = \"conductor\", metal = \"Al\", roughness = 0.3 }",
        &ALL,
    );
}

#[test]
fn every_method_converges_on_a_sheen() {
    direct_and_bidirectional_converge(
        "type = \"sheen\"\ncolor = { rgb = [0.9, 0.8, 1.0] }\nroughness = 0.4\n\
         base = { type = \"diffuse\", reflectance = { rgb = [0.2, 0.05, 0.3] } }",
        &ALL,
    );
}

#[test]
fn extreme_coats_stay_finite() {
    for keys in [
        "ior = 4\nbase = { type = \"diffuse\", reflectance = 1 }",
        "ior = 1\nroughness = 1\nbase = { type = \"diffuse\", reflectance = 1 }",
        "absorption = 1e9\nthickness = 0.001\nbase = { type = \"diffuse\", reflectance = 1 }",
        "alpha = 1e-9\nbase = { type = \"conductor\", fresnel = 1, alpha = 0 }",
        "SHEEN color = 1\nalpha = 0\nbase = { type = \"diffuse\", reflectance = 1 }",
        "SHEEN color = 1\nroughness = 1\nbase = { type = \"conductor\", fresnel = 1, alpha = 0 }",
    ] {
        let toml = match keys.strip_prefix("SHEEN ") {
            Some(k) => format!("type = \"sheen\"\n{k}"),
            None => format!("type = \"coated\"\n{keys}"),
        };
        let scene = sphere_on_floor_scene(&toml);
        for method in ["pt", "adaptive+quasi"] {
            let mut ov = pt_ov(16, 12, 16, 5);
            ov.method = Some(method.into());
            let img = render_file(&scene.path, &ov);
            let y = img.image.channel(quasar::film::LUMINANCE).unwrap();
            assert!(y.iter().all(|v| v.is_finite() && *v >= 0.0), "{keys} {method}");
        }
    }
}
