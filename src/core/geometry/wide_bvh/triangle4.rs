//! Four triangles tested against one ray at once: Moeller-Trumbore in structure-of-arrays form
//! over `wide::f32x4` lanes (SSE on x86-64, NEON on aarch64, scalar elsewhere).
//!
//! Every lane performs exactly the operations of the scalar [`TriangleGeom::intersect`] in the
//! same order (glam's cross and dot products: `a.y*b.z - a.z*b.y`, `(x*x' + y*y') + z*z'`), so
//! a lane's t and barycentrics are bit for bit the scalar test's and a ray hits the same
//! triangles through the wide BVH as through a triangle-by-triangle test.

use glam::Vec3A;
use wide::{CmpGe, CmpGt, CmpLe, CmpLt, f32x4};

use crate::core::geometry::TriangleGeom;

/// A ray splatted across four lanes.
#[derive(Clone, Copy, Debug)]
pub(super) struct RayLanes {
    o: [f32x4; 3],
    d: [f32x4; 3],
}

impl RayLanes {
    /// The ray o + t d in every lane.
    #[inline(always)]
    pub(super) fn new(o: Vec3A, d: Vec3A) -> Self {
        Self {
            o: [f32x4::splat(o.x), f32x4::splat(o.y), f32x4::splat(o.z)],
            d: [f32x4::splat(d.x), f32x4::splat(d.y), f32x4::splat(d.z)],
        }
    }
}

/// Up to four triangles, one per lane: first vertex, the two edges from it, as in
/// [`TriangleGeom`], and their cross product (the unnormalised geometric normal, which
/// [`TriangleGeom::intersect`] computes per test); an unused lane holds a degenerate triangle
/// (zero edges), which no ray hits.
#[derive(Clone, Copy, Debug)]
pub(super) struct Triangle4 {
    v0: [f32x4; 3],
    e1: [f32x4; 3],
    e2: [f32x4; 3],
    /// e1 x e2.
    n: [f32x4; 3],
    /// The triangles' indices (an unused lane repeats the first).
    pub(super) prim: [u32; 4],
}

#[inline(always)]
fn cross(a: &[f32x4; 3], b: &[f32x4; 3]) -> [f32x4; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

#[inline(always)]
fn dot(a: &[f32x4; 3], b: &[f32x4; 3]) -> f32x4 {
    (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]
}

impl Triangle4 {
    /// Packs one to four triangles `(index, geometry)`.
    pub(super) fn pack(tris: &[(u32, TriangleGeom)]) -> Self {
        assert!((1..=4).contains(&tris.len()), "a packet holds one to four triangles");
        let lane = |k: usize| tris.get(k).copied();
        let first = tris[0].0;
        let field = |f: &dyn Fn(&TriangleGeom) -> Vec3A| -> [f32x4; 3] {
            let v: [Vec3A; 4] = std::array::from_fn(|k| lane(k).map_or(Vec3A::ZERO, |(_, g)| f(&g)));
            [0, 1, 2].map(|a| f32x4::new([v[0][a], v[1][a], v[2][a], v[3][a]]))
        };
        Self {
            v0: field(&|g| g.v0),
            e1: field(&|g| g.e1),
            e2: field(&|g| g.e2),
            n: field(&|g| g.e1.cross(g.e2)),
            prim: std::array::from_fn(|k| lane(k).map_or(first, |(i, _)| i)),
        }
    }

    /// The lanes whose triangle the ray hits at t in (0, `t_max`), as a bit mask (bit k = lane
    /// k), with |det| and the numerators of t, b1 and b2 per lane (det's sign folded in; each
    /// divided by |det| is the value: meaningful only in the hit lanes).
    #[inline(always)]
    fn hits(&self, ray: &RayLanes, t_max: f32) -> (u32, f32x4, f32x4, f32x4, f32x4) {
        let zero = f32x4::ZERO;
        let s = [ray.o[0] - self.v0[0], ray.o[1] - self.v0[1], ray.o[2] - self.v0[2]];
        let r = cross(&s, &ray.d);
        let det = -dot(&ray.d, &self.n);
        // det's sign bit, folded into the numerators so that the tests need no division
        let sign = det & f32x4::splat(-0.0);
        let abs_det = det ^ sign;
        let b1 = dot(&self.e2, &r) ^ sign;
        let b2 = -dot(&self.e1, &r) ^ sign;
        let t = dot(&s, &self.n) ^ sign;
        let ok = abs_det.cmp_gt(zero)
            & abs_det.is_finite()
            & b1.cmp_ge(zero)
            & b2.cmp_ge(zero)
            & (b1 + b2).cmp_le(abs_det)
            & t.cmp_gt(zero)
            & t.cmp_lt(abs_det * f32x4::splat(t_max));
        (ok.move_mask() as u32, abs_det, t, b1, b2)
    }

    /// The nearest hit among the four triangles at t in (0, `t_max`): (lane, t, b1, b2). Ties go
    /// to the lowest lane. Only a packet with a hit divides, and only the nearest lane's
    /// barycentrics are scaled.
    #[inline(always)]
    pub(super) fn nearest(&self, ray: &RayLanes, t_max: f32) -> Option<(usize, f32, f32, f32)> {
        let (mut mask, abs_det, t, b1, b2) = self.hits(ray, t_max);
        if mask == 0 {
            return None;
        }
        let inv = f32x4::ONE / abs_det;
        let t = (t * inv).to_array();
        let inv = inv.to_array();
        let mut best = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        while mask != 0 {
            let k = mask.trailing_zeros() as usize;
            if t[k] < t[best] {
                best = k;
            }
            mask &= mask - 1;
        }
        Some((best, t[best], b1.to_array()[best] * inv[best], b2.to_array()[best] * inv[best]))
    }

    /// True when the ray hits any of the four triangles at t in (0, `t_max`).
    #[inline(always)]
    pub(super) fn any(&self, ray: &RayLanes, t_max: f32) -> bool {
        self.hits(ray, t_max).0 != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::sampling::{Sampler, uniform_sphere};
    use glam::Vec3;

    #[test]
    fn lanes_agree_bit_for_bit_with_the_scalar_test() {
        let mut s = Sampler::new(7, 1, 2);
        let mut hits = 0;
        for round in 0..4000 {
            let tris: Vec<(u32, TriangleGeom)> = (0..1 + round % 4)
                .map(|k| {
                    let c = Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 2.0 - 1.0;
                    let scale = 0.1 + s.get_1d();
                    let v = |s: &mut Sampler| c + uniform_sphere(s.get_2d()) * scale;
                    let (a, b, d) = (v(&mut s), v(&mut s), v(&mut s));
                    (k as u32 + 10, TriangleGeom::new(a, b, d))
                })
                .collect();
            let packet = Triangle4::pack(&tris);
            // most rays aimed at a point of a triangle (a few of them just past its edges)
            let o = Vec3A::from(uniform_sphere(s.get_2d()) * 3.0);
            let g = &tris[(s.get_1d() * tris.len() as f32) as usize % tris.len()].1;
            let (u, v) = (s.get_1d() * 1.1, s.get_1d() * 1.1);
            let target =
                if u + v <= 1.1 { g.v0 + g.e1 * u + g.e2 * v } else { g.v0 + g.e1 * (1.1 - v) + g.e2 * (1.1 - u) };
            let d = (target - o).normalize();
            let t_max = if round % 3 == 0 { 2.5 } else { f32::INFINITY };
            let ray = RayLanes::new(o, d);
            let scalar = tris
                .iter()
                .enumerate()
                .filter_map(|(k, (_, g))| g.intersect(o, d, 0.0, t_max).map(|h| (k, h)))
                .fold(None::<(usize, (f32, f32, f32))>, |best, (k, h)| match best {
                    Some((_, b)) if b.0 <= h.0 => best,
                    _ => Some((k, h)),
                });
            let wide = packet.nearest(&ray, t_max);
            match (scalar, wide) {
                (None, None) => {}
                (Some((k, (t, b1, b2))), Some((kw, tw, b1w, b2w))) => {
                    hits += 1;
                    assert_eq!(
                        (k, t.to_bits(), b1.to_bits(), b2.to_bits()),
                        (kw, tw.to_bits(), b1w.to_bits(), b2w.to_bits())
                    );
                    assert_eq!(packet.prim[kw], tris[k].0);
                }
                other => panic!("round {round}: scalar and wide disagree: {other:?}"),
            }
            assert_eq!(packet.any(&ray, t_max), scalar.is_some());
        }
        assert!(hits > 2000, "only {hits} hits");
    }

    #[test]
    fn unused_lanes_are_never_hit() {
        let g = TriangleGeom::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        let packet = Triangle4::pack(&[(3, g)]);
        assert_eq!(packet.prim, [3; 4]);
        // a ray through the origin, where the zero-edge lanes sit
        let ray = RayLanes::new(Vec3A::new(0.0, 0.0, 1.0), Vec3A::new(0.0, 0.0, -1.0));
        let (lane, t, _, _) = packet.nearest(&ray, f32::INFINITY).unwrap();
        assert_eq!((lane, t), (0, 1.0));
        let ray = RayLanes::new(Vec3A::new(5.0, 0.0, 1.0), Vec3A::new(0.0, 0.0, -1.0));
        assert!(packet.nearest(&ray, f32::INFINITY).is_none());
    }
}
