//! The settings of the bidirectional methods (`vismap`, `adaptive`, `quasi`, `adaptive+quasi`):
//! one type, validated once by the method table (`integrator::method`).

/// Where camera paths gather photons.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GatherDepth {
    /// Every pixel at this depth (`vismap --gather-depth D`; 0 = first non-specular vertex).
    Fixed(u32),
    /// Per pixel and iteration, the depth of least non-uniformity kappa (docs/architecture.md §7.5), up to
    /// `max_depth`.
    Adaptive {
        /// Deepest depth considered.
        max_depth: u32,
        /// The paper's variant: the depth comes from the iteration's own first camera ray (biased:
        /// the choice depends on the estimate's own path). Otherwise: the mode of the depths
        /// chosen by independent pilot paths of earlier iterations (unbiased per iteration).
        paper: bool,
    },
}

/// Photons per iteration and pixel unless `photons_per_iteration` says otherwise. Chosen from
/// the time to relMSE 0.01 of `auto` at 1, 2, 4, 8 and 16 photons per pixel (BENCHMARKS.md,
/// issue 15): the best count is 4 on the glass plate (photons are cheap: most leave the scene
/// after one or two hits) and 1 in the closed glossy room (every photon bounces until Russian
/// roulette ends it); 2 is within 30% of the best on both, where 1 took twice the best time on
/// the glass plate.
pub const DEFAULT_PHOTONS_PER_PIXEL: u64 = 2;

/// Settings of the bidirectional methods: `vismap`, `adaptive`, `quasi`, `adaptive+quasi`
/// (CLI: `--iterations --photons-per-iteration --gather-depth --radius --alpha --cone`).
#[derive(Clone, Copy, Debug)]
pub struct VismapSettings {
    /// Number of iterations (each: one camera path per pixel and one photon pass).
    pub iterations: u32,
    /// Photons per iteration (None: [`DEFAULT_PHOTONS_PER_PIXEL`] per pixel).
    pub photons_per_iteration: Option<u64>,
    /// How the gather depth is chosen.
    pub depth: GatherDepth,
    /// Half-angle in degrees of the quasi-specular cone (None: no quasi-specular tracing).
    pub cone_deg: Option<f32>,
    /// Initial indirect gather radius in scene units (None: automatic from the pixel footprint).
    pub radius: Option<f32>,
    /// Automatic initial indirect radius, in pixel footprints at the path's first non-specular
    /// vertex (the visibility point itself at gather depth 0).
    pub radius_pixels: f32,
    /// Caustic radius / indirect radius (< 1: caustics are sharper than smooth indirect light).
    pub caustic_ratio: f32,
    /// Radius reduction parameter alpha in (0, 1) of progressive photon mapping.
    pub alpha: f32,
    /// Longest chain of specular events a camera path follows.
    pub max_specular: u32,
}

impl Default for VismapSettings {
    fn default() -> Self {
        Self {
            iterations: 64,
            photons_per_iteration: None,
            depth: GatherDepth::Fixed(0),
            cone_deg: None,
            radius: None,
            radius_pixels: DEFAULT_RADIUS_PIXELS,
            caustic_ratio: 0.5,
            alpha: DEFAULT_ALPHA,
            max_specular: 64,
        }
    }
}

/// The default radius reduction alpha, chosen from measured time to error (BENCHMARKS.md
/// "Radius reduction alpha"): on the glass plate and the glossy room, relMSE at equal time
/// from 2 to 64 s falls as alpha grows from 0.5 to 0.8 (block z-tests passing at every
/// budget); 0.75 reaches relMSE 0.003 1.45x sooner than the literature's 2/3 and 11-12% later
/// than 0.8, whose asymptotically best rate (bias ~ N^(alpha - 1), variance ~ N^-alpha:
/// both N^-2/3) needs longer renders than any measured to pay off; 0.75's bias still decays as
/// N^-1/4, faster than 0.8's N^-1/5, beyond where a reference can check it.
pub const DEFAULT_ALPHA: f32 = 0.75;

/// The default automatic initial gather radius, in pixel footprints at the first non-specular
/// vertex (`radius_pixels`).
pub const DEFAULT_RADIUS_PIXELS: f32 = 3.0;

/// Most depths an adaptive histogram tracks (0..=MAX_ADAPTIVE_DEPTH).
pub const MAX_ADAPTIVE_DEPTH: u32 = 7;

impl VismapSettings {
    /// Photons per iteration for an image of `pixels` pixels (at least 1).
    pub fn photons(&self, pixels: u64) -> u64 {
        self.photons_per_iteration.unwrap_or(pixels.saturating_mul(DEFAULT_PHOTONS_PER_PIXEL)).max(1)
    }

    /// Header entries (`photons_per_iteration` needs the image's pixel count for its default).
    pub fn header(&self, pixels: u64) -> Vec<(String, String)> {
        let depth = match self.depth {
            GatherDepth::Fixed(d) => d.to_string(),
            GatherDepth::Adaptive { max_depth, paper } => {
                format!("adaptive (0..={max_depth}, {})", if paper { "paper variant" } else { "earlier iterations" })
            }
        };
        vec![
            ("photons_per_iteration".into(), self.photons(pixels).to_string()),
            ("gather_depth".into(), depth),
            ("cone_deg".into(), self.cone_deg.map_or("none".into(), |c| c.to_string())),
            (
                "radius".into(),
                self.radius.map_or(format!("auto ({} pixel footprints)", self.radius_pixels), |r| r.to_string()),
            ),
            ("caustic_radius_ratio".into(), self.caustic_ratio.to_string()),
            ("alpha".into(), self.alpha.to_string()),
        ]
    }
}
