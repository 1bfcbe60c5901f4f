//! quasar-materials: spectra, colorimetry and BSDF models.
//!
//! A [`Material`] is plain data (spectral parameters) that produces a [`Bsdf`] for the
//! wavelengths of a path; integrators only call the BSDF's `f`, `sample_f` and `pdf`.
#![warn(missing_docs)]

pub mod absorption;
pub mod bsdf;
pub mod catalogue;
pub mod coating;
pub mod frame;
pub mod material;
pub mod non_uniformity;
pub mod pbr;
pub mod scattering;
pub mod spectrum;
pub mod tabulated;
pub mod tabulation;
pub mod warp;

pub use absorption::Absorption;
pub use bsdf::microfacet::Masking;
pub use bsdf::{Bsdf, BsdfSample, CoatedBsdf, Lobe, TabulatedBsdf, TransportMode};
pub use coating::{CoatAbsorption, Coating};
pub use frame::Frame;
pub use material::{ConductorFresnel, Ior, Material};
pub use non_uniformity::{NARROW_KAPPA, NonUniformity};
pub use pbr::{PbrParams, pbr_material, pbr_material_at};
pub use scattering::{HenyeyGreenstein, Scattering};
pub use tabulated::{TabulatedSpec, TabulatedTable};
