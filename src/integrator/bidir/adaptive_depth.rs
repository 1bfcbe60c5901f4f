//! The gather depth of every pixel and iteration (docs/architecture.md §7.5): fixed
//! (`vismap`), or adaptive — the depth of least non-uniformity kappa along a pixel's path, chosen
//! as the mode of the depths that independent pilot paths of *earlier* iterations picked, so
//! that each iteration stays an unbiased estimate (the paper's own variant, the iteration's own
//! first ray, is kept behind `--adaptive-paper` and is biased). Pilot paths of every iteration
//! are traced on every render share, in iteration order, so shards and resumed renders choose
//! the depths the uninterrupted render chooses. After [`PILOT_ITERATIONS`] iterations the
//! histogram stays as it is.

use glam::Vec2;
use quasar_materials::spectrum::SampledWavelengths;
use rayon::prelude::*;

use super::settings::{GatherDepth, MAX_ADAPTIVE_DEPTH, VismapSettings};
use super::visibility_point::{GatherRule, pilot_gather_depth};
use crate::core::bytes::{ByteReader, ByteWriter};
use crate::core::camera::Camera;
use crate::core::sampling::{Sampler, mix64};
use crate::core::scene::Scene;
use crate::film::Channel;

/// Iterations with pilot paths: from then on the histogram (this many pilots plus iteration 0's
/// per pixel) is kept as it is, so that a long render stops paying for a camera path per pixel
/// and iteration that no longer changes the depths (measured on the glass plate: the pilots were
/// 14% of an iteration's time; a depth chosen as the mode of 33 pilots is as good as any later).
pub const PILOT_ITERATIONS: u32 = 32;

/// Depths a histogram tracks.
const BINS: usize = MAX_ADAPTIVE_DEPTH as usize + 1;

/// The per-pixel gather depths: pilot histograms, and the depths used so far (`trace_depth.Y`).
#[derive(Clone, Debug, PartialEq)]
pub struct GatherDepths {
    /// Per pixel: how often pilot paths chose each depth.
    histogram: Vec<[u32; BINS]>,
    /// Iterations whose pilot paths are in the histogram (1..=pilots).
    pilots: u32,
    /// Per pixel: sum of the depths used.
    depth_sum: Vec<u64>,
    /// Per pixel: iterations with a depth.
    depth_count: Vec<u32>,
}

impl GatherDepths {
    /// No pilots yet, for `pixels` pixels.
    pub fn new(pixels: usize) -> Self {
        Self { histogram: vec![[0; BINS]; pixels], pilots: 0, depth_sum: vec![0; pixels], depth_count: vec![0; pixels] }
    }

    /// The most frequent depth of pixel `i` (ties: the smaller depth; none seen: 0).
    fn mode(&self, i: usize) -> u32 {
        let c = &self.histogram[i];
        let mut best = 0;
        for d in 1..c.len() {
            if c[d] > c[best] {
                best = d;
            }
        }
        best as u32
    }

    fn add(&mut self, pilots: Vec<Option<u32>>) {
        for (c, d) in self.histogram.iter_mut().zip(pilots) {
            if let Some(d) = d {
                c[d as usize] += 1;
            }
        }
    }

    /// The gather depth of every pixel for iteration `k` (at its wavelengths `wl`), after
    /// tracing the pilot paths of the iterations before it that are not in the histogram yet
    /// (`wl_of` gives their wavelengths).
    #[allow(clippy::too_many_arguments)]
    pub fn for_iteration(
        &mut self,
        scene: &Scene,
        camera: &Camera,
        settings: &VismapSettings,
        rule: &GatherRule,
        seed: u64,
        k: u32,
        wl_of: impl Fn(u32) -> SampledWavelengths,
    ) -> Vec<Option<u32>> {
        let n = self.histogram.len();
        let w = camera.width() as usize;
        let pilot = |i: usize, stream_seed: u64, k: u32, wl: SampledWavelengths, max_depth: u32| {
            let mut sampler = Sampler::new(stream_seed, i as u64, k as u64);
            let film_pos = Vec2::new((i % w) as f32, (i / w) as f32) + sampler.get_2d();
            pilot_gather_depth(scene, camera.ray(film_pos), wl, &mut sampler, rule, max_depth)
        };
        match settings.depth {
            GatherDepth::Fixed(d) => vec![Some(d); n],
            GatherDepth::Adaptive { max_depth, paper: true } => {
                // the iteration's own stream: the same first camera ray as the estimate
                let wl = wl_of(k);
                (0..n).into_par_iter().map(|i| pilot(i, seed, k, wl, max_depth)).collect()
            }
            GatherDepth::Adaptive { max_depth, paper: false } => {
                let pilot_seed = mix64(seed ^ 0x0070_696c_6f74);
                // the pilots of iterations 1..k (k's own only informs later iterations), and
                // before iteration 1 an extra pilot (stream 0) so that it has a depth to use
                while (self.pilots + 1 < k && self.pilots < PILOT_ITERATIONS) || self.pilots == 0 {
                    let j = self.pilots + 1;
                    let wl = wl_of(j);
                    if j == 1 {
                        let first = (0..n).into_par_iter().map(|i| pilot(i, pilot_seed, 0, wl, max_depth)).collect();
                        self.add(first);
                    }
                    if j == k {
                        break;
                    }
                    let next = (0..n).into_par_iter().map(|i| pilot(i, pilot_seed, j, wl, max_depth)).collect();
                    self.add(next);
                    self.pilots = j;
                }
                let chosen = (0..n).map(|i| Some(self.mode(i))).collect();
                if k <= PILOT_ITERATIONS && self.pilots < k {
                    let wl = wl_of(k);
                    let next = (0..n).into_par_iter().map(|i| pilot(i, pilot_seed, k, wl, max_depth)).collect();
                    self.add(next);
                    self.pilots = k;
                }
                chosen
            }
        }
    }

    /// Records the depths an iteration used.
    pub fn record(&mut self, depths: &[Option<u32>]) {
        for (i, d) in depths.iter().enumerate() {
            if let Some(d) = d {
                self.depth_sum[i] += *d as u64;
                self.depth_count[i] += 1;
            }
        }
    }

    /// `trace_depth.Y`: the mean gather depth used per pixel.
    pub fn channel(&self) -> Channel {
        let values = self
            .depth_sum
            .iter()
            .zip(&self.depth_count)
            .map(|(&s, &c)| if c > 0 { s as f32 / c as f32 } else { 0.0 })
            .collect();
        Channel { name: "trace_depth.Y".into(), values }
    }

    /// Appends the state to `w`.
    pub fn save(&self, w: &mut ByteWriter) {
        w.u64(self.histogram.len() as u64);
        w.u32(self.pilots);
        for h in &self.histogram {
            h.iter().for_each(|&c| w.u32(c));
        }
        for (&s, &c) in self.depth_sum.iter().zip(&self.depth_count) {
            w.u64(s);
            w.u32(c);
        }
    }

    /// Reads a state saved by [`save`](Self::save) for `pixels` pixels.
    pub fn load(r: &mut ByteReader, pixels: usize) -> Result<Self, String> {
        let n = r.u64()?;
        if n != pixels as u64 {
            return Err(format!("gather depths of {n} pixels for an image of {pixels}"));
        }
        let mut s = Self::new(pixels);
        s.pilots = r.u32()?;
        for h in s.histogram.iter_mut() {
            for c in h.iter_mut() {
                *c = r.u32()?;
            }
        }
        for i in 0..pixels {
            s.depth_sum[i] = r.u64()?;
            s.depth_count[i] = r.u32()?;
        }
        Ok(s)
    }
}
