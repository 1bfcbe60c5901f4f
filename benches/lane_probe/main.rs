//! Lane probe (issue 15; BENCHMARKS.md "Sixth engine round: a lane probe"): how much faster
//! `pt`'s estimator runs when W paths advance together, one per SIMD lane, as Mitsuba's
//! `llvm_ad_spectral` runs its path tracer, measured before anyone rewrites the integrator, the
//! BSDFs and the lights that way, and which parts of the work lanes speed up.
//!
//! The probe is `pt`'s estimator (next-event estimation with the power heuristic against BSDF
//! sampling, emission and the environment found by BSDF-sampled rays with their MIS weights,
//! Russian roulette from the third scattering event, four hero wavelengths, quasar's ray
//! offsets) for the scenes it needs: Lambertian and non-dispersive dielectric surfaces without
//! textures or shading normals, triangle area lights and one constant environment (the Cornell
//! box, the glass plate). It keeps W paths in structure-of-arrays form and gives a lane the next
//! (pixel, sample) as soon as its path ends. The variants differ in what runs over the lanes:
//!
//! - `lanes`: the path arithmetic (emission and its MIS weight, the light sample, the BSDF and
//!   its sample, the frame, the ray offsets, Russian roulette) as loops over the W lanes that
//!   call quasar's own `DiffuseBsdf` and `DielectricBsdf` per lane; the rays traced one at a time
//!   through quasar's BVH; hit data, random numbers and spectra fetched per lane through quasar's
//!   own types;
//! - `+gather`: also the random numbers (quasar's PCG32 streams, one per lane, advanced
//!   together), hit points, materials, emission and reflectance, from lane loops over flat tables;
//! - `+packets`: also the closest hits, from a packet traversal of a binary BVH built here, all W
//!   rays against a node's box and a leaf's triangles at once (ray-parallel SIMD, as Embree's
//!   packet traversal serves Mitsuba's `rtcIntersect16`); `+shadow packets` traces the shadow
//!   rays so too;
//! - `diffuse lanes` (Lambertian scenes without an environment): `+packets` with the light
//!   sample and the BSDF sample written for lanes, without branches or `Option`s.
//!
//! Every variant draws the random numbers `pt` draws for the same seed, in `pt`'s order, and
//! finds the same hits, so every variant's image mean is the same value bit for bit, and `pt`'s
//! differs from it only through the probe's 1 nm linear spectra (3e-5 on the Cornell box). Not a
//! test and not a second renderer: a measurement of what lanes buy.
//!
//! Run (the portable build, then one for this CPU, e.g. AVX-512):
//!   cargo bench --bench lane_probe -- [SCENE] [--size N] [--spp N] [--rounds R] [--stages] [--only VARIANT]
//!   RUSTFLAGS="-C target-cpu=native" CARGO_TARGET_DIR=target/native cargo bench --bench lane_probe

// the lane loops index several arrays by the same lane, as the SIMD code they become does
#![allow(clippy::needless_range_loop)]

mod lanes;
mod packet_bvh;
mod render;
mod tables;

use std::f32::consts::FRAC_1_PI;
use std::path::Path;
use std::time::Instant;

use glam::{Vec2, Vec3};
use lanes::*;
use packet_bvh::PacketBvh;
use quasar::core::camera::Camera;
use quasar::core::geometry::ray::point_error;
use quasar::core::geometry::{NONE, Ray, offset_origin};
use quasar::core::light::Light;
use quasar::core::sampling::{
    Sampler, UNIFORM_SPHERE_PDF, cosine_hemisphere, mix64, power_heuristic, uniform_sphere, uniform_triangle,
};
use quasar::core::scene::Scene;
use quasar::integrator::per_pixel::PerPixel;
use quasar::integrator::pt::{PtSettings, russian_roulette};
use quasar::materials::bsdf::microfacet::SMOOTH_ALPHA;
use quasar::materials::bsdf::{DielectricBsdf, DiffuseBsdf, TrowbridgeReitz};
use quasar::materials::spectrum::{LAMBDA_MAX, LAMBDA_MIN, SampledSpectrum, SampledWavelengths};
use quasar::materials::{Frame, Lobe, Material, TransportMode};
use quasar::render::driver::{self, DriverOptions};
use quasar::render::job::load_scene;
use render::*;
use tables::*;

/// Hero wavelengths per path.
const NW: usize = 4;
/// Points of the 1 nm tables.
const GRID: usize = (LAMBDA_MAX - LAMBDA_MIN) as usize + 1;
/// Parts of the loop timed with `--stages`.
const N_STAGES: usize = 5;
const STAGE_NAMES: [&str; N_STAGES] = ["shadow rays", "film, new paths", "closest hits", "gathers", "path arithmetic"];

/// What the probe gathers once per scene.
struct Probe {
    tables: Tables,
    bvh: PacketBvh,
    tris: TriTable,
}

fn main() {
    let mut args = std::env::args().skip(1).filter(|a| a != "--bench");
    let mut scene_path = "scenes/cornell-box/cornell-box.toml".to_string();
    let (mut spp, mut rounds, mut size, mut show_stages) = (64u32, 3usize, 128u32, false);
    let mut only: Option<String> = None;
    while let Some(a) = args.next() {
        let mut num = |flag: &str| args.next().and_then(|v| v.parse().ok()).unwrap_or_else(|| panic!("{flag} N"));
        match a.as_str() {
            "--spp" => spp = num("--spp"),
            "--rounds" => rounds = num("--rounds") as usize,
            "--size" => size = num("--size"),
            "--stages" => show_stages = true,
            "--only" => only = args.next(),
            _ => scene_path = a,
        }
    }
    let desc = load_scene(Path::new(&scene_path)).expect("scene loads");
    let scene = Scene::compile(&desc).expect("scene compiles");
    let camera = Camera::new(&desc.camera, size, size).expect("camera");
    let tables = match Tables::new(&scene) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("{scene_path}: the probe cannot render this scene: {e}");
            std::process::exit(2);
        }
    };
    let probe = Probe { tables, bvh: PacketBvh::new(&scene), tris: TriTable::new(&scene) };
    let samples = size as f64 * size as f64 * spp as f64;
    let none = Variant { gather: false, packet: false, shadow_packet: false, diffuse_lanes: false };
    let gather = Variant { gather: true, ..none };
    let packet = Variant { packet: true, ..gather };
    let all = Variant { shadow_packet: true, ..packet };
    let hand = Variant { diffuse_lanes: true, ..packet };
    let hand1 = Variant { diffuse_lanes: true, packet: false, ..gather };
    type Run<'a> = (&'a str, Box<dyn Fn(Option<&mut [f64; N_STAGES]>) -> f64 + 'a>);
    let seed = 1;
    let (scene, probe, camera) = (&scene, &probe, &camera);
    let mut probes: Vec<Run> = vec![
        ("W=1", Box::new(move |s| render_lanes::<1>(scene, probe, camera, spp, seed, none, s))),
        ("W=16 lanes", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, none, s))),
        ("W=1 +gather", Box::new(move |s| render_lanes::<1>(scene, probe, camera, spp, seed, gather, s))),
        ("W=16 +gather", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, gather, s))),
        ("W=8 +packets", Box::new(move |s| render_lanes::<8>(scene, probe, camera, spp, seed, packet, s))),
        ("W=16 +packets", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, packet, s))),
        ("W=16 +shadow packets", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, all, s))),
        ("W=1 diffuse lanes", Box::new(move |s| render_lanes::<1>(scene, probe, camera, spp, seed, hand1, s))),
        ("W=16 diffuse lanes", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, hand, s))),
    ];
    probes.retain(|(name, _)| only.as_deref().is_none_or(|o| *name == o));
    if !probe.tables.all_diffuse() {
        probes.retain(|(name, _)| !name.contains("diffuse lanes"));
    }
    // (name, best seconds, image mean)
    let mut best: Vec<(String, f64, f64)> = Vec::new();
    let mut record = |name: &str, s: f64, mean: f64| match best.iter_mut().find(|b| b.0 == name) {
        Some(b) => b.1 = b.1.min(s),
        None => best.push((name.to_string(), s, mean)),
    };
    for _ in 0..rounds {
        let t = Instant::now();
        // `pt` as a render runs it: with its x86-64-v3 kernel where the CPU has one
        let isa = quasar::core::isa::Isa::best();
        let mut method = PerPixel::new(scene, camera, PtSettings::default(), seed, (0, 1), isa);
        let opts = DriverOptions { units: spp, threads: Some(1), ..Default::default() };
        let r = driver::run(&mut method, scene, camera, &opts).expect("render runs");
        let s = t.elapsed().as_secs_f64();
        let n: u64 = r.film.pixels.iter().map(|p| p.samples).sum();
        let sum: f64 = r.film.pixels.iter().map(|p| p.sum_y(quasar::film::Quantity::Beauty)).sum();
        record("quasar pt", s, sum / n as f64);
        for (name, f) in &probes {
            let t = Instant::now();
            let mean = f(None) / samples;
            record(name, t.elapsed().as_secs_f64(), mean);
        }
    }
    println!("{scene_path}, {size}x{size}, {spp} spp, 1 thread, best of {rounds}:");
    let base = best[0].1;
    for (name, s, mean) in &best {
        println!(
            "  {name:<21} {s:>6.3} s  {:>6.3} M samples/s  {:>5.2}x quasar pt   mean Y {mean:.6}",
            samples / s / 1e6,
            base / s
        );
    }
    if show_stages {
        println!("seconds per part of the loop (one more run each, with the clock read in every round):");
        println!("  {:<21} {}", "", STAGE_NAMES.map(|n| format!("{n:>16}")).join(""));
        for (name, f) in &probes {
            let mut st = [0.0; N_STAGES];
            f(Some(&mut st));
            println!("  {name:<21} {}", st.map(|s| format!("{s:>16.3}")).join(""));
        }
    }
}
