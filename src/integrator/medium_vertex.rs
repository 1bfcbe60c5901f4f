//! A path's scattering event inside a homogeneous medium (docs/architecture.md §5): the vertex
//! [`crate::core::medium::MediumStack::sample_segment`] placed on a ray's segment, with its
//! next-event estimate (the phase function in place of a BSDF, MIS against phase sampling) and
//! the phase-sampled direction the path continues in. Every method's camera paths and `direct`
//! make their medium vertices here; the photons sample the same phase function.

use quasar_materials::HenyeyGreenstein;
use quasar_materials::spectrum::SampledWavelengths;

use super::direct::{PrevVertex, UnshadowedLight, sample_light_in_medium};
use crate::core::geometry::Ray;
use crate::core::medium::MediumStack;
use crate::core::sampling::Sampler;
use crate::core::scene::Scene;

/// A scattering vertex inside a medium and the path's continuation from it.
#[derive(Clone, Copy, Debug)]
pub struct MediumVertex {
    /// The light sample of the vertex (its shadow segment's transmittance applied), to be
    /// multiplied by the path's throughput; None where it carries nothing.
    pub light: Option<UnshadowedLight>,
    /// The phase-sampled ray the path continues along (weight p / pdf = 1).
    pub next: Ray,
    /// The vertex as the previous one of emission found along `next` (MIS against the light
    /// sample).
    pub prev: PrevVertex,
}

/// The vertex at distance `t` along `ray` inside the innermost medium of `media`, which
/// scatters by `phase`: light sampling first, then the phase sample (this order of random
/// numbers is every caller's).
#[inline(always)]
pub fn scatter_in_medium(
    scene: &Scene,
    ray: &Ray,
    t: f32,
    phase: &HenyeyGreenstein,
    media: &MediumStack,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
) -> MediumVertex {
    let p = ray.origin + ray.dir * t;
    let wo = -ray.dir;
    let light = sample_light_in_medium(scene, p, wo, phase, wl, sampler).map(|l| l.through(media, scene, wl));
    let (wi, pdf) = phase.sample(wo, sampler.get_2d());
    MediumVertex { light, next: Ray::new(p, wi), prev: PrevVertex { p, pdf } }
}
