//! CIE 1931 2-degree colour-matching functions and standard illuminants, linearly interpolated
//! from the 5 nm tables in [`cie_data`](super::cie_data).

use glam::{Vec3A, Vec4};

use super::cie_data::{CIE_D65, CIE_X, CIE_Y, CIE_Z, CMF_LAMBDA_START, D65_LAMBDA_START, TABLE_STEP};

/// Integral of ybar over the tables' range (nm), the sensor's normalisation constant:
/// a spectrally flat radiance of 1 has Y = 1.
pub const CIE_Y_INTEGRAL: f32 = 106.857_03;

/// Linear interpolation in a table sampled every `TABLE_STEP` nm from `start`; 0 outside.
#[inline]
fn lerp_table(table: &[f32], start: f32, lambda: f32) -> f32 {
    let x = (lambda - start) / TABLE_STEP;
    if x.is_nan() || x < 0.0 || x > (table.len() - 1) as f32 {
        return 0.0;
    }
    let i = (x as usize).min(table.len() - 2);
    let t = x - i as f32;
    table[i] * (1.0 - t) + table[i + 1] * t
}

/// The three colour-matching tables interleaved, one (xbar, ybar, zbar) entry per knot, so that
/// [`cmf`] finds its interval once for all three.
const CMF_XYZ: [[f32; 3]; CIE_X.len()] = {
    let mut t = [[0.0; 3]; CIE_X.len()];
    let mut i = 0;
    while i < t.len() {
        t[i] = [CIE_X[i], CIE_Y[i], CIE_Z[i]];
        i += 1;
    }
    t
};

/// (xbar, ybar, zbar) at `lambda` nm; 0 outside 360..=830 nm (the same linear interpolation as
/// [`ybar`], done once for the three tables).
#[inline]
pub fn cmf(lambda: f32) -> [f32; 3] {
    let x = (lambda - CMF_LAMBDA_START) / TABLE_STEP;
    if x.is_nan() || x < 0.0 || x > (CMF_XYZ.len() - 1) as f32 {
        return [0.0; 3];
    }
    let i = (x as usize).min(CMF_XYZ.len() - 2);
    let t = x - i as f32;
    let (a, b) = (CMF_XYZ[i], CMF_XYZ[i + 1]);
    [0, 1, 2].map(|k| a[k] * (1.0 - t) + b[k] * t)
}

/// (xbar, ybar, zbar) at every whole nanometre of 360..=830 nm (the 5 nm tables' linear
/// interpolation there), so that within a 1 nm cell the colour-matching functions are the linear
/// interpolation of two entries ([`cmf_at`]).
static CMF_NM: CmfRows = CmfRows({
    let mut t = [[0.0; 4]; 471];
    let mut k = 0;
    while k < t.len() {
        let (i, r) = (k / 5, k % 5);
        let f = r as f32 / 5.0;
        let mut c = 0;
        while c < 3 {
            t[k][c] = if r == 0 { CMF_XYZ[i][c] } else { CMF_XYZ[i][c] * (1.0 - f) + CMF_XYZ[i + 1][c] * f };
            c += 1;
        }
        k += 1;
    }
    t
});

/// Rows (xbar, ybar, zbar, 0), aligned so that a row loads as one SIMD vector.
#[repr(C, align(16))]
struct CmfRows([[f32; 4]; 471]);

/// (xbar, ybar, zbar) at 360 + `cell` + `t` nm (a wavelength's place on the 1 nm grid,
/// `GridPos`): [`cmf`] to rounding, by one linear interpolation between two whole nanometres; 0
/// for a cell outside the grid.
#[inline]
pub fn cmf_at(cell: u32, t: f32) -> Vec3A {
    let k = cell as usize;
    if k + 1 >= CMF_NM.0.len() {
        return Vec3A::ZERO;
    }
    let row = |k: usize| Vec3A::from_vec4(Vec4::from_array(CMF_NM.0[k]));
    let (a, b) = (row(k), row(k + 1));
    a + t * (b - a)
}

/// ybar at `lambda` nm (the photopic luminous efficiency V(lambda)).
#[inline]
pub fn ybar(lambda: f32) -> f32 {
    lerp_table(&CIE_Y, CMF_LAMBDA_START, lambda)
}

/// CIE D65 relative spectral power (100 at 560 nm); 0 outside 300..=830 nm.
#[inline]
pub fn d65(lambda: f32) -> f32 {
    lerp_table(&CIE_D65, D65_LAMBDA_START, lambda)
}

/// CIE standard illuminant A: Planck's law at 2856 K normalised to 100 at 560 nm (CIE 015 formula for A:
/// T = 2848 K with c2 = 1.435e7 nm K, i.e. 2856 K on the modern c2 scale).
pub fn illuminant_a(lambda: f32) -> f32 {
    let l = lambda as f64;
    let c2 = 1.435e7_f64;
    let v = 100.0 * (560.0 / l).powi(5) * ((c2 / (2848.0 * 560.0)).exp() - 1.0) / ((c2 / (2848.0 * l)).exp() - 1.0);
    v as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ybar_integral_matches_constant() {
        let s: f32 = CIE_Y.iter().sum::<f32>() * TABLE_STEP;
        assert!((s - CIE_Y_INTEGRAL).abs() / CIE_Y_INTEGRAL < 1e-3, "{s}");
    }

    #[test]
    fn illuminant_a_is_100_at_560() {
        assert!((illuminant_a(560.0) - 100.0).abs() < 1e-3);
        // CIE 015 tabulates A(400 nm) = 14.708 and A(700 nm) = 198.261.
        assert!((illuminant_a(400.0) - 14.708).abs() < 0.01, "{}", illuminant_a(400.0));
        assert!((illuminant_a(700.0) - 198.261).abs() < 0.02, "{}", illuminant_a(700.0));
    }

    #[test]
    fn interleaved_cmf_is_the_three_tables() {
        let mut l = 355.0;
        while l < 835.0 {
            let want = [&CIE_X, &CIE_Y, &CIE_Z].map(|t| lerp_table(t, CMF_LAMBDA_START, l));
            assert_eq!(cmf(l), want, "{l}");
            l += 0.73;
        }
    }

    #[test]
    fn d65_is_100_at_560() {
        assert!((d65(560.0) - 100.0).abs() < 1e-3);
        assert_eq!(d65(200.0), 0.0);
    }

    #[test]
    fn grid_colour_matching_is_the_table_interpolation() {
        let mut l = 360.0f32;
        while l <= 830.0 {
            let x = l - 360.0;
            let cell = (x as u32).min(469);
            let (a, b) = (cmf(l), cmf_at(cell, x - cell as f32));
            for k in 0..3 {
                // rounding of two interpolations: about 1e-7 of the neighbouring table values
                assert!((a[k] - b[k]).abs() <= 5e-8 + 1e-6 * a[k].abs(), "{l} nm: {a:?} vs {b:?}");
            }
            l += 0.173;
        }
        assert_eq!(cmf_at(u32::MAX, 0.0), Vec3A::ZERO);
    }
}
