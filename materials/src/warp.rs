//! Warps of uniform numbers to disks and hemispheres, shared by the BSDFs and the renderer's
//! light sampling (pbrt-v4 section A.5).

use std::f32::consts::{FRAC_PI_4, TAU};

use glam::{Vec2, Vec3};

/// (sin a, cos a) for |a| <= pi/4 by their Taylor polynomials to a^9 and a^10, whose
/// truncation errors there, (pi/4)^11 / 11! and (pi/4)^12 / 12!, are below 2e-9: as accurate
/// as f32 allows, without a call into libm. Evaluated in Estrin's scheme (pairs of terms in
/// a^2 combined by powers a^4, a^8) rather than Horner's: the sampled direction is on the
/// path's critical chain (it is the next ray), and Estrin's dependency chain is shorter.
#[inline]
fn sin_cos_quarter(a: f32) -> (f32, f32) {
    let a2 = a * a;
    let a4 = a2 * a2;
    let a8 = a4 * a4;
    // sin a / a = 1 - a^2/3! + a^4/5! - a^6/7! + a^8/9!
    let s01 = 1.0 - a2 * (1.0 / 6.0);
    let s23 = 1.0 / 120.0 - a2 * (1.0 / 5040.0);
    let s = a * ((s01 + a4 * s23) + a8 * (1.0 / 362_880.0));
    // cos a = 1 - a^2/2! + a^4/4! - a^6/6! + a^8/8! - a^10/10!
    let c01 = 1.0 - a2 * 0.5;
    let c23 = 1.0 / 24.0 - a2 * (1.0 / 720.0);
    let c45 = 1.0 / 40_320.0 - a2 * (1.0 / 3_628_800.0);
    let c = (c01 + a4 * c23) + a8 * c45;
    (s, c)
}

/// (sin 2 pi t, cos 2 pi t) for t in [0, 1] (a whole turn, e.g. an azimuth phi = 2 pi u):
/// t = k / 4 + a / (2 pi) with the nearest quarter turn k, so |a| <= pi/4, and
/// sin(a + k pi/2), cos(a + k pi/2) are (sin a, cos a) swapped for odd k and negated by sign
/// flips, without a branch or a call into libm. Agrees with libm's to 2e-7 (for t down to
/// -1/8, where the truncation that rounds 4t + 1/2 still rounds down).
#[inline]
pub fn sin_cos_turns(t: f32) -> (f32, f32) {
    let k = (4.0 * t + 0.5) as i32;
    let (s, c) = sin_cos_quarter(TAU * (t - 0.25 * k as f32));
    let k = k as u32;
    // k = 1: (c, -s); k = 2: (-s, -c); k = 3: (-c, s)
    let (s, c) = if k & 1 == 1 { (c, s) } else { (s, c) };
    let sign = 0x8000_0000u32;
    let s_flip = if k & 2 == 2 { sign } else { 0 };
    let c_flip = if (k ^ (k >> 1)) & 1 == 1 { sign } else { 0 };
    (f32::from_bits(s.to_bits() ^ s_flip), f32::from_bits(c.to_bits() ^ c_flip))
}

/// Shirley–Chiu concentric map of [0, 1]^2 onto the unit disk (area preserving): with
/// o = 2u - 1, radius r = the component of larger magnitude and angle pi/4 (q / r) from the other
/// component q, measured from the x axis when r = o.x and from the y axis otherwise. Written
/// with selects instead of branches: which component is larger is a coin flip per sample, which
/// a branch predictor cannot learn.
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    let x_major = o.x.abs() > o.y.abs();
    let (r, q) = if x_major { (o.x, o.y) } else { (o.y, o.x) };
    // r = 0 only at the centre, where q = 0 too and the point is the origin
    let ratio = if r != 0.0 { q / r } else { 0.0 };
    let (s, c) = sin_cos_quarter(FRAC_PI_4 * ratio);
    let (along, across) = if x_major { (c, s) } else { (s, c) };
    Vec2::new(r * along, r * across)
}

/// Cosine-weighted direction on the upper hemisphere (density cos(theta) / pi): Malley's method
/// with the polar map of the unit disk, radius sqrt(u.x) and azimuth 2 pi u.y, so that
/// z = sqrt(1 - u.x). Its three parts (two square roots and the azimuth's sine and cosine)
/// are independent of each other, which makes the sampled direction, the next ray of a path,
/// ready sooner than with the concentric map (a division, then the polynomials, then the
/// square root). The two maps differ only in how they distort strata of the unit square,
/// and quasar's samples are independent uniforms.
#[inline(always)]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let r = u.x.max(0.0).sqrt();
    let (s, c) = sin_cos_turns(u.y);
    let z = (1.0 - u.x).max(0.0).sqrt();
    Vec3::new(r * c, r * s, z)
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
    fn whole_turn_sine_and_cosine_are_libm_s_to_rounding() {
        let mut worst = 0.0f64;
        for k in 0..=100_000 {
            let t = k as f32 / 100_000.0;
            let (s, c) = sin_cos_turns(t);
            let (se, ce) = (std::f64::consts::TAU * t as f64).sin_cos();
            worst = worst.max((s as f64 - se).abs()).max((c as f64 - ce).abs());
        }
        assert!(worst < 2e-7, "{worst}");
        // the quarter turns themselves, exactly
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25), (1.0, 0.0));
        assert_eq!(sin_cos_turns(0.5), (-0.0, -1.0));
        assert_eq!(sin_cos_turns(0.75), (-1.0, -0.0));
        assert_eq!(sin_cos_turns(1.0), (0.0, 1.0));
    }

    #[test]
    fn concentric_disk_maps_the_centre_to_the_origin() {
        assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
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
