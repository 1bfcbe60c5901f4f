//! `direct`: emission seen directly and direct light at the first non-specular vertex (next-event
//! estimation with MIS against one BSDF sample; pbrt-v4's `LightPathIntegrator` without the
//! path), through specular chains at most `max_depth` events long; the first non-specular vertex
//! may be a scattering event inside a medium. A debugging and preview
//! method: fast, noise-free where lights are large, and the `emission` + `direct` layers of
//! `pt` exactly in expectation (which its test checks). The whole method is this file and its
//! row in the method table.

use quasar_materials::TransportMode;
use quasar_materials::spectrum::SampledWavelengths;

use super::direct::{PrevVertex, emitted_at_hit, escaped_radiance, sample_light};
use super::entry::{Built, MethodEntry};
use super::medium_vertex::scatter_in_medium;
use super::per_pixel::{PerPixel, PixelEstimator};
use super::pt::MAX_DEPTH;
use super::scatter::scatter;
use crate::core::geometry::Ray;
use crate::core::medium::{MediumStack, SegmentEvent};
use crate::core::sampling::Sampler;
use crate::core::scene::Scene;
use crate::film::{LayeredRadiance, PathClass};

/// Longest specular chain followed before the first non-specular vertex, by default.
const DEFAULT_MAX_SPECULAR: u32 = 16;

/// Direct lighting at the first non-specular vertex.
#[derive(Clone, Copy, Debug)]
pub struct DirectLighting {
    /// Specular events followed before giving up.
    pub max_specular: u32,
}

/// The method table's row of `direct`.
pub static DIRECT: MethodEntry = MethodEntry {
    name: "direct",
    summary: "direct lighting only: lights seen directly or through specular chains, and NEE + MIS at the first non-specular vertex (a preview and debugging method; no indirect light)",
    params: &[&MAX_DEPTH],
    variant: None,
    bytes_per_pixel: super::per_pixel::PER_PIXEL_BYTES_PER_PIXEL,
    build: |b, r| {
        let max_specular = r.int(&MAX_DEPTH)?.map_or(DEFAULT_MAX_SPECULAR, |d| d as u32);
        let method = PerPixel::new(b.scene, b.camera, DirectLighting { max_specular }, b.seed, b.shard, b.isa);
        Ok(Built { method: Box::new(method), units: b.spp })
    },
};

impl PixelEstimator for DirectLighting {
    #[inline(always)]
    fn radiance(
        &self,
        scene: &Scene,
        mut ray: Ray,
        wl: &mut SampledWavelengths,
        sampler: &mut Sampler,
    ) -> LayeredRadiance {
        let mut out = LayeredRadiance::default();
        let mut beta = quasar_materials::spectrum::SampledSpectrum::one();
        let mut prev = PrevVertex::eye(ray.origin);
        let class = PathClass::default();
        let mut media = MediumStack::default();
        // Beer-Lambert transmittance of the segment to `hit` inside the innermost medium
        let absorbed = |media: &MediumStack, hit: Option<&_>, wl: &SampledWavelengths| {
            media.transmittance_to(scene, hit, wl).unwrap_or(quasar_materials::spectrum::SampledSpectrum::one())
        };
        for _ in 0..=self.max_specular {
            let hit = scene.intersect(&ray);
            match media.sample_segment(scene, hit.as_ref().map_or(f32::INFINITY, |h| h.t), wl, sampler) {
                None => {}
                Some(SegmentEvent::Surface(w)) => beta *= w,
                Some(SegmentEvent::Scatter { t, weight, phase }) => {
                    // the first non-specular vertex is in a medium: its light sample and the
                    // phase sample's one segment (light that crosses it unscattered)
                    beta *= weight;
                    let v = scatter_in_medium(scene, &ray, t, &phase, &media, wl, sampler);
                    if let Some(l) = v.light {
                        l.for_path(beta, class.scattered(false)).resolve(scene, &mut out);
                    }
                    let hit = scene.intersect(&v.next);
                    let le = absorbed(&media, hit.as_ref(), wl)
                        * match hit {
                            Some(hit) => emitted_at_hit(scene, &hit, -v.next.dir, &v.prev, wl),
                            None => escaped_radiance(scene, &v.prev, v.next.dir, wl),
                        };
                    out.add(class.scattered(false), beta * le);
                    break;
                }
            }
            let Some(si) = hit else {
                out.add(class, beta * escaped_radiance(scene, &prev, ray.dir, wl));
                break;
            };
            let wo = -ray.dir;
            out.add(class, beta * emitted_at_hit(scene, &si, wo, &prev, wl));
            let bsdf = scene.bsdf_at(&si, wl);
            let frame = si.frame();
            let wo_local = frame.to_local(wo);
            if !bsdf.is_specular() {
                let light = sample_light(scene, &si, &bsdf, wo_local, wl, sampler, |_| false);
                let sc = scatter(&bsdf, &si, &frame, wo, wo_local, TransportMode::Radiance, sampler);
                // the light sample's shadow ray just before the BSDF sample's ray, as in `pt`
                // (docs/architecture.md §7.2)
                if let Some(l) = light {
                    let through = media.after(scene, &si, wo, l.shadow.dir);
                    l.through(&through, scene, wl).for_path(beta, class.scattered(false)).resolve(scene, &mut out);
                }
                // the BSDF-sampling half of MIS: one segment, emitters only
                if let Some(sc) = sc {
                    let next = PrevVertex { p: si.p, pdf: sc.bs.pdf };
                    let hit = scene.intersect(&si.spawn_ray(sc.wi));
                    let t = absorbed(&media.after(scene, &si, wo, sc.wi), hit.as_ref(), wl);
                    let le = t * match hit {
                        Some(hit) => emitted_at_hit(scene, &hit, -sc.wi, &next, wl),
                        None => escaped_radiance(scene, &next, sc.wi, wl),
                    };
                    out.add(class.scattered(false), beta * sc.weight() * le);
                }
                break;
            }
            let Some(sc) = scatter(&bsdf, &si, &frame, wo, wo_local, TransportMode::Radiance, sampler) else { break };
            beta *= sc.weight();
            prev = PrevVertex { p: si.p, pdf: f32::INFINITY };
            media = media.after(scene, &si, wo, sc.wi);
            ray = si.spawn_ray(sc.wi);
        }
        out
    }

    fn header(&self) -> Vec<(String, String)> {
        vec![("max_depth".into(), self.max_specular.to_string())]
    }
}
