//! quasar: a physically based, spectral CPU renderer (docs/architecture.md).
//!
//! Data flow: `quasar_importers` turns files into a plain [`quasar_importers::SceneDesc`];
//! [`core::scene::Scene::compile`] builds the BVH, lights and materials; a method of the method
//! table ([`integrator::method`]) renders passes into the [`film::Film`] under the one render
//! loop ([`render::driver`]); [`output`] writes the multi-layer EXR.
#![warn(missing_docs)]

pub mod core;
pub mod film;
pub mod integrator;
pub mod output;
pub mod render;
pub mod tools;

pub use quasar_importers as importers;
pub use quasar_materials as materials;
