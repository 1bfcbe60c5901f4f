//! Method benchmarks (not a criterion harness: each figure is one render, and the renders are
//! long): photon-pass throughput of `vismap`, memory per visibility point, and the equal-time
//! error of each method against a converged reference on the shipped scenes. Results go into
//! BENCHMARKS.md.
//!
//! Run: `cargo bench --bench methods` (environment: QUASAR_BENCH_REF_SPP, QUASAR_BENCH_TIMES,
//! QUASAR_BENCH_SCENES to change the reference quality, the time budgets and the scenes).

use std::path::Path;
use std::time::Instant;

use quasar::compare::rel_mse;
use quasar::integrator::vismap::{self, GatherDepth, VismapRun, VismapSettings};
use quasar::job::{JobOverrides, load_scene, render_desc};
use quasar::method::BidirectionalOptions;

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn photon_throughput(scene_path: &str) {
    let desc = load_scene(Path::new(scene_path)).expect("scene loads");
    let scene = quasar::scene::Scene::compile(&desc).unwrap();
    let camera = quasar::camera::Camera::new(&desc.camera, 160, 120).unwrap();
    for threads in [1, 2] {
        for depth in [0, 1] {
            let settings = VismapSettings {
                iterations: 8,
                photons_per_iteration: Some(200_000),
                depth: GatherDepth::Fixed(depth),
                ..VismapSettings::default()
            };
            let run = VismapRun { seed: 1, time_limit: None, progress: false };
            let t = Instant::now();
            let (result, stats) = vismap::render(&scene, &camera, &settings, &run, threads);
            let total = t.elapsed().as_secs_f64();
            let points = result.film.pixels.len();
            let per_point = std::mem::size_of::<vismap::visibility_point::VisibilityPoint>()
                + std::mem::size_of::<vismap::photon_pass::GatherRadii>()
                + std::mem::size_of::<vismap::photon_pass::PhotonSums>()
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

fn equal_time(scene_path: &str, w: u32, h: u32, ref_spp: u32, times: &[f64]) {
    let desc = load_scene(Path::new(scene_path)).expect("scene loads");
    let base = JobOverrides { width: Some(w), height: Some(h), ..Default::default() };
    let t = Instant::now();
    let reference = render_desc(
        &desc,
        &JobOverrides { spp: Some(ref_spp), seed: Some(1000), method: Some("pt".into()), ..base.clone() },
        false,
    )
    .unwrap();
    let r = reference.image.channel("Y").unwrap().to_vec();
    println!("{scene_path}: reference pt {w}x{h} {ref_spp} spp in {:.1} s", t.elapsed().as_secs_f64());
    println!("| method | budget (s) | samples or iterations | relMSE |");
    println!("|---|---|---|---|");
    let methods: [(&str, Option<u32>); 3] = [("pt", None), ("vismap", Some(0)), ("vismap", Some(1))];
    for &budget in times {
        for (method, depth) in methods {
            let ov = JobOverrides {
                time_s: Some(budget),
                seed: Some(1),
                method: Some(method.into()),
                bidir: BidirectionalOptions {
                    gather_depth: depth,
                    photons_per_iteration: depth.map(|_| (w * h * 4) as u64),
                    ..Default::default()
                },
                ..base.clone()
            };
            let out = render_desc(&desc, &ov, false).unwrap();
            let e = rel_mse(out.image.channel("Y").unwrap(), &r);
            let name = depth.map_or(method.to_string(), |d| format!("{method} depth {d}"));
            println!("| {name} | {budget} | {} | {e:.5} |", out.result.spp);
        }
    }
}

fn main() {
    // `cargo bench` passes --bench; nothing else is accepted.
    let scenes: String =
        env_or("QUASAR_BENCH_SCENES", "scenes/glass-plate/glass-plate.toml,scenes/cornell-box/cornell-box.toml".into());
    let ref_spp = env_or("QUASAR_BENCH_REF_SPP", 16384u32);
    let times: String = env_or("QUASAR_BENCH_TIMES", "1,2,4,8".into());
    let times: Vec<f64> = times.split(',').filter_map(|t| t.parse().ok()).collect();
    for s in scenes.split(',') {
        photon_throughput(s);
    }
    for s in scenes.split(',') {
        equal_time(s, 64, 48, ref_spp, &times);
    }
}
