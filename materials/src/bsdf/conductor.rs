//! Conductors: a perfect mirror when smooth, else the Torrance–Sparrow / Walter et al. 2007
//! microfacet BRDF f = D(wm) F(wo . wm) G(wo, wi) / (4 |cos o| |cos i|) with the GGX distribution,
//! height-correlated Smith G and visible-normal sampling (see [`super::microfacet`]).

use glam::{Vec2, Vec3};

use super::fresnel::SampledFresnel;
use super::microfacet::TrowbridgeReitz;
use super::{BsdfSample, Lobe, MIN_SPECULAR_COS, TransportMode, mirror_z as flip, reflect, reflecting_side};
use crate::spectrum::SampledSpectrum;

/// Smooth or GGX-rough conductor. One-sided conductors are black from behind (wo.z <= 0);
/// two-sided ones mirror the configuration into the upper hemisphere (z -> -z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConductorBsdf {
    /// Microfacet distribution; effectively smooth alpha gives a mirror.
    pub distrib: TrowbridgeReitz,
    /// Fresnel reflectance.
    pub fresnel: SampledFresnel,
    /// Reflect on both sides.
    pub two_sided: bool,
}

impl ConductorBsdf {
    /// A conductor BSDF.
    pub fn new(distrib: TrowbridgeReitz, fresnel: SampledFresnel, two_sided: bool) -> Self {
        Self { distrib, fresnel, two_sided }
    }

    /// True when the conductor is a perfect mirror.
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.distrib.effectively_smooth()
    }

    /// Whether the configuration must be mirrored (Some(true)), used as is (Some(false)) or is
    /// black (None: wo behind a one-sided surface or in the tangent plane).
    #[inline]
    fn orientation(&self, wo: Vec3) -> Option<bool> {
        reflecting_side(wo, self.two_sided)
    }

    /// f (when `want_f`, else 0) and pdf for wo in the upper hemisphere (shared by `f`, `pdf` and
    /// `sample_f`, so the three agree exactly; `pdf` skips the Fresnel term).
    #[inline(always)]
    fn eval_upper(&self, wo: Vec3, wi: Vec3, want_f: bool) -> (SampledSpectrum, f32) {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return (SampledSpectrum::zero(), 0.0);
        }
        let h = wo + wi;
        let len2 = h.length_squared();
        if len2.is_nan() || len2 <= 0.0 {
            return (SampledSpectrum::zero(), 0.0);
        }
        let wm = h / len2.sqrt();
        let cos_om = wo.dot(wm);
        if cos_om.is_nan() || cos_om <= 0.0 {
            return (SampledSpectrum::zero(), 0.0);
        }
        let f = if want_f {
            self.fresnel.eval(cos_om) * (0.25 * self.distrib.d(wm) * self.distrib.g_over_cos(wo, wi))
        } else {
            SampledSpectrum::zero()
        };
        let pdf = self.distrib.pdf_wm(wo, wm) / (4.0 * cos_om);
        if !(f.is_finite() && pdf.is_finite()) {
            return (SampledSpectrum::zero(), 0.0);
        }
        (f, pdf)
    }

    /// BRDF value (0 for a mirror).
    pub fn f(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if self.is_specular() {
            return SampledSpectrum::zero();
        }
        match self.orientation(wo) {
            Some(fl) => self.eval_upper(flip(wo, fl), flip(wi, fl), true).0,
            None => SampledSpectrum::zero(),
        }
    }

    /// [`f`](Self::f) and [`pdf`](Self::pdf) from one evaluation of the microfacet terms.
    #[inline]
    pub fn f_pdf(&self, wo: Vec3, wi: Vec3) -> (SampledSpectrum, f32) {
        if self.is_specular() {
            return (SampledSpectrum::zero(), 0.0);
        }
        match self.orientation(wo) {
            Some(fl) => self.eval_upper(flip(wo, fl), flip(wi, fl), true),
            None => (SampledSpectrum::zero(), 0.0),
        }
    }

    /// Mirror: wi = (-wo.x, -wo.y, wo.z), f = F(cos) / cos, pdf = 1. Rough: a visible normal
    /// wm ~ D_wo, wi = reflect(wo, wm), pdf = D_wo(wm) / (4 |wo . wm|) (reflection Jacobian).
    #[inline(always)]
    pub fn sample_f(&self, wo: Vec3, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let fl = self.orientation(wo)?;
        let wo_u = flip(wo, fl);
        if self.is_specular() {
            let wi = Vec3::new(-wo_u.x, -wo_u.y, wo_u.z);
            let cos = wi.z;
            if cos < MIN_SPECULAR_COS {
                return None;
            }
            let f = self.fresnel.eval(cos) / cos;
            return Some(BsdfSample {
                f,
                wi: flip(wi, fl),
                pdf: 1.0,
                lobe: Lobe::Reflection,
                specular: true,
                eta: 1.0,
            });
        }
        let wm = self.distrib.sample_wm(wo_u, u);
        let wi = reflect(wo_u, wm);
        let (f, pdf) = self.eval_upper(wo_u, wi, true);
        if pdf.is_nan() || pdf <= 0.0 || f.is_black() {
            return None;
        }
        Some(BsdfSample { f, wi: flip(wi, fl), pdf, lobe: Lobe::Reflection, specular: false, eta: 1.0 })
    }

    /// Solid-angle density of `sample_f` (0 for a mirror).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.is_specular() {
            return 0.0;
        }
        match self.orientation(wo) {
            Some(fl) => self.eval_upper(flip(wo, fl), flip(wi, fl), false).1,
            None => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::test_util::{SplitMix, random_dir};

    fn white(alpha: f32, two_sided: bool) -> ConductorBsdf {
        ConductorBsdf::new(TrowbridgeReitz::new(alpha), SampledFresnel::Constant(SampledSpectrum::one()), two_sided)
    }

    #[test]
    fn reciprocity() {
        let gold = SampledFresnel::Complex {
            eta: SampledSpectrum([1.4, 0.4, 0.2, 0.15]),
            k: SampledSpectrum([1.9, 2.5, 3.3, 4.5]),
        };
        let mut rng = SplitMix(7);
        for alpha in [0.01f32, 0.05, 0.3, 1.0] {
            let b = ConductorBsdf::new(TrowbridgeReitz::new(alpha), gold, false);
            for _ in 0..2000 {
                let (wo, wi) = (random_dir(&mut rng), random_dir(&mut rng));
                let (wo, wi) = (Vec3::new(wo.x, wo.y, wo.z.abs()), Vec3::new(wi.x, wi.y, wi.z.abs()));
                let (a, c) = (b.f(wo, wi), b.f(wi, wo));
                for i in 0..4 {
                    assert!((a[i] - c[i]).abs() <= 1e-4 * a[i].max(c[i]) + 1e-7, "{alpha} {wo} {wi}: {a:?} {c:?}");
                }
            }
        }
    }

    #[test]
    fn sample_weights_agree_with_f_and_pdf() {
        let mut rng = SplitMix(11);
        for alpha in [0.002f32, 0.05, 0.3, 1.0] {
            for two_sided in [false, true] {
                let b = white(alpha, two_sided);
                for _ in 0..4000 {
                    let wo = random_dir(&mut rng);
                    let u = Vec2::new(rng.next(), rng.next());
                    let Some(s) = b.sample_f(wo, u, TransportMode::Radiance) else { continue };
                    assert!(wo.z > 0.0 || two_sided);
                    assert!((s.wi.z > 0.0) == (wo.z > 0.0) && !s.specular);
                    let (f, pdf) = (b.f(wo, s.wi), b.pdf(wo, s.wi));
                    assert_eq!(b.f_pdf(wo, s.wi), (f, pdf));
                    let wi = random_dir(&mut rng);
                    assert_eq!(b.f_pdf(wo, wi), (b.f(wo, wi), b.pdf(wo, wi)));
                    assert!((pdf - s.pdf).abs() <= 1e-4 * pdf, "{pdf} {}", s.pdf);
                    let w1 = s.f[0] * s.wi.z.abs() / s.pdf;
                    let w2 = f[0] * s.wi.z.abs() / pdf;
                    assert!((w1 - w2).abs() < 1e-4 && w1 <= 1.0 + 1e-5, "{w1} {w2}");
                }
            }
        }
    }

    #[test]
    fn tiny_alpha_is_a_mirror() {
        for alpha in [0.0f32, 1e-4, 9.9e-4] {
            let b = ConductorBsdf::new(
                TrowbridgeReitz::new(alpha),
                SampledFresnel::Constant(SampledSpectrum::splat(0.8)),
                true,
            );
            assert!(b.is_specular());
            for wo in [Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.0, -0.6, -0.8)] {
                let s = b.sample_f(wo, Vec2::new(0.3, 0.9), TransportMode::Radiance).unwrap();
                assert!(s.specular && s.pdf == 1.0 && s.lobe == Lobe::Reflection);
                assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
                assert!((s.f[0] * s.wi.z.abs() - 0.8).abs() < 1e-6);
                assert!(b.f(wo, s.wi).is_black() && b.pdf(wo, s.wi) == 0.0);
            }
            let one = ConductorBsdf::new(
                TrowbridgeReitz::new(alpha),
                SampledFresnel::Constant(SampledSpectrum::one()),
                false,
            );
            assert!(one.sample_f(Vec3::new(0.0, 0.6, -0.8), Vec2::splat(0.5), TransportMode::Radiance).is_none());
        }
    }
}
