//! The scattering of a homogeneous medium inside a transmitting surface (a diffuser, an opal
//! glass, a milky light guide): the spectral scattering coefficient sigma_s(lambda) in 1/m and a
//! Henyey-Greenstein phase function of asymmetry g (Henyey and Greenstein 1941; pbrt-v4 §11.3.1):
//!
//! p(cos theta) = (1 - g²) / (4 pi (1 + g² - 2 g cos theta)^(3/2)),
//!
//! theta the angle between the direction the light travelled and the one it leaves in, so g > 0
//! scatters forwards, g = 0 is isotropic and g < 0 scatters back; g is the mean cosine of theta.
//! Together with the medium's absorption sigma_a (crate::absorption) it gives the extinction
//! sigma_t = sigma_a + sigma_s and the single-scattering albedo sigma_s / sigma_t.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::Frame;
use crate::absorption::MAX_ABSORPTION;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// Largest |g| used: beyond it the phase function's peak (about 1 / (pi (1 - |g|)²)) and the
/// sampling formula's cancellation leave f32; a given g of +-1 scatters as +-[`MAX_ASYMMETRY`].
pub const MAX_ASYMMETRY: f32 = 0.9999;

/// A medium's scattering: sigma_s(lambda) and the phase function's asymmetry.
#[derive(Clone, Debug, PartialEq)]
pub struct Scattering {
    /// sigma_s(lambda) in 1/m (>= 0).
    pub coefficient: Spectrum,
    /// Henyey-Greenstein asymmetry g in [-1, 1].
    pub g: f32,
}

impl Scattering {
    /// sigma_s at the path's wavelengths, 1/m, in [0, [`MAX_ABSORPTION`]] (the same bound as
    /// sigma_a's).
    #[inline]
    pub fn sigma_s(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        self.coefficient.sample(wl).map(|v| if v > 0.0 { v.min(MAX_ABSORPTION) } else { 0.0 })
    }

    /// The phase function.
    #[inline]
    pub fn phase(&self) -> HenyeyGreenstein {
        HenyeyGreenstein::new(self.g)
    }

    /// Checks the values: a coefficient finite and >= 0 over 360-830 nm, g in [-1, 1].
    pub fn validate(&self) -> Result<(), String> {
        let bad = (360..=830).map(|l| self.coefficient.value(l as f32)).any(|v| !(v.is_finite() && v >= 0.0));
        if bad {
            return Err("the scattering coefficient must be finite and >= 0 (1/m)".into());
        }
        if !(-1.0..=1.0).contains(&self.g) {
            return Err(format!("the phase asymmetry `phase_g` must lie in [-1, 1], got {}", self.g));
        }
        Ok(())
    }

    /// The same scattering with its spectrum pre-sampled for rendering ([`Spectrum::densified`]).
    pub fn densified(&self) -> Self {
        Self { coefficient: self.coefficient.densified(), g: self.g }
    }
}

/// The Henyey-Greenstein phase function (module doc); directions are unit vectors pointing away
/// from the scattering point, as a BSDF's: `wo` towards where the light goes (the camera's side),
/// `wi` towards where it comes from, so the light travelled along -wi and leaves along wo and
/// cos theta = -wo . wi.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    g: f32,
}

impl HenyeyGreenstein {
    /// The phase function of asymmetry `g` (clamped to +-[`MAX_ASYMMETRY`]; |g| < 1e-3 is
    /// isotropic, where the inverted distribution's division by g loses its precision, so that
    /// the value and the sampled density stay one function).
    #[inline]
    pub fn new(g: f32) -> Self {
        Self { g: if g.abs() < 1e-3 { 0.0 } else { g.clamp(-MAX_ASYMMETRY, MAX_ASYMMETRY) } }
    }

    /// The asymmetry g used (clamped).
    #[inline]
    pub fn g(&self) -> f32 {
        self.g
    }

    /// p(cos theta) in 1/sr for the cosine between the light's direction of travel before and
    /// after scattering.
    #[inline]
    pub fn value(&self, cos_theta: f32) -> f32 {
        let g = self.g;
        let denom = (1.0 + g * g - 2.0 * g * cos_theta).max(1e-12);
        (1.0 - g * g) / (4.0 * PI * denom * denom.sqrt())
    }

    /// p for the pair (`wo`, `wi`), which is also the pdf of [`sample`](Self::sample).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.value(-wo.dot(wi))
    }

    /// Samples `wi` given `wo` with density p (so the weight p / pdf is exactly 1), by inverting
    /// the cumulative distribution of cos theta (pbrt-v4 §11.3.1); returns (wi, pdf).
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let g = self.g;
        let cos_theta = if g == 0.0 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
            ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
        };
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let (sin_phi, cos_phi) = (2.0 * PI * u.y).sin_cos();
        // cos theta = -wo . wi: the sampled direction about wo, reversed
        let local = Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta);
        let wi = -Frame::from_z(wo).from_local(local);
        (wi, self.value(cos_theta))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The phase function integrates to 1 and its mean cosine is g.
    #[test]
    fn normalised_with_mean_cosine_g() {
        for g in [-0.9f32, -0.3, 0.0, 0.5, 0.95] {
            let hg = HenyeyGreenstein::new(g);
            let n = 200_000;
            let (mut total, mut mean) = (0.0f64, 0.0f64);
            for i in 0..n {
                // midpoint rule in cos theta (the azimuth integrates to 2 pi)
                let c = -1.0 + (i as f64 + 0.5) * 2.0 / n as f64;
                let p = f64::from(hg.value(c as f32)) * 2.0 * std::f64::consts::PI * 2.0 / n as f64;
                total += p;
                mean += p * c;
            }
            assert!((total - 1.0).abs() < 2e-3, "g {g}: integral {total}");
            assert!((mean - f64::from(g)).abs() < 2e-3, "g {g}: mean cosine {mean}");
        }
    }

    #[test]
    fn validation_names_the_bad_value() {
        let ok = Scattering { coefficient: Spectrum::Constant(10.0), g: 0.5 };
        assert!(ok.validate().is_ok());
        let e = Scattering { g: 1.5, ..ok.clone() }.validate().unwrap_err();
        assert!(e.contains("phase_g"), "{e}");
        assert!(Scattering { coefficient: Spectrum::Constant(-1.0), g: 0.0 }.validate().is_err());
    }
}
