//! Direct lighting shared by every integrator: next-event estimation with MIS (power heuristic,
//! Veach 1997 ch. 9) and the matching MIS weights of emitters reached by BSDF sampling.

use glam::Vec3;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use quasar_materials::{Bsdf, HenyeyGreenstein, TransportMode};

use crate::core::light::Light;
use crate::core::medium::MediumStack;
use crate::core::sampling::{Sampler, power_heuristic};
use crate::core::scene::{Scene, SurfaceInteraction};
use crate::film::{LayeredRadiance, PathClass};

/// How the current path vertex was reached, for the MIS weight of emission found there.
#[derive(Clone, Copy, Debug)]
pub struct PrevVertex {
    /// Position of the previous scattering vertex (or the eye).
    pub p: Vec3,
    /// Solid-angle pdf of the BSDF sample that left it; infinity for specular samples and
    /// camera rays (no light sampling was possible there, so emission gets the full weight).
    pub pdf: f32,
}

impl PrevVertex {
    /// The eye: emission seen directly is never light-sampled.
    pub fn eye(p: Vec3) -> Self {
        Self { p, pdf: f32::INFINITY }
    }
}

/// Next-event estimation at `si`: one power-proportional light choice and one point on it;
/// returns f |cos| Li w_light / (p_select pdf_light) (path throughput not included), 0 when the
/// shadow ray is blocked.
#[inline]
pub fn sample_direct(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    wo_local: Vec3,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
) -> SampledSpectrum {
    match sample_light(scene, si, bsdf, wo_local, wl, sampler, |_| false) {
        Some(ls) if !scene.occluded(&ls.shadow) => ls.contribution,
        _ => SampledSpectrum::zero(),
    }
}

/// A light sample of next-event estimation before its visibility is known: what it adds when
/// nothing blocks `shadow`.
#[derive(Clone, Copy, Debug)]
pub struct UnshadowedLight {
    /// The segment from the vertex towards the light point.
    pub shadow: crate::core::geometry::Ray,
    /// f |cos| Li w_light / (p_select pdf_light), as [`sample_direct`] returns it when the
    /// segment is clear.
    pub contribution: SampledSpectrum,
}

impl UnshadowedLight {
    /// This sample with its segment inside the media `media` (those the path is in once it
    /// leaves the vertex towards the light, [`MediumStack::after`]): the contribution times the
    /// Beer-Lambert transmittance of the innermost one over the segment (0 over an infinite
    /// segment in an absorbing medium).
    #[inline(always)]
    pub fn through(mut self, media: &MediumStack, scene: &Scene, wl: &SampledWavelengths) -> Self {
        if let Some(t) = media.transmittance(scene, self.shadow.t_max, wl) {
            self.contribution *= t;
        }
        self
    }

    /// This sample as a path's: its contribution times the path throughput `beta`, for layer
    /// `class` of the path's sums.
    #[inline(always)]
    pub fn for_path(self, beta: SampledSpectrum, class: PathClass) -> PendingLight {
        PendingLight { shadow: self.shadow, contribution: beta * self.contribution, class }
    }
}

/// A path's light sample whose shadow ray is still to be traced: the path integrators trace it
/// just before the path's next ray, which measured 1.03-1.08x faster than tracing it at once
/// (docs/architecture.md §7.2), and add it before anything that ray finds, so the sums are those
/// of tracing it at once, bit for bit.
#[derive(Clone, Copy, Debug)]
pub struct PendingLight {
    shadow: crate::core::geometry::Ray,
    contribution: SampledSpectrum,
    class: PathClass,
}

impl PendingLight {
    /// Traces the shadow ray and adds the contribution to `out` if nothing blocks it.
    #[inline(always)]
    pub fn resolve(self, scene: &Scene, out: &mut LayeredRadiance) {
        if !scene.occluded(&self.shadow) {
            out.add(self.class, self.contribution);
        }
    }
}

/// Next-event estimation at `si` without its shadow ray, restricted to the directions where
/// `excluded(wi_local)` is false: one power-proportional light choice and one point on it, the
/// BSDF's f and pdf there and the MIS weight; None where the sample contributes nothing
/// whatever the visibility. Light samples in the excluded set contribute nothing
/// (docs/architecture.md §7.5: the quasi-specular cone C is estimated by the continued path
/// instead), except samples of delta lights (point, spot, directional), which a continued path
/// can never hit and which are therefore always counted. [`sample_direct`] traces the shadow
/// ray at once; the path integrators hold it as a [`PendingLight`].
#[inline(always)]
pub fn sample_light(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    wo_local: Vec3,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
    excluded: impl Fn(Vec3) -> bool,
) -> Option<UnshadowedLight> {
    let (ls, p_light) = light_sample_at(scene, si.p, wl, sampler)?;
    let wi_local = si.frame().to_local(ls.wi);
    // a delta light is never excluded: no continued path can hit it (docs/architecture.md §7.5)
    if !ls.delta && excluded(wi_local) {
        return None;
    }
    let (f, p_bsdf) = bsdf.f_pdf(wo_local, wi_local, TransportMode::Radiance);
    let f = f * wi_local.z.abs();
    if f.is_black() {
        return None;
    }
    let w = if ls.delta { 1.0 } else { power_heuristic(p_light, p_bsdf) };
    Some(UnshadowedLight { shadow: si.spawn_shadow_ray(ls.wi, ls.dist), contribution: f * ls.li * (w / p_light) })
}

/// Next-event estimation at a scattering point `p` inside a medium, seen from `wo`: as
/// [`sample_light`], with the phase function in place of the BSDF (its value is its pdf, so the
/// MIS weight is the power heuristic of the light's pdf against p). The shadow ray's
/// transmittance is the caller's ([`UnshadowedLight::through`]).
#[inline]
pub fn sample_light_in_medium(
    scene: &Scene,
    p: Vec3,
    wo: Vec3,
    phase: &HenyeyGreenstein,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
) -> Option<UnshadowedLight> {
    let (ls, p_light) = light_sample_at(scene, p, wl, sampler)?;
    let f = phase.eval(wo, ls.wi);
    let w = if ls.delta { 1.0 } else { power_heuristic(p_light, f) };
    let mut shadow = crate::core::geometry::Ray::new(p, ls.wi);
    if ls.dist.is_finite() {
        shadow.t_max = (ls.dist * (1.0 - 1e-4)).max(0.0);
    }
    Some(UnshadowedLight { shadow, contribution: ls.li * (f * w / p_light) })
}

/// One power-proportional light choice and one point on it, seen from `p`: the sample and
/// its pdf p_select pdf_light; None where it carries nothing.
#[inline(always)]
fn light_sample_at(
    scene: &Scene,
    p: Vec3,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
) -> Option<(crate::core::light::LightSample, f32)> {
    let u_light = sampler.get_u64();
    let u_point = sampler.get_2d();
    let (li_index, p_select) = scene.light_sampler.sample(u_light)?;
    let ls = scene.lights[li_index].sample_li(p, u_point, wl, &scene.emissions)?;
    if ls.pdf <= 0.0 || ls.li.is_black() {
        return None;
    }
    Some((ls, p_select * ls.pdf))
}

/// MIS-weighted emission of the surface at `si` towards `wo`, reached from `prev`
/// (the BSDF-sampling half of [`sample_direct`]). Zero for non-emitters.
#[inline(always)]
pub fn emitted_at_hit(
    scene: &Scene,
    si: &SurfaceInteraction,
    wo: Vec3,
    prev: &PrevVertex,
    wl: &SampledWavelengths,
) -> SampledSpectrum {
    if si.light == crate::core::geometry::NONE {
        return SampledSpectrum::zero();
    }
    let light = &scene.lights[si.light as usize];
    let Light::Area { emission, .. } = light else { return SampledSpectrum::zero() };
    let le = scene.emissions[*emission as usize].radiance(si.ng, wo, si.uv, wl);
    if le.is_black() {
        return le;
    }
    if prev.pdf.is_infinite() {
        return le;
    }
    let p_light = scene.light_sampler.pmf(si.light as usize) * light.pdf_li_area(prev.p, si.p, si.ng);
    le * power_heuristic(prev.pdf, p_light)
}

/// MIS-weighted radiance of the lights at infinity seen by a ray that left `prev` in direction
/// `dir` and escaped.
#[inline(always)]
pub fn escaped_radiance(scene: &Scene, prev: &PrevVertex, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
    let mut sum = SampledSpectrum::zero();
    for &i in &scene.infinite_lights {
        let light = &scene.lights[i];
        let le = light.le_escaped(dir, wl);
        if le.is_black() {
            continue;
        }
        let w = if prev.pdf.is_infinite() {
            1.0
        } else {
            power_heuristic(prev.pdf, scene.light_sampler.pmf(i) * light.pdf_li_escaped(dir))
        };
        sum += le * w;
    }
    sum
}
