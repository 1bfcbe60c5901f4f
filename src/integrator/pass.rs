//! The pass boundary between the render driver and a method: [`RenderMethod`].

use crate::film::{Channel, Film};

/// How a pass ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassEnd {
    /// Every pixel received every unit of the pass.
    Complete,
    /// A stop request ended the pass part-way: some pixels have fewer units (each pixel is still
    /// the mean of its own samples, so the image stays valid, but the state is no checkpoint).
    Partial,
}

/// What a method may ask of the driver during a pass.
pub struct PassControl<'a> {
    /// Reports `n` pixel-units done (the progress bar).
    pub progress: &'a (dyn Fn(u64) + Sync),
    /// True once the user asked the render to stop (Ctrl-C).
    pub stop: &'a (dyn Fn() -> bool + Sync),
}

/// The interface between the render driver and a method. A method renders *units* — samples
/// per pixel, iterations — of this render share (their random streams and indices are the
/// method's business, so that passes of any size give the same image); the driver owns the
/// budgets, the loop, checkpoints and output. Called once per pass, so dynamic dispatch costs
/// nothing; the per-ray code inside stays statically dispatched.
pub trait RenderMethod: Send {
    /// An empty film of the kind this method fills (with batch statistics of block means for
    /// methods whose pixels share work within a unit).
    fn new_film(&self, width: u32, height: u32) -> Film;

    /// What one unit is, in the plural, for progress lines ("samples per pixel", "iterations").
    fn unit_name(&self) -> &'static str;

    /// Largest number of units one pass may render (1 for methods whose units cost a whole
    /// image each).
    fn max_pass(&self) -> u32;

    /// Renders this shard's units `first..first + count` (counted from 0) into `film`.
    fn render_pass(&mut self, film: &mut Film, first: u32, count: u32, control: &PassControl) -> PassEnd;

    /// The method's own state after the units rendered so far (opaque to the driver; stored in
    /// checkpoints).
    fn save_state(&self) -> Vec<u8>;

    /// Restores [`save_state`](Self::save_state)'s bytes; errors say what does not fit.
    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String>;

    /// Extra output channels (e.g. `trace_depth.Y`).
    fn extra_channels(&self) -> Vec<Channel> {
        Vec::new()
    }

    /// Header entries: the method's settings and statistics.
    fn header(&self) -> Vec<(String, String)> {
        Vec::new()
    }
}
