//! The auxiliary outputs asked for by `--aov` (the rows of `film/outputs.rs` produced by
//! [`Producer::AovPass`]): per pixel, `samples` camera rays jittered uniformly over the pixel as
//! the beauty's are (the same box filter), each finding the first surface it hits. The normals
//! and the position there, and the albedo, are the means over the rays (0 for a ray that
//! misses), so a pixel inside one flat surface gets that surface's values exactly and an edge
//! pixel the coverage-weighted blend; the ids are those covering most of the pixel's rays; the
//! Cryptomatte layers store each name's coverage, its share of the rays. The albedo is the
//! directional-hemispherical reflectance rho(wo) = integral of f |cos| over the sphere at the
//! first non-specular surface (through mirrors and smooth glass, times their throughput), one
//! BSDF sample f |cos| / pdf per ray at hero wavelengths, as the reflectance a surface shows
//! under D65 of luminance 1 in linear sRGB (so a white diffuse surface is (1, 1, 1)).
//! The pass does not depend on the shard: every shard computes it in full from the render's
//! seed, and `quasar merge` keeps the first image's.

use std::sync::OnceLock;

use glam::{Vec2, Vec3};
use quasar_materials::TransportMode;
use quasar_materials::spectrum::color::xyz_to_linear_srgb;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths, cie};
use rayon::prelude::*;

use crate::core::camera::Camera;
use crate::core::sampling::Sampler;
use crate::core::scene::Scene;
use crate::film::Channel;
use crate::film::outputs::{ChannelSet, OutputGroup, Producer};
use crate::integrator::scatter::scatter;
use crate::output::cryptomatte;

/// Specular events followed before the albedo gives up (a ray trapped between mirrors).
const MAX_SPECULAR: u32 = 16;

/// The names the id outputs refer to: the scene's materials and meshes (objects), in index order.
pub struct IdNames<'a> {
    /// Material names.
    pub materials: &'a [String],
    /// Mesh (object) names.
    pub objects: &'a [String],
}

/// What the rays of one pixel found.
#[derive(Default)]
struct PixelAovs {
    normal: Vec3,
    normal_geometric: Vec3,
    position: Vec3,
    albedo: [f64; 3],
    /// (material index, rays) and (object index, rays).
    materials: Vec<(u32, u32)>,
    objects: Vec<(u32, u32)>,
}

/// Adds `k` rays to the count of `id`.
fn count(list: &mut Vec<(u32, u32)>, id: u32, k: u32) {
    match list.iter_mut().find(|(i, _)| *i == id) {
        Some((_, n)) => *n += k,
        None => list.push((id, k)),
    }
}

/// Y of D65 relative to a flat spectrum of 1 under the film's normalisation:
/// integral(D65 ybar) / integral(ybar), 1 nm midpoints over 360-830 nm.
fn d65_luminance() -> f32 {
    static Y: OnceLock<f32> = OnceLock::new();
    *Y.get_or_init(|| {
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for i in 0..470 {
            let l = 360.5 + i as f32;
            num += f64::from(cie::d65(l) * cie::ybar(l));
            den += f64::from(cie::ybar(l));
        }
        (num / den) as f32
    })
}

/// One ray's estimate of the albedo (linear sRGB) where `ray` first meets a non-specular surface.
fn albedo_sample(scene: &Scene, mut ray: crate::core::geometry::ray::Ray, sampler: &mut Sampler) -> [f32; 3] {
    let mut wl = SampledWavelengths::sample_visible(sampler.get_1d());
    let mut beta = SampledSpectrum::one();
    for _ in 0..=MAX_SPECULAR {
        let Some(si) = scene.intersect(&ray) else { return [0.0; 3] };
        let bsdf = scene.bsdf_at(&si, &mut wl);
        let frame = si.frame();
        let wo = -ray.dir;
        let specular = bsdf.is_specular();
        let Some(sc) = scatter(&bsdf, &si, &frame, wo, frame.to_local(wo), TransportMode::Radiance, sampler) else {
            return [0.0; 3];
        };
        beta *= sc.weight();
        if !specular {
            let lit = SampledSpectrum(std::array::from_fn(|i| beta.0[i] * cie::d65(wl.lambda(i))));
            let xyz = wl.to_xyz(lit).map(|v| v / d65_luminance());
            let rgb = xyz_to_linear_srgb(xyz);
            return if rgb.iter().all(|v| v.is_finite()) { rgb } else { [0.0; 3] };
        }
        ray = si.spawn_ray(sc.wi);
    }
    [0.0; 3]
}

/// The channels and header entries of the rows `rows` (each produced by the AOV pass) for
/// `samples` rays per pixel; pixel i's ray s uses the random numbers of `(seed, i, s)`.
pub fn aov_pass(
    scene: &Scene,
    camera: &Camera,
    names: &IdNames<'_>,
    rows: &[&'static OutputGroup],
    samples: u32,
    seed: u64,
) -> (Vec<Channel>, Vec<(String, String)>) {
    debug_assert!(rows.iter().all(|r| r.producer == Producer::AovPass));
    let wants = |name: &str| rows.iter().any(|r| r.aov == Some(name));
    let want_albedo = wants("albedo");
    // the per-pixel id lists (a small allocation each) only when an id output reads them
    let want_ids = ["material_id", "object_id", "crypto_material", "crypto_object"].iter().any(|n| wants(n));
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    let n = samples.max(1);
    let pixels: Vec<PixelAovs> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let mut px = PixelAovs::default();
            for s in 0..n {
                let mut sampler = Sampler::new(seed ^ 0xa0f5, i as u64, u64::from(s));
                let jitter = sampler.get_2d();
                let ray = camera.ray(Vec2::new((i % w) as f32, (i / w) as f32) + jitter);
                let Some(si) = scene.intersect(&ray) else { continue };
                px.normal += si.ns;
                px.normal_geometric += si.ng;
                px.position += si.p;
                if want_ids {
                    count(&mut px.materials, si.material, 1);
                    count(&mut px.objects, scene.accel.info[si.prim as usize].mesh, 1);
                }
                if want_albedo {
                    let a = albedo_sample(scene, ray, &mut sampler);
                    for (acc, v) in px.albedo.iter_mut().zip(a) {
                        *acc += f64::from(v);
                    }
                }
            }
            px
        })
        .collect();
    let inv = 1.0 / n as f32;
    let mut channels = Vec::new();
    let mut header = vec![("aov_samples".to_string(), n.to_string())];
    let vector = |layer: &str, get: &dyn Fn(&PixelAovs) -> Vec3| -> Vec<Channel> {
        ChannelSet::Xyz
            .names()
            .iter()
            .enumerate()
            .map(|(k, c)| Channel {
                name: format!("{layer}.{c}"),
                values: pixels.iter().map(|p| get(p)[k] * inv).collect(),
            })
            .collect()
    };
    let majority =
        |list: &[(u32, u32)]| list.iter().max_by_key(|&&(id, n)| (n, std::cmp::Reverse(id))).map(|&(id, _)| id);
    let id_table = |list: &[String]| {
        let map: serde_json::Map<String, serde_json::Value> =
            list.iter().enumerate().map(|(i, name)| ((i + 1).to_string(), name.clone().into())).collect();
        serde_json::Value::Object(map).to_string()
    };
    for row in rows {
        match row.aov.unwrap_or_default() {
            "normal" => channels.extend(vector(row.layer, &|p| p.normal)),
            "normal_geometric" => channels.extend(vector(row.layer, &|p| p.normal_geometric)),
            "position" => channels.extend(vector(row.layer, &|p| p.position)),
            "albedo" => {
                for (k, c) in ChannelSet::Rgb.names().iter().enumerate() {
                    let values = pixels.iter().map(|p| (p.albedo[k] / f64::from(n)) as f32).collect();
                    channels.push(Channel { name: format!("{}.{c}", row.layer), values });
                }
            }
            "material_id" => {
                let values = pixels.iter().map(|p| majority(&p.materials).map_or(0.0, |m| (m + 1) as f32)).collect();
                channels.push(Channel { name: format!("{}.Y", row.layer), values });
                header.push(("material_ids".into(), id_table(names.materials)));
            }
            "object_id" => {
                let values = pixels.iter().map(|p| majority(&p.objects).map_or(0.0, |m| (m + 1) as f32)).collect();
                channels.push(Channel { name: format!("{}.Y", row.layer), values });
                header.push(("object_ids".into(), id_table(names.objects)));
            }
            "crypto_material" | "crypto_object" => {
                let crypto_material = row.aov == Some("crypto_material");
                let list = if crypto_material { names.materials } else { names.objects };
                let get = |p: &'_ PixelAovs| -> Vec<(u32, u32)> {
                    if crypto_material { p.materials.clone() } else { p.objects.clone() }
                };
                // one id per name: meshes (or materials) that share a name share its matte
                let mut seen = std::collections::HashMap::new();
                let first_of: Vec<u32> =
                    list.iter().enumerate().map(|(i, n)| *seen.entry(n.as_str()).or_insert(i as u32)).collect();
                let coverage: Vec<Vec<(u32, f32)>> = pixels
                    .iter()
                    .map(|p| {
                        let mut by_name: Vec<(u32, u32)> = Vec::new();
                        for (id, k) in get(p) {
                            count(&mut by_name, first_of[id as usize], k);
                        }
                        by_name.into_iter().map(|(id, k)| (id, k as f32 * inv)).collect()
                    })
                    .collect();
                // the manifest lists the names the image holds
                let mut used: Vec<u32> = coverage.iter().flatten().map(|&(id, _)| id).collect();
                used.sort_unstable();
                used.dedup();
                let used_names: Vec<String> = used.iter().map(|&i| list[i as usize].clone()).collect();
                channels.extend(cryptomatte::channels(row.layer, list, &coverage));
                header.extend(cryptomatte::header(row.layer, &used_names));
            }
            // a row of the AOV pass without its arm here writes nothing (tests/aovs.rs asks
            // for every row and checks that each is written)
            _ => {}
        }
    }
    (channels, header)
}
