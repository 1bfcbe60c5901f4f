//! A binary BVH traversed by W rays at once.

use super::*;

/// A binary BVH over the scene's triangles for the probe's packet traversal (median splits,
/// leaves of at most four triangles): W rays visit a node together when any of them enters it,
/// and a leaf's triangles are tested against all W rays at once (ray-parallel SIMD, the way
/// Embree's packet traversal serves `rtcIntersect16`).
pub(crate) struct PacketBvh {
    /// Per node: bounds and either (first child, 0) or (first triangle, count).
    pub(crate) nodes: Vec<([f32; 3], [f32; 3], u32, u32)>,
    /// Per triangle (in leaf order): v0, e1, e2, e1 x e2, index in the scene.
    pub(crate) tris: Vec<(Vec3, Vec3, Vec3, Vec3, u32)>,
}

impl PacketBvh {
    /// The BVH of `scene`'s triangles.
    pub(crate) fn new(scene: &Scene) -> Self {
        let geom = &scene.accel.geom;
        let mut idx: Vec<u32> = (0..geom.len() as u32).collect();
        let mut bvh = Self { nodes: vec![([0.0; 3], [0.0; 3], 0, 0)], tris: Vec::new() };
        bvh.build(scene, 0, &mut idx);
        bvh
    }

    /// Fills `node` with the bounds of triangles `idx`: a leaf of up to four, else two children
    /// split at the median centroid along the widest axis.
    fn build(&mut self, scene: &Scene, node: usize, idx: &mut [u32]) {
        let g = |i: u32| &scene.accel.geom[i as usize];
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for &i in idx.iter() {
            let t = g(i);
            for v in [t.v0, t.v0 + t.e1, t.v0 + t.e2] {
                lo = lo.min(Vec3::from(v));
                hi = hi.max(Vec3::from(v));
            }
        }
        if idx.len() <= 4 {
            self.nodes[node] = (lo.to_array(), hi.to_array(), self.tris.len() as u32, idx.len() as u32);
            for &i in idx.iter() {
                let t = g(i);
                let (e1, e2) = (Vec3::from(t.e1), Vec3::from(t.e2));
                self.tris.push((Vec3::from(t.v0), e1, e2, e1.cross(e2), i));
            }
            return;
        }
        let axis = (hi - lo).max_position();
        let c = |i: u32| {
            let t = g(i);
            (t.v0 * 3.0 + t.e1 + t.e2)[axis]
        };
        idx.sort_by(|&a, &b| c(a).total_cmp(&c(b)));
        let first = self.nodes.len();
        self.nodes.push(([0.0; 3], [0.0; 3], 0, 0));
        self.nodes.push(([0.0; 3], [0.0; 3], 0, 0));
        self.nodes[node] = (lo.to_array(), hi.to_array(), first as u32, 0);
        let (a, b) = idx.split_at_mut(idx.len() / 2);
        self.build(scene, first, a);
        self.build(scene, first + 1, b);
    }

    /// Lanes whose ray (o, d) enters node `n` at t in [0, t_max].
    #[inline(always)]
    fn enter<const W: usize>(&self, n: usize, o: &V<W>, inv: &V<W>, t_max: &L<W>, live: &[bool; W]) -> [bool; W] {
        let (lo, hi, _, _) = &self.nodes[n];
        let mut m = [false; W];
        for i in 0..W {
            let (x0, x1) = ((lo[0] - o.x[i]) * inv.x[i], (hi[0] - o.x[i]) * inv.x[i]);
            let (y0, y1) = ((lo[1] - o.y[i]) * inv.y[i], (hi[1] - o.y[i]) * inv.y[i]);
            let (z0, z1) = ((lo[2] - o.z[i]) * inv.z[i], (hi[2] - o.z[i]) * inv.z[i]);
            let near = x0.min(x1).max(y0.min(y1)).max(z0.min(z1)).max(0.0);
            let far = x0.max(x1).min(y0.max(y1)).min(z0.max(z1)).min(t_max[i]) * (1.0 + 4.0 * f32::EPSILON);
            m[i] = live[i] & (near <= far);
        }
        m
    }

    /// Per lane: whether the ray hits triangle `k` before `t_max`, and (t, b1, b2): the
    /// Moeller-Trumbore test of quasar's `Triangle4` per lane, with one division per lane (a
    /// form without it, which divides only for a triangle that some lane hits, measured slower).
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn hits<const W: usize>(&self, k: usize, o: &V<W>, d: &V<W>, t_max: &L<W>) -> ([bool; W], L<W>, L<W>, L<W>) {
        let (v0, e1, e2, n, _) = self.tris[k];
        let (mut m, mut tt, mut bb1, mut bb2) = ([false; W], [0.0; W], [0.0; W], [0.0; W]);
        for i in 0..W {
            let (sx, sy, sz) = (o.x[i] - v0.x, o.y[i] - v0.y, o.z[i] - v0.z);
            let (rx, ry, rz) = (sy * d.z[i] - sz * d.y[i], sz * d.x[i] - sx * d.z[i], sx * d.y[i] - sy * d.x[i]);
            let det = -(d.x[i] * n.x + d.y[i] * n.y + d.z[i] * n.z);
            let inv = 1.0 / det;
            let b1 = (e2.x * rx + e2.y * ry + e2.z * rz) * inv;
            let b2 = -(e1.x * rx + e1.y * ry + e1.z * rz) * inv;
            let t = (sx * n.x + sy * n.y + sz * n.z) * inv;
            m[i] = det != 0.0 && b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 && t > 0.0 && t < t_max[i];
            (tt[i], bb1[i], bb2[i]) = (t, b1, b2);
        }
        (m, tt, bb1, bb2)
    }

    /// The nearest hit of every live lane's ray: (scene triangle or NONE, t, b1, b2) per lane.
    #[allow(clippy::type_complexity)]
    pub(crate) fn nearest<const W: usize>(&self, o: &V<W>, d: &V<W>, live: &[bool; W]) -> ([u32; W], L<W>, L<W>, L<W>) {
        let inv = inverse_direction(d);
        let (mut prim, mut t_best, mut b1, mut b2) = ([NONE; W], [1e38f32; W], [0.0; W], [0.0; W]);
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let n = stack[sp] as usize;
            let m = self.enter(n, o, &inv, &t_best, live);
            if !m.iter().any(|&x| x) {
                continue;
            }
            let (_, _, first, count) = self.nodes[n];
            if count == 0 {
                // nearer child last (popped first), by the first entering lane's direction
                let lane = m.iter().position(|&x| x).unwrap_or(0);
                let (lo, hi, _, _) = &self.nodes[first as usize];
                let (lo2, hi2, _, _) = &self.nodes[first as usize + 1];
                let axis = (0..3)
                    .max_by(|&a, &b| {
                        (hi[a] + lo[a] - hi2[a] - lo2[a]).abs().total_cmp(&(hi[b] + lo[b] - hi2[b] - lo2[b]).abs())
                    })
                    .unwrap();
                let dir = [d.x[lane], d.y[lane], d.z[lane]][axis];
                let left_first = (hi[axis] + lo[axis] <= hi2[axis] + lo2[axis]) == (dir >= 0.0);
                let (a, b) = if left_first { (first + 1, first) } else { (first, first + 1) };
                stack[sp] = a;
                stack[sp + 1] = b;
                sp += 2;
            } else {
                for k in first as usize..(first + count) as usize {
                    let (h, t, u, v) = self.hits(k, o, d, &t_best);
                    let tri = self.tris[k].4;
                    for i in 0..W {
                        let h = h[i] & m[i];
                        t_best[i] = if h { t[i] } else { t_best[i] };
                        b1[i] = if h { u[i] } else { b1[i] };
                        b2[i] = if h { v[i] } else { b2[i] };
                        prim[i] = if h { tri } else { prim[i] };
                    }
                }
            }
        }
        (prim, t_best, b1, b2)
    }

    /// Per live lane: whether its ray is blocked before its `t_max`.
    pub(crate) fn occluded<const W: usize>(&self, o: &V<W>, d: &V<W>, t_max: &L<W>, live: &[bool; W]) -> [bool; W] {
        let inv = inverse_direction(d);
        let mut blocked = [false; W];
        let mut open = *live;
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let n = stack[sp] as usize;
            let m = self.enter(n, o, &inv, t_max, &open);
            if !m.iter().any(|&x| x) {
                continue;
            }
            let (_, _, first, count) = self.nodes[n];
            if count == 0 {
                stack[sp] = first;
                stack[sp + 1] = first + 1;
                sp += 2;
            } else {
                for k in first as usize..(first + count) as usize {
                    let (h, ..) = self.hits(k, o, d, t_max);
                    for i in 0..W {
                        blocked[i] |= h[i] & m[i];
                        open[i] &= !blocked[i];
                    }
                }
                if !open.iter().any(|&x| x) {
                    break;
                }
            }
        }
        blocked
    }
}

/// 1 / d per lane and axis, a tiny component clamped to +-1e-30 first (as quasar's `SlabRay`
/// does), so that the slab test's (bound - o) * inv never multiplies 0 by infinity.
#[inline(always)]
fn inverse_direction<const W: usize>(d: &V<W>) -> V<W> {
    let mut inv = V::<W>::ZERO;
    for i in 0..W {
        let f = |x: f32| 1.0 / if x.abs() < 1e-30 { 1e-30f32.copysign(x) } else { x };
        (inv.x[i], inv.y[i], inv.z[i]) = (f(d.x[i]), f(d.y[i]), f(d.z[i]));
    }
    inv
}
