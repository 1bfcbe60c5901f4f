//! Warps of uniform numbers to disks and hemispheres, shared by the BSDFs and the renderer's
//! light sampling (pbrt-v4 section A.5).

use std::f32::consts::FRAC_PI_4;

use glam::{Vec2, Vec3};

/// (sin a, cos a) for |a| <= pi/4 by their Taylor polynomials to a^9 and a^10, whose
/// truncation errors there, (pi/4)^11 / 11! and (pi/4)^12 / 12!, are below 2e-9: as accurate
/// as f32 allows, without a call into libm.
#[inline]
fn sin_cos_quarter(a: f32) -> (f32, f32) {
    let a2 = a * a;
    let s = a * (1.0 + a2 * (-1.0 / 6.0 + a2 * (1.0 / 120.0 + a2 * (-1.0 / 5040.0 + a2 * (1.0 / 362_880.0)))));
    let c =
        1.0 + a2 * (-0.5 + a2 * (1.0 / 24.0 + a2 * (-1.0 / 720.0 + a2 * (1.0 / 40_320.0 + a2 * (-1.0 / 3_628_800.0)))));
    (s, c)
}

/// Shirley–Chiu concentric map of [0, 1]^2 onto the unit disk (area preserving).
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // theta = pi/4 (y / x) in the left and right quarters, pi/2 - pi/4 (x / y) in the others,
    // whose cosine and sine are the sine and cosine of pi/4 (x / y)
    if o.x.abs() > o.y.abs() {
        let (s, c) = sin_cos_quarter(FRAC_PI_4 * (o.y / o.x));
        Vec2::new(o.x * c, o.x * s)
    } else {
        let (s, c) = sin_cos_quarter(FRAC_PI_4 * (o.x / o.y));
        Vec2::new(o.y * s, o.y * c)
    }
}

/// Cosine-weighted direction on the upper hemisphere (density cos(theta) / pi): a uniform disk
/// point lifted to the hemisphere (Malley's method).
#[inline(always)]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_sine_and_cosine_are_libm_s_to_rounding() {
        let mut worst = 0.0f64;
        for k in 0..=10_000 {
            let a = (k as f32 / 10_000.0 * 2.0 - 1.0) * FRAC_PI_4;
            let (s, c) = sin_cos_quarter(a);
            let (se, ce) = (a as f64).sin_cos();
            worst = worst.max((s as f64 - se).abs()).max((c as f64 - ce).abs());
        }
        assert!(worst < 2e-7, "{worst}");
    }

    #[test]
    fn concentric_disk_points_are_on_the_disk_at_the_mapped_radius() {
        for i in 0..=40 {
            for j in 0..=40 {
                let u = Vec2::new(i as f32 / 40.0, j as f32 / 40.0);
                let d = concentric_disk(u);
                let o = 2.0 * u - Vec2::ONE;
                let r = o.x.abs().max(o.y.abs());
                assert!((d.length() - r).abs() < 1e-6, "{u}: {d}");
            }
        }
    }
}
