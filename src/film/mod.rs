//! The film: per-pixel accumulation of the radiance layers in CIE XYZ, and their conversion to
//! the output AOV channels (docs/architecture.md §6), with the statistics of their standard errors.

mod blocks;
mod layers;
pub mod outputs;
mod scratch;
mod spectral;

pub use blocks::{BLOCK_BASE, BlockBatches, BlockLevel, block_sizes};
pub use layers::{LayeredRadiance, PathClass};
pub use outputs::{ChannelSet, DEPTH, LUMINANCE, SAMPLES, STDERR};
pub use spectral::{MAX_SPECTRAL_BINS, SpectralBins, SpectralSums};

use glam::Vec3A;
use quasar_materials::spectrum::color::xyz_to_linear_srgb;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use rayon::iter::Either;
use rayon::prelude::*;

/// The epsilon of relative errors, (a - r)^2 / (r^2 + REL_EPS): keeps black pixels from
/// dominating the film's error estimate and `quasar compare`'s relMSE (in Y units, where a
/// flat spectral radiance of 1 gives Y = 1).
pub const REL_EPS: f64 = 1e-3;
/// Number of radiance layers (emission, direct, indirect, caustic).
pub const N_LAYERS: usize = 4;
/// Names of the radiance layers, in accumulation order.
pub const LAYER_NAMES: [&str; N_LAYERS] = ["emission", "direct", "indirect", "caustic"];
/// The layers whose sum is the beauty image (`caustic` is a part of `indirect`).
pub const BEAUTY_LAYERS: usize = 3;

/// A luminance the film keeps variance statistics of: the beauty image or one layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Y of emission + direct + indirect.
    Beauty,
    /// Y of layer `LAYER_NAMES[i]`.
    Layer(usize),
}

/// Number of [`Quantity`] values: the beauty and every layer.
pub const N_QUANTITIES: usize = 1 + N_LAYERS;

impl Quantity {
    /// Every quantity, in index order.
    pub const ALL: [Quantity; N_QUANTITIES] = {
        let mut all = [Quantity::Beauty; N_QUANTITIES];
        let mut i = 0;
        while i < N_LAYERS {
            all[1 + i] = Quantity::Layer(i);
            i += 1;
        }
        all
    };

    /// Position in per-sample arrays: 0 for the beauty, 1 + i for layer i.
    #[inline]
    pub fn index(self) -> usize {
        match self {
            Self::Beauty => 0,
            Self::Layer(i) => 1 + i,
        }
    }

    /// The quantity of a layer name ("" or "beauty" for the beauty).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "" | "beauty" => Some(Self::Beauty),
            _ => LAYER_NAMES.iter().position(|&l| l == name).map(Self::Layer),
        }
    }

    /// Name as in the EXR channels ("beauty" for the bare channels).
    pub fn name(self) -> &'static str {
        match self {
            Self::Beauty => "beauty",
            Self::Layer(i) => LAYER_NAMES[i],
        }
    }
}

/// Sum of XYZ per layer for one pixel, in f64 so long renders do not lose precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelSum {
    /// [layer][X, Y, Z].
    pub xyz: [[f64; 3]; N_LAYERS],
    /// Sum of the squared beauty luminance of the samples (for the per-pixel noise estimate).
    pub y_sq: f64,
    /// Sum of the squared luminance of each layer's samples.
    pub layer_y_sq: [f64; N_LAYERS],
    /// Samples accumulated (including rejected non-finite ones, which count as zero).
    pub samples: u64,
    /// Samples whose value was not finite and was dropped.
    pub rejected: u64,
}

impl PixelSum {
    /// Adds one path's layered radiance at wavelengths `wl` and returns the sample's luminance
    /// per [`Quantity`]. A sample with any non-finite component is replaced by zero (and
    /// counted), so no NaN/inf can reach a pixel. Always inlined: the render kernels' x86-64-v3
    /// copies then cover it (`pt` with the camera ray alone, `--max-depth 0`, 1.08x; unbounded 1.01x).
    #[inline(always)]
    pub fn add(&mut self, l: &LayeredRadiance, wl: &SampledWavelengths) -> [f64; N_QUANTITIES] {
        let w = wl.xyz_weights();
        let xyz = |s: SampledSpectrum| if s.is_black() { Vec3A::ZERO } else { w.apply_vec(s) };
        let layers = l.layers().map(xyz);
        self.samples += 1;
        if !layers.iter().fold(Vec3A::ZERO, |a, &v| a + v).is_finite() {
            // a sum of finite values can overflow to infinity: check each before rejecting
            if layers.iter().any(|v| !v.is_finite()) {
                self.rejected += 1;
                return [0.0; N_QUANTITIES];
            }
        }
        let mut y = [0.0f64; N_QUANTITIES];
        for (i, v) in layers.iter().enumerate() {
            y[1 + i] = v.y as f64;
            self.layer_y_sq[i] += y[1 + i] * y[1 + i];
        }
        y[0] = y[1..=BEAUTY_LAYERS].iter().sum();
        self.y_sq += y[0] * y[0];
        for (acc, v) in self.xyz.iter_mut().zip(layers) {
            for k in 0..3 {
                acc[k] += v[k] as f64;
            }
        }
        y
    }

    /// Sum of the samples' luminance of `q`.
    #[inline]
    pub fn sum_y(&self, q: Quantity) -> f64 {
        match q {
            Quantity::Beauty => self.xyz[..BEAUTY_LAYERS].iter().map(|l| l[1]).sum(),
            Quantity::Layer(i) => self.xyz[i][1],
        }
    }

    /// Standard error of the pixel's mean luminance of `q`, sqrt(s^2 / n) with the unbiased
    /// sample variance s^2 of the per-sample luminance; 0 with fewer than two samples.
    pub fn stderr(&self, q: Quantity) -> f64 {
        if self.samples < 2 {
            return 0.0;
        }
        let n = self.samples as f64;
        let sum = self.sum_y(q);
        let sq = match q {
            Quantity::Beauty => self.y_sq,
            Quantity::Layer(i) => self.layer_y_sq[i],
        };
        let var = ((sq - sum * sum / n) / (n - 1.0)).max(0.0);
        (var / n).sqrt()
    }

    /// Standard error of the pixel's mean beauty luminance ([`stderr`](Self::stderr) of the beauty).
    pub fn stderr_y(&self) -> f64 {
        self.stderr(Quantity::Beauty)
    }

    /// Adds another sum (same pixel, disjoint samples).
    pub fn merge(&mut self, o: &PixelSum) {
        for l in 0..N_LAYERS {
            for k in 0..3 {
                self.xyz[l][k] += o.xyz[l][k];
            }
        }
        self.y_sq += o.y_sq;
        for (a, b) in self.layer_y_sq.iter_mut().zip(o.layer_y_sq) {
            *a += b;
        }
        self.samples += o.samples;
        self.rejected += o.rejected;
    }
}

/// An image of pixel sums, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixel sums.
    pub pixels: Vec<PixelSum>,
    /// Batch statistics of block means, for films filled one whole image per batch
    /// ([`add_batch`](Self::add_batch)): the bidirectional methods, whose pixels share photons
    /// and wavelengths within an iteration, so that per-pixel errors are correlated.
    pub blocks: Option<BlockBatches>,
    /// Spectral radiance bins of the beauty (`--spectral-bins`), None when not asked for.
    pub spectral: Option<SpectralSums>,
}

/// One row of a [`Film`], for a pass that fills the rows in parallel ([`Film::rows_mut`]).
pub struct FilmRow<'a> {
    pixels: &'a mut [PixelSum],
    spectral: Option<(SpectralBins, &'a mut [f64])>,
}

impl FilmRow<'_> {
    /// Pixels in the row.
    pub fn width(&self) -> usize {
        self.pixels.len()
    }

    /// Adds one sample to pixel `x` of the row: its layers ([`PixelSum::add`], whose per-quantity
    /// luminance it returns) and, unless the sample was rejected as non-finite, the beauty's
    /// spectral bins.
    #[inline(always)]
    pub fn add(&mut self, x: usize, l: &LayeredRadiance, wl: &SampledWavelengths) -> [f64; N_QUANTITIES] {
        let px = &mut self.pixels[x];
        let rejected = px.rejected;
        let y = px.add(l, wl);
        if let Some((bins, sums)) = &mut self.spectral
            && px.rejected == rejected
        {
            let n = bins.count();
            bins.add(&mut sums[x * n..(x + 1) * n], l.emission + l.direct + l.indirect, wl);
        }
        y
    }
}

/// A named float channel of an output image.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// EXR channel name, `layer.channel` (Blender/Nuke convention) or a bare beauty channel.
    pub name: String,
    /// Row-major values, row 0 at the top.
    pub values: Vec<f32>,
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![PixelSum::default(); width as usize * height as usize],
            blocks: None,
            spectral: None,
        }
    }

    /// This film with empty spectral bins `bins` (replacing any it had).
    pub fn with_spectral(mut self, bins: SpectralBins) -> Self {
        self.spectral = Some(SpectralSums::new(bins, self.pixels.len()));
        self
    }

    /// The rows of the film, top first, each with its part of every sum.
    pub fn rows_mut(&mut self) -> impl IndexedParallelIterator<Item = FilmRow<'_>> {
        let w = (self.width as usize).max(1);
        let rows = self.pixels.par_chunks_mut(w);
        match &mut self.spectral {
            Some(s) => {
                let bins = s.bins;
                Either::Left(
                    rows.zip(s.sums.par_chunks_mut(w * bins.count()))
                        .map(move |(pixels, sums)| FilmRow { pixels, spectral: Some((bins, sums)) }),
                )
            }
            None => Either::Right(rows.map(|pixels| FilmRow { pixels, spectral: None })),
        }
    }

    /// An empty film that keeps batch statistics of its block means (see [`BlockBatches`]).
    pub fn with_block_batches(width: u32, height: u32) -> Self {
        Self { blocks: Some(BlockBatches::new(width as usize, height as usize)), ..Self::new(width, height) }
    }

    /// Adds one sample to every pixel, `sample(i)` for pixel i (row-major: one iteration of a
    /// bidirectional method, computed here row by row in parallel) and, with block statistics,
    /// the batch's block means.
    pub fn add_batch(&mut self, sample: impl Fn(usize) -> (LayeredRadiance, SampledWavelengths) + Sync) {
        let w = self.width as usize;
        // the luminances go to the block statistics, which keep their list between batches
        let mut blocks = self.blocks.take();
        let mut y = match &mut blocks {
            Some(b) => b.take_luminances(),
            None => vec![[0.0; N_QUANTITIES]; self.pixels.len()],
        };
        self.rows_mut().zip(y.par_chunks_mut(w.max(1))).enumerate().with_max_len(1).for_each(|(r, (mut row, y))| {
            for (x, y) in y.iter_mut().enumerate() {
                let (l, wl) = sample(r * w + x);
                *y = row.add(x, &l, &wl);
            }
        });
        if let Some(b) = &mut blocks {
            b.add_luminances(y);
        }
        self.blocks = blocks;
    }

    /// Mean luminance of `q` at pixel `i`.
    pub fn mean_y(&self, i: usize, q: Quantity) -> f64 {
        let p = &self.pixels[i];
        if p.samples == 0 { 0.0 } else { p.sum_y(q) / p.samples as f64 }
    }

    /// Mean XYZ of `layer` at pixel `i`.
    pub fn mean_xyz(&self, i: usize, layer: usize) -> [f64; 3] {
        let p = &self.pixels[i];
        if p.samples == 0 {
            return [0.0; 3];
        }
        p.xyz[layer].map(|v| v / p.samples as f64)
    }

    /// Output channels: beauty `R,G,B` (the default layer, plain RGB), the beauty's CIE XYZ in
    /// its own layer `XYZ.X/Y/Z` (`XYZ.Y` = [`LUMINANCE`]: a top-level `Y` is read as alpha by
    /// OpenImageIO), and `<layer>.R/G/B` for every layer.
    /// Beauty is the sum of the emission, direct and indirect layers' RGB, so beauty = emission +
    /// direct + indirect exactly up to one float rounding per addition; `caustic` is the part of
    /// `indirect` that reached its diffuse vertex through specular events only.
    pub fn channels(&self) -> Vec<Channel> {
        let n = self.pixels.len();
        let mut beauty = [vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]];
        let mut xyz_out = [vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]];
        let mut layers: Vec<[Vec<f32>; 3]> =
            (0..N_LAYERS).map(|_| [vec![0.0; n], vec![0.0; n], vec![0.0; n]]).collect();
        for i in 0..n {
            let mut sum_rgb = [0.0f32; 3];
            let mut sum_xyz = [0.0f32; 3];
            for (l, layer) in layers.iter_mut().enumerate() {
                let xyz = self.mean_xyz(i, l).map(|v| v as f32);
                let rgb = xyz_to_linear_srgb(xyz);
                for k in 0..3 {
                    layer[k][i] = rgb[k];
                }
                if l < BEAUTY_LAYERS {
                    for k in 0..3 {
                        sum_rgb[k] += rgb[k];
                    }
                    for k in 0..3 {
                        sum_xyz[k] += xyz[k];
                    }
                }
            }
            for k in 0..3 {
                beauty[k][i] = sum_rgb[k];
                xyz_out[k][i] = sum_xyz[k];
            }
        }
        // the names from the output table (film/outputs.rs): beauty "", XYZ, then each layer
        let names = |layer: &str, set: ChannelSet| {
            set.names().iter().map(|c| outputs::channel_name(layer, c)).collect::<Vec<_>>()
        };
        let mut out = Vec::new();
        for (name, values) in names("", ChannelSet::Rgb).into_iter().zip(beauty) {
            out.push(Channel { name, values });
        }
        for (name, values) in names("XYZ", ChannelSet::Xyz).into_iter().zip(xyz_out) {
            out.push(Channel { name, values });
        }
        for (l, layer) in layers.into_iter().enumerate() {
            for (name, values) in names(LAYER_NAMES[l], ChannelSet::Rgb).into_iter().zip(layer) {
                out.push(Channel { name, values });
            }
        }
        out.push(Channel { name: SAMPLES.into(), values: self.pixels.iter().map(|p| p.samples as f32).collect() });
        out.push(Channel { name: STDERR.into(), values: self.pixels.iter().map(|p| p.stderr_y() as f32).collect() });
        if let Some(b) = &self.blocks {
            out.extend(b.channels(self.width as usize, self.height as usize));
        }
        if let Some(s) = &self.spectral {
            out.extend(s.channels(|p| self.pixels[p].samples));
        }
        out
    }

    /// The image's estimated RMS relative error: sqrt of the mean over pixels of
    /// stderr^2 / (Y^2 + 1e-3), the expected relMSE against the converged image (the relMSE of
    /// `quasar compare`) if the pixel estimates are unbiased. Infinite before every pixel has two
    /// samples.
    pub fn estimated_rel_error(&self) -> f64 {
        if self.pixels.iter().any(|p| p.samples < 2) {
            return f64::INFINITY;
        }
        let sum: f64 = self
            .pixels
            .iter()
            .map(|p| {
                let y: f64 = p.xyz[..BEAUTY_LAYERS].iter().map(|l| l[1]).sum::<f64>() / p.samples as f64;
                let e = p.stderr_y();
                e * e / (y * y + REL_EPS)
            })
            .sum();
        (sum / self.pixels.len().max(1) as f64).sqrt()
    }

    /// Total number of rejected (non-finite) samples.
    pub fn rejected_samples(&self) -> u64 {
        self.pixels.iter().map(|p| p.rejected).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

    #[test]
    fn standard_error_of_known_samples() {
        let wl = SampledWavelengths::from_parts([550.0; 4], [1.0; 4]);
        let mut p = PixelSum::default();
        let unit = wl.luminance(SampledSpectrum::one());
        for v in [1.0f32, 3.0] {
            let l = LayeredRadiance { direct: SampledSpectrum::one() * v, ..Default::default() };
            p.add(&l, &wl);
        }
        // samples y = unit, 3 unit: variance 2 unit^2, stderr sqrt(2 / 2) unit
        assert!((p.stderr_y() - unit as f64).abs() < 1e-4 * unit as f64);
        let mut film = Film::new(1, 1);
        assert!(film.estimated_rel_error().is_infinite());
        film.pixels[0] = p;
        let y = 2.0 * unit as f64;
        let expected = (unit as f64 * unit as f64 / (y * y + REL_EPS)).sqrt();
        assert!((film.estimated_rel_error() - expected).abs() < 1e-6);
    }

    /// The output table and the film agree: every channel the film writes has its row, and
    /// every row the film produces in every render is written (the radiance layers included).
    #[test]
    fn the_film_writes_its_rows_of_the_output_table() {
        let film = Film::with_block_batches(3, 2).with_spectral(SpectralBins::new(4, 400.0, 700.0).unwrap());
        let written: Vec<String> = film.channels().into_iter().map(|c| c.name).collect();
        for name in &written {
            let row = outputs::group_of(name).unwrap_or_else(|| panic!("{name} has no row in OUTPUTS"));
            assert_eq!(row.producer, outputs::Producer::Film, "{name}");
        }
        for row in outputs::OUTPUTS.iter().filter(|r| r.producer == outputs::Producer::Film) {
            assert!(written.iter().any(|n| row.holds(n)), "the film writes no channel of {}", row.pattern());
            for name in row.channel_names() {
                assert!(written.contains(&name), "the film does not write {name}");
            }
        }
        for layer in LAYER_NAMES {
            assert!(outputs::OUTPUTS.iter().any(|r| r.layer == layer), "layer {layer} has no row");
        }
    }
}
