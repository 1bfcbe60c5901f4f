//! The split of a path's radiance into the film's layers (docs/architecture.md §6): emission (lights
//! seen directly or through specular chains, L^V), direct (one non-specular event, L^D) and
//! indirect (L^I), with the caustic part of indirect (L S+ D S* E paths) also kept on its own.

use quasar_materials::spectrum::SampledSpectrum;

/// Radiance of one camera path (or one pixel sample of a bidirectional method) split into layers.
/// `caustic` is a subset of `indirect`, not an extra term: beauty = emission + direct + indirect.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LayeredRadiance {
    /// Lights seen directly or through specular chains (L^V).
    pub emission: SampledSpectrum,
    /// Light after exactly one non-specular scattering event with no specular event between
    /// it and the light (L^D).
    pub direct: SampledSpectrum,
    /// Everything else (L^I), caustics included.
    pub indirect: SampledSpectrum,
    /// The part of `indirect` that reached the one non-specular vertex of the path through
    /// specular events only (light -> specular+ -> diffuse -> specular* -> eye).
    pub caustic: SampledSpectrum,
}

/// Where a light contribution belongs, from the path's history between the eye and the light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PathClass {
    /// Non-specular scattering events so far.
    pub nonspecular: u32,
    /// A specular event happened after the last non-specular one.
    pub specular_since: bool,
}

impl PathClass {
    /// The class after one more scattering event.
    #[inline]
    pub fn scattered(self, specular: bool) -> Self {
        if specular {
            Self { specular_since: true, ..self }
        } else {
            Self { nonspecular: self.nonspecular + 1, specular_since: false }
        }
    }
}

impl LayeredRadiance {
    /// The layers in the order of [`super::LAYER_NAMES`] (an array of `N_LAYERS`: a layer name
    /// without its field here does not compile).
    #[inline(always)]
    pub fn layers(&self) -> [SampledSpectrum; super::N_LAYERS] {
        [self.emission, self.direct, self.indirect, self.caustic]
    }

    /// Adds emission `l` reached by a path of class `c` (the light is the next vertex).
    #[inline]
    pub fn add(&mut self, c: PathClass, l: SampledSpectrum) {
        match (c.nonspecular, c.specular_since) {
            (0, _) => self.emission += l,
            (1, false) => self.direct += l,
            (1, true) => {
                self.indirect += l;
                self.caustic += l;
            }
            _ => self.indirect += l,
        }
    }

    /// Adds indirect light `l`; `caustic` marks it as part of the caustic layer too.
    #[inline]
    pub fn add_indirect(&mut self, l: SampledSpectrum, caustic: bool) {
        self.indirect += l;
        if caustic {
            self.caustic += l;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_classified_by_their_scattering_events() {
        let one = SampledSpectrum::one();
        let eye = PathClass::default();
        let mut l = LayeredRadiance::default();
        l.add(eye, one); // light seen directly
        l.add(eye.scattered(true), one); // through a mirror
        assert_eq!(l.emission, one * 2.0);
        let d = eye.scattered(false);
        l.add(d, one); // diffuse, then the light
        assert_eq!(l.direct, one);
        l.add(d.scattered(true), one); // diffuse, mirror, light: a caustic
        assert_eq!(l.caustic, one);
        l.add(d.scattered(false), one); // two diffuse events
        assert_eq!(l.indirect, one * 2.0);
        assert_eq!(l.caustic, one);
        // a specular event before the diffuse one does not make a caustic
        l.add(eye.scattered(true).scattered(false), one);
        assert_eq!(l.direct, one * 2.0);
    }
}
