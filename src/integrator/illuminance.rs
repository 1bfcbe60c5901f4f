//! Illuminance at a point of free space: E(p, n) = integral of L(p, w) max(0, n . w) dw over the
//! sphere, estimated as pi times the radiance that a white Lambertian at p facing n would
//! reflect: next-event estimation with MIS against a cosine-sampled direction at p, and the
//! path tracer ([`super::pt::trace`]) for the light arriving along that direction. Unbiased for
//! every light (delta lights through next-event estimation); the point itself neither blocks
//! nor reflects light (a virtual meter, docs/photometry.md).

use glam::{Vec2, Vec3};
use quasar_materials::TransportMode;
use quasar_materials::bsdf::{Bsdf, DiffuseBsdf};
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

use super::direct::{PrevVertex, sample_direct};
use super::pt::{PathState, PtSettings, trace};
use super::scatter::scatter;
use crate::core::sampling::Sampler;
use crate::core::scene::{Scene, SurfaceInteraction};
use crate::film::{LayeredRadiance, PathClass};

/// One sample of the spectral illuminance at `p` on a plane of unit normal `n` (W/(m^2 nm) per
/// unit of the scene's radiance scale) at the wavelengths `wl`; `p_err` bounds the rounding error
/// of `p` (None: a point in free space), so that rays leave a surface point cleanly.
pub fn illuminance_sample(
    scene: &Scene,
    p: Vec3,
    p_err: Option<Vec3>,
    n: Vec3,
    wl: &mut SampledWavelengths,
    sampler: &mut Sampler,
) -> SampledSpectrum {
    let si = SurfaceInteraction {
        p,
        p_err: p_err.unwrap_or(Vec3::splat(1e-6 * (1.0 + p.abs().max_element()))),
        ng: n,
        ns: n,
        t: 0.0,
        prim: 0,
        material: 0,
        light: crate::core::geometry::NONE,
        uv: Vec2::ZERO,
        bary: Vec2::ZERO,
    };
    let white = Bsdf::Diffuse(DiffuseBsdf { r: SampledSpectrum::one(), two_sided: false });
    let frame = si.frame();
    let wo_local = Vec3::Z;
    let mut l = sample_direct(scene, &si, &white, wo_local, wl, sampler);
    if let Some(sc) = scatter(&white, &si, &frame, n, wo_local, TransportMode::Radiance, sampler) {
        let state = PathState {
            beta: sc.weight(),
            class: PathClass::default().scattered(false),
            prev: PrevVertex { p, pdf: sc.bs.pdf },
            eta_scale: 1.0,
            depth: 1,
            // a meter stands outside every medium
            media: Default::default(),
        };
        let mut out = LayeredRadiance::default();
        trace(scene, si.spawn_ray(sc.wi), state, wl, sampler, &PtSettings::default(), &mut out);
        l += out.emission + out.direct + out.indirect;
    }
    l * std::f32::consts::PI
}
