//! One iteration of the bidirectional methods (docs/architecture.md §7.4): the hero
//! wavelengths it shares between its camera and light passes, the camera paths and their
//! visibility points with gather radii (the progressive schedule r_k^2 = r_1^2 prod (j - 1 +
//! alpha) / j of Knaus & Zwicker 2011, scaled per pixel by a pilot photon pass and normalised by
//! the disk's covered share), the visibility grid, the photon pass, and the photon density
//! estimate L^I = beta sum(f Phi) / (N pi r^2 c).

use std::f64::consts::PI;
use std::time::Instant;

use glam::Vec2;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use rayon::prelude::*;

use super::coverage::disk_coverage;
use super::gather_disk::GatherDisk;
use super::grid::VisibilityGrid;
use super::photon_pass::{self, DiskCoverage, PhotonRecord, PhotonSums, trace_photons};
use super::ranges::for_each_part;
use super::settings::VismapSettings;
use super::visibility_point::{CameraPathResult, GatherRule, VisibilityPoint, trace_camera_path};
use crate::core::camera::Camera;
use crate::core::isa::Isa;
use crate::core::sampling::{Sampler, mix64};
use crate::core::scene::Scene;
use crate::film::LayeredRadiance;

/// Squared radius factor of iteration k (1-based): prod_{j=2..k} (j - 1 + alpha) / j.
pub fn radius2_factor(k: u32, alpha: f64) -> f64 {
    (2..=k).fold(1.0, |acc, j| acc * (j as f64 - 1.0 + alpha) / j as f64)
}

/// The hero wavelength number of iteration k: a golden-ratio sequence offset by the seed, so
/// iterations are stratified over the spectrum without knowing their count in advance.
pub fn iteration_wavelength_u(seed: u64, k: u32) -> f32 {
    let offset = (mix64(seed ^ 0x7761_7665) >> 40) as f64 / (1u64 << 24) as f64;
    ((offset + k as f64 * 0.618_033_988_749_894_8).fract()) as f32
}

/// Pixels whose camera paths one task traces into one list of visibility points.
const CAMERA_BATCH: usize = 64;

/// The camera paths of one batch of pixels and their visibility points, refilled every
/// iteration.
#[derive(Default)]
struct CameraBatch<'s> {
    paths: Vec<CameraPathResult>,
    points: Vec<VisibilityPoint<'s>>,
}

/// The per-point lists of an iteration, or one camera batch's part of them.
struct PointLists<'a, 's> {
    points: &'a mut [VisibilityPoint<'s>],
    owners: &'a mut [usize],
    point_wl: &'a mut [SampledWavelengths],
    coverage: &'a mut [DiskCoverage],
    disks: &'a mut [GatherDisk],
}

impl PointLists<'_, '_> {
    /// The lists cut before point `at`.
    fn split_at(self, at: usize) -> (Self, Self) {
        let (p0, p1) = self.points.split_at_mut(at);
        let (o0, o1) = self.owners.split_at_mut(at);
        let (w0, w1) = self.point_wl.split_at_mut(at);
        let (c0, c1) = self.coverage.split_at_mut(at);
        let (d0, d1) = self.disks.split_at_mut(at);
        (
            PointLists { points: p0, owners: o0, point_wl: w0, coverage: c0, disks: d0 },
            PointLists { points: p1, owners: o1, point_wl: w1, coverage: c1, disks: d1 },
        )
    }
}

/// One iteration's passes: camera paths with their visibility points, the grid over them and
/// the photon pass at the iteration's wavelengths, all keyed by iteration number `k`.
pub struct Iteration {
    /// Seed of the camera streams.
    pub seed: u64,
    /// Seed of the photon streams.
    pub photon_seed: u64,
    /// Iteration number (0: the radius pilot).
    pub k: u32,
    /// The iteration's wavelengths.
    pub wl: SampledWavelengths,
    /// Photons traced.
    pub n_photons: u64,
    /// What the photon pass keeps: the sums of an iteration, or the counts of the radius pilot.
    pub record: PhotonRecord,
    /// Instruction set of the camera-path, photon and coverage kernels.
    pub isa: Isa,
}

/// What [`Iteration::run`] produced. A render keeps one and hands it to every iteration, which
/// refills its lists in place: once they have grown, an iteration allocates nothing.
pub struct IterationResult<'s> {
    /// The pixel of every visibility point.
    pub owners: Vec<usize>,
    /// The visibility points.
    pub points: Vec<VisibilityPoint<'s>>,
    /// Their gather disks (centre, normal, radii): the grid's input, the photons' first tests
    /// and the estimate's radii.
    pub disks: Vec<GatherDisk>,
    /// The covered shares of their disks (measured where photons landed, 1 elsewhere).
    pub coverage: Vec<DiskCoverage>,
    /// The photon pass.
    pub photons: photon_pass::PhotonPassResult,
    /// Bytes of the visibility grid.
    pub grid_bytes: usize,
    /// Wall-clock seconds of each phase.
    pub seconds: PhaseSeconds,
    /// The wavelengths of each visibility point's path.
    point_wl: Vec<SampledWavelengths>,
    grid: VisibilityGrid,
    /// The camera paths of every batch of [`CAMERA_BATCH`] pixels with their points (which
    /// are joined into `points` in pixel order).
    batches: Vec<CameraBatch<'s>>,
    /// Where each batch's points start in `points` (one more entry than batches).
    batch_first_point: Vec<usize>,
    /// Where each pixel's points start in `points` (one more entry than pixels).
    first_point: Vec<usize>,
}

impl Default for IterationResult<'_> {
    fn default() -> Self {
        Self {
            owners: Vec::new(),
            points: Vec::new(),
            disks: Vec::new(),
            coverage: Vec::new(),
            photons: photon_pass::PhotonPassResult::default(),
            grid_bytes: 0,
            seconds: PhaseSeconds::default(),
            point_wl: Vec::new(),
            grid: VisibilityGrid::empty(),
            batches: Vec::new(),
            batch_first_point: Vec::new(),
            first_point: Vec::new(),
        }
    }
}

/// Wall-clock seconds of the phases of bidirectional iterations (summed over iterations): what
/// the header's `time_share` reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseSeconds {
    /// Gather-depth and radius pilots.
    pub pilots: f64,
    /// Camera paths to the visibility points.
    pub camera: f64,
    /// The gather disks' covered shares (probe rays).
    pub coverage: f64,
    /// The visibility grid.
    pub grid: f64,
    /// Tracing the photons and gathering them.
    pub photons: f64,
    /// Estimates into the film.
    pub film: f64,
}

impl PhaseSeconds {
    /// Adds `o` phase by phase.
    pub fn add(&mut self, o: &PhaseSeconds) {
        self.pilots += o.pilots;
        self.camera += o.camera;
        self.coverage += o.coverage;
        self.grid += o.grid;
        self.photons += o.photons;
        self.film += o.film;
    }

    /// "pilots 2%, camera 21%, ..." : each phase's share of their sum.
    pub fn shares(&self) -> String {
        let phases = [
            ("pilots", self.pilots),
            ("camera", self.camera),
            ("coverage", self.coverage),
            ("grid", self.grid),
            ("photons", self.photons),
            ("film", self.film),
        ];
        let total: f64 = phases.iter().map(|p| p.1).sum();
        let total = if total > 0.0 { total } else { 1.0 };
        phases.iter().map(|(n, s)| format!("{n} {:.0}%", 100.0 * s / total)).collect::<Vec<_>>().join(", ")
    }
}

impl Iteration {
    /// Traces one camera path per pixel at gather depths `depths`, gives every visibility
    /// point the indirect radius `radius_of(pixel, point)` (caustic radius: the settings' ratio
    /// of it) and gathers the iteration's photons, into `out` (whose lists are reused).
    #[allow(clippy::too_many_arguments)]
    pub fn run<'s>(
        &self,
        scene: &'s Scene,
        camera: &Camera,
        settings: &VismapSettings,
        base_rule: &GatherRule,
        depths: &[Option<u32>],
        radius_of: impl Fn(usize, &VisibilityPoint) -> f32 + Sync,
        out: &mut IterationResult<'s>,
    ) {
        let w = camera.width() as usize;
        let mut seconds = PhaseSeconds::default();
        let mut clock = Instant::now();
        let mut lap = |phase: &mut f64| {
            let now = Instant::now();
            *phase += (now - clock).as_secs_f64();
            clock = now;
        };
        // batches of pixels, each with one list of visibility points, joined in pixel order
        let IterationResult {
            batches,
            batch_first_point,
            owners,
            points,
            disks,
            coverage,
            photons,
            point_wl,
            grid,
            ..
        } = out;
        batches.resize_with(depths.len().div_ceil(CAMERA_BATCH), CameraBatch::default);
        // (one batch per task at most, see ITEMS_PER_TASK: the batches' costs differ widely)
        batches.par_iter_mut().enumerate().with_max_len(1).for_each(|(b, batch)| {
            batch.paths.clear();
            batch.points.clear();
            batch.paths.reserve(CAMERA_BATCH);
            batch.points.reserve(CAMERA_BATCH);
            let pixels = b * CAMERA_BATCH..((b + 1) * CAMERA_BATCH).min(depths.len());
            // the camera-path kernel, compiled once per instruction set (core::isa)
            self.isa.run(
                #[inline(always)]
                || {
                    for (i, depth) in pixels.clone().zip(&depths[pixels]) {
                        let mut sampler = Sampler::new(self.seed, i as u64, self.k as u64);
                        let film_pos = Vec2::new((i % w) as f32, (i / w) as f32) + sampler.get_2d();
                        let rule = GatherRule { depth: depth.unwrap_or(0), ..*base_rule };
                        batch.paths.push(trace_camera_path(
                            scene,
                            camera.ray(film_pos),
                            self.wl,
                            &mut sampler,
                            &rule,
                            &mut batch.points,
                        ));
                    }
                },
            );
        });
        batch_first_point.clear();
        batch_first_point.push(0);
        for b in batches.iter() {
            batch_first_point.push(batch_first_point[batch_first_point.len() - 1] + b.points.len());
        }
        // the batches' points joined in parallel into the reused lists (`resize` writes only
        // the entries a list grows by: every entry is overwritten below)
        let n_points = batch_first_point[batches.len()];
        match batches.iter().find_map(|b| b.points.first()) {
            Some(&vp) => points.resize(n_points, vp),
            None => points.clear(),
        }
        owners.resize(n_points, 0);
        point_wl.resize(n_points, self.wl);
        // every point's gather disk and its covered shares, taken as full in the same parallel
        // join (they only matter where photons landed, an empty disk's estimate being 0
        // whatever its share, so they are measured after the photon pass, for those disks only)
        coverage.resize(n_points, DiskCoverage::FULL);
        disks.resize(n_points, GatherDisk::default());
        let (batches, first) = (&*batches, &*batch_first_point);
        for_each_part(
            PointLists { points, owners, point_wl, coverage, disks },
            0..batches.len(),
            &|lists: PointLists, lo, mid| lists.split_at(first[mid] - first[lo]),
            &|b, slot| {
                let batch = &batches[b];
                slot.points.copy_from_slice(&batch.points);
                let mut j = 0;
                for (i, p) in batch.paths.iter().enumerate() {
                    let n = p.points as usize;
                    slot.owners[j..j + n].fill(b * CAMERA_BATCH + i);
                    slot.point_wl[j..j + n].fill(p.wl);
                    j += n;
                }
                for (j, vp) in slot.points.iter().enumerate() {
                    let r = radius_of(slot.owners[j], vp);
                    slot.coverage[j] = DiskCoverage::FULL;
                    slot.disks[j] = GatherDisk { p: vp.p, indirect: r, ng: vp.ng, caustic: r * settings.caustic_ratio };
                }
            },
        );
        lap(&mut seconds.camera);
        grid.rebuild(disks);
        lap(&mut seconds.grid);
        trace_photons(
            scene,
            &self.wl,
            points,
            point_wl,
            disks,
            grid,
            self.n_photons,
            self.photon_seed,
            self.k,
            *base_rule,
            self.record,
            self.isa,
            photons,
        );
        lap(&mut seconds.photons);
        coverage
            .par_iter_mut()
            .enumerate()
            .with_max_len(super::ITEMS_PER_TASK)
            .filter(|(j, _)| photons.sums[*j].photons > 0)
            .for_each(|(j, c)| {
                let rotation = (mix64(self.seed ^ mix64(((self.k as u64) << 40) ^ j as u64)) >> 40) as f32
                    * (std::f32::consts::TAU / (1u64 << 24) as f32);
                let disk = &disks[j];
                (c.indirect, c.caustic) = self.isa.run(
                    #[inline(always)]
                    || disk_coverage(scene, &points[j], disk.indirect, disk.caustic, rotation),
                );
            });
        lap(&mut seconds.coverage);
        out.grid_bytes = out.grid.memory_bytes();
        out.seconds = seconds;
    }
}

/// L^I of one visibility point by photon class.
struct Gathered {
    /// Photons with a non-specular bounce: beta sum / (N pi r_i^2).
    indirect_radius: SampledSpectrum,
    /// Caustic photons: beta sum / (N pi r_c^2).
    caustic_radius: SampledSpectrum,
    /// The purely specular part of `caustic_radius`.
    specular_only: SampledSpectrum,
}

/// L^I of one visibility point: beta * sum(f Phi) / (N pi r^2 c) for the indirect and caustic
/// photon classes, each with its own radius r and covered share c of its disk.
fn gathered_radiance(
    sums: &PhotonSums,
    disk: &GatherDisk,
    coverage: &DiskCoverage,
    n_photons: u64,
    beta: SampledSpectrum,
) -> Gathered {
    let estimate = |s: &[f64; 4], r: f32, coverage: f32| {
        let area = PI * (r as f64) * (r as f64) * coverage as f64 * n_photons as f64;
        if !(area > 0.0 && area.is_finite()) {
            return SampledSpectrum::zero();
        }
        SampledSpectrum(std::array::from_fn(|k| (s[k] / area) as f32)) * beta
    };
    Gathered {
        indirect_radius: estimate(&sums.indirect, disk.indirect, coverage.indirect),
        caustic_radius: estimate(&sums.caustic, disk.caustic, coverage.caustic),
        specular_only: estimate(&sums.specular_only, disk.caustic, coverage.caustic),
    }
}

impl IterationResult<'_> {
    /// Every pixel's estimate of this iteration, `estimate(i)` for pixel i: its camera path's
    /// radiance plus the photons gathered at its visibility points, at the path's wavelengths.
    pub fn estimates(&mut self, n_photons: u64) -> impl Fn(usize) -> (LayeredRadiance, SampledWavelengths) + Sync + '_ {
        // a pixel's points follow each other in pixel order
        let first = &mut self.first_point;
        first.clear();
        first.push(0usize);
        for p in self.batches.iter().flat_map(|b| &b.paths) {
            first.push(first[first.len() - 1] + p.points as usize);
        }
        let (batches, first, points, sums, disks, coverage) =
            (&self.batches, &self.first_point, &self.points, &self.photons.sums, &self.disks, &self.coverage);
        move |i| {
            let p = &batches[i / CAMERA_BATCH].paths[i % CAMERA_BATCH];
            let mut l = p.radiance;
            for j in first[i]..first[i + 1] {
                let vp = &points[j];
                let g = gathered_radiance(&sums[j], &disks[j], &coverage[j], n_photons, vp.beta);
                l.add_indirect(g.caustic_radius, false);
                l.add_indirect(g.indirect_radius, false);
                // the caustic layer: light -> specular+ -> this first non-specular vertex -> eye
                if vp.class.nonspecular == 0 {
                    l.caustic += g.specular_only;
                }
            }
            (l, p.wl)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_radius_pilots_counts_are_the_photons_an_iteration_gathers() {
        // one iteration of the glossy room (its narrow floor passed through, the gather points on
        // diffuse surfaces without a cone: points with a cone are covered by
        // `arrival`'s test) with its photon pass kept as sums and as counts: every point counts
        // exactly the photons it summed, and the counting pass evaluates nothing
        let (desc, scene) = crate::integrator::bidir::shipped_scene("glossy-room/glossy-room.toml");
        let camera = Camera::new(&desc.camera, 40, 30).unwrap();
        let rule =
            GatherRule { depth: 0, cone_cos: Some(10f32.to_radians().cos()), max_specular: 16, pass_narrow: false };
        let depths = vec![Some(0); 40 * 30];
        let gather = |record| {
            let it = Iteration {
                seed: 3,
                photon_seed: 5,
                k: 1,
                wl: SampledWavelengths::sample_visible(0.3),
                n_photons: 20_000,
                record,
                isa: Isa::best(),
            };
            let mut r = IterationResult::default();
            it.run(&scene, &camera, &VismapSettings::default(), &rule, &depths, |_, _| 0.1, &mut r);
            (r.photons.sums, r.photons.lookups)
        };
        let (sums, lookups) = gather(PhotonRecord::Sums);
        let (counts, count_lookups) = gather(PhotonRecord::Counts);
        assert_eq!(lookups, count_lookups);
        assert_eq!(sums.len(), counts.len());
        let photons: Vec<u32> = sums.iter().map(|s| s.photons).collect();
        assert_eq!(photons, counts.iter().map(|s| s.photons).collect::<Vec<_>>());
        assert!(photons.iter().map(|&n| n as u64).sum::<u64>() > 10_000, "too few photons gathered to compare");
        assert!(sums.iter().any(|s| s.indirect.iter().any(|&v| v > 0.0)));
        assert!(counts.iter().all(|s| s.indirect == [0.0; 4] && s.caustic == [0.0; 4] && s.specular_only == [0.0; 4]));
    }

    #[test]
    fn radius_schedule_is_the_ppm_recurrence() {
        let a = 2.0 / 3.0;
        assert_eq!(radius2_factor(1, a), 1.0);
        for k in 2..50 {
            let ratio = radius2_factor(k, a) / radius2_factor(k - 1, a);
            assert!((ratio - (k as f64 - 1.0 + a) / k as f64).abs() < 1e-12);
        }
        // r_k^2 ~ k^(alpha - 1) / Gamma(1 + alpha): -> 0 (consistency), slowly enough that the
        // sum of r_k^2 diverges (variance -> 0); Gamma(5/3) = 0.9027
        let k = 10_000u32;
        let expected = (k as f64).powf(a - 1.0) / 0.902_745;
        assert!((radius2_factor(k, a) / expected - 1.0).abs() < 0.01);
    }

    #[test]
    fn iteration_wavelengths_are_stratified() {
        let mut u: Vec<f32> = (1..=100).map(|k| iteration_wavelength_u(7, k)).collect();
        u.sort_by(f32::total_cmp);
        for (i, v) in u.iter().enumerate() {
            assert!((v - (i as f32 + 0.5) / 100.0).abs() < 0.03, "{i}: {v}");
        }
    }
}
