//! One scattering step of a path: a BSDF sample turned into the world-space continuation.

use glam::Vec3;
use quasar_materials::{Bsdf, BsdfSample, Frame, TransportMode};

use crate::core::sampling::Sampler;
use crate::core::scene::SurfaceInteraction;

/// A sampled continuation of a path.
#[derive(Clone, Copy, Debug)]
pub struct Scattered {
    /// The BSDF sample (local frame).
    pub bs: BsdfSample,
    /// The sampled direction in world space.
    pub wi: Vec3,
}

impl Scattered {
    /// The throughput factor f |cos wi| / pdf of this step.
    #[inline]
    pub fn weight(&self) -> quasar_materials::spectrum::SampledSpectrum {
        self.bs.f * (self.bs.wi.z.abs() / self.bs.pdf)
    }
}

/// Samples the BSDF at `si` (shading `frame`) for the outgoing direction `wo` (world; `wo_local`
/// in the frame), consuming three numbers of `sampler`. None when the path ends there: nothing
/// scattered, a zero pdf or value, or a direction whose side of the shading frame disagrees with
/// its side of the geometric surface (a shading-normal leak, which would cross the surface
/// without refraction).
#[inline(always)]
pub fn scatter(
    bsdf: &Bsdf,
    si: &SurfaceInteraction,
    frame: &Frame,
    wo: Vec3,
    wo_local: Vec3,
    mode: TransportMode,
    sampler: &mut Sampler,
) -> Option<Scattered> {
    let uc = sampler.get_1d();
    let u = sampler.get_2d();
    let bs = bsdf.sample_f(wo_local, uc, u, mode)?;
    if bs.pdf <= 0.0 || bs.f.is_black() {
        return None;
    }
    let wi = frame.from_local(bs.wi);
    if (bs.wi.z * wo_local.z > 0.0) != (wi.dot(si.ng) * wo.dot(si.ng) > 0.0) {
        return None;
    }
    Some(Scattered { bs, wi })
}
