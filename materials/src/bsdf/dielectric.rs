//! Dielectric interfaces: smooth (Dirac reflection + refraction chosen with the Fresnel
//! probability) and rough (Walter et al. 2007, "Microfacet models for refraction through rough
//! surfaces", with pbrt-v4's generalised half vector wm = normalize(eta' wi + wo) for both lobes).
//!
//! `eta` is the IOR of the inside (z < 0) over the outside (z > 0); a path with wo.z < 0 is
//! inside and sees 1/eta. eta' in the formulas below is the relative IOR crossed by a
//! transmission (eta when wo is outside, 1/eta when inside; 1 for a reflection).

use glam::{Vec2, Vec3};

use super::fresnel::fr_dielectric;
use super::microfacet::TrowbridgeReitz;
use super::{BsdfSample, Lobe, MIN_SPECULAR_COS, TransportMode, reflect, refract};
use crate::spectrum::SampledSpectrum;

/// Smooth or GGX-rough dielectric interface with relative IOR `eta` (inside / outside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricBsdf {
    /// IOR of the inside relative to the outside (> 0; 1 = index-matched, a pass-through).
    pub eta: f32,
    /// Microfacet distribution; effectively smooth alpha gives a Dirac interface.
    pub distrib: TrowbridgeReitz,
    /// Factor on the transmitted light at this crossing (1 = clear; in [0, 1]): a coloured
    /// glass's tint, glTF's base colour of a transmissive material. Sampling ignores it.
    pub tint: SampledSpectrum,
}

impl DielectricBsdf {
    /// A clear dielectric BSDF; a non-finite or non-positive `eta` is replaced by 1 (pass-through).
    pub fn new(eta: f32, distrib: TrowbridgeReitz) -> Self {
        Self { eta: if eta.is_finite() && eta > 0.0 { eta } else { 1.0 }, distrib, tint: SampledSpectrum::one() }
    }

    /// The same interface whose transmitted light is multiplied by `tint`.
    pub fn with_tint(self, tint: SampledSpectrum) -> Self {
        Self { tint, ..self }
    }

    /// `f` as a spectrum: tinted for a transmission (wo and wi on opposite sides).
    #[inline(always)]
    fn spectrum(&self, f: f32, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if (wo.z > 0.0) == (wi.z > 0.0) { SampledSpectrum::splat(f) } else { f * self.tint }
    }

    /// True for a smooth interface or eta = 1 (both lobes are Dirac deltas).
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.eta == 1.0 || self.distrib.effectively_smooth()
    }

    /// Rough f and pdf, shared by `f`, `pdf` and `sample_f`.
    ///
    /// Reflection: f = D G F / (4 |cos o cos i|), pdf = D_wo(wm) / (4 |wo.wm|) * F.
    /// Transmission: with h = eta' wi + wo, wm = h / |h| and (wi.wm + wo.wm / eta')^2 = |h|^2 / eta'^2,
    /// f = (1 - F) D G |wi.wm| |wo.wm| eta'^2 / (|cos o cos i| |h|^2), divided by eta'^2 in
    /// Radiance mode; pdf = D_wo(wm) |wi.wm| eta'^2 / |h|^2 * (1 - F).
    /// F = fr_dielectric(wo.wm, eta). Back-facing microfacets (wm on the wrong side of wo or wi)
    /// contribute nothing.
    #[inline(always)]
    fn eval_rough(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (f32, f32) {
        let (co, ci) = (wo.z, wi.z);
        if co == 0.0 || ci == 0.0 {
            return (0.0, 0.0);
        }
        let reflect = (co > 0.0) == (ci > 0.0);
        let etap = if reflect {
            1.0
        } else if co > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let h = wi * etap + wo;
        let len2 = h.length_squared();
        if !(len2 > 0.0 && len2.is_finite()) {
            return (0.0, 0.0);
        }
        let mut wm = h / len2.sqrt();
        if wm.z < 0.0 {
            wm = -wm;
        }
        let (dot_o, dot_i) = (wo.dot(wm), wi.dot(wm));
        if dot_o == 0.0 || dot_i == 0.0 || (dot_o > 0.0) != (co > 0.0) || (dot_i > 0.0) != (ci > 0.0) {
            return (0.0, 0.0);
        }
        let fr = fr_dielectric(dot_o, self.eta);
        let d = self.distrib.d(wm);
        let g_cos = self.distrib.g_over_cos(wo, wi);
        let pdf_wm = self.distrib.pdf_wm(wo, wm);
        let (f, pdf) = if reflect {
            (0.25 * d * g_cos * fr, pdf_wm / (4.0 * dot_o.abs()) * fr)
        } else {
            let jac = etap * etap / len2; // 1 / (wi.wm + wo.wm / eta')^2
            let mut f = (1.0 - fr) * d * g_cos * (dot_i * dot_o).abs() * jac;
            if mode == TransportMode::Radiance {
                f /= etap * etap;
            }
            (f, pdf_wm * dot_i.abs() * jac * (1.0 - fr))
        };
        if f.is_finite() && pdf.is_finite() && f >= 0.0 && pdf >= 0.0 { (f, pdf) } else { (0.0, 0.0) }
    }

    /// BSDF value (0 for a smooth interface).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if self.is_specular() {
            return SampledSpectrum::zero();
        }
        self.spectrum(self.eval_rough(wo, wi, mode).0, wo, wi)
    }

    /// [`f`](Self::f) and [`pdf`](Self::pdf) from one evaluation of the rough model.
    #[inline]
    pub fn f_pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, f32) {
        if self.is_specular() {
            return (SampledSpectrum::zero(), 0.0);
        }
        let (f, pdf) = self.eval_rough(wo, wi, mode);
        (self.spectrum(f, wo, wi), pdf)
    }

    /// Solid-angle density of `sample_f` (0 for a smooth interface).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        if self.is_specular() {
            return 0.0;
        }
        self.eval_rough(wo, wi, mode).1
    }

    /// Smooth: reflection with probability R = F(cos o), else refraction; the delta weights are
    /// R and T = 1 - R (T / eta'^2 in Radiance mode), so f = weight / |cos i|, pdf = R or T.
    /// Rough: wm from the visible normals of wo, then reflection with probability F(wo.wm) or
    /// refraction through wm; f and pdf from the rough model.
    #[inline(always)]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        if self.is_specular() {
            let r = fr_dielectric(wo.z, self.eta);
            let t = 1.0 - r;
            if uc < r {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let c = wi.z.abs();
                if c < MIN_SPECULAR_COS {
                    return None;
                }
                return Some(BsdfSample {
                    f: SampledSpectrum::splat(r / c),
                    wi,
                    pdf: r,
                    lobe: Lobe::Reflection,
                    specular: true,
                    eta: 1.0,
                });
            }
            let (wi, etap) = refract(wo, Vec3::Z, self.eta)?;
            let c = wi.z.abs();
            if c < MIN_SPECULAR_COS || t.is_nan() || t <= 0.0 || (wi.z > 0.0) == (wo.z > 0.0) {
                return None;
            }
            let mut ft = t / c;
            if mode == TransportMode::Radiance {
                ft /= etap * etap;
            }
            return Some(BsdfSample {
                f: ft * self.tint,
                wi,
                pdf: t,
                lobe: Lobe::Transmission,
                specular: true,
                eta: etap,
            });
        }
        let wm = self.distrib.sample_wm(wo, u);
        let r = fr_dielectric(wo.dot(wm), self.eta);
        let (wi, lobe, etap) = if uc < r {
            (reflect(wo, wm), Lobe::Reflection, 1.0)
        } else {
            let (wi, etap) = refract(wo, wm, self.eta)?;
            (wi, Lobe::Transmission, etap)
        };
        let same_side = (wi.z > 0.0) == (wo.z > 0.0);
        if wi.z == 0.0 || same_side != (lobe == Lobe::Reflection) {
            return None;
        }
        let (f, pdf) = self.eval_rough(wo, wi, mode);
        if !(pdf > 0.0 && f > 0.0) {
            return None;
        }
        Some(BsdfSample { f: self.spectrum(f, wo, wi), wi, pdf, lobe, specular: false, eta: etap })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::test_util::{SplitMix, random_dir};

    const MODES: [TransportMode; 2] = [TransportMode::Radiance, TransportMode::Importance];

    #[test]
    fn smooth_reflection_plus_transmission_is_one() {
        for eta in [1.0001f32, 1.33, 1.5, 4.0, 0.7] {
            let b = DielectricBsdf::new(eta, TrowbridgeReitz::new(0.0));
            for cz in [1.0f32, 0.8, 0.3, 0.05, 1e-3, -1e-3, -0.05, -0.3, -0.8, -1.0] {
                let wo = Vec3::new((1.0 - cz * cz).sqrt(), 0.0, cz);
                let mut total = [0.0f32; 2];
                for (k, mode) in MODES.into_iter().enumerate() {
                    let mut seen_reflection = false;
                    for uc in [0.0f32, 0.999_999_9] {
                        let Some(s) = b.sample_f(wo, uc, Vec2::splat(0.5), mode) else { continue };
                        assert!(s.specular && s.f.is_finite());
                        if s.lobe == Lobe::Reflection {
                            if seen_reflection {
                                continue; // total internal reflection: both uc chose it
                            }
                            seen_reflection = true;
                        }
                        let scale = if mode == TransportMode::Radiance { s.eta * s.eta } else { 1.0 };
                        let w = s.f[0] * s.wi.z.abs() * scale; // delta weight (R or T)
                        total[k] += w;
                        assert!((w / s.pdf - 1.0).abs() < 1e-4, "{w} {}", s.pdf);
                    }
                }
                for t in total {
                    assert!((t - 1.0).abs() < 1e-5, "eta {eta} cos {cz}: {t}");
                }
            }
        }
    }

    #[test]
    fn rough_reciprocity() {
        let mut rng = SplitMix(3);
        for eta in [1.5f32, 1.0001, 4.0] {
            for alpha in [0.05f32, 0.3, 1.0] {
                let b = DielectricBsdf::new(eta, TrowbridgeReitz::new(alpha));
                for _ in 0..3000 {
                    let (wo, wi) = (random_dir(&mut rng), random_dir(&mut rng));
                    let a = b.f(wo, wi, TransportMode::Radiance)[0];
                    let c = b.f(wi, wo, TransportMode::Radiance)[0];
                    // f(wo, wi) / n(wo)^2 = f(wi, wo) / n(wi)^2 (n = 1 outside, eta inside)
                    let n2 = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta * eta };
                    let (a, c) = (a / n2(wo), c / n2(wi));
                    assert!((a - c).abs() <= 2e-3 * a.max(c) + 1e-6, "eta {eta} alpha {alpha} {wo} {wi}: {a} {c}");
                    // The unscaled (Importance) BTDF divided by n(wi)^2 is symmetric too.
                    let ai = b.f(wo, wi, TransportMode::Importance)[0] / n2(wi);
                    let ci = b.f(wi, wo, TransportMode::Importance)[0] / n2(wo);
                    assert!((ai - ci).abs() <= 2e-3 * ai.max(ci) + 1e-6);
                }
            }
        }
    }

    #[test]
    fn sample_weights_agree_with_f_and_pdf() {
        let mut rng = SplitMix(5);
        for eta in [1.5f32, 1.0001, 4.0, 0.8] {
            for alpha in [0.002f32, 0.05, 0.3, 1.0] {
                let b = DielectricBsdf::new(eta, TrowbridgeReitz::new(alpha));
                for mode in MODES {
                    for _ in 0..2000 {
                        let wo = random_dir(&mut rng);
                        let (uc, u) = (rng.next(), Vec2::new(rng.next(), rng.next()));
                        let Some(s) = b.sample_f(wo, uc, u, mode) else { continue };
                        assert!(!s.specular);
                        assert_eq!(s.lobe == Lobe::Reflection, (s.wi.z > 0.0) == (wo.z > 0.0));
                        let (f, pdf) = (b.f(wo, s.wi, mode)[0], b.pdf(wo, s.wi, mode));
                        assert_eq!(b.f_pdf(wo, s.wi, mode), (SampledSpectrum::splat(f), pdf));
                        let wi = random_dir(&mut rng);
                        assert_eq!(b.f_pdf(wo, wi, mode), (b.f(wo, wi, mode), b.pdf(wo, wi, mode)));
                        assert!((pdf - s.pdf).abs() <= 1e-4 * pdf && (f - s.f[0]).abs() <= 1e-4 * f);
                        let w = s.f[0] * s.wi.z.abs() / s.pdf;
                        if mode == TransportMode::Importance {
                            // Each lobe's weight is G / G1(wo) <= 1.
                            assert!(w <= 1.0 + 1e-3, "eta {eta} alpha {alpha}: {w}");
                        }
                        if s.lobe == Lobe::Transmission {
                            let expect = if wo.z > 0.0 { eta } else { 1.0 / eta };
                            assert!((s.eta - expect).abs() < 1e-6);
                        }
                    }
                }
            }
        }
    }

    /// The tint multiplies transmitted light only, in `f`, `f_pdf` and `sample_f`, smooth and
    /// rough, and leaves the densities alone (sampling ignores it).
    #[test]
    fn the_tint_scales_transmission_only() {
        let tint = SampledSpectrum([0.2, 0.4, 0.6, 0.8]);
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        for alpha in [0.0, 0.3] {
            let clear = DielectricBsdf::new(1.5, TrowbridgeReitz::new(alpha));
            let tinted = clear.with_tint(tint);
            let mut rng = SplitMix(7);
            let (mut seen_t, mut seen_r) = (false, false);
            for _ in 0..64 {
                let (uc, u) = (rng.next(), Vec2::new(rng.next(), rng.next()));
                let (Some(a), Some(b)) = (
                    clear.sample_f(wo, uc, u, TransportMode::Radiance),
                    tinted.sample_f(wo, uc, u, TransportMode::Radiance),
                ) else {
                    continue;
                };
                assert_eq!((a.wi, a.pdf), (b.wi, b.pdf));
                let want = if a.lobe == Lobe::Transmission { a.f * tint } else { a.f };
                assert_eq!(b.f, want, "alpha {alpha}, {:?}", a.lobe);
                seen_t |= a.lobe == Lobe::Transmission;
                seen_r |= a.lobe == Lobe::Reflection;
                if alpha > 0.0 {
                    let (fa, pa) = clear.f_pdf(wo, a.wi, TransportMode::Radiance);
                    let (fb, pb) = tinted.f_pdf(wo, a.wi, TransportMode::Radiance);
                    assert_eq!(pa, pb);
                    assert_eq!(fb, if a.lobe == Lobe::Transmission { fa * tint } else { fa });
                    assert_eq!(tinted.f(wo, a.wi, TransportMode::Radiance), fb);
                }
            }
            assert!(seen_t && seen_r, "alpha {alpha}: both lobes sampled");
        }
    }
}
