//! The scene's triangles and their BVH: a four-wide BVH with four-triangle leaf packets
//! ([`wide_bvh`](super::wide_bvh)) whose topology obvhs' PLOC builder makes, with the triangles'
//! shading data reordered into leaf order so that nearby hits read nearby records.

use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;

use super::mesh::{TriangleGeom, TriangleInfo};
use super::ray::Ray;
use super::wide_bvh::{self, WideBvh};

/// A closest-hit record: which triangle (in BVH order), distance and barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index into [`Accel::geom`] / [`Accel::info`].
    pub prim: u32,
    /// Ray distance.
    pub t: f32,
    /// Barycentric weight of v1.
    pub b1: f32,
    /// Barycentric weight of v2.
    pub b2: f32,
}

/// The power of two that maps a scene whose largest |coordinate| is `extent` to about 2^14
/// units (1 for an empty or degenerate extent).
fn build_scale(extent: f32) -> f32 {
    if !(extent > 0.0 && extent.is_finite()) {
        return 1.0;
    }
    let e = (14 - extent.log2().round() as i32).clamp(-100, 100);
    2f32.powi(e)
}

/// The scene's triangles and their BVH.
///
/// The builder sees a uniformly scaled copy of the scene whose bounding box spans about 2^14
/// units (a power of two, so exact), which keeps its topology independent of the scene's unit;
/// bounds and triangle tests are in world space.
pub struct Accel {
    bvh: WideBvh,
    /// Intersection data, BVH order.
    pub geom: Vec<TriangleGeom>,
    /// Shading data, BVH order.
    pub info: Vec<TriangleInfo>,
}

impl Accel {
    /// Builds the BVH over `tris` (vertex triples) with their shading data, both reordered into
    /// the BVH's leaf order.
    pub fn build(tris: &[[Vec3; 3]], info: &[TriangleInfo], params: BvhBuildParams) -> Self {
        assert_eq!(tris.len(), info.len());
        let extent = tris.iter().flatten().fold(0.0f32, |m, p| m.max(p.abs().max_element()));
        let (bvh, order) = wide_bvh::build(tris, build_scale(extent), params);
        let geom = order
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                TriangleGeom::new(t[0], t[1], t[2])
            })
            .collect();
        let info = order.iter().map(|&i| info[i as usize]).collect();
        Self { bvh, geom, info }
    }

    /// Default build quality for renders: PLOC with reinsertion.
    pub fn default_params() -> BvhBuildParams {
        BvhBuildParams::medium_build()
    }

    /// Closest hit along `ray` within (0, ray.t_max).
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        // -0.0 components become +0.0, as before the wide BVH (the triangle test is unaffected;
        // the slab test treats both zeros alike)
        let d = Vec3A::from(ray.dir) + Vec3A::ZERO;
        let (prim, t, b1, b2) = self.bvh.intersect(Vec3A::from(ray.origin), d, ray.t_max)?;
        Some(Hit { prim, t, b1, b2 })
    }

    /// True when something blocks the segment from `ray.origin` up to (excluding) `ray.t_max`.
    #[inline(always)]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let d = Vec3A::from(ray.dir) + Vec3A::ZERO;
        self.bvh.occluded(Vec3A::from(ray.origin), d, ray.t_max)
    }

    /// Bytes used by the BVH nodes, leaf packets and triangle data.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.geom.len() * std::mem::size_of::<TriangleGeom>()
            + self.info.len() * std::mem::size_of::<TriangleInfo>()
    }
}
