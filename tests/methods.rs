//! The paper's methods (docs/architecture.md §7.5-7.6): `adaptive`, `quasi` and `adaptive+quasi` converge to
//! the reference path tracer for several cone angles; the adaptive depth moves gathering off
//! narrow lobes; `auto` picks what the scene needs.

mod common;

use std::path::Path;

use common::{
    ALL_QUANTITIES, assert_converges_from, bidir_ov, glossy_floor_scene, mean, pt_ov, rel_mse, render_file, shipped,
    write_scene,
};
use quasar::render::job::{JobOutput, JobOverrides};

fn method_ov(w: u32, h: u32, method: &str, cone: Option<f32>, iterations: u32) -> JobOverrides {
    let ov = bidir_ov(w, h, method, iterations, 20_000, 7);
    match cone {
        Some(c) => ov.with_param("cone_deg", c),
        None => ov,
    }
}

/// Renders every method/cone combination at 16 and 256 iterations and checks that relMSE against
/// the `pt` reference falls and that the 256-iteration image passes the block z-test against it:
/// the beauty, emission and direct layers from 4-pixel blocks, the photon-gathered indirect and
/// caustic layers from 16-pixel blocks (their sparse caustics through the plate's thin side
/// faces and on the narrow floor are heavy-tailed in smaller blocks at this budget); a method
/// marked `coarse` (vismap gathering on a narrow lobe) is tested from 16-pixel blocks only.
fn check_methods(path: &Path, reference: &JobOutput, w: u32, h: u32, methods: &[(&str, Option<f32>, bool)]) {
    let r = reference.image.channel("XYZ.Y").unwrap();
    for &(method, cone, coarse) in methods {
        let few = render_file(path, &method_ov(w, h, method, cone, 16)).image;
        let e_few = rel_mse(few.channel("XYZ.Y").unwrap(), r);
        let img = render_file(path, &method_ov(w, h, method, cone, 256));
        let y = img.image.channel("XYZ.Y").unwrap();
        let e = rel_mse(y, r);
        eprintln!("{}: {method} cone {cone:?}: relMSE {e_few:.5} -> {e:.5}", path.display());
        assert!(y.iter().all(|v| v.is_finite()));
        assert!(e < e_few, "{method} cone {cone:?}: relMSE {e_few} -> {e}");
        let label = format!("{method} cone {cone:?}");
        let (gathered, camera) = (&ALL_QUANTITIES[3..], &ALL_QUANTITIES[..3]);
        assert_converges_from(if coarse { 16 } else { 4 }, &label, &img, reference, camera);
        assert_converges_from(16, &label, &img, reference, gathered);
    }
}

/// The glass plate (narrow top face): every method converges to pt for cones of 1, 10 and 30
/// degrees. pt reference: 16384 spp.
#[test]
fn methods_converge_to_pt_on_the_glass_plate() {
    let path = shipped("glass-plate/glass-plate.toml");
    let reference = render_file(&path, &pt_ov(40, 30, 16384, 101));
    check_methods(
        &path,
        &reference,
        40,
        30,
        &[
            ("adaptive", None, false),
            ("quasi", Some(1.0), false),
            ("quasi", Some(10.0), false),
            ("quasi", Some(30.0), false),
            ("adaptive+quasi", Some(1.0), false),
            ("adaptive+quasi", Some(10.0), false),
            ("adaptive+quasi", Some(30.0), false),
        ],
    );
}

/// A narrow glossy floor (GGX alpha 0.03 conductor) mirroring a lit diffuse wall and sphere:
/// secondary highlights. Every method converges to pt.
#[test]
fn methods_converge_to_pt_on_a_narrow_glossy_scene() {
    let scene = write_scene(&narrow_glossy(), &[]);
    let reference = render_file(&scene.path, &pt_ov(40, 30, 8192, 101));
    check_methods(
        &scene.path,
        &reference,
        40,
        30,
        &[
            ("vismap", None, true),
            ("adaptive", None, false),
            ("quasi", Some(1.0), false),
            ("quasi", Some(10.0), false),
            ("quasi", Some(30.0), false),
            ("adaptive+quasi", Some(1.0), false),
            ("adaptive+quasi", Some(10.0), false),
            ("adaptive+quasi", Some(30.0), false),
        ],
    );
}

/// The glossy-floor scene with a narrow (alpha 0.03) GGX conductor floor.
fn narrow_glossy() -> String {
    glossy_floor_scene("[materials.floor]\ntype = \"conductor\"\nfresnel = 0.9\nalpha = 0.03\n")
}

/// Which material each pixel centre sees directly (None: background), by the same camera rays.
fn materials_seen(path: &Path, w: u32, h: u32) -> Vec<Option<String>> {
    let desc = quasar::render::job::load_scene(path).unwrap();
    let scene = quasar::core::scene::Scene::compile(&desc).unwrap();
    let camera = quasar::core::camera::Camera::new(&desc.camera, w, h).unwrap();
    (0..w * h)
        .map(|i| {
            let ray = camera.ray(glam::Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5));
            scene.intersect(&ray).map(|si| scene.material_names[si.material as usize].clone())
        })
        .collect()
}

/// Mean `trace_depth.Y` of an adaptive render over the pixels that see `material`.
fn trace_depth_on(path: &Path, method: &str, material: &str) -> f64 {
    let (w, h) = (80, 60);
    let seen = materials_seen(path, w, h);
    let img = render_file(path, &method_ov(w, h, method, None, 32)).image;
    let td = img.channel("trace_depth.Y").unwrap();
    let v: Vec<f32> = seen.iter().zip(td).filter(|(m, _)| m.as_deref() == Some(material)).map(|(_, &d)| d).collect();
    assert!(v.len() > 20, "{material}: only {} pixels", v.len());
    mean(&v)
}

/// The adaptive depth moves gathering off the narrow top face of the glass plate to the bottom face
/// (depth 1, the paper's "second diffuse scattering") and keeps it at the first non-specular
/// vertex (depth 0) behind the smooth end faces and on the substrate. (A few percent of the top
/// face's pilot paths are reflected off it and escape; their only candidate is depth 0, so early
/// iterations' modes are occasionally 0.) With the quasi-specular cone the narrow top-face event
/// is quasi-specular and does not count as depth: the same bottom-face vertex is depth 0.
#[test]
fn trace_depth_is_one_on_the_narrow_top_face_and_zero_on_the_sides() {
    let path = shipped("glass-plate/glass-plate.toml");
    let top = trace_depth_on(&path, "adaptive", "glass_top");
    let side = trace_depth_on(&path, "adaptive", "glass_side");
    let substrate = trace_depth_on(&path, "adaptive", "substrate");
    eprintln!("adaptive: top {top:.3}, side {side:.3}, substrate {substrate:.3}");
    assert!((top - 1.0).abs() < 0.1, "top face {top}");
    assert!(side < 0.05, "side faces {side}");
    assert!(substrate < 0.01, "substrate {substrate}");
    let top = trace_depth_on(&path, "adaptive+quasi", "glass_top");
    eprintln!("adaptive+quasi: top {top:.3}");
    assert!(top < 0.1, "adaptive+quasi: top face {top}");
}

/// `auto` renders the diffuse Cornell box with pt and the narrow glass plate with adaptive+quasi.
#[test]
fn auto_picks_pt_for_diffuse_and_adaptive_quasi_for_narrow_scenes() {
    for (scene, expected) in
        [("cornell-box/cornell-box.toml", "pt"), ("glass-plate/glass-plate.toml", "adaptive+quasi")]
    {
        let ov = JobOverrides { width: Some(8), height: Some(6), spp: Some(1), ..Default::default() };
        let img = render_file(&shipped(scene), &ov).image;
        assert_eq!(img.meta("method"), Some(expected), "{scene}");
        assert_eq!(img.meta("method_requested"), Some("auto"));
    }
}

/// The scene's `[render]` table sets the bidirectional methods; the command line overrides it,
/// and settings a method does not use (the scene's cone under `--method vismap`) are ignored.
#[test]
fn render_table_sets_the_bidirectional_methods() {
    let base = narrow_glossy();
    let text = base.replace(
        "[render]\nwidth = 40\nheight = 30",
        "[render]\nwidth = 8\nheight = 6\nmethod = \"quasi\"\niterations = 3\ncone_deg = 25\nphotons_per_iteration = 100",
    );
    assert_ne!(text, base);
    let scene = write_scene(&text, &[]);
    let img = render_file(&scene.path, &JobOverrides::default()).image;
    assert_eq!(img.meta("method"), Some("quasi"));
    assert_eq!(img.meta("iterations"), Some("3"));
    assert_eq!(img.meta("cone_deg"), Some("25"));
    assert_eq!(img.meta("photons_per_iteration"), Some("100"));
    let ov = JobOverrides { method: Some("vismap".into()), ..Default::default() }.with_param("iterations", 2u32);
    let img = render_file(&scene.path, &ov).image;
    assert_eq!(img.meta("method"), Some("vismap"));
    assert_eq!(img.meta("iterations"), Some("2"));
    assert_eq!(img.meta("cone_deg"), Some("none"));
}

/// The kappa table is made on first use (docs/architecture.md §5): asked for first by several
/// rayon workers at once (a method built without making it), it is made once, and it is each
/// material's own table.
#[test]
fn the_kappa_table_is_made_once_even_when_workers_ask_for_it_together() {
    use quasar::core::scene::Scene;
    use quasar_materials::{NARROW_KAPPA, NonUniformity};
    use rayon::prelude::*;

    let desc = quasar::render::job::load_scene(&shipped("glass-plate/glass-plate.toml")).unwrap();
    let scene = Scene::compile(&desc).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
    let tables: Vec<usize> =
        pool.install(|| (0..64).into_par_iter().map(|_| scene.non_uniformity().as_ptr() as usize).collect());
    assert!(tables.iter().all(|&t| t == tables[0]), "more than one table");
    assert_eq!(scene.non_uniformity().len(), scene.materials.len());
    for (m, nu) in scene.materials.iter().zip(scene.non_uniformity()) {
        assert_eq!(*nu, NonUniformity::of_material(m));
    }
    let kappa = |name: &str| {
        let i = scene.material_names.iter().position(|n| n == name).unwrap();
        scene.non_uniformity()[i].typical()
    };
    assert!((kappa("substrate") - 1.0).abs() < 0.05, "{}", kappa("substrate"));
    assert!(kappa("glass_top") > NARROW_KAPPA, "{}", kappa("glass_top"));
    assert!(kappa("glass_side").is_infinite());
}
