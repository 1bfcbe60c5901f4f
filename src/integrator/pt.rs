//! `pt`: the reference unidirectional path tracer (docs/architecture.md §7.2): next-event estimation
//! with MIS (power heuristic) against BSDF sampling, Russian roulette, unbounded depth by default.
//! Contributions are split into layers by the path's scattering history ([`PathClass`]).

use quasar_materials::TransportMode;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

use super::direct::{PendingLight, PrevVertex, emitted_at_hit, escaped_radiance, sample_light};
use super::entry::{Built, MethodEntry};
use super::params::{ParamDefault, ParamKind, ParamSpec};
use super::per_pixel::PerPixel;
use super::scatter::scatter;
use crate::core::geometry::Ray;
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
        Ok(Built { method: Box::new(PerPixel::new(b.scene, b.camera, settings, b.seed, b.shard, b.isa)), units: b.spp })
    },
};

impl super::per_pixel::PixelEstimator for PtSettings {
    #[inline(always)]
    fn radiance(&self, scene: &Scene, ray: Ray, wl: &mut SampledWavelengths, sampler: &mut Sampler) -> LayeredRadiance {
        radiance(scene, ray, wl, sampler, self)
    }

    fn header(&self) -> Vec<(String, String)> {
        vec![("max_depth".into(), self.max_depth.map_or("unbounded".into(), |d| d.to_string()))]
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
        }
    }
}

/// Traces one camera path and returns its layered radiance at the (possibly terminated)
/// wavelengths `wl`.
#[inline(always)]
pub fn radiance(
    scene: &Scene,
    ray: Ray,
    wl: &mut SampledWavelengths,
    sampler: &mut Sampler,
    settings: &PtSettings,
) -> LayeredRadiance {
    let mut out = LayeredRadiance::default();
    trace(scene, ray, PathState::eye(ray.origin), wl, sampler, settings, &mut out);
    out
}

/// Continues a path in `state` along `ray` as the path tracer does (NEE + MIS at every
/// non-specular vertex, Russian roulette from `settings.rr_depth` scattering events), adding
/// what it finds to `out`. The bidirectional methods call it where their own estimator ends
/// a path for a reason other than the estimate itself (a cap on gather points or specular
/// events), so that no light is lost there (docs/architecture.md §7.5).
#[inline(always)]
pub fn trace(
    scene: &Scene,
    mut ray: Ray,
    state: PathState,
    wl: &mut SampledWavelengths,
    sampler: &mut Sampler,
    settings: &PtSettings,
    out: &mut LayeredRadiance,
) {
    let PathState { mut beta, mut class, mut prev, mut eta_scale, mut depth } = state;
    // the last vertex's light sample: its shadow ray is traced just before the path's next
    // ray (the two are independent), and its contribution, times the path throughput, added
    // if the segment is clear, before anything the next ray finds
    let mut pending: Option<PendingLight> = None;
    loop {
        if let Some(l) = pending.take() {
            l.resolve(scene, out);
        }
        let Some(si) = scene.intersect(&ray) else {
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
            pending = sample_light(scene, &si, &bsdf, wo_local, wl, sampler, |_| false)
                .map(|l| l.for_path(beta, class.scattered(false)));
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
