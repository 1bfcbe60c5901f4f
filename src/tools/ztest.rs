//! The block z-test: does an image converge to a reference within both images' standard errors?
//!
//! Both images are split into square blocks at several scales — `base` pixels, then twice, four
//! times ... that size, and finally the whole image — and every block mean is compared with the
//! reference's: z = (m_a - m_b) / sqrt(se_a^2 + se_b^2). An unbiased image gives z ~ N(0, 1)
//! in every block; a bias shows as |z| growing with the samples. The test fails when, at any
//! scale, more than `max_failing_share` of the blocks (and at least one) have |z| > `z_limit`,
//! or when the image mean's |z| exceeds `mean_z_limit`. Coarse scales catch a small bias spread
//! over a region (a 1% bias over a quarter of the image) that no single fine block resolves.
//!
//! The standard error of a block mean is the render's own batch estimate where it has one
//! ([`Estimate::block_var`]: the spread of the block's mean over independent iterations, which
//! sees the correlation of pixels sharing photons and wavelengths in the bidirectional methods),
//! otherwise sqrt(sum of the pixels' stderr^2) / n, exact for independent pixels (`pt`, whose
//! every pixel sample has its own wavelengths and random stream).

use std::collections::BTreeMap;
use std::fmt;

use crate::film::{BLOCK_BASE, Film, LUMINANCE, Quantity, STDERR, block_sizes};
use crate::output::ExrImage;

/// A luminance image with the variances of its estimates.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Pixel values (mean luminance).
    pub values: Vec<f64>,
    /// Variance of each pixel's mean (stderr^2).
    pub pixel_var: Vec<f64>,
    /// Variance of block means by block size (row-major blocks, edge blocks partial), where the
    /// render measured it from its iterations.
    pub block_var: BTreeMap<usize, Vec<f64>>,
}

impl Estimate {
    /// The `quantity` of a film (beauty or one layer, luminance Y), with the film's block
    /// batch statistics if it has them.
    pub fn from_film(film: &Film, quantity: Quantity) -> Self {
        let n = film.pixels.len();
        let values = (0..n).map(|i| film.mean_y(i, quantity)).collect();
        let pixel_var = film.pixels.iter().map(|p| p.stderr(quantity).powi(2)).collect();
        let block_var = film.blocks.as_ref().map_or_else(BTreeMap::new, |b| b.variances(quantity));
        Self { width: film.width as usize, height: film.height as usize, values, pixel_var, block_var }
    }

    /// The beauty luminance `Y` of an EXR written by quasar (or by the cross-check script) with
    /// its `stderr.Y` and, if present, `stderr.block<N>` channels.
    pub fn from_exr(img: &ExrImage) -> Result<Self, String> {
        let y = img.channel(LUMINANCE).ok_or(format!("the image has no {LUMINANCE} channel"))?;
        let se = img.channel(STDERR).ok_or(format!("the image has no {STDERR} channel"))?;
        let mut block_var = BTreeMap::new();
        for c in &img.channels {
            let Some(size) = c.name.strip_prefix("stderr.block").and_then(|s| s.parse::<usize>().ok()) else {
                continue;
            };
            if size == 0 {
                continue;
            }
            let (cols, rows) = (img.width.div_ceil(size), img.height.div_ceil(size));
            let v = (0..rows * cols)
                .map(|b| {
                    let (bx, by) = (b % cols, b / cols);
                    (c.values[by * size * img.width + bx * size] as f64).powi(2)
                })
                .collect();
            block_var.insert(size, v);
        }
        Ok(Self {
            width: img.width,
            height: img.height,
            values: y.iter().map(|&v| v as f64).collect(),
            pixel_var: se.iter().map(|&v| (v as f64).powi(2)).collect(),
            block_var,
        })
    }

    /// Mean and variance of the mean of block (bx, by) of side `size`.
    fn block(&self, size: usize, bx: usize, by: usize) -> (f64, f64) {
        let (x1, y1) = (((bx + 1) * size).min(self.width), ((by + 1) * size).min(self.height));
        let (mut sum, mut var) = (0.0, 0.0);
        for y in by * size..y1 {
            for x in bx * size..x1 {
                sum += self.values[y * self.width + x];
                var += self.pixel_var[y * self.width + x];
            }
        }
        let n = ((x1 - bx * size) * (y1 - by * size)) as f64;
        let cols = self.width.div_ceil(size);
        let var = match self.block_var.get(&size) {
            Some(v) => v[by * cols + bx],
            None => var / (n * n),
        };
        (sum / n, var)
    }
}

/// The thresholds of the block z-test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZTest {
    /// Side in pixels of the finest blocks.
    pub base: usize,
    /// A block fails when its |z| exceeds this.
    pub z_limit: f64,
    /// A scale fails when more than this share of its blocks fail (and at least one does).
    pub max_failing_share: f64,
    /// The test fails when the image mean's |z| exceeds this.
    pub mean_z_limit: f64,
}

impl Default for ZTest {
    /// [`BLOCK_BASE`]-pixel blocks, |z| > 4.5 in more than 2% of a scale's blocks (at least one),
    /// image mean |z| > 4. Unbiased Gaussian errors exceed |z| = 4.5 in 7 blocks per million;
    /// the 2% absorb the rare heavy-tailed block of a photon estimate.
    fn default() -> Self {
        Self { base: BLOCK_BASE, z_limit: 4.5, max_failing_share: 0.02, mean_z_limit: 4.0 }
    }
}

/// One block's comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockZ {
    /// Block column.
    pub bx: usize,
    /// Block row.
    pub by: usize,
    /// Mean of the image over the block.
    pub mean: f64,
    /// Mean of the reference over the block.
    pub reference: f64,
    /// (mean - reference) / sqrt(se^2 + se_ref^2); 0 where both are exactly equal.
    pub z: f64,
}

/// The comparison at one block size.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaleZ {
    /// Block side in pixels.
    pub size: usize,
    /// Every block.
    pub blocks: Vec<BlockZ>,
    /// Blocks with |z| above the limit.
    pub failing: usize,
    /// Root mean square of the blocks' z.
    pub rms_z: f64,
}

impl ScaleZ {
    /// The block of largest |z|.
    pub fn worst(&self) -> Option<&BlockZ> {
        self.blocks.iter().max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))
    }
}

/// The outcome of [`ZTest::run`].
#[derive(Clone, Debug, PartialEq)]
pub struct ZReport {
    /// The thresholds used.
    pub test: ZTest,
    /// One entry per block size, finest first; the last is the whole image.
    pub scales: Vec<ScaleZ>,
}

impl ZReport {
    /// The whole-image comparison (the last scale's only block).
    pub fn image(&self) -> BlockZ {
        self.scales.last().and_then(|s| s.blocks.first().copied()).unwrap_or(BlockZ {
            bx: 0,
            by: 0,
            mean: 0.0,
            reference: 0.0,
            z: 0.0,
        })
    }

    /// Ratio of the image mean to the reference mean, and its standard deviation.
    pub fn mean_ratio(&self) -> (f64, f64) {
        let b = self.image();
        let ratio = b.mean / b.reference;
        let sigma = if b.z != 0.0 { ((b.mean - b.reference) / b.z / b.reference).abs() } else { 0.0 };
        (ratio, sigma)
    }

    /// True when a scale has too many failing blocks or the image mean's z is too large.
    pub fn failed(&self) -> bool {
        self.image().z.abs() > self.test.mean_z_limit
            || self
                .scales
                .iter()
                .any(|s| s.failing > 0 && s.failing as f64 > self.test.max_failing_share * s.blocks.len() as f64)
    }
}

impl fmt::Display for ZReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (ratio, sigma) = self.mean_ratio();
        writeln!(
            f,
            "block z-test ({}): image mean ratio {ratio:.5} +- {sigma:.5} (z {:+.2}, limit {})",
            if self.failed() { "FAILED" } else { "passed" },
            self.image().z,
            self.test.mean_z_limit
        )?;
        for s in &self.scales {
            let worst = s.worst().map_or(String::new(), |w| {
                format!(
                    ", worst block ({}, {}) z {:+.2} ratio {:.4}",
                    w.bx,
                    w.by,
                    w.z,
                    if w.reference != 0.0 { w.mean / w.reference } else { f64::NAN }
                )
            });
            writeln!(
                f,
                "  {:>4} px blocks: {:>5} blocks, {:>4} with |z| > {} ({:.2}%, limit {}%), rms z {:.3}{worst}",
                s.size,
                s.blocks.len(),
                s.failing,
                self.test.z_limit,
                100.0 * s.failing as f64 / s.blocks.len().max(1) as f64,
                100.0 * self.test.max_failing_share,
                s.rms_z
            )?;
        }
        Ok(())
    }
}

impl ZTest {
    /// Compares `image` with `reference` (same size) at every block size.
    pub fn run(&self, image: &Estimate, reference: &Estimate) -> Result<ZReport, String> {
        if (image.width, image.height) != (reference.width, reference.height) {
            return Err(format!(
                "image sizes differ: {}x{} vs reference {}x{}",
                image.width, image.height, reference.width, reference.height
            ));
        }
        let mut scales = Vec::new();
        for size in block_sizes(self.base, image.width, image.height) {
            let (cols, rows) = (image.width.div_ceil(size), image.height.div_ceil(size));
            let mut blocks = Vec::with_capacity(cols * rows);
            for by in 0..rows {
                for bx in 0..cols {
                    let (m, v) = image.block(size, bx, by);
                    let (r, vr) = reference.block(size, bx, by);
                    let d = m - r;
                    let z = if d == 0.0 { 0.0 } else { d / (v + vr).sqrt() };
                    let z = if z.is_nan() { f64::INFINITY } else { z };
                    blocks.push(BlockZ { bx, by, mean: m, reference: r, z });
                }
            }
            let failing = blocks.iter().filter(|b| b.z.abs() > self.z_limit).count();
            let rms_z = (blocks.iter().map(|b| b.z * b.z).sum::<f64>() / blocks.len().max(1) as f64).sqrt();
            scales.push(ScaleZ { size, blocks, failing, rms_z });
        }
        Ok(ZReport { test: *self, scales })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: usize, h: usize, v: f64, var: f64) -> Estimate {
        Estimate {
            width: w,
            height: h,
            values: vec![v; w * h],
            pixel_var: vec![var; w * h],
            block_var: BTreeMap::new(),
        }
    }

    #[test]
    fn block_sizes_end_with_the_whole_image() {
        assert_eq!(block_sizes(4, 40, 30), [4, 8, 16, 32, 64]);
        assert_eq!(block_sizes(4, 16, 16), [4, 8, 16]);
        assert_eq!(block_sizes(4, 3, 2), [4]);
    }

    #[test]
    fn z_of_known_blocks() {
        let a = flat(8, 8, 1.01, 1e-4);
        let b = flat(8, 8, 1.0, 1e-4);
        let r = ZTest::default().run(&a, &b).unwrap();
        // a 4x4 block: var 1e-4 / 16 per image, z = 0.01 / sqrt(2e-4 / 16)
        let z4 = 0.01 / (2e-4f64 / 16.0).sqrt();
        assert!((r.scales[0].blocks[0].z - z4).abs() < 1e-9);
        assert!((r.image().z - 0.01 / (2e-4f64 / 64.0).sqrt()).abs() < 1e-9);
        assert!(r.failed());
        let r = ZTest::default().run(&b, &b).unwrap();
        assert!(!r.failed());
        assert_eq!(r.image().z, 0.0);
        // the batch variance replaces the pixel-based one where given
        let mut c = a.clone();
        c.block_var.insert(8, vec![1.0]);
        let r = ZTest::default().run(&c, &b).unwrap();
        assert!(r.image().z.abs() < 0.011);
        assert!(ZTest::default().run(&flat(4, 4, 1.0, 1.0), &b).is_err());
    }
}
