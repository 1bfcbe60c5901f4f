//! quasar-importers: the plain-data [`SceneDesc`] and the importers that produce it.
#![warn(missing_docs)]

pub mod scene_desc;

pub use scene_desc::*;
