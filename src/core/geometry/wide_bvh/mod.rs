//! A four-wide BVH for CPU traversal: every node holds the bounds of up to four children in
//! structure-of-arrays form, tested against a ray in one `wide::f32x4` operation per slab, and
//! every leaf holds one or more [`Triangle4`] packets tested four triangles at once (the layout
//! of Embree's BVH4 + triangle4; Wald et al., "Embree: a kernel framework for efficient CPU ray
//! tracing", 2014). The topology comes from obvhs' PLOC builder ([`build`]).
//!
//! Box tests are conservative (pbrt-v4 section 6.8.2: the far distance is enlarged by 1 + 2
//! gamma(3)), triangle tests are the exact scalar Moeller-Trumbore test per lane, so the BVH
//! finds exactly the hits a test of every triangle would.

mod build;
mod triangle4;

use std::mem::MaybeUninit;

use glam::Vec3A;
use wide::{CmpLe, f32x4};

use super::ray::gamma;
pub(crate) use build::build;
use triangle4::{RayLanes, Triangle4};

/// A link to a child: an inner node's index, or a leaf's packet range, or nothing.
///
/// Bit 31 set marks a leaf: bits 27..31 hold the number of packets minus one (1 to 16 packets)
/// and bits 0..27 the first packet's index.
type Link = u32;

const LEAF: Link = 1 << 31;
const EMPTY: Link = u32::MAX;
/// Most packets in one leaf.
const MAX_LEAF_PACKETS: usize = 16;
/// Largest first-packet index a leaf link can hold.
const MAX_PACKET_INDEX: usize = (1 << 27) - 1;

#[inline(always)]
fn leaf_link(first: usize, count: usize) -> Link {
    debug_assert!((1..=MAX_LEAF_PACKETS).contains(&count) && first <= MAX_PACKET_INDEX);
    LEAF | (((count - 1) as u32) << 27) | first as u32
}

#[inline(always)]
fn leaf_range(link: Link) -> std::ops::Range<usize> {
    let first = (link & ((1 << 27) - 1)) as usize;
    first..first + ((link >> 27) & 0xf) as usize + 1
}

/// An inner node: the bounds of four children (lo x, lo y, lo z, hi x, hi y, hi z, one lane per
/// child; an unused slot has lo = hi = +inf, which no ray enters) and their links.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node4 {
    bounds: [f32x4; 6],
    link: [Link; 4],
}

/// The largest ray distance traversed: finite even after the slab test's conservative
/// enlargement (which an unused slot needs, see [`SlabRay::enter`]), and far beyond any scene
/// (coordinates are at most `MAX_COORDINATE` = 1e15).
const T_LIMIT: f32 = 1e38;

/// Entries of the traversal stack that fit the common case without a heap allocation.
const STACK: usize = 256;

/// The per-ray constants of the slab test: origin and (clamped) inverse direction per axis.
struct SlabRay {
    o: [f32x4; 3],
    inv: [f32x4; 3],
}

impl SlabRay {
    #[inline(always)]
    fn new(o: Vec3A, d: Vec3A) -> Self {
        // a zero or tiny component would make (bound - o) * inv a NaN (0 * inf); +-1e-30 keeps
        // the product finite or a correctly signed infinity
        let tiny = Vec3A::splat(1e-30);
        let inv = Vec3A::ONE / Vec3A::select(d.abs().cmplt(tiny), tiny.copysign(d), d);
        Self {
            o: [f32x4::splat(o.x), f32x4::splat(o.y), f32x4::splat(o.z)],
            inv: [f32x4::splat(inv.x), f32x4::splat(inv.y), f32x4::splat(inv.z)],
        }
    }

    /// The children of `node` the ray enters at t in [0, t_max] (bit mask) and their entry
    /// distances. `t_max` must be finite: an unused slot (a point at +infinity) is then never
    /// entered (its entry distance is +infinity on an axis the ray travels up, and its exit
    /// distance -infinity when it travels down on every axis).
    #[inline(always)]
    fn enter(&self, node: &Node4, t_max: f32) -> (u32, f32x4) {
        let b = &node.bounds;
        let slab = |axis: usize| {
            let (t0, t1) = ((b[axis] - self.o[axis]) * self.inv[axis], (b[axis + 3] - self.o[axis]) * self.inv[axis]);
            (t0.fast_min(t1), t0.fast_max(t1))
        };
        let ((nx, fx), (ny, fy), (nz, fz)) = (slab(0), slab(1), slab(2));
        let t_near = nx.fast_max(ny).fast_max(nz.fast_max(f32x4::ZERO));
        let t_far = fx.fast_min(fy).fast_min(fz.fast_min(f32x4::splat(t_max))) * f32x4::splat(1.0 + 2.0 * gamma(3));
        (t_near.cmp_le(t_far).move_mask() as u32, t_near)
    }
}

/// The BVH: inner nodes, leaf packets and the root link.
pub(crate) struct WideBvh {
    nodes: Vec<Node4>,
    packets: Vec<Triangle4>,
    root: Link,
    /// Most stack entries a traversal can need (3 per inner node on the deepest path, plus 1).
    stack_bound: usize,
}

impl WideBvh {
    /// The nearest hit of o + t d (unit or not) at t in (0, `t_max`): (triangle index, t, b1, b2).
    #[inline(always)]
    pub(crate) fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Option<(u32, f32, f32, f32)> {
        if self.root == EMPTY {
            return None;
        }
        if self.stack_bound <= STACK {
            let mut stack = [MaybeUninit::<(Link, f32)>::uninit(); STACK];
            self.nearest(o, d, t_max, &mut stack)
        } else {
            let mut stack = vec![MaybeUninit::<(Link, f32)>::uninit(); self.stack_bound];
            self.nearest(o, d, t_max, &mut stack)
        }
    }

    /// True when o + t d hits a triangle at t in (0, `t_max`).
    #[inline(always)]
    pub(crate) fn occluded(&self, o: Vec3A, d: Vec3A, t_max: f32) -> bool {
        if self.root == EMPTY {
            return false;
        }
        if self.stack_bound <= STACK {
            let mut stack = [MaybeUninit::<Link>::uninit(); STACK];
            self.any(o, d, t_max, &mut stack)
        } else {
            let mut stack = vec![MaybeUninit::<Link>::uninit(); self.stack_bound];
            self.any(o, d, t_max, &mut stack)
        }
    }

    #[inline(always)]
    fn nearest(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_max: f32,
        stack: &mut [MaybeUninit<(Link, f32)>],
    ) -> Option<(u32, f32, f32, f32)> {
        let lanes = RayLanes::new(o, d);
        let slabs = SlabRay::new(o, d);
        let mut best_t = t_max.min(T_LIMIT);
        let mut best = None;
        let mut sp = 0usize;
        let mut link = self.root;
        loop {
            if link & LEAF == 0 {
                let node = &self.nodes[link as usize];
                let (mut mask, t_near) = slabs.enter(node, best_t);
                if mask != 0 {
                    let t_near = t_near.to_array();
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if mask == 0 {
                        link = node.link[first];
                        continue;
                    }
                    // two to four children: inserted above the stack's top in order of
                    // decreasing distance (insertion sort), so the nearest is popped next
                    let base = sp;
                    let mut k = first;
                    loop {
                        let e = (node.link[k], t_near[k]);
                        let mut j = sp;
                        // SAFETY (both reads): base <= j - 1 < sp, entries written above
                        while j > base && unsafe { stack[j - 1].assume_init_read() }.1 < e.1 {
                            stack[j] = stack[j - 1];
                            j -= 1;
                        }
                        stack[j].write(e);
                        sp += 1;
                        if mask == 0 {
                            break;
                        }
                        k = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                    }
                }
            } else {
                for p in &self.packets[leaf_range(link)] {
                    if let Some((lane, t, b1, b2)) = p.nearest(&lanes, best_t) {
                        best_t = t;
                        best = Some((p.prim[lane], t, b1, b2));
                    }
                }
            }
            // the next pushed child that the nearest hit so far does not hide
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                // SAFETY: entries below `sp` were written by the pushes above
                let (l, t_near) = unsafe { stack[sp].assume_init_read() };
                if t_near <= best_t * (1.0 + 2.0 * gamma(3)) {
                    link = l;
                    break;
                }
            }
        }
    }

    #[inline(always)]
    fn any(&self, o: Vec3A, d: Vec3A, t_max: f32, stack: &mut [MaybeUninit<Link>]) -> bool {
        let lanes = RayLanes::new(o, d);
        let slabs = SlabRay::new(o, d);
        let t_max = t_max.min(T_LIMIT);
        let mut sp = 0usize;
        let mut link = self.root;
        loop {
            if link & LEAF == 0 {
                let node = &self.nodes[link as usize];
                let (mut mask, _) = slabs.enter(node, t_max);
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    while mask != 0 {
                        let k = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        stack[sp].write(node.link[k]);
                        sp += 1;
                    }
                    link = node.link[first];
                    continue;
                }
            } else if self.packets[leaf_range(link)].iter().any(|p| p.any(&lanes, t_max)) {
                return true;
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            // SAFETY: entries below `sp` were written by the pushes above
            link = unsafe { stack[sp].assume_init_read() };
        }
    }

    /// Bytes held by nodes and packets.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node4>() + self.packets.len() * std::mem::size_of::<Triangle4>()
    }
}
