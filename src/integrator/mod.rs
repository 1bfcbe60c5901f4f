//! The integration methods (docs/architecture.md §7): each one turns camera rays (and,
//! for the bidirectional methods, light paths) into layered radiance, in passes the render
//! driver (`render::driver`) asks for through [`pass::RenderMethod`]. The methods are a closed set
//! chosen by name in one table, [`method::METHODS`].

pub mod analysis;
pub mod bidir;
pub mod direct;
pub mod direct_lighting;
pub mod entry;
pub mod illuminance;
pub mod medium_vertex;
pub mod method;
pub mod params;
pub mod pass;
pub mod per_pixel;
pub mod pt;
pub mod scatter;
