//! The forward (light) pass of `vismap` (docs/architecture.md §7.4, step 2): photons leave the lights
//! (power-proportional choice), scatter by BSDF sampling with Russian roulette, and at every
//! non-specular hit after at least one bounce add f(wo, wi) * flux to the visibility points whose
//! gather disk contains the hit.

use std::sync::atomic::AtomicU32;

use quasar_materials::TransportMode;
use quasar_materials::spectrum::SampledWavelengths;
use rayon::prelude::*;

use super::arrival::{Arrival, Deposit, Deposits, Gatherer, PhotonCounts, PointSides, point_sides};
use super::gather_disk::GatherDisk;
use super::grid::VisibilityGrid;
use super::lookup_pipeline::LookupPipeline;
use super::quasi_cone::in_cone;
use super::ranges::ByRange;
use super::visibility_point::{GatherRule, VisibilityPoint};
use crate::core::geometry::Ray;
use crate::core::isa::Isa;
use crate::core::medium::{MAX_MEDIUM_SCATTERS, SegmentEvent};
use crate::core::sampling::Sampler;
use crate::core::scene::Scene;
use crate::integrator::pt::russian_roulette;
use crate::integrator::scatter::scatter;

/// Photons traced per parallel work item (the unit of the fixed-order reduction).
const CHUNK: usize = 256;
/// Photon bounces before Russian roulette may end a photon.
const RR_DEPTH: u32 = 3;
/// A hard cap on photon path length (Russian roulette ends paths long before in practice).
const MAX_BOUNCES: u32 = 1000;
/// Shares of one visibility point's gather disks that can receive photons
/// ([`super::coverage`]; the radii are its [`GatherDisk`]'s).
#[derive(Clone, Copy, Debug)]
pub struct DiskCoverage {
    /// Share of the indirect disk.
    pub indirect: f32,
    /// Share of the caustic disk.
    pub caustic: f32,
}

impl DiskCoverage {
    /// A disk taken as fully covered (one that received no photon is never measured: its
    /// estimate is 0 whatever its share).
    pub const FULL: Self = Self { indirect: 1.0, caustic: 1.0 };
}

/// Accumulated photon contributions of one visibility point: sum of f * flux, split by photon
/// class. Divided by N pi r^2 of the class's radius it is the reflected radiance L^I.
#[derive(Clone, Copy, Debug, Default)]
pub struct PhotonSums {
    /// Photons with at least one non-specular (and not quasi-specular) bounce: radius r_i.
    pub indirect: [f64; 4],
    /// Caustic photons (all bounces specular or quasi-specular): radius r_c.
    pub caustic: [f64; 4],
    /// The part of `caustic` whose bounces were all truly specular (the `caustic` AOV layer).
    pub specular_only: [f64; 4],
    /// Photons gathered (of either class, whatever their value): the local photon density
    /// times the gather disk's area, for the automatic radius.
    pub photons: u32,
}

/// What a photon pass keeps of the photons its visibility points accept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhotonRecord {
    /// Every point's [`PhotonSums`], f * flux by photon class: an iteration's estimate.
    Sums,
    /// Only how many photons each point accepted ([`PhotonSums::photons`]; the spectral sums
    /// stay 0): the radius pilot's photon density, without a BSDF evaluation or a deposit per
    /// accepted photon (at the pilot's default radii, 7.6 per look-up in the glossy room at
    /// 1024x768; BENCHMARKS.md "The radius pilot counts"), and for a point without a
    /// quasi-specular cone without reading the point (`arrival::PhotonCounts`). The one
    /// difference from `Sums`' count: a photon whose value would not be finite, which `Sums`
    /// drops, is counted.
    Counts,
}

/// What one photon pass produced. A render keeps one and hands it to every iteration's pass,
/// which refills its lists in place.
#[derive(Default)]
pub struct PhotonPassResult {
    /// Per visibility point.
    pub sums: Vec<PhotonSums>,
    /// Photon-surface hits after >= 1 bounce (looked up in the grid).
    pub lookups: u64,
    /// Every chunk of photons' deposits, kept for the next pass.
    chunks: Vec<PhotonChunk>,
}

/// The deposits of one chunk of photons, grouped by range of points (in photon order within
/// a range).
#[derive(Default)]
struct PhotonChunk {
    grouped: ByRange<Deposit>,
    lookups: u64,
}

thread_local! {
    /// A chunk's deposits in photon order before they are grouped: one list per thread, kept,
    /// so that only the grouped lists stay allocated per chunk.
    static DEPOSITS: std::cell::RefCell<Vec<Deposit>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Traces `n_photons` photons at the iteration's wavelengths `wl` with streams keyed by
/// (`seed`, `iteration`, photon number) into `out` (its sums one per visibility point, all of
/// them or the photon counts alone as `record` says). Bounces the camera side passes through
/// (`rule`: inside a quasi-specular cone, or off a narrow lobe) keep a photon a caustic photon.
/// The reduction adds every point's deposits in photon order (ranges of points in parallel), so
/// the result is the same for any thread count.
#[allow(clippy::too_many_arguments)]
pub fn trace_photons(
    scene: &Scene,
    wl: &SampledWavelengths,
    points: &[VisibilityPoint],
    point_wl: &[SampledWavelengths],
    disks: &[GatherDisk],
    grid: &VisibilityGrid,
    n_photons: u64,
    seed: u64,
    iteration: u32,
    rule: GatherRule,
    record: PhotonRecord,
    isa: Isa,
    out: &mut PhotonPassResult,
) {
    let n_chunks = n_photons.div_ceil(CHUNK as u64) as usize;
    let photons_of = |c: usize| c as u64 * CHUNK as u64..((c as u64 + 1) * CHUNK as u64).min(n_photons);
    if record == PhotonRecord::Counts {
        let counts: Vec<AtomicU32> = points.iter().map(|_| AtomicU32::new(0)).collect();
        let sides: Vec<PointSides> = points.par_iter().map(point_sides).collect();
        out.lookups = (0..n_chunks)
            .into_par_iter()
            .with_max_len(1)
            .map(|c| {
                let mut gatherer = PhotonCounts { counts: &counts, points, sides: &sides };
                let mut pipeline = LookupPipeline::new(disks, grid);
                // the photon kernel, compiled once per instruction set (core::isa)
                isa.run(
                    #[inline(always)]
                    || {
                        let n = photons_of(c)
                            .map(|i| {
                                let mut sampler = Sampler::new(seed, i, iteration as u64);
                                trace_photon(scene, wl, rule, &mut sampler, &mut pipeline, &mut gatherer)
                            })
                            .sum::<u64>();
                        pipeline.finish(&mut gatherer);
                        n
                    },
                )
            })
            .sum();
        out.sums.clear();
        out.sums.extend(counts.into_iter().map(|c| PhotonSums { photons: c.into_inner(), ..PhotonSums::default() }));
        return;
    }
    // the points fall into ranges that are summed in parallel; every chunk of photons sorts its
    // deposits by range (stably), so that each range adds its deposits in photon order
    let range = points.len().div_ceil(4 * rayon::current_num_threads()).max(1);
    let n_ranges = points.len().div_ceil(range);
    let PhotonPassResult { sums, lookups, chunks } = out;
    chunks.resize_with(n_chunks, PhotonChunk::default);
    chunks.par_iter_mut().enumerate().with_max_len(1).for_each(|(c, chunk)| {
        // (tracing a photon starts no parallel work, so the thread's list is not borrowed twice)
        DEPOSITS.with_borrow_mut(|deposits| {
            deposits.clear();
            deposits.reserve(2 * CHUNK);
            chunk.lookups = 0;
            let mut gatherer = Deposits { list: deposits, points, point_wl };
            let mut pipeline = LookupPipeline::new(disks, grid);
            // the photon kernel, compiled once per instruction set (core::isa)
            isa.run(
                #[inline(always)]
                || {
                    for i in photons_of(c) {
                        let mut sampler = Sampler::new(seed, i, iteration as u64);
                        chunk.lookups += trace_photon(scene, wl, rule, &mut sampler, &mut pipeline, &mut gatherer);
                    }
                    pipeline.finish(&mut gatherer);
                },
            );
            chunk.grouped.regroup(deposits, n_ranges, |d| d.point as usize / range);
        });
    });
    sums.clear();
    sums.resize(points.len(), PhotonSums::default());
    let chunks = &*chunks;
    sums.par_chunks_mut(range).enumerate().for_each(|(r, sums)| {
        let first = r * range;
        for chunk in chunks {
            for d in chunk.grouped.of(r) {
                let sum = &mut sums[d.point as usize - first];
                sum.photons += 1;
                let acc = if d.caustic { &mut sum.caustic } else { &mut sum.indirect };
                for (a, v) in acc.iter_mut().zip(d.value.0) {
                    *a += v as f64;
                }
                if d.specular_only {
                    for (a, v) in sum.specular_only.iter_mut().zip(d.value.0) {
                        *a += v as f64;
                    }
                }
            }
        }
    });
    *lookups = chunks.iter().map(|c| c.lookups).sum();
}

/// One photon path, its hits after >= 1 bounce looked up in `pipeline` (whose accepted
/// arrivals go to `gatherer`, in hit order, some of them during later photons' paths). Returns
/// the number of grid look-ups started.
#[inline(always)]
fn trace_photon(
    scene: &Scene,
    wl_iteration: &SampledWavelengths,
    rule: GatherRule,
    sampler: &mut Sampler,
    pipeline: &mut LookupPipeline,
    gatherer: &mut impl Gatherer,
) -> u64 {
    let Some((light_index, p_select)) = scene.light_sampler.sample(sampler.get_u64()) else { return 0 };
    let u_pos = sampler.get_2d();
    let u_dir = sampler.get_2d();
    let mut wl = *wl_iteration;
    let light = &scene.lights[light_index];
    let Some(photon) = light.sample_emission(u_pos, u_dir, &wl, &scene.emissions, scene.center) else {
        return 0;
    };
    let mut beta = photon.flux / p_select;
    let beta0 = beta.max_component();
    let mut ray = Ray::new(photon.origin, photon.dir);
    let mut caustic = true;
    let mut specular_only = true;
    let mut lookups = 0;
    // the last hit's arrival, pushed just before the photon's next ray is traced, as a camera
    // path's shadow ray is (docs/architecture.md §7.2; measured faster), still in hit order
    let mut pending: Option<(glam::Vec3, glam::Vec3, Arrival)> = None;
    // photons leave the lights outside every medium (core::medium)
    let mut media = crate::core::medium::MediumStack::default();
    // scattering events in media so far (a photon that scattered there before its first surface
    // is no direct light: it is deposited there)
    let mut medium_scatters = 0u32;
    let mut bounce = 0;
    while bounce < MAX_BOUNCES {
        if let Some((p, ng, arrival)) = pending.take() {
            pipeline.push(p, ng, arrival, gatherer);
        }
        let hit = scene.intersect(&ray);
        // the segment inside the innermost medium: absorbed (Beer-Lambert), or scattered at a
        // sampled distance by the phase function (which is its own adjoint)
        match media.sample_segment(scene, hit.as_ref().map_or(f32::INFINITY, |h| h.t), &wl, sampler) {
            None => {}
            Some(SegmentEvent::Surface(w)) => {
                beta *= w;
                if beta.is_black() {
                    break;
                }
            }
            Some(SegmentEvent::Scatter { t, weight, phase }) => {
                beta *= weight;
                medium_scatters += 1;
                if !beta.is_finite() || beta.is_black() || medium_scatters > MAX_MEDIUM_SCATTERS {
                    break;
                }
                let p = ray.origin + ray.dir * t;
                ray = Ray::new(p, phase.sample(-ray.dir, sampler.get_2d()).0);
                (caustic, specular_only) = (false, false);
                if bounce + medium_scatters >= RR_DEPTH && !roulette(&mut beta, beta0, sampler) {
                    break;
                }
                continue;
            }
        }
        let Some(si) = hit else { break };
        let bsdf = scene.bsdf_at(&si, &mut wl);
        let wi_photon = -ray.dir;
        // the photon's incidence cosine on the surface it hit (geometric normal)
        let cos_in = wi_photon.dot(si.ng);
        if (bounce > 0 || medium_scatters > 0) && !bsdf.is_specular() {
            lookups += 1;
            // the photon at this hit, whichever point's disk it lands in
            let arrival = Arrival {
                caustic,
                specular_only,
                hero_only: wl.secondary_terminated(),
                above: cos_in > 0.0,
                wi: wi_photon,
                cos_hit: cos_in.abs(),
                beta,
            };
            pending = Some((si.p, si.ng, arrival));
        }
        let frame = si.frame();
        let wo_local = frame.to_local(wi_photon);
        let Some(sc) = scatter(&bsdf, &si, &frame, wi_photon, wo_local, TransportMode::Importance, sampler) else {
            break;
        };
        let (bs, wi) = (sc.bs, sc.wi);
        // adjoint BSDF with shading normals (Veach 1997, eq. 5.19): the importance throughput
        // f |wi . ns| / pdf times |wo . ns| |wi . ng| / (|wo . ng| |wi . ns|)
        let cos_o_g = cos_in.abs();
        if cos_o_g <= 0.0 {
            break;
        }
        beta *= bs.f * (wo_local.z.abs() * wi.dot(si.ng).abs() / (cos_o_g * bs.pdf));
        if !beta.is_finite() || beta.is_black() {
            break;
        }
        specular_only &= bs.specular;
        // the camera side passes through narrow lobes and cones: photons bounced there stay
        // caustic photons (sharp, gathered with the caustic radius)
        caustic &= bs.specular || {
            let t = rule.treat(scene, &si, &bsdf, wo_local);
            t.pass_through || in_cone(&t.cone, bs.wi)
        };
        media = media.after(scene, &si, wi_photon, wi);
        ray = si.spawn_ray(wi);
        bounce += 1;
        if bounce + medium_scatters >= RR_DEPTH && !roulette(&mut beta, beta0, sampler) {
            break;
        }
    }
    if let Some((p, ng, arrival)) = pending {
        pipeline.push(p, ng, arrival, gatherer);
    }
    lookups
}

/// Russian roulette on a photon's throughput `beta` relative to its emitted flux `beta0`; false
/// when the photon ends.
#[inline(always)]
fn roulette(beta: &mut quasar_materials::spectrum::SampledSpectrum, beta0: f32, sampler: &mut Sampler) -> bool {
    let mut rel = *beta / beta0;
    if !russian_roulette(&mut rel, 1.0, sampler.get_1d()) {
        return false;
    }
    *beta = rel * beta0;
    true
}
