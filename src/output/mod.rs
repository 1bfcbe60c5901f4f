//! Writing images: multi-layer OpenEXR (atomic) and tone-mapped PNG previews.

pub mod atomic;
pub mod cryptomatte;
pub mod exr_file;
pub mod false_colour;
pub mod preview;
pub mod text;

pub use atomic::{OutputTarget, WriteError, check_writable, write_atomic, write_atomic_bytes, write_png_atomic};
pub use exr_file::{ExrImage, read_exr, write_exr_atomic};
pub use preview::write_preview_png;
