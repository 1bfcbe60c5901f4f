//! Geometry: rays, triangles, the BVH and surface interactions.

pub mod accel;
pub mod mesh;
pub mod ray;
mod wide_bvh;

pub use accel::{Accel, Hit};
pub use mesh::{NONE, TriangleGeom, TriangleInfo};
pub use ray::{Ray, offset_origin};
