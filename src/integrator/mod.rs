//! Integrators (DESIGN.md section 3). Each one turns camera rays into layered radiance.

pub mod pt;

pub use pt::{LayeredRadiance, PtSettings};
