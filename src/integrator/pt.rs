//! `pt`: the reference unidirectional path tracer (DESIGN.md section 3.1): next-event estimation
//! with MIS (power heuristic) against BSDF sampling, Russian roulette, unbounded depth by default.
//! The estimate is split by the number of non-specular scattering events before the light:
//! 0 -> emission (lights seen directly or through specular chains), 1 -> direct, >= 2 -> indirect.

use glam::Vec3;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use quasar_materials::{Bsdf, TransportMode};

use crate::geometry::{NONE, Ray};
use crate::sampling::{Sampler, power_heuristic};
use crate::scene::{Scene, SurfaceInteraction};

/// Radiance of one camera path split into the film's layers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LayeredRadiance {
    /// Lights seen directly or through specular chains (L^V).
    pub emission: SampledSpectrum,
    /// Light after exactly one non-specular scattering event (L^D).
    pub direct: SampledSpectrum,
    /// Light after two or more non-specular events (L^I).
    pub indirect: SampledSpectrum,
}

impl LayeredRadiance {
    /// Adds `l` to the layer for a path with `nonspecular` non-specular events.
    #[inline]
    pub fn add(&mut self, nonspecular: u32, l: SampledSpectrum) {
        match nonspecular {
            0 => self.emission += l,
            1 => self.direct += l,
            _ => self.indirect += l,
        }
    }
}

/// Settings of the path tracer.
#[derive(Clone, Copy, Debug)]
pub struct PtSettings {
    /// Maximum number of scattering events (None = unbounded, Russian roulette ends paths).
    pub max_depth: Option<u32>,
    /// Depth from which Russian roulette may end paths.
    pub rr_depth: u32,
}

impl Default for PtSettings {
    fn default() -> Self {
        Self { max_depth: None, rr_depth: 3 }
    }
}

/// Next-event estimation at `si`: samples a light (power-proportional) and a point on it, and
/// returns beta-free contribution f * Li * |cos| * w_light / (p_select * pdf_light).
#[inline]
pub fn sample_direct(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    wo_local: Vec3,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
) -> SampledSpectrum {
    let u_light = sampler.get_1d();
    let u_point = sampler.get_2d();
    let Some((li_index, p_select)) = scene.light_sampler.sample(u_light) else {
        return SampledSpectrum::zero();
    };
    let light = &scene.lights[li_index];
    let Some(ls) = light.sample_li(si.p, u_point, wl, &scene.emissions) else {
        return SampledSpectrum::zero();
    };
    if ls.pdf <= 0.0 || ls.li.is_black() {
        return SampledSpectrum::zero();
    }
    let frame = si.frame();
    let wi_local = frame.to_local(ls.wi);
    let f = bsdf.f(wo_local, wi_local, TransportMode::Radiance) * wi_local.z.abs();
    if f.is_black() {
        return SampledSpectrum::zero();
    }
    if scene.occluded(&si.spawn_shadow_ray(ls.wi, ls.dist)) {
        return SampledSpectrum::zero();
    }
    let p_light = p_select * ls.pdf;
    let w = if ls.delta {
        1.0
    } else {
        let p_bsdf = bsdf.pdf(wo_local, wi_local, TransportMode::Radiance);
        power_heuristic(p_light, p_bsdf)
    };
    f * ls.li * (w / p_light)
}

/// Traces one camera path and returns its layered radiance at the (possibly terminated)
/// wavelengths `wl`.
pub fn radiance(
    scene: &Scene,
    mut ray: Ray,
    wl: &mut SampledWavelengths,
    sampler: &mut Sampler,
    settings: &PtSettings,
) -> LayeredRadiance {
    let mut out = LayeredRadiance::default();
    let mut beta = SampledSpectrum::one();
    let mut nonspecular = 0u32;
    let mut specular_bounce = true;
    let mut prev_p = ray.origin;
    let mut prev_pdf = 0.0f32;
    let mut eta_scale = 1.0f32;
    let mut depth = 0u32;
    loop {
        let Some(si) = scene.intersect(&ray) else {
            for &i in &scene.infinite_lights {
                let light = &scene.lights[i];
                let le = light.le_escaped(wl);
                if le.is_black() {
                    continue;
                }
                let w = if specular_bounce {
                    1.0
                } else {
                    let p_light = scene.light_sampler.pmf(i) * light.pdf_li_escaped();
                    power_heuristic(prev_pdf, p_light)
                };
                out.add(nonspecular, beta * le * w);
            }
            break;
        };
        let wo = -ray.dir;
        if si.light != NONE {
            let light = &scene.lights[si.light as usize];
            if let crate::light::Light::Area { emission, .. } = light {
                let le = scene.emissions[*emission as usize].radiance(si.ng, wo, wl);
                if !le.is_black() {
                    let w = if specular_bounce {
                        1.0
                    } else {
                        let p_light = scene.light_sampler.pmf(si.light as usize) * light.pdf_li_area(prev_p, si.p, si.ng);
                        power_heuristic(prev_pdf, p_light)
                    };
                    out.add(nonspecular, beta * le * w);
                }
            }
        }
        if settings.max_depth.is_some_and(|m| depth >= m) {
            break;
        }
        let bsdf = scene.materials[si.material as usize].bsdf(wl);
        let frame = si.frame();
        let wo_local = frame.to_local(wo);
        if !bsdf.is_specular() {
            let ld = sample_direct(scene, &si, &bsdf, wo_local, wl, sampler);
            if !ld.is_black() {
                out.add(nonspecular + 1, beta * ld);
            }
        }
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let Some(bs) = bsdf.sample_f(wo_local, uc, u, TransportMode::Radiance) else { break };
        if bs.pdf <= 0.0 || bs.f.is_black() {
            break;
        }
        let wi = frame.from_local(bs.wi);
        // Reject directions on the wrong side of the geometric surface (shading-normal leaks).
        let reflect = bs.wi.z * wo_local.z > 0.0;
        if reflect != (wi.dot(si.ng) * wo.dot(si.ng) > 0.0) {
            break;
        }
        beta *= bs.f * (bs.wi.z.abs() / bs.pdf);
        if !beta.is_finite() {
            break;
        }
        specular_bounce = bs.specular;
        if !bs.specular {
            nonspecular += 1;
        }
        if bs.lobe == quasar_materials::Lobe::Transmission {
            eta_scale *= bs.eta * bs.eta;
        }
        prev_pdf = if bs.specular { f32::INFINITY } else { bs.pdf };
        prev_p = si.p;
        ray = si.spawn_ray(wi);
        depth += 1;

        // Russian roulette on the throughput with the radiance-scaling of refraction undone.
        let rr = beta.max_component() * eta_scale;
        if depth >= settings.rr_depth && rr < 1.0 {
            let q = (1.0 - rr).max(0.05);
            if sampler.get_1d() < q {
                break;
            }
            beta /= 1.0 - q;
        }
    }
    out
}
