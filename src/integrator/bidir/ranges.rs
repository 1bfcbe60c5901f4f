//! Deterministic parallel reductions over ranges of an index (visibility points, grid
//! buckets): every parallel task groups what it produced by the range it goes to, and each
//! range is then reduced on its own, in parallel, visiting the tasks' groups in task order, so
//! the result does not depend on the number of threads.

/// One task's items grouped by range, each group in the task's order (a stable counting sort).
/// Its lists are kept and refilled by [`regroup`](Self::regroup), so a task that runs every
/// iteration allocates only while its lists still grow.
pub(crate) struct ByRange<T> {
    items: Vec<T>,
    /// `items[starts[r]..starts[r + 1]]` go to range r.
    starts: Vec<u32>,
}

impl<T> Default for ByRange<T> {
    fn default() -> Self {
        Self { items: Vec::new(), starts: Vec::new() }
    }
}

impl<T: Copy> ByRange<T> {
    /// Groups `items` into `n_ranges` ranges by `range_of` (which must be < `n_ranges`).
    #[cfg(test)]
    pub(crate) fn group(items: &[T], n_ranges: usize, range_of: impl Fn(&T) -> usize) -> Self {
        let mut g = Self::default();
        g.regroup(items, n_ranges, range_of);
        g
    }

    /// [`group`](Self::group) into this value's lists.
    pub(crate) fn regroup(&mut self, items: &[T], n_ranges: usize, range_of: impl Fn(&T) -> usize) {
        let starts = &mut self.starts;
        starts.clear();
        starts.resize(n_ranges + 1, 0);
        for item in items {
            starts[range_of(item) + 1] += 1;
        }
        for r in 0..n_ranges {
            starts[r + 1] += starts[r];
        }
        // every entry is overwritten below (`resize` writes only what the list grows by)
        match items.first() {
            Some(&first) => self.items.resize(items.len(), first),
            None => self.items.clear(),
        }
        // `starts[r]` serves as range r's fill position, ending at range r + 1's start
        for &item in items {
            let f = &mut starts[range_of(&item)];
            self.items[*f as usize] = item;
            *f += 1;
        }
        for r in (1..=n_ranges).rev() {
            starts[r] = starts[r - 1];
        }
        starts[0] = 0;
    }

    /// The items of range `r`, in the task's order.
    pub(crate) fn of(&self, r: usize) -> &[T] {
        &self.items[self.starts[r] as usize..self.starts[r + 1] as usize]
    }
}

/// Calls `f(r, part)` for the parts r in `parts` of `whole`, in parallel: `cut(s, lo, mid)`
/// splits `s`, which holds the parts `lo..hi`, into the parts `lo..mid` and `mid..hi` (a slice
/// or a tuple of slices at the first item of part `mid`). Halves recursively with
/// `rayon::join`, so filling the parts of one list in parallel allocates nothing.
pub(crate) fn for_each_part<S: Send>(
    whole: S,
    parts: std::ops::Range<usize>,
    cut: &(impl Fn(S, usize, usize) -> (S, S) + Sync),
    f: &(impl Fn(usize, S) + Sync),
) {
    match parts.len() {
        0 => {}
        1 => f(parts.start, whole),
        n => {
            let mid = parts.start + n / 2;
            let (a, b) = cut(whole, parts.start, mid);
            rayon::join(|| for_each_part(a, parts.start..mid, cut, f), || for_each_part(b, mid..parts.end, cut, f));
        }
    }
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
    fn regrouping_reuses_the_lists_and_forgets_the_last_grouping() {
        let mut g = ByRange::default();
        for (n, ranges) in [(500u32, 13usize), (20, 3), (0, 5), (300, 7)] {
            let items: Vec<(u32, u32)> = (0..n).map(|k| ((k * 7919) % ranges as u32, k)).collect();
            g.regroup(&items, ranges, |&(r, _)| r as usize);
            let fresh = ByRange::group(&items, ranges, |&(r, _)| r as usize);
            for r in 0..ranges {
                assert_eq!(g.of(r), fresh.of(r), "{n} items, range {r}");
            }
            assert_eq!(g.starts, fresh.starts);
        }
    }

    #[test]
    fn every_part_is_visited_once_with_its_items() {
        let bounds = [0usize, 3, 3, 8, 10, 17];
        let mut v = vec![usize::MAX; 17];
        let seen = std::sync::Mutex::new(Vec::new());
        for_each_part(
            &mut v[..],
            0..bounds.len() - 1,
            &|s: &mut [usize], lo, mid| s.split_at_mut(bounds[mid] - bounds[lo]),
            &|r, part: &mut [usize]| {
                assert_eq!(part.len(), bounds[r + 1] - bounds[r], "part {r}");
                part.fill(r);
                seen.lock().unwrap().push(r);
            },
        );
        let mut seen = seen.into_inner().unwrap();
        seen.sort();
        assert_eq!(seen, [0, 1, 2, 3, 4]);
        assert_eq!(v, [0, 0, 0, 2, 2, 2, 2, 2, 3, 3, 4, 4, 4, 4, 4, 4, 4]);
    }
}
