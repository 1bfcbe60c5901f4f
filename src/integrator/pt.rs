//! `pt`: the reference unidirectional path tracer (docs/architecture.md §7.2): next-event estimation
//! with MIS (power heuristic) against BSDF sampling, Russian roulette, unbounded depth by default;
//! inside a scattering medium, distance sampling and phase-function vertices (`medium_vertex`).
//! Contributions are split into layers by the path's scattering history ([`PathClass`]).

use quasar_materials::TransportMode;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

use super::direct::{PendingLight, PrevVertex, emitted_at_hit, escaped_radiance, sample_light};
use super::entry::{Built, MethodEntry};
use super::medium_vertex::scatter_in_medium;
use super::params::{ParamDefault, ParamKind, ParamSpec};
use super::per_pixel::PerPixel;
use super::scatter::scatter;
use crate::core::geometry::Ray;
use crate::core::medium::{MAX_MEDIUM_SCATTERS, MediumStack, SegmentEvent};
use crate::core::sampling::Sampler;
use crate::core::scene::Scene;
use crate::film::{LayeredRadiance, PathClass};

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

/// `max_depth`: the largest number of scattering events of a path.
pub static MAX_DEPTH: ParamSpec = ParamSpec {
    key: "max_depth",
    flag: "max-depth",
    kind: ParamKind::Int { min: 0, max: 1_000_000 },
    default: ParamDefault::Computed("pt: unbounded, Russian roulette ends paths; direct: 16"),
    doc: "maximum number of scattering events per path (direct: of the specular chain before the first non-specular vertex)",
};

/// The method table's row of `pt`.
pub static PT: MethodEntry = MethodEntry {
    name: "pt",
    summary: "reference path tracer: next-event estimation + MIS (power heuristic), Russian roulette, unbounded depth",
    params: &[&MAX_DEPTH],
    variant: None,
    bytes_per_pixel: super::per_pixel::PER_PIXEL_BYTES_PER_PIXEL,
    build: |b, r| {
        let settings = PtSettings { max_depth: r.int(&MAX_DEPTH)?.map(|d| d as u32), ..PtSettings::default() };
        // the kernels of a scene without absorbing media do no media bookkeeping at all
        Ok(Built {
            method: if b.scene.has_media() {
                Box::new(PerPixel::new(b.scene, b.camera, PathTracer::<true>(settings), b.seed, b.shard, b.isa))
            } else {
                Box::new(PerPixel::new(b.scene, b.camera, PathTracer::<false>(settings), b.seed, b.shard, b.isa))
            },
            units: b.spp,
        })
    },
};

/// `pt`'s per-pixel estimator, compiled with the absorbing media tracked (`MEDIA`: the scene
/// has some) or without a trace of them.
#[derive(Clone, Copy, Debug)]
pub struct PathTracer<const MEDIA: bool>(pub PtSettings);

impl<const MEDIA: bool> super::per_pixel::PixelEstimator for PathTracer<MEDIA> {
    #[inline(always)]
    fn radiance(&self, scene: &Scene, ray: Ray, wl: &mut SampledWavelengths, sampler: &mut Sampler) -> LayeredRadiance {
        let mut out = LayeredRadiance::default();
        trace_in::<MEDIA>(scene, ray, PathState::eye(ray.origin), wl, sampler, &self.0, &mut out);
        out
    }

    fn header(&self) -> Vec<(String, String)> {
        vec![("max_depth".into(), self.0.max_depth.map_or("unbounded".into(), |d| d.to_string()))]
    }
}

/// Russian roulette on the throughput `beta` (with refraction's radiance scaling `eta_scale`
/// undone): survives with probability min(1, max beta), at least 5%; returns false when the path
/// ends and otherwise rescales `beta` so that the estimate stays unbiased.
#[inline]
pub fn russian_roulette(beta: &mut SampledSpectrum, eta_scale: f32, u: f32) -> bool {
    let rr = beta.max_component() * eta_scale;
    if rr >= 1.0 {
        return true;
    }
    let q = (1.0 - rr).max(0.05);
    if u < q {
        return false;
    }
    *beta /= 1.0 - q;
    true
}

/// A camera path between two vertices: what [`trace`] needs to continue it.
#[derive(Clone, Copy, Debug)]
pub struct PathState {
    /// Throughput from the eye to the next vertex.
    pub beta: SampledSpectrum,
    /// Layer class of the path so far.
    pub class: PathClass,
    /// The vertex the next ray leaves (for the MIS weight of emission found along it).
    pub prev: PrevVertex,
    /// Product of eta^2 over refractions (undone for Russian roulette).
    pub eta_scale: f32,
    /// Scattering events so far.
    pub depth: u32,
    /// The absorbing media the path is inside (`core::medium`).
    pub media: MediumStack,
}

impl PathState {
    /// A path leaving the eye at `origin`.
    pub fn eye(origin: glam::Vec3) -> Self {
        Self {
            beta: SampledSpectrum::one(),
            class: PathClass::default(),
            prev: PrevVertex::eye(origin),
            eta_scale: 1.0,
            depth: 0,
            media: MediumStack::default(),
        }
    }
}

/// Continues a path in `state` along `ray` as the path tracer does (NEE + MIS at every
/// non-specular vertex, Russian roulette from `settings.rr_depth` scattering events), adding
/// what it finds to `out`. The bidirectional methods call it where their own estimator ends
/// a path for a reason other than the estimate itself (a cap on gather points or specular
/// events), so that no light is lost there (docs/architecture.md §7.5).
#[inline(always)]
pub fn trace(
    scene: &Scene,
    ray: Ray,
    state: PathState,
    wl: &mut SampledWavelengths,
    sampler: &mut Sampler,
    settings: &PtSettings,
    out: &mut LayeredRadiance,
) {
    // a scene without absorbing media runs the loop without their bookkeeping (the same code
    // as before media existed: `pt` costs what it did)
    if scene.has_media() {
        trace_in::<true>(scene, ray, state, wl, sampler, settings, out)
    } else {
        trace_in::<false>(scene, ray, state, wl, sampler, settings, out)
    }
}

/// [`trace`], with the absorbing media tracked (`MEDIA`) or not.
#[inline(always)]
fn trace_in<const MEDIA: bool>(
    scene: &Scene,
    mut ray: Ray,
    state: PathState,
    wl: &mut SampledWavelengths,
    sampler: &mut Sampler,
    settings: &PtSettings,
    out: &mut LayeredRadiance,
) {
    let PathState { mut beta, mut class, mut prev, mut eta_scale, mut depth, mut media } = state;
    let mut medium_scatters = 0u32;
    // the last vertex's light sample: its shadow ray is traced just before the path's next
    // ray (the two are independent), and its contribution, times the path throughput, added
    // if the segment is clear, before anything the next ray finds
    let mut pending: Option<PendingLight> = None;
    loop {
        if let Some(l) = pending.take() {
            l.resolve(scene, out);
        }
        let hit = scene.intersect(&ray);
        // the segment inside the innermost medium: absorbed (Beer-Lambert), or scattered at a
        // sampled distance (core::medium)
        if MEDIA {
            let t_end = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
            match media.sample_segment(scene, t_end, wl, sampler) {
                None => {}
                Some(SegmentEvent::Surface(w)) => beta *= w,
                Some(SegmentEvent::Scatter { t, weight, phase }) => {
                    beta *= weight;
                    medium_scatters += 1;
                    if !beta.is_finite()
                        || beta.is_black()
                        || medium_scatters > MAX_MEDIUM_SCATTERS
                        || settings.max_depth.is_some_and(|m| depth >= m)
                    {
                        break;
                    }
                    let v = scatter_in_medium(scene, &ray, t, &phase, &media, wl, sampler);
                    pending = v.light.map(|l| l.for_path(beta, class.scattered(false)));
                    class = class.scattered(false);
                    (prev, ray) = (v.prev, v.next);
                    depth += 1;
                    if depth >= settings.rr_depth && !russian_roulette(&mut beta, eta_scale, sampler.get_1d()) {
                        break;
                    }
                    continue;
                }
            }
        }
        let Some(si) = hit else {
            out.add(class, beta * escaped_radiance(scene, &prev, ray.dir, wl));
            break;
        };
        let wo = -ray.dir;
        out.add(class, beta * emitted_at_hit(scene, &si, wo, &prev, wl));
        if settings.max_depth.is_some_and(|m| depth >= m) {
            break;
        }
        let bsdf = scene.bsdf_at(&si, wl);
        let frame = si.frame();
        let wo_local = frame.to_local(wo);
        if !bsdf.is_specular() {
            pending = sample_light(scene, &si, &bsdf, wo_local, wl, sampler, |_| false).map(|l| {
                let l = if MEDIA { l.through(&media.after(scene, &si, wo, l.shadow.dir), scene, wl) } else { l };
                l.for_path(beta, class.scattered(false))
            });
        }
        let Some(sc) = scatter(&bsdf, &si, &frame, wo, wo_local, TransportMode::Radiance, sampler) else { break };
        let (bs, wi) = (sc.bs, sc.wi);
        beta *= sc.weight();
        if !beta.is_finite() {
            break;
        }
        class = class.scattered(bs.specular);
        if bs.lobe == quasar_materials::Lobe::Transmission {
            eta_scale *= bs.eta * bs.eta;
        }
        prev = PrevVertex { p: si.p, pdf: if bs.specular { f32::INFINITY } else { bs.pdf } };
        if MEDIA {
            media = media.after(scene, &si, wo, wi);
        }
        ray = si.spawn_ray(wi);
        depth += 1;
        if depth >= settings.rr_depth && !russian_roulette(&mut beta, eta_scale, sampler.get_1d()) {
            break;
        }
    }
    // a path that ends after a light sample: that sample's shadow ray
    if let Some(l) = pending {
        l.resolve(scene, out);
    }
}
