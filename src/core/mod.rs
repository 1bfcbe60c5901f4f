//! The render-time scene: geometry and its BVH, camera, lights (with environment maps),
//! textures, and the random numbers and warps every integrator samples with. Depends on nothing
//! else of the crate.

pub mod alias_table;
pub mod bytes;
pub mod camera;
pub mod emission;
pub mod emission_grid;
pub mod env_map;
pub mod geometry;
pub mod interaction;
pub mod isa;
pub mod light;
pub mod luminaire;
pub mod media;
pub mod medium;
pub mod prefetch;
pub mod sampling;
pub mod scene;
pub mod texture;
