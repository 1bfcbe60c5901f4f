//! Building the four-wide BVH: obvhs' PLOC builder (Meister & Bittner 2018, with reinsertion)
//! makes a binary tree, which is collapsed into four-wide nodes by opening, at each node, the
//! child of largest surface area until it has four children (Wald et al. 2008, "Getting rid of
//! packets"); every subtree of at most four triangles becomes one [`Triangle4`] leaf packet.
//!
//! The node bounds are recomputed from the triangles' own vertices (exact minima and maxima in
//! world space), so only the topology comes from the builder.

use std::time::Duration;

use glam::Vec3;
use obvhs::{BvhBuildParams, bvh2::builder::build_bvh2_from_tris, triangle::Triangle};
use wide::f32x4;

use super::{EMPTY, LEAF, Link, MAX_LEAF_PACKETS, MAX_PACKET_INDEX, Node4, Triangle4, WideBvh, leaf_link};
use crate::core::geometry::TriangleGeom;

/// Subtrees of at most this many triangles become one leaf.
const LEAF_TRIANGLES: usize = 4;

/// Bounds of a set of points.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    lo: Vec3,
    hi: Vec3,
}

impl Bounds {
    const EMPTY: Self = Self { lo: Vec3::INFINITY, hi: Vec3::NEG_INFINITY };

    fn union(self, o: Self) -> Self {
        Self { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    fn of_triangle(t: &[Vec3; 3]) -> Self {
        Self { lo: t[0].min(t[1]).min(t[2]), hi: t[0].max(t[1]).max(t[2]) }
    }

    /// Half the surface area (the SAH's measure of how often a random ray enters the box).
    fn half_area(&self) -> f32 {
        let e = (self.hi - self.lo).max(Vec3::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }
}

/// A binary node waiting to become a wide link: where the link goes (None = the root, else
/// (wide node, child slot)) and how many inner wide nodes lie above it.
struct Pending {
    node2: usize,
    slot: Option<(usize, usize)>,
    depth: usize,
}

/// Builds the BVH over `tris` (world space; `scale`: the power of two applied to the vertices
/// handed to the builder, which only affects its topology). Returns the BVH and the leaf order
/// of the triangles: `order[i]` is the input index of the triangle the BVH calls `i`.
pub(crate) fn build(tris: &[[Vec3; 3]], scale: f32, mut params: BvhBuildParams) -> (WideBvh, Vec<u32>) {
    let empty = WideBvh { nodes: Vec::new(), packets: Vec::new(), root: EMPTY, stack_bound: 0 };
    if tris.is_empty() {
        return (empty, Vec::new());
    }
    // a binary leaf becomes packets of four: keep leaves within one wide leaf's packets
    params.max_prims_per_leaf = params.max_prims_per_leaf.clamp(1, (LEAF_TRIANGLES * MAX_LEAF_PACKETS) as u32);
    let scaled: Vec<Triangle> = tris
        .iter()
        .map(|t| Triangle { v0: (t[0] * scale).into(), v1: (t[1] * scale).into(), v2: (t[2] * scale).into() })
        .collect();
    let bvh2 = build_bvh2_from_tris(&scaled, params, &mut Duration::default());
    drop(scaled);
    let nodes2 = &bvh2.nodes;
    let leaf_prims = |n: usize| {
        let f = nodes2[n].first_index as usize;
        &bvh2.primitive_indices[f..f + nodes2[n].prim_count as usize]
    };
    let children = |n: usize| [nodes2[n].first_index as usize, nodes2[n].first_index as usize + 1];

    // subtree triangle counts and exact bounds, children before parents
    let mut count = vec![0usize; nodes2.len()];
    let mut bounds = vec![Bounds::EMPTY; nodes2.len()];
    let mut post = Vec::with_capacity(nodes2.len());
    let mut todo = vec![0usize];
    while let Some(n) = todo.pop() {
        post.push(n);
        if nodes2[n].prim_count == 0 {
            todo.extend(children(n));
        }
    }
    for &n in post.iter().rev() {
        if nodes2[n].prim_count > 0 {
            let prims = leaf_prims(n);
            count[n] = prims.len();
            bounds[n] = prims.iter().fold(Bounds::EMPTY, |b, &p| b.union(Bounds::of_triangle(&tris[p as usize])));
        } else {
            let [a, b] = children(n);
            count[n] = count[a] + count[b];
            bounds[n] = bounds[a].union(bounds[b]);
        }
    }
    drop(post);

    let mut out = WideBvh { nodes: Vec::new(), packets: Vec::new(), root: EMPTY, stack_bound: 0 };
    let mut order: Vec<u32> = Vec::with_capacity(tris.len());
    let mut new_index = vec![u32::MAX; tris.len()];
    let mut work = vec![Pending { node2: 0, slot: None, depth: 0 }];
    while let Some(Pending { node2: n, slot, depth }) = work.pop() {
        let link = if nodes2[n].prim_count > 0 || count[n] <= LEAF_TRIANGLES {
            // the subtree's triangles, in tree order, as packets of four
            let mut prims = Vec::with_capacity(count[n]);
            let mut sub = vec![n];
            while let Some(m) = sub.pop() {
                if nodes2[m].prim_count > 0 {
                    prims.extend_from_slice(leaf_prims(m));
                } else {
                    let [a, b] = children(m);
                    sub.extend([b, a]);
                }
            }
            let first = out.packets.len();
            for chunk in prims.chunks(LEAF_TRIANGLES) {
                let lanes: Vec<(u32, TriangleGeom)> = chunk
                    .iter()
                    .map(|&p| {
                        let p = p as usize;
                        if new_index[p] == u32::MAX {
                            new_index[p] = order.len() as u32;
                            order.push(p as u32);
                        }
                        let t = &tris[p];
                        (new_index[p], TriangleGeom::new(t[0], t[1], t[2]))
                    })
                    .collect();
                out.packets.push(Triangle4::pack(&lanes));
            }
            assert!(first <= MAX_PACKET_INDEX, "more BVH leaf packets than a link can address");
            out.stack_bound = out.stack_bound.max(3 * depth + 1);
            leaf_link(first, out.packets.len() - first)
        } else {
            // open the largest inner child until there are four
            let mut kids: Vec<usize> = children(n).to_vec();
            while kids.len() < 4 {
                let open = kids
                    .iter()
                    .enumerate()
                    .filter(|&(_, &k)| nodes2[k].prim_count == 0 && count[k] > LEAF_TRIANGLES)
                    .max_by(|a, b| bounds[*a.1].half_area().total_cmp(&bounds[*b.1].half_area()))
                    .map(|(i, _)| i);
                let Some(i) = open else { break };
                let k = kids.swap_remove(i);
                kids.extend(children(k));
            }
            // free slots: split a small subtree (one packet's worth) into its two halves when
            // their boxes are smaller than the whole's (two walls of a room in one leaf have a
            // box as large as the room), largest saving first
            while kids.len() < 4 {
                let saving = |k: usize| {
                    let [a, b] = children(k);
                    bounds[k].half_area() - bounds[a].half_area() - bounds[b].half_area()
                };
                let open = kids
                    .iter()
                    .enumerate()
                    .filter(|&(_, &k)| nodes2[k].prim_count == 0 && saving(k) > 0.0)
                    .max_by(|a, b| saving(*a.1).total_cmp(&saving(*b.1)))
                    .map(|(i, _)| i);
                let Some(i) = open else { break };
                let k = kids.swap_remove(i);
                kids.extend(children(k));
            }
            let index = out.nodes.len();
            // an unused slot is a point at +infinity, which the slab test rejects for every ray
            // (the traversal's t_max is finite)
            let (mut lo, mut hi) = ([[f32::INFINITY; 4]; 3], [[f32::INFINITY; 4]; 3]);
            for (c, &k) in kids.iter().enumerate() {
                for axis in 0..3 {
                    lo[axis][c] = bounds[k].lo[axis];
                    hi[axis][c] = bounds[k].hi[axis];
                }
            }
            let lanes = [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]];
            out.nodes.push(Node4 { bounds: lanes.map(f32x4::new), link: [EMPTY; 4] });
            for (c, &k) in kids.iter().enumerate().rev() {
                work.push(Pending { node2: k, slot: Some((index, c)), depth: depth + 1 });
            }
            index as Link
        };
        match slot {
            None => out.root = link,
            Some((parent, c)) => out.nodes[parent].link[c] = link,
        }
    }
    debug_assert!(out.nodes.len() < LEAF as usize);
    (out, order)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::sampling::{Sampler, uniform_sphere};
    use glam::Vec3A;

    /// The nearest hit by testing every triangle (ties to the lowest index).
    fn brute_force(tris: &[[Vec3; 3]], o: Vec3A, d: Vec3A, t_max: f32) -> Option<(usize, f32)> {
        tris.iter()
            .enumerate()
            .filter_map(|(i, t)| TriangleGeom::new(t[0], t[1], t[2]).intersect(o, d, 0.0, t_max).map(|h| (i, h.0)))
            .fold(
                None,
                |best: Option<(usize, f32)>, (i, t)| if best.is_some_and(|b| b.1 <= t) { best } else { Some((i, t)) },
            )
    }

    fn random_soup(n: usize, s: &mut Sampler) -> Vec<[Vec3; 3]> {
        (0..n)
            .map(|_| {
                let c = (Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 2.0 - 1.0) * 3.0;
                let r = 0.05 + 0.4 * s.get_1d();
                [0, 1, 2].map(|_| c + uniform_sphere(s.get_2d()) * r)
            })
            .collect()
    }

    #[test]
    fn finds_what_testing_every_triangle_finds() {
        let mut s = Sampler::new(3, 4, 5);
        for n in [1usize, 2, 3, 4, 5, 7, 16, 33, 200, 3000] {
            let tris = random_soup(n, &mut s);
            let (bvh, order) = build(&tris, 1.0, BvhBuildParams::medium_build());
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..n as u32).collect::<Vec<_>>(), "every triangle once");
            assert!(bvh.stack_bound <= super::super::STACK, "{n}: stack bound {}", bvh.stack_bound);
            for k in 0..2000 {
                let o = Vec3A::from(uniform_sphere(s.get_2d()) * 6.0 * s.get_1d());
                let d = Vec3A::from(uniform_sphere(s.get_2d()));
                let t_max = if k % 4 == 0 { 3.0 } else { f32::INFINITY };
                let want = brute_force(&tris, o, d, t_max);
                let got = bvh.intersect(o, d, t_max);
                match (want, got) {
                    (None, None) => {}
                    (Some((i, t)), Some((p, tg, _, _))) => {
                        assert_eq!(t.to_bits(), tg.to_bits(), "{n} triangles, ray {k}");
                        // an exact tie may pick another triangle at the same distance
                        let tp = &tris[order[p as usize] as usize];
                        let tt = TriangleGeom::new(tp[0], tp[1], tp[2]).intersect(o, d, 0.0, t_max).unwrap().0;
                        assert_eq!(tt.to_bits(), t.to_bits(), "{n} triangles, ray {k}: hit {i}");
                    }
                    other => panic!("{n} triangles, ray {k}: {other:?}"),
                }
                assert_eq!(bvh.occluded(o, d, t_max), want.is_some(), "{n} triangles, ray {k}");
            }
        }
    }

    #[test]
    fn axis_parallel_rays_and_rays_along_box_faces_are_not_lost() {
        // a floor made of a grid of quads; rays exactly along the axes, from points on box faces
        let mut tris = Vec::new();
        for i in 0..8 {
            for j in 0..8 {
                let (x, z) = (i as f32, j as f32);
                let (a, b, c, d) = (
                    Vec3::new(x, 0.0, z),
                    Vec3::new(x + 1.0, 0.0, z),
                    Vec3::new(x + 1.0, 0.0, z + 1.0),
                    Vec3::new(x, 0.0, z + 1.0),
                );
                tris.push([a, b, c]);
                tris.push([a, c, d]);
            }
        }
        let (bvh, _) = build(&tris, 1.0, BvhBuildParams::medium_build());
        for i in 0..=16 {
            for j in 0..=16 {
                let (x, z) = (0.01 + i as f32 * 0.5, 0.01 + j as f32 * 0.49);
                for d in [Vec3A::new(0.0, -1.0, 0.0), Vec3A::new(-0.0, -1.0, -0.0)] {
                    let o = Vec3A::new(x, 1.0, z);
                    let inside = x < 8.0 && z < 8.0;
                    assert_eq!(bvh.intersect(o, d, f32::INFINITY).is_some(), inside, "({x}, {z})");
                    assert_eq!(bvh.occluded(o, d, f32::INFINITY), inside, "({x}, {z})");
                }
            }
        }
        // a ray lying in the floor's plane does not hit it; one just above along +x misses too
        assert!(bvh.intersect(Vec3A::new(-1.0, 0.0, 0.5), Vec3A::X, f32::INFINITY).is_none());
        assert!(bvh.intersect(Vec3A::new(-1.0, 1e-3, 0.5), Vec3A::X, f32::INFINITY).is_none());
    }

    #[test]
    fn deep_trees_fall_back_to_a_heap_stack() {
        // rays are checked with a bound forced above the fixed stack
        let mut s = Sampler::new(9, 9, 9);
        let tris = random_soup(500, &mut s);
        let (mut bvh, _) = build(&tris, 1.0, BvhBuildParams::medium_build());
        let fixed: Vec<_> = (0..200)
            .map(|_| (Vec3A::from(uniform_sphere(s.get_2d()) * 5.0), Vec3A::from(uniform_sphere(s.get_2d()))))
            .collect();
        let before: Vec<_> = fixed.iter().map(|&(o, d)| bvh.intersect(o, d, f32::INFINITY)).collect();
        bvh.stack_bound = super::super::STACK + 1;
        let after: Vec<_> = fixed.iter().map(|&(o, d)| bvh.intersect(o, d, f32::INFINITY)).collect();
        assert_eq!(before, after);
    }
}
