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
}
