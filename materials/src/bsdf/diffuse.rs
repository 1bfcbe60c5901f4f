//! Lambertian reflection: f = R / pi, sampled with a cosine-weighted hemisphere (Malley's method
//! over the concentric disk map of Shirley & Chiu 1997).

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::{BsdfSample, Lobe, TransportMode};
use crate::spectrum::SampledSpectrum;
use crate::warp::cosine_hemisphere as sample_cosine_hemisphere;

/// Lambertian reflector with albedo `r`; black from behind (wo.z <= 0) unless `two_sided`, in
/// which case it reflects on whichever side `wo` is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseBsdf {
    /// Albedo per wavelength, in [0, 1].
    pub r: SampledSpectrum,
    /// Reflect on both sides.
    pub two_sided: bool,
}

impl DiffuseBsdf {
    /// A Lambertian BSDF; the albedo is clamped to [0, 1] (NaN -> 0).
    #[inline(always)]
    pub fn new(r: SampledSpectrum, two_sided: bool) -> Self {
        Self { r: r.clamp_unit(), two_sided }
    }

    /// +1 when wo is above the surface, -1 below for a two-sided surface, None when black.
    #[inline]
    fn side(&self, wo: Vec3) -> Option<f32> {
        if wo.z > 0.0 {
            Some(1.0)
        } else if wo.z < 0.0 && self.two_sided {
            Some(-1.0)
        } else {
            None
        }
    }

    /// f = R / pi when wi is on wo's (reflecting) side, else 0.
    pub fn f(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        match self.side(wo) {
            Some(s) if wi.z * s > 0.0 => self.r * FRAC_1_PI,
            _ => SampledSpectrum::zero(),
        }
    }

    /// [`f`](Self::f) and [`pdf`](Self::pdf) together.
    #[inline(always)]
    pub fn f_pdf(&self, wo: Vec3, wi: Vec3) -> (SampledSpectrum, f32) {
        match self.side(wo) {
            Some(s) if wi.z * s > 0.0 && !self.r.is_black() => (self.r * FRAC_1_PI, wi.z.abs() * FRAC_1_PI),
            _ => (SampledSpectrum::zero(), 0.0),
        }
    }

    /// Cosine-weighted sample on wo's side; the weight f |cos| / pdf is exactly R.
    #[inline(always)]
    pub fn sample_f(&self, wo: Vec3, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let s = self.side(wo)?;
        if self.r.is_black() {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        wi.z *= s;
        let pdf = wi.z.abs() * FRAC_1_PI;
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample { f: self.r * FRAC_1_PI, wi, pdf, lobe: Lobe::Reflection, specular: false, eta: 1.0 })
    }

    /// |cos wi| / pi on wo's side, else 0.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self.side(wo) {
            Some(s) if wi.z * s > 0.0 && !self.r.is_black() => wi.z.abs() * FRAC_1_PI,
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sided_is_black_from_behind_and_two_sided_flips() {
        let r = SampledSpectrum([0.2, 0.4, 0.6, 1.0]);
        let one = DiffuseBsdf::new(r, false);
        let two = DiffuseBsdf::new(r, true);
        let up = Vec3::new(0.3, 0.0, 0.95).normalize();
        let down = Vec3::new(0.3, 0.0, -0.95).normalize();
        assert_eq!(one.f(up, up), r * FRAC_1_PI);
        assert!(one.f(down, down).is_black() && one.pdf(down, down) == 0.0);
        assert!(one.sample_f(down, Vec2::splat(0.5), TransportMode::Radiance).is_none());
        assert_eq!(two.f(down, down), r * FRAC_1_PI);
        assert!(two.f(down, up).is_black() && one.f(up, down).is_black());
        let s = two.sample_f(down, Vec2::new(0.3, 0.8), TransportMode::Radiance).unwrap();
        assert!(s.wi.z < 0.0 && (s.pdf - two.pdf(down, s.wi)).abs() < 1e-6);
        for b in [one, two, DiffuseBsdf::new(SampledSpectrum::zero(), true)] {
            for (wo, wi) in [(up, up), (up, down), (down, down), (down, up), (Vec3::X, up)] {
                assert_eq!(b.f_pdf(wo, wi), (b.f(wo, wi), b.pdf(wo, wi)));
            }
        }
        // wo exactly in the tangent plane: no side to reflect on.
        assert!(two.sample_f(Vec3::X, Vec2::splat(0.5), TransportMode::Radiance).is_none());
    }

    #[test]
    fn sample_weight_is_the_albedo() {
        let r = SampledSpectrum([0.1, 0.5, 0.7, 0.9]);
        let b = DiffuseBsdf::new(r, false);
        for i in 0..64 {
            let u = Vec2::new((i % 8) as f32 / 8.0 + 0.01, (i / 8) as f32 / 8.0 + 0.02);
            let s = b.sample_f(Vec3::Z, u, TransportMode::Radiance).unwrap();
            let w = s.f * (s.wi.z.abs() / s.pdf);
            assert!((w - r).0.iter().all(|d| d.abs() < 1e-5));
            assert!((s.wi.length() - 1.0).abs() < 1e-5);
        }
    }
}
