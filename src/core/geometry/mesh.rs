//! Render-time triangle storage: compact intersection data in BVH order plus shading data.

use glam::{Vec3, Vec3A};

/// Intersection data of one triangle (Moeller-Trumbore with precomputed edges).
#[derive(Clone, Copy, Debug)]
pub struct TriangleGeom {
    /// First vertex.
    pub v0: Vec3A,
    /// v1 - v0.
    pub e1: Vec3A,
    /// v2 - v0.
    pub e2: Vec3A,
    /// Unit geometric normal, e1 x e2 normalised (zero for a degenerate triangle), computed
    /// once so that a hit does not normalise it.
    pub n: Vec3A,
}

impl TriangleGeom {
    /// From three vertices.
    pub fn new(v0: Vec3, v1: Vec3, v2: Vec3) -> Self {
        let (e1, e2) = (Vec3A::from(v1 - v0), Vec3A::from(v2 - v0));
        Self { v0: v0.into(), e1, e2, n: Vec3A::from(Vec3::from(e1.cross(e2)).normalize_or_zero()) }
    }

    /// Moeller-Trumbore: returns (t, b1, b2) for a hit with t in (t_min, t_max). Edge tests are
    /// inclusive so that a ray through a shared edge hits at least one of the two triangles.
    #[inline(always)]
    pub fn intersect(&self, o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> Option<(f32, f32, f32)> {
        let p = d.cross(self.e2);
        let det = self.e1.dot(p);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let s = o - self.v0;
        let b1 = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&b1) {
            return None;
        }
        let q = s.cross(self.e1);
        let b2 = d.dot(q) * inv;
        if b2 < 0.0 || b1 + b2 > 1.0 {
            return None;
        }
        let t = self.e2.dot(q) * inv;
        if t > t_min && t < t_max { Some((t, b1, b2)) } else { None }
    }

    /// Unnormalised geometric normal e1 x e2 (counter-clockwise winding faces its viewer).
    #[inline]
    pub fn normal_unnormalised(&self) -> Vec3 {
        Vec3::from(self.e1.cross(self.e2))
    }

    /// Area.
    #[inline]
    pub fn area(&self) -> f32 {
        0.5 * self.normal_unnormalised().length()
    }

    /// Point at barycentrics (b1, b2): v0 + b1 e1 + b2 e2.
    #[inline]
    pub fn point(&self, b1: f32, b2: f32) -> Vec3 {
        Vec3::from(self.v0 + self.e1 * b1 + self.e2 * b2)
    }

    /// Point at barycentrics (b1, b2) with its absolute rounding-error bound
    /// ([`super::ray::point_error`]), for robust ray spawning.
    #[inline]
    pub fn point_with_error(&self, b1: f32, b2: f32) -> (Vec3, Vec3) {
        let v0 = Vec3::from(self.v0);
        let a = Vec3::from(self.e1 * b1);
        let b = Vec3::from(self.e2 * b2);
        (v0 + a + b, super::ray::point_error(v0, a, b))
    }
}

/// Shading data of one triangle (same order as the geometry).
#[derive(Clone, Copy, Debug)]
pub struct TriangleInfo {
    /// Index into the compiled material table.
    pub material: u32,
    /// Index of the area light this triangle is, or `u32::MAX`.
    pub light: u32,
    /// Index of the first of three per-vertex normals in the normal pool, or `u32::MAX` (flat).
    pub normals: u32,
    /// Index of the source mesh (for messages and AOVs).
    pub mesh: u32,
    /// Index of the first of three per-vertex texture coordinates in the uv pool, or `u32::MAX`
    /// (kept only for triangles whose material is textured).
    pub uvs: u32,
}

/// Sentinel for "none" in [`TriangleInfo`] index fields.
pub const NONE: u32 = u32::MAX;
