//! A uniform hash grid over visibility points (pbrt-v4 SPPM's grid): every point is entered in
//! each cell the box around its gather region overlaps, so a photon looks up only the cell it
//! landed in.

use glam::{IVec3, Vec3};
use rayon::prelude::*;

use super::ranges::{ByRange, for_each_part};

/// What the grid indexes: the region around a point from which it gathers photons, as a radius
/// (the cells are sized by the median radius) and a box around the point holding the region.
pub trait GatherRegion: Sync {
    /// The point, the region's radius, and the half extents of the box centred on the point that
    /// holds every position the region accepts (at most the radius on every axis).
    fn centre_radius_extent(&self) -> (Vec3, f32, Vec3);
}

/// A ball: centre and radius.
impl GatherRegion for (Vec3, f32) {
    #[inline]
    fn centre_radius_extent(&self) -> (Vec3, f32, Vec3) {
        (self.0, self.1, Vec3::splat(self.1))
    }
}

/// Spatial hash of visibility points with per-point radii, built once per iteration.
pub struct VisibilityGrid {
    origin: Vec3,
    inv_cell: f32,
    mask: u64,
    /// `starts[b]..starts[b + 1]` indexes `entries` for bucket b.
    starts: Vec<u32>,
    entries: Vec<u32>,
    /// The build's working lists, kept for the next build.
    lists: BuildLists,
}

/// The working lists of [`VisibilityGrid::rebuild`].
#[derive(Default)]
struct BuildLists {
    /// The valid radii (for their median).
    radii: Vec<f32>,
    /// Per chunk of points: its (bucket, point) pairs grouped by bucket range.
    chunks: Vec<ByRange<(u32, u32)>>,
    /// Where each bucket range's entries start (one more entry than ranges).
    range_start: Vec<usize>,
}

/// A chunk's (bucket, point) pairs in point order before they are grouped by bucket range,
/// and the distinct buckets of the point being entered: one pair of lists per thread, kept, so
/// that only the grouped pairs stay allocated per chunk.
struct ChunkLists {
    pairs: Vec<(u32, u32)>,
    mine: Vec<u32>,
}

thread_local! {
    static CHUNK_LISTS: std::cell::RefCell<ChunkLists> =
        const { std::cell::RefCell::new(ChunkLists { pairs: Vec::new(), mine: Vec::new() }) };
}

#[inline]
fn hash_cell(c: IVec3) -> u64 {
    let h = (c.x as u32 as u64).wrapping_mul(73_856_093)
        ^ (c.y as u32 as u64).wrapping_mul(19_349_663)
        ^ (c.z as u32 as u64).wrapping_mul(83_492_791);
    crate::core::sampling::mix64(h)
}

/// Points per parallel task of the grid build (small: points far from the camera have large
/// radii and enter many more cells than near ones, so large chunks balance badly).
const GRID_CHUNK: usize = 256;

/// Bucket ranges sorted in parallel by the grid build (fewer when there are fewer buckets).
const BUCKET_RANGES: u64 = 64;

/// The largest number of cells one point may be entered in, per axis (keeps outliers with huge
/// radii from blowing the grid up; their cell range is exact, only the cell size adapts).
const MAX_CELLS_PER_AXIS: f32 = 8.0;

impl VisibilityGrid {
    /// Builds the grid over the gather regions `points` for point indices `0..points.len()`;
    /// points with a radius that is not finite and > 0 are left out. Deterministic: entries of
    /// a bucket are in point order.
    pub fn build<P: GatherRegion>(points: &[P]) -> Self {
        let mut grid = Self::empty();
        grid.rebuild(points);
        grid
    }

    /// A grid over no points.
    pub fn empty() -> Self {
        Self {
            origin: Vec3::ZERO,
            inv_cell: 1.0,
            mask: 0,
            starts: vec![0, 0],
            entries: Vec::new(),
            lists: BuildLists::default(),
        }
    }

    /// [`build`](Self::build) into this grid's tables (an iteration reuses the last one's).
    pub fn rebuild<P: GatherRegion>(&mut self, points: &[P]) {
        let BuildLists { radii, chunks, range_start } = &mut self.lists;
        radii.clear();
        radii.extend(points.iter().map(|p| p.centre_radius_extent().1).filter(|r| r.is_finite() && *r > 0.0));
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
        for (p, r, e) in points.iter().map(P::centre_radius_extent) {
            if r.is_finite() && r > 0.0 {
                lo = lo.min(p - e);
            }
        }
        let inv_cell = 1.0 / cell;
        let buckets = (points.len() * 2).next_power_of_two().max(16) as u64;
        let mask = buckets - 1;
        // (bucket, point) pairs, each point once per distinct bucket, in point order, grouped
        // by bucket range: chunks of points in parallel
        let shift = buckets.trailing_zeros().saturating_sub(BUCKET_RANGES.trailing_zeros());
        let ranges = (buckets >> shift) as usize;
        chunks.resize_with(points.len().div_ceil(GRID_CHUNK), ByRange::default);
        chunks.par_iter_mut().zip(points.par_chunks(GRID_CHUNK)).enumerate().with_max_len(1).for_each(
            |(c, (grouped, chunk))| {
                // (a chunk starts no parallel work, so the thread's lists are not borrowed twice)
                CHUNK_LISTS.with_borrow_mut(|ChunkLists { pairs, mine }| {
                    pairs.clear();
                    pairs.reserve(chunk.len() * 8);
                    for (j, (p, r, e)) in chunk.iter().map(P::centre_radius_extent).enumerate() {
                        if !(r.is_finite() && r > 0.0) {
                            continue;
                        }
                        // both corners are >= 0 (lo is the least corner, rounded the same way), so
                        // truncation is the floor
                        let a = ((p - e - lo) * inv_cell).as_ivec3();
                        let b = ((p + e - lo) * inv_cell).as_ivec3();
                        // distinct buckets only (cells of one point rarely share a bucket)
                        mine.clear();
                        for z in a.z..=b.z {
                            for y in a.y..=b.y {
                                for x in a.x..=b.x {
                                    let bk = (hash_cell(IVec3::new(x, y, z)) & mask) as u32;
                                    if !mine.contains(&bk) {
                                        mine.push(bk);
                                    }
                                }
                            }
                        }
                        let i = (c * GRID_CHUNK + j) as u32;
                        pairs.extend(mine.iter().map(|&bk| (bk, i)));
                    }
                    grouped.regroup(pairs, ranges, |&(bk, _)| (bk >> shift) as usize);
                });
            },
        );
        // where each range's entries start: the ranges in order, each holding its pairs of
        // every chunk
        range_start.clear();
        range_start.push(0);
        for r in 0..ranges {
            range_start.push(range_start[r] + chunks.iter().map(|c| c.of(r).len()).sum::<usize>());
        }
        let total = range_start[ranges];
        // every entry and start is overwritten below (`resize` writes only what a table grows by)
        self.entries.resize(total, 0);
        self.starts.resize(buckets as usize + 1, 0);
        // a counting sort per range, in parallel: a range's buckets and entries are its own,
        // and its pairs arrive in chunk order, so every bucket lists its points in point order
        let (chunks, range_start) = (&*chunks, &*range_start);
        for_each_part(
            (&mut self.starts[..buckets as usize], &mut self.entries[..]),
            0..ranges,
            &|(starts, entries): (&mut [u32], &mut [u32]), lo, mid| {
                let (s0, s1) = starts.split_at_mut((mid - lo) << shift);
                let (e0, e1) = entries.split_at_mut(range_start[mid] - range_start[lo]);
                ((s0, e0), (s1, e1))
            },
            &|r, (starts, entries)| {
                let first_bucket = (r << shift) as u32;
                starts.fill(0);
                for c in chunks {
                    for &(bk, _) in c.of(r) {
                        starts[(bk - first_bucket) as usize] += 1;
                    }
                }
                let mut sum = 0u32;
                for s in starts.iter_mut() {
                    (*s, sum) = (sum, sum + *s);
                }
                // `starts` serves as each bucket's fill position, ending at the next one's start
                for c in chunks {
                    for &(bk, i) in c.of(r) {
                        let fill = &mut starts[(bk - first_bucket) as usize];
                        entries[*fill as usize] = i;
                        *fill += 1;
                    }
                }
                let base = range_start[r] as u32;
                for k in (0..starts.len()).rev() {
                    starts[k] = base + if k == 0 { 0 } else { starts[k - 1] };
                }
            },
        );
        self.starts[buckets as usize] = total as u32;
        (self.origin, self.inv_cell, self.mask) = (lo, inv_cell, mask);
    }

    /// Indices of the points whose cells include the cell of `p` (a superset of the points
    /// within their radius of `p`; the caller checks the distance).
    #[inline]
    pub fn candidates(&self, p: Vec3) -> &[u32] {
        self.bucket(p).map_or(&[], |b| self.entries_of(b))
    }

    /// The bucket of the cell of `p` (None when the grid is empty or `p` is not finite): the
    /// first step of [`candidates`](Self::candidates), for a caller that prefetches
    /// ([`prefetch_bucket`](Self::prefetch_bucket)) before it reads the bucket's entries.
    #[inline]
    pub fn bucket(&self, p: Vec3) -> Option<usize> {
        if self.entries.is_empty() {
            return None;
        }
        let c = ((p - self.origin) * self.inv_cell).floor();
        if !c.is_finite() {
            return None;
        }
        Some((hash_cell(c.as_ivec3()) & self.mask) as usize)
    }

    /// Starts loading where bucket `b`'s entries begin and end.
    #[inline]
    pub fn prefetch_bucket(&self, b: usize) {
        crate::core::prefetch::prefetch(&self.starts[b]);
    }

    /// The points entered in bucket `b`: [`candidates`](Self::candidates) of a position in it.
    #[inline]
    pub fn entries_of(&self, b: usize) -> &[u32] {
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
    fn buckets_list_their_points_once_each_in_point_order() {
        // enough points for every bucket range and many chunks, radii spread over 20x, a few
        // left out
        let mut s = Sampler::new(4, 5, 6);
        let points: Vec<(Vec3, f32)> = (0..20_000)
            .map(|k| {
                let r = if k % 997 == 3 { f32::NAN } else { 0.01 + 0.2 * s.get_1d() * s.get_1d() };
                (Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 10.0, r)
            })
            .collect();
        let grid = VisibilityGrid::build(&points);
        // the reference: every point pushed into each distinct bucket of its cells, in order
        let buckets = grid.starts.len() - 1;
        let mut reference: Vec<Vec<u32>> = vec![Vec::new(); buckets];
        for (i, (p, r)) in points.iter().enumerate() {
            if !r.is_finite() {
                continue;
            }
            let a = ((*p - Vec3::splat(*r) - grid.origin) * grid.inv_cell).floor().as_ivec3();
            let b = ((*p + Vec3::splat(*r) - grid.origin) * grid.inv_cell).floor().as_ivec3();
            for z in a.z..=b.z {
                for y in a.y..=b.y {
                    for x in a.x..=b.x {
                        let list = &mut reference[(hash_cell(IVec3::new(x, y, z)) & grid.mask) as usize];
                        if !list.contains(&(i as u32)) {
                            list.push(i as u32);
                        }
                    }
                }
            }
        }
        for (bk, expected) in reference.iter().enumerate() {
            let got = &grid.entries[grid.starts[bk] as usize..grid.starts[bk + 1] as usize];
            assert_eq!(got, &expected[..], "bucket {bk}");
        }
        assert_eq!(grid.starts[buckets] as usize, grid.entries.len());
    }

    #[test]
    fn photons_just_inside_a_radius_find_the_point_far_from_the_origin() {
        // points spread over 2 km with centimetre radii, 1 km from the origin: the cells'
        // coordinates are large and rounded, and photons sit just inside the sphere, half of
        // them towards the corners of its bounding box
        let mut s = Sampler::new(9, 8, 7);
        let offset = Vec3::new(1000.0, -700.0, 350.0);
        let points: Vec<(Vec3, f32)> = (0..3000)
            .map(|_| (offset + Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 2000.0, 0.01 + 0.04 * s.get_1d()))
            .collect();
        let grid = VisibilityGrid::build(&points);
        let mut tested = 0;
        for (i, (p, r)) in points.iter().enumerate() {
            for _ in 0..20 {
                let dir = crate::core::sampling::uniform_sphere(s.get_2d());
                // towards the corners (diagonal directions) half of the time
                let dir = if s.get_1d() < 0.5 { (dir.signum() + dir * 0.1).normalize() } else { dir };
                let q = *p + dir * (*r * (1.0 - 1e-6 * s.get_1d()));
                if (q - *p).length_squared() <= r * r {
                    tested += 1;
                    assert!(grid.candidates(q).contains(&(i as u32)), "point {i} missing at {q}");
                }
            }
        }
        assert!(tested > 20_000, "{tested}");
    }

    #[test]
    fn bad_radii_are_left_out() {
        let grid = VisibilityGrid::build(&[(Vec3::ZERO, f32::NAN), (Vec3::ONE, 0.0), (Vec3::ZERO, 1.0)]);
        assert_eq!(grid.candidates(Vec3::ZERO), &[2]);
        assert!(VisibilityGrid::build::<(Vec3, f32)>(&[]).candidates(Vec3::ZERO).is_empty());
    }
}
