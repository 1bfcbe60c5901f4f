//! Photometric -> radiometric conversion for lights given in photometric units (glTF candela,
//! lux, nits).
//!
//! The sensor's luminance is Y = integral L ybar / integral ybar (docs/architecture.md §3), and the
//! photometric luminance is L_v = 683 lm/W * integral L ybar = [`LUMINANCE_PER_Y`] * Y (cd/m^2).
//! Light colours are spectra normalised to Y = 1 (`Spectrum::rgb_illuminant`), so a photometric
//! quantity Q (cd, lx or cd/m^2) becomes the radiometric scale `Q / LUMINANCE_PER_Y` (W/(sr nm),
//! W/(m^2 nm) or W/(sr m^2 nm) per unit of the normalised spectrum). A 1 cd white point light then
//! renders a white Lambertian plane 1 m below it with Y * LUMINANCE_PER_Y = 1/pi cd/m^2.

use quasar_materials::spectrum::cie::CIE_Y_INTEGRAL;

/// Maximum luminous efficacy of radiation, lm/W (photopic, 555 nm).
pub const LUMINOUS_EFFICACY: f32 = 683.0;

/// cd/m^2 per unit of rendered luminance Y: 683 lm/W times the integral of ybar (nm).
pub const LUMINANCE_PER_Y: f32 = LUMINOUS_EFFICACY * CIE_Y_INTEGRAL;

/// The radiometric scale of a light given in a photometric unit (see the module documentation).
#[inline]
pub fn photometric_scale(q: f32) -> f32 {
    q / LUMINANCE_PER_Y
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_materials::spectrum::Spectrum;

    #[test]
    fn one_candela_of_white_has_luminous_intensity_one() {
        // luminous intensity = 683 * integral I(lambda) ybar(lambda) dlambda
        let s = Spectrum::rgb_illuminant([1.0; 3]).unwrap();
        let scale = photometric_scale(1.0);
        let mut iv = 0.0f64;
        for l in 360..830 {
            let l = l as f32 + 0.5;
            iv += f64::from(scale * s.value(l) * quasar_materials::spectrum::cie::ybar(l));
        }
        let iv = iv * f64::from(LUMINOUS_EFFICACY);
        assert!((iv - 1.0).abs() < 2e-3, "{iv}");
    }
}
