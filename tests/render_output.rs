//! Properties of every render: layers add up, no NaN/inf, determinism across thread counts,
//! the EXR's channels and header.

mod common;

use common::{render_file, write_scene};
use quasar::output::read_exr;
use quasar::render::job::{JobOverrides, write_outputs};

/// A small closed box with an area light, a glass sphere, a rough metal sphere and a two-sided
/// diffuse quad: every material and a caustic path.
const BOX: &str = r#"
[render]
width = 20
height = 16
[camera]
position = [0, 1, 3.2]
target = [0, 1, 0]
fov_deg = 50
[materials.white]
type = "diffuse"
reflectance = { rgb = [0.8, 0.8, 0.8] }
[materials.red]
type = "diffuse"
reflectance = { rgb = [0.8, 0.1, 0.1] }
two_sided = true
[materials.glass]
type = "dielectric"
ior = "BK7"
[materials.rough_glass]
type = "dielectric"
ior = 1.5
alpha = 0.2
[materials.metal]
type = "conductor"
alpha = 0.1
fresnel = { constant = 0.9 }
[[shape]]
type = "quad"
corner = [-1, 0, 1]
edge1 = [2, 0, 0]
edge2 = [0, 0, -2]
material = "white"
[[shape]]
type = "quad"
corner = [-1, 2, -1]
edge1 = [2, 0, 0]
edge2 = [0, 0, 2]
material = "white"
[[shape]]
type = "quad"
corner = [-1, 0, -1]
edge1 = [2, 0, 0]
edge2 = [0, 2, 0]
material = "white"
[[shape]]
type = "quad"
corner = [-1, 0, 1]
edge1 = [0, 0, -2]
edge2 = [0, 2, 0]
material = "red"
[[shape]]
type = "quad"
corner = [-0.3, 1.99, -0.3]
edge1 = [0.6, 0, 0]
edge2 = [0, 0, 0.6]
material = "white"
emission = { spectrum = { blackbody = 4000 }, scale = 20 }
[[shape]]
type = "sphere"
center = [-0.4, 0.4, -0.2]
radius = 0.35
material = "glass"
[[shape]]
type = "sphere"
center = [0.45, 0.3, 0.2]
radius = 0.3
material = "metal"
[[shape]]
type = "sphere"
center = [0.3, 1.2, -0.5]
radius = 0.2
material = "rough_glass"
"#;

#[test]
fn beauty_is_the_sum_of_layers_and_every_pixel_is_finite() {
    let scene = write_scene(BOX, &[]);
    let out = render_file(&scene.path, &JobOverrides { spp: Some(16), seed: Some(5), ..Default::default() });
    let img = &out.image;
    for c in ["R", "G", "B"] {
        let beauty = img.channel(c).unwrap();
        let e = img.channel(&format!("emission.{c}")).unwrap();
        let d = img.channel(&format!("direct.{c}")).unwrap();
        let i = img.channel(&format!("indirect.{c}")).unwrap();
        for k in 0..beauty.len() {
            assert!(beauty[k].is_finite());
            let sum = e[k] + d[k] + i[k];
            assert!((beauty[k] - sum).abs() <= 4.0 * f32::EPSILON * sum.abs().max(1e-30), "pixel {k} {c}");
        }
    }
    for ch in &img.channels {
        if ch.name != "depth.Z" {
            assert!(ch.values.iter().all(|v| v.is_finite()), "{} has a non-finite value", ch.name);
        }
    }
    // something of each kind of light transport is there
    assert!(common::mean(img.channel("emission.R").unwrap()) > 0.0);
    assert!(common::mean(img.channel("direct.R").unwrap()) > 0.0);
    assert!(common::mean(img.channel("indirect.R").unwrap()) > 0.0);
}

#[test]
fn same_seed_gives_bit_identical_pixels_with_one_and_two_threads() {
    let scene = write_scene(BOX, &[]);
    let run = |threads| {
        render_file(
            &scene.path,
            &JobOverrides { spp: Some(4), seed: Some(42), threads: Some(threads), ..Default::default() },
        )
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.image.channels.len(), b.image.channels.len());
    for (ca, cb) in a.image.channels.iter().zip(&b.image.channels) {
        assert_eq!(ca.name, cb.name);
        let bits_a: Vec<u32> = ca.values.iter().map(|v| v.to_bits()).collect();
        let bits_b: Vec<u32> = cb.values.iter().map(|v| v.to_bits()).collect();
        assert_eq!(bits_a, bits_b, "channel {} differs between 1 and 2 threads", ca.name);
    }
    // and a different seed gives a different image
    let c = render_file(&scene.path, &JobOverrides { spp: Some(4), seed: Some(43), ..Default::default() });
    assert_ne!(a.image.channel("R"), c.image.channel("R"));
}

#[test]
fn exr_file_has_the_layers_and_settings() {
    let scene = write_scene(BOX, &[]);
    let ov = JobOverrides { spp: Some(2), seed: Some(9), method: Some("pt".into()), ..Default::default() };
    let out = render_file(&scene.path, &ov);
    let path = scene.dir.path().join("out.exr");
    let png = scene.dir.path().join("out.png");
    write_outputs(&out, &path, Some(&png)).unwrap();
    let back = read_exr(&path).unwrap();
    let mut names: Vec<_> = back.channels.iter().map(|c| c.name.as_str()).collect();
    names.sort();
    for n in [
        "R",
        "G",
        "B",
        "XYZ.X",
        "XYZ.Y",
        "XYZ.Z",
        "emission.R",
        "emission.G",
        "emission.B",
        "direct.R",
        "direct.G",
        "direct.B",
        "indirect.R",
        "indirect.G",
        "indirect.B",
        "caustic.R",
        "caustic.G",
        "caustic.B",
        "depth.Z",
        "spp.Y",
    ] {
        assert!(names.contains(&n), "missing channel {n} in {names:?}");
    }
    // the default layer is plain RGB (a top-level Y is read as alpha by OpenImageIO)
    assert!(names.iter().filter(|n| !n.contains('.')).eq(["B", "G", "R"].iter()), "{names:?}");
    assert_eq!(back.meta("method"), Some("pt"));
    assert_eq!(back.meta("spp"), Some("2"));
    assert_eq!(back.meta("seed"), Some("9"));
    assert!(back.meta("render_time_s").is_some());
    assert_eq!(back.channel("R").unwrap(), out.image.channel("R").unwrap());
    assert!(back.channel("spp.Y").unwrap().iter().all(|&s| s == 2.0));
    assert!(image_size(&png) == (20, 16));
}

fn image_size(p: &std::path::Path) -> (u32, u32) {
    let bytes = std::fs::read(p).unwrap();
    // PNG IHDR: width and height are big-endian u32 at offsets 16 and 20
    (u32::from_be_bytes(bytes[16..20].try_into().unwrap()), u32::from_be_bytes(bytes[20..24].try_into().unwrap()))
}
