//! The integration methods, chosen by name in one place (DESIGN.md section 3), and the settings
//! of the bidirectional ones from the command line.

use anyhow::{Result, bail};

use crate::core::scene::Scene;
use crate::integrator::analysis::SceneAnalysis;
use crate::integrator::bidir::{GatherDepth, MAX_ADAPTIVE_DEPTH, VismapSettings};

/// Integration methods the renderer offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Scene analysis picks the method (DESIGN.md 3.5).
    Auto,
    /// Reference path tracer (3.1).
    Pt,
    /// Bidirectional tracing with visibility maps at a fixed gather depth (3.2).
    Vismap,
    /// Adaptive backward-trace depth (3.3).
    Adaptive,
    /// Quasi-specular backward tracing (3.4).
    Quasi,
    /// Both (3.4, last paragraph).
    AdaptiveQuasi,
}

/// Every method name, as accepted on the command line and in scene files.
pub const METHOD_NAMES: [&str; 6] = ["auto", "pt", "vismap", "adaptive", "quasi", "adaptive+quasi"];

impl Method {
    /// Parses a method name.
    pub fn from_name(name: &str) -> Result<Self> {
        Ok(match name {
            "auto" => Self::Auto,
            "pt" => Self::Pt,
            "vismap" => Self::Vismap,
            "adaptive" => Self::Adaptive,
            "quasi" => Self::Quasi,
            "adaptive+quasi" => Self::AdaptiveQuasi,
            _ => bail!("unknown method '{name}' (expected one of: {})", METHOD_NAMES.join(", ")),
        })
    }

    /// The method actually run: `auto` becomes what [`SceneAnalysis::auto_method`] says.
    pub fn resolve(self, scene: &Scene) -> Self {
        match self {
            Self::Auto => Self::from_name(SceneAnalysis::of(scene).auto_method()).unwrap_or(Self::Pt),
            m => m,
        }
    }

    /// Name as written in headers.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Pt => "pt",
            Self::Vismap => "vismap",
            Self::Adaptive => "adaptive",
            Self::Quasi => "quasi",
            Self::AdaptiveQuasi => "adaptive+quasi",
        }
    }

    /// True for the methods built on visibility maps and photons.
    pub fn is_bidirectional(self) -> bool {
        matches!(self, Self::Vismap | Self::Adaptive | Self::Quasi | Self::AdaptiveQuasi)
    }
}

/// Command-line settings of the bidirectional methods (None: the method's default).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BidirectionalOptions {
    /// Iterations (default: the scene's spp).
    pub iterations: Option<u32>,
    /// Photons per iteration (default: one per pixel).
    pub photons_per_iteration: Option<u64>,
    /// Fixed gather depth (`vismap`, `quasi`; default 0).
    pub gather_depth: Option<u32>,
    /// Deepest depth the adaptive methods consider (default 4).
    pub max_gather_depth: Option<u32>,
    /// The adaptive methods pick the depth from the iteration's own first ray (the paper's,
    /// biased variant) instead of earlier iterations' pilot paths.
    pub adaptive_paper: bool,
    /// Quasi-specular cone half-angle in degrees (default 10).
    pub cone_deg: Option<f32>,
    /// Initial gather radius in scene units (default: from the pixel footprint).
    pub radius: Option<f32>,
    /// Radius reduction alpha (default 2/3).
    pub alpha: Option<f32>,
}

impl BidirectionalOptions {
    /// True when any option was given.
    pub fn any(&self) -> bool {
        *self != Self::default()
    }

    /// The scene file's `[render]` settings as options.
    pub fn from_scene(s: &quasar_importers::BidirectionalSettings) -> Self {
        Self {
            iterations: s.iterations,
            photons_per_iteration: s.photons_per_iteration,
            gather_depth: s.gather_depth,
            max_gather_depth: s.max_gather_depth,
            adaptive_paper: false,
            cone_deg: s.cone_deg,
            radius: s.radius,
            alpha: s.alpha,
        }
    }

    /// Only the options `method` uses (scene-file settings may name others: a scene written for
    /// `quasi` can still be rendered with `--method vismap`).
    pub fn applicable_to(&self, method: Method) -> Self {
        let adaptive = matches!(method, Method::Adaptive | Method::AdaptiveQuasi);
        let quasi = matches!(method, Method::Quasi | Method::AdaptiveQuasi);
        Self {
            gather_depth: self.gather_depth.filter(|_| !adaptive),
            max_gather_depth: self.max_gather_depth.filter(|_| adaptive),
            adaptive_paper: self.adaptive_paper && adaptive,
            cone_deg: self.cone_deg.filter(|_| quasi),
            ..self.clone()
        }
    }

    /// These options, with the ones not given taken from `fallback`.
    pub fn or(&self, fallback: &Self) -> Self {
        Self {
            iterations: self.iterations.or(fallback.iterations),
            photons_per_iteration: self.photons_per_iteration.or(fallback.photons_per_iteration),
            gather_depth: self.gather_depth.or(fallback.gather_depth),
            max_gather_depth: self.max_gather_depth.or(fallback.max_gather_depth),
            adaptive_paper: self.adaptive_paper || fallback.adaptive_paper,
            cone_deg: self.cone_deg.or(fallback.cone_deg),
            radius: self.radius.or(fallback.radius),
            alpha: self.alpha.or(fallback.alpha),
        }
    }
}

/// Default deepest gather depth of the adaptive methods.
pub const DEFAULT_MAX_GATHER_DEPTH: u32 = 4;
/// Default quasi-specular cone half-angle (degrees).
pub const DEFAULT_CONE_DEG: f32 = 10.0;

/// The settings of a bidirectional `method` from `o`; `iterations` is the default iteration count.
/// Errors name the option and its valid range; options the method does not use are errors too.
pub fn bidirectional_settings(method: Method, o: &BidirectionalOptions, iterations: u32) -> Result<VismapSettings> {
    let adaptive = matches!(method, Method::Adaptive | Method::AdaptiveQuasi);
    let quasi = matches!(method, Method::Quasi | Method::AdaptiveQuasi);
    if adaptive && o.gather_depth.is_some() {
        bail!("--gather-depth fixes the depth; {} chooses it (use --max-gather-depth)", method.name());
    }
    if !adaptive && (o.max_gather_depth.is_some() || o.adaptive_paper) {
        bail!("--max-gather-depth and --adaptive-paper apply to adaptive and adaptive+quasi");
    }
    if !quasi && o.cone_deg.is_some() {
        bail!("--cone applies to quasi and adaptive+quasi");
    }
    let mut v = VismapSettings { iterations: o.iterations.unwrap_or(iterations).max(1), ..VismapSettings::default() };
    if let Some(n) = o.photons_per_iteration {
        if n == 0 || n > 1 << 32 {
            bail!("--photons-per-iteration must be in 1..=2^32, got {n}");
        }
        v.photons_per_iteration = Some(n);
    }
    let fixed = o.gather_depth.unwrap_or(0);
    if fixed > 64 {
        bail!("--gather-depth must be in 0..=64, got {fixed}");
    }
    v.depth = GatherDepth::Fixed(fixed);
    if adaptive {
        let max_depth = o.max_gather_depth.unwrap_or(DEFAULT_MAX_GATHER_DEPTH);
        if max_depth > MAX_ADAPTIVE_DEPTH {
            bail!("--max-gather-depth must be in 0..={MAX_ADAPTIVE_DEPTH}, got {max_depth}");
        }
        v.depth = GatherDepth::Adaptive { max_depth, paper: o.adaptive_paper };
    }
    if quasi {
        let c = o.cone_deg.unwrap_or(DEFAULT_CONE_DEG);
        if !(c > 0.0 && c < 90.0) {
            bail!("--cone must be in (0, 90) degrees, got {c}");
        }
        v.cone_deg = Some(c);
    }
    if let Some(r) = o.radius {
        if !(r > 0.0 && r.is_finite()) {
            bail!("--radius must be a positive length, got {r}");
        }
        v.radius = Some(r);
    }
    if let Some(a) = o.alpha {
        if !(a > 0.0 && a < 1.0) {
            bail!("--alpha must be in (0, 1), got {a}");
        }
        v.alpha = a;
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_options_are_checked() {
        for n in METHOD_NAMES {
            assert_eq!(Method::from_name(n).unwrap().name(), n);
        }
        assert!(Method::from_name("bdpt").is_err());
        let o = |f: fn(&mut BidirectionalOptions)| {
            let mut o = BidirectionalOptions::default();
            f(&mut o);
            o
        };
        assert!(bidirectional_settings(Method::Vismap, &o(|o| o.cone_deg = Some(5.0)), 4).is_err());
        assert!(bidirectional_settings(Method::Adaptive, &o(|o| o.gather_depth = Some(1)), 4).is_err());
        assert!(bidirectional_settings(Method::Quasi, &o(|o| o.cone_deg = Some(95.0)), 4).is_err());
        assert!(bidirectional_settings(Method::Vismap, &o(|o| o.alpha = Some(1.0)), 4).is_err());
        let v = bidirectional_settings(Method::AdaptiveQuasi, &o(|o| o.cone_deg = Some(30.0)), 9).unwrap();
        assert_eq!(v.iterations, 9);
        assert_eq!(v.cone_deg, Some(30.0));
        assert_eq!(v.depth, GatherDepth::Adaptive { max_depth: DEFAULT_MAX_GATHER_DEPTH, paper: false });
    }
}
