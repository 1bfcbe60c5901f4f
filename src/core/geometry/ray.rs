//! Rays and robust ray-origin offsetting.

use glam::Vec3;

/// A ray o + t d with t in (0, t_max).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub origin: Vec3,
    /// Direction (unit length).
    pub dir: Vec3,
    /// Largest accepted hit distance.
    pub t_max: f32,
}

impl Ray {
    /// A ray to infinity.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir, t_max: f32::INFINITY }
    }
}

/// Conservative bound on the relative rounding error of n floating-point operations,
/// gamma(n) = n eps / (1 - n eps) with eps = 2^-24 (Higham; pbrt-v4 section 6.8.1).
#[inline]
pub const fn gamma(n: i32) -> f32 {
    let e = n as f32 * (f32::EPSILON * 0.5);
    e / (1.0 - e)
}

/// Absolute error bound of the hit point p = v0 + b1 e1 + b2 e2 evaluated in f32. Barycentric
/// re-evaluation keeps p on the triangle's plane up to this rounding error, whatever the error
/// of b1 and b2 (pbrt-v4 section 6.8.5).
#[inline]
pub fn point_error(v0: Vec3, b1e1: Vec3, b2e2: Vec3) -> Vec3 {
    gamma(7) * (v0.abs() + b1e1.abs() + b2e2.abs())
}

/// Moves the point `p` (with per-axis absolute error bound `p_err`) off a surface with unit
/// geometric normal `n`, to the side `dir` points to: first by the projection of the error box
/// onto the normal, then by one float step away from the surface per axis, so the offset
/// origin is provably on `dir`'s side of the surface (pbrt-v4 section 6.8.6). The offset scales
/// with the coordinates' magnitudes, so it is invisible at any scene scale from 1e-4 to 1e5.
#[inline]
pub fn offset_origin(p: Vec3, p_err: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    let d = n.abs().dot(p_err);
    let mut offset = d * n;
    if dir.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    Vec3::new(float_step(po.x, offset.x), float_step(po.y, offset.y), float_step(po.z, offset.z))
}

/// `v` moved by one float step towards +infinity when `dir` > 0, towards -infinity when `dir` <
/// 0, unchanged when `dir` is 0 (pbrt-v4's `NextFloatUp` / `NextFloatDown` for finite `v`),
/// written with selects rather than branches: the offset's signs are as random as the
/// surfaces' normals, so branches on them mispredict.
#[inline]
fn float_step(v: f32, dir: f32) -> f32 {
    let up = dir > 0.0;
    // zero steps to the smallest subnormal of the direction's sign
    let v0 = if v == 0.0 { if up { 0.0 } else { -0.0 } } else { v };
    let bits = v0.to_bits();
    // away from zero when moving the way of the sign (or from zero itself)
    let away = (v0 > 0.0) == up || v0 == 0.0;
    let stepped = f32::from_bits(if away { bits.wrapping_add(1) } else { bits.wrapping_sub(1) });
    if dir == 0.0 { v } else { stepped }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_steps_are_next_up_and_next_down() {
        for v in [0.0f32, -0.0, 1.0, -1.0, 1e-30, -1e-30, 3.5e5, -7.25, f32::MIN_POSITIVE, 1e-45, -1e-45, 1e30] {
            assert_eq!(float_step(v, 1.0).to_bits(), v.next_up().to_bits(), "{v} up");
            assert_eq!(float_step(v, -2.0).to_bits(), v.next_down().to_bits(), "{v} down");
            assert_eq!(float_step(v, 0.0).to_bits(), v.to_bits(), "{v} still");
        }
    }

    #[test]
    fn offset_moves_to_the_requested_side_at_all_scales() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        for scale in [1e-4f32, 1e-2, 1.0, 1e3, 1e5] {
            let p = Vec3::new(0.7, -1.3, 2.1) * scale;
            let err = point_error(p, Vec3::ZERO, Vec3::ZERO);
            let up = offset_origin(p, err, n, n);
            let down = offset_origin(p, err, n, -n);
            assert!((up - p).dot(n) > 0.0, "scale {scale}");
            assert!((down - p).dot(n) < 0.0, "scale {scale}");
            // the offset is tiny relative to the scene scale
            assert!((up - p).length() < 1e-5 * scale, "scale {scale}: {}", (up - p).length());
        }
    }

    #[test]
    fn offset_points_never_reintersect_their_triangle() {
        use crate::core::geometry::TriangleGeom;
        use glam::Vec3A;
        // A tilted triangle far from the origin; rays leaving each hit point along the
        // reflected direction must not hit the same triangle again.
        for scale in [1e-4f32, 1.0, 1e5] {
            let v0 = Vec3::new(3.1, 7.3, -2.2) * scale;
            let v1 = v0 + Vec3::new(1.0, 0.2, 0.1) * scale;
            let v2 = v0 + Vec3::new(0.1, 0.3, 1.0) * scale;
            let tri = TriangleGeom::new(v0, v1, v2);
            let n = tri.normal_unnormalised().normalize();
            let mut misses = 0;
            for i in 0..200 {
                let b1 = (i as f32 * 0.618).fract() * 0.5;
                let b2 = (i as f32 * 0.414).fract() * 0.5;
                let d_in = (-n + Vec3::new(0.3, (i as f32).sin() * 0.2, 0.1)).normalize();
                let o = tri.point(b1, b2) - d_in * scale;
                let Some((_t, h1, h2)) = tri.intersect(o.into(), d_in.into(), 0.0, f32::INFINITY) else {
                    misses += 1;
                    continue;
                };
                let (p, err) = tri.point_with_error(h1, h2);
                let d_out = d_in - 2.0 * d_in.dot(n) * n;
                let po = offset_origin(p, err, n, d_out);
                assert!(tri.intersect(Vec3A::from(po), d_out.into(), 0.0, f32::INFINITY).is_none(), "scale {scale}");
                let po = offset_origin(p, err, n, d_in);
                assert!(tri.intersect(Vec3A::from(po), d_in.into(), 0.0, f32::INFINITY).is_none(), "scale {scale}");
            }
            assert!(misses < 10);
        }
    }
}
