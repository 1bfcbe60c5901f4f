//! The row type of the method table ([`super::method::METHODS`]): a method's name, its
//! parameters and its constructor.

use super::params::{ParamError, ParamReader, ParamSpec};
use super::pass::RenderMethod;
use crate::core::camera::Camera;
use crate::core::scene::Scene;

/// What a method's constructor gets besides its parameters.
pub struct Build<'s> {
    /// The compiled scene.
    pub scene: &'s Scene,
    /// The camera (and image size).
    pub camera: &'s Camera,
    /// Seed of every random stream.
    pub seed: u64,
    /// Render share (K, N) of `--shard K/N`.
    pub shard: (u32, u32),
    /// Samples per pixel asked for (`--spp` or the scene's; a cap when time or an error target
    /// ends the render).
    pub spp: u32,
    /// Instruction set of the render kernels (checked to be available on this CPU).
    pub isa: crate::core::isa::Isa,
}

/// A method ready to render.
pub struct Built<'s> {
    /// Its passes.
    pub method: Box<dyn RenderMethod + 's>,
    /// Units (samples per pixel, iterations) of the whole render, before sharding.
    pub units: u32,
}

/// One row of the method table.
pub struct MethodEntry {
    /// Name on the command line, in scene files and in headers.
    pub name: &'static str,
    /// One line on what it is (help text, `quasar info`).
    pub summary: &'static str,
    /// The parameters it reads.
    pub params: &'static [&'static ParamSpec],
    /// The parameter `name:VALUE` sets in `quasar bench convergence --methods` (none: no option).
    pub variant: Option<&'static ParamSpec>,
    /// Peak memory per image pixel (film, method state, output buffers), bytes: the largest
    /// per-pixel slope of peak resident memory measured on the shipped scenes, plus 25%
    /// (BENCHMARKS.md "Memory per pixel"); `render::memory` refuses renders that exceed the
    /// machine's memory by it.
    pub bytes_per_pixel: u64,
    /// Builds the method from its parameters (each validated there, once).
    pub build: for<'s> fn(&Build<'s>, &ParamReader) -> Result<Built<'s>, ParamError>,
}

impl std::fmt::Debug for MethodEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name)
    }
}

impl PartialEq for MethodEntry {
    fn eq(&self, o: &Self) -> bool {
        self.name == o.name
    }
}
