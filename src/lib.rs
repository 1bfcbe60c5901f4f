//! quasar renderer
