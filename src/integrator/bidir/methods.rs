//! The method table's rows of the four bidirectional methods and their parameters:
//!
//! | parameter | vismap | adaptive | quasi | adaptive+quasi | meaning |
//! |---|---|---|---|---|---|
//! | `iterations` | x | x | x | x | iterations (default: the scene's spp) |
//! | `photons_per_iteration` | x | x | x | x | photons per iteration (default: two per pixel) |
//! | `gather_depth` | x | | x | | fixed gather depth (0: the first non-specular vertex) |
//! | `max_gather_depth` | | x | | x | deepest depth the adaptive choice considers (default 4) |
//! | `adaptive_paper` | | x | | x | the paper's own, biased depth choice |
//! | `cone_deg` | | | x | x | quasi-specular cone half-angle (default 10 degrees) |
//! | `radius` | x | x | x | x | initial gather radius (default: automatic) |
//! | `alpha` | x | x | x | x | radius reduction alpha (default 0.75) |

use super::passes::Bidirectional;
use super::settings::{DEFAULT_ALPHA, DEFAULT_RADIUS_PIXELS, GatherDepth, MAX_ADAPTIVE_DEPTH, VismapSettings};
use crate::integrator::entry::{Build, Built, MethodEntry};
use crate::integrator::params::{ParamDefault, ParamError, ParamKind, ParamReader, ParamSpec};

/// `iterations`.
pub static ITERATIONS: ParamSpec = ParamSpec {
    key: "iterations",
    flag: "iterations",
    kind: ParamKind::Int { min: 1, max: u32::MAX as i128 },
    default: ParamDefault::Computed("the scene's spp"),
    doc: "number of iterations",
};
/// `photons_per_iteration`.
pub static PHOTONS: ParamSpec = ParamSpec {
    key: "photons_per_iteration",
    flag: "photons-per-iteration",
    kind: ParamKind::Int { min: 1, max: 1 << 32 },
    default: ParamDefault::Computed("two per pixel"),
    doc: "photons traced per iteration",
};
/// `gather_depth`.
pub static GATHER_DEPTH: ParamSpec = ParamSpec {
    key: "gather_depth",
    flag: "gather-depth",
    kind: ParamKind::Int { min: 0, max: 64 },
    default: ParamDefault::Int(0),
    doc: "non-specular camera-path vertex where photons are gathered (0 = first)",
};
/// `max_gather_depth`.
pub static MAX_GATHER_DEPTH: ParamSpec = ParamSpec {
    key: "max_gather_depth",
    flag: "max-gather-depth",
    kind: ParamKind::Int { min: 0, max: MAX_ADAPTIVE_DEPTH as i128 },
    default: ParamDefault::Int(DEFAULT_MAX_GATHER_DEPTH as i64),
    doc: "deepest gather depth considered",
};
/// `adaptive_paper`.
pub static ADAPTIVE_PAPER: ParamSpec = ParamSpec {
    key: "adaptive_paper",
    flag: "adaptive-paper",
    kind: ParamKind::Bool,
    default: ParamDefault::Bool(false),
    doc: "choose the depth from the iteration's own first ray (the paper's variant; biased) instead of earlier iterations' pilot paths",
};
/// `cone_deg`.
pub static CONE: ParamSpec = ParamSpec {
    key: "cone_deg",
    flag: "cone",
    kind: ParamKind::Real { min: 0.0, max: 90.0 },
    default: ParamDefault::Real(DEFAULT_CONE_DEG as f64),
    doc: "half-angle in degrees of the quasi-specular cone",
};
/// `radius`.
pub static RADIUS: ParamSpec = ParamSpec {
    key: "radius",
    flag: "radius",
    kind: ParamKind::Length,
    default: ParamDefault::Computed("automatic (3 pixel footprints, shrunk where photons are dense)"),
    doc: "initial gather radius, in the scene file's length units on the command line as in its `[render]` table (a TOML scene's `units`; metres for the other formats)",
};
/// `radius_pixels`.
pub static RADIUS_PIXELS: ParamSpec = ParamSpec {
    key: "radius_pixels",
    flag: "radius-pixels",
    kind: ParamKind::Real { min: 0.01, max: 1000.0 },
    default: ParamDefault::Real(DEFAULT_RADIUS_PIXELS as f64),
    doc: "automatic initial gather radius in pixel footprints at the first non-specular vertex (without --radius)",
};
/// `alpha`.
pub static ALPHA: ParamSpec = ParamSpec {
    key: "alpha",
    flag: "alpha",
    kind: ParamKind::Real { min: 0.0, max: 1.0 },
    default: ParamDefault::Real(DEFAULT_ALPHA as f64),
    doc: "radius reduction alpha of progressive photon mapping",
};

/// Peak memory per pixel of the bidirectional methods: at most 2358 bytes measured on the
/// shipped scenes at the default two photons per pixel (`adaptive+quasi` on the glossy room;
/// BENCHMARKS.md "Memory per pixel"), plus 25%. The photon count hardly changes it (photons are
/// gathered as they are traced): 8 per pixel added 45 bytes on the glass plate.
pub const BIDIR_BYTES_PER_PIXEL: u64 = 2950;

/// Default deepest gather depth of the adaptive methods.
pub const DEFAULT_MAX_GATHER_DEPTH: u32 = 4;
/// Default quasi-specular cone half-angle (degrees).
pub const DEFAULT_CONE_DEG: f32 = 10.0;

/// Reads the settings of a bidirectional method (`adaptive`: the depth is chosen; `quasi`: with
/// the cone); `iterations` defaults to `spp`.
fn settings(r: &ParamReader, adaptive: bool, quasi: bool, spp: u32) -> Result<VismapSettings, ParamError> {
    let mut v = VismapSettings {
        iterations: r.int(&ITERATIONS)?.map_or(spp, |i| i as u32).max(1),
        photons_per_iteration: r.int(&PHOTONS)?.map(|n| n as u64),
        ..VismapSettings::default()
    };
    v.depth = if adaptive {
        let max_depth = r.int(&MAX_GATHER_DEPTH)?.map_or(DEFAULT_MAX_GATHER_DEPTH, |d| d as u32);
        GatherDepth::Adaptive { max_depth, paper: r.bool(&ADAPTIVE_PAPER)?.unwrap_or(false) }
    } else {
        GatherDepth::Fixed(r.int(&GATHER_DEPTH)?.map_or(0, |d| d as u32))
    };
    if quasi {
        v.cone_deg = Some(r.real(&CONE)?.map_or(DEFAULT_CONE_DEG, |c| c as f32));
    }
    v.radius = r.real(&RADIUS)?.map(|x| x as f32);
    if let Some(k) = r.real(&RADIUS_PIXELS)? {
        v.radius_pixels = k as f32;
    }
    if let Some(a) = r.real(&ALPHA)? {
        v.alpha = a as f32;
    }
    Ok(v)
}

fn build<'s>(b: &Build<'s>, r: &ParamReader, adaptive: bool, quasi: bool) -> Result<Built<'s>, ParamError> {
    let s = settings(r, adaptive, quasi, b.spp)?;
    // the kappa table, made here with every core before the passes read it
    b.scene.non_uniformity();
    Ok(Built {
        units: s.iterations,
        method: Box::new(Bidirectional::new(b.scene, b.camera, s, b.seed, b.shard, b.isa)),
    })
}

/// `vismap`.
pub static VISMAP: MethodEntry = MethodEntry {
    name: "vismap",
    summary: "bidirectional stochastic ray tracing with visibility maps (Zhdanov, Ershov & Voloboy 2015): per iteration one camera path per pixel leaves a visibility point at the gather depth, photons from the lights are gathered there within progressively shrinking radii",
    params: &[&ITERATIONS, &PHOTONS, &GATHER_DEPTH, &RADIUS, &RADIUS_PIXELS, &ALPHA],
    variant: Some(&GATHER_DEPTH),
    bytes_per_pixel: BIDIR_BYTES_PER_PIXEL,
    build: |b, r| build(b, r, false, false),
};

/// `adaptive`.
pub static ADAPTIVE: MethodEntry = MethodEntry {
    name: "adaptive",
    summary: "vismap with a per-pixel gather depth: the vertex of least non-uniformity kappa (most diffuse BSDF), chosen from earlier iterations' pilot paths so that each iteration stays unbiased",
    params: &[&ITERATIONS, &PHOTONS, &MAX_GATHER_DEPTH, &ADAPTIVE_PAPER, &RADIUS, &RADIUS_PIXELS, &ALPHA],
    variant: Some(&ADAPTIVE_PAPER),
    bytes_per_pixel: BIDIR_BYTES_PER_PIXEL,
    build: |b, r| build(b, r, true, false),
};

/// `quasi`.
pub static QUASI: MethodEntry = MethodEntry {
    name: "quasi",
    summary: "quasi-specular backward tracing: samples within the cone around a glossy surface's mirror or refraction direction continue the path, narrow lobes are passed through, light and photons are gathered over the rest of the sphere; what auto runs on narrow or specular scenes when its pilot measures it 2x faster than pt",
    params: &[&ITERATIONS, &PHOTONS, &GATHER_DEPTH, &CONE, &RADIUS, &RADIUS_PIXELS, &ALPHA],
    variant: Some(&CONE),
    bytes_per_pixel: BIDIR_BYTES_PER_PIXEL,
    build: |b, r| build(b, r, false, true),
};

/// `adaptive+quasi`.
pub static ADAPTIVE_QUASI: MethodEntry = MethodEntry {
    name: "adaptive+quasi",
    summary: "adaptive depth and quasi-specular tracing together (quasi-specular events do not count as depth)",
    params: &[&ITERATIONS, &PHOTONS, &MAX_GATHER_DEPTH, &ADAPTIVE_PAPER, &CONE, &RADIUS, &RADIUS_PIXELS, &ALPHA],
    variant: Some(&CONE),
    bytes_per_pixel: BIDIR_BYTES_PER_PIXEL,
    build: |b, r| build(b, r, true, true),
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::params::MethodParams;

    /// The typed defaults of the parameter table are what the methods use without a value.
    #[test]
    fn typed_defaults_are_the_settings_without_values() {
        let params = MethodParams::default();
        let r = ParamReader::new(&params);
        let s = settings(&r, true, true, 8).unwrap();
        let real = |d: ParamDefault| match d {
            ParamDefault::Real(x) => x,
            other => panic!("{other:?} is not a number"),
        };
        assert_eq!(f64::from(s.alpha), real(ALPHA.default));
        assert_eq!(f64::from(s.radius_pixels), real(RADIUS_PIXELS.default));
        assert_eq!(s.cone_deg.map(f64::from), Some(real(CONE.default)));
        assert_eq!(s.depth, GatherDepth::Adaptive { max_depth: 4, paper: false });
        assert_eq!(
            (MAX_GATHER_DEPTH.default, ADAPTIVE_PAPER.default),
            (ParamDefault::Int(4), ParamDefault::Bool(false))
        );
        let fixed = settings(&r, false, false, 8).unwrap();
        assert_eq!((fixed.depth, GATHER_DEPTH.default), (GatherDepth::Fixed(0), ParamDefault::Int(0)));
        assert_eq!(fixed.iterations, 8);
    }
}
