//! Deterministic parallel reductions over ranges of an index (visibility points, grid
//! buckets): every parallel task groups what it produced by the range it goes to, and each
//! range is then reduced on its own, in parallel, visiting the tasks' groups in task order, so
//! the result does not depend on the number of threads.

/// One task's items grouped by range, each group in the task's order (a stable counting sort).
pub(crate) struct ByRange<T> {
    items: Vec<T>,
    /// `items[starts[r]..starts[r + 1]]` go to range r.
    starts: Vec<u32>,
}

impl<T: Copy> ByRange<T> {
    /// Groups `items` into `n_ranges` ranges by `range_of` (which must be < `n_ranges`).
    pub(crate) fn group(items: &[T], n_ranges: usize, range_of: impl Fn(&T) -> usize) -> Self {
        let mut starts = vec![0u32; n_ranges + 1];
        for item in items {
            starts[range_of(item) + 1] += 1;
        }
        for r in 0..n_ranges {
            starts[r + 1] += starts[r];
        }
        let mut fill = starts.clone();
        let mut grouped = items.to_vec();
        for &item in items {
            let f = &mut fill[range_of(&item)];
            grouped[*f as usize] = item;
            *f += 1;
        }
        Self { items: grouped, starts }
    }

    /// The items of range `r`, in the task's order.
    pub(crate) fn of(&self, r: usize) -> &[T] {
        &self.items[self.starts[r] as usize..self.starts[r + 1] as usize]
    }
}

/// `v` cut into consecutive slices of the given lengths (which must add up to `v.len()`), for
/// filling the parts of one list in parallel.
pub(crate) fn split_by_lengths<T>(mut v: &mut [T], lengths: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut parts = Vec::new();
    for n in lengths {
        let (head, tail) = v.split_at_mut(n);
        parts.push(head);
        v = tail;
    }
    debug_assert!(v.is_empty(), "the lengths do not cover the slice");
    parts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_are_stable_and_complete() {
        let items: Vec<(u32, u32)> = (0..500).map(|k| ((k * 7919) % 13, k)).collect();
        let g = ByRange::group(&items, 13, |&(r, _)| r as usize);
        let mut seen = 0;
        for r in 0..13 {
            let mine = g.of(r);
            assert!(mine.iter().all(|&(rr, _)| rr as usize == r));
            assert!(mine.windows(2).all(|w| w[0].1 < w[1].1), "range {r} out of order");
            seen += mine.len();
        }
        assert_eq!(seen, items.len());
    }

    #[test]
    fn split_parts_have_the_lengths() {
        let mut v: Vec<u32> = (0..10).collect();
        let parts = split_by_lengths(&mut v, [3, 0, 5, 2].into_iter());
        let lens: Vec<usize> = parts.iter().map(|p| p.len()).collect();
        assert_eq!(lens, [3, 0, 5, 2]);
        assert_eq!(parts[2], &[3, 4, 5, 6, 7]);
    }
}
