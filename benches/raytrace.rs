//! Ray-tracing throughput: BVH build time and rays/s (primary, incoherent, shadow) at 1 and 2
//! threads, on the shipped scenes and a generated 1M-triangle mesh, plus obvhs' own closest-hit
//! traversal on the same rays as the baseline. Results go into BENCHMARKS.md.
//!
//! Run: `cargo bench --bench raytrace` (add `-- --quick` for a shorter run).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3, Vec3A};
use quasar::core::camera::Camera;
use quasar::core::geometry::{Accel, NONE, Ray, TriangleInfo};
use quasar::core::sampling::{Sampler, uniform_sphere};
use quasar::core::scene::Scene;
use rayon::prelude::*;

/// A bumpy UV sphere with `n_theta * n_phi * 2` triangles.
fn bumpy_sphere(n_theta: usize, n_phi: usize) -> Vec<[Vec3; 3]> {
    let p = |i: usize, j: usize| {
        let t = std::f32::consts::PI * i as f32 / n_theta as f32;
        let f = 2.0 * std::f32::consts::PI * j as f32 / n_phi as f32;
        let r = 1.0 + 0.05 * (7.0 * t).sin() * (11.0 * f).cos();
        Vec3::new(r * t.sin() * f.cos(), r * t.cos(), r * t.sin() * f.sin())
    };
    let mut tris = Vec::with_capacity(n_theta * n_phi * 2);
    for i in 0..n_theta {
        for j in 0..n_phi {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    tris
}

fn info(n: usize) -> Vec<TriangleInfo> {
    vec![TriangleInfo { material: 0, light: NONE, normals: NONE, mesh: 0, uvs: NONE, colors: NONE }; n]
}

struct RaySets {
    primary: Vec<Ray>,
    incoherent: Vec<Ray>,
    shadow: Vec<Ray>,
}

/// Primary rays of a 256x256 image, incoherent rays (random origins in the bounds, random
/// directions) and shadow rays from primary hits to random points of the bounding box top.
fn ray_sets(accel: &Accel, camera: &Camera, center: Vec3, radius: f32) -> RaySets {
    let (w, h) = (camera.width(), camera.height());
    let primary: Vec<Ray> =
        (0..w * h).map(|i| camera.ray(Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5))).collect();
    let mut s = Sampler::new(1, 2, 3);
    let incoherent: Vec<Ray> = (0..w * h)
        .map(|_| {
            let o = center + uniform_sphere(s.get_2d()) * radius * 0.5 * s.get_1d().sqrt();
            Ray::new(o, uniform_sphere(s.get_2d()))
        })
        .collect();
    let shadow: Vec<Ray> = primary
        .iter()
        .filter_map(|r| {
            let hit = accel.intersect(r)?;
            let p = r.origin + r.dir * hit.t * 0.999;
            let target = center + Vec3::new(s.get_1d() - 0.5, 1.0, s.get_1d() - 0.5) * radius * 0.8;
            let d = target - p;
            Some(Ray { origin: p, dir: d.normalize(), t_max: d.length() })
        })
        .collect();
    RaySets { primary, incoherent, shadow }
}

fn bench_accel(c: &mut Criterion, name: &str, tris: &[[Vec3; 3]], camera: &Camera, center: Vec3, radius: f32) {
    let infos = info(tris.len());
    let mut g = c.benchmark_group(format!("bvh_build/{name}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(tris.len() as u64));
    g.bench_function("medium_build", |b| b.iter(|| black_box(Accel::build(tris, &infos, Accel::default_params()))));
    g.finish();

    let accel = Accel::build(tris, &infos, Accel::default_params());
    let sets = ray_sets(&accel, camera, center, radius);
    // obvhs' own path for the baseline: its Triangle::intersect through primitive_indices
    let obv: Vec<obvhs::triangle::Triangle> =
        tris.iter().map(|t| obvhs::triangle::Triangle { v0: t[0].into(), v1: t[1].into(), v2: t[2].into() }).collect();
    let obvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(&obv, Accel::default_params(), &mut Default::default());

    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut g = c.benchmark_group(format!("rays/{name}/{threads}t"));
        g.sample_size(10);
        for (kind, rays) in [("primary", &sets.primary), ("incoherent", &sets.incoherent)] {
            g.throughput(Throughput::Elements(rays.len() as u64));
            g.bench_function(kind, |b| {
                b.iter(|| pool.install(|| rays.par_iter().filter(|r| accel.intersect(r).is_some()).count()))
            });
            g.bench_function(format!("{kind}_obvhs_baseline"), |b| {
                b.iter(|| {
                    pool.install(|| {
                        rays.par_iter()
                            .filter(|r| {
                                let ray = obvhs::ray::Ray::new_inf(Vec3A::from(r.origin), Vec3A::from(r.dir));
                                let mut hit = obvhs::ray::RayHit::none();
                                obvh.ray_traverse(ray, &mut hit, |ray, id| {
                                    obv[obvh.primitive_indices[id] as usize].intersect(ray)
                                })
                            })
                            .count()
                    })
                })
            });
        }
        g.throughput(Throughput::Elements(sets.shadow.len() as u64));
        g.bench_function("shadow", |b| {
            b.iter(|| pool.install(|| sets.shadow.par_iter().filter(|r| accel.occluded(r)).count()))
        });
        g.finish();
    }
}

fn scene_tris(scene: &Scene) -> Vec<[Vec3; 3]> {
    scene
        .accel
        .geom
        .iter()
        .map(|g| {
            let v0 = Vec3::from(g.v0);
            [v0, v0 + Vec3::from(g.e1), v0 + Vec3::from(g.e2)]
        })
        .collect()
}

fn benches(c: &mut Criterion) {
    for (name, path) in
        [("cornell-box", "scenes/cornell-box/cornell-box.toml"), ("glass-plate", "scenes/glass-plate/glass-plate.toml")]
    {
        let desc = quasar::render::job::load_scene(std::path::Path::new(path)).expect("shipped scene loads");
        let scene = Scene::compile(&desc).unwrap();
        let camera = Camera::new(&desc.camera, 256, 256).unwrap();
        bench_accel(c, name, &scene_tris(&scene), &camera, scene.center, scene.radius);
    }
    let tris = bumpy_sphere(500, 1000);
    let cam = quasar::importers::CameraDesc {
        position: Vec3::new(0.0, 0.5, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_deg: 45.0,
        fov_axis: quasar::importers::FovAxis::Y,
    };
    let camera = Camera::new(&cam, 256, 256).unwrap();
    bench_accel(c, "bumpy-sphere-1M", &tris, &camera, Vec3::ZERO, 1.05);
}

criterion_group!(raytrace, benches);
criterion_main!(raytrace);
