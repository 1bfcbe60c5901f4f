//! The bidirectional methods `vismap`, `adaptive`, `quasi` and `adaptive+quasi`: stochastic ray
//! tracing with visibility maps (Zhdanov, Ershov & Voloboy 2015; docs/architecture.md §7.4-7.5).
//! Each iteration shares one hero-wavelength set between a backward pass (one camera path per
//! pixel, ending in a [`VisibilityPoint`](visibility_point::VisibilityPoint) at the gather depth)
//! and a forward pass of photons whose hits after >= 1 bounce add
//! L^I = beta f(wo, wi) Phi / (N_F pi r^2) at the visibility points within radius r. The image is
//! the average of the iterations' L^V + L^D + L^I. Radii shrink as progressive photon mapping's
//! r_k^2 = r_{k-1}^2 (k - 1 + alpha) / k (Knaus & Zwicker 2011), so the average converges to the
//! path tracer's image. The adaptive-depth and quasi-specular methods (§7.5) are the same
//! passes with a per-pixel gather depth and a cone C around ideal directions.

pub mod adaptive_depth;
mod arrival;
pub mod coverage;
pub mod gather_disk;
pub mod grid;
pub mod iteration;
mod lookup_pipeline;
pub mod methods;
pub mod passes;
pub mod photon_pass;
pub mod quasi_cone;
pub mod radius_pilot;
mod ranges;
pub mod settings;
pub mod visibility_point;

/// A shipped scene (a path under `scenes/`) as its description and the compiled scene, for the
/// unit tests of the passes.
#[cfg(test)]
pub(crate) fn shipped_scene(rel: &str) -> (quasar_importers::SceneDesc, crate::core::scene::Scene) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(rel);
    let text = std::fs::read_to_string(&path).unwrap();
    let desc = quasar_importers::parse_toml_scene(&text, &path, &quasar_importers::ImportOptions::default()).unwrap();
    let scene = crate::core::scene::Scene::compile(&desc).unwrap();
    (desc, scene)
}

/// Most pixels or points in one parallel task of a per-pixel or per-point loop. rayon cuts an
/// indexed iterator into about four pieces per thread and cuts a piece further only when another
/// thread steals it before it starts, so work concentrated in one piece (the disks that received
/// photons, the pixels whose adaptive-depth pilot is not settled) would run on one thread;
/// pieces of at most this many items let idle threads take their share (the coverage probes of
/// the glass plate at 128x96 took 1.18x less time with two threads than with one before).
pub(crate) const ITEMS_PER_TASK: usize = 64;
