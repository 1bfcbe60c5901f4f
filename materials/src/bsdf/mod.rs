//! BSDF models (docs/architecture.md §5). All directions are in the local shading frame (z = normal),
//! both `wo` and `wi` point away from the surface, and values are in 1/sr (pbrt-v4 conventions).
//! The integrator only calls [`Bsdf::f`], [`Bsdf::sample_f`] and [`Bsdf::pdf`].

use glam::Vec3;

use crate::spectrum::SampledSpectrum;

pub mod coat_albedo;
pub mod coat_base;
pub mod coated;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod fresnel;
pub mod microfacet;
pub mod sheen;
pub mod tabulated;

pub use coat_base::CoatBase;
pub use coated::CoatedBsdf;
pub use conductor::ConductorBsdf;
pub use dielectric::DielectricBsdf;
pub use diffuse::DiffuseBsdf;
pub use fresnel::SampledFresnel;
pub use microfacet::TrowbridgeReitz;
pub use sheen::SheenBsdf;
pub use tabulated::TabulatedBsdf;

/// Which quantity a path carries: radiance (camera paths) or importance (light paths / photons).
/// Non-symmetric scattering (refraction's 1/eta^2 radiance scaling) depends on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Camera -> light paths.
    Radiance,
    /// Light -> camera paths (photons).
    Importance,
}

/// Whether a sampled direction is reflected or transmitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    /// wi on the same side as wo.
    Reflection,
    /// wi on the other side.
    Transmission,
}

/// A direction sampled from a BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// BSDF value f(wo, wi) (for specular samples: the delta's weight divided by |cos wi|,
    /// so that `f * |cos| / pdf` is the path throughput factor in every case).
    pub f: SampledSpectrum,
    /// Sampled incident direction (local frame).
    pub wi: Vec3,
    /// Solid-angle density of `wi` (for specular samples: the discrete probability of the lobe).
    pub pdf: f32,
    /// Reflection or transmission.
    pub lobe: Lobe,
    /// True for a Dirac-delta lobe (pdf is a discrete probability, not a density).
    pub specular: bool,
    /// Relative IOR crossed by a transmission (eta_t / eta_i), 1 for reflection.
    pub eta: f32,
}

/// Specular samples whose |cos wi| is below this are dropped: f = weight / |cos| would overflow.
pub(crate) const MIN_SPECULAR_COS: f32 = 1e-30;

/// The side a reflector that reflects on one face (or both, `two_sided`) sees `wo` from:
/// Some(false) above, Some(true) below (the configuration is mirrored into the upper hemisphere
/// with [`mirror_z`]), None where it is black (behind a one-sided surface, in the tangent plane).
#[inline]
pub(crate) fn reflecting_side(wo: Vec3, two_sided: bool) -> Option<bool> {
    if wo.z > 0.0 {
        Some(false)
    } else if wo.z < 0.0 && two_sided {
        Some(true)
    } else {
        None
    }
}

/// `v` with its z negated when `flipped` (see [`reflecting_side`]).
#[inline]
pub(crate) fn mirror_z(v: Vec3, flipped: bool) -> Vec3 {
    if flipped { Vec3::new(v.x, v.y, -v.z) } else { v }
}

/// Mirror reflection of `wo` about the unit normal `n`: 2 (wo . n) n - wo.
#[inline]
pub(crate) fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// Refraction of `wi` (pointing away from the surface) through the interface with unit normal `n`
/// and relative IOR `eta` (the side `n` points away from over the side it points to), by Snell's
/// law: wt = -wi / eta' + (cos i / eta' - cos t) n', where a `wi` below the interface flips n and
/// uses eta' = 1/eta. Returns (wt, eta') or None under total internal reflection.
#[inline]
pub(crate) fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    let (mut eta, mut n) = (eta, n);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t.is_nan() || sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let wt = -wi / eta + (cos_i / eta - cos_t) * n;
    wt.is_finite().then_some((wt, eta))
}

/// A BSDF at one surface point and one set of wavelengths (closed set, enum dispatch). It may
/// borrow a material's table (`'a`), so it lives no longer than the scene's materials.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf<'a> {
    /// Scatters nothing (f = 0, no samples): the back of one-sided surfaces, absorbers.
    Black,
    /// Lambertian reflection.
    Diffuse(DiffuseBsdf),
    /// Smooth or GGX-rough conductor.
    Conductor(ConductorBsdf),
    /// Smooth or GGX-rough dielectric interface.
    Dielectric(DielectricBsdf),
    /// Tabulated spectral BRDF/BTDF (measured or generated data).
    Tabulated(TabulatedBsdf<'a>),
    /// A dielectric coat over an opaque base (layered, position-free).
    Coated(CoatedBsdf<'a>),
    /// A sheen (fibre) layer over an opaque base.
    Sheen(SheenBsdf<'a>),
}

impl Bsdf<'_> {
    /// A BSDF that scatters nothing.
    #[inline]
    pub fn black() -> Bsdf<'static> {
        Bsdf::Black
    }

    /// The same BSDF without a borrow, for every model that holds its parameters by value;
    /// None for a tabulated BSDF (it borrows its table).
    pub fn detached(self) -> Option<Bsdf<'static>> {
        match self {
            Bsdf::Black => Some(Bsdf::Black),
            Bsdf::Diffuse(b) => Some(Bsdf::Diffuse(b)),
            Bsdf::Conductor(b) => Some(Bsdf::Conductor(b)),
            Bsdf::Dielectric(b) => Some(Bsdf::Dielectric(b)),
            Bsdf::Tabulated(_) => None,
            Bsdf::Coated(b) => b.detached().map(Bsdf::Coated),
            Bsdf::Sheen(b) => b.detached().map(Bsdf::Sheen),
        }
    }

    /// f(wo, wi) in 1/sr (0 for specular lobes).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        match self {
            Bsdf::Black => SampledSpectrum::zero(),
            Bsdf::Diffuse(b) => b.f(wo, wi),
            Bsdf::Conductor(b) => b.f(wo, wi),
            Bsdf::Dielectric(b) => b.f(wo, wi, mode),
            Bsdf::Tabulated(b) => b.f(wo, wi, mode),
            Bsdf::Coated(b) => b.f(wo, wi, mode),
            Bsdf::Sheen(b) => b.f_pdf(wo, wi, mode).0,
        }
    }

    /// (f(wo, wi), pdf(wo, wi)) together, for next-event estimation with MIS: the analytic
    /// models share their half vector, Fresnel and microfacet terms between the two.
    #[inline(always)]
    pub fn f_pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, f32) {
        match self {
            Bsdf::Black => (SampledSpectrum::zero(), 0.0),
            Bsdf::Diffuse(b) => b.f_pdf(wo, wi),
            Bsdf::Conductor(b) => b.f_pdf(wo, wi),
            Bsdf::Dielectric(b) => b.f_pdf(wo, wi, mode),
            Bsdf::Tabulated(b) => (b.f(wo, wi, mode), b.pdf(wo, wi, mode)),
            Bsdf::Coated(b) => b.f_pdf(wo, wi, mode),
            Bsdf::Sheen(b) => b.f_pdf(wo, wi, mode),
        }
    }

    /// Samples wi given wo and three uniform numbers in [0, 1): `uc` picks the lobe, `u` the
    /// direction. None when nothing is scattered (black side, absorbed, below the horizon).
    #[inline(always)]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: glam::Vec2, mode: TransportMode) -> Option<BsdfSample> {
        match self {
            Bsdf::Black => None,
            Bsdf::Diffuse(b) => b.sample_f(wo, u, mode),
            Bsdf::Conductor(b) => b.sample_f(wo, u, mode),
            Bsdf::Dielectric(b) => b.sample_f(wo, uc, u, mode),
            Bsdf::Tabulated(b) => b.sample_f(wo, uc, u, mode),
            Bsdf::Coated(b) => b.sample_f(wo, uc, u, mode),
            Bsdf::Sheen(b) => b.sample_f(wo, uc, u, mode),
        }
    }

    /// Solid-angle density with which `sample_f` returns wi (0 for specular lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        match self {
            Bsdf::Black => 0.0,
            Bsdf::Diffuse(b) => b.pdf(wo, wi),
            Bsdf::Conductor(b) => b.pdf(wo, wi),
            Bsdf::Dielectric(b) => b.pdf(wo, wi, mode),
            Bsdf::Tabulated(b) => b.pdf(wo, wi, mode),
            Bsdf::Coated(b) => b.pdf(wo, wi, mode),
            Bsdf::Sheen(b) => b.f_pdf(wo, wi, mode).1,
        }
    }

    /// True when every lobe is a Dirac delta (no light sampling, a specular path vertex).
    /// [`Bsdf::Black`] has no lobes and reports false (like pbrt-v4's empty flags).
    pub fn is_specular(&self) -> bool {
        match self {
            Bsdf::Black | Bsdf::Diffuse(_) | Bsdf::Tabulated(_) | Bsdf::Coated(_) | Bsdf::Sheen(_) => false,
            Bsdf::Conductor(b) => b.is_specular(),
            Bsdf::Dielectric(b) => b.is_specular(),
        }
    }

    /// True when the BSDF can transmit light to the other side of the surface.
    pub fn has_transmission(&self) -> bool {
        match self {
            Bsdf::Dielectric(_) => true,
            Bsdf::Tabulated(b) => b.has_transmission(),
            _ => false,
        }
    }

    /// The ideal (specular) scattering directions of `wo` in the local frame: the mirror
    /// direction and, for dielectrics, the Snell refraction direction (None under total internal
    /// reflection). These are the axes of the quasi-specular cones (docs/architecture.md §7.5).
    /// Lambertian and black surfaces have no lobe around them and return (None, None).
    pub fn ideal_directions(&self, wo: Vec3) -> (Option<Vec3>, Option<Vec3>) {
        let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
        match self {
            Bsdf::Black | Bsdf::Diffuse(_) | Bsdf::Sheen(_) => (None, None),
            Bsdf::Conductor(_) | Bsdf::Coated(_) => (Some(mirror), None),
            Bsdf::Dielectric(b) => (Some(mirror), refract(wo, Vec3::Z, b.eta).map(|(wt, _)| wt.normalize())),
            Bsdf::Tabulated(b) => {
                let t = b.has_transmission().then(|| refract(wo, Vec3::Z, b.eta()).map(|(wt, _)| wt.normalize()));
                (Some(mirror), t.flatten())
            }
        }
    }
}

/// Deterministic helpers for the unit tests of this module tree.
#[cfg(test)]
pub(crate) mod test_util {
    use glam::Vec3;

    /// SplitMix64 (Steele, Lea & Flood 2014) as a tiny seeded generator.
    pub struct SplitMix(pub u64);

    impl SplitMix {
        /// Next uniform f32 in [0, 1) (24 random bits).
        pub fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
        }
    }

    /// Uniform direction on the sphere.
    pub fn random_dir(rng: &mut SplitMix) -> Vec3 {
        let z = 1.0 - 2.0 * rng.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * rng.next();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;
    use test_util::{SplitMix, random_dir};

    fn all_models() -> Vec<Bsdf<'static>> {
        let gold = SampledFresnel::Complex {
            eta: SampledSpectrum([1.4, 0.4, 0.2, 0.15]),
            k: SampledSpectrum([1.9, 2.5, 3.3, 4.5]),
        };
        let mut v = vec![Bsdf::black()];
        for two_sided in [false, true] {
            v.push(Bsdf::Diffuse(DiffuseBsdf::new(SampledSpectrum::splat(0.7), two_sided)));
            for alpha in [0.0f32, 1e-4, 1e-3, 0.01, 0.3, 1.0] {
                for fresnel in [SampledFresnel::Constant(SampledSpectrum::one()), gold] {
                    v.push(Bsdf::Conductor(ConductorBsdf::new(TrowbridgeReitz::new(alpha), fresnel, two_sided)));
                }
            }
        }
        for eta in [1.0f32, 1.0001, 1.5, 4.0, 0.25] {
            for alpha in [0.0f32, 1e-4, 1e-3, 0.01, 0.3, 1.0] {
                v.push(Bsdf::Dielectric(DielectricBsdf::new(eta, TrowbridgeReitz::new(alpha))));
            }
        }
        for eta in [1.0f32, 1.5, 4.0] {
            for alpha in [0.0f32, 0.01, 1.0] {
                let row = crate::bsdf::coat_albedo::CoatAlbedo::for_eta(eta).row(alpha);
                let coat = TrowbridgeReitz::new(crate::bsdf::coat_albedo::coat_alpha(alpha));
                for (base, depth) in [
                    (CoatBase::Diffuse(DiffuseBsdf::new(SampledSpectrum::one(), true)), 0.0f32),
                    (CoatBase::Conductor(ConductorBsdf::new(TrowbridgeReitz::new(1e-3), gold, true)), 50.0),
                ] {
                    let d = SampledSpectrum::splat(depth);
                    v.push(Bsdf::Coated(CoatedBsdf::new(coat, eta, row, d, SampledSpectrum::one(), base, false)));
                }
            }
        }
        for alpha in [0.0f32, 0.01, 0.3, 1.0, f32::NAN] {
            let base = CoatBase::Diffuse(DiffuseBsdf::new(SampledSpectrum::one(), true));
            v.push(Bsdf::Sheen(SheenBsdf::new(SampledSpectrum([1.0, 0.5, 0.0, 1.0]), 1.0, alpha, base, alpha > 0.1)));
        }
        v
    }

    fn extreme_dirs() -> Vec<Vec3> {
        let mut v = vec![Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::Y];
        for z in [0.0f32, 1e-30, 1e-12, 1e-7, 1e-6, 1e-3, 0.05, 0.5] {
            for s in [1.0f32, -1.0] {
                let zz = s * z;
                v.push(Vec3::new((1.0 - zz * zz).sqrt(), 0.0, zz));
                v.push(Vec3::new(0.0, -(1.0 - zz * zz).sqrt(), zz));
            }
        }
        let mut rng = SplitMix(99);
        v.extend((0..24).map(|_| random_dir(&mut rng)));
        v
    }

    #[test]
    fn extremes_never_produce_nan_inf_or_negative_values() {
        let dirs = extreme_dirs();
        let us = [0.0f32, 1e-7, 0.25, 0.5, 0.999_999_9];
        for b in all_models() {
            for mode in [TransportMode::Radiance, TransportMode::Importance] {
                for &wo in &dirs {
                    for &wi in &dirs {
                        let f = b.f(wo, wi, mode);
                        let p = b.pdf(wo, wi, mode);
                        assert!(f.is_finite() && f.min_component() >= 0.0, "{b:?} {wo} {wi}: {f:?}");
                        assert!(p.is_finite() && p >= 0.0, "{b:?} {wo} {wi}: {p}");
                        if b.is_specular() {
                            assert!(f.is_black() && p == 0.0);
                        }
                    }
                    for &uc in &us {
                        for &u0 in &us {
                            for &u1 in &us {
                                let Some(s) = b.sample_f(wo, uc, Vec2::new(u0, u1), mode) else { continue };
                                assert!(s.f.is_finite() && s.f.min_component() >= 0.0, "{b:?} {wo}: {s:?}");
                                assert!(s.pdf.is_finite() && s.pdf > 0.0, "{b:?} {wo}: {s:?}");
                                assert!(s.wi.is_finite() && (s.wi.length() - 1.0).abs() < 1e-3, "{b:?} {wo}: {s:?}");
                                assert!(s.eta.is_finite() && s.eta > 0.0);
                                let w = s.f * (s.wi.z.abs() / s.pdf);
                                assert!(w.is_finite(), "{b:?} {wo}: {s:?}");
                                assert_eq!(s.specular, b.is_specular());
                                assert_eq!(
                                    s.lobe == Lobe::Reflection,
                                    (s.wi.z > 0.0) == (wo.z > 0.0),
                                    "{b:?} {wo}: {s:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn black_scatters_nothing() {
        let b = Bsdf::black();
        assert!(b.f(Vec3::Z, Vec3::Z, TransportMode::Radiance).is_black());
        assert!(b.sample_f(Vec3::Z, 0.5, Vec2::splat(0.5), TransportMode::Radiance).is_none());
        assert_eq!(b.pdf(Vec3::Z, Vec3::Z, TransportMode::Radiance), 0.0);
        assert!(!b.is_specular() && !b.has_transmission());
    }

    #[test]
    fn refract_obeys_snell_and_reflect_is_an_involution() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let (wt, etap) = refract(wo, Vec3::Z, 1.5).unwrap();
        assert_eq!(etap, 1.5);
        assert!((wt.length() - 1.0).abs() < 1e-6 && wt.z < 0.0);
        assert!((0.6f32 - 1.5 * (1.0 - wt.z * wt.z).sqrt()).abs() < 1e-6);
        let (back, etap2) = refract(wt, Vec3::Z, 1.5).unwrap();
        assert!((back - wo).length() < 1e-6 && (etap2 - 1.0 / 1.5).abs() < 1e-7);
        assert!(refract(Vec3::new(0.9, 0.0, -0.436).normalize(), Vec3::Z, 1.5).is_none());
        let n = Vec3::new(0.1, 0.2, 0.97).normalize();
        assert!((reflect(reflect(wo, n), n) - wo).length() < 1e-6);
    }
}
