//! Colour spaces: CIE XYZ <-> linear sRGB (D65) and luminance (the RGB -> spectrum uplift is
//! [`rgb_uplift`](super::rgb_uplift)).

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

/// The sRGB transfer function decoded for an 8-bit value (IEC 61966-2-1: v/12.92 up to
/// 0.04045, ((v + 0.055)/1.055)^2.4 above), from a 256-entry table.
#[inline]
pub fn srgb8_to_linear(v: u8) -> f32 {
    static LUT: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    LUT.get_or_init(|| {
        std::array::from_fn(|i| {
            let c = i as f32 / 255.0;
            if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
        })
    })[usize::from(v)]
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrices_are_inverse() {
        let v = [0.3, 0.5, 0.9];
        let r = xyz_to_linear_srgb(linear_srgb_to_xyz(v));
        for k in 0..3 {
            assert!((r[k] - v[k]).abs() < 1e-5);
        }
    }

    #[test]
    fn srgb_decoding() {
        assert_eq!(srgb8_to_linear(0), 0.0);
        assert_eq!(srgb8_to_linear(255), 1.0);
        assert!((srgb8_to_linear(10) - 10.0 / 255.0 / 12.92).abs() < 1e-7);
        assert!((srgb8_to_linear(128) - 0.215_860_5).abs() < 1e-5);
    }
}
