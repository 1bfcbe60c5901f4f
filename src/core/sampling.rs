//! Random numbers and warping functions (pbrt-v4 chapter A.5 / 13.6).

use glam::{Vec2, Vec3};
use rand_core::Rng;
use rand_pcg::Pcg32;

/// A reproducible uniform random stream for one (pixel, sample) pair or one photon, derived from
/// the render seed by hashing, so results do not depend on thread scheduling.
pub struct Sampler {
    rng: Pcg32,
}

/// SplitMix64 finaliser: a strong 64-bit mix used to derive independent stream keys.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Sampler {
    /// The stream for (`seed`, `index`, `sample`): e.g. index = pixel number, sample = sample number.
    pub fn new(seed: u64, index: u64, sample: u64) -> Self {
        let state = mix64(seed ^ mix64(index.wrapping_add(0x9e37_79b9_7f4a_7c15)));
        let stream = mix64(sample ^ mix64(seed.wrapping_add(0x632b_e59b_d9b4_e019)));
        Self { rng: Pcg32::new(state, stream) }
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn get_1d(&mut self) -> f32 {
        (self.rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// A uniform 64-bit integer (two steps of the stream), for choices among more items than a
    /// 24-bit float resolves evenly ([`AliasTable::sample`](crate::core::alias_table::AliasTable::sample)).
    #[inline]
    pub fn get_u64(&mut self) -> u64 {
        ((self.rng.next_u32() as u64) << 32) | self.rng.next_u32() as u64
    }

    /// Two uniforms in [0, 1).
    #[inline]
    pub fn get_2d(&mut self) -> Vec2 {
        Vec2::new(self.get_1d(), self.get_1d())
    }
}

/// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos_turns(u.y);
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

/// Density of [`uniform_sphere`].
pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * std::f32::consts::PI);

/// Uniform point on a triangle as barycentrics (b1, b2) (Heitz 2019's low-distortion map would
/// also do; this is the classic square-root map, pbrt-v4 `SampleUniformTriangle` v3).
pub fn uniform_triangle(u: Vec2) -> (f32, f32) {
    let su = u.x.sqrt();
    (1.0 - su, u.y * su)
}

/// Uniform direction inside a cone of half-angle acos(cos_max) around +z; pdf = 1/(2 pi (1 - cos_max)).
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_t = (1.0 - u.x) + u.x * cos_max;
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos_turns(u.y);
    Vec3::new(sin_t * cos_phi, sin_t * sin_phi, cos_t)
}

pub use quasar_materials::warp::{concentric_disk, cosine_hemisphere, sin_cos_turns};

/// Veach's power heuristic with beta = 2 for one sample from each of two strategies:
/// w_a = p_a^2 / (p_a^2 + p_b^2); infinite p_a (delta) gives 1.
#[inline]
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    if pdf_a.is_infinite() {
        return 1.0;
    }
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a + b == 0.0 || !(a + b).is_finite() {
        return if pdf_a >= pdf_b { 1.0 } else { 0.0 };
    }
    a / (a + b)
}

/// A discrete distribution over items with non-negative weights, sampled by inverting its CDF.
/// The probabilities are divided out once when it is built, so that sampling and
/// [`pmf`](Self::pmf) (once per light sample and per emitter hit of a path) never divide.
#[derive(Clone, Debug, Default)]
pub struct Distribution1D {
    cdf: Vec<f64>,
    /// (cdf[i] - cdf[i - 1]) / total per item; all 0 when the total is 0.
    pmf: Vec<f32>,
    total: f64,
}

impl Distribution1D {
    /// Builds from weights (non-finite or negative weights count as 0).
    pub fn new(weights: &[f64]) -> Self {
        let mut cdf = Vec::with_capacity(weights.len());
        let mut acc = 0.0;
        for &w in weights {
            if w.is_finite() && w > 0.0 {
                acc += w;
            }
            cdf.push(acc);
        }
        let mut prev = 0.0;
        let pmf = cdf
            .iter()
            .map(|&c| {
                let p = if acc > 0.0 { ((c - prev) / acc) as f32 } else { 0.0 };
                prev = c;
                p
            })
            .collect();
        Self { cdf, pmf, total: acc }
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.cdf.len()
    }

    /// True with no items.
    pub fn is_empty(&self) -> bool {
        self.cdf.is_empty()
    }

    /// Sum of the weights.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// Picks an item with probability weight / total; None when every weight is 0.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        if self.total <= 0.0 {
            return None;
        }
        let target = u as f64 * self.total;
        let i = self.cdf.partition_point(|&c| c <= target).min(self.cdf.len() - 1);
        Some((i, self.pmf(i)))
    }

    /// [`sample`](Self::sample) that also returns where `u` fell within the chosen item's share
    /// of [0, 1), rescaled to [0, 1): a fresh uniform number for sampling inside the item.
    pub fn sample_remapped(&self, u: f32) -> Option<(usize, f32, f32)> {
        let (i, pmf) = self.sample(u)?;
        let prev = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let width = self.cdf[i] - prev;
        let r = if width > 0.0 { ((u as f64 * self.total - prev) / width) as f32 } else { 0.5 };
        Some((i, pmf, r.clamp(0.0, 1.0 - f32::EPSILON)))
    }

    /// Probability of item `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distribution_matches_weights() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]);
        assert_eq!(d.pmf(1), 0.0);
        assert!((d.pmf(2) - 0.75).abs() < 1e-6);
        let mut counts = [0usize; 3];
        for k in 0..4000 {
            let (i, _) = d.sample((k as f32 + 0.5) / 4000.0).unwrap();
            counts[i] += 1;
        }
        assert_eq!(counts[1], 0);
        assert!((counts[2] as f32 / 4000.0 - 0.75).abs() < 1e-3);
        assert!(Distribution1D::new(&[0.0, f64::NAN]).sample(0.5).is_none());
    }

    #[test]
    fn pmf_is_each_weight_over_the_total() {
        let w = [0.3, 0.0, 1.7, f64::NAN, 2.0e-9, 5.0];
        let d = Distribution1D::new(&w);
        let total: f64 = w.iter().filter(|v| v.is_finite()).sum();
        for (i, &wi) in w.iter().enumerate() {
            let expect = if wi.is_finite() { (wi / total) as f32 } else { 0.0 };
            assert!((d.pmf(i) - expect).abs() <= expect * 1e-6, "item {i}: {} vs {expect}", d.pmf(i));
        }
        assert_eq!(d.pmf(w.len()), 0.0);
        let empty = Distribution1D::new(&[0.0, -1.0]);
        assert_eq!((empty.pmf(0), empty.pmf(1)), (0.0, 0.0));
    }

    #[test]
    fn sampler_streams_are_reproducible_and_distinct() {
        let a: Vec<f32> = {
            let mut s = Sampler::new(1, 2, 3);
            (0..4).map(|_| s.get_1d()).collect()
        };
        let b: Vec<f32> = {
            let mut s = Sampler::new(1, 2, 3);
            (0..4).map(|_| s.get_1d()).collect()
        };
        let c: Vec<f32> = {
            let mut s = Sampler::new(1, 2, 4);
            (0..4).map(|_| s.get_1d()).collect()
        };
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert!(a.iter().all(|v| (0.0..1.0).contains(v)));
    }
}
