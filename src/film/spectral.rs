//! Spectral radiance bins of the beauty image (`--spectral-bins`), written as the emissive
//! channels `S0.<lambda>nm` of the OpenEXR spectral layout of Fichet, Pacanowski and Wilkie,
//! "An OpenEXR Layout for Spectral Images", JCGT 10(3), 2021 (the layout pbrt-v4's spectral film
//! writes and colour-science reads).
//!
//! Bin b covers [lambda_b, lambda_b + d) with d = (max - min) / n. A path's hero wavelengths
//! lambda_i (density p(lambda_i), N = 4 of them) give the unbiased estimate of the bin's mean
//! spectral radiance
//!
//!   L_b = (1/d) integral_bin L(lambda) dlambda ~ (1/N) sum_i 1[lambda_i in bin] L(lambda_i) / (p(lambda_i) d),
//!
//! the same Monte Carlo integral over wavelength as the film's CIE XYZ, with the bin's box
//! in place of a colour matching function. A pixel's channel is the mean over its samples, in
//! the radiance units of the scene (W m^-2 sr^-1 nm^-1 when its lights are absolute).

use quasar_materials::spectrum::sampled::{LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES};
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

use super::Channel;

/// Most bins a render may ask for (one per 0.5 nm over the sampled range).
pub const MAX_SPECTRAL_BINS: u32 = 940;

/// The spectral bins of a render: `n` equal bins over [`min_nm`, `max_nm`], inside the
/// sampled range [LAMBDA_MIN, LAMBDA_MAX] (validated once, by [`SpectralBins::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralBins {
    n: u32,
    min_nm: f32,
    max_nm: f32,
}

impl SpectralBins {
    /// `n` bins over [`min_nm`, `max_nm`]; an error says which bound is out of range.
    pub fn new(n: u32, min_nm: f32, max_nm: f32) -> Result<Self, String> {
        if !(1..=MAX_SPECTRAL_BINS).contains(&n) {
            return Err(format!("{n} spectral bins: give 1 to {MAX_SPECTRAL_BINS}"));
        }
        let in_range = |v: f32| (LAMBDA_MIN..=LAMBDA_MAX).contains(&v);
        if !(in_range(min_nm) && in_range(max_nm) && min_nm < max_nm) {
            return Err(format!(
                "spectral range {min_nm}:{max_nm} nm: give MIN < MAX inside the sampled range {LAMBDA_MIN}:{LAMBDA_MAX} nm"
            ));
        }
        Ok(Self { n, min_nm, max_nm })
    }

    /// Number of bins.
    pub fn count(&self) -> usize {
        self.n as usize
    }

    /// Width of a bin in nm.
    pub fn width_nm(&self) -> f32 {
        (self.max_nm - self.min_nm) / self.n as f32
    }

    /// The range [min, max] in nm.
    pub fn range_nm(&self) -> (f32, f32) {
        (self.min_nm, self.max_nm)
    }

    /// Centre of bin `b` in nm, the wavelength its channel is named after.
    pub fn centre_nm(&self, b: usize) -> f64 {
        let d = (self.max_nm as f64 - self.min_nm as f64) / self.n as f64;
        self.min_nm as f64 + (b as f64 + 0.5) * d
    }

    /// The bin holding `lambda`, None outside the range (the last bin includes `max_nm`).
    #[inline]
    pub fn bin_of(&self, lambda: f32) -> Option<usize> {
        if !(self.min_nm..=self.max_nm).contains(&lambda) {
            return None;
        }
        let b = ((lambda - self.min_nm) / (self.max_nm - self.min_nm) * self.n as f32) as usize;
        Some(b.min(self.n as usize - 1))
    }

    /// Channel name of bin `b`: `S0.` and the centre in nm with six decimals and a comma as
    /// the decimal separator, as Fichet et al. 2021 (sec. 3.1) and pbrt-v4 write it
    /// (`S0.550,000000nm`).
    pub fn channel_name(&self, b: usize) -> String {
        let micro = (self.centre_nm(b) * 1e6).round() as u64;
        format!("S0.{},{:06}nm", micro / 1_000_000, micro % 1_000_000)
    }

    /// Adds one sample's estimate of every bin's mean (see the module doc) to `sums`.
    #[inline]
    pub fn add(&self, sums: &mut [f64], l: SampledSpectrum, wl: &SampledWavelengths) {
        let pdf = wl.pdf();
        let scale = 1.0 / (N_SPECTRUM_SAMPLES as f64 * self.width_nm() as f64);
        for i in 0..N_SPECTRUM_SAMPLES {
            if pdf.0[i] == 0.0 || l.0[i] == 0.0 {
                continue;
            }
            if let Some(b) = self.bin_of(wl.lambda(i)) {
                sums[b] += l.0[i] as f64 / pdf.0[i] as f64 * scale;
            }
        }
    }

    /// True for a channel name of an emissive spectral bin (`S0.<lambda>nm`).
    pub fn is_channel(name: &str) -> bool {
        name.strip_prefix("S0.")
            .and_then(|r| r.strip_suffix("nm"))
            .is_some_and(|v| !v.is_empty() && v.chars().all(|c| c.is_ascii_digit() || c == ','))
    }

    /// The header attributes the layout defines for an emissive image: its version and the
    /// radiance units of the `S0` channels (per nm implied by the spectral channels, as in
    /// pbrt-v4 and the authors' reference code).
    pub fn attributes() -> [(&'static str, &'static str); 2] {
        [("spectralLayoutVersion", "1.0"), ("emissiveUnits", "W.m^-2.sr^-1")]
    }
}

/// The per-pixel sums of the spectral bins: `count` values per pixel, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralSums {
    /// The bins.
    pub bins: SpectralBins,
    /// Sum over a pixel's samples of each bin's estimate, pixel-major (`bins.count()` per pixel).
    pub sums: Vec<f64>,
}

impl SpectralSums {
    /// Zero sums for `pixels` pixels.
    pub fn new(bins: SpectralBins, pixels: usize) -> Self {
        Self { bins, sums: vec![0.0; pixels * bins.count()] }
    }

    /// Channels `S0.<lambda>nm` of the mean over `samples[p]` samples of every pixel p.
    pub fn channels(&self, samples: impl Fn(usize) -> u64) -> Vec<Channel> {
        let n = self.bins.count();
        let pixels = self.sums.len() / n;
        (0..n)
            .map(|b| Channel {
                name: self.bins.channel_name(b),
                values: (0..pixels)
                    .map(|p| match samples(p) {
                        0 => 0.0,
                        s => (self.sums[p * n + b] / s as f64) as f32,
                    })
                    .collect(),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_are_validated_named_and_located() {
        assert!(SpectralBins::new(0, 400.0, 700.0).is_err());
        assert!(SpectralBins::new(MAX_SPECTRAL_BINS + 1, 400.0, 700.0).is_err());
        assert!(SpectralBins::new(4, 700.0, 400.0).is_err());
        assert!(SpectralBins::new(4, 300.0, 700.0).unwrap_err().contains("360:830"));
        let b = SpectralBins::new(3, 400.0, 700.0).unwrap();
        assert_eq!(b.channel_name(0), "S0.450,000000nm");
        assert_eq!(b.channel_name(1), "S0.550,000000nm");
        let fine = SpectralBins::new(470, 360.0, 830.0).unwrap();
        assert_eq!(fine.channel_name(0), "S0.360,500000nm");
        let odd = SpectralBins::new(7, 360.0, 830.0).unwrap();
        assert_eq!(odd.channel_name(0), format!("S0.393,571429nm"));
        assert_eq!(b.bin_of(399.9), None);
        assert_eq!(b.bin_of(400.0), Some(0));
        assert_eq!(b.bin_of(500.0), Some(1));
        assert_eq!(b.bin_of(700.0), Some(2));
        assert_eq!(b.bin_of(700.1), None);
        assert!(SpectralBins::is_channel(&fine.channel_name(3)));
        assert!(!SpectralBins::is_channel("S0.Y") && !SpectralBins::is_channel("XYZ.Y"));
    }

    #[test]
    fn a_sample_adds_its_monte_carlo_weight_to_its_bin() {
        let b = SpectralBins::new(3, 400.0, 700.0).unwrap();
        let wl = SampledWavelengths::from_parts([450.0, 460.0, 650.0, 800.0], [0.01, 0.02, 0.0, 0.01]);
        let mut sums = vec![0.0; 3];
        b.add(&mut sums, SampledSpectrum([1.0, 2.0, 5.0, 7.0]), &wl);
        // bin 0: (1 / 0.01 + 2 / 0.02) / (4 x 100 nm); 650 nm has pdf 0 (terminated), 800 nm is outside
        assert!((sums[0] - 0.5).abs() < 1e-6, "{sums:?}");
        assert_eq!(&sums[1..], &[0.0, 0.0]);
        let s = SpectralSums { bins: b, sums: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0] };
        let ch = s.channels(|p| [2, 0][p]);
        assert_eq!(ch[2].name, "S0.650,000000nm");
        assert_eq!(ch[2].values, vec![1.5, 0.0]);
    }
}
