//! A photon arriving inside a visibility point's gather disk, and what the point does with it
//! (docs/architecture.md §7.4): the point's own tests ([`admits`]: the viewer's side of the
//! surface, the quasi-specular cone, the geometric cosine), then either its value f * flux as a
//! deposit of an iteration ([`Deposits`]) or one more photon in the radius pilot's count
//! ([`PhotonCounts`], which tests points without a cone from one byte per point).

use std::sync::atomic::{AtomicU32, Ordering};

use quasar_materials::TransportMode;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

use super::quasi_cone::in_cone;
use super::visibility_point::VisibilityPoint;
use crate::core::prefetch::{prefetch, prefetch_all};

/// A photon arriving inside a visibility point's gather disk (its distance, normal and plane
/// tests passed), before the point's own tests.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Arrival {
    /// All bounces so far specular or quasi-specular.
    pub(super) caustic: bool,
    /// All bounces so far specular.
    pub(super) specular_only: bool,
    /// The photon's secondary wavelengths were terminated.
    pub(super) hero_only: bool,
    /// The photon arrived on the side the hit surface's winding normal points to.
    pub(super) above: bool,
    /// Towards where the photon came from.
    pub(super) wi: glam::Vec3,
    /// |wi . ng| on the surface the photon landed on: the cosine of the flux density that the
    /// photons within a disk measure.
    pub(super) cos_hit: f32,
    /// The photon's flux.
    pub(super) beta: SampledSpectrum,
}

/// The point's own tests of an arrival: the direction in the point's shading frame and
/// |wi . ng|, or None when the point does not gather the photon.
#[inline(always)]
pub(super) fn admits(vp: &VisibilityPoint, a: &Arrival) -> Option<(glam::Vec3, f32)> {
    // a reflector only sees photons that arrived on its viewer's side of the surface the photon
    // hit (no light through a wall from inside a closed object)
    if !vp.bsdf.has_transmission() && a.above != vp.viewer_above {
        return None;
    }
    // the photon density measures irradiance on the geometric surface the photons landed on;
    // the BSDF integrates against the point's shading cosine: |wi . ns| / |wi . ng_hit| (Veach
    // 1997, 5.3). The landing surface's normal, not the point's: on a curved mesh a photon
    // grazing its own facet can arrive parallel to the point's facet, and 1 / |wi . ng_point|
    // would have an infinite variance (a pixel 15x too bright after a thousand iterations)
    let wi_local = vp.frame.to_local(a.wi);
    if in_cone(&vp.cone, wi_local) {
        return None; // the path continued through the cone estimates this light
    }
    if a.cos_hit <= 0.0 || a.cos_hit.is_nan() {
        return None;
    }
    Some((wi_local, a.cos_hit))
}

/// Receives the arrivals of one photon's path.
pub(super) trait Gatherer {
    /// The photon arrived inside the gather disk of point `vi`.
    fn arrive(&mut self, vi: u32, a: &Arrival);

    /// Starts loading what [`arrive`](Self::arrive) will read of point `vi` (a hint, see
    /// `core::prefetch`).
    fn prefetch(&self, vi: u32);
}

/// A chunk's deposits, in photon order (an iteration's photon pass).
pub(super) struct Deposits<'a, 'p> {
    /// The chunk's list.
    pub(super) list: &'a mut Vec<Deposit>,
    /// The iteration's visibility points.
    pub(super) points: &'a [VisibilityPoint<'p>],
    /// The wavelengths of each point's camera path.
    pub(super) point_wl: &'a [SampledWavelengths],
}

impl Gatherer for Deposits<'_, '_> {
    #[inline(always)]
    fn arrive(&mut self, vi: u32, a: &Arrival) {
        let vp = &self.points[vi as usize];
        let Some((wi_local, cos_g)) = admits(vp, a) else { return };
        let f = vp.bsdf.f(vp.wo_local, wi_local, TransportMode::Radiance);
        let mut value = f * a.beta * (wi_local.z.abs() / cos_g);
        // a dispersive event on either subpath makes the whole path hero-only: the visibility
        // point's wavelengths carry the hero's 1/N pdf once
        let (vp_term, ph_term) = (self.point_wl[vi as usize].secondary_terminated(), a.hero_only);
        if vp_term || ph_term {
            for k in 1..4 {
                value[k] = 0.0;
            }
            if ph_term && !vp_term {
                value[0] *= 4.0;
            }
        }
        if value.is_finite() {
            self.list.push(Deposit { point: vi, caustic: a.caustic, specular_only: a.specular_only, value });
        }
    }

    #[inline]
    fn prefetch(&self, vi: u32) {
        prefetch_all(&self.points[vi as usize]);
        prefetch_all(&self.point_wl[vi as usize]);
    }
}

/// What [`admits`] reads of a point without a quasi-specular cone, in one byte per point: the
/// counting pass tests most arrivals without reading the point (bits [`GATHERS_BOTH_SIDES`],
/// [`VIEWER_ABOVE`], [`HAS_CONE`]).
pub(super) type PointSides = u8;
/// The point's BSDF transmits: it gathers photons from both sides.
pub(super) const GATHERS_BOTH_SIDES: PointSides = 1;
/// The point's viewer is on the side its normal points to.
pub(super) const VIEWER_ABOVE: PointSides = 2;
/// The point has a quasi-specular cone: its arrivals need the point itself.
pub(super) const HAS_CONE: PointSides = 4;

/// The [`PointSides`] of `vp`.
pub(super) fn point_sides(vp: &VisibilityPoint) -> PointSides {
    (vp.bsdf.has_transmission() as u8 * GATHERS_BOTH_SIDES)
        | (vp.viewer_above as u8 * VIEWER_ABOVE)
        | (vp.cone.is_some() as u8 * HAS_CONE)
}

/// Photons accepted per point, shared by every thread (the radius pilot's photon pass: integer
/// sums do not depend on the order of the additions).
pub(super) struct PhotonCounts<'a, 'p> {
    /// Per point.
    pub(super) counts: &'a [AtomicU32],
    /// The pilot's visibility points (read for those with a cone).
    pub(super) points: &'a [VisibilityPoint<'p>],
    /// Per point, [`point_sides`].
    pub(super) sides: &'a [PointSides],
}

impl Gatherer for PhotonCounts<'_, '_> {
    #[inline]
    fn arrive(&mut self, vi: u32, a: &Arrival) {
        let sides = self.sides[vi as usize];
        // without a cone, `admits` is the side test and the arrival's |wi . ng_hit| > 0
        let admitted = if sides & HAS_CONE == 0 {
            (sides & GATHERS_BOTH_SIDES != 0 || a.above == (sides & VIEWER_ABOVE != 0)) && a.cos_hit > 0.0
        } else {
            admits(&self.points[vi as usize], a).is_some()
        };
        if admitted {
            self.counts[vi as usize].fetch_add(1, Ordering::Relaxed);
        }
    }

    #[inline]
    fn prefetch(&self, vi: u32) {
        prefetch(&self.sides[vi as usize]);
        prefetch(&self.counts[vi as usize]);
    }
}

/// One photon's contribution to one visibility point.
#[derive(Clone, Copy, Debug)]
pub(super) struct Deposit {
    /// The point's index.
    pub(super) point: u32,
    /// The photon's class: [`Arrival::caustic`].
    pub(super) caustic: bool,
    /// [`Arrival::specular_only`].
    pub(super) specular_only: bool,
    /// f * flux at the point's wavelengths.
    pub(super) value: SampledSpectrum,
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::core::sampling::{Sampler, uniform_sphere};
    use crate::integrator::bidir::gather_disk::tests::normals;
    use crate::integrator::bidir::quasi_cone::QuasiCone;

    #[test]
    fn the_counts_test_from_a_points_sides_admits_what_the_point_admits() {
        // points of every kind (reflector or transmitter, viewer on either side, with or without
        // a cone) and arrivals from both sides, some perpendicular to the normal: the counting
        // pass's test from the one-byte sides agrees with `admits` on the point itself
        use quasar_materials::spectrum::Spectrum;
        use quasar_materials::{Frame, Ior, Material};
        let mut wl = SampledWavelengths::sample_uniform(0.5);
        let glass = Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.05, transmittance: None }.bsdf(&mut wl);
        let white = Material::Diffuse { reflectance: Spectrum::Constant(0.5), two_sided: true }.bsdf(&mut wl);
        let mut s = Sampler::new(11, 0, 0);
        let points: Vec<VisibilityPoint> = normals(&mut s)
            .into_iter()
            .enumerate()
            .map(|(k, ng)| {
                let bsdf = if k % 2 == 0 { glass } else { white };
                let wo_local = Vec3::new(0.3, 0.1, 0.9).normalize();
                VisibilityPoint {
                    p: Vec3::ZERO,
                    ng,
                    frame: Frame::from_z(ng),
                    wo_local,
                    bsdf,
                    beta: SampledSpectrum::one(),
                    class: crate::film::PathClass::default(),
                    depth: 0,
                    footprint_distance: 1.0,
                    cone: if k % 3 == 0 { QuasiCone::at(&bsdf, wo_local, 0.9) } else { None },
                    viewer_above: k % 4 < 2,
                }
            })
            .collect();
        let sides: Vec<PointSides> = points.iter().map(point_sides).collect();
        let counts: Vec<AtomicU32> = points.iter().map(|_| AtomicU32::new(0)).collect();
        let mut gatherer = PhotonCounts { counts: &counts, points: &points, sides: &sides };
        let mut expected = vec![0u32; points.len()];
        let n_arrivals = 40 * points.len();
        for j in 0..n_arrivals {
            let vi = j % points.len();
            let ng = points[vi].ng;
            let wi = if j % 7 == 0 { ng.any_orthonormal_vector() } else { uniform_sphere(s.get_2d()) };
            let above = s.get_1d() < 0.5;
            let a = Arrival {
                caustic: false,
                specular_only: false,
                hero_only: false,
                above,
                wi,
                cos_hit: wi.dot(ng).abs(),
                beta: SampledSpectrum::one(),
            };
            expected[vi] += admits(&points[vi], &a).is_some() as u32;
            gatherer.arrive(vi as u32, &a);
        }
        let counted: Vec<u32> = counts.into_iter().map(AtomicU32::into_inner).collect();
        assert_eq!(counted, expected);
        // both of the counting pass's branches ran, and both outcomes occurred
        assert!(points.iter().any(|vp| vp.cone.is_some()) && points.iter().any(|vp| vp.cone.is_none()));
        let admitted: u32 = expected.iter().sum();
        assert!(admitted > n_arrivals as u32 / 5 && admitted < n_arrivals as u32 * 4 / 5, "{admitted} of {n_arrivals}");
    }

    #[test]
    fn a_photon_is_weighed_by_its_cosine_on_the_surface_it_landed_on() {
        // a point on a curved mesh: geometric normal z, shading normal tilted by 5 degrees. A
        // photon that landed on a neighbouring facet at 0.2 from its normal can travel parallel
        // to the point's facet; its deposit is f beta |wi . ns| / 0.2, not divided by its
        // cosine on the point's facet (1e-7 here: a deposit ten million times too large)
        use quasar_materials::spectrum::Spectrum;
        use quasar_materials::{Frame, Material};
        let mut wl = SampledWavelengths::sample_uniform(0.5);
        let white = Material::Diffuse { reflectance: Spectrum::Constant(0.5), two_sided: false }.bsdf(&mut wl);
        let tilt = 5f32.to_radians();
        let ns = Vec3::new(tilt.sin(), 0.0, tilt.cos());
        let vp = VisibilityPoint {
            p: Vec3::ZERO,
            ng: Vec3::Z,
            frame: Frame::from_z(ns),
            wo_local: Vec3::Z,
            bsdf: white,
            beta: SampledSpectrum::one(),
            class: crate::film::PathClass::default(),
            depth: 0,
            footprint_distance: 1.0,
            cone: None,
            viewer_above: true,
        };
        let wi = Vec3::new(1.0, 0.0, 1e-7).normalize();
        let a = Arrival { above: true, wi, cos_hit: 0.2, beta: SampledSpectrum::one(), ..Arrival::default() };
        let (points, point_wl) = ([vp], [wl]);
        let mut list = Vec::new();
        Deposits { list: &mut list, points: &points, point_wl: &point_wl }.arrive(0, &a);
        assert_eq!(list.len(), 1);
        let expected = 0.5 / std::f32::consts::PI * wi.dot(ns) / 0.2;
        assert!((list[0].value[0] / expected - 1.0).abs() < 1e-4, "{} vs {expected}", list[0].value[0]);
        // a photon parallel to the surface it landed on is not gathered
        let grazing = Arrival { cos_hit: 0.0, ..a };
        Deposits { list: &mut list, points: &points, point_wl: &point_wl }.arrive(0, &grazing);
        assert_eq!(list.len(), 1);
    }
}
