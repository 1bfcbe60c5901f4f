//! The media of a scene (docs/architecture.md §5): the distinct media inside its transmitting
//! materials, and which one each material bounds. Materials whose interiors are equal (the same
//! absorption and scattering) share one medium, so the faces of one body may carry different
//! finishes (a light guide's polished sides and frosted front) and still bound one medium: a
//! path's [`super::medium::MediumStack`] holds media, not materials.

use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use quasar_materials::{Absorption, Scattering};

/// The medium id of a clear material (no absorption, no scattering).
pub const CLEAR: u32 = u32::MAX;

/// A homogeneous medium, its spectra pre-sampled for rendering.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    absorption: Option<Absorption>,
    scattering: Option<Scattering>,
}

impl Medium {
    /// The extinction sigma_t = sigma_a + sigma_s at `wl` (1/m).
    #[inline]
    pub fn sigma_t(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        let a = self.absorption.as_ref().map_or(SampledSpectrum::zero(), |a| a.sigma_a(wl));
        match &self.scattering {
            Some(s) => a + s.sigma_s(wl),
            None => a,
        }
    }

    /// The scattering, None for a medium that only absorbs.
    #[inline]
    pub fn scattering(&self) -> Option<&Scattering> {
        self.scattering.as_ref()
    }
}

/// The distinct media of a scene and the medium inside each material.
#[derive(Clone, Debug, Default)]
pub struct MediaTable {
    media: Vec<Medium>,
    of_material: Vec<u32>,
}

impl MediaTable {
    /// The media inside `materials`, equal interiors merged into one.
    pub fn new(materials: &[quasar_importers::MaterialDesc]) -> Self {
        let mut keys: Vec<(&Option<Absorption>, &Option<Scattering>)> = Vec::new();
        let mut media = Vec::new();
        let of_material = materials
            .iter()
            .map(|m| {
                if m.absorption.is_none() && m.scattering.is_none() {
                    return CLEAR;
                }
                let key = (&m.absorption, &m.scattering);
                match keys.iter().position(|k| *k == key) {
                    Some(i) => i as u32,
                    None => {
                        keys.push(key);
                        media.push(Medium {
                            absorption: m.absorption.as_ref().map(Absorption::densified),
                            scattering: m.scattering.as_ref().map(Scattering::densified),
                        });
                        (media.len() - 1) as u32
                    }
                }
            })
            .collect();
        Self { media, of_material }
    }

    /// Whether the scene has no medium at all.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.media.is_empty()
    }

    /// The id of the medium inside material `m` ([`CLEAR`] for a clear one).
    #[inline(always)]
    pub fn medium_of(&self, m: u32) -> u32 {
        self.of_material.get(m as usize).copied().unwrap_or(CLEAR)
    }

    /// The medium of id `id`; None for [`CLEAR`].
    #[inline(always)]
    pub fn get(&self, id: u32) -> Option<&Medium> {
        self.media.get(id as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_importers::MaterialDesc;
    use quasar_materials::spectrum::Spectrum;
    use quasar_materials::{Ior, Material};

    fn glass(sigma_a: Option<f32>, finish: f32) -> MaterialDesc {
        MaterialDesc {
            name: format!("glass {sigma_a:?} {finish}"),
            material: Material::Dielectric { ior: Ior::Constant(1.5), alpha: finish, transmittance: None },
            absorption: sigma_a.map(|s| Absorption::Coefficient(Spectrum::Constant(s))),
            scattering: None,
            textures: Default::default(),
            source: Default::default(),
        }
    }

    /// Two finishes of one absorbing glass share a medium; another coefficient is another
    /// medium; a clear glass has none.
    #[test]
    fn equal_interiors_share_a_medium() {
        let t =
            MediaTable::new(&[glass(Some(2.0), 0.0), glass(None, 0.0), glass(Some(2.0), 0.3), glass(Some(3.0), 0.0)]);
        assert_eq!((t.medium_of(0), t.medium_of(1), t.medium_of(2), t.medium_of(3)), (0, CLEAR, 0, 1));
        assert!(t.get(CLEAR).is_none() && t.get(1).is_some() && !t.is_empty());
        assert!(MediaTable::new(&[glass(None, 0.0)]).is_empty());
    }
}
