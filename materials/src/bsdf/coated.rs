//! A dielectric coat over an opaque base: the position-free layered model of Weidlich & Wilkie
//! (2007, "Arbitrarily layered micro-facet surfaces") with the interreflection term of a
//! Lambertian base made exact, as in Mitsuba's `roughplastic` (docs/architecture.md §5).
//!
//! For wo, wi in the upper hemisphere, with wo', wi' their refractions into the coat (Snell,
//! smooth; cos' their cosines), E the coat reflection's directional albedo ([`CoatRow`]):
//!
//! f = f_coat(wo, wi) + (1 - E(cos o)) (1 - E(cos i)) / eta^2 * A * M * f_base(wo', wi'),
//!
//! - f_coat: the GGX reflection of the coat's top interface (dielectric Fresnel);
//! - 1 / eta^2: the radiance and solid-angle change of the two crossings (n^2 cos dw is invariant);
//! - A = exp(-tau (1 / cos o' + 1 / cos i')): the coat's absorption along the two paths in it;
//! - M: the light that the coat's underside reflects back onto the base. For a Lambertian base of
//!   albedo rho, M = 1 / (1 - rho K) sums the bounces exactly (the light under the coat is
//!   diffuse), with K = F_int (the coat's hemispherical internal reflectance) times the fraction
//!   of it that survives the absorption down and up (the coating's `CoatAbsorption`; exact for a
//!   smooth coat). For a conductor base of normal reflectance R, the light stays near the angle
//!   it came in at, and M = 1 / (1 - R e^(-2 tau) sqrt(E(cos o) E(cos i))) sums the bounces of a
//!   mirror base exactly (a smooth coat reflects from inside what it reflects from outside). For
//!   a tabulated base M = 1 (single scattering). The errors against a random walk between the
//!   layers are measured in materials/tests/coated.rs and docs/validation.md.
//!
//! The model is reciprocal (f is symmetric in wo, wi) and never gains energy: over a white
//! Lambertian base without absorption the albedo is exactly 1 - (the coat lobe's own loss).
//! Sampling picks the coat lobe with probability P(cos o) (its albedo against the base's, kept
//! in [0.1, 0.9]) or samples the base at wo' and refracts the result out; `pdf` is the mixture's
//! exact density (base directions beyond the critical angle fail and are missing mass).

use glam::{Vec2, Vec3};

use super::coat_albedo::{CoatRow, RoughnessPos};
use super::fresnel::fr_dielectric;
use super::microfacet::TrowbridgeReitz;
use super::{BsdfSample, CoatBase, Lobe, TransportMode, mirror_z as flip, reflect, reflecting_side};
use crate::spectrum::SampledSpectrum;
use std::f32::consts::PI;

/// A coated surface at one set of wavelengths (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatedBsdf<'a> {
    coat: TrowbridgeReitz,
    eta: f32,
    albedo: CoatRow,
    /// Optical depth of the coat at normal incidence per wavelength (0: clear).
    depth: SampledSpectrum,
    /// M / eta^2 per wavelength for a Lambertian base, 1 / eta^2 otherwise.
    scale: SampledSpectrum,
    /// A conductor base's normal-incidence reflectance (its bounces under the coat), else 0.
    specular_albedo: SampledSpectrum,
    /// The factor C of a conductor base's trapped light (see the module documentation), else 0.
    trapped_scale: SampledSpectrum,
    /// A conductor base's roughness in the albedo table's grid.
    base_pos: RoughnessPos,
    /// The base's mean albedo (for the lobe choice).
    base_weight: f32,
    two_sided: bool,
    base: CoatBase<'a>,
}

/// Direction in the coat of the outside direction `w` (upper hemisphere): tangential part / eta.
#[inline(always)]
fn inside(w: Vec3, eta: f32) -> Vec3 {
    let (x, y) = (w.x / eta, w.y / eta);
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

/// The outside direction of the direction `w` in the coat (None beyond the critical angle).
#[inline(always)]
fn outside(w: Vec3, eta: f32) -> Option<Vec3> {
    let (x, y) = (w.x * eta, w.y * eta);
    let z2 = 1.0 - x * x - y * y;
    (z2 > 0.0 && w.z > 0.0).then(|| Vec3::new(x, y, z2.sqrt()))
}

impl<'a> CoatedBsdf<'a> {
    /// A coat of GGX distribution `coat` (never effectively smooth: see
    /// [`crate::bsdf::coat_albedo::coat_alpha`]), relative IOR `eta` >= 1 with its albedo table row,
    /// optical depth `depth` and, for the Lambertian interreflection, the fraction
    /// `interreflection` of the internal reflectance that the absorption leaves
    /// (the coating's `CoatAbsorption::interreflection`), over `base`.
    pub fn new(
        coat: TrowbridgeReitz,
        eta: f32,
        albedo: CoatRow,
        depth: SampledSpectrum,
        interreflection: SampledSpectrum,
        base: CoatBase<'a>,
        two_sided: bool,
    ) -> Self {
        let eta = if eta.is_finite() && eta >= 1.0 { eta } else { 1.0 };
        let inv_eta2 = 1.0 / (eta * eta);
        let zero = SampledSpectrum::zero();
        let one = SampledSpectrum::one();
        let f_int = albedo.internal_reflectance();
        let mut base_pos = RoughnessPos::of(0.0);
        let mut trapped_scale = zero;
        let (scale, specular_albedo, base_weight) = match &base {
            CoatBase::Diffuse(d) => {
                let m = (one - d.r * interreflection * f_int).map(|x| 1.0 / x.max(1e-6));
                (m * inv_eta2, zero, base.mean_albedo())
            }
            CoatBase::Conductor(c) => {
                let r = c.fresnel.eval(1.0);
                base_pos = RoughnessPos::of(c.distrib.alpha());
                let norm = albedo.trapped_norm(base_pos);
                if norm > 1e-6 {
                    // trapped light on the base: reflected (albedo w_g), into the escape cone
                    // (w_g - t_g) where it leaves unless the coat reflects it (F_c)
                    let (w_g, t_g) = albedo.trapped_bounce(base_pos);
                    let f_c = albedo.cone_reflectance();
                    let leave = r * ((w_g - t_g).max(0.0) * (1.0 - f_c));
                    let stay = r * interreflection * (t_g + (w_g - t_g).max(0.0) * f_c);
                    let exits = leave * (one - stay).map(|x| 1.0 / x.max(1e-6));
                    trapped_scale = r * interreflection * exits * (1.0 / (PI * eta * eta * norm));
                }
                (SampledSpectrum::splat(inv_eta2), r * depth.map(|tau| (-2.0 * tau).exp()), base.mean_albedo())
            }
            CoatBase::Tabulated(_) => (SampledSpectrum::splat(inv_eta2), zero, base.mean_albedo()),
        };
        Self { coat, eta, albedo, depth, scale, specular_albedo, trapped_scale, base_pos, base_weight, two_sided, base }
    }

    /// Probability of sampling the coat lobe for an incidence of cosine `mu`.
    #[inline]
    fn coat_probability(&self, mu: f32) -> f32 {
        let e = self.albedo.albedo(mu);
        let d = e + (1.0 - e) * self.base_weight;
        (if d > 0.0 { e / d } else { 1.0 }).clamp(0.1, 0.9)
    }

    /// (f, pdf) for wo, wi both in the upper hemisphere.
    #[inline(always)]
    fn eval_upper(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, f32) {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (SampledSpectrum::zero(), 0.0);
        }
        let mut f = SampledSpectrum::zero();
        let mut pdf_coat = 0.0;
        let h = wo + wi;
        let len2 = h.length_squared();
        if len2 > 0.0 {
            let wm = h / len2.sqrt();
            let cos_om = wo.dot(wm);
            if cos_om > 0.0 {
                let v = fr_dielectric(cos_om, self.eta) * 0.25 * self.coat.d(wm) * self.coat.g_over_cos(wo, wi);
                f = SampledSpectrum::splat(v);
                pdf_coat = self.coat.pdf_wm(wo, wm) / (4.0 * cos_om);
            }
        }
        let (o, i) = (inside(wo, self.eta), inside(wi, self.eta));
        let (fb, pb) = self.base.f_pdf(o, i, mode);
        let (eo, ei) = (self.albedo.albedo(wo.z), self.albedo.albedo(wi.z));
        let mut layer = fb * self.scale * ((1.0 - eo) * (1.0 - ei));
        if !self.specular_albedo.is_black() {
            // a glossy base: the light that the coat's underside reflects back into the escape
            // cone bounces near the angle it came in at (a smooth coat reflects from inside what
            // it reflects from outside: F_int(mu') = F(mu)); the part the base sends beyond the
            // critical angle, t, is trapped light (below)
            let (to, ti) = (self.albedo.trapped(self.base_pos, o.z), self.albedo.trapped(self.base_pos, i.z));
            let (wo_, wi_) = (self.albedo.white(self.base_pos, o.z), self.albedo.white(self.base_pos, i.z));
            let k = (eo * ei * (wo_ - to).max(0.0) * (wi_ - ti).max(0.0)).sqrt();
            layer *= (SampledSpectrum::one() - self.specular_albedo * k).map(|x| 1.0 / x.max(1e-6));
            layer += self.trapped_scale * ((1.0 - eo) * (1.0 - ei) * to * ti);
        }
        if !self.depth.is_black() {
            let path = 1.0 / o.z + 1.0 / i.z;
            layer *= self.depth.map(|tau| (-tau * path).exp());
        }
        f += layer;
        let p = self.coat_probability(wo.z);
        let pdf = p * pdf_coat + (1.0 - p) * pb * wi.z / (self.eta * self.eta * i.z);
        if !(f.is_finite() && pdf.is_finite()) {
            return (SampledSpectrum::zero(), 0.0);
        }
        (f, pdf)
    }

    /// Whether to mirror the configuration (Some(true)), use it (Some(false)) or return black.
    #[inline]
    fn orientation(&self, wo: Vec3) -> Option<bool> {
        reflecting_side(wo, self.two_sided)
    }

    /// f(wo, wi) and its sampling density together.
    #[inline]
    pub fn f_pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, f32) {
        match self.orientation(wo) {
            Some(fl) => self.eval_upper(flip(wo, fl), flip(wi, fl), mode),
            None => (SampledSpectrum::zero(), 0.0),
        }
    }

    /// BSDF value.
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        self.f_pdf(wo, wi, mode).0
    }

    /// Solid-angle density of [`sample_f`](Self::sample_f).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        self.f_pdf(wo, wi, mode).1
    }

    /// The coat lobe with probability P(cos o) (a visible normal, mirror reflection), else the
    /// base sampled at wo' (with `uc` rescaled) and refracted out.
    #[inline]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let fl = self.orientation(wo)?;
        let wo_u = flip(wo, fl);
        let p = self.coat_probability(wo_u.z);
        let wi = if uc < p {
            reflect(wo_u, self.coat.sample_wm(wo_u, u))
        } else {
            let uc = ((uc - p) / (1.0 - p)).min(1.0 - f32::EPSILON);
            let s = self.base.sample_f(inside(wo_u, self.eta), uc, u, mode)?;
            outside(s.wi, self.eta)?
        };
        if wi.z <= 0.0 {
            return None;
        }
        let (f, pdf) = self.eval_upper(wo_u, wi, mode);
        if pdf.is_nan() || pdf <= 0.0 || f.is_black() {
            return None;
        }
        Some(BsdfSample { f, wi: flip(wi, fl), pdf, lobe: Lobe::Reflection, specular: false, eta: 1.0 })
    }

    /// The same BSDF over a base that borrows nothing (None for a tabulated base).
    pub(crate) fn detached(self) -> Option<CoatedBsdf<'static>> {
        let base = self.base.detached()?;
        Some(CoatedBsdf {
            coat: self.coat,
            eta: self.eta,
            albedo: self.albedo,
            depth: self.depth,
            scale: self.scale,
            specular_albedo: self.specular_albedo,
            trapped_scale: self.trapped_scale,
            base_pos: self.base_pos,
            base_weight: self.base_weight,
            two_sided: self.two_sided,
            base,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::coat_albedo::{CoatAlbedo, coat_alpha};
    use crate::bsdf::test_util::{SplitMix, random_dir};
    use crate::bsdf::{ConductorBsdf, DiffuseBsdf, SampledFresnel};

    fn coated(alpha: f32, base: CoatBase<'static>, depth: f32) -> CoatedBsdf<'static> {
        let row = CoatAlbedo::for_eta(1.5).row(alpha);
        // the interreflection factor only scales M over a Lambertian base: any value in (0, 1]
        let tr = (-depth).exp();
        CoatedBsdf::new(
            TrowbridgeReitz::new(coat_alpha(alpha)),
            1.5,
            row,
            SampledSpectrum::splat(depth),
            SampledSpectrum::splat(tr),
            base,
            true,
        )
    }

    fn bases() -> Vec<CoatBase<'static>> {
        vec![
            CoatBase::Diffuse(DiffuseBsdf::new(SampledSpectrum([0.9, 0.5, 0.2, 1.0]), true)),
            CoatBase::Conductor(ConductorBsdf::new(
                TrowbridgeReitz::new(0.2),
                SampledFresnel::Constant(SampledSpectrum::splat(0.9)),
                true,
            )),
        ]
    }

    #[test]
    fn reciprocal_and_consistent_with_its_samples() {
        let mut rng = SplitMix(5);
        for alpha in [0.0f32, 0.05, 0.4] {
            for base in bases() {
                for depth in [0.0f32, 0.3] {
                    let b = coated(alpha, base, depth);
                    for _ in 0..3000 {
                        let (wo, wi) = (random_dir(&mut rng), random_dir(&mut rng));
                        let (wo, wi) = (Vec3::new(wo.x, wo.y, wo.z.abs()), Vec3::new(wi.x, wi.y, wi.z.abs()));
                        let (a, c) = (b.f(wo, wi, TransportMode::Radiance), b.f(wi, wo, TransportMode::Importance));
                        for k in 0..4 {
                            assert!((a[k] - c[k]).abs() <= 1e-3 * a[k].max(c[k]) + 1e-6, "{wo} {wi}: {a:?} {c:?}");
                        }
                        let u = Vec2::new(rng.next(), rng.next());
                        if let Some(s) = b.sample_f(wo, rng.next(), u, TransportMode::Radiance) {
                            let (f, pdf) = b.f_pdf(wo, s.wi, TransportMode::Radiance);
                            assert!((pdf - s.pdf).abs() <= 1e-5 * pdf && f == s.f);
                            assert!(s.wi.z > 0.0 && !s.specular && s.lobe == Lobe::Reflection);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn back_side_is_mirrored_or_black() {
        let b = coated(0.1, bases()[0], 0.0);
        let (wo, wi) = (Vec3::new(0.3, 0.1, 0.9).normalize(), Vec3::new(-0.2, 0.4, 0.8).normalize());
        let back = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
        assert_eq!(b.f_pdf(wo, wi, TransportMode::Radiance), b.f_pdf(back(wo), back(wi), TransportMode::Radiance));
        let one = CoatedBsdf { two_sided: false, ..b };
        assert!(one.f(back(wo), back(wi), TransportMode::Radiance).is_black());
        assert!(one.sample_f(back(wo), 0.5, Vec2::splat(0.5), TransportMode::Radiance).is_none());
    }
}
