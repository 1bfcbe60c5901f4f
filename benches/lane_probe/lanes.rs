//! Lane types: W floats, W 3-vectors, per-lane helpers and W random streams.

use super::*;

/// W floats, one per lane.
pub(crate) type L<const W: usize> = [f32; W];

/// Three lane vectors: x, y and z of W 3-vectors.
#[derive(Clone, Copy)]
pub(crate) struct V<const W: usize> {
    pub(crate) x: L<W>,
    pub(crate) y: L<W>,
    pub(crate) z: L<W>,
}

impl<const W: usize> V<W> {
    /// The zero vector in every lane.
    pub(crate) const ZERO: Self = Self { x: [0.0; W], y: [0.0; W], z: [0.0; W] };

    /// Stores `v` in lane `i`.
    #[inline(always)]
    pub(crate) fn set(&mut self, i: usize, v: Vec3) {
        (self.x[i], self.y[i], self.z[i]) = (v.x, v.y, v.z);
    }

    /// The vector of lane `i`.
    #[inline(always)]
    pub(crate) fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }
}

/// `offset_origin(p, p_err, n, d)` for every lane.
#[inline(always)]
pub(crate) fn offset<const W: usize>(p: &V<W>, e: &V<W>, n: &V<W>, d: &V<W>, out: &mut V<W>) {
    for i in 0..W {
        out.set(i, offset_origin(p.get(i), e.get(i), n.get(i), d.get(i)));
    }
}

/// quasar's `power_heuristic` (w = a^2 / (a^2 + b^2), 1 for an infinite `a`) written as selects
/// for the lane loops.
#[inline(always)]
pub(crate) fn power(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    let s = a2 + b2;
    if s > 0.0 && s.is_finite() {
        a2 / s
    } else if a >= b {
        1.0
    } else {
        0.0
    }
}

/// Quasar's `Sampler` streams (PCG32 from `rand_pcg`, seeded as `Sampler::new` seeds it), one
/// per lane, advanced together: the probe draws the same numbers per path at every width.
pub(crate) struct LaneRng<const W: usize> {
    pub(crate) state: [u64; W],
    pub(crate) inc: [u64; W],
}

/// PCG32's LCG multiplier (`rand_pcg`'s `Lcg64Xsh32`).
const PCG_MULT: u64 = 6_364_136_223_846_793_005;

impl<const W: usize> LaneRng<W> {
    /// Lane `i` starts the stream of `Sampler::new(seed, index, sample)`.
    pub(crate) fn start(&mut self, i: usize, seed: u64, index: u64, sample: u64) {
        let state = mix64(seed ^ mix64(index.wrapping_add(0x9e37_79b9_7f4a_7c15)));
        let stream = mix64(sample ^ mix64(seed.wrapping_add(0x632b_e59b_d9b4_e019)));
        self.inc[i] = (stream << 1) | 1;
        self.state[i] = state.wrapping_add(self.inc[i]).wrapping_mul(PCG_MULT).wrapping_add(self.inc[i]);
    }

    /// PCG's XSH RR output of state `s`.
    #[inline(always)]
    fn output(s: u64) -> u32 {
        let xsh = (((s >> 18) ^ s) >> 27) as u32;
        xsh.rotate_right((s >> 59) as u32)
    }

    /// The next number of lane `i` alone.
    #[inline(always)]
    pub(crate) fn next_one(&mut self, i: usize) -> u32 {
        let s = self.state[i];
        self.state[i] = s.wrapping_mul(PCG_MULT).wrapping_add(self.inc[i]);
        Self::output(s)
    }

    /// The next number of every lane in `on` (the others keep their state).
    #[inline(always)]
    pub(crate) fn next(&mut self, on: &[bool; W]) -> [u32; W] {
        let mut out = [0u32; W];
        for i in 0..W {
            let s = self.state[i];
            let n = s.wrapping_mul(PCG_MULT).wrapping_add(self.inc[i]);
            self.state[i] = if on[i] { n } else { s };
            out[i] = Self::output(s);
        }
        out
    }

    /// `Sampler::get_1d` in every lane of `on`.
    #[inline(always)]
    pub(crate) fn uniform(&mut self, on: &[bool; W]) -> L<W> {
        self.next(on).map(|u| (u >> 8) as f32 * (1.0 / 16_777_216.0))
    }
}

/// `Sampler::get_1d` from a raw number.
#[inline(always)]
pub(crate) fn unit(u: u32) -> f32 {
    (u >> 8) as f32 * (1.0 / 16_777_216.0)
}
