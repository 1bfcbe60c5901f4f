//! The forward (light) pass of `vismap` (docs/architecture.md §7.4, step 2): photons leave the lights
//! (power-proportional choice), scatter by BSDF sampling with Russian roulette, and at every
//! non-specular hit after at least one bounce add f(wo, wi) * flux to the visibility points whose
//! gather disk contains the hit.

use std::sync::atomic::AtomicU32;

use quasar_materials::spectrum::SampledWavelengths;
use quasar_materials::{NARROW_KAPPA, TransportMode};
use rayon::prelude::*;

use super::arrival::{Arrival, Deposit, Deposits, Gatherer, PhotonCounts, PointSides, point_sides};
use super::grid::{GatherRegion, VisibilityGrid};
use super::quasi_cone::QuasiCone;
use super::ranges::ByRange;
use super::visibility_point::VisibilityPoint;
use crate::core::geometry::Ray;
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
/// Cosine of the largest angle (60 degrees) between the surface normals of a photon hit and a
/// visibility point for the photon to count there: keeps photons on one side of a thin object
/// (a plate on a table) or on the other wall of a corner from lighting the other. The excluded
/// set shrinks to the surfaces' creases as the radius shrinks, so the estimate stays consistent.
pub const MIN_NORMAL_COS: f32 = 0.5;
/// Largest distance of a photon hit from the visibility point's tangent plane, as a fraction of
/// the gather radius: the gather region is a flattened disk, not a ball (Jensen 2001, 7.2), so a
/// photon on a nearby parallel surface (the inside of a thin wall, an object within an object)
/// is not counted. A sphere of radius R deviates from its tangent plane by s^2 / (2R) at distance
/// s, so nothing of a curved surface is excluded while r < R / 2.
pub const MAX_PLANE_DISTANCE: f32 = 0.25;

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

/// A visibility point's gather disk in the current iteration: centre, normal and radii, 32
/// bytes in one cache line, what a photon's first tests read. Most of a grid cell's
/// candidates are out of a photon's reach; testing them here instead of in the points (a few
/// cache lines each) and their radii keeps the photon pass from waiting on memory once the
/// points outgrow the caches (`auto`, glossy room, 1024x768: the photon pass took 1.8x the time
/// per pixel of 128x96; BENCHMARKS.md "Photon look-ups at large images").
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GatherDisk {
    /// The visibility point's position.
    pub p: glam::Vec3,
    /// Radius for photons that bounced off non-specular surfaces before.
    pub indirect: f32,
    /// The point's unit geometric normal.
    pub ng: glam::Vec3,
    /// Radius for caustic photons.
    pub caustic: f32,
}

/// The region a photon must land in: within the larger radius r of the point and within
/// h = [`MAX_PLANE_DISTANCE`] r of its tangent plane. Along a unit axis e its box reaches
/// max(d . e) over |d| <= r, |d . n| <= h: r where r |n . e| <= h, else
/// h |n . e| + sqrt(r^2 - h^2) sqrt(1 - (n . e)^2) (the maximum on the slab's face), taken 0.1%
/// wider for the rounding of n and of the photon's test, and never more than r. A floor's or
/// a wall's disk is entered in the cells of a box a quarter of the radius thick instead of the
/// ball's.
impl GatherRegion for GatherDisk {
    #[inline]
    fn centre_radius_extent(&self) -> (glam::Vec3, f32, glam::Vec3) {
        let r = self.indirect.max(self.caustic);
        let h = MAX_PLANE_DISTANCE * r;
        let n = self.ng.abs();
        let slab = (n * h + (1.0 - n * n).max(glam::Vec3::ZERO).map(f32::sqrt) * (r * r - h * h).sqrt()) * 1.001;
        let extent = glam::Vec3::select(
            (n * r).cmple(glam::Vec3::splat(h)),
            glam::Vec3::splat(r),
            slab.min(glam::Vec3::splat(r)),
        );
        (self.p, r, extent)
    }
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
/// them or the photon counts alone as `record` says). With a quasi-specular cone (`cone_cos`),
/// bounces inside it keep a photon a caustic photon. The reduction adds every point's deposits
/// in photon order (ranges of points in parallel), so the result is the same for any thread
/// count.
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
    cone_cos: Option<f32>,
    record: PhotonRecord,
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
                photons_of(c)
                    .map(|i| {
                        let mut sampler = Sampler::new(seed, i, iteration as u64);
                        trace_photon(scene, wl, disks, grid, cone_cos, &mut sampler, &mut gatherer)
                    })
                    .sum::<u64>()
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
            for i in photons_of(c) {
                let mut sampler = Sampler::new(seed, i, iteration as u64);
                chunk.lookups += trace_photon(scene, wl, disks, grid, cone_cos, &mut sampler, &mut gatherer);
            }
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

/// One photon path, its accepted arrivals given to `gatherer`. Returns the number of grid
/// lookups made.
#[allow(clippy::too_many_arguments)]
fn trace_photon(
    scene: &Scene,
    wl_iteration: &SampledWavelengths,
    disks: &[GatherDisk],
    grid: &VisibilityGrid,
    cone_cos: Option<f32>,
    sampler: &mut Sampler,
    gatherer: &mut impl Gatherer,
) -> u64 {
    let Some((light_index, p_select)) = scene.light_sampler.sample(sampler.get_1d()) else { return 0 };
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
    for bounce in 0..MAX_BOUNCES {
        let Some(si) = scene.intersect(&ray) else { break };
        let bsdf = scene.bsdf_at(&si, &mut wl);
        let wi_photon = -ray.dir;
        if bounce > 0 && !bsdf.is_specular() {
            lookups += 1;
            // the photon at this hit, whichever point's disk it lands in
            let arrival = Arrival {
                caustic,
                specular_only,
                hero_only: wl.secondary_terminated(),
                above: wi_photon.dot(si.ng) > 0.0,
                wi: wi_photon,
                beta,
            };
            for &vi in grid.candidates(si.p) {
                let disk = &disks[vi as usize];
                let r = if caustic { disk.caustic } else { disk.indirect };
                let d = si.p - disk.p;
                if d.length_squared() > r * r
                    || disk.ng.dot(si.ng) < MIN_NORMAL_COS
                    || d.dot(disk.ng).abs() > MAX_PLANE_DISTANCE * r
                {
                    continue;
                }
                gatherer.arrive(vi, disk.ng, &arrival);
            }
        }
        let frame = si.frame();
        let wo_local = frame.to_local(wi_photon);
        let Some(sc) = scatter(&bsdf, &si, &frame, wi_photon, wo_local, TransportMode::Importance, sampler) else {
            break;
        };
        let (bs, wi) = (sc.bs, sc.wi);
        // adjoint BSDF with shading normals (Veach 1997, eq. 5.19): the importance throughput
        // f |wi . ns| / pdf times |wo . ns| |wi . ng| / (|wo . ng| |wi . ns|)
        let cos_o_g = wi_photon.dot(si.ng).abs();
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
        caustic &= bs.specular
            || cone_cos.is_some_and(|c| {
                scene.non_uniformity()[si.material as usize].at(wo_local.z) > NARROW_KAPPA
                    || QuasiCone::at(&bsdf, wo_local, c).is_some_and(|k| k.contains(bs.wi))
            });
        ray = si.spawn_ray(wi);
        if bounce + 1 >= RR_DEPTH {
            // roulette on the throughput relative to the emitted flux
            let mut rel = beta / beta0;
            if !russian_roulette(&mut rel, 1.0, sampler.get_1d()) {
                break;
            }
            beta = rel * beta0;
        }
    }
    lookups
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::core::sampling::uniform_sphere;

    /// Normals along the axes, just off them, at 45 degrees and random.
    fn normals(s: &mut Sampler) -> Vec<Vec3> {
        let mut n = vec![Vec3::X, Vec3::NEG_Y, Vec3::Z, Vec3::new(1.0, 1e-4, 0.0).normalize(), Vec3::ONE.normalize()];
        n.extend((0..200).map(|_| uniform_sphere(s.get_2d())));
        n
    }

    #[test]
    fn a_disks_box_holds_the_region_tightly() {
        // the farthest reach of {|d| <= r, |d . n| <= h} along each axis, found by brute force
        // over the region's boundary, is inside the box and at least 95% of it (a box no
        // larger than needed), and the box is never larger than the ball's
        let mut s = Sampler::new(3, 1, 4);
        for n in normals(&mut s) {
            let disk = GatherDisk { p: Vec3::new(1.0, -2.0, 3.0), indirect: 0.2, ng: n, caustic: 0.1 };
            let (p, r, e) = disk.centre_radius_extent();
            assert_eq!((p, r), (disk.p, 0.2));
            let h = MAX_PLANE_DISTANCE * r;
            let mut reach = Vec3::ZERO;
            for _ in 0..20_000 {
                let dir = uniform_sphere(s.get_2d());
                // the ray from the centre along dir leaves the region at the sphere or at the slab
                let t = if dir.dot(n).abs() * r > h { h / dir.dot(n).abs() } else { r };
                reach = reach.max((dir * t).abs());
            }
            assert!(reach.cmple(e).all(), "n {n}: reach {reach} outside the box {e}");
            assert!(e.cmple(Vec3::splat(r)).all(), "n {n}: box {e}");
            assert!((reach / e).cmpge(Vec3::splat(0.95)).all(), "n {n}: reach {reach}, box {e}");
        }
    }

    #[test]
    fn every_photon_a_disk_accepts_finds_it_in_the_grid() {
        // disks on random planes with radii spread over 10x; photons inside each disk's region,
        // half of them at its rim, must find the point among the grid's candidates
        let mut s = Sampler::new(5, 9, 2);
        let ns = normals(&mut s);
        let disks: Vec<GatherDisk> = (0..3000)
            .map(|k| {
                let r = 0.01 + 0.1 * s.get_1d();
                let p = Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 4.0 - 2.0;
                GatherDisk { p, indirect: r, ng: ns[k % ns.len()], caustic: 0.5 * r }
            })
            .collect();
        let grid = VisibilityGrid::build(&disks);
        let mut tested = 0;
        for (i, disk) in disks.iter().enumerate() {
            let r = disk.indirect;
            let h = MAX_PLANE_DISTANCE * r;
            for _ in 0..30 {
                let dir = uniform_sphere(s.get_2d());
                let t = if dir.dot(disk.ng).abs() * r > h { h / dir.dot(disk.ng).abs() } else { r };
                let d = dir * t * if s.get_1d() < 0.5 { 1.0 - 1e-6 } else { s.get_1d() };
                if d.length_squared() <= r * r && d.dot(disk.ng).abs() <= h {
                    tested += 1;
                    assert!(grid.candidates(disk.p + d).contains(&(i as u32)), "disk {i} missing at {d}");
                }
            }
        }
        assert!(tested > 80_000, "{tested}");
    }
}
