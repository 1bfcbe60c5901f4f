//! The backward (camera) pass of `vismap` (DESIGN.md section 3.2 step 2): a camera path that
//! collects emission and MIS direct light up to its gather vertex and leaves a
//! [`VisibilityPoint`] there for the photons of the forward pass.

use glam::Vec3;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use quasar_materials::{Bsdf, Frame, TransportMode};

use crate::geometry::Ray;
use crate::integrator::direct::{PrevVertex, emitted_at_hit, escaped_radiance, sample_direct};
use crate::integrator::layers::{LayeredRadiance, PathClass};
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction};

/// A camera-path vertex where photons are gathered (one per pixel and iteration at most).
#[derive(Clone, Copy, Debug)]
pub struct VisibilityPoint {
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal of the surface (its winding side, not flipped).
    pub ng: Vec3,
    /// Shading frame.
    pub frame: Frame,
    /// Direction towards the eye along the path, in the shading frame.
    pub wo_local: Vec3,
    /// The BSDF at the iteration's wavelengths.
    pub bsdf: Bsdf,
    /// Camera-path throughput from the eye to this vertex.
    pub beta: SampledSpectrum,
    /// Non-specular events before this vertex (the gather depth).
    pub depth: u32,
    /// Distance from the eye to the path's first non-specular vertex along the path (the
    /// pixel's footprint there sets the automatic gather radius).
    pub footprint_distance: f32,
}

/// What one camera path of an iteration produced.
#[derive(Clone, Copy, Debug)]
pub struct CameraPathResult {
    /// Emission and direct light collected on the way (layers `emission`, `direct`, and the
    /// `indirect` light found before the gather vertex when the gather depth is > 0).
    pub radiance: LayeredRadiance,
    /// The gather vertex, if the path reached one.
    pub point: Option<VisibilityPoint>,
    /// The path's wavelengths (secondaries terminated by a dispersive interface).
    pub wl: SampledWavelengths,
}

/// MIS direct light at a gather vertex: light sampling (as everywhere) plus one BSDF sample traced
/// to its first hit, weighted against light sampling when that hit is an emitter or escapes.
/// Emission reached through a specular surface is not counted: photons carry it.
fn gather_vertex_direct(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    wo_local: Vec3,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
) -> SampledSpectrum {
    let mut l = sample_direct(scene, si, bsdf, wo_local, wl, sampler);
    let uc = sampler.get_1d();
    let u = sampler.get_2d();
    let Some(bs) = bsdf.sample_f(wo_local, uc, u, TransportMode::Radiance) else { return l };
    if bs.pdf <= 0.0 || bs.f.is_black() || bs.specular {
        return l;
    }
    let frame = si.frame();
    let wi = frame.from_local(bs.wi);
    let wo = frame.from_local(wo_local);
    if (bs.wi.z * wo_local.z > 0.0) != (wi.dot(si.ng) * wo.dot(si.ng) > 0.0) {
        return l;
    }
    let weight = bs.f * (bs.wi.z.abs() / bs.pdf);
    let prev = PrevVertex { p: si.p, pdf: bs.pdf };
    let ray = si.spawn_ray(wi);
    match scene.intersect(&ray) {
        Some(hit) => l += weight * emitted_at_hit(scene, &hit, -wi, &prev, wl),
        None => l += weight * escaped_radiance(scene, &prev, wl),
    }
    l
}

/// Traces the camera path of one pixel for one iteration: specular events are followed exactly;
/// at every non-specular vertex before `gather_depth` MIS direct light is added and the path
/// continues by BSDF sampling; the non-specular vertex number `gather_depth` becomes the
/// visibility point (after adding its own direct light). Paths are not Russian-rouletted: they
/// are at most `gather_depth` + 1 non-specular vertices long; `max_specular` bounds specular
/// chains (a path caught between mirrors).
pub fn trace_camera_path(
    scene: &Scene,
    mut ray: Ray,
    mut wl: SampledWavelengths,
    sampler: &mut Sampler,
    gather_depth: u32,
    max_specular: u32,
) -> CameraPathResult {
    let mut out = LayeredRadiance::default();
    let mut beta = SampledSpectrum::one();
    let mut class = PathClass::default();
    let mut prev = PrevVertex::eye(ray.origin);
    let mut path_length = 0.0f32;
    let mut specular_events = 0u32;
    loop {
        let Some(si) = scene.intersect(&ray) else {
            out.add(class, beta * escaped_radiance(scene, &prev, &wl));
            break;
        };
        if class.nonspecular == 0 {
            path_length += si.t;
        }
        let wo = -ray.dir;
        out.add(class, beta * emitted_at_hit(scene, &si, wo, &prev, &wl));
        let bsdf = scene.materials[si.material as usize].bsdf(&mut wl);
        let frame = si.frame();
        let wo_local = frame.to_local(wo);
        if !bsdf.is_specular() {
            if class.nonspecular == gather_depth {
                let ld = gather_vertex_direct(scene, &si, &bsdf, wo_local, &wl, sampler);
                out.add(class.scattered(false), beta * ld);
                let point = VisibilityPoint {
                    p: si.p,
                    ng: si.ng,
                    frame,
                    wo_local,
                    bsdf,
                    beta,
                    depth: class.nonspecular,
                    footprint_distance: path_length,
                };
                return CameraPathResult { radiance: out, point: Some(point), wl };
            }
            let ld = sample_direct(scene, &si, &bsdf, wo_local, &wl, sampler);
            out.add(class.scattered(false), beta * ld);
        } else {
            specular_events += 1;
            if specular_events > max_specular {
                break;
            }
        }
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let Some(bs) = bsdf.sample_f(wo_local, uc, u, TransportMode::Radiance) else { break };
        if bs.pdf <= 0.0 || bs.f.is_black() {
            break;
        }
        let wi = frame.from_local(bs.wi);
        if (bs.wi.z * wo_local.z > 0.0) != (wi.dot(si.ng) * wo.dot(si.ng) > 0.0) {
            break;
        }
        beta *= bs.f * (bs.wi.z.abs() / bs.pdf);
        if !beta.is_finite() || beta.is_black() {
            break;
        }
        class = class.scattered(bs.specular);
        prev = PrevVertex { p: si.p, pdf: if bs.specular { f32::INFINITY } else { bs.pdf } };
        ray = si.spawn_ray(wi);
    }
    CameraPathResult { radiance: out, point: None, wl }
}
