//! Integrators (DESIGN.md section 3). Each one turns camera rays (and, for the bidirectional
//! methods, light paths) into layered radiance.

pub mod analysis;
pub mod bidir;
pub mod direct;
pub mod method;
pub mod pt;
pub mod scatter;

pub use bidir::VismapSettings;
pub use pt::PtSettings;
