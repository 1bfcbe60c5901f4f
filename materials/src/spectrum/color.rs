//! Colour spaces: CIE XYZ <-> linear sRGB (D65), luminance, and the bounded RGB -> spectrum uplift.

/// XYZ -> linear sRGB (IEC 61966-2-1, D65 white), row-major.
pub const XYZ_TO_SRGB: [[f32; 3]; 3] = [
    [3.240_454_2, -1.537_138_5, -0.498_531_4],
    [-0.969_266, 1.876_010_8, 0.041_556_0],
    [0.055_643_4, -0.204_025_9, 1.057_225_2],
];

/// Linear sRGB -> XYZ (inverse of [`XYZ_TO_SRGB`]), row-major.
pub const SRGB_TO_XYZ: [[f32; 3]; 3] = [
    [0.412_456_4, 0.357_576_1, 0.180_437_5],
    [0.212_672_9, 0.715_152_2, 0.072_175_0],
    [0.019_333_9, 0.119_192, 0.950_304_1],
];

/// Multiplies a 3x3 row-major matrix with a vector.
#[inline]
pub fn mat3_mul(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// CIE XYZ -> linear sRGB.
#[inline]
pub fn xyz_to_linear_srgb(xyz: [f32; 3]) -> [f32; 3] {
    mat3_mul(&XYZ_TO_SRGB, xyz)
}

/// Linear sRGB -> CIE XYZ.
#[inline]
pub fn linear_srgb_to_xyz(rgb: [f32; 3]) -> [f32; 3] {
    mat3_mul(&SRGB_TO_XYZ, rgb)
}

/// Luminance Y of a linear sRGB colour.
#[inline]
pub fn srgb_luminance(rgb: [f32; 3]) -> f32 {
    SRGB_TO_XYZ[1][0] * rgb[0] + SRGB_TO_XYZ[1][1] * rgb[1] + SRGB_TO_XYZ[1][2] * rgb[2]
}

/// Blue/green and green/red transition wavelengths (nm) and width (nm) of the uplift basis.
const UPLIFT_BG: f32 = 490.0;
const UPLIFT_GR: f32 = 585.0;
const UPLIFT_WIDTH: f32 = 9.0;

#[inline]
fn logistic(x: f32) -> f32 {
    1.0 / (1.0 + (-x).exp())
}

/// Bounded, smooth RGB -> spectrum uplift for reflectances (a three-band basis in the spirit of
/// Smits 1999): rho(lambda) = b * B(lambda) + g * G(lambda) + r * R(lambda), where B, G, R are
/// logistic bands with B + G + R = 1 and each >= 0. Hence rho lies in [min(rgb), max(rgb)]: grey
/// maps to the flat spectrum of the same value and a reflectance <= 1 stays <= 1 (energy bounded).
/// The hue is preserved approximately, not exactly; measured materials should use tables.
#[inline]
pub fn rgb_uplift(rgb: [f32; 3], lambda: f32) -> f32 {
    let s_bg = logistic((lambda - UPLIFT_BG) / UPLIFT_WIDTH);
    let s_gr = logistic((lambda - UPLIFT_GR) / UPLIFT_WIDTH);
    let blue = 1.0 - s_bg;
    let red = s_gr;
    let green = (s_bg - s_gr).max(0.0);
    rgb[0] * red + rgb[1] * green + rgb[2] * blue
}

#[cfg(test)]
mod tests {
    use super::super::cie;
    use super::*;

    fn reflectance_to_srgb_under_d65(rgb: [f32; 3]) -> [f32; 3] {
        // XYZ of the reflected D65 light, normalised so that a perfect white has Y = 1.
        let mut xyz = [0.0f64; 3];
        let mut norm = 0.0f64;
        for l in 360..830 {
            let l = l as f32 + 0.5;
            let e = cie::d65(l) as f64;
            let c = cie::cmf(l);
            let r = rgb_uplift(rgb, l) as f64;
            for k in 0..3 {
                xyz[k] += e * r * c[k] as f64;
            }
            norm += e * c[1] as f64;
        }
        xyz_to_linear_srgb(xyz.map(|v| (v / norm) as f32))
    }

    #[test]
    fn matrices_are_inverse() {
        let v = [0.3, 0.5, 0.9];
        let r = xyz_to_linear_srgb(linear_srgb_to_xyz(v));
        for k in 0..3 {
            assert!((r[k] - v[k]).abs() < 1e-5);
        }
    }

    #[test]
    fn uplift_is_bounded_and_grey_is_flat() {
        for l in (360..=830).step_by(5) {
            let l = l as f32;
            assert!((rgb_uplift([0.5, 0.5, 0.5], l) - 0.5).abs() < 1e-6);
            let v = rgb_uplift([1.0, 0.0, 1.0], l);
            assert!((0.0..=1.0).contains(&v));
        }
        let w = reflectance_to_srgb_under_d65([1.0, 1.0, 1.0]);
        for c in w {
            assert!((c - 1.0).abs() < 0.01, "{w:?}");
        }
    }

    #[test]
    fn uplift_keeps_the_dominant_primary() {
        for k in 0..3 {
            let mut rgb = [0.1; 3];
            rgb[k] = 0.8;
            let out = reflectance_to_srgb_under_d65(rgb);
            let argmax = (0..3).max_by(|a, b| out[*a].total_cmp(&out[*b])).unwrap();
            assert_eq!(argmax, k, "{rgb:?} -> {out:?}");
        }
    }
}
