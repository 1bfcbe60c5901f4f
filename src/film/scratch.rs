//! Working storage that a type keeps between calls so that a call made once per iteration
//! allocates only while its lists still grow.

use std::fmt;

/// Storage kept between calls; not part of its owner's value: it compares equal to any other,
/// clones as empty and prints as nothing, so an owner can still derive `Clone`, `PartialEq` and
/// `Debug` over its real fields.
#[derive(Default)]
pub struct Scratch<T: Default>(pub T);

impl<T: Default> Clone for Scratch<T> {
    fn clone(&self) -> Self {
        Self(T::default())
    }
}

impl<T: Default> PartialEq for Scratch<T> {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl<T: Default> fmt::Debug for Scratch<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Scratch")
    }
}
