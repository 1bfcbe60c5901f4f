//! The bidirectional methods as the render driver sees them: one unit is one iteration
//! (a camera pass leaving visibility points, a photon pass gathered there), rendered into a film
//! that keeps batch statistics of its block means (the pixels of an iteration share wavelengths
//! and photons). Deterministic for a seed: every camera path, pilot path and photon has its own
//! stream keyed by the iteration number, and all reductions run in a fixed order. Shard K of N
//! renders the iterations k with (k - 1) mod N = K.

use std::time::Instant;

use quasar_materials::spectrum::SampledWavelengths;

use super::adaptive_depth::GatherDepths;
use super::iteration::{Iteration, IterationResult, PhaseSeconds, iteration_wavelength_u, radius2_factor};
use super::photon_pass::PhotonRecord;
use super::radius_pilot::radius_pilot;
use super::settings::{GatherDepth, VismapSettings};
use super::visibility_point::{GatherRule, VisibilityPoint};
use crate::core::bytes::{ByteReader, ByteWriter};
use crate::core::camera::Camera;
use crate::core::isa::Isa;
use crate::core::sampling::mix64;
use crate::core::scene::Scene;
use crate::film::{Channel, Film};
use crate::integrator::pass::{PassControl, PassEnd, RenderMethod};

/// Figures of a bidirectional render, for the header and benchmarks.
#[derive(Clone, Copy, Debug, Default)]
pub struct VismapStats {
    /// Photons traced in all.
    pub photons: u64,
    /// Photon hits looked up in the visibility grid.
    pub lookups: u64,
    /// Seconds spent in iterations (camera pass, grid and photon pass).
    pub photon_seconds: f64,
    /// Largest visibility-grid size of an iteration, bytes.
    pub grid_bytes: usize,
    /// Most visibility points of an iteration.
    pub max_points: usize,
    /// Seconds per phase, summed over the iterations.
    pub seconds: PhaseSeconds,
}

/// A bidirectional render in progress.
pub struct Bidirectional<'s> {
    scene: &'s Scene,
    camera: &'s Camera,
    settings: VismapSettings,
    seed: u64,
    shard: (u32, u32),
    isa: Isa,
    rule: GatherRule,
    n_photons: u64,
    depths: GatherDepths,
    /// Per-pixel scale of the automatic radius (from the pilot pass before iteration 1).
    radius_scales: Option<Vec<f32>>,
    /// Iteration 1's depths, when the radius pilot needed them before the iteration ran.
    first_depths: Option<Vec<Option<u32>>>,
    /// Statistics of this run.
    pub stats: VismapStats,
    /// The last iteration's lists, refilled by the next.
    result: IterationResult<'s>,
    /// The last iteration's gather depths, refilled by the next.
    iteration_depths: Vec<Option<u32>>,
}

impl<'s> Bidirectional<'s> {
    /// A render of `settings` over `camera`'s image, for share `shard` = (K, N), its kernels
    /// compiled for `isa`.
    pub fn new(
        scene: &'s Scene,
        camera: &'s Camera,
        settings: VismapSettings,
        seed: u64,
        shard: (u32, u32),
        isa: Isa,
    ) -> Self {
        let pixels = camera.width() as usize * camera.height() as usize;
        let cone_cos = settings.cone_deg.map(|d| d.clamp(0.0, 90.0).to_radians().cos());
        Self {
            scene,
            camera,
            rule: GatherRule {
                depth: 0,
                cone_cos,
                max_specular: settings.max_specular,
                pass_narrow: matches!(settings.depth, GatherDepth::Adaptive { paper: false, .. }),
            },
            n_photons: settings.photons(pixels as u64),
            settings,
            seed,
            shard: (shard.0, shard.1.max(1)),
            isa,
            depths: GatherDepths::new(pixels),
            radius_scales: None,
            first_depths: None,
            stats: VismapStats::default(),
            result: IterationResult::default(),
            iteration_depths: Vec::new(),
        }
    }

    fn photon_seed(&self) -> u64 {
        mix64(self.seed ^ 0x7068_6f74_6f6e)
    }

    fn wavelengths(&self, k: u32) -> SampledWavelengths {
        SampledWavelengths::sample_visible(iteration_wavelength_u(self.seed, k))
    }

    /// The depths of iteration `k` into `depths` (pilots of earlier iterations caught up),
    /// and the radius pilot (with iteration 1's depths) before the first.
    fn depths_for(&mut self, k: u32, depths: &mut Vec<Option<u32>>) {
        let (scene, camera, seed, settings, rule) = (self.scene, self.camera, self.seed, self.settings, self.rule);
        let wl_of = |j| SampledWavelengths::sample_visible(iteration_wavelength_u(seed, j));
        if self.radius_scales.is_none() {
            let mut first = Vec::new();
            self.depths.for_iteration(scene, camera, &settings, &rule, seed, 1, wl_of, &mut first);
            let scales = radius_pilot(
                scene,
                camera,
                &settings,
                &rule,
                &first,
                Iteration {
                    seed,
                    photon_seed: self.photon_seed(),
                    k: 0,
                    wl: wl_of(0),
                    n_photons: self.n_photons,
                    record: PhotonRecord::Counts,
                    isa: self.isa,
                },
                &mut self.result,
            );
            self.radius_scales = Some(scales);
            self.first_depths = Some(first);
        }
        if k == 1
            && let Some(d) = self.first_depths.take()
        {
            *depths = d;
            return;
        }
        self.first_depths = None;
        self.depths.for_iteration(scene, camera, &settings, &rule, seed, k, wl_of, depths);
    }

    /// Renders iteration `k` into `film`.
    fn iteration(&mut self, film: &mut Film, k: u32) {
        let t = Instant::now();
        let mut depths = std::mem::take(&mut self.iteration_depths);
        self.depths_for(k, &mut depths);
        let pilots = t.elapsed().as_secs_f64();
        let (settings, n_photons) = (self.settings, self.n_photons);
        let pixel_angle = self.camera.pixel_solid_angle().sqrt();
        let shrink = radius2_factor(k, settings.alpha.clamp(1e-3, 1.0) as f64).sqrt() as f32;
        let scales = self.radius_scales.as_deref().unwrap_or_default();
        let radius_of = |i: usize, vp: &VisibilityPoint| {
            settings.radius.unwrap_or(settings.radius_pixels * pixel_angle * vp.footprint_distance * scales[i]) * shrink
        };
        let it = Iteration {
            seed: self.seed,
            photon_seed: self.photon_seed(),
            k,
            wl: self.wavelengths(k),
            n_photons,
            record: PhotonRecord::Sums,
            isa: self.isa,
        };
        let t = Instant::now();
        let result = &mut self.result;
        it.run(self.scene, self.camera, &settings, &self.rule, &depths, radius_of, result);
        let t_film = Instant::now();
        film.add_batch(result.estimates(n_photons));
        self.depths.record(&depths);
        let s = &mut self.stats;
        s.seconds.add(&PhaseSeconds { pilots, film: t_film.elapsed().as_secs_f64(), ..result.seconds });
        s.grid_bytes = s.grid_bytes.max(result.grid_bytes);
        s.max_points = s.max_points.max(result.points.len());
        s.photon_seconds += t.elapsed().as_secs_f64();
        s.photons += n_photons;
        s.lookups += result.photons.lookups;
        self.iteration_depths = depths;
    }
}

impl RenderMethod for Bidirectional<'_> {
    fn new_film(&self, width: u32, height: u32) -> Film {
        Film::with_block_batches(width, height)
    }

    fn unit_name(&self) -> &'static str {
        "iterations"
    }

    fn max_pass(&self) -> u32 {
        1
    }

    fn render_pass(&mut self, film: &mut Film, first: u32, count: u32, control: &PassControl) -> PassEnd {
        let pixels = self.camera.width() as u64 * self.camera.height() as u64;
        for unit in first..first + count {
            let k = 1 + self.shard.0 + self.shard.1 * unit;
            self.iteration(film, k);
            (control.progress)(pixels);
        }
        PassEnd::Complete
    }

    fn save_state(&self) -> Vec<u8> {
        let mut w = ByteWriter::default();
        w.bytes(b"BIDIR1");
        self.depths.save(&mut w);
        let scales = self.radius_scales.as_deref().unwrap_or_default();
        w.u64(scales.len() as u64);
        scales.iter().for_each(|&v| w.f32(v));
        w.0
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let pixels = self.camera.width() as usize * self.camera.height() as usize;
        let mut r = ByteReader::new(bytes);
        if r.take(6).ok() != Some(&b"BIDIR1"[..]) {
            return Err("the checkpoint holds another method's state".into());
        }
        self.depths = GatherDepths::load(&mut r, pixels)?;
        let n = r.u64()? as usize;
        if n != 0 && n != pixels {
            return Err(format!("radius scales of {n} pixels for an image of {pixels}"));
        }
        let scales = (0..n).map(|_| r.f32()).collect::<Result<Vec<_>, _>>()?;
        self.radius_scales = (n > 0).then_some(scales);
        if r.remaining() != 0 {
            return Err("trailing bytes in the method state".into());
        }
        Ok(())
    }

    fn extra_channels(&self) -> Vec<Channel> {
        vec![self.depths.channel()]
    }

    fn header(&self) -> Vec<(String, String)> {
        let pixels = self.camera.width() as u64 * self.camera.height() as u64;
        let mut h = self.settings.header(pixels);
        h.push(("photons".into(), self.stats.photons.to_string()));
        h.push(("time_share".into(), self.stats.seconds.shares()));
        h
    }
}
