//! BSDF models (DESIGN.md section 4). All directions are in the local shading frame (z = normal),
//! both `wo` and `wi` point away from the surface, and values are in 1/sr (pbrt-v4 conventions).
//! The integrator only calls [`Bsdf::f`], [`Bsdf::sample_f`] and [`Bsdf::pdf`].

use glam::Vec3;

use crate::spectrum::SampledSpectrum;

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

/// A BSDF at one surface point and one set of wavelengths (closed set, enum dispatch).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    /// Placeholder until the models land.
    Black,
}

impl Bsdf {
    /// f(wo, wi) in 1/sr (0 for specular lobes).
    pub fn f(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        SampledSpectrum::zero()
    }
    /// Samples wi given wo and three uniform numbers.
    pub fn sample_f(&self, _wo: Vec3, _uc: f32, _u: glam::Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        None
    }
    /// Solid-angle density with which `sample_f` returns wi (0 for specular lobes).
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> f32 {
        0.0
    }
    /// True when every lobe is a Dirac delta (no light sampling, a specular path vertex).
    pub fn is_specular(&self) -> bool {
        false
    }
}
