//! Batch statistics of block means: the honest standard error of a region's mean when the
//! pixels' errors are correlated.
//!
//! Within one iteration of a bidirectional method every pixel sees the same wavelengths and
//! neighbouring pixels gather the same photons, so the per-pixel `stderr.Y` values cannot be
//! combined into the error of a block mean as if the pixels were independent (that would
//! underestimate it by about the square root of the number of pixels sharing a photon).
//! Iterations are independent, though: the mean of block b in iteration k, M_bk, is an
//! independent sample for every k, and var(mean_k M_bk) = s^2(M_b) / K (batch means).
//! Blocks are squares of [`BLOCK_BASE`] pixels, doubled until one block covers the image,
//! aligned at the top-left pixel (edge blocks are partial).

use std::collections::BTreeMap;

use rayon::prelude::*;

use super::scratch::Scratch;
use super::{Channel, N_QUANTITIES, Quantity};

/// Side in pixels of the finest blocks of [`BlockBatches`] and of the block z-test.
pub const BLOCK_BASE: usize = 4;

/// The block sizes of a `width` x `height` image from `base`: doubled while smaller than the
/// image's larger side, then one block covering the whole image.
pub fn block_sizes(base: usize, width: usize, height: usize) -> Vec<usize> {
    let side = width.max(height).max(1);
    let mut sizes = Vec::new();
    let mut s = base.max(1);
    while s < side {
        sizes.push(s);
        s *= 2;
    }
    sizes.push(s);
    sizes
}

/// The sums of one block size.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockLevel {
    /// Block side in pixels.
    pub size: usize,
    /// Blocks per row.
    pub cols: usize,
    /// Block rows.
    pub rows: usize,
    /// Per block (row-major) and quantity: sum over batches of the block's mean.
    pub sum: Vec<[f64; N_QUANTITIES]>,
    /// Per block and quantity: sum over batches of the squared block mean.
    pub sum_sq: Vec<[f64; N_QUANTITIES]>,
}

/// Batch statistics of the block means of every [`Quantity`] at every block size.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockBatches {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Finest first; the last level is one block covering the image.
    pub levels: Vec<BlockLevel>,
    /// Batches added.
    pub batches: u64,
    /// The working lists of a batch, kept for the next one.
    lists: Scratch<BatchLists>,
}

/// Sums of one quantity vector per block and the pixels they hold.
type BlockSums = Vec<([f64; N_QUANTITIES], u32)>;

/// The working lists of [`BlockBatches::add`], kept between batches.
#[derive(Default)]
struct BatchLists {
    /// Per pixel and quantity: a batch's luminance (the film's, see [`BlockBatches::take_luminances`]).
    y: Vec<[f64; N_QUANTITIES]>,
    /// The block sums of the level being summed.
    block: BlockSums,
    /// The block sums of the level before it.
    finer: BlockSums,
    /// The finest level's block column of every pixel column.
    col_of: Vec<usize>,
}

impl BlockBatches {
    /// Empty statistics for a `width` x `height` image.
    pub fn new(width: usize, height: usize) -> Self {
        let levels = block_sizes(BLOCK_BASE, width, height)
            .into_iter()
            .map(|size| {
                let (cols, rows) = (width.div_ceil(size), height.div_ceil(size));
                BlockLevel {
                    size,
                    cols,
                    rows,
                    sum: vec![[0.0; N_QUANTITIES]; cols * rows],
                    sum_sq: vec![[0.0; N_QUANTITIES]; cols * rows],
                }
            })
            .collect();
        Self { width, height, levels, batches: 0, lists: Scratch::default() }
    }

    /// Adds one batch: `y[pixel][quantity]`, one sample per pixel, row-major. The finest
    /// level's block sums come from the pixels; each coarser level's (blocks of twice the side)
    /// from the 2 x 2 blocks of the level before it.
    pub fn add(&mut self, y: &[[f64; N_QUANTITIES]]) {
        let w = self.width;
        let BatchLists { block, finer, col_of, .. } = &mut self.lists.0;
        let mut finer_cols = 0;
        for (li, level) in self.levels.iter_mut().enumerate() {
            block.clear();
            block.resize(level.cols * level.rows, ([0.0f64; N_QUANTITIES], 0u32));
            if li == 0 {
                col_of.clear();
                col_of.extend((0..w).map(|x| x / level.size));
                // one row of blocks per task, each adding its band of pixel rows in order
                let col_of = &*col_of;
                block.par_chunks_mut(level.cols.max(1)).zip(y.par_chunks((w * level.size).max(1))).for_each(
                    |(blocks, band)| {
                        for pixels in band.chunks(w.max(1)) {
                            for (v, &c) in pixels.iter().zip(col_of) {
                                let b = &mut blocks[c];
                                b.1 += 1;
                                for (acc, x) in b.0.iter_mut().zip(v) {
                                    *acc += x;
                                }
                            }
                        }
                    },
                );
            } else {
                for (i, s) in finer.iter().enumerate() {
                    let b = &mut block[(i / finer_cols / 2) * level.cols + (i % finer_cols) / 2];
                    b.1 += s.1;
                    for (acc, x) in b.0.iter_mut().zip(&s.0) {
                        *acc += x;
                    }
                }
            }
            level.sum.par_iter_mut().zip(&mut level.sum_sq).zip(&*block).with_min_len(256).for_each(
                |((sum, sum_sq), (s, n))| {
                    let n = (*n).max(1) as f64;
                    for (q, v) in s.iter().enumerate() {
                        let m = v / n;
                        sum[q] += m;
                        sum_sq[q] += m * m;
                    }
                },
            );
            std::mem::swap(block, finer);
            finer_cols = level.cols;
        }
        self.batches += 1;
    }

    /// A list of one luminance vector per pixel for the next batch: the last batch's list,
    /// resized, with stale values wherever the caller does not write (it must write every
    /// pixel). Give it back with [`add_luminances`](Self::add_luminances).
    pub(super) fn take_luminances(&mut self) -> Vec<[f64; N_QUANTITIES]> {
        let mut y = std::mem::take(&mut self.lists.0.y);
        y.resize(self.width * self.height, [0.0; N_QUANTITIES]);
        y
    }

    /// [`add`](Self::add) of a list from [`take_luminances`](Self::take_luminances), which is
    /// kept for the next batch.
    pub(super) fn add_luminances(&mut self, y: Vec<[f64; N_QUANTITIES]>) {
        self.add(&y);
        self.lists.0.y = y;
    }

    /// Adds the statistics of disjoint batches of the same image (a shard, a resumed part).
    pub fn merge(&mut self, o: &BlockBatches) {
        for (a, b) in self.levels.iter_mut().zip(&o.levels) {
            for (x, y) in a.sum.iter_mut().zip(&b.sum).chain(a.sum_sq.iter_mut().zip(&b.sum_sq)) {
                for q in 0..N_QUANTITIES {
                    x[q] += y[q];
                }
            }
        }
        self.batches += o.batches;
    }

    /// Variance of the block means of `q` (over the batches) by block size: s^2 / K with the
    /// unbiased sample variance s^2 of the K batch means; 0 with fewer than two batches.
    pub fn variances(&self, q: Quantity) -> BTreeMap<usize, Vec<f64>> {
        let k = self.batches as f64;
        let qi = q.index();
        self.levels
            .iter()
            .map(|l| {
                let v = l
                    .sum
                    .iter()
                    .zip(&l.sum_sq)
                    .map(|(s, sq)| {
                        if self.batches < 2 {
                            return 0.0;
                        }
                        ((sq[qi] - s[qi] * s[qi] / k) / (k - 1.0)).max(0.0) / k
                    })
                    .collect();
                (l.size, v)
            })
            .collect()
    }

    /// EXR channels `stderr.block<N>`: at every pixel, the standard error of the beauty mean
    /// of its N x N block.
    pub fn channels(&self, width: usize, height: usize) -> Vec<Channel> {
        let var = self.variances(Quantity::Beauty);
        self.levels
            .iter()
            .map(|l| {
                let v = &var[&l.size];
                let values = (0..width * height)
                    .map(|i| v[(i / width / l.size) * l.cols + (i % width) / l.size].sqrt() as f32)
                    .collect();
                Channel { name: format!("stderr.block{}", l.size), values }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coarse_levels_from_fine_blocks_equal_pixel_sums() {
        // an odd-sized image: partial edge blocks at every level
        let (w, h) = (37, 23);
        let mut b = BlockBatches::new(w, h);
        let mut seed = 7u64;
        let mut next = || {
            seed = crate::core::sampling::mix64(seed);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let y: Vec<[f64; N_QUANTITIES]> = (0..w * h).map(|_| std::array::from_fn(|_| next())).collect();
        b.add(&y);
        for level in &b.levels {
            for (blk, got) in level.sum.iter().enumerate() {
                let (br, bc) = (blk / level.cols, blk % level.cols);
                let mut sum = [0.0f64; N_QUANTITIES];
                let mut n = 0;
                for (i, v) in y.iter().enumerate() {
                    if (i / w) / level.size == br && (i % w) / level.size == bc {
                        n += 1;
                        (0..N_QUANTITIES).for_each(|q| sum[q] += v[q]);
                    }
                }
                for q in 0..N_QUANTITIES {
                    let want = sum[q] / n as f64;
                    assert!((got[q] - want).abs() <= 1e-12 * want.abs(), "size {} block {blk}", level.size);
                }
            }
        }
    }

    #[test]
    fn levels_cover_the_image() {
        let b = BlockBatches::new(10, 6);
        let sizes: Vec<_> = b.levels.iter().map(|l| (l.size, l.cols, l.rows)).collect();
        assert_eq!(sizes, [(4, 3, 2), (8, 2, 1), (16, 1, 1)]);
    }

    #[test]
    fn batch_variance_of_correlated_pixels() {
        // every pixel of a batch has the same value: the block mean varies like one pixel
        let mut b = BlockBatches::new(8, 8);
        for v in [1.0, 3.0] {
            b.add(&vec![[v; N_QUANTITIES]; 64]);
        }
        let var = b.variances(Quantity::Beauty);
        // s^2 = 2, K = 2: 1
        assert!(var.values().flatten().all(|&x| (x - 1.0).abs() < 1e-12));
        let mut c = b.clone();
        c.merge(&b);
        assert_eq!(c.batches, 4);
        // values 1, 3, 1, 3: s^2 = 4/3, / 4
        assert!((c.variances(Quantity::Layer(2))[&8][0] - 1.0 / 3.0).abs() < 1e-12);
    }
}
