//! The backward (camera) pass (docs/architecture.md §7.4 step 1, with the quasi-specular cone of
//! §7.5): a camera path collects emission and MIS direct light up to its gather vertex and
//! leaves [`VisibilityPoint`]s there for the photons of the forward pass.

use glam::Vec3;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use quasar_materials::{Bsdf, Frame, Lobe, NARROW_KAPPA, TransportMode};

use super::quasi_cone::{QuasiCone, in_cone};
use crate::core::geometry::Ray;
use crate::core::medium::{MediumStack, SegmentEvent};
use crate::core::sampling::Sampler;
use crate::core::scene::{Scene, SurfaceInteraction};
use crate::film::{LayeredRadiance, PathClass};
use crate::integrator::direct::{PendingLight, PrevVertex, emitted_at_hit, escaped_radiance, sample_light};
use crate::integrator::medium_vertex::scatter_in_medium;
use crate::integrator::pt::{self, PathState, PtSettings};
use crate::integrator::scatter::scatter;

/// Most visibility points one camera path may leave (a chain of quasi-specular gather vertices);
/// the path continues as the path tracer after the last one.
pub const MAX_POINTS_PER_PATH: usize = 8;

/// A camera-path vertex where photons are gathered.
#[derive(Clone, Copy, Debug)]
pub struct VisibilityPoint<'a> {
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal of the surface (its winding side, not flipped).
    pub ng: Vec3,
    /// Shading frame.
    pub frame: Frame,
    /// Direction towards the eye along the path, in the shading frame.
    pub wo_local: Vec3,
    /// The BSDF at the iteration's wavelengths.
    pub bsdf: Bsdf<'a>,
    /// Camera-path throughput from the eye to this vertex.
    pub beta: SampledSpectrum,
    /// The path's layer class on arrival (light gathered here is one more non-specular event).
    pub class: PathClass,
    /// Gather depth of this vertex (non-specular, non-quasi-specular events before it).
    pub depth: u32,
    /// Distance from the eye to the path's first non-specular vertex along the path (the
    /// pixel's footprint there sets the automatic gather radius).
    pub footprint_distance: f32,
    /// Photons arriving inside this continued set C are not gathered here (the quasi-specular
    /// cone, a narrow lobe's hemisphere: [`VertexTreatment::cone`]).
    pub cone: Option<QuasiCone>,
    /// The viewer is on the side `ng` points to.
    pub viewer_above: bool,
}

/// How a camera path chooses its gather vertices.
#[derive(Clone, Copy, Debug)]
pub struct GatherRule {
    /// Gather at the non-specular vertex with this many non-specular, non-quasi-specular events
    /// before it.
    pub depth: u32,
    /// cos(theta_c) of the quasi-specular cone, or None (plain `vismap`).
    pub cone_cos: Option<f32>,
    /// Specular and passed-through events after which a camera path is continued as the path
    /// tracer (with Russian roulette: a chain of mirrors need not end otherwise).
    pub max_specular: u32,
    /// Pass narrow lobes through without a cone too (`adaptive`): they are not gather candidates
    /// and do not count as depth, so a path that its pixel's depth would have gathered on a
    /// narrow lobe (a pixel straddling a diffuse and a narrow surface) gathers at the next
    /// vertex instead (docs/architecture.md §7.5).
    pub pass_narrow: bool,
}

/// How the camera-path methods treat one non-specular vertex (docs/architecture.md §7.5),
/// decided from the vertex alone (its material and the direction it is seen from), so that
/// every choice below is unbiased.
#[derive(Clone, Copy, Debug)]
pub struct VertexTreatment {
    /// Every lobe is narrow: traced through (full NEE with MIS, a BSDF-sampled continuation over
    /// the whole sphere), never gathered on, not counted as depth.
    pub pass_through: bool,
    /// The continued set C: the quasi-specular cone(s) and, where one lobe of a transmitting BSDF
    /// is narrow and the other is not, the narrow lobe's whole hemisphere. None: every direction
    /// is gathered.
    pub cone: Option<QuasiCone>,
    /// kappa of what a visibility point here gathers: the whole BSDF's, or that of the lobe left
    /// outside C.
    pub kappa: f32,
}

impl GatherRule {
    /// The treatment of a non-specular vertex with `bsdf` seen from `wo_local`. A lobe is narrow
    /// when its kappa(wo) exceeds [`NARROW_KAPPA`]: photons arriving within it are too rare there
    /// to estimate the rest of the sphere (they would show as fireflies and as light missing
    /// everywhere else). A BSDF whose every lobe is narrow is passed through; a transmitting one
    /// with one narrow lobe continues that lobe's hemisphere as it continues a quasi-specular
    /// cone and gathers the other (the rough bottom face of a glass plate, seen from inside:
    /// its refraction is narrow, but its reflection of a lamp seen through the top face is wide
    /// and is found by the photons, not by a BSDF sample that must hit the lamp through the top).
    /// A reflection back into a dielectric (seen from its denser side: [`reflects_inward`]) is
    /// gathered however narrow: the path it would continue stays inside the glass, where light
    /// sampling finds no emitter (every shadow ray meets the glass's own boundary), so passing
    /// it through leaves its light to BSDF samples that must leave through another interface
    /// and hit an emitter, the path tracer's estimator; the photons that entered the glass reach
    /// it directly (BENCHMARKS.md, issue 47: the rough-bottom plates).
    /// Plain `vismap` (no cone, `pass_narrow` off) gathers everywhere.
    #[inline]
    pub fn treat(&self, scene: &Scene, si: &SurfaceInteraction, bsdf: &Bsdf, wo_local: Vec3) -> VertexTreatment {
        let nu = &scene.non_uniformity()[si.material as usize];
        let whole = nu.at(wo_local.z);
        let axes = self.cone_cos.and_then(|c| QuasiCone::at(bsdf, wo_local, c));
        if self.cone_cos.is_none() && !self.pass_narrow {
            return VertexTreatment { pass_through: false, cone: None, kappa: whole };
        }
        let pass_through = VertexTreatment { pass_through: true, cone: None, kappa: whole };
        if !bsdf.has_transmission() {
            return if whole > NARROW_KAPPA {
                pass_through
            } else {
                VertexTreatment { pass_through: false, cone: axes, kappa: whole }
            };
        }
        let (reflection, transmission) = nu.lobes_at(wo_local.z);
        let side = wo_local.z.signum();
        let narrow_reflection = reflection > NARROW_KAPPA && !reflects_inward(bsdf, wo_local);
        match (narrow_reflection, transmission > NARROW_KAPPA) {
            (true, true) => pass_through,
            (false, false) => VertexTreatment { pass_through: false, cone: axes, kappa: whole },
            (true, false) => VertexTreatment {
                pass_through: false,
                cone: Some(QuasiCone::with_hemisphere(axes, side)),
                kappa: transmission,
            },
            (false, true) => VertexTreatment {
                pass_through: false,
                cone: Some(QuasiCone::with_hemisphere(axes, -side)),
                kappa: reflection,
            },
        }
    }
}

/// Whether `bsdf`'s reflection at `wo_local` goes back into a denser dielectric: a rough
/// dielectric interface seen from its inside (relative IOR above 1 and `wo` below the surface,
/// or below 1 and above it).
#[inline]
pub fn reflects_inward(bsdf: &Bsdf, wo_local: Vec3) -> bool {
    matches!(bsdf, Bsdf::Dielectric(d) if d.eta != 1.0 && (d.eta > 1.0) == (wo_local.z < 0.0))
}

/// What one camera path of an iteration produced besides its visibility points (which
/// [`trace_camera_path`] appends to the caller's list: one list per batch of pixels, kept
/// between iterations).
#[derive(Clone, Copy, Debug)]
pub struct CameraPathResult {
    /// Emission and direct light collected on the way (and indirect light found before the
    /// gather vertex when the gather depth is > 0).
    pub radiance: LayeredRadiance,
    /// How many gather vertices the path reached (at most [`MAX_POINTS_PER_PATH`]).
    pub points: u32,
    /// The path's wavelengths (secondaries terminated by a dispersive interface).
    pub wl: SampledWavelengths,
}

/// The BSDF-sampling half of MIS direct light at a gather vertex whose sampled direction left
/// the continued set C: the one segment is traced and an emitter (or the environment) found there is
/// weighted against light sampling. Emission reached through a specular surface is not counted:
/// photons carry it. The segment lies in `media` (absorbing it attenuates).
#[allow(clippy::too_many_arguments)]
fn direct_by_bsdf_sample(
    scene: &Scene,
    si: &SurfaceInteraction,
    wi: Vec3,
    pdf: f32,
    weight: SampledSpectrum,
    media: &MediumStack,
    wl: &SampledWavelengths,
) -> SampledSpectrum {
    let prev = PrevVertex { p: si.p, pdf };
    let hit = scene.intersect(&si.spawn_ray(wi));
    let weight = match media.transmittance_to(scene, hit.as_ref(), wl) {
        Some(t) => weight * t,
        None => weight,
    };
    match hit {
        Some(hit) => weight * emitted_at_hit(scene, &hit, -wi, &prev, wl),
        None => weight * escaped_radiance(scene, &prev, wi, wl),
    }
}

/// Traces the camera path of one pixel for one iteration. Specular events are followed exactly.
/// At a non-specular vertex before the gather depth, MIS direct light is added and the path
/// continues by BSDF sampling (a sample inside the continued set C does not count as depth). At
/// a gather vertex, direct light over the whole sphere is added (light sampling and the BSDF
/// sample, MIS: the BSDF sample finds the emitter whether it continues the path or not, and
/// photons carry no direct light) and a visibility point gathering photons from C' is left; a
/// BSDF sample inside C continues the path (the integral over C), otherwise its one segment is
/// traced for the emitter hit and the path ends. Without a continued set every gather vertex
/// ends the path (plain `vismap`). Paths are not Russian-rouletted while they leave visibility
/// points; a path that reaches [`MAX_POINTS_PER_PATH`] gather vertices, or more than
/// `max_specular` specular or passed-through ([`VertexTreatment::pass_through`]) events, is
/// continued from there as the path tracer ([`pt::trace`]) so that the light from C there is
/// not lost (docs/architecture.md §7.5: no path is cut by a cap). The visibility points are
/// appended to `points`.
#[inline(always)]
pub fn trace_camera_path<'s>(
    scene: &'s Scene,
    mut ray: Ray,
    mut wl: SampledWavelengths,
    sampler: &mut Sampler,
    rule: &GatherRule,
    points: &mut Vec<VisibilityPoint<'s>>,
) -> CameraPathResult {
    let mut out = LayeredRadiance::default();
    let first_point = points.len();
    let mut beta = SampledSpectrum::one();
    let mut class = PathClass::default();
    let mut prev = PrevVertex::eye(ray.origin);
    let mut footprint_distance = 0.0f32;
    let mut depth = 0u32;
    let mut pass_through_events = 0u32;
    let mut eta_scale = 1.0f32;
    let mut events = 0u32;
    let mut media = MediumStack::default();
    // the last vertex's light sample, its shadow ray traced just before the path's next ray, as in
    // `pt` (docs/architecture.md §7.2)
    let mut pending: Option<PendingLight> = None;
    loop {
        if let Some(l) = pending.take() {
            l.resolve(scene, &mut out);
        }
        let hit = scene.intersect(&ray);
        // the segment inside the innermost medium: absorbed (Beer-Lambert), or scattered at a
        // sampled distance (core::medium); a path that scatters in a medium continues from there
        // as the path tracer (visibility points stay on surfaces: docs/architecture.md §5)
        match media.sample_segment(scene, hit.as_ref().map_or(f32::INFINITY, |h| h.t), &wl, sampler) {
            None => {}
            Some(SegmentEvent::Surface(w)) => beta *= w,
            Some(SegmentEvent::Scatter { t, weight, phase }) => {
                beta *= weight;
                if beta.is_finite() && !beta.is_black() {
                    let v = scatter_in_medium(scene, &ray, t, &phase, &media, &wl, sampler);
                    if let Some(l) = pending.take() {
                        l.resolve(scene, &mut out);
                    }
                    if let Some(l) = v.light {
                        l.for_path(beta, class.scattered(false)).resolve(scene, &mut out);
                    }
                    let class = class.scattered(false);
                    let state = PathState { beta, class, prev: v.prev, eta_scale, depth: events + 1, media };
                    pt::trace(scene, v.next, state, &mut wl, sampler, &PtSettings::default(), &mut out);
                }
                break;
            }
        }
        let Some(si) = hit else {
            out.add(class, beta * escaped_radiance(scene, &prev, ray.dir, &wl));
            break;
        };
        if class.nonspecular == 0 {
            footprint_distance += si.t;
        }
        let wo = -ray.dir;
        out.add(class, beta * emitted_at_hit(scene, &si, wo, &prev, &wl));
        let bsdf = scene.bsdf_at(&si, &mut wl);
        let frame = si.frame();
        let wo_local = frame.to_local(wo);
        let specular = bsdf.is_specular();
        let treatment = (!specular).then(|| rule.treat(scene, &si, &bsdf, wo_local));
        let narrow = treatment.is_some_and(|t| t.pass_through);
        let cone = treatment.and_then(|t| t.cone);
        let gather = !specular && !narrow && depth == rule.depth;
        // a light sample's segment lies in the media the path is in once it leaves towards it
        let light_sample = |sampler: &mut Sampler, wl: &SampledWavelengths| {
            sample_light(scene, &si, &bsdf, wo_local, wl, sampler, |_| false).map(|l| {
                l.through(&media.after(scene, &si, wo, l.shadow.dir), scene, wl).for_path(beta, class.scattered(false))
            })
        };
        if gather {
            pending = light_sample(sampler, &wl);
            points.push(VisibilityPoint {
                p: si.p,
                ng: si.ng,
                frame,
                wo_local,
                bsdf,
                beta,
                class,
                depth,
                footprint_distance,
                cone,
                viewer_above: wo.dot(si.ng) > 0.0,
            });
        } else if !specular {
            pending = light_sample(sampler, &wl);
        }
        if specular || narrow {
            pass_through_events += 1;
        }
        let Some(sc) = scatter(&bsdf, &si, &frame, wo, wo_local, TransportMode::Radiance, sampler) else { break };
        let (bs, wi, weight) = (sc.bs, sc.wi, sc.weight());
        let quasi_specular = !bs.specular && in_cone(&cone, bs.wi);
        if gather && !quasi_specular {
            // the sample left the cone: it estimates the direct light of C' (MIS) and ends the path
            if let Some(l) = pending.take() {
                l.resolve(scene, &mut out);
            }
            let media = media.after(scene, &si, wo, wi);
            out.add(class.scattered(false), beta * direct_by_bsdf_sample(scene, &si, wi, bs.pdf, weight, &media, &wl));
            break;
        }
        beta *= weight;
        if !beta.is_finite() || beta.is_black() {
            break;
        }
        class = class.scattered(bs.specular);
        if !bs.specular && !quasi_specular && !narrow {
            depth += 1;
        }
        if bs.lobe == Lobe::Transmission {
            eta_scale *= bs.eta * bs.eta;
        }
        events += 1;
        // emission found by this sample is MIS-weighted against the vertex's light sample, which
        // covers the whole sphere (inside C too)
        let pdf = if bs.specular { f32::INFINITY } else { bs.pdf };
        prev = PrevVertex { p: si.p, pdf };
        media = media.after(scene, &si, wo, wi);
        ray = si.spawn_ray(wi);
        if points.len() - first_point >= MAX_POINTS_PER_PATH || pass_through_events > rule.max_specular {
            // the rest of the path as the (unbiased) path tracer: full light sampling at every
            // vertex, Russian roulette instead of a cap
            if let Some(l) = pending.take() {
                l.resolve(scene, &mut out);
            }
            let state = PathState { beta, class, prev, eta_scale, depth: events, media };
            pt::trace(scene, ray, state, &mut wl, sampler, &PtSettings::default(), &mut out);
            break;
        }
    }
    if let Some(l) = pending {
        l.resolve(scene, &mut out);
    }
    CameraPathResult { radiance: out, points: (points.len() - first_point) as u32, wl }
}

/// The non-uniformity a pilot path gives the depth at which it leaves the scene: that of a
/// Lambertian vertex, the smallest a surface has, so a diffuse vertex before it (kappa 1, the
/// smaller depth) still wins the tie.
pub const ESCAPED_KAPPA: f32 = 1.0;

/// The gather depth a path of this pixel would choose for itself (docs/architecture.md §7.5): traced by BSDF
/// sampling alone (no light sampling), it returns argmin over depths j of kappa(x_j), the
/// non-uniformity of the first non-specular vertex at depth j (ties: the smaller depth), over at
/// most `max_depth` + 1 depths; None when the path meets no non-specular vertex. A vertex that
/// the rule passes through (a narrow lobe) or, with a cone, whose sample is quasi-specular, is
/// not a candidate (its lobe is traced through), like specular vertices. A path that leaves the
/// scene after a non-specular vertex makes the next depth a candidate of kappa 1
/// ([`ESCAPED_KAPPA`]): a camera path gathering there meets only the environment (emission found
/// by the BSDF sample, MIS-weighted against the light sample, no density estimate), so a glossy
/// vertex whose reflections escape is not chosen to gather on.
pub fn pilot_gather_depth(
    scene: &Scene,
    mut ray: Ray,
    mut wl: SampledWavelengths,
    sampler: &mut Sampler,
    rule: &GatherRule,
    max_depth: u32,
) -> Option<u32> {
    let mut best: Option<(f32, u32)> = None;
    let mut depth = 0u32;
    let mut last_depth_seen = None;
    let mut specular_events = 0u32;
    loop {
        let Some(si) = scene.intersect(&ray) else {
            // left the scene: the next depth meets only the environment
            if last_depth_seen.is_some_and(|d| d < depth)
                && depth <= max_depth
                && best.is_none_or(|(k, _)| ESCAPED_KAPPA < k)
            {
                best = Some((ESCAPED_KAPPA, depth));
            }
            break;
        };
        let bsdf = scene.bsdf_at(&si, &mut wl);
        let frame = si.frame();
        let wo_local = frame.to_local(-ray.dir);
        let specular = bsdf.is_specular();
        if specular {
            specular_events += 1;
            if specular_events > rule.max_specular {
                break;
            }
        }
        let sample = scatter(&bsdf, &si, &frame, -ray.dir, wo_local, TransportMode::Radiance, sampler);
        let treatment = (!specular).then(|| rule.treat(scene, &si, &bsdf, wo_local));
        let narrow = treatment.is_some_and(|t| t.pass_through);
        let cone = treatment.and_then(|t| t.cone);
        let quasi_specular = narrow || sample.is_some_and(|sc| !sc.bs.specular && in_cone(&cone, sc.bs.wi));
        if let Some(t) = treatment
            && !quasi_specular
            && last_depth_seen != Some(depth)
        {
            last_depth_seen = Some(depth);
            let kappa = t.kappa;
            if best.is_none_or(|(k, _)| kappa < k) {
                best = Some((kappa, depth));
            }
            if depth >= max_depth || kappa <= 1.0 {
                break; // nothing deeper can be more uniform than a Lambertian vertex
            }
        }
        let Some(sc) = sample else { break };
        if !sc.bs.specular && !quasi_specular {
            depth += 1;
        }
        ray = si.spawn_ray(sc.wi);
    }
    best.map(|(_, d)| d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_materials::bsdf::dielectric::DielectricBsdf;
    use quasar_materials::bsdf::microfacet::TrowbridgeReitz;

    #[test]
    fn only_a_reflection_back_into_the_denser_side_reflects_inward() {
        let glass = Bsdf::Dielectric(DielectricBsdf::new(1.5, TrowbridgeReitz::new(0.1)));
        let (above, below) = (Vec3::new(0.3, 0.0, 0.95).normalize(), Vec3::new(0.3, 0.0, -0.95).normalize());
        assert!(reflects_inward(&glass, below), "inside a glass whose normal points out");
        assert!(!reflects_inward(&glass, above));
        // a surface whose normal points into the glass (relative IOR below 1)
        let flipped = Bsdf::Dielectric(DielectricBsdf::new(1.0 / 1.5, TrowbridgeReitz::new(0.1)));
        assert!(reflects_inward(&flipped, above) && !reflects_inward(&flipped, below));
        // index-matched (a pass-through) surfaces never do
        let matched = Bsdf::Dielectric(DielectricBsdf::new(1.0, TrowbridgeReitz::new(0.1)));
        assert!(!reflects_inward(&matched, below) && !reflects_inward(&matched, above));
    }

    #[test]
    fn the_rough_bottom_of_a_plate_seen_from_inside_gathers_its_reflection() {
        // the alpha 0.1 bottom of the benchmark plate, hit from inside the glass: both of its
        // lobes are narrow there (it was passed through whole), but its reflection goes back
        // into the glass, so it is gathered and only the refraction's hemisphere is continued
        let (_, scene) = crate::integrator::bidir::shipped_scene("bench/plate-rough-bottom-0.1.toml");
        let dir = Vec3::new(0.3, -1.0, 0.1).normalize();
        let si = scene.intersect(&Ray::new(Vec3::new(0.0, 0.011, 0.0), dir)).expect("the plate's bottom");
        assert!((si.p.y - 0.001).abs() < 1e-4, "hit at {:?}", si.p);
        let mut wl = SampledWavelengths::sample_visible(0.5);
        let bsdf = scene.bsdf_at(&si, &mut wl);
        let wo_local = si.frame().to_local(-dir);
        let (reflection, transmission) = scene.non_uniformity()[si.material as usize].lobes_at(wo_local.z);
        assert!(reflection > NARROW_KAPPA && transmission > NARROW_KAPPA, "R {reflection} T {transmission}");
        let rule =
            GatherRule { depth: 0, cone_cos: Some(10f32.to_radians().cos()), max_specular: 16, pass_narrow: false };
        let t = rule.treat(&scene, &si, &bsdf, wo_local);
        assert!(!t.pass_through && t.cone.is_some());
        assert_eq!(t.kappa, reflection, "the gathered lobe is the reflection");
    }
}
