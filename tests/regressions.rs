//! Regression scenes of the correctness review (issue 13), each rendered with the methods that
//! apply and compared with `pt` by the block z-test (`quasar::tools::ztest`) of the beauty and of every
//! layer: delta lights inside the quasi-specular cone, camera paths through long chains of
//! glossy gather points, every light type seen via a glossy surface.

mod common;

use common::{
    ALL_QUANTITIES, assert_converges, assert_converges_from, bidir_ov, pt_ov, render_file, shipped, write_scene,
};
use quasar::film::Quantity;

/// Renders `scene` with each of `methods` and asserts that the block z-test passes and that the
/// image mean is within 1% of `pt`'s (at `reference_spp`) with 95% confidence (|ratio - 1| +
/// 2 sigma < 1%). The budgets keep sigma, both images' error of the ratio, at about 0.002 or
/// less, so that an unbiased method passes for any seed: |ratio - 1| may then be 3 sigma.
fn within_one_percent(scene: &str, reference_spp: u32, methods: &[&str], iterations: u32, photons: u64) {
    let path = shipped(scene);
    let reference = render_file(&path, &pt_ov(16, 16, reference_spp, 1));
    for &method in methods {
        let img = render_file(&path, &bidir_ov(16, 16, method, iterations, photons, 2));
        let report = assert_converges(&format!("{scene} {method}"), &img, &reference, &ALL_QUANTITIES);
        let (ratio, sigma) = report.mean_ratio();
        eprintln!("{scene} {method}: mean ratio {ratio} +- {sigma}");
        assert!((ratio - 1.0).abs() + 2.0 * sigma < 0.01, "{scene} {method}: mean ratio {ratio} +- {sigma}");
    }
}

/// Bug 1: a directional light's highlight on a narrow glossy floor was black in the
/// quasi-specular methods (the light sample fell inside the cone and was dropped).
#[test]
fn directional_highlight_on_a_narrow_floor() {
    within_one_percent("tests/narrow-sun.toml", 32_768, &["quasi", "adaptive+quasi"], 2048, 1024);
}

/// Bug 1: a point light's highlight inside the 10 degree cone (96% too dark before).
#[test]
fn point_light_highlight_on_a_narrow_floor() {
    within_one_percent("tests/narrow-point.toml", 65_536, &["quasi", "adaptive+quasi"], 61_440, 256);
}

/// Bug 2: facing glossy conductors, about 9 bounces: camera paths were cut after 8 gather
/// points (adaptive+quasi / pt = 0.2 before). `adaptive` passes the narrow conductors through
/// too (within 1% for 16 of 16 seeds).
#[test]
fn facing_glossy_conductors() {
    within_one_percent("tests/facing-mirrors.toml", 16_384, &["adaptive", "quasi", "adaptive+quasi"], 512, 4096);
}

/// A chain of 12 to 15 glossy reflections ending at a diffuse wall lit inside the gap. `vismap`
/// gathers on the glossy panels themselves, where photons arriving within the lobes are too
/// rare to converge at a testable budget (unbiased, but with fireflies the z-test flags), so it
/// is not tested here; `adaptive` passes the narrow panels (kappa 51 at 45 degrees) through as
/// the quasi methods do (it passed for 16 of 16 seeds).
#[test]
fn long_glossy_chain() {
    let path = shipped("tests/glossy-chain.toml");
    let reference = render_file(&path, &pt_ov(16, 16, 16384, 1));
    for method in ["adaptive", "quasi", "adaptive+quasi"] {
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

/// The shipped lightguide's camera, as the file has it.
const LIGHTGUIDE_CAMERA: &str = "[camera]\nposition = [0.04, 0.06, 0.30]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 50\n";

/// The shipped lightguide (light carried through PMMA by total internal reflection, let out by
/// the extraction face) seen from 8 cm in front of the rod's middle, so that every pixel looks
/// through the narrow front face (GGX alpha 0.02) or the polished top face: the methods that pass
/// narrow lobes through (`auto` picks `quasi` here) against `pt`, every layer, from
/// 16-pixel blocks. Both sides are heavy-tailed in smaller blocks, and the standard errors of a
/// 16-pixel block are 10-25% of its mean at this budget: the test guards against gross errors (the
/// quasi-specular bugs above were 80-100%, `adaptive` gathering on narrow vertices behind the
/// front face was 7% low in the mean of 24 renders of 4096 iterations); the particle-tracer check
/// is the precise one.
///
/// Not tested here, with the reasons measured (docs/validation.md, "Tests that hold for any
/// seed"): `vismap`, which gathers on the narrow front face itself, where photons leaving the rod
/// within the lobe are too rare to converge at a testable budget (3 of 4 seeds render 13-18% of
/// the rod's indirect light at 256 iterations, the fourth 134%; heavy-tailed, as in the long
/// glossy chain above); and the housing around the rod in the file's own view, which the path
/// tracer reaches only through caustic paths into the LEDs (its 16384-spp images there differ
/// 3-10x from a 262144-spp one), so a pt reference cannot judge it. Those diffuse regions are
/// compared with Mitsuba's particle tracer instead (`tests/crosscheck/lightguide_ptracer.py`,
/// `vismap` and `auto`, run by `.ci/run`).
#[test]
fn lightguide_front_under_the_narrow_lobe_methods() {
    let text = std::fs::read_to_string(shipped("lightguide/lightguide.toml")).unwrap();
    let front = text.replace(
        LIGHTGUIDE_CAMERA,
        "[camera]\nposition = [0.012, 0.016, 0.08]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 12\n",
    );
    assert_ne!(front, text, "the lightguide's camera moved");
    let scene = write_scene(&front, &[]);
    let reference = render_file(&scene.path, &pt_ov(32, 24, 16384, 1));
    for method in ["adaptive", "quasi", "adaptive+quasi"] {
        let img = render_file(&scene.path, &bidir_ov(32, 24, method, 256, 8192, 2));
        assert_converges_from(16, &format!("lightguide front {method}"), &img, &reference, &ALL_QUANTITIES);
    }
}

/// `auto` at its default settings (two photons per pixel, the automatic radius) converges on
/// the shipped scenes it renders with a bidirectional method, at 256 iterations: the glass plate
/// and the glossy room. Not the lightguide: in its own view `pt` reaches the housing only
/// through caustic paths into the LEDs, so a `pt` reference there is low in a typical render
/// and confident about it (docs/validation.md, "Tests that hold for any seed"). A seed scan of
/// this test with the lightguide from 8-pixel blocks gave an rms z of 1.5-2.4 over its 12
/// blocks for 21 of 21 seeds, its worst block always on the side of `auto` being brighter (+1.1
/// to +3.2%, z up to +4.35). `auto` at its defaults on the lightguide is checked against
/// Mitsuba's particle tracer instead (`tests/crosscheck/lightguide_ptracer.py`, run by
/// `.ci/run`), and the method it picks there, `quasi` (asserted here), against `pt`
/// from the rod's front by the test above.
#[test]
fn auto_at_default_settings_converges_on_the_shipped_scenes() {
    for scene in ["glass-plate/glass-plate.toml", "glossy-room/glossy-room.toml"] {
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
        assert_eq!(img.image.meta("method"), Some("quasi"), "{scene}");
        assert_converges(&format!("{scene} auto"), &img, &reference, &[Quantity::Beauty]);
    }
    // the lightguide's pick, which the particle-tracer check relies on
    let ov = quasar::render::job::JobOverrides { width: Some(8), height: Some(6), ..Default::default() }
        .with_param("iterations", 1u32);
    let img = render_file(&shipped("lightguide/lightguide.toml"), &ov);
    assert_eq!(img.image.meta("method"), Some("quasi"), "lightguide");
}
