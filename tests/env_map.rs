//! Lat-long environment maps (docs/architecture.md §4): a diffuse floor under a structured sky has the
//! radiance a E / pi of the irradiance E the map's upper hemisphere gives (quadrature over its
//! texels), with pt (importance-sampled light samples + MIS) and with the photons of vismap; a
//! uniform map renders like the constant environment of the same radiance.

mod common;

use common::{bidir_ov, mean, pt_ov, render_file, write_scene};
use quasar::film::Channel;
use quasar::output::{ExrImage, write_exr_atomic};

const W: usize = 32;
const H: usize = 16;

/// A sky: a bright 3 x 2 texel "sun" in a blue gradient, a dim ground.
fn sky(x: usize, y: usize) -> [f32; 3] {
    if y >= H / 2 {
        return [0.05, 0.04, 0.03];
    }
    if (10..13).contains(&x) && (3..5).contains(&y) {
        return [40.0, 36.0, 30.0];
    }
    let t = y as f32 / (H / 2) as f32;
    [0.2 + 0.3 * t, 0.35 + 0.3 * t, 0.9]
}

fn write_map(dir: &std::path::Path, f: impl Fn(usize, usize) -> [f32; 3]) {
    let texels: Vec<[f32; 3]> = (0..W * H).map(|i| f(i % W, i / W)).collect();
    let ch = |k: usize, n: &str| Channel { name: n.into(), values: texels.iter().map(|t| t[k]).collect() };
    let img = ExrImage { width: W, height: H, channels: vec![ch(0, "R"), ch(1, "G"), ch(2, "B")], metadata: vec![] };
    write_exr_atomic(&img, &dir.join("sky.exr")).unwrap();
}

/// Luminance of the irradiance on an upward-facing plane: sum over the upper hemisphere's
/// texels of Y(rgb) times the integral of cos theta over the texel,
/// (2 pi / W) (sin^2 theta_1 - sin^2 theta_0) / 2.
fn irradiance_y(f: impl Fn(usize, usize) -> [f32; 3]) -> f64 {
    let mut e = 0.0f64;
    for y in 0..H / 2 {
        let (t0, t1) = (std::f64::consts::PI * y as f64 / H as f64, std::f64::consts::PI * (y + 1) as f64 / H as f64);
        let w = (2.0 * std::f64::consts::PI / W as f64) * (t1.sin().powi(2) - t0.sin().powi(2)) / 2.0;
        for x in 0..W {
            e += quasar::materials::spectrum::color::srgb_luminance(f(x, y)) as f64 * w;
        }
    }
    e
}

const FLOOR: &str = r#"
[camera]
position = [0, 3, 0.001]
target = [0, 0, 0]
fov_deg = 20
[materials.grey]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [100, 100]
normal = [0, 1, 0]
material = "grey"
[[light]]
type = "environment"
file = "sky.exr"
rotate_deg = 37
scale = 2.0
"#;

#[test]
fn floor_under_a_structured_sky_matches_the_quadrature() {
    let scene = write_scene(FLOOR, &[]);
    write_map(scene.dir.path(), sky);
    let expected = 0.5 * 2.0 * irradiance_y(sky) / std::f64::consts::PI;
    for (label, ov) in [("pt", pt_ov(8, 8, 1024, 1)), ("vismap", bidir_ov(8, 8, "vismap", 256, 20_000, 2))] {
        let img = render_file(&scene.path, &ov).image;
        let y = mean(img.channel(quasar::film::LUMINANCE).unwrap());
        eprintln!("{label}: floor Y {y:.5}, quadrature {expected:.5}");
        // the uplift table reproduces texel colours within 2.3e-3 (docs/validation.md)
        assert!((y / expected - 1.0).abs() < 0.01, "{label}: {y} vs {expected}");
    }
}

#[test]
fn a_uniform_map_renders_like_the_constant_environment() {
    let scene = write_scene(FLOOR, &[]);
    // scale 2 x texels 0.35 = D65 of luminance 0.7
    write_map(scene.dir.path(), |_, _| [0.35, 0.35, 0.35]);
    let constant = write_scene(
        &FLOOR.replace(
            "file = \"sky.exr\"\nrotate_deg = 37\nscale = 2.0",
            "spectrum = { illuminant = \"D65\" }\nscale = 0.7",
        ),
        &[],
    );
    let a = render_file(&scene.path, &pt_ov(8, 8, 512, 1));
    let b = render_file(&constant.path, &pt_ov(8, 8, 512, 2));
    common::assert_converges("uniform map vs constant environment", &a, &b, &common::ALL_QUANTITIES);
}

#[test]
fn bad_map_references_name_the_scene_line() {
    let scene = write_scene(&FLOOR.replace("sky.exr", "missing.exr"), &[]);
    let e = quasar::render::job::load_scene(&scene.path).unwrap_err().to_string();
    assert!(e.contains("missing.exr") && e.contains("scene.toml:"), "{e}");
    let scene = write_scene(&FLOOR.replace("scale = 2.0", "scale = 2.0\nspectrum = 1"), &[]);
    write_map(scene.dir.path(), sky);
    let e = quasar::render::job::load_scene(&scene.path).unwrap_err().to_string();
    assert!(e.contains("exclude each other"), "{e}");
}
