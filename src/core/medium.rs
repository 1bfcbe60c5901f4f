//! Homogeneous media inside transmitting surfaces (docs/architecture.md §5): a material may have
//! an interior absorption coefficient sigma_a(lambda) and scattering coefficient sigma_s(lambda)
//! (1/m) with a Henyey-Greenstein phase function. A path segment inside it is attenuated by
//! Beer-Lambert, T = exp(-sigma_t t) with sigma_t = sigma_a + sigma_s, and where the medium
//! scatters the path samples where along the segment it scatters ([`MediumStack::sample_segment`]).
//! Which medium a segment lies in is tracked per path by a [`MediumStack`] of the media it has
//! entered and not left (`core::media`): crossing a surface from the side its geometric normal
//! points to (outside) pushes the medium inside its material, crossing it from the back pops
//! that medium, and a reflection changes nothing. So a glass inside water is water again once
//! the path leaves the glass, with no priority to declare (the rule of Cycles' volume stack), as
//! long as surfaces do not overlap; paths start outside every medium (a camera inside a medium
//! is not modelled).

use glam::Vec3;
use quasar_materials::HenyeyGreenstein;
use quasar_materials::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};

use super::interaction::SurfaceInteraction;
use super::sampling::Sampler;
use super::scene::Scene;

/// Most scattering events in media on one path: a path that scatters more often ends there.
/// Without a cap a dense medium of albedo 1 (sigma_s of 1e6/m in a centimetre: 10^4 mean free
/// paths, about 10^8 events to leave by a random walk) would hang a render; with it, the light
/// of paths longer than this is lost (a bias only in such media, stated in docs/architecture.md
/// §5).
pub const MAX_MEDIUM_SCATTERS: u32 = 4096;

/// What happens along a ray's segment inside a medium ([`MediumStack::sample_segment`]).
#[derive(Clone, Copy, Debug)]
pub enum SegmentEvent {
    /// The ray reaches the segment's end (the surface it hit, or infinity); the path's
    /// throughput is multiplied by `weight`.
    Surface(SampledSpectrum),
    /// The ray scatters at distance `t`; the throughput is multiplied by `weight` and the path
    /// continues by the phase function `phase`.
    Scatter {
        /// Distance along the ray (m).
        t: f32,
        /// sigma_s T(t) / pdf(t) per wavelength.
        weight: SampledSpectrum,
        /// The medium's phase function.
        phase: HenyeyGreenstein,
    },
}

/// Nesting depth tracked: a fifth medium entered inside four others is not tracked (its
/// segments take the fourth's medium).
pub const MAX_NESTED_MEDIA: usize = 4;

/// The media a path is inside, innermost last (medium ids of [`super::media::MediaTable`]; a
/// clear transmitting material's is [`CLEAR`](super::media::CLEAR)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumStack {
    ids: [u32; MAX_NESTED_MEDIA],
    len: u8,
}

impl MediumStack {
    /// The innermost medium the path is inside, if any ([`CLEAR`](super::media::CLEAR) inside a clear material).
    #[inline]
    pub fn innermost(&self) -> Option<u32> {
        self.len.checked_sub(1).map(|i| self.ids[i as usize])
    }

    /// The stack after the path leaves `si` towards `wi`, having arrived from `wo` (both pointing
    /// away from the surface): unchanged by a reflection (both on one side of the geometric
    /// normal) and in a scene without media; entering (from the normal's side) pushes
    /// the medium inside the surface's material, leaving pops the innermost entry of that medium
    /// (so the faces of one body may have different materials, as long as their media are equal).
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
        let medium = scene.medium_of(si.material);
        if from_outside {
            if (s.len as usize) < MAX_NESTED_MEDIA {
                s.ids[s.len as usize] = medium;
                s.len += 1;
            }
        } else if let Some(i) = s.ids[..s.len as usize].iter().rposition(|&m| m == medium) {
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

    /// Beer-Lambert transmittance exp(-sigma_t t) over a segment of length `t` (m) inside the
    /// innermost medium, at wavelengths `wl` (the light that crosses it unscattered); None where
    /// the segment lies in no medium.
    #[inline(always)]
    pub fn transmittance(&self, scene: &Scene, t: f32, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        Some(beer_lambert(scene.medium(self.innermost()?)?.sigma_t(wl), t))
    }

    /// Where along a ray's segment of length `t_end` (m; infinite for a ray that escapes) the
    /// path's next event lies: in a medium that only absorbs, the segment's end with weight T
    /// (no random number is used); in a scattering one, a distance t drawn from the mixture
    /// over the path's wavelengths of the densities sigma_t exp(-sigma_t t) (one-sample MIS over
    /// wavelengths, so that no wavelength's weight is unbounded; pbrt-v4 §14.1 reaches the same
    /// end with the hero wavelength's density and spectral MIS ratios): a scattering event at t < t_end with weight
    /// sigma_s T(t) / mean(sigma_t T(t)), or the end with weight T(t_end) / mean(T(t_end)).
    /// None where the segment lies in no medium.
    #[inline(always)]
    pub fn sample_segment(
        &self,
        scene: &Scene,
        t_end: f32,
        wl: &SampledWavelengths,
        sampler: &mut Sampler,
    ) -> Option<SegmentEvent> {
        let medium = scene.medium(self.innermost()?)?;
        let sigma_t = medium.sigma_t(wl);
        let Some(scattering) = medium.scattering() else {
            return Some(SegmentEvent::Surface(beer_lambert(sigma_t, t_end)));
        };
        // after a dispersive interface only the hero wavelength carries light
        let lanes = if wl.secondary_terminated() { 1 } else { N_SPECTRUM_SAMPLES };
        let (u_lane, u) = (sampler.get_1d(), sampler.get_1d());
        let lane = ((u_lane * lanes as f32) as usize).min(lanes - 1);
        let s = sigma_t.0[lane];
        let t = if s > 0.0 { -(1.0 - u).max(f32::MIN_POSITIVE).ln() / s } else { f32::INFINITY };
        let mean = |v: SampledSpectrum| v.0[..lanes].iter().sum::<f32>() / lanes as f32;
        if t < t_end {
            let tr = beer_lambert(sigma_t, t);
            let pdf = mean(sigma_t * tr);
            if pdf.is_nan() || pdf <= 0.0 {
                return Some(SegmentEvent::Surface(SampledSpectrum::zero()));
            }
            let weight = scattering.sigma_s(wl) * tr / pdf;
            Some(SegmentEvent::Scatter { t, weight, phase: scattering.phase() })
        } else {
            let tr = beer_lambert(sigma_t, t_end);
            let p = mean(tr);
            Some(SegmentEvent::Surface(if p > 0.0 { tr / p } else { SampledSpectrum::zero() }))
        }
    }
}

/// exp(-sigma t) per wavelength; 1 where sigma is 0 (also over an infinite length), 0 where
/// sigma > 0 over an infinite length.
#[inline(always)]
fn beer_lambert(sigma: SampledSpectrum, t: f32) -> SampledSpectrum {
    SampledSpectrum(std::array::from_fn(|i| if sigma.0[i] > 0.0 { (-sigma.0[i] * t).exp() } else { 1.0 }))
}
