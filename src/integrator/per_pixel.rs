//! The pass of every method whose units are independent samples per pixel (`pt`, `direct`):
//! sample s of pixel i gets its own hashed random stream (seed, pixel, global sample index),
//! fresh hero wavelengths and a jittered camera ray, and the film sums a pixel's samples in
//! sample order, so the image does not depend on the pass sizes or the thread count. Shard K of
//! N renders the global samples K + N s.

use glam::Vec2;
use quasar_materials::spectrum::SampledWavelengths;
use rayon::prelude::*;

use super::pass::{PassControl, PassEnd, RenderMethod};
use crate::core::camera::Camera;
use crate::core::geometry::Ray;
use crate::core::isa::Isa;
use crate::core::sampling::Sampler;
use crate::core::scene::Scene;
use crate::film::{Film, FilmRow, LayeredRadiance};

/// Peak memory per pixel of the per-pixel methods (`pt`, `direct`): 319 bytes measured on every
/// shipped scene (BENCHMARKS.md "Memory per pixel"), plus 25%.
pub const PER_PIXEL_BYTES_PER_PIXEL: u64 = 400;

/// An estimator of the radiance along one camera ray: what a per-pixel method adds to the
/// generic pass.
pub trait PixelEstimator: Sync + Send {
    /// The layered radiance of one path starting with `ray` at the (possibly terminated)
    /// wavelengths `wl`.
    fn radiance(&self, scene: &Scene, ray: Ray, wl: &mut SampledWavelengths, sampler: &mut Sampler) -> LayeredRadiance;

    /// Header entries of the estimator's settings.
    fn header(&self) -> Vec<(String, String)>;
}

/// Samples-per-pixel passes of an estimator.
pub struct PerPixel<'s, E> {
    scene: &'s Scene,
    camera: &'s Camera,
    estimator: E,
    seed: u64,
    shard: (u32, u32),
    isa: Isa,
}

impl<'s, E: PixelEstimator> PerPixel<'s, E> {
    /// The method of `estimator` over `camera`'s image, for render share `shard` = (K, N), its
    /// kernel compiled for `isa`.
    pub fn new(scene: &'s Scene, camera: &'s Camera, estimator: E, seed: u64, shard: (u32, u32), isa: Isa) -> Self {
        Self { scene, camera, estimator, seed, shard: (shard.0, shard.1.max(1)), isa }
    }

    /// One sample of pixel (x, y) with global sample index `s`.
    #[inline(always)]
    fn sample(&self, x: u32, y: u32, s: u32) -> (LayeredRadiance, SampledWavelengths) {
        let index = y as u64 * self.camera.width() as u64 + x as u64;
        let mut sampler = Sampler::new(self.seed, index, s as u64);
        let mut wl = SampledWavelengths::sample_visible(sampler.get_1d());
        let jitter = sampler.get_2d();
        let ray = self.camera.ray(Vec2::new(x as f32, y as f32) + jitter);
        let l = self.estimator.radiance(self.scene, ray, &mut wl, &mut sampler);
        (l, wl)
    }

    /// The samples `first..first + count` of every pixel of image row `y`, added to `row`: the
    /// pass's kernel, compiled once per instruction set ([`crate::core::isa`]).
    #[inline(always)]
    fn row(&self, row: &mut FilmRow<'_>, y: u32, first: u32, count: u32) {
        let (k, n) = self.shard;
        for x in 0..row.width() {
            for s in first..first + count {
                let (l, wl) = self.sample(x as u32, y, k + n * s);
                row.add(x, &l, &wl);
            }
        }
    }
}

impl<E: PixelEstimator> RenderMethod for PerPixel<'_, E> {
    fn new_film(&self, width: u32, height: u32) -> Film {
        Film::new(width, height)
    }

    fn unit_name(&self) -> &'static str {
        "samples per pixel"
    }

    fn max_pass(&self) -> u32 {
        64
    }

    fn render_pass(&mut self, film: &mut Film, first: u32, count: u32, control: &PassControl) -> PassEnd {
        let w = self.camera.width() as usize;
        let this = &*self;
        let skipped: usize = film
            .rows_mut()
            .enumerate()
            // one row per task: rows differ in cost (sky and objects), and rayon would otherwise
            // leave a piece of a quarter of a thread's rows to the thread that started it
            .with_max_len(1)
            .map(|(y, mut row)| {
                // an interrupted pass leaves the remaining rows with fewer samples
                if (control.stop)() {
                    return 1;
                }
                this.isa.run(
                    #[inline(always)]
                    || this.row(&mut row, y as u32, first, count),
                );
                (control.progress)(w as u64 * count as u64);
                0
            })
            .sum();
        if skipped > 0 { PassEnd::Partial } else { PassEnd::Complete }
    }

    fn save_state(&self) -> Vec<u8> {
        Vec::new()
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        if bytes.is_empty() { Ok(()) } else { Err("the checkpoint holds another method's state".into()) }
    }

    fn header(&self) -> Vec<(String, String)> {
        self.estimator.header()
    }
}
