//! Spectral model (docs/architecture.md §3): hero-wavelength sampled spectra, spectral curves,
//! CIE colorimetry and the RGB uplift.

pub mod cie;
#[rustfmt::skip]
pub mod cie_data;
pub mod color;
pub mod curve;
pub mod rgb_uplift;
pub mod sampled;

pub use curve::DenseSpectrum;
pub use curve::{RgbSpectrum, Spectrum, SpectrumError, StandardIlluminant};
pub use sampled::{
    GridPos, LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths, XyzWeights,
};
