//! Spectral curves: the closed set of ways a scene can specify a spectrum.

mod dense;

pub use dense::{DENSE_TOLERANCE, DenseSpectrum, GRID_CELLS};

use super::cie;
use super::rgb_uplift::{RgbToSpectrumTable, SigmoidPolynomial, fit_or_nearest};
use super::sampled::{LAMBDA_MAX, LAMBDA_MIN, SampledSpectrum, SampledWavelengths};

/// 1 / the luminance of the D65 spectrum: the factor that gives an RGB light colour (1, 1, 1)
/// luminance 1.
static D65_INVERSE_LUMINANCE: std::sync::LazyLock<f32> = std::sync::LazyLock::new(|| 1.0 / luminance_of(cie::d65));

/// A CIE standard illuminant available by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StandardIlluminant {
    /// CIE illuminant A (incandescent, 2856 K).
    A,
    /// CIE illuminant D65 (average daylight, 6504 K).
    D65,
}

impl StandardIlluminant {
    /// Looks an illuminant up by its CIE name ("A", "D65"; case-insensitive).
    pub fn from_name(name: &str) -> Option<Self> {
        match name.to_ascii_uppercase().as_str() {
            "A" => Some(Self::A),
            "D65" => Some(Self::D65),
            _ => None,
        }
    }

    /// Relative spectral power as tabulated by the CIE (100 at 560 nm).
    fn relative(self, lambda: f32) -> f32 {
        match self {
            Self::A => cie::illuminant_a(lambda),
            Self::D65 => cie::d65(lambda),
        }
    }
}

/// A spectral curve over wavelength in nm.
///
/// Emission curves that describe a *colour* of light (blackbody, CIE illuminants, RGB lights) are
/// normalised to luminance 1 (integral S ybar / integral ybar = 1), so that a light's `scale` is the
/// luminance-equivalent radiance: a flat spectrum of value `scale` would have the same Y.
/// Tabulated and constant curves are used as given (absolute values).
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// Piecewise-linear table, strictly increasing wavelengths, **zero outside the table**.
    PiecewiseLinear {
        /// Wavelengths in nm, strictly increasing.
        lambda: Vec<f32>,
        /// Values at those wavelengths.
        values: Vec<f32>,
    },
    /// Planck's law at `kelvin`, normalised to luminance 1.
    Blackbody {
        /// Temperature in kelvin (> 0).
        kelvin: f32,
        /// Normalisation factor computed at construction (see [`Spectrum::blackbody`]).
        norm: f32,
    },
    /// A CIE standard illuminant normalised to luminance 1.
    Illuminant {
        /// Which illuminant.
        illuminant: StandardIlluminant,
        /// Normalisation factor computed at construction.
        norm: f32,
    },
    /// A reflectance given as linear sRGB in [0, 1], uplifted to the smooth spectrum in (0, 1) of
    /// Jakob & Hanika 2019 whose colour under D65 is that RGB (see
    /// [`rgb_uplift`](super::rgb_uplift)).
    RgbReflectance(RgbSpectrum),
    /// A light colour given as linear sRGB (any non-negative values): the uplift of
    /// rgb / max(rgb), times max(rgb), times D65 normalised to luminance 1, so that (1,1,1) is D65
    /// white and the light's colour is the RGB.
    RgbIlluminant {
        /// The colour, non-negative linear sRGB.
        rgb: [f32; 3],
        /// The uplift of rgb / max(rgb).
        model: SigmoidPolynomial,
        /// Normalisation of D65 to luminance 1.
        norm: f32,
    },
    /// Another curve pre-sampled on the 1 nm grid for rendering ([`Spectrum::densified`]): the
    /// same values to float rounding, looked up instead of evaluated.
    Dense(DenseSpectrum),
}

/// An RGB colour and the reflectance spectrum it was uplifted to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbSpectrum {
    /// The colour, linear sRGB in [0, 1].
    pub rgb: [f32; 3],
    /// Its uplift.
    pub model: SigmoidPolynomial,
}

/// Error building a spectrum from invalid data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    /// The table has fewer than 1 entries or mismatched lengths.
    #[error("spectrum table needs equally many wavelengths and values (got {0} and {1}), at least one")]
    Shape(usize, usize),
    /// A wavelength or value is NaN or infinite.
    #[error("spectrum table entry {index} is not finite (wavelength {lambda}, value {value})")]
    NotFinite {
        /// Index in the table.
        index: usize,
        /// Wavelength at that index.
        lambda: f32,
        /// Value at that index.
        value: f32,
    },
    /// Wavelengths are not strictly increasing.
    #[error("spectrum wavelengths must be strictly increasing: entry {index} ({lambda} nm) follows {prev} nm")]
    NotIncreasing {
        /// Index in the table.
        index: usize,
        /// Wavelength at that index.
        lambda: f32,
        /// Previous wavelength.
        prev: f32,
    },
    /// A value is negative.
    #[error("spectrum value at entry {index} ({lambda} nm) is negative: {value}")]
    Negative {
        /// Index in the table.
        index: usize,
        /// Wavelength at that index.
        lambda: f32,
        /// The negative value.
        value: f32,
    },
    /// A parameter (temperature, constant, rgb) is out of range.
    #[error("{0}")]
    Parameter(String),
}

/// Luminance of a curve under the sensor normalisation: integral S ybar / integral ybar
/// (1 nm midpoint rule over 360..830 nm).
fn luminance_of(f: impl Fn(f32) -> f32) -> f32 {
    let mut s = 0.0f64;
    let n = (LAMBDA_MAX - LAMBDA_MIN) as usize;
    for i in 0..n {
        let l = LAMBDA_MIN + i as f32 + 0.5;
        s += (f(l) * cie::ybar(l)) as f64;
    }
    (s / cie::CIE_Y_INTEGRAL as f64) as f32
}

/// A piecewise-linear table at `lambda`: zero outside [ls[0], ls[n-1]].
#[inline]
fn piecewise_linear(ls: &[f32], values: &[f32], lambda: f32) -> f32 {
    let n = ls.len();
    if !(lambda >= ls[0] && lambda <= ls[n - 1]) {
        return 0.0;
    }
    if n == 1 {
        return values[0];
    }
    let i = knot_interval(ls, lambda);
    let t = (lambda - ls[i]) / (ls[i + 1] - ls[i]);
    values[i] * (1.0 - t) + values[i + 1] * t
}

/// The interval of a strictly increasing knot table holding `lambda` (which lies in
/// [ls[0], ls[n-1]], n >= 2): the i in 0..n-1 with ls[i] <= lambda < ls[i+1], or n-2 at the last
/// knot. The first guess assumes evenly spaced knots (measured spectra usually are), so the common
/// case costs one multiply; otherwise a binary search gives the same interval.
#[inline]
fn knot_interval(ls: &[f32], lambda: f32) -> usize {
    let n = ls.len();
    let last = n - 2;
    let guess = (((lambda - ls[0]) * (last + 1) as f32 / (ls[n - 1] - ls[0])) as usize).min(last);
    let holds = |i: usize| ls[i] <= lambda && (i == last || lambda < ls[i + 1]);
    if holds(guess) {
        guess
    } else if guess > 0 && holds(guess - 1) {
        guess - 1
    } else if guess < last && holds(guess + 1) {
        guess + 1
    } else {
        // first index with ls[i] > lambda, minus one
        ls.partition_point(|&x| x <= lambda).clamp(1, n - 1) - 1
    }
}

/// Planck's law, spectral radiance in W/(sr m^2 nm) at `lambda` nm (pbrt-v4 `Blackbody`).
pub fn planck(lambda: f32, kelvin: f32) -> f32 {
    if kelvin <= 0.0 {
        return 0.0;
    }
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = lambda as f64 * 1e-9;
    let le = (2.0 * H * C * C) / (l.powi(5) * (((H * C) / (l * KB * kelvin as f64)).exp() - 1.0));
    (le * 1e-9) as f32
}

impl Spectrum {
    /// A piecewise-linear table after validation (finite, non-negative, strictly increasing).
    pub fn piecewise_linear(lambda: Vec<f32>, values: Vec<f32>) -> Result<Self, SpectrumError> {
        if lambda.len() != values.len() || lambda.is_empty() {
            return Err(SpectrumError::Shape(lambda.len(), values.len()));
        }
        for (i, (&l, &v)) in lambda.iter().zip(&values).enumerate() {
            if !l.is_finite() || !v.is_finite() {
                return Err(SpectrumError::NotFinite { index: i, lambda: l, value: v });
            }
            if v < 0.0 {
                return Err(SpectrumError::Negative { index: i, lambda: l, value: v });
            }
            if i > 0 && l <= lambda[i - 1] {
                return Err(SpectrumError::NotIncreasing { index: i, lambda: l, prev: lambda[i - 1] });
            }
        }
        Ok(Self::PiecewiseLinear { lambda, values })
    }

    /// A constant spectrum after validation (finite, non-negative).
    pub fn constant(v: f32) -> Result<Self, SpectrumError> {
        if !v.is_finite() || v < 0.0 {
            return Err(SpectrumError::Parameter(format!("constant spectrum must be finite and >= 0, got {v}")));
        }
        Ok(Self::Constant(v))
    }

    /// A blackbody emitter at `kelvin`, normalised to luminance 1.
    pub fn blackbody(kelvin: f32) -> Result<Self, SpectrumError> {
        if !(100.0..=1e6).contains(&kelvin) {
            return Err(SpectrumError::Parameter(format!("blackbody temperature must be in 100..1e6 K, got {kelvin}")));
        }
        let y = luminance_of(|l| planck(l, kelvin));
        Ok(Self::Blackbody { kelvin, norm: 1.0 / y })
    }

    /// A CIE standard illuminant normalised to luminance 1.
    pub fn illuminant(illuminant: StandardIlluminant) -> Self {
        let y = luminance_of(|l| illuminant.relative(l));
        Self::Illuminant { illuminant, norm: 1.0 / y }
    }

    /// A reflectance from linear sRGB; components must be finite and in [0, 1]. The uplift is
    /// fitted for this colour (its colour under D65 round-trips to within 3e-5).
    pub fn rgb_reflectance(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        if rgb.iter().any(|c| !c.is_finite() || *c < 0.0 || *c > 1.0) {
            return Err(SpectrumError::Parameter(format!("reflectance rgb components must be in [0, 1], got {rgb:?}")));
        }
        Ok(Self::RgbReflectance(RgbSpectrum { rgb, model: fit_or_nearest(rgb) }))
    }

    /// A reflectance from a linear sRGB colour that changes per shading point (a texel), with
    /// the uplift interpolated in [`RgbToSpectrumTable`] (components clamped to [0, 1]; NaN is 0).
    pub fn rgb_reflectance_interpolated(rgb: [f32; 3]) -> Self {
        let rgb = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
        Self::RgbReflectance(RgbSpectrum { rgb, model: RgbToSpectrumTable::get().lookup(rgb) })
    }

    /// A light colour from linear sRGB; components must be finite and >= 0.
    pub fn rgb_illuminant(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        if rgb.iter().any(|c| !c.is_finite() || *c < 0.0) {
            return Err(SpectrumError::Parameter(format!("light rgb components must be finite and >= 0, got {rgb:?}")));
        }
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        let model = fit_or_nearest(if m > 0.0 { rgb.map(|v| v / m) } else { [0.0; 3] });
        Ok(Self::RgbIlluminant { rgb, model, norm: *D65_INVERSE_LUMINANCE })
    }

    /// A light colour that changes per shading point (an emissive texel): [`Self::rgb_illuminant`]
    /// with the uplift of the normalised colour interpolated in [`RgbToSpectrumTable`]
    /// (non-finite or negative components are 0).
    pub fn rgb_illuminant_interpolated(rgb: [f32; 3]) -> Self {
        let rgb = rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        let model = RgbToSpectrumTable::get().lookup(if m > 0.0 { rgb.map(|v| v / m) } else { [0.0; 3] });
        Self::RgbIlluminant { rgb, model, norm: *D65_INVERSE_LUMINANCE }
    }

    /// Value at `lambda` nm.
    pub fn value(&self, lambda: f32) -> f32 {
        match self {
            Self::Constant(v) => *v,
            Self::PiecewiseLinear { lambda: ls, values } => piecewise_linear(ls, values, lambda),
            Self::Blackbody { kelvin, norm } => planck(lambda, *kelvin) * norm,
            Self::Illuminant { illuminant, norm } => illuminant.relative(lambda) * norm,
            Self::RgbReflectance(s) => s.model.eval(lambda),
            Self::RgbIlluminant { rgb, model, norm } => {
                let m = rgb[0].max(rgb[1]).max(rgb[2]);
                if m <= 0.0 {
                    return 0.0;
                }
                m * model.eval(lambda) * cie::d65(lambda) * norm
            }
            Self::Dense(d) => d.curve().value(lambda),
        }
    }

    /// The curve as rendering should hold it: pre-sampled on the 1 nm grid where the grid
    /// reproduces it ([`DenseSpectrum::new`]), otherwise unchanged.
    pub fn densified(&self) -> Self {
        DenseSpectrum::new(self).map_or_else(|| self.clone(), Self::Dense)
    }

    /// Values at the path's wavelengths (the variant is matched once for all of them).
    #[inline(always)]
    pub fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Self::Constant(v) => SampledSpectrum::splat(*v),
            Self::Dense(d) => d.sample(wl),
            Self::PiecewiseLinear { lambda: ls, values } => {
                SampledSpectrum(wl.lambdas().map(|l| piecewise_linear(ls, values, l)))
            }
            Self::RgbReflectance(s) => SampledSpectrum(wl.lambdas().map(|l| s.model.eval(l))),
            Self::Illuminant { illuminant, norm } => {
                SampledSpectrum(wl.lambdas().map(|l| illuminant.relative(l) * norm))
            }
            _ => SampledSpectrum(wl.lambdas().map(|l| self.value(l))),
        }
    }

    /// Largest value over 360..830 nm (1 nm grid plus table knots): bounds reflectances.
    pub fn max_value(&self) -> f32 {
        if let Self::Dense(d) = self {
            return d.curve().max_value();
        }
        let mut m = 0.0f32;
        let mut l = LAMBDA_MIN;
        while l <= LAMBDA_MAX {
            m = m.max(self.value(l));
            l += 1.0;
        }
        if let Self::PiecewiseLinear { lambda, values } = self {
            for (&l, &v) in lambda.iter().zip(values) {
                if (LAMBDA_MIN..=LAMBDA_MAX).contains(&l) {
                    m = m.max(v);
                }
            }
        }
        m
    }

    /// Luminance: integral S ybar / integral ybar (1 for a flat spectrum of 1).
    pub fn luminance(&self) -> f32 {
        luminance_of(|l| self.value(l))
    }

    /// Mean value over 360..830 nm (radiometric, unweighted): used for power-proportional light
    /// selection, where every wavelength the renderer samples must have a non-zero chance.
    pub fn mean_value(&self) -> f32 {
        let n = (LAMBDA_MAX - LAMBDA_MIN) as usize;
        let s: f64 = (0..n).map(|i| self.value(LAMBDA_MIN + i as f32 + 0.5) as f64).sum();
        (s / n as f64) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_zero_outside_and_linear_inside() {
        let s = Spectrum::piecewise_linear(vec![400.0, 500.0, 600.0], vec![1.0, 3.0, 2.0]).unwrap();
        assert_eq!(s.value(399.9), 0.0);
        assert_eq!(s.value(600.1), 0.0);
        assert!((s.value(450.0) - 2.0).abs() < 1e-6);
        assert!((s.value(550.0) - 2.5).abs() < 1e-6);
        assert_eq!(s.value(600.0), 2.0);
        assert_eq!(s.value(400.0), 1.0);
    }

    #[test]
    fn table_validation_names_the_entry() {
        let e = Spectrum::piecewise_linear(vec![400.0, 390.0], vec![1.0, 1.0]).unwrap_err();
        assert!(matches!(e, SpectrumError::NotIncreasing { index: 1, .. }));
        let e = Spectrum::piecewise_linear(vec![400.0, 410.0], vec![1.0, f32::NAN]).unwrap_err();
        assert!(matches!(e, SpectrumError::NotFinite { index: 1, .. }));
        let e = Spectrum::piecewise_linear(vec![400.0, 410.0], vec![-1.0, 1.0]).unwrap_err();
        assert!(matches!(e, SpectrumError::Negative { index: 0, .. }));
    }

    #[test]
    fn light_colours_are_normalised_to_unit_luminance() {
        for s in [
            Spectrum::blackbody(2700.0).unwrap(),
            Spectrum::blackbody(6500.0).unwrap(),
            Spectrum::illuminant(StandardIlluminant::A),
            Spectrum::illuminant(StandardIlluminant::D65),
            Spectrum::rgb_illuminant([1.0, 1.0, 1.0]).unwrap(),
        ] {
            assert!((s.luminance() - 1.0).abs() < 1e-3, "{s:?}: {}", s.luminance());
        }
    }

    #[test]
    fn knot_interval_is_the_binary_search_interval() {
        let even: Vec<f32> = (0..76).map(|i| 380.0 + 5.0 * i as f32).collect();
        let uneven = vec![360.0, 361.0, 400.0, 401.5, 402.0, 650.0, 829.0, 830.0];
        for ls in [even, uneven, vec![400.0, 700.0]] {
            let mut l = ls[0];
            while l <= ls[ls.len() - 1] {
                let want = ls.partition_point(|&x| x <= l).clamp(1, ls.len() - 1) - 1;
                assert_eq!(knot_interval(&ls, l), want, "{l} in {ls:?}");
                l += 0.37;
            }
            for &l in &ls {
                let want = ls.partition_point(|&x| x <= l).clamp(1, ls.len() - 1) - 1;
                assert_eq!(knot_interval(&ls, l), want, "knot {l}");
            }
        }
    }

    #[test]
    fn planck_peak_follows_wien() {
        // Wien: lambda_max = 2.897771955e6 nm K / T
        let t = 5000.0;
        let peak = (380..=780).map(|l| l as f32).max_by(|a, b| planck(*a, t).total_cmp(&planck(*b, t))).unwrap();
        assert!((peak - 2.897_772e6 / t).abs() <= 1.0, "{peak}");
    }
}
