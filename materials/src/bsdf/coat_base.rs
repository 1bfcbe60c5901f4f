//! The opaque base under a layer (a coat, [`super::CoatedBsdf`], or a sheen, [`super::SheenBsdf`]):
//! a closed set with enum dispatch, evaluated and sampled in the upper hemisphere.

use glam::{Vec2, Vec3};

use super::{BsdfSample, ConductorBsdf, DiffuseBsdf, TabulatedBsdf, TransportMode};
use crate::spectrum::SampledSpectrum;

/// The opaque base under a layer (a closed set, enum dispatch).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CoatBase<'a> {
    /// Lambertian.
    Diffuse(DiffuseBsdf),
    /// GGX-rough conductor (alpha >= the smooth threshold).
    Conductor(ConductorBsdf),
    /// Tabulated reflector.
    Tabulated(TabulatedBsdf<'a>),
}

impl CoatBase<'_> {
    /// f and pdf of the base.
    #[inline(always)]
    pub(crate) fn f_pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, f32) {
        match self {
            CoatBase::Diffuse(b) => b.f_pdf(wo, wi),
            CoatBase::Conductor(b) => b.f_pdf(wo, wi),
            CoatBase::Tabulated(b) => (b.f(wo, wi, mode), b.pdf(wo, wi, mode)),
        }
    }

    /// The base's own sample.
    #[inline(always)]
    pub(crate) fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        match self {
            CoatBase::Diffuse(b) => b.sample_f(wo, u, mode),
            CoatBase::Conductor(b) => b.sample_f(wo, u, mode),
            CoatBase::Tabulated(b) => b.sample_f(wo, uc, u, mode),
        }
    }

    /// A rough mean albedo for choosing between the layer's lobe and the base: a diffuse base's
    /// mean reflectance, a conductor's mean normal-incidence Fresnel reflectance, 0.5 for a table.
    pub(crate) fn mean_albedo(&self) -> f32 {
        match self {
            CoatBase::Diffuse(d) => d.r.average(),
            CoatBase::Conductor(c) => c.fresnel.eval(1.0).average(),
            CoatBase::Tabulated(_) => 0.5,
        }
    }

    /// The same base without a borrow (None for a tabulated one, which borrows its table).
    pub(crate) fn detached(self) -> Option<CoatBase<'static>> {
        match self {
            CoatBase::Diffuse(b) => Some(CoatBase::Diffuse(b)),
            CoatBase::Conductor(b) => Some(CoatBase::Conductor(b)),
            CoatBase::Tabulated(_) => None,
        }
    }
}
