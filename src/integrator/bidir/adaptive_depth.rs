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

/// The most frequent depth of a histogram (ties: the smaller depth; none seen: 0).
fn mode_of(c: &[u32; BINS]) -> usize {
    let mut best = 0;
    for d in 1..c.len() {
        if c[d] > c[best] {
            best = d;
        }
    }
    best
}

/// True when `remaining` more pilots, however they fall, cannot change the mode of `c`: it
/// leads every other depth by more than `remaining`.
fn mode_is_settled(c: &[u32; BINS], remaining: u32) -> bool {
    let best = mode_of(c);
    c.iter().enumerate().all(|(d, &n)| d == best || n + remaining < c[best])
}

impl GatherDepths {
    /// No pilots yet, for `pixels` pixels.
    pub fn new(pixels: usize) -> Self {
        Self { histogram: vec![[0; BINS]; pixels], pilots: 0, depth_sum: vec![0; pixels], depth_count: vec![0; pixels] }
    }

    /// The most frequent depth of pixel `i` (ties: the smaller depth; none seen: 0).
    fn mode(&self, i: usize) -> u32 {
        mode_of(&self.histogram[i]) as u32
    }

    /// Traces pilot `stream` (0..=[`PILOT_ITERATIONS`], in order) of every pixel whose mode
    /// it can still change, `pilot(i)` for pixel i, into the histograms. This pilot and those
    /// after it are `remaining` = `PILOT_ITERATIONS + 1 - stream`; a pixel whose mode leads
    /// every other depth by more than that is skipped: no sequence of the remaining pilots
    /// could change its mode (ties go to the smaller depth, so a lead of exactly that many
    /// could), neither now nor after any of them, so every iteration's depth is the one the
    /// full pilots would choose.
    fn add_pilots(&mut self, stream: u32, pilot: impl Fn(usize) -> Option<u32> + Sync) {
        let remaining = PILOT_ITERATIONS + 1 - stream;
        self.histogram.par_iter_mut().enumerate().with_max_len(super::ITEMS_PER_TASK).for_each(|(i, c)| {
            if mode_is_settled(c, remaining) {
                return;
            }
            if let Some(d) = pilot(i) {
                c[d as usize] += 1;
            }
        });
    }

    /// The gather depth of every pixel for iteration `k` (at its wavelengths `wl`) into
    /// `depths`, after tracing the pilot paths of the iterations before it that are not in the
    /// histogram yet (`wl_of` gives their wavelengths).
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
        depths: &mut Vec<Option<u32>>,
    ) {
        let n = self.histogram.len();
        let w = camera.width() as usize;
        let pilot = |i: usize, stream_seed: u64, k: u32, wl: SampledWavelengths, max_depth: u32| {
            let mut sampler = Sampler::new(stream_seed, i as u64, k as u64);
            let film_pos = Vec2::new((i % w) as f32, (i / w) as f32) + sampler.get_2d();
            pilot_gather_depth(scene, camera.ray(film_pos), wl, &mut sampler, rule, max_depth)
        };
        depths.clear();
        match settings.depth {
            GatherDepth::Fixed(d) => depths.resize(n, Some(d)),
            GatherDepth::Adaptive { max_depth, paper: true } => {
                // the iteration's own stream: the same first camera ray as the estimate
                let wl = wl_of(k);
                (0..n)
                    .into_par_iter()
                    .with_max_len(super::ITEMS_PER_TASK)
                    .map(|i| pilot(i, seed, k, wl, max_depth))
                    .collect_into_vec(depths);
            }
            GatherDepth::Adaptive { max_depth, paper: false } => {
                let pilot_seed = mix64(seed ^ 0x0070_696c_6f74);
                // the pilots of iterations 1..k (k's own only informs later iterations), and
                // before iteration 1 an extra pilot (stream 0) so that it has a depth to use
                while (self.pilots + 1 < k && self.pilots < PILOT_ITERATIONS) || self.pilots == 0 {
                    let j = self.pilots + 1;
                    let wl = wl_of(j);
                    if j == 1 {
                        self.add_pilots(0, |i| pilot(i, pilot_seed, 0, wl, max_depth));
                    }
                    if j == k {
                        break;
                    }
                    self.add_pilots(j, |i| pilot(i, pilot_seed, j, wl, max_depth));
                    self.pilots = j;
                }
                let this = &*self;
                (0..n)
                    .into_par_iter()
                    .with_max_len(super::ITEMS_PER_TASK)
                    .map(|i| Some(this.mode(i)))
                    .collect_into_vec(depths);
                if k <= PILOT_ITERATIONS && self.pilots < k {
                    let wl = wl_of(k);
                    self.add_pilots(k, |i| pilot(i, pilot_seed, k, wl, max_depth));
                    self.pilots = k;
                }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every sequence of `remaining` pilots, as depths: every depth's count after each of them.
    fn modes_after_every_sequence(c: &[u32; BINS], remaining: u32, seen: &mut Vec<usize>) {
        seen.push(mode_of(c));
        if remaining > 0 {
            for d in 0..BINS {
                let mut next = *c;
                next[d] += 1;
                modes_after_every_sequence(&next, remaining - 1, seen);
            }
        }
    }

    #[test]
    fn a_settled_mode_survives_every_sequence_of_the_remaining_pilots() {
        let mut rng = crate::core::sampling::Sampler::new(3, 1, 4);
        let (mut settled, mut open) = (0, 0);
        for _ in 0..400 {
            let mut c = [0u32; BINS];
            for _ in 0..(rng.get_1d() * 12.0) as usize {
                // pilots bunched at a few depths, as a pixel's are
                c[((rng.get_1d() * rng.get_1d()) * BINS as f32) as usize] += 1;
            }
            let remaining = (rng.get_1d() * 4.0) as u32;
            let mut modes = Vec::new();
            modes_after_every_sequence(&c, remaining, &mut modes);
            let fixed = modes.iter().all(|&m| m == mode_of(&c));
            if mode_is_settled(&c, remaining) {
                assert!(fixed, "{c:?} with {remaining} to come was taken as settled");
                settled += 1;
            } else {
                open += 1;
            }
        }
        assert!(settled > 50 && open > 50, "{settled} settled, {open} open: the cases do not test both sides");
    }

    #[test]
    fn skipping_pilots_keeps_every_iterations_mode() {
        // pixels whose pilots agree more or less often, some finding no depth at all
        let n = 500;
        let pilot = |i: usize, stream: u32| {
            let mut s = crate::core::sampling::Sampler::new(11, i as u64, stream as u64);
            let agree = (i % 10) as f32 / 9.0;
            if s.get_1d() < 0.05 {
                None
            } else if s.get_1d() < agree {
                Some((i % BINS) as u32)
            } else {
                Some((s.get_1d() * BINS as f32) as u32 % BINS as u32)
            }
        };
        let mut skipping = GatherDepths::new(n);
        let mut full = vec![[0u32; BINS]; n];
        let mut traced = 0;
        for stream in 0..=PILOT_ITERATIONS {
            let count = std::sync::atomic::AtomicUsize::new(0);
            skipping.add_pilots(stream, |i| {
                count.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                pilot(i, stream)
            });
            traced += count.into_inner();
            for (i, c) in full.iter_mut().enumerate() {
                if let Some(d) = pilot(i, stream) {
                    c[d as usize] += 1;
                }
                assert_eq!(skipping.mode(i) as usize, mode_of(c), "pixel {i} after pilot {stream}");
            }
        }
        let all = n * (PILOT_ITERATIONS as usize + 1);
        assert!(traced < all * 9 / 10, "{traced} of {all} pilots traced: the skip never fired");
    }

    #[test]
    fn a_tie_the_remaining_pilots_could_reach_is_not_settled() {
        // depth 3 leads depth 1 by 2; two more pilots at depth 1 tie it, and a tie goes to the
        // smaller depth
        let mut c = [0u32; BINS];
        (c[1], c[3]) = (4, 6);
        assert!(!mode_is_settled(&c, 2));
        assert!(mode_is_settled(&c, 1));
    }
}
