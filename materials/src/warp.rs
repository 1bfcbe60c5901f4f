//! Warps of uniform numbers to disks and hemispheres, shared by the BSDFs and the renderer's
//! light sampling (pbrt-v4 section A.5).

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};

use glam::{Vec2, Vec3};

/// Shirley–Chiu concentric map of [0, 1]^2 onto the unit disk (area preserving).
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) =
        if o.x.abs() > o.y.abs() { (o.x, FRAC_PI_4 * (o.y / o.x)) } else { (o.y, FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y)) };
    Vec2::new(r * theta.cos(), r * theta.sin())
}

/// Cosine-weighted direction on the upper hemisphere (density cos(theta) / pi): a uniform disk
/// point lifted to the hemisphere (Malley's method).
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}
