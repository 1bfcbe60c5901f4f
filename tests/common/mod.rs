//! Helpers shared by the integration tests: write a scene into a temporary directory and render it.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use quasar::render::job::{JobOutput, JobOverrides, load_scene, render_desc};

/// A temporary directory holding one scene file.
pub struct TempScene {
    /// Keeps the directory alive.
    pub dir: tempfile::TempDir,
    /// The scene file.
    pub path: PathBuf,
}

/// Writes `toml` as `scene.toml` (plus extra files) into a fresh temporary directory.
pub fn write_scene(toml: &str, extra: &[(&str, &str)]) -> TempScene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, toml).unwrap();
    for (name, text) in extra {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    TempScene { dir, path }
}

/// Renders a scene file with the given overrides.
pub fn render_file(path: &Path, ov: &JobOverrides) -> JobOutput {
    let desc = load_scene(path).unwrap_or_else(|e| panic!("{e:#}"));
    render_desc(&desc, ov, false).unwrap_or_else(|e| panic!("{e:#}"))
}

/// Relative mean squared error of `a` against reference `r`: [`quasar::tools::compare::rel_mse`] (the
/// metric of `quasar compare`), for images of the same size.
pub fn rel_mse(a: &[f32], r: &[f32]) -> f64 {
    assert_eq!(a.len(), r.len());
    quasar::tools::compare::rel_mse(a, r)
}

/// Mean relative error of `a` against reference `r`: [`quasar::tools::compare::mean_rel_error`], for
/// images of the same size.
pub fn mean_rel_error(a: &[f32], r: &[f32]) -> f64 {
    assert_eq!(a.len(), r.len());
    quasar::tools::compare::mean_rel_error(a, r)
}

/// Mean of a slice.
pub fn mean(v: &[f32]) -> f64 {
    v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64
}

/// Luminance of layer `name` from its `name.R/G/B` channels.
pub fn layer_luminance(img: &quasar::output::ExrImage, name: &str) -> Vec<f32> {
    let c = |k: &str| img.channel(&format!("{name}.{k}")).unwrap();
    let (r, g, b) = (c("R"), c("G"), c("B"));
    (0..r.len()).map(|i| quasar::materials::spectrum::color::srgb_luminance([r[i], g[i], b[i]])).collect()
}

/// A closed white furnace: a diffuse sphere of albedo `a` seen from its centre, emitting `le`
/// from its inner surface, in a `size` x `size` image. Its radiance is Le / (1 - a) everywhere
/// (the geometric series of bounces).
pub fn furnace_scene(a: f64, le: f64, size: u32) -> TempScene {
    furnace_scene_emitting(a, "{ constant = 1.0 }", le, size)
}

/// [`furnace_scene`] whose inner surface emits `scale` times the TOML spectrum `spectrum` (an
/// inline table such as `{ wavelengths = [...], values = [...] }`).
pub fn furnace_scene_emitting(a: f64, spectrum: &str, scale: f64, size: u32) -> TempScene {
    write_scene(
        &format!(
            r#"
[render]
width = {size}
height = {size}
[camera]
position = [0, 0, 0]
target = [0, 0, -1]
fov_deg = 60
[materials.wall]
type = "diffuse"
reflectance = {{ constant = {a} }}
[[shape]]
type = "sphere"
center = [0, 0, 0]
radius = 1.0
material = "wall"
flip_normals = true
emission = {{ spectrum = {spectrum}, scale = {scale} }}
"#
        ),
        &[],
    )
}

/// Checks a furnace render: Y = Le / (1 - a) within 1%, and the layers emission = Le (1%),
/// direct = a Le (2%) and indirect = a^2 Le / (1 - a) (3%).
pub fn check_furnace(img: &quasar::output::ExrImage, a: f64, le: f64, label: &str) {
    let y = mean(img.channel("XYZ.Y").unwrap());
    let e = mean(&layer_luminance(img, "emission"));
    let d = mean(&layer_luminance(img, "direct"));
    let i = mean(&layer_luminance(img, "indirect"));
    eprintln!("furnace {label}: Y {y:.5} emission {e:.5} direct {d:.5} indirect {i:.5}");
    let expected = le / (1.0 - a);
    assert!((y - expected).abs() / expected < 0.01, "{label}: furnace radiance {y}, expected {expected}");
    assert!((e - le).abs() < 0.01 * le, "{label}: emission {e}");
    assert!((d - a * le).abs() < 0.02 * a * le, "{label}: direct {d}");
    let ind = a * a * le / (1.0 - a);
    assert!((i - ind).abs() < 0.03 * ind, "{label}: indirect {i}");
}

/// A 40 x 30 scene of a glossy floor mirroring a lit diffuse wall and sphere (secondary
/// highlights): `floor` is the `[materials.floor]` table of the floor.
pub fn glossy_floor_scene(floor: &str) -> String {
    GLOSSY_FLOOR.replace("FLOOR", floor)
}

const GLOSSY_FLOOR: &str = r#"
[render]
width = 40
height = 30
[camera]
position = [0, 0.6, 2.4]
target = [0, 0.3, 0]
fov_deg = 45
FLOOR
[materials.wall]
type = "diffuse"
reflectance = { rgb = [0.8, 0.5, 0.3] }
[materials.white]
type = "diffuse"
reflectance = 0.7
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [3, 3]
normal = [0, 1, 0]
material = "floor"
[[shape]]
type = "quad"
center = [0, 1, -1.2]
size = [3, 2]
normal = [0, 0, 1]
material = "wall"
[[shape]]
type = "sphere"
center = [0.3, 0.3, -0.3]
radius = 0.3
subdivisions = 3
material = "white"
[[shape]]
type = "quad"
center = [-0.5, 1.6, 0.2]
size = [0.5, 0.5]
normal = [0, -1, 0]
material = "white"
emission = { spectrum = { blackbody = 5000 }, scale = 6.0 }
[[light]]
type = "environment"
scale = 0.05
"#;

/// A shipped scene file (`scenes/<name>`).
pub fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)
}

/// Overrides for a `pt` render of `spp` samples at `w` x `h`.
pub fn pt_ov(w: u32, h: u32, spp: u32, seed: u64) -> JobOverrides {
    JobOverrides {
        width: Some(w),
        height: Some(h),
        spp: Some(spp),
        seed: Some(seed),
        method: Some("pt".into()),
        ..Default::default()
    }
}

/// Where the ray through image point `f` (pixels) meets the floor plane y = 0.
pub fn floor_hit(camera: &quasar::core::camera::Camera, f: glam::Vec2) -> glam::Vec3 {
    let r = camera.ray(f);
    r.origin + r.dir * (-r.origin.y / r.dir.y)
}

/// The mean of `f` (a function of the image point, in pixels) over pixel (`px`, `py`) by a
/// `k` x `k` midpoint rule: the expected value of a pixel whose samples are jittered over it.
pub fn pixel_mean(px: u32, py: u32, k: u32, f: impl Fn(glam::Vec2) -> f64) -> f64 {
    let mut sum = 0.0;
    for a in 0..k {
        for b in 0..k {
            sum += f(glam::Vec2::new(px as f32 + (a as f32 + 0.5) / k as f32, py as f32 + (b as f32 + 0.5) / k as f32));
        }
    }
    sum / f64::from(k * k)
}

/// Checks an image of estimates `got` with standard errors `sigma` against the expected pixel
/// values `want`: every pixel within 4.5 standard errors, the image mean within 4 of its
/// standard error, and the same test must reject `want` scaled by `1 + bias` (so it can see a
/// bias of that size). Returns the worst pixel |z|, the image mean ratio and its z.
pub fn assert_z_image(label: &str, got: &[f64], sigma: &[f64], want: &[f64], bias: f64) -> (f64, f64, f64) {
    let mut worst = 0.0f64;
    for (i, ((g, s), w)) in got.iter().zip(sigma).zip(want).enumerate() {
        let z = (g - w) / s;
        worst = worst.max(z.abs());
        assert!(z.abs() < 4.5, "{label}: pixel {i}: {g:.5} +- {s:.5}, expected {w:.5} (z {z:.2})");
    }
    let (sum_got, sum_want): (f64, f64) = (got.iter().sum(), want.iter().sum());
    let se = sigma.iter().map(|s| s * s).sum::<f64>().sqrt();
    let z = (sum_got - sum_want) / se;
    let z_biased = (sum_got - (1.0 + bias) * sum_want) / se;
    eprintln!("{label}: worst pixel |z| {worst:.2}; image mean ratio {:.5} (z {z:.2})", sum_got / sum_want);
    assert!(z.abs() < 4.0, "{label}: the image mean is off: ratio {} (z {z:.2})", sum_got / sum_want);
    assert!(z_biased.abs() > 4.0, "{label}: a {bias} error would pass (z {z_biased:.2})");
    (worst, sum_got / sum_want, z)
}

/// Overrides for the `illuminance.Y` layer of a 12 x 12 image at `samples` per pixel (1 spp
/// `pt`, the scenes' default seed 0, 2 threads).
pub fn illuminance_layer_ov(samples: u32) -> JobOverrides {
    JobOverrides { threads: Some(2), illuminance_samples: Some(samples), ..pt_ov(12, 12, 1, 0) }
}

/// Overrides for a bidirectional `method` render of `iterations` with `photons` per iteration.
pub fn bidir_ov(w: u32, h: u32, method: &str, iterations: u32, photons: u64, seed: u64) -> JobOverrides {
    JobOverrides {
        width: Some(w),
        height: Some(h),
        seed: Some(seed),
        method: Some(method.into()),
        ..Default::default()
    }
    .with_param("iterations", iterations)
    .with_param("photons_per_iteration", photons)
}

/// The beauty and every layer.
pub const ALL_QUANTITIES: [quasar::film::Quantity; quasar::film::N_QUANTITIES] = quasar::film::Quantity::ALL;

/// Runs the block z-test ([`quasar::tools::ztest`], finest blocks of `base` pixels) of `image` against
/// `reference` for each quantity (beauty and layers, luminance), prints the reports and returns
/// them.
pub fn z_test_from(
    base: usize,
    label: &str,
    image: &JobOutput,
    reference: &JobOutput,
    quantities: &[quasar::film::Quantity],
) -> Vec<quasar::tools::ztest::ZReport> {
    use quasar::tools::ztest::{Estimate, ZTest};
    quantities
        .iter()
        .map(|&q| {
            let a = Estimate::from_film(&image.result.film, q);
            let b = Estimate::from_film(&reference.result.film, q);
            let r = ZTest { base, ..ZTest::default() }.run(&a, &b).unwrap();
            let text = r.to_string();
            eprintln!(
                "{label} [{}]: {}",
                q.name(),
                if r.failed() { text.as_str() } else { text.lines().next().unwrap_or("") }
            );
            r
        })
        .collect()
}

/// [`assert_converges_from`] the finest blocks ([`quasar::film::BLOCK_BASE`] pixels).
pub fn assert_converges(
    label: &str,
    image: &JobOutput,
    reference: &JobOutput,
    quantities: &[quasar::film::Quantity],
) -> quasar::tools::ztest::ZReport {
    assert_converges_from(quasar::film::BLOCK_BASE, label, image, reference, quantities)
}

/// [`z_test_from`], failing the test when any quantity fails; returns the first quantity's
/// report. A `base` above the finest blocks is for estimates that are heavy-tailed in small
/// blocks at the test's budget (photon density estimates of sparse caustics or on narrow lobes:
/// most small blocks see no photon of the kind, a few see a large one, and their sample
/// variance understates the error); they are tested where enough photons fall per block.
pub fn assert_converges_from(
    base: usize,
    label: &str,
    image: &JobOutput,
    reference: &JobOutput,
    quantities: &[quasar::film::Quantity],
) -> quasar::tools::ztest::ZReport {
    let reports = z_test_from(base, label, image, reference, quantities);
    for (r, q) in reports.iter().zip(quantities) {
        assert!(!r.failed(), "{label} [{}] differs from the reference beyond its standard errors:\n{r}", q.name());
    }
    reports.into_iter().next().unwrap()
}

/// The image's mean luminance and its standard error: from the per-pixel errors for the per-pixel
/// methods, from the whole image's batch statistics (the largest `stderr.block` channel) for the
/// bidirectional ones, whose pixels share an iteration's wavelengths.
pub fn mean_and_error(img: &quasar::output::ExrImage) -> (f64, f64) {
    let y = img.channel(quasar::film::LUMINANCE).unwrap();
    let n = y.len() as f64;
    let mean = y.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
    let whole = img
        .channels
        .iter()
        .filter(|c| c.name.starts_with("stderr.block"))
        .max_by_key(|c| c.name.trim_start_matches("stderr.block").parse::<usize>().unwrap_or(0));
    let se = match whole {
        Some(c) => f64::from(c.values[0]),
        None => img.channel("stderr.Y").unwrap().iter().map(|&s| f64::from(s).powi(2)).sum::<f64>().sqrt() / n,
    };
    (mean, se)
}

/// 64 samples per pixel (or iterations) with seed 3, and 1000 photons per iteration for the
/// methods that trace photons: a quick render of a small analytic scene.
pub fn quick_ov(method: &str) -> JobOverrides {
    let ov = JobOverrides { spp: Some(64), seed: Some(3), method: Some(method.into()), ..Default::default() };
    if quasar::integrator::method::find(method).unwrap().params.iter().any(|p| p.key == "photons_per_iteration") {
        ov.with_param("photons_per_iteration", 1000u32)
    } else {
        ov
    }
}

/// A transmitting sphere (radius 0.3 m, its material's keys `sphere`) on a diffuse
/// floor under a small area light and a dim sky, 40x30: its shadow and caustic come from photons
/// and camera paths that cross it (the media tests).
pub fn sphere_on_floor_scene(sphere: &str) -> TempScene {
    write_scene(&SPHERE_ON_FLOOR.replace("SPHERE_KEYS", sphere), &[])
}

const SPHERE_ON_FLOOR: &str = r#"
[render]
width = 40
height = 30
[camera]
position = [0, 1.2, 2.2]
target = [0, 0.2, 0]
fov_deg = 40
[materials.floor]
type = "diffuse"
reflectance = 0.6
[materials.sphere]
SPHERE_KEYS
[materials.black]
type = "diffuse"
reflectance = 0
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [4, 4]
normal = [0, 1, 0]
material = "floor"
[[shape]]
type = "sphere"
center = [0, 0.3, 0]
radius = 0.3
subdivisions = 3
material = "sphere"
[[shape]]
type = "quad"
center = [0.3, 1.6, -0.3]
size = [0.4, 0.4]
normal = [0, -1, 0]
material = "black"
emission = { spectrum = { constant = 1 }, scale = 20 }
[[light]]
type = "environment"
scale = 0.05
"#;

/// Every bidirectional method on `scene` (256 iterations of 20,000 photons, 40x30) passes the
/// block z-tests against `reference` (`pt`): finite, the beauty and the first layers at 8-pixel
/// blocks, the others at 16.
pub fn assert_bidirectional_methods_converge(scene: &Path, reference: &JobOutput) {
    assert_methods_converge(scene, reference, &["vismap", "adaptive", "quasi", "adaptive+quasi"]);
}

/// [`assert_bidirectional_methods_converge`] for the bidirectional `methods` named.
pub fn assert_methods_converge(scene: &Path, reference: &JobOutput, methods: &[&str]) {
    for &method in methods {
        let img = render_file(scene, &bidir_ov(40, 30, method, 256, 20_000, 7));
        assert!(img.image.channel(quasar::film::LUMINANCE).unwrap().iter().all(|v| v.is_finite()));
        assert_converges_from(8, method, &img, reference, &ALL_QUANTITIES[..3]);
        assert_converges_from(16, method, &img, reference, &ALL_QUANTITIES[3..]);
    }
}

/// The layer of the film named `name` (`emission`, `direct`, `indirect`, `caustic`).
pub fn layer(name: &str) -> quasar::film::Quantity {
    quasar::film::Quantity::Layer(quasar::film::LAYER_NAMES.iter().position(|&l| l == name).unwrap())
}

/// Two quads bounding a slab of material `m` between z = -half and z = half (metres), normals
/// outwards.
pub fn slab(m: &str, half: f32) -> String {
    format!(
        "[[shape]]\ntype = \"quad\"\ncenter = [0, 0, {half}]\nsize = [4, 4]\nnormal = [0, 0, 1]\nmaterial = \"{m}\"\n\
         [[shape]]\ntype = \"quad\"\ncenter = [0, 0, {}]\nsize = [4, 4]\nnormal = [0, 0, -1]\nmaterial = \"{m}\"\n",
        -half
    )
}
