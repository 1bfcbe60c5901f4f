//! Materials: plain data (spectral parameters) that produce a [`Bsdf`] at a path's wavelengths.
//! (Stub: the BSDF helper replaces the bodies; the public API below is fixed.)

use crate::bsdf::Bsdf;
use crate::spectrum::{SampledWavelengths, Spectrum};

/// Fresnel reflectance model of a conductor.
#[derive(Clone, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Angle-independent reflectance (spectrum in [0, 1]).
    Constant(Spectrum),
    /// Spectral complex index of refraction eta + i k (relative to the outside medium).
    Complex {
        /// Real part.
        eta: Spectrum,
        /// Imaginary part (absorption).
        k: Spectrum,
    },
}

/// Index of refraction of a dielectric as a function of wavelength.
#[derive(Clone, Debug, PartialEq)]
pub enum Ior {
    /// Same IOR at every wavelength (no dispersion).
    Constant(f32),
    /// Cauchy: n(lambda) = a + b / lambda^2, lambda in micrometres, b in um^2.
    Cauchy {
        /// Constant term.
        a: f32,
        /// Coefficient of 1/lambda^2 (um^2).
        b: f32,
    },
    /// Sellmeier: n^2 = 1 + sum_i B_i lambda^2 / (lambda^2 - C_i), lambda in micrometres, C_i in um^2.
    Sellmeier {
        /// B coefficients.
        b: [f32; 3],
        /// C coefficients (um^2).
        c: [f32; 3],
    },
}

/// A surface material (DESIGN.md section 4): the closed set of analytic models.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflector with albedo `reflectance`; black from behind unless `two_sided`.
    Diffuse {
        /// Albedo spectrum in [0, 1].
        reflectance: Spectrum,
        /// Reflect on both sides of the surface.
        two_sided: bool,
    },
    /// Smooth (alpha = 0) or GGX-rough conductor.
    Conductor {
        /// GGX alpha (used directly; 0 = smooth mirror).
        alpha: f32,
        /// Fresnel model.
        fresnel: ConductorFresnel,
        /// Reflect on both sides of the surface.
        two_sided: bool,
    },
    /// Smooth (alpha = 0) or GGX-rough dielectric interface.
    Dielectric {
        /// IOR of the inside (the side the geometric normal points away from) relative to outside.
        ior: Ior,
        /// GGX alpha (used directly; 0 = smooth).
        alpha: f32,
    },
}

impl Material {
    /// The BSDF at the path's wavelengths; a dispersive IOR terminates the secondary wavelengths.
    pub fn bsdf(&self, _wl: &mut SampledWavelengths) -> Bsdf {
        unimplemented!("filled in by the BSDF work")
    }
}
