//! Method benchmarks (not a criterion harness: each figure is one render, and the renders are
//! long): photon-pass throughput of `vismap`, memory per visibility point, and the equal-time
//! error of each method against a converged reference on the shipped scenes. Results go into
//! BENCHMARKS.md.
//!
//! Run: `cargo bench --bench methods` (environment: QUASAR_BENCH_REF_SPP and
//! QUASAR_BENCH_REF_ITERATIONS for the references, QUASAR_BENCH_TIMES for the budgets,
//! QUASAR_BENCH_THROUGHPUT=0 to skip the photon throughput part).

use std::path::Path;
use std::time::Instant;

use quasar::integrator::bidir::passes::Bidirectional;
use quasar::integrator::bidir::settings::{GatherDepth, VismapSettings};
use quasar::integrator::bidir::{gather_disk, photon_pass, visibility_point};
use quasar::render::driver::{self, DriverOptions};
use quasar::render::job::{JobOverrides, load_scene, render_desc};
use quasar::tools::convergence;

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn photon_throughput(scene_path: &str) {
    let desc = load_scene(Path::new(scene_path)).expect("scene loads");
    let scene = quasar::core::scene::Scene::compile(&desc).unwrap();
    let camera = quasar::core::camera::Camera::new(&desc.camera, 160, 120).unwrap();
    for threads in [1, 2] {
        for depth in [0, 1] {
            let settings = VismapSettings {
                iterations: 8,
                photons_per_iteration: Some(200_000),
                depth: GatherDepth::Fixed(depth),
                ..VismapSettings::default()
            };
            let isa = quasar::core::isa::Isa::best();
            let mut method = Bidirectional::new(&scene, &camera, settings, 1, (0, 1), isa);
            let opts = DriverOptions { units: settings.iterations, threads: Some(threads), ..Default::default() };
            let t = Instant::now();
            let result = driver::run(&mut method, &scene, &camera, &opts).expect("render runs");
            let stats = method.stats;
            let total = t.elapsed().as_secs_f64();
            let points = result.film.pixels.len();
            let per_point = std::mem::size_of::<visibility_point::VisibilityPoint>()
                + std::mem::size_of::<gather_disk::GatherDisk>()
                + std::mem::size_of::<photon_pass::DiskCoverage>()
                + std::mem::size_of::<photon_pass::PhotonSums>()
                + std::mem::size_of::<quasar::materials::spectrum::SampledWavelengths>();
            println!(
                "{scene_path} {threads}t depth {depth}: {:.3} Mphotons/s, {:.3} M lookups/s (photon pass {:.2} s of {:.2} s); \
                 {} bytes per visibility point + grid {:.1} bytes per point",
                stats.photons as f64 / stats.photon_seconds / 1e6,
                stats.lookups as f64 / stats.photon_seconds / 1e6,
                stats.photon_seconds,
                total,
                per_point,
                stats.grid_bytes as f64 / points as f64,
            );
        }
    }
}

/// The methods compared (see `quasar bench convergence --methods`).
const METHODS: &str = "pt,vismap:0,vismap:1,adaptive,adaptive:paper,quasi,adaptive+quasi";

/// Error-vs-time curves of every method against `reference` (a converged render), printed as a
/// markdown table with the time each needs to reach `target`.
fn equal_time(scene_path: &str, w: u32, h: u32, reference: &[f32], times: &[f64], target: f64) {
    let desc = load_scene(Path::new(scene_path)).expect("scene loads");
    let photons = (w * h * 4) as u64;
    let base = JobOverrides { width: Some(w), height: Some(h), seed: Some(1), ..Default::default() }
        .with_param("photons_per_iteration", photons);
    let methods = convergence::parse_methods(METHODS).unwrap();
    let points = convergence::run(&desc, &base, &methods, times, reference, |_| {}).unwrap();
    println!("\n{scene_path} ({w}x{h}, {photons} photons per iteration): relMSE vs seconds");
    print!("{}", convergence::markdown_table(&points, target));
}

/// A pt reference render (`spp` samples per pixel) of the luminance.
fn pt_reference(scene_path: &str, w: u32, h: u32, spp: u32) -> Vec<f32> {
    let desc = load_scene(Path::new(scene_path)).expect("scene loads");
    let t = Instant::now();
    let y = convergence::pt_reference(&desc, w, h, spp, 1000, false).unwrap();
    println!("{scene_path}: reference pt {w}x{h} {spp} spp in {:.1} s", t.elapsed().as_secs_f64());
    y
}

/// A long `quasi` reference (for scenes where pt does not converge in reasonable time).
fn quasi_reference(scene_path: &str, w: u32, h: u32, iterations: u32, radius: f32) -> Vec<f32> {
    let desc = load_scene(Path::new(scene_path)).expect("scene loads");
    let t = Instant::now();
    let ov = JobOverrides {
        width: Some(w),
        height: Some(h),
        seed: Some(1000),
        method: Some("quasi".into()),
        ..Default::default()
    }
    .with_param("iterations", iterations)
    .with_param("photons_per_iteration", (w * h * 16) as u64)
    .with_param("radius", radius);
    let y = render_desc(&desc, &ov, false).unwrap().image.channel(quasar::film::LUMINANCE).unwrap().to_vec();
    println!(
        "{scene_path}: reference quasi {w}x{h} {iterations} iterations, radius {radius} in {:.1} s",
        t.elapsed().as_secs_f64()
    );
    y
}

fn main() {
    // `cargo bench` passes --bench; nothing else is accepted.
    let ref_spp = env_or("QUASAR_BENCH_REF_SPP", 16384u32);
    let times: String = env_or("QUASAR_BENCH_TIMES", "1,2,4,8,16".into());
    let times: Vec<f64> = times.split(',').filter_map(|t| t.parse().ok()).collect();
    let glass = "scenes/glass-plate/glass-plate.toml";
    let lightguide = "scenes/lightguide/lightguide.toml";
    if env_or("QUASAR_BENCH_THROUGHPUT", 1u32) == 1 {
        photon_throughput(glass);
        photon_throughput("scenes/cornell-box/cornell-box.toml");
    }
    let r = pt_reference(glass, 64, 48, ref_spp);
    equal_time(glass, 64, 48, &r, &times, 0.02);
    let r = quasi_reference(lightguide, 64, 32, env_or("QUASAR_BENCH_REF_ITERATIONS", 2048u32), 0.0005);
    equal_time(lightguide, 64, 32, &r, &times, 0.1);
}
