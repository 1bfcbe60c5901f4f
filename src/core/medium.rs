//! Absorbing media inside transmitting surfaces (docs/architecture.md §5): a material may have
//! an interior absorption coefficient sigma_a(lambda) (1/m), and a path segment inside it is
//! attenuated by Beer-Lambert, T = exp(-sigma_a t). Which medium a segment lies in is tracked per
//! path by a [`MediumStack`] of the transmitting surfaces it has entered and not left: crossing a
//! surface from the side its geometric normal points to (outside) pushes its material, crossing
//! it from the back pops it, and a reflection changes nothing. So a glass inside water is water
//! again once the path leaves the glass, with no priority to declare (the rule of Cycles' volume
//! stack), as long as surfaces do not overlap; paths start outside every medium (a camera inside
//! a medium is not modelled).

use glam::Vec3;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

use super::interaction::SurfaceInteraction;
use super::scene::Scene;

/// Nesting depth tracked: a fifth medium entered inside four others is not tracked (its
/// segments take the fourth's absorption).
pub const MAX_NESTED_MEDIA: usize = 4;

/// The transmitting surfaces a path is inside, innermost last (material indices).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumStack {
    ids: [u32; MAX_NESTED_MEDIA],
    len: u8,
}

impl MediumStack {
    /// The innermost material the path is inside, if any.
    #[inline]
    pub fn innermost(&self) -> Option<u32> {
        self.len.checked_sub(1).map(|i| self.ids[i as usize])
    }

    /// The stack after the path leaves `si` towards `wi`, having arrived from `wo` (both pointing
    /// away from the surface): unchanged by a reflection (both on one side of the geometric
    /// normal) and in a scene without absorbing media; entering (from the normal's side) pushes
    /// the surface's material, leaving pops its innermost entry.
    #[inline(always)]
    pub fn after(self, scene: &Scene, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Self {
        if !scene.has_media() {
            return self;
        }
        let (from_outside, to_outside) = (wo.dot(si.ng) > 0.0, wi.dot(si.ng) > 0.0);
        if from_outside == to_outside {
            return self;
        }
        let mut s = self;
        if from_outside {
            if (s.len as usize) < MAX_NESTED_MEDIA {
                s.ids[s.len as usize] = si.material;
                s.len += 1;
            }
        } else if let Some(i) = s.ids[..s.len as usize].iter().rposition(|&m| m == si.material) {
            s.ids.copy_within(i + 1..s.len as usize, i);
            s.len -= 1;
        }
        s
    }

    /// [`transmittance`](Self::transmittance) of a ray's segment to `hit`, infinite when the
    /// ray escapes (0 then in an absorbing medium).
    #[inline(always)]
    pub fn transmittance_to(
        &self,
        scene: &Scene,
        hit: Option<&SurfaceInteraction>,
        wl: &SampledWavelengths,
    ) -> Option<SampledSpectrum> {
        self.transmittance(scene, hit.map_or(f32::INFINITY, |h| h.t), wl)
    }

    /// Beer-Lambert transmittance exp(-sigma_a t) over a segment of length `t` (m) inside the
    /// innermost medium, at wavelengths `wl`; None where the segment does not attenuate (no
    /// medium, or one without absorption).
    #[inline(always)]
    pub fn transmittance(&self, scene: &Scene, t: f32, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        let s = scene.absorption(self.innermost()?)?.sigma_a(wl);
        Some(SampledSpectrum(std::array::from_fn(|i| if s.0[i] > 0.0 { (-s.0[i] * t).exp() } else { 1.0 })))
    }
}
