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

/// Moves `p` off a surface with geometric normal `n` to the side `dir` points to, far enough that
/// re-intersecting the same surface is impossible and close enough to be invisible at any scene
/// scale. Integer-ULP offset of Waechter & Binder, "A Fast and Robust Method for Avoiding
/// Self-Intersection" (Ray Tracing Gems, ch. 6): the offset grows with |p| (float spacing) and a
/// fixed absolute floor covers points near the origin.
pub fn offset_origin(p: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let n = if n.dot(dir) < 0.0 { -n } else { n };
    let of_i = [(INT_SCALE * n.x) as i32, (INT_SCALE * n.y) as i32, (INT_SCALE * n.z) as i32];
    let pa = p.to_array();
    let na = n.to_array();
    let mut out = [0.0f32; 3];
    for k in 0..3 {
        let delta = if pa[k] < 0.0 { -of_i[k] } else { of_i[k] };
        let p_i = f32::from_bits((pa[k].to_bits() as i32).wrapping_add(delta) as u32);
        out[k] = if pa[k].abs() < ORIGIN { pa[k] + FLOAT_SCALE * na[k] } else { p_i };
    }
    Vec3::from_array(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_requested_side_at_all_scales() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        for scale in [1e-4f32, 1e-2, 1.0, 1e3, 1e5] {
            let p = Vec3::new(0.7, -1.3, 2.1) * scale;
            let up = offset_origin(p, n, n);
            let down = offset_origin(p, n, -n);
            assert!((up - p).dot(n) > 0.0, "scale {scale}");
            assert!((down - p).dot(n) < 0.0, "scale {scale}");
            // the offset is tiny relative to the scene scale
            assert!((up - p).length() < 1e-3 * scale.max(1e-2));
        }
    }
}
