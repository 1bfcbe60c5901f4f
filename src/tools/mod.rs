//! Tools built on the renderer: image comparison and the block z-test, merging shards,
//! convergence benchmarks and plots, BSDF reports, the material library generator, import
//! benchmarks and the Mitsuba 3 export of the cross-check.

pub mod bsdf_report;
pub mod compare;
pub mod convergence;
pub mod doc_tables;
pub mod import_bench;
pub mod info;
pub mod light_summary;
pub mod material_library;
pub mod merge;
pub mod mitsuba_export;
pub mod mitsuba_obj;
pub mod plot;
pub mod report_format;
pub mod ztest;
