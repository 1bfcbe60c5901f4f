//! The absorption of a clear medium inside a transmitting surface (a coloured glass, PMMA, a
//! liquid): the spectral absorption coefficient sigma_a(lambda) in 1/m of Beer-Lambert's law
//! T(d) = exp(-sigma_a d), given directly or as an internal transmittance T measured at a
//! thickness d (glass catalogues; glTF's `attenuationColor` at `attenuationDistance`), whence
//! sigma_a = -ln(T) / d.

use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// Largest sigma_a kept (1/m): beyond it a millimetre transmits less than exp(-1e6), which f32
/// holds as 0 anyway; a transmittance of 0 at a thickness maps here instead of to infinity.
pub const MAX_ABSORPTION: f32 = 1e9;

/// A medium's absorption coefficient.
#[derive(Clone, Debug, PartialEq)]
pub enum Absorption {
    /// sigma_a(lambda) in 1/m (>= 0).
    Coefficient(Spectrum),
    /// The internal transmittance (in [0, 1]) over `thickness` metres.
    Transmittance {
        /// T(lambda), without the surfaces' reflections.
        transmittance: Spectrum,
        /// The thickness it was measured at, metres (> 0).
        thickness: f32,
    },
}

impl Absorption {
    /// sigma_a at the path's wavelengths, 1/m, in [0, [`MAX_ABSORPTION`]].
    #[inline]
    pub fn sigma_a(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        let s = match self {
            Self::Coefficient(s) => s.sample(wl),
            Self::Transmittance { transmittance, thickness } => {
                transmittance.sample(wl).map(|t| if t >= 1.0 { 0.0 } else { -t.max(0.0).ln() / thickness })
            }
        };
        s.map(|v| if v > 0.0 { v.min(MAX_ABSORPTION) } else { 0.0 })
    }

    /// Checks the values: a coefficient >= 0, a transmittance in [0, 1] and a thickness > 0,
    /// all finite.
    pub fn validate(&self) -> Result<(), String> {
        // the smallest and largest value over 360..=830 nm (1 nm steps)
        let range = |s: &Spectrum| {
            (360..=830).map(|l| s.value(l as f32)).fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
                (
                    if v.is_nan() { f32::NEG_INFINITY } else { lo.min(v) },
                    if v.is_nan() { f32::INFINITY } else { hi.max(v) },
                )
            })
        };
        match self {
            Self::Coefficient(s) => {
                let (lo, hi) = range(s);
                if lo < 0.0 || !hi.is_finite() {
                    return Err("the absorption coefficient must be finite and >= 0 (1/m)".into());
                }
            }
            Self::Transmittance { transmittance, thickness } => {
                let (lo, hi) = range(transmittance);
                if lo < 0.0 || hi > 1.0 {
                    return Err("the internal transmittance must lie in [0, 1]".into());
                }
                if !(thickness.is_finite() && *thickness > 0.0) {
                    return Err(format!("the thickness must be a positive length, got {thickness}"));
                }
            }
        }
        Ok(())
    }

    /// The same absorption with its spectra pre-sampled for rendering ([`Spectrum::densified`]).
    pub fn densified(&self) -> Self {
        match self {
            Self::Coefficient(s) => Self::Coefficient(s.densified()),
            Self::Transmittance { transmittance, thickness } => {
                Self::Transmittance { transmittance: transmittance.densified(), thickness: *thickness }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transmittance_at_a_thickness_is_its_coefficient() {
        let wl = SampledWavelengths::from_parts([450.0, 500.0, 550.0, 600.0], [1.0; 4]);
        let t = Absorption::Transmittance { transmittance: Spectrum::Constant(0.5), thickness: 0.01 };
        let s = t.sigma_a(&wl);
        assert!((s.0[0] - std::f32::consts::LN_2 / 0.01).abs() < 1e-3, "{s:?}");
        assert_eq!(Absorption::Coefficient(Spectrum::Constant(3.0)).sigma_a(&wl).0, [3.0; 4]);
        let opaque = Absorption::Transmittance { transmittance: Spectrum::Constant(0.0), thickness: 1.0 };
        assert_eq!(opaque.sigma_a(&wl).0, [MAX_ABSORPTION; 4]);
        let clear = Absorption::Transmittance { transmittance: Spectrum::Constant(1.0), thickness: 1.0 };
        assert_eq!(clear.sigma_a(&wl).0, [0.0; 4]);
        assert!(Absorption::Coefficient(Spectrum::Constant(-1.0)).validate().is_err());
        assert!(
            Absorption::Transmittance { transmittance: Spectrum::Constant(0.5), thickness: 0.0 }.validate().is_err()
        );
    }
}
