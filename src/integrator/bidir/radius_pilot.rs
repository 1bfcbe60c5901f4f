//! The radius pilot of the bidirectional methods: an iteration before the first, not part of
//! the image, whose photon counts set the per-pixel scale of the automatic gather radius
//! (docs/architecture.md §7.4).

use super::iteration::{Iteration, IterationResult};
use super::photon_pass::PhotonRecord;
use super::settings::VismapSettings;
use super::visibility_point::{GatherRule, VisibilityPoint};
use crate::core::camera::Camera;
use crate::core::scene::Scene;

/// Photons a gather disk should hold in an iteration: the automatic radius is shrunk (never
/// grown) until the pilot pass's photon density puts this many photons in it.
pub const RADIUS_PILOT_PHOTONS: f32 = 8.0;
/// The automatic radius is not shrunk below this share of its pixel-footprint default.
pub const MIN_RADIUS_SCALE: f32 = 0.1;

/// The per-pixel scale of the automatic gather radius, from a pilot iteration (number 0, not
/// part of the image) at the default radius: where its photon count M exceeds
/// [`RADIUS_PILOT_PHOTONS`] the radius is scaled by sqrt(RADIUS_PILOT_PHOTONS / M), so that
/// a disk holds about that many photons; dim pixels keep the default (scale 1). The
/// photon-mapping bias grows with the radius squared, so many photons per iteration buy a
/// small radius instead of a needlessly precise blur. Every shard computes the same pilot.
/// `it` is the pilot iteration (k = 0): its photon pass only counts ([`PhotonRecord::Counts`]),
/// and it runs in the render's own lists `r`, which the first iteration then refills instead
/// of growing a second set.
pub fn radius_pilot<'s>(
    scene: &'s Scene,
    camera: &Camera,
    settings: &VismapSettings,
    base_rule: &GatherRule,
    depths: &[Option<u32>],
    it: Iteration,
    r: &mut IterationResult<'s>,
) -> Vec<f32> {
    if settings.radius.is_some() {
        return vec![1.0; depths.len()];
    }
    debug_assert!(it.k == 0 && it.record == PhotonRecord::Counts);
    let pixel_angle = camera.pixel_solid_angle().sqrt();
    let radius_of = |_: usize, vp: &VisibilityPoint| settings.radius_pixels * pixel_angle * vp.footprint_distance;
    it.run(scene, camera, settings, base_rule, depths, radius_of, r);
    // photons per fully covered disk
    let mut count = vec![(0.0f32, 0u32); depths.len()];
    for (j, &i) in r.owners.iter().enumerate() {
        count[i].0 += r.photons.sums[j].photons as f32 / r.coverage[j].indirect;
        count[i].1 += 1;
    }
    count
        .iter()
        .map(|&(m, n)| {
            let m = m / n.max(1) as f32;
            if m > RADIUS_PILOT_PHOTONS { (RADIUS_PILOT_PHOTONS / m).sqrt().max(MIN_RADIUS_SCALE) } else { 1.0 }
        })
        .collect()
}
