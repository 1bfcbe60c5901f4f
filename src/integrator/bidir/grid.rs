//! A uniform hash grid over visibility points (pbrt-v4 SPPM's grid): every point is entered in
//! each cell its gather sphere overlaps, so a photon looks up only the cell it landed in.

use glam::{IVec3, Vec3};
use rayon::prelude::*;

/// Spatial hash of visibility points with per-point radii, built once per iteration.
pub struct VisibilityGrid {
    origin: Vec3,
    inv_cell: f32,
    mask: u64,
    /// `starts[b]..starts[b + 1]` indexes `entries` for bucket b.
    starts: Vec<u32>,
    entries: Vec<u32>,
}

#[inline]
fn hash_cell(c: IVec3) -> u64 {
    let h = (c.x as u32 as u64).wrapping_mul(73_856_093)
        ^ (c.y as u32 as u64).wrapping_mul(19_349_663)
        ^ (c.z as u32 as u64).wrapping_mul(83_492_791);
    crate::core::sampling::mix64(h)
}

/// Points per parallel task of the grid build.
const GRID_CHUNK: usize = 2048;

/// The largest number of cells one point may be entered in, per axis (keeps outliers with huge
/// radii from blowing the grid up; their cell range is exact, only the cell size adapts).
const MAX_CELLS_PER_AXIS: f32 = 8.0;

impl VisibilityGrid {
    /// Builds the grid over `points` (position, radius) for point indices `0..points.len()`;
    /// points with a radius that is not finite and > 0 are left out. Deterministic: entries of
    /// a bucket are in point order.
    pub fn build(points: &[(Vec3, f32)]) -> Self {
        let mut grid = Self::empty();
        grid.rebuild(points);
        grid
    }

    /// A grid over no points.
    pub fn empty() -> Self {
        Self { origin: Vec3::ZERO, inv_cell: 1.0, mask: 0, starts: vec![0, 0], entries: Vec::new() }
    }

    /// [`build`](Self::build) into this grid's tables (an iteration reuses the last one's).
    pub fn rebuild(&mut self, points: &[(Vec3, f32)]) {
        let mut radii: Vec<f32> = points.iter().map(|p| p.1).filter(|r| r.is_finite() && *r > 0.0).collect();
        if radii.is_empty() {
            (self.origin, self.inv_cell, self.mask) = (Vec3::ZERO, 1.0, 0);
            self.starts.clear();
            self.starts.extend([0, 0]);
            self.entries.clear();
            return;
        }
        let mid = radii.len() / 2;
        let median = *radii.select_nth_unstable_by(mid, f32::total_cmp).1;
        let max = radii.iter().copied().fold(0.0f32, f32::max);
        let cell = (2.0 * median).max(2.0 * max / MAX_CELLS_PER_AXIS);
        let mut lo = Vec3::splat(f32::INFINITY);
        for (p, r) in points {
            if r.is_finite() && *r > 0.0 {
                lo = lo.min(*p - Vec3::splat(*r));
            }
        }
        let inv_cell = 1.0 / cell;
        let buckets = (points.len() * 2).next_power_of_two().max(16) as u64;
        let mask = buckets - 1;
        // (bucket, point) pairs, each point once per distinct bucket, in point order: chunks of
        // points in parallel, concatenated in chunk order
        let chunks: Vec<Vec<(u32, u32)>> = points
            .par_chunks(GRID_CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let mut pairs = Vec::with_capacity(chunk.len() * 4);
                let mut mine: Vec<u32> = Vec::new();
                for (j, (p, r)) in chunk.iter().enumerate() {
                    if !(r.is_finite() && *r > 0.0) {
                        continue;
                    }
                    let a = ((*p - Vec3::splat(*r) - lo) * inv_cell).floor().as_ivec3();
                    let b = ((*p + Vec3::splat(*r) - lo) * inv_cell).floor().as_ivec3();
                    mine.clear();
                    for z in a.z..=b.z {
                        for y in a.y..=b.y {
                            for x in a.x..=b.x {
                                mine.push((hash_cell(IVec3::new(x, y, z)) & mask) as u32);
                            }
                        }
                    }
                    mine.sort_unstable();
                    mine.dedup();
                    let i = (c * GRID_CHUNK + j) as u32;
                    pairs.extend(mine.iter().map(|&bk| (bk, i)));
                }
                pairs
            })
            .collect();
        // counting sort by bucket, stable in point order (`starts` counts, then fills)
        let starts = &mut self.starts;
        starts.clear();
        starts.resize(buckets as usize + 1, 0);
        for &(bk, _) in chunks.iter().flatten() {
            starts[bk as usize + 1] += 1;
        }
        for k in 0..buckets as usize {
            starts[k + 1] += starts[k];
        }
        self.entries.clear();
        self.entries.resize(starts[buckets as usize] as usize, 0);
        for &(bk, i) in chunks.iter().flatten() {
            let fill = &mut starts[bk as usize];
            self.entries[*fill as usize] = i;
            *fill += 1;
        }
        // each bucket's fill ended at the next one's start: shift back
        for k in (1..=buckets as usize).rev() {
            starts[k] = starts[k - 1];
        }
        starts[0] = 0;
        (self.origin, self.inv_cell, self.mask) = (lo, inv_cell, mask);
    }

    /// Indices of the points whose cells include the cell of `p` (a superset of the points
    /// within their radius of `p`; the caller checks the distance).
    #[inline]
    pub fn candidates(&self, p: Vec3) -> &[u32] {
        if self.entries.is_empty() {
            return &[];
        }
        let c = ((p - self.origin) * self.inv_cell).floor();
        if !c.is_finite() {
            return &[];
        }
        let b = (hash_cell(c.as_ivec3()) & self.mask) as usize;
        &self.entries[self.starts[b] as usize..self.starts[b + 1] as usize]
    }

    /// Bytes used by the grid's tables.
    pub fn memory_bytes(&self) -> usize {
        (self.starts.len() + self.entries.len()) * 4
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::sampling::Sampler;

    #[test]
    fn every_point_within_its_radius_is_a_candidate() {
        let mut s = Sampler::new(1, 2, 3);
        let points: Vec<(Vec3, f32)> = (0..2000)
            .map(|_| (Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 10.0, 0.05 + 0.5 * s.get_1d()))
            .collect();
        let grid = VisibilityGrid::build(&points);
        for _ in 0..2000 {
            let q = Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 10.0;
            let cand = grid.candidates(q);
            // no duplicates in a bucket
            let mut sorted = cand.to_vec();
            sorted.dedup();
            assert_eq!(sorted.len(), cand.len());
            for (i, (p, r)) in points.iter().enumerate() {
                if (q - *p).length() <= *r {
                    assert!(cand.contains(&(i as u32)), "point {i} missing");
                }
            }
        }
    }

    #[test]
    fn bad_radii_are_left_out() {
        let grid = VisibilityGrid::build(&[(Vec3::ZERO, f32::NAN), (Vec3::ONE, 0.0), (Vec3::ZERO, 1.0)]);
        assert_eq!(grid.candidates(Vec3::ZERO), &[2]);
        assert!(VisibilityGrid::build(&[]).candidates(Vec3::ZERO).is_empty());
    }
}
