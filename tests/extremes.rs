//! Numerical extremes (docs/architecture.md §9): every method stays finite and panic-free at extreme
//! roughness, IOR, incidence, scene scale, radiance and spectra, on degenerate geometry, with
//! zero-area lights, lights inside objects and the camera inside glass; where a physical answer
//! exists, it is checked.

mod common;

use common::{mean, rel_mse, render_file, write_scene};
use quasar::output::ExrImage;
use quasar::render::job::JobOverrides;

/// Every method, with small budgets: (name, overrides).
fn every_method(w: u32, h: u32, seed: u64) -> Vec<(&'static str, JobOverrides)> {
    // with spectral bins, so that their channels are checked for finiteness too
    let bins = quasar::film::SpectralBins::new(16, 360.0, 830.0).ok();
    let base =
        JobOverrides { width: Some(w), height: Some(h), seed: Some(seed), spectral_bins: bins, ..Default::default() };
    let bidir = |method: &'static str, cone: Option<f32>| {
        (method, {
            let ov = JobOverrides { method: Some(method.into()), ..base.clone() }
                .with_param("iterations", 4u32)
                .with_param("photons_per_iteration", 2000u32);
            match cone {
                Some(c) => ov.with_param("cone_deg", c),
                None => ov,
            }
        })
    };
    vec![
        ("pt", JobOverrides { method: Some("pt".into()), spp: Some(8), ..base.clone() }),
        bidir("vismap", None),
        bidir("adaptive", None),
        bidir("quasi", Some(10.0)),
        bidir("adaptive+quasi", Some(30.0)),
    ]
}

/// No NaN or inf in any channel (depth.Z: +inf marks a miss, never NaN) and no negative radiance.
fn assert_finite(img: &ExrImage, what: &str) {
    for c in &img.channels {
        if c.name == "depth.Z" {
            assert!(c.values.iter().all(|v| !v.is_nan() && *v >= 0.0), "{what}: {} has NaN", c.name);
            continue;
        }
        assert!(c.values.iter().all(|v| v.is_finite()), "{what}: {} has a non-finite value", c.name);
        if c.name == quasar::film::LUMINANCE {
            assert!(c.values.iter().all(|v| *v >= 0.0), "{what}: negative luminance");
        }
    }
}

/// Renders `scene` with every method; checks finiteness and returns the images.
fn render_every_method(scene: &str, w: u32, h: u32, what: &str) -> Vec<(&'static str, ExrImage)> {
    let s = write_scene(scene, &[]);
    every_method(w, h, 3)
        .into_iter()
        .map(|(name, ov)| {
            let img = render_file(&s.path, &ov).image;
            assert_finite(&img, &format!("{what}, {name}"));
            (name, img)
        })
        .collect()
}

/// A floor, a back wall, a sphere of material `sphere` (TOML body) and a quad light, with every
/// length multiplied by `scale` and the light's radiance `radiance`.
fn test_scene(sphere: &str, scale: f64, radiance: f64, spectrum: &str) -> String {
    let l = |v: f64| v * scale;
    format!(
        r#"
[camera]
position = [0, {cy}, {cz}]
target = [0, {ty}, 0]
fov_deg = 45
[materials.white]
type = "diffuse"
reflectance = 0.7
[materials.probe]
{sphere}
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [{s4}, {s4}]
normal = [0, 1, 0]
material = "white"
[[shape]]
type = "quad"
center = [0, {s1}, {m1}]
size = [{s4}, {s2}]
normal = [0, 0, 1]
material = "white"
[[shape]]
type = "sphere"
center = [0, {r}, 0]
radius = {r}
subdivisions = 2
material = "probe"
[[shape]]
type = "quad"
center = [{lx}, {ly}, 0]
size = [{ls}, {ls}]
normal = [0, -1, 0]
material = "white"
emission = {{ spectrum = {spectrum}, scale = {radiance:e} }}
"#,
        cy = l(0.8),
        cz = l(2.5),
        ty = l(0.4),
        s4 = l(4.0),
        s1 = l(1.0),
        m1 = l(-1.0),
        s2 = l(2.0),
        r = l(0.4),
        lx = l(-0.6),
        ly = l(1.8),
        ls = l(0.6),
    )
}

const WHITE: &str = "{ constant = 1 }";

#[test]
fn extreme_roughness_and_ior_stay_finite_for_every_method() {
    for (what, sphere) in [
        ("conductor alpha 1e-4", "type = \"conductor\"\nfresnel = 0.9\nalpha = 1e-4"),
        ("conductor alpha 2e-3", "type = \"conductor\"\nfresnel = 0.9\nalpha = 2e-3"),
        ("conductor alpha 1", "type = \"conductor\"\nfresnel = 0.9\nalpha = 1.0"),
        ("dielectric IOR 1.0001", "type = \"dielectric\"\nior = 1.0001\nalpha = 0.01"),
        ("dielectric IOR 1.0001 smooth", "type = \"dielectric\"\nior = 1.0001"),
        ("dielectric IOR 4", "type = \"dielectric\"\nior = 4.0"),
        ("dielectric IOR 4 alpha 1", "type = \"dielectric\"\nior = 4.0\nalpha = 1.0"),
        ("dielectric IOR 1.5 alpha 1e-4", "type = \"dielectric\"\nior = 1.5\nalpha = 1e-4"),
        ("dispersive glass", "type = \"dielectric\"\nior = \"BK7\"\nalpha = 0.05"),
    ] {
        render_every_method(&test_scene(sphere, 1.0, 5.0, WHITE), 12, 10, what);
    }
}

/// A GGX conductor of alpha 2e-3 (just rough, above the 1e-3 threshold where it becomes the
/// smooth mirror) renders like the mirror; alpha 1e-4 is the mirror.
#[test]
fn nearly_smooth_rough_conductor_converges_to_the_mirror() {
    let render = |alpha: &str| {
        let s =
            write_scene(&test_scene(&format!("type = \"conductor\"\nfresnel = 0.9\n{alpha}"), 1.0, 5.0, WHITE), &[]);
        let ov = JobOverrides {
            width: Some(24),
            height: Some(20),
            spp: Some(1024),
            seed: Some(5),
            method: Some("pt".into()),
            ..Default::default()
        };
        render_file(&s.path, &ov).image.channel(quasar::film::LUMINANCE).unwrap().to_vec()
    };
    let mirror = render("alpha = 0");
    for alpha in ["alpha = 1e-4", "alpha = 2e-3"] {
        let e = rel_mse(&render(alpha), &mirror);
        eprintln!("{alpha}: relMSE vs mirror {e:.5}");
        assert!(e < 0.01, "{alpha}: relMSE {e} against the mirror");
    }
}

/// The same scene at 1e-4 m, 1 m and 1e5 m renders the same image (radiance does not depend on
/// scale), with every method.
#[test]
fn scene_scale_from_1e_minus_4_to_1e5_metres_gives_the_same_image() {
    let reference: Vec<(&str, ExrImage)> =
        render_every_method(&test_scene("type = \"diffuse\"\nreflectance = 0.5", 1.0, 5.0, WHITE), 16, 12, "scale 1");
    for scale in [1e-4, 1e5] {
        let imgs = render_every_method(
            &test_scene("type = \"diffuse\"\nreflectance = 0.5", scale, 5.0, WHITE),
            16,
            12,
            "scale",
        );
        for ((name, a), (_, r)) in imgs.iter().zip(&reference) {
            let (ma, mr) =
                (mean(a.channel(quasar::film::LUMINANCE).unwrap()), mean(r.channel(quasar::film::LUMINANCE).unwrap()));
            eprintln!("scale {scale:e} {name}: mean {ma:.5} vs {mr:.5}");
            assert!((ma - mr).abs() < 0.05 * mr, "scale {scale:e}, {name}: mean {ma} vs {mr} at 1 m");
        }
    }
}

/// Radiance 2^-66 and 2^66 (about 1.4e-20 and 7.4e19) give the image of radiance 1 scaled by
/// exactly that factor (same seed, same paths), for every method. The factors are powers of two,
/// so every product scales without rounding: with 1e-20 and 1e20 a path's Russian-roulette or
/// sampling decision could flip on a last-bit difference (for one seed in six, one photon of
/// `vismap` took another path and a pixel doubled; radiance 1e-3 did the same, 2 and 1024 did
/// not), which is not what this test is about.
#[test]
fn huge_and_tiny_radiance_scale_the_image_linearly() {
    let sphere = "type = \"dielectric\"\nior = 1.5\nalpha = 0.1";
    let unit = render_every_method(&test_scene(sphere, 1.0, 1.0, WHITE), 12, 10, "radiance 1");
    for k in [2f64.powi(-66), 2f64.powi(66)] {
        let imgs = render_every_method(&test_scene(sphere, 1.0, k, WHITE), 12, 10, "radiance");
        for ((name, a), (_, u)) in imgs.iter().zip(&unit) {
            let (ma, mu) = (
                mean(a.channel(quasar::film::LUMINANCE).unwrap()) / k,
                mean(u.channel(quasar::film::LUMINANCE).unwrap()),
            );
            assert!(mu > 0.0);
            assert!((ma - mu).abs() < 1e-4 * mu, "radiance {k:e}, {name}: {ma} vs {mu}");
        }
    }
}

/// A light whose spectrum is a 0.2 nm wide spike at 550 nm: rarely sampled, never NaN, and seen
/// directly it has the luminance of its integral (1e4 * 0.1 nm * ybar(550) / integral(ybar)).
#[test]
fn single_wavelength_spike_is_finite_and_has_its_luminance() {
    let spike = "{ wavelengths = [549.9, 550.0, 550.1], values = [0, 1e4, 0] }";
    render_every_method(&test_scene("type = \"diffuse\"\nreflectance = 0.5", 1.0, 1.0, spike), 12, 10, "spike");
    let s = write_scene(
        &format!(
            r#"
[camera]
position = [0, 0, 1]
target = [0, 0, 0]
fov_deg = 10
[materials.black]
type = "diffuse"
reflectance = 0
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [1, 1]
normal = [0, 0, 1]
material = "black"
emission = {{ spectrum = {spike}, scale = 1 }}
"#
        ),
        &[],
    );
    let ov = JobOverrides {
        width: Some(8),
        height: Some(8),
        spp: Some(8192),
        seed: Some(2),
        method: Some("pt".into()),
        ..Default::default()
    };
    let img = render_file(&s.path, &ov).image;
    assert_finite(&img, "spike seen directly");
    // integral of the triangle = 1e4 * 0.1 nm = 1000; ybar(550 nm) = 0.99495; integral ybar = 106.857
    let expected = 1000.0 * 0.994_950 / 106.856_895;
    let y = mean(img.channel(quasar::film::LUMINANCE).unwrap());
    eprintln!("spike: Y {y} expected {expected}");
    assert!((y - expected).abs() < 0.1 * expected, "spike luminance {y}, expected {expected}");
}

/// Degenerate (zero-area, collinear, repeated-vertex) and sliver triangles, and a zero-area
/// emitter: nothing breaks, and the zero-area light emits nothing.
#[test]
fn degenerate_triangles_and_zero_area_lights() {
    let obj = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1e-9 0\nv 0.5 0.5 0\nv 1 1 1e-8\n\
               f 1 2 3\nf 1 1 2\nf 1 2 4\nf 1 5 6\nf 2 5 5\n";
    let scene = r#"
[camera]
position = [0.5, 0.5, 2]
target = [0.5, 0.3, 0]
fov_deg = 60
[materials.white]
type = "diffuse"
reflectance = 0.7
[[shape]]
type = "mesh"
file = "degenerate.obj"
material = "white"
[[shape]]
type = "mesh"
file = "degenerate.obj"
material = "white"
emission = { spectrum = { constant = 1 }, scale = 100 }
transform = { translate = [0, 0, 0.5] }
[[shape]]
type = "quad"
center = [0, -0.5, 0]
size = [4, 4]
normal = [0, 1, 0]
material = "white"
[[light]]
type = "environment"
scale = 0.5
"#;
    let s = write_scene(scene, &[("degenerate.obj", obj)]);
    for (name, ov) in every_method(12, 10, 4) {
        let img = render_file(&s.path, &ov).image;
        assert_finite(&img, &format!("degenerate, {name}"));
    }
}

/// A point light and an area light inside closed opaque spheres light nothing outside: the image
/// is exactly black for every method (no leak through ray offsets or photon gathering).
#[test]
fn lights_inside_closed_objects_do_not_leak() {
    let scene = r#"
[camera]
position = [0, 1, 4]
target = [0, 0.5, 0]
fov_deg = 50
[materials.white]
type = "diffuse"
reflectance = 0.8
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [6, 6]
normal = [0, 1, 0]
material = "white"
[[shape]]
type = "sphere"
center = [-0.8, 0.6, 0]
radius = 0.5
material = "white"
[[shape]]
type = "sphere"
center = [0.8, 0.6, 0]
radius = 0.5
material = "white"
[[shape]]
type = "sphere"
center = [0.8, 0.6, 0]
radius = 0.2
subdivisions = 1
material = "white"
emission = { spectrum = { constant = 1 }, scale = 50 }
[[light]]
type = "point"
position = [-0.8, 0.6, 0]
scale = 100
"#;
    for (name, img) in render_every_method(scene, 16, 12, "lights inside") {
        let y = img.channel(quasar::film::LUMINANCE).unwrap();
        assert!(y.iter().all(|&v| v == 0.0), "{name}: light leaked, max {}", y.iter().cloned().fold(0.0, f32::max));
    }
}

/// The camera inside a closed glass sphere sees the lit room through it: finite, not black, and
/// the bidirectional methods agree with pt on the image mean within 10%.
#[test]
fn camera_inside_glass() {
    let scene = r#"
[camera]
position = [0, 0.5, 0]
target = [0, 0.2, -1]
fov_deg = 70
[materials.white]
type = "diffuse"
reflectance = 0.7
[materials.glass]
type = "dielectric"
ior = 1.5
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [8, 8]
normal = [0, 1, 0]
material = "white"
[[shape]]
type = "sphere"
center = [0, 0.5, 0]
radius = 0.3
material = "glass"
[[shape]]
type = "quad"
center = [0, 3, 0]
size = [2, 2]
normal = [0, -1, 0]
material = "white"
emission = { spectrum = { constant = 1 }, scale = 5 }
"#;
    let s = write_scene(scene, &[]);
    let pt = JobOverrides {
        width: Some(12),
        height: Some(10),
        spp: Some(512),
        seed: Some(1),
        method: Some("pt".into()),
        ..Default::default()
    };
    let r = mean(render_file(&s.path, &pt).image.channel(quasar::film::LUMINANCE).unwrap());
    assert!(r > 0.0);
    for (name, img) in render_every_method(scene, 12, 10, "camera inside glass") {
        let m = mean(img.channel(quasar::film::LUMINANCE).unwrap());
        eprintln!("camera inside glass, {name}: mean {m:.5} vs pt {r:.5}");
        assert!(m > 0.0, "{name}: black");
        if name != "pt" {
            let ov = every_method(12, 10, 1).into_iter().find(|(n, _)| *n == name).unwrap().1;
            let ov = ov.with_param("iterations", 128u32).with_param("photons_per_iteration", 20_000u32);
            let m = mean(render_file(&s.path, &ov).image.channel(quasar::film::LUMINANCE).unwrap());
            assert!((m - r).abs() < 0.1 * r, "{name}: mean {m} vs pt {r}");
        }
    }
}

/// Grazing incidence: a camera 1e-6 m above a huge floor looking along it (cos of the floor hits
/// below 1e-6), with a rough conductor and a narrow dielectric floor.
#[test]
fn grazing_incidence_stays_finite() {
    for floor in ["type = \"conductor\"\nfresnel = 0.9\nalpha = 0.01", "type = \"dielectric\"\nior = 1.5\nalpha = 0.02"]
    {
        let scene = format!(
            r#"
[camera]
position = [0, 1e-6, 0]
target = [0, 1e-6, -1]
fov_deg = 30
[materials.floor]
{floor}
[materials.white]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [1e4, 1e4]
normal = [0, 1, 0]
material = "floor"
[[shape]]
type = "quad"
center = [0, 1, -50]
size = [20, 4]
normal = [0, 0, 1]
material = "white"
emission = {{ spectrum = {{ constant = 1 }}, scale = 2 }}
[[light]]
type = "environment"
scale = 0.2
"#
        );
        render_every_method(&scene, 12, 10, "grazing");
    }
}

/// Zero-area and exactly duplicated triangles are dropped at compile time: they can never be hit
/// (or only z-fight), and masses of them made the BVH build quadratic (a fuzz-style input of
/// 20,000 copies of one triangle took 9 s; a sphere of radius 1e-45 hung).
#[test]
fn duplicate_and_zero_area_triangles_are_dropped() {
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e-45 0 0\n");
    for i in 0..20_000 {
        obj += if i % 2 == 0 { "f 1 2 3\n" } else { "f 2 3 1\n" };
    }
    obj += "f 1 4 1\nf 3 2 1\n"; // zero area; the reversed (back-facing) copy is kept
    let s = write_scene(
        "[[shape]]\ntype = \"mesh\"\nfile = \"m.obj\"\nmaterial = \"m\"\n[materials.m]\ntype = \"diffuse\"\nreflectance = 0.5\n",
        &[("m.obj", &obj)],
    );
    let desc = quasar::render::job::load_scene(&s.path).unwrap();
    let scene = quasar::core::scene::Scene::compile(&desc).unwrap();
    assert_eq!(scene.triangle_count(), 2);
    assert_eq!(scene.dropped_triangles, 20_000);
}
