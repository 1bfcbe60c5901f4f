//! Spectra sampled at the path's wavelengths (hero-wavelength sampling, Wilkie et al. 2014).

use std::ops::{Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Sub};

use glam::{Vec3A, Vec4};

use super::cie;

/// Number of wavelengths a path carries: one hero wavelength and three equally spaced rotations.
pub const N_SPECTRUM_SAMPLES: usize = 4;
/// Shortest wavelength (nm) the renderer simulates.
pub const LAMBDA_MIN: f32 = 360.0;
/// Longest wavelength (nm) the renderer simulates.
pub const LAMBDA_MAX: f32 = 830.0;

/// floor(x) as an index, at most `last`, for x in [0, 2^24] (checked by the callers): the
/// conversion without the saturating checks of `as`, which cost more than the look-ups they
/// serve on the per-sample path.
#[inline(always)]
pub(crate) fn floor_index(x: f32, last: usize) -> usize {
    debug_assert!((0.0..=16_777_216.0).contains(&x));
    // SAFETY: x is finite and within [0, 2^24], so its truncation fits an i32
    let i = unsafe { x.to_int_unchecked::<i32>() } as usize;
    i.min(last)
}

/// Number of 1 nm cells over [LAMBDA_MIN, LAMBDA_MAX]: the grid of pre-sampled spectra
/// ([`DenseSpectrum`](super::DenseSpectrum)).
pub const GRID_CELLS: usize = (LAMBDA_MAX - LAMBDA_MIN) as usize;

/// Where a wavelength lies on the 1 nm grid: `cell` (0..GRID_CELLS, or [`GridPos::OUTSIDE`]
/// for a wavelength outside the grid) and the position `t` in [0, 1] within the cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridPos {
    /// Cell index, lambda in [LAMBDA_MIN + cell, LAMBDA_MIN + cell + 1].
    pub cell: u32,
    /// lambda - (LAMBDA_MIN + cell).
    pub t: f32,
}

impl GridPos {
    /// The cell of a wavelength outside [LAMBDA_MIN, LAMBDA_MAX] (or NaN).
    pub const OUTSIDE: u32 = u32::MAX;

    /// The grid position of `lambda` nm; LAMBDA_MAX is the end (t = 1) of the last cell.
    #[inline]
    pub fn of(lambda: f32) -> Self {
        let x = lambda - LAMBDA_MIN;
        if !(x >= 0.0 && x <= GRID_CELLS as f32) {
            return Self { cell: Self::OUTSIDE, t: 0.0 };
        }
        let cell = floor_index(x, GRID_CELLS - 1) as u32;
        Self { cell, t: x - cell as f32 }
    }
}

/// Values of a spectral quantity at the [`N_SPECTRUM_SAMPLES`] wavelengths of a [`SampledWavelengths`].
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SampledSpectrum(pub [f32; N_SPECTRUM_SAMPLES]);

impl SampledSpectrum {
    /// The same value at every wavelength.
    #[inline]
    pub const fn splat(v: f32) -> Self {
        Self([v; N_SPECTRUM_SAMPLES])
    }
    /// Zero at every wavelength.
    #[inline]
    pub const fn zero() -> Self {
        Self::splat(0.0)
    }
    /// One at every wavelength.
    #[inline]
    pub const fn one() -> Self {
        Self::splat(1.0)
    }
    /// True when every value is exactly zero.
    #[inline]
    pub fn is_black(&self) -> bool {
        self.0.iter().all(|&v| v == 0.0)
    }
    /// True when every value is finite (no NaN, no infinity).
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }
    /// Largest value.
    #[inline]
    pub fn max_component(&self) -> f32 {
        self.0.iter().copied().fold(f32::NEG_INFINITY, f32::max)
    }
    /// Smallest value.
    #[inline]
    pub fn min_component(&self) -> f32 {
        self.0.iter().copied().fold(f32::INFINITY, f32::min)
    }
    /// Arithmetic mean of the values.
    #[inline]
    pub fn average(&self) -> f32 {
        self.0.iter().sum::<f32>() / N_SPECTRUM_SAMPLES as f32
    }
    /// Applies `f` to every value.
    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self(self.0.map(f))
    }
    /// Each value clamped to [0, 1], with NaN and infinities of either sign replaced by 0 (a
    /// reflectance made safe; the same as `v.clamp(0.0, 1.0)` for a finite v). One vector
    /// operation, so that the four values are written as one store.
    #[inline(always)]
    pub fn clamp_unit(self) -> Self {
        let v = Vec4::from_array(self.0);
        // ZERO.max(v) keeps v where v >= 0 (-0.0 included, as f32::clamp does), ONE.min(..) keeps it where <= 1
        let clamped = Vec4::ONE.min(Vec4::ZERO.max(v));
        Self(Vec4::select(v.is_finite_mask(), clamped, Vec4::ZERO).to_array())
    }
    /// Division that yields 0 where the divisor is 0 (pbrt's `SafeDiv`).
    #[inline]
    pub fn safe_div(self, d: Self) -> Self {
        let mut r = self;
        for i in 0..N_SPECTRUM_SAMPLES {
            r.0[i] = if d.0[i] != 0.0 { self.0[i] / d.0[i] } else { 0.0 };
        }
        r
    }
    /// Component-wise square root.
    #[inline]
    pub fn sqrt(self) -> Self {
        self.map(f32::sqrt)
    }
}

impl Index<usize> for SampledSpectrum {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        &self.0[i]
    }
}
impl IndexMut<usize> for SampledSpectrum {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0[i]
    }
}

macro_rules! componentwise {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
        impl $tr for SampledSpectrum {
            type Output = Self;
            #[inline]
            fn $f(self, o: Self) -> Self {
                Self(std::array::from_fn(|i| self.0[i] $op o.0[i]))
            }
        }
        impl $tr<f32> for SampledSpectrum {
            type Output = Self;
            #[inline]
            fn $f(self, o: f32) -> Self {
                Self(self.0.map(|v| v $op o))
            }
        }
        impl $tra for SampledSpectrum {
            #[inline]
            fn $fa(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
        impl $tra<f32> for SampledSpectrum {
            #[inline]
            fn $fa(&mut self, o: f32) {
                *self = *self $op o;
            }
        }
    };
}
componentwise!(Add, add, AddAssign, add_assign, +);
componentwise!(Mul, mul, MulAssign, mul_assign, *);
componentwise!(Div, div, DivAssign, div_assign, /);

impl Sub for SampledSpectrum {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self(std::array::from_fn(|i| self.0[i] - o.0[i]))
    }
}
impl Mul<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    #[inline]
    fn mul(self, s: SampledSpectrum) -> SampledSpectrum {
        s * self
    }
}

/// The wavelengths (nm) a path carries and their sampling densities (1/nm).
///
/// `lambda[0]` is the hero wavelength; the others are rotations of it by multiples of
/// (LAMBDA_MAX - LAMBDA_MIN) / 4. A pdf of 0 marks a terminated secondary wavelength (after a
/// dispersive interface): it contributes nothing from then on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    lambda: [f32; N_SPECTRUM_SAMPLES],
    pdf: [f32; N_SPECTRUM_SAMPLES],
    /// The wavelengths' places on the 1 nm grid of pre-sampled spectra.
    grid: [GridPos; N_SPECTRUM_SAMPLES],
}

impl SampledWavelengths {
    /// Hero-wavelength sampling, uniform over [LAMBDA_MIN, LAMBDA_MAX]: lambda_0 = lerp(u), the
    /// others rotated by equal steps with wrap-around; every pdf is 1 / (LAMBDA_MAX - LAMBDA_MIN).
    pub fn sample_uniform(u: f32) -> Self {
        let range = LAMBDA_MAX - LAMBDA_MIN;
        let u = u.clamp(0.0, 1.0);
        let mut lambda = [0.0; N_SPECTRUM_SAMPLES];
        lambda[0] = LAMBDA_MIN + u * range;
        let delta = range / N_SPECTRUM_SAMPLES as f32;
        for i in 1..N_SPECTRUM_SAMPLES {
            let mut l = lambda[i - 1] + delta;
            if l > LAMBDA_MAX {
                l -= range;
            }
            lambda[i] = l;
        }
        Self::from_parts(lambda, [1.0 / range; N_SPECTRUM_SAMPLES])
    }

    /// Hero-wavelength sampling with density (close to) the visual importance function of
    /// pbrt-v4 (sec. 4.6.5), p(lambda) ~ 1 / cosh^2(0.0072 (lambda - 538)), restricted to
    /// [LAMBDA_MIN, LAMBDA_MAX] (a tabulated inverse CDF, see `visible`). The rotations are taken in the CDF domain (u + i/4 mod 1), so the
    /// four wavelengths are stratified in the importance measure and each has the same marginal pdf.
    #[inline(always)]
    pub fn sample_visible(u: f32) -> Self {
        // i / N exactly, so each lane is u + i / N as a scalar loop would compute it
        let up = Vec4::splat(u) + Vec4::from_array(std::array::from_fn(|i| i as f32 / N_SPECTRUM_SAMPLES as f32));
        let up = Vec4::select(up.cmpge(Vec4::ONE), up - Vec4::ONE, up);
        let (lambda, pdf) = visible::table().sample(up);
        // GridPos::of without its range test: the table's wavelengths lie in [LAMBDA_MIN, LAMBDA_MAX]
        let x = lambda - LAMBDA_MIN;
        let cell = x.to_array().map(|x| floor_index(x, GRID_CELLS - 1) as u32);
        let t = (x - Vec4::from_array(cell.map(|c| c as f32))).to_array();
        let grid = std::array::from_fn(|i| GridPos { cell: cell[i], t: t[i] });
        Self { lambda: lambda.to_array(), pdf: pdf.to_array(), grid }
    }

    /// Builds wavelengths with explicit values and densities (tests, single-wavelength probes).
    pub fn from_parts(lambda: [f32; N_SPECTRUM_SAMPLES], pdf: [f32; N_SPECTRUM_SAMPLES]) -> Self {
        Self { lambda, pdf, grid: lambda.map(GridPos::of) }
    }

    /// The wavelengths' places on the 1 nm grid ([`DenseSpectrum`](super::DenseSpectrum)).
    #[inline]
    pub fn grid(&self) -> &[GridPos; N_SPECTRUM_SAMPLES] {
        &self.grid
    }

    /// Wavelength `i` in nm.
    #[inline]
    pub fn lambda(&self, i: usize) -> f32 {
        self.lambda[i]
    }

    /// All wavelengths in nm.
    #[inline]
    pub fn lambdas(&self) -> &[f32; N_SPECTRUM_SAMPLES] {
        &self.lambda
    }

    /// Sampling densities (1/nm) as a spectrum; terminated secondaries are 0.
    #[inline]
    pub fn pdf(&self) -> SampledSpectrum {
        SampledSpectrum(self.pdf)
    }

    /// Keeps only the hero wavelength (a dispersive event made the path wavelength-specific).
    /// The hero's pdf is divided by N so that the estimator stays unbiased: the hero now carries
    /// the whole sample (pbrt-v4 `TerminateSecondary`).
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for i in 1..N_SPECTRUM_SAMPLES {
            self.pdf[i] = 0.0;
        }
        self.pdf[0] /= N_SPECTRUM_SAMPLES as f32;
    }

    /// True once [`terminate_secondary`](Self::terminate_secondary) has been called.
    #[inline]
    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1..].iter().all(|&p| p == 0.0)
    }

    /// Converts a radiance estimate at these wavelengths into CIE XYZ, normalised so that a
    /// spectrally flat radiance of 1 gives Y = 1:
    /// XYZ = (1/N) sum_i L(lambda_i) cmf(lambda_i) / p(lambda_i) / integral(ybar).
    pub fn to_xyz(&self, l: SampledSpectrum) -> [f32; 3] {
        self.xyz_weights().apply(l)
    }

    /// The per-wavelength factors of [`to_xyz`](Self::to_xyz), to convert several estimates at
    /// these wavelengths (a sample's layers) with one colour-matching look-up per wavelength.
    #[inline]
    pub fn xyz_weights(&self) -> XyzWeights {
        let norm = 1.0 / (N_SPECTRUM_SAMPLES as f32 * cie::CIE_Y_INTEGRAL);
        let lanes = if self.secondary_terminated() { 1 } else { N_SPECTRUM_SAMPLES };
        let mut w = [Vec3A::ZERO; N_SPECTRUM_SAMPLES];
        for ((w, &pdf), g) in w.iter_mut().zip(&self.pdf).zip(&self.grid).take(lanes) {
            if pdf > 0.0 {
                *w = cie::cmf_at(g.cell, g.t) * (norm / pdf);
            }
        }
        XyzWeights { w, lanes }
    }

    /// Luminance Y only (same normalisation as [`to_xyz`](Self::to_xyz)).
    pub fn luminance(&self, l: SampledSpectrum) -> f32 {
        self.to_xyz(l)[1]
    }
}

/// cmf(lambda_i) / (N p(lambda_i) integral(ybar)) per wavelength: XYZ = sum_i L(lambda_i)
/// weight_i over the wavelengths still carried ([`SampledWavelengths::xyz_weights`]). Each
/// weight is one SIMD vector (X, Y, Z, 0), so a conversion is four multiply-adds of vectors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct XyzWeights {
    w: [Vec3A; N_SPECTRUM_SAMPLES],
    /// 1 after the secondaries were terminated (their values are ignored, whatever they hold),
    /// else all.
    lanes: usize,
}

impl XyzWeights {
    /// The XYZ of the estimate `l`.
    #[inline]
    pub fn apply(&self, l: SampledSpectrum) -> [f32; 3] {
        self.apply_vec(l).to_array()
    }

    /// [`apply`](Self::apply) as a vector: the sum over wavelengths in wavelength order, from
    /// zero, so each component is bit for bit the scalar sum.
    #[inline]
    pub fn apply_vec(&self, l: SampledSpectrum) -> Vec3A {
        let mut xyz = Vec3A::ZERO;
        if self.lanes == N_SPECTRUM_SAMPLES {
            for (w, &v) in self.w.iter().zip(&l.0) {
                xyz += *w * v;
            }
        } else {
            xyz += self.w[0] * l.0[0];
        }
        xyz
    }
}

mod visible;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamp_unit_is_the_scalar_clamp_with_non_finite_values_zero() {
        let cases = [
            [0.25, -0.5, 1.5, 1.0],
            [0.0, -0.0, f32::NAN, f32::INFINITY],
            [f32::NEG_INFINITY, f32::MIN_POSITIVE, 1.0 + f32::EPSILON, -f32::MIN_POSITIVE],
            [f32::MAX, -f32::MAX, 0.999_999_9, 1e-30],
        ];
        for c in cases {
            let got = SampledSpectrum(c).clamp_unit().0;
            let want = c.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 });
            assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{c:?}");
        }
    }

    #[test]
    fn uniform_wavelengths_are_rotations_inside_range() {
        for k in 0..100 {
            let wl = SampledWavelengths::sample_uniform(k as f32 / 100.0);
            for i in 0..N_SPECTRUM_SAMPLES {
                assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(&wl.lambda(i)));
            }
        }
    }

    #[test]
    fn visible_pdf_integrates_to_one() {
        let n = 10_000;
        let h = (LAMBDA_MAX - LAMBDA_MIN) / n as f32;
        let s: f32 = (0..n).map(|i| visible::target_pdf(LAMBDA_MIN + (i as f32 + 0.5) * h) * h).sum();
        assert!((s - 1.0).abs() < 1e-3, "{s}");
    }

    #[test]
    fn visible_wavelengths_are_rotated_in_the_cdf_and_placed_on_the_grid() {
        for k in 0..5000 {
            let u = if k == 0 { 1.0 - f32::EPSILON } else { (k as f32 * 0.618_034).fract() };
            let wl = SampledWavelengths::sample_visible(u);
            for i in 0..N_SPECTRUM_SAMPLES {
                let up = u + i as f32 / N_SPECTRUM_SAMPLES as f32;
                let (l, p) = visible::table().sample(Vec4::splat(if up >= 1.0 { up - 1.0 } else { up }));
                assert_eq!((wl.lambda(i).to_bits(), wl.pdf[i].to_bits()), (l.x.to_bits(), p.x.to_bits()), "u = {u}");
                assert_eq!(wl.grid()[i], GridPos::of(wl.lambda(i)), "u = {u}");
            }
        }
    }

    #[test]
    fn flat_radiance_gives_unit_luminance_on_average() {
        // Monte Carlo over stratified hero wavelengths: E[Y] = 1 for L = 1.
        for sampler in [SampledWavelengths::sample_uniform, SampledWavelengths::sample_visible] {
            let n = 4000;
            let y: f64 = (0..n)
                .map(|k| {
                    let wl = sampler((k as f32 + 0.5) / n as f32);
                    wl.luminance(SampledSpectrum::one()) as f64
                })
                .sum::<f64>()
                / n as f64;
            assert!((y - 1.0).abs() < 2e-3, "{y}");
        }
    }

    #[test]
    fn terminating_secondaries_keeps_the_estimate_unbiased() {
        let n = 4000;
        let y: f64 = (0..n)
            .map(|k| {
                let mut wl = SampledWavelengths::sample_visible((k as f32 + 0.5) / n as f32);
                wl.terminate_secondary();
                wl.luminance(SampledSpectrum::one()) as f64
            })
            .sum::<f64>()
            / n as f64;
        assert!((y - 1.0).abs() < 5e-3, "{y}");
    }

    #[test]
    fn vector_xyz_is_the_scalar_sum_in_wavelength_order() {
        // the scalar definition: XYZ_k = sum over the carried wavelengths i, in order from 0.0,
        // of L_i w_ik, with w_ik = cmf_k(lambda_i) / (N p_i integral(ybar))
        let norm = 1.0 / (N_SPECTRUM_SAMPLES as f32 * cie::CIE_Y_INTEGRAL);
        for k in 0..500 {
            let mut wl = SampledWavelengths::sample_visible((k as f32 + 0.37) / 500.0);
            let l = SampledSpectrum(std::array::from_fn(|i| ((k * 7 + i * 13) % 17) as f32 * 0.37 - 1.5));
            let terminated = k % 3 == 0;
            if terminated {
                wl.terminate_secondary();
            }
            let carried = if terminated { 1 } else { N_SPECTRUM_SAMPLES };
            let mut expected = [0.0f32; 3];
            for i in 0..carried {
                let cmf = cie::cmf_at(wl.grid[i].cell, wl.grid[i].t);
                let f = norm / wl.pdf[i];
                for c in 0..3 {
                    expected[c] += l.0[i] * (cmf[c] * f);
                }
            }
            let got = wl.xyz_weights().apply(l);
            assert_eq!(got.map(f32::to_bits), expected.map(f32::to_bits), "sample {k}");
            if terminated {
                // whatever the secondaries hold (a NaN included), only the hero counts
                let garbage = SampledSpectrum([l.0[0], f32::NAN, f32::INFINITY, -3.0]);
                assert_eq!(wl.xyz_weights().apply(garbage).map(f32::to_bits), expected.map(f32::to_bits));
            }
        }
    }

    #[test]
    fn grid_positions_cover_the_range() {
        assert_eq!(GridPos::of(LAMBDA_MIN), GridPos { cell: 0, t: 0.0 });
        assert_eq!(GridPos::of(LAMBDA_MAX), GridPos { cell: GRID_CELLS as u32 - 1, t: 1.0 });
        assert_eq!(GridPos::of(550.25), GridPos { cell: 190, t: 0.25 });
        for l in [359.99, 830.01, f32::NAN, f32::INFINITY] {
            assert_eq!(GridPos::of(l).cell, GridPos::OUTSIDE);
        }
    }
}
