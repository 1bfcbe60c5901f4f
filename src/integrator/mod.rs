//! Integrators (DESIGN.md section 3). Each one turns camera rays (and, for the bidirectional
//! methods, light paths) into layered radiance.

pub mod direct;
pub mod layers;
pub mod pt;
pub mod scatter;
pub mod vismap;

pub use layers::{LayeredRadiance, PathClass};
pub use pt::PtSettings;
pub use vismap::VismapSettings;
