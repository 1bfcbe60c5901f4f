//! Triangle BVH: an obvhs compressed wide BVH (CWBVH, Ylitie et al. 2017) built with PLOC, with the
//! triangles reordered into BVH leaf order so traversal reads them sequentially.

use std::time::Duration;

use glam::{Vec3, Vec3A};
use obvhs::{BvhBuildParams, cwbvh::CwBvh, cwbvh::builder::build_cwbvh_from_tris, ray::RayHit, triangle::Triangle};

use super::mesh::{TriangleGeom, TriangleInfo};
use super::ray::Ray;

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
fn traversal_scale(extent: f32) -> f32 {
    if !(extent > 0.0 && extent.is_finite()) {
        return 1.0;
    }
    let e = (14 - extent.log2().round() as i32).clamp(-100, 100);
    2f32.powi(e)
}

/// The scene's triangles and their BVH.
///
/// The BVH is built and traversed in a uniformly scaled copy of the scene whose bounding box
/// spans about 2^14 units: obvhs skips every node a ray leaves before t = 1e-4 (a fixed
/// epsilon of its traversal, in scene units), which in metres would hide every surface within
/// 0.1 mm of a ray's origin (a 0.1 mm scene would be half invisible to its own shadow rays).
/// The scale is a power of two, so scaling and unscaling distances is exact.
pub struct Accel {
    bvh: Option<CwBvh>,
    /// World -> traversal space scale (a power of two).
    to_bvh: f32,
    /// Intersection data, BVH order.
    pub geom: Vec<TriangleGeom>,
    /// Shading data, BVH order.
    pub info: Vec<TriangleInfo>,
}

impl Accel {
    /// Builds the BVH over `tris` (vertex triples) with their shading data. Triangles are
    /// duplicated/reordered to match the BVH's primitive order.
    pub fn build(tris: &[[Vec3; 3]], info: &[TriangleInfo], params: BvhBuildParams) -> Self {
        assert_eq!(tris.len(), info.len());
        if tris.is_empty() {
            return Self { bvh: None, to_bvh: 1.0, geom: Vec::new(), info: Vec::new() };
        }
        let extent = tris.iter().flatten().fold(0.0f32, |m, p| m.max(p.abs().max_element()));
        let to_bvh = traversal_scale(extent);
        let obv: Vec<Triangle> = tris
            .iter()
            .map(|t| Triangle { v0: (t[0] * to_bvh).into(), v1: (t[1] * to_bvh).into(), v2: (t[2] * to_bvh).into() })
            .collect();
        let bvh = build_cwbvh_from_tris(&obv, params, &mut Duration::default());
        let geom = bvh
            .primitive_indices
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                TriangleGeom::new(t[0], t[1], t[2])
            })
            .collect();
        let info = bvh.primitive_indices.iter().map(|&i| info[i as usize]).collect();
        Self { bvh: Some(bvh), to_bvh, geom, info }
    }

    /// Default build quality for renders: PLOC with reinsertion and pre-splits.
    pub fn default_params() -> BvhBuildParams {
        BvhBuildParams::medium_build()
    }

    /// Closest hit along `ray` within (0, ray.t_max).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let o = Vec3A::from(ray.origin);
        // -0.0 components become +0.0: obvhs picks the traversal octant by sign but divides
        // by the component, and 1 / -0.0 = -inf then skips boxes (an exactly axis-parallel ray
        // such as (-0, -1, -0) missed a flat floor)
        let d = Vec3A::from(ray.dir) + Vec3A::ZERO;
        let (s, inv) = (self.to_bvh, 1.0 / self.to_bvh);
        let oray = obvhs::ray::Ray::new(o * s, d, 0.0, ray.t_max * s);
        let mut rh = RayHit::none();
        let mut best: Option<Hit> = None;
        // triangles are intersected in world space; the traversal sees distances times s
        bvh.ray_traverse(oray, &mut rh, |r, id| match self.geom[id].intersect(o, d, 0.0, r.tmax * inv) {
            Some((t, b1, b2)) => {
                best = Some(Hit { prim: id as u32, t, b1, b2 });
                t * s
            }
            None => f32::INFINITY,
        });
        best
    }

    /// True when something blocks the segment from `ray.origin` up to (excluding) `ray.t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let Some(bvh) = self.bvh.as_ref() else { return false };
        let o = Vec3A::from(ray.origin);
        let d = Vec3A::from(ray.dir) + Vec3A::ZERO; // no -0.0 (see `intersect`)
        let (s, inv) = (self.to_bvh, 1.0 / self.to_bvh);
        let oray = obvhs::ray::Ray::new(o * s, d, 0.0, ray.t_max * s);
        !bvh.ray_traverse_miss(oray, |r, id| match self.geom[id].intersect(o, d, 0.0, r.tmax * inv) {
            Some((t, _, _)) => t * s,
            None => f32::INFINITY,
        })
    }

    /// The world -> traversal scale.
    pub fn traversal_scale(&self) -> f32 {
        self.to_bvh
    }

    /// Bytes used by the BVH nodes, index list and triangle data.
    pub fn memory_bytes(&self) -> usize {
        let bvh = self
            .bvh
            .as_ref()
            .map_or(0, |b| b.nodes.len() * std::mem::size_of_val(&b.nodes[0]) + b.primitive_indices.len() * 4);
        bvh + self.geom.len() * std::mem::size_of::<TriangleGeom>()
            + self.info.len() * std::mem::size_of::<TriangleInfo>()
    }
}
