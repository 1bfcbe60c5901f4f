//! The settings of a render job that override the scene file's `[render]` table: the command
//! line's, or a program's.

use std::path::PathBuf;

use crate::core::isa::Isa;
use crate::film::SpectralBins;
use crate::integrator::params::MethodParams;

/// Settings that override the scene file's `[render]` table (None = keep the scene's).
#[derive(Clone, Debug, Default)]
pub struct JobOverrides {
    /// Image width.
    pub width: Option<u32>,
    /// Image height.
    pub height: Option<u32>,
    /// Samples per pixel.
    pub spp: Option<u32>,
    /// Time budget in seconds.
    pub time_s: Option<f64>,
    /// Stop at this estimated RMS relative error of the image (or at the time budget or sample
    /// cap, whichever comes first).
    pub target_error: Option<f64>,
    /// Seed.
    pub seed: Option<u64>,
    /// Threads.
    pub threads: Option<usize>,
    /// Method name.
    pub method: Option<String>,
    /// Method parameters (keys of the method table: `cone_deg`, `iterations`, `max_depth`, ...),
    /// over the scene file's.
    pub params: MethodParams,
    /// Render share k of n of the samples / iterations (`--shard K/N`, merged by `quasar merge`).
    pub shard: Option<(u32, u32)>,
    /// Write checkpoints to this file.
    pub checkpoint: Option<PathBuf>,
    /// Continue the render stored in this checkpoint.
    pub resume: Option<PathBuf>,
    /// Microfacet masking-shadowing form (default: the scene's, height-correlated).
    pub masking: Option<quasar_materials::Masking>,
    /// Samples per pixel of the `illuminance.Y` layer (0: none), over the scene's setting.
    pub illuminance_samples: Option<u32>,
    /// Write the beauty's spectral radiance in these bins as `S0.<lambda>nm` channels.
    pub spectral_bins: Option<SpectralBins>,
    /// The auxiliary outputs to write (names of `--aov`), over the scene's `aovs`.
    pub aovs: Option<Vec<String>>,
    /// Rays per pixel of the auxiliary outputs, over the scene's `aov_samples`.
    pub aov_samples: Option<u32>,
    /// Instruction set of the render kernels (None: the best this CPU runs).
    pub isa: Option<Isa>,
}

impl JobOverrides {
    /// These overrides with method parameter `key` set (a key of the method table).
    pub fn with_param(mut self, key: &str, value: impl Into<crate::integrator::params::ParamValue>) -> Self {
        self.params.set(key, value);
        self
    }
}
