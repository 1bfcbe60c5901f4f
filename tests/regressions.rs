//! Regression scenes of the correctness review (issue 13), each rendered with the methods that
//! apply and compared with `pt` by the block z-test (`quasar::tools::ztest`) of the beauty and of every
//! layer: delta lights inside the quasi-specular cone, camera paths through long chains of
//! glossy gather points, every light type seen via a glossy surface.

mod common;

use common::{ALL_QUANTITIES, assert_converges, assert_converges_from, bidir_ov, pt_ov, render_file, shipped};
use quasar::film::Quantity;

/// Renders `scene` with `method` and asserts that the block z-test passes and that the image
/// mean is within 1% of `pt`'s with 95% confidence (|ratio - 1| + 2 sigma < 1%).
fn within_one_percent(scene: &str, method: &str, iterations: u32, photons: u64) {
    let path = shipped(scene);
    let reference = render_file(&path, &pt_ov(16, 16, 16384, 1));
    let img = render_file(&path, &bidir_ov(16, 16, method, iterations, photons, 2));
    let report = assert_converges(&format!("{scene} {method}"), &img, &reference, &ALL_QUANTITIES);
    let (ratio, sigma) = report.mean_ratio();
    assert!((ratio - 1.0).abs() + 2.0 * sigma < 0.01, "{scene} {method}: mean ratio {ratio} +- {sigma}");
}

/// Bug 1: a directional light's highlight on a narrow glossy floor was black in the
/// quasi-specular methods (the light sample fell inside the cone and was dropped).
#[test]
fn directional_highlight_on_a_narrow_floor() {
    for method in ["quasi", "adaptive+quasi"] {
        within_one_percent("tests/narrow-sun.toml", method, 1024, 1024);
    }
}

/// Bug 1: a point light's highlight inside the 10 degree cone (96% too dark before).
#[test]
fn point_light_highlight_on_a_narrow_floor() {
    for method in ["quasi", "adaptive+quasi"] {
        within_one_percent("tests/narrow-point.toml", method, 12_288, 256);
    }
}

/// Bug 2: facing glossy conductors, about 9 bounces: camera paths were cut after 8 gather
/// points (adaptive+quasi / pt = 0.2 before).
#[test]
fn facing_glossy_conductors() {
    for method in ["quasi", "adaptive+quasi"] {
        within_one_percent("tests/facing-mirrors.toml", method, 512, 4096);
    }
}

/// A chain of 12 to 15 glossy reflections ending at a diffuse wall lit inside the gap. The
/// fixed-depth methods (`vismap`, `adaptive` with its depth limit of 7) gather on the glossy
/// panels themselves, where photons arriving within the lobes are too rare to converge at a
/// testable budget (unbiased, but with fireflies the z-test flags); `auto` never picks them
/// for such scenes, so only the quasi-specular methods are tested here.
#[test]
fn long_glossy_chain() {
    let path = shipped("tests/glossy-chain.toml");
    let reference = render_file(&path, &pt_ov(16, 16, 16384, 1));
    for method in ["quasi", "adaptive+quasi"] {
        let img = render_file(&path, &bidir_ov(16, 16, method, 2048, 2048, 2));
        assert_converges(&format!("glossy chain {method}"), &img, &reference, &ALL_QUANTITIES);
    }
}

/// Every light type (area, point, spot, directional, environment) lighting a diffuse wall and
/// sphere, seen directly and via a glossy floor (GGX alpha 0.3, F 0.9, gathered on with the
/// quasi-specular cone), under every method: beauty and layers converge to pt.
#[test]
fn every_light_type_via_a_glossy_floor_under_every_method() {
    for light in ["area", "point", "spot", "directional", "environment"] {
        let path = shipped(&format!("tests/glossy-{light}.toml"));
        let reference = render_file(&path, &pt_ov(48, 32, 2048, 1));
        for method in ["vismap", "adaptive", "quasi", "adaptive+quasi"] {
            let img = render_file(&path, &bidir_ov(48, 32, method, 256, 16384, 2));
            assert_converges(&format!("{light} light, {method}"), &img, &reference, &ALL_QUANTITIES);
        }
    }
}

/// The shipped lightguide (light carried through PMMA by total internal reflection, let out by
/// the narrow-lobe extraction face) under every bidirectional method, every layer. The light
/// leaving the guide reaches the camera through caustic paths: `pt`'s own pixels there have
/// relative errors near 50% at this budget and the photon estimates are heavy-tailed in small
/// blocks, so the test runs from 16-pixel blocks (where each is a sum over hundreds of
/// independent iterations and photons).
#[test]
fn lightguide_under_every_method() {
    let path = shipped("lightguide/lightguide.toml");
    let reference = render_file(&path, &pt_ov(32, 24, 16384, 1));
    for method in ["vismap", "adaptive", "quasi", "adaptive+quasi"] {
        let img = render_file(&path, &bidir_ov(32, 24, method, 256, 8192, 2));
        assert_converges_from(16, &format!("lightguide {method}"), &img, &reference, &ALL_QUANTITIES);
    }
}

/// `auto` at its default settings (two photons per pixel, the automatic radius) converges on
/// the shipped scenes it renders with a bidirectional method, at 256 iterations.
#[test]
fn auto_at_default_settings_converges_on_the_shipped_scenes() {
    for scene in ["glass-plate/glass-plate.toml", "glossy-room/glossy-room.toml", "lightguide/lightguide.toml"] {
        let path = shipped(scene);
        let reference = render_file(&path, &pt_ov(32, 24, 8192, 1));
        let ov = quasar::render::job::JobOverrides {
            width: Some(32),
            height: Some(24),
            seed: Some(2),
            ..Default::default()
        }
        .with_param("iterations", 256u32);
        let img = render_file(&path, &ov);
        assert_eq!(img.image.meta("method"), Some("adaptive+quasi"), "{scene}");
        assert_converges(&format!("{scene} auto"), &img, &reference, &[Quantity::Beauty]);
    }
}
