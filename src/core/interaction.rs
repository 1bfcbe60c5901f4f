//! What a ray hit: [`GeometricHit`] (the point and its geometric normal, for probe rays) and
//! [`SurfaceInteraction`] (with the shading normal, material, light, texture coordinates and
//! barycentrics that shading needs), and the tangent-space normal mapping of a hit.

use glam::{Vec2, Vec3};
use quasar_materials::Frame;

use crate::core::geometry::{Ray, TriangleGeom};

/// A ray's hit with its geometry only: what probe rays need ([`Scene::intersect_geometry`]).
#[derive(Clone, Copy, Debug)]
pub struct GeometricHit {
    /// Position (computed from barycentrics), as in [`SurfaceInteraction::p`].
    pub p: Vec3,
    /// Absolute per-axis rounding-error bound of `p`.
    pub p_err: Vec3,
    /// Unit geometric normal (the triangle's winding), as in [`SurfaceInteraction::ng`].
    pub ng: Vec3,
    /// Ray distance to the hit.
    pub t: f32,
}

impl GeometricHit {
    /// A ray leaving the hit in direction `w`, offset past the rounding error of `p` (the
    /// same origin [`SurfaceInteraction::spawn_ray`] gives).
    pub fn spawn_ray(&self, w: Vec3) -> Ray {
        Ray::new(crate::core::geometry::offset_origin(self.p, self.p_err, self.ng, w), w)
    }
}

/// A surface point hit by a ray, with everything shading needs.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    /// Position (computed from barycentrics).
    pub p: Vec3,
    /// Absolute per-axis rounding-error bound of `p`.
    pub p_err: Vec3,
    /// Unit geometric normal (winding order; not flipped towards the ray).
    pub ng: Vec3,
    /// Unit shading normal, on the same side as `ng`.
    pub ns: Vec3,
    /// Distance along the ray.
    pub t: f32,
    /// Triangle index (BVH order).
    pub prim: u32,
    /// Material index.
    pub material: u32,
    /// Area light index or [`NONE`].
    pub light: u32,
    /// Texture coordinates (zero unless the material is textured).
    pub uv: Vec2,
    /// Barycentric coordinates (b1, b2) of the hit in its triangle (for vertex colours).
    pub bary: Vec2,
}

impl SurfaceInteraction {
    /// The shading frame (z = shading normal).
    pub fn frame(&self) -> Frame {
        Frame::from_z(self.ns)
    }

    /// A ray leaving the surface in direction `w`, offset off the surface to the side of `w`.
    pub fn spawn_ray(&self, w: Vec3) -> Ray {
        Ray::new(crate::core::geometry::offset_origin(self.p, self.p_err, self.ng, w), w)
    }

    /// A shadow ray towards a point at distance `dist` in direction `w` (stops just short of it;
    /// `dist` = infinity for distant lights).
    #[inline(always)]
    pub fn spawn_shadow_ray(&self, w: Vec3, dist: f32) -> Ray {
        let o = crate::core::geometry::offset_origin(self.p, self.p_err, self.ng, w);
        let mut r = Ray::new(o, w);
        if dist.is_finite() {
            r.t_max = (dist * (1.0 - 1e-4)).max(0.0);
        }
        r
    }
}

/// The shading normal `ns` perturbed by tangent-space normal `n` (glTF convention: +X along
/// increasing u, +Y along decreasing v, +Z = `ns`), with the tangent frame from the triangle's
/// texture coordinates `uv`; `ns` unchanged when the frame or the result is degenerate. The result
/// stays on the side of `ng`.
pub(super) fn normal_mapped(g: &TriangleGeom, uv: &[Vec2], ns: Vec3, ng: Vec3, n: Vec3) -> Vec3 {
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    if det == 0.0 || !det.is_finite() {
        return ns;
    }
    let (e1, e2) = (Vec3::from(g.e1), Vec3::from(g.e2));
    let dpdu = (e1 * d2.y - e2 * d1.y) / det;
    let dpdv = (e2 * d1.x - e1 * d2.x) / det;
    let t = (dpdu - ns * ns.dot(dpdu)).normalize_or_zero();
    if t == Vec3::ZERO || !t.is_finite() {
        return ns;
    }
    let mut b = ns.cross(t);
    if b.dot(dpdv) > 0.0 {
        b = -b;
    }
    let m = (t * n.x + b * n.y + ns * n.z).normalize_or_zero();
    if m == Vec3::ZERO || !m.is_finite() {
        return ns;
    }
    if m.dot(ng) < 0.0 { -m } else { m }
}
