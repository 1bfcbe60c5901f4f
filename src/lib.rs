//! quasar: a physically based, spectral CPU renderer (see DESIGN.md).
//!
//! Data flow: `quasar_importers` turns files into a plain [`quasar_importers::SceneDesc`];
//! [`scene::Scene::compile`] builds the BVH, lights and materials; an integrator
//! ([`integrator`]) estimates radiance per pixel into the [`film::Film`]; [`output`] writes the
//! multi-layer EXR.
#![warn(missing_docs)]

pub mod analysis;
pub mod bsdf_report;
pub mod camera;
pub mod checkpoint;
pub mod compare;
pub mod convergence;
pub mod env_map;
pub mod film;
pub mod geometry;
pub mod import_bench;
pub mod integrator;
pub mod interrupt;
pub mod job;
pub mod light;
pub mod material_library;
pub mod merge;
pub mod method;
pub mod mitsuba_export;
pub mod output;
pub mod plot;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod ztest;

pub use quasar_importers as importers;
pub use quasar_materials as materials;
