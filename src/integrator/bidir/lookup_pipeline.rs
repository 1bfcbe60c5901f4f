//! A photon pass's grid look-ups, each spread over the next few hits of the photon stream
//! (software pipelining with prefetch; Chen et al., "Improving hash join performance through
//! prefetching", ICDE 2004).
//!
//! A look-up reads four things in a chain, each found from the last: the cell's bucket, the
//! bucket's entries, the candidates' gather disks, the accepted points. Once the visibility
//! points outgrow the caches each is a miss, and done at once the photon pass waits for four
//! misses in a row per hit (`auto`, glossy room, 1024x768: 25% of the render's samples stalled
//! on these loads). Here a hit advances one stage per later hit of the pass: each stage reads
//! what the previous one prefetched and prefetches what the next one reads, while the photons'
//! own tracing (a BVH traversal and a BSDF sample between two hits) runs in between. The
//! gatherer receives the same arrivals in the same order (hit by hit, candidates in entry
//! order) as a look-up done at once, so the result is the same bit for bit.

use std::cell::RefCell;

use glam::Vec3;

use super::arrival::{Arrival, Gatherer};
use super::gather_disk::GatherDisk;
use super::grid::VisibilityGrid;
use crate::core::prefetch::prefetch;

/// Look-ups in flight: one per stage before the last. A look-up pushed now runs stage 0 (its
/// bucket); each later push runs the next stage of every look-up in flight: 1 the bucket's
/// entries, 2 the candidates' disks, 3 the disk tests, 4 the gatherer, after which its slot takes
/// the new look-up.
const DEPTH: usize = 4;

thread_local! {
    /// The accepted points of each slot, kept between pipelines so that a chunk of photons
    /// allocates nothing.
    static ACCEPTED: RefCell<[Vec<u32>; DEPTH]> = RefCell::new(Default::default());
}

/// One photon hit on its way through the stages. A slot without a bucket does nothing at any
/// stage (an empty slot of a filling or draining pipeline, or a hit outside the grid).
#[derive(Default)]
struct Lookup<'g> {
    /// The hit.
    p: Vec3,
    /// The hit surface's unit geometric normal.
    ng: Vec3,
    /// The photon as it arrived.
    arrival: Arrival,
    /// The bucket of the hit's cell (stage 0).
    bucket: Option<usize>,
    /// The points entered in that bucket (stage 1).
    candidates: &'g [u32],
}

/// The look-ups in flight of one chunk of photons.
pub(super) struct LookupPipeline<'g> {
    disks: &'g [GatherDisk],
    grid: &'g VisibilityGrid,
    /// The look-ups, oldest at `oldest`, then in push order.
    slots: [Lookup<'g>; DEPTH],
    /// Per slot, the candidates whose disk holds the hit (stage 3), in entry order.
    accepted: [Vec<u32>; DEPTH],
    /// Slot of the oldest look-up.
    oldest: usize,
}

impl<'g> LookupPipeline<'g> {
    /// An empty pipeline over the iteration's disks and grid.
    pub(super) fn new(disks: &'g [GatherDisk], grid: &'g VisibilityGrid) -> Self {
        let mut accepted = ACCEPTED.with_borrow_mut(std::mem::take);
        accepted.iter_mut().for_each(Vec::clear);
        Self { disks, grid, slots: Default::default(), accepted, oldest: 0 }
    }

    /// Starts the look-up of a photon hit at `p` (unit geometric normal `ng`), after moving every
    /// look-up in flight one stage on (the oldest hands its accepted points to `gatherer`).
    #[inline]
    pub(super) fn push(&mut self, p: Vec3, ng: Vec3, arrival: Arrival, gatherer: &mut impl Gatherer) {
        let k = self.advance(gatherer);
        let bucket = self.grid.bucket(p);
        if let Some(b) = bucket {
            self.grid.prefetch_bucket(b);
        }
        self.slots[k] = Lookup { p, ng, arrival, bucket, candidates: &[] };
    }

    /// Finishes every look-up in flight, in order, and hands the accepted-point lists back to the
    /// thread for its next pipeline.
    pub(super) fn finish(mut self, gatherer: &mut impl Gatherer) {
        for _ in 0..DEPTH {
            let k = self.advance(gatherer);
            self.slots[k] = Lookup::default();
        }
        let accepted = std::mem::take(&mut self.accepted);
        ACCEPTED.with_borrow_mut(|lists| *lists = accepted);
    }

    /// Runs the next stage of every look-up in flight, oldest first, and returns the oldest's
    /// slot, free for the next look-up.
    #[inline(always)]
    fn advance(&mut self, gatherer: &mut impl Gatherer) -> usize {
        let Self { disks, grid, slots, accepted, oldest } = self;
        let slot = |age: usize| (*oldest + age) % DEPTH;
        // stage 4: the oldest's accepted points, to the gatherer
        let k = slot(0);
        for &vi in &accepted[k] {
            gatherer.arrive(vi, &slots[k].arrival);
        }
        // stage 3: the disk tests
        let k = slot(1);
        let (l, list) = (&slots[k], &mut accepted[k]);
        list.clear();
        for &vi in l.candidates {
            if disks[vi as usize].holds(l.p, l.ng, l.arrival.caustic) {
                list.push(vi);
                gatherer.prefetch(vi);
            }
        }
        // stage 2: the candidates' disks
        for &vi in slots[slot(2)].candidates {
            prefetch(&disks[vi as usize]);
        }
        // stage 1: the bucket's entries
        let l = &mut slots[slot(3)];
        if let Some(b) = l.bucket {
            l.candidates = grid.entries_of(b);
            if let (Some(first), Some(last)) = (l.candidates.first(), l.candidates.last()) {
                prefetch(first);
                prefetch(last);
            }
        }
        let free = slot(0);
        *oldest = slot(1);
        free
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::sampling::{Sampler, uniform_sphere};

    /// Every arrival in order: point, the hit's number (in `Arrival::beta[0]`).
    #[derive(Default)]
    struct Log(Vec<(u32, f32)>);

    impl Gatherer for Log {
        fn arrive(&mut self, vi: u32, a: &Arrival) {
            self.0.push((vi, a.beta[0]));
        }

        fn prefetch(&self, _: u32) {}
    }

    #[test]
    fn the_pipeline_hands_over_the_arrivals_of_a_look_up_done_at_once() {
        // disks on a few planes, hits near them (some far outside every disk, some caustic);
        // the pipeline's arrivals equal those of the direct look-up (the grid's candidates
        // whose disk holds the hit), in the same order, for any number of hits per chunk
        let mut s = Sampler::new(17, 3, 1);
        let planes = [Vec3::Z, Vec3::X, Vec3::new(1.0, 1.0, 0.0).normalize()];
        let disks: Vec<GatherDisk> = (0..4000)
            .map(|k| {
                let ng = planes[k % 3];
                let p = (Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 2.0 - 1.0).reject_from(ng);
                let r = 0.02 + 0.08 * s.get_1d();
                GatherDisk { p, indirect: r, ng, caustic: 0.5 * r }
            })
            .collect();
        let grid = VisibilityGrid::build(&disks);
        for hits in [0usize, 1, 3, 4, 5, 700] {
            let (mut direct, mut piped) = (Log::default(), Log::default());
            let mut pipeline = LookupPipeline::new(&disks, &grid);
            for h in 0..hits {
                let disk = &disks[(s.get_1d() * disks.len() as f32) as usize % disks.len()];
                let far = if h % 10 == 0 { 50.0 } else { 1.0 };
                let p = disk.p + uniform_sphere(s.get_2d()) * (0.1 * s.get_1d() * far);
                let ng = if h % 7 == 0 { uniform_sphere(s.get_2d()) } else { disk.ng };
                let mut arrival = Arrival { caustic: h % 3 == 0, ..Arrival::default() };
                arrival.beta[0] = h as f32;
                for &vi in grid.candidates(p) {
                    if disks[vi as usize].holds(p, ng, arrival.caustic) {
                        direct.arrive(vi, &arrival);
                    }
                }
                pipeline.push(p, ng, arrival, &mut piped);
            }
            pipeline.finish(&mut piped);
            assert_eq!(piped.0, direct.0, "{hits} hits");
            if hits == 700 {
                assert!(direct.0.len() > hits, "{} arrivals", direct.0.len());
            }
        }
    }
}
