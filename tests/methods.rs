//! The paper's methods (docs/architecture.md §7.5-7.6): `adaptive`, `quasi` and `adaptive+quasi` converge to
//! the reference path tracer for several cone angles; the adaptive depth moves gathering off
//! narrow lobes; `auto` picks what the scene needs.

mod common;

use std::path::Path;

use common::{
    ALL_QUANTITIES, assert_converges_from, bidir_ov, glossy_floor_scene, mean, mean_rel_error, pt_ov, render_file,
    shipped, write_scene,
};
use quasar::render::job::{JobOutput, JobOverrides};

fn method_ov(w: u32, h: u32, method: &str, cone: Option<f32>, iterations: u32) -> JobOverrides {
    let ov = bidir_ov(w, h, method, iterations, 20_000, 7);
    match cone {
        Some(c) => ov.with_param("cone_deg", c),
        None => ov,
    }
}

/// How a method is tested by [`check_methods`]: its iterations, and the side of the finest blocks
/// its beauty is z-tested from.
#[derive(Clone, Copy)]
struct Budget {
    iterations: u32,
    base: usize,
}

/// The budget of a method that passes narrow lobes through (`adaptive` and the quasi-specular
/// methods) or gathers behind them.
const PASSES_NARROW_LOBES: Budget = Budget { iterations: 256, base: 4 };

/// The budget of `vismap` on a large narrow surface, which it gathers on: 16 renders put single
/// 4-, 8- and 16-pixel blocks up to 24, 4.8 and 6.1 of their claimed standard errors from the
/// renders' mean at 256 iterations; at 1024 iterations 16-pixel blocks stay within 2.6.
const VISMAP_ON_NARROW_LOBES: Budget = Budget { iterations: 1024, base: 16 };

/// The methods that pass narrow lobes through, with the quasi-specular cones of 1, 10 and 30
/// degrees, each at [`PASSES_NARROW_LOBES`].
const NARROW_LOBE_PASSING_METHODS: [(&str, Option<f32>, Budget); 7] = [
    ("adaptive", None, PASSES_NARROW_LOBES),
    ("quasi", Some(1.0), PASSES_NARROW_LOBES),
    ("quasi", Some(10.0), PASSES_NARROW_LOBES),
    ("quasi", Some(30.0), PASSES_NARROW_LOBES),
    ("adaptive+quasi", Some(1.0), PASSES_NARROW_LOBES),
    ("adaptive+quasi", Some(10.0), PASSES_NARROW_LOBES),
    ("adaptive+quasi", Some(30.0), PASSES_NARROW_LOBES),
];

/// Renders every method/cone combination at 16 iterations and at its budget and checks that the
/// mean relative error against the `pt` reference falls (an L1 measure: one firefly in the longer
/// render, as `quasi` with a 1-degree cone inside the floor's wider lobe makes, raised relMSE from
/// 0.033 to 0.097 for one seed of 16) and that the longer image passes the block z-test against
/// it: the beauty from the budget's blocks, the emission and direct layers (camera paths and light
/// samples only) from 4-pixel blocks, the photon-gathered indirect and caustic layers from the
/// budget's blocks but at least 16 pixels (their sparse caustics through the plate's thin side
/// faces and on the narrow floor are heavy-tailed in smaller blocks).
fn check_methods(path: &Path, reference: &JobOutput, w: u32, h: u32, methods: &[(&str, Option<f32>, Budget)]) {
    check_methods_on(path, reference, w, h, methods, &ALL_QUANTITIES[3..]);
}

/// [`check_methods`] with the photon-gathered layers to z-test given.
fn check_methods_on(
    path: &Path,
    reference: &JobOutput,
    w: u32,
    h: u32,
    methods: &[(&str, Option<f32>, Budget)],
    gathered_layers: &[quasar::film::Quantity],
) {
    let r = reference.image.channel(quasar::film::LUMINANCE).unwrap();
    for &(method, cone, budget) in methods {
        let few = render_file(path, &method_ov(w, h, method, cone, 16)).image;
        let e_few = mean_rel_error(few.channel(quasar::film::LUMINANCE).unwrap(), r);
        let img = render_file(path, &method_ov(w, h, method, cone, budget.iterations));
        let y = img.image.channel(quasar::film::LUMINANCE).unwrap();
        let e = mean_rel_error(y, r);
        eprintln!("{}: {method} cone {cone:?}: mean relative error {e_few:.5} -> {e:.5}", path.display());
        assert!(y.iter().all(|v| v.is_finite()));
        assert!(e < e_few, "{method} cone {cone:?}: mean relative error {e_few} -> {e}");
        let label = format!("{method} cone {cone:?}");
        let (beauty, camera, gathered) = (&ALL_QUANTITIES[..1], &ALL_QUANTITIES[1..3], gathered_layers);
        assert_converges_from(budget.base, &label, &img, reference, beauty);
        assert_converges_from(4, &label, &img, reference, camera);
        assert_converges_from(budget.base.max(16), &label, &img, reference, gathered);
    }
}

/// The glass plate (narrow top face): every method converges to pt for cones of 1, 10 and 30
/// degrees. pt reference: 16384 spp.
#[test]
fn methods_converge_to_pt_on_the_glass_plate() {
    let path = shipped("glass-plate/glass-plate.toml");
    let reference = render_file(&path, &pt_ov(40, 30, 16384, 101));
    check_methods(&path, &reference, 40, 30, &NARROW_LOBE_PASSING_METHODS);
}

/// The glass plate of the paper's Fig. 2 with a rough dielectric bottom (GGX alpha 0.3) instead
/// of a diffuse layer (scenes/bench): seen from inside the glass its refraction is narrow and its
/// reflection wide, so the methods that pass narrow lobes through continue the refraction's
/// hemisphere and gather the reflection's (docs/architecture.md §7.5). Every method converges to
/// pt (65536 spp: the lamp reaches the plate's pixels through two rough interfaces, a hard case
/// for pt's own reference) in the beauty and every layer but `caustic`. That layer holds here
/// the lamp seen through a side face, mirrored by the bottom face from inside at grazing
/// incidence and out through another side face. The bottom's reflection back into the glass is
/// gathered there, but this light is its direct light, which photons never carry and a light
/// sample cannot reach through the polished side: a rare event for every method that finds it
/// by BSDF sampling, pt included (pt's caustic sum over the image is 0.37-0.45 from seed to seed
/// at 65536 spp), so after 512 iterations most blocks have seen none and their sample variance
/// says nothing of the true one (`adaptive+quasi` fails that layer's block test with a mean
/// ratio of 0.90 +- 0.28). The camera paths do find it: at pixel (8, 16), a million paths of
/// `vismap` at gather depth 1 give 0.0143 where pt gives 0.0133 (`indirect`, of which `caustic`
/// is a part, is tested).
#[test]
fn methods_converge_to_pt_on_the_glass_plate_with_a_rough_bottom() {
    let path = shipped("bench/plate-rough-bottom-0.3.toml");
    let reference = render_file(&path, &pt_ov(40, 30, 65536, 101));
    let split = Budget { iterations: 512, base: 16 };
    check_methods_on(
        &path,
        &reference,
        40,
        30,
        &[("adaptive", None, split), ("quasi", Some(10.0), split), ("adaptive+quasi", Some(10.0), split)],
        &ALL_QUANTITIES[3..4],
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
        &[&[("vismap", None, VISMAP_ON_NARROW_LOBES)][..], &NARROW_LOBE_PASSING_METHODS].concat(),
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

/// On the glass plate every adaptive method passes the narrow top face through (kappa > 20, not
/// counted as depth): it gathers at the bottom face, depth 0, as it does behind the smooth end
/// faces and on the substrate. (Before narrow lobes were passed through, plain `adaptive` gathered
/// there at depth 1, the paper's "second diffuse scattering", except in the pixels that straddle
/// the plate's edge, whose depth 0 put the paths landing on the top face onto its narrow lobe.)
#[test]
fn trace_depth_is_zero_on_the_glass_plate_with_its_narrow_top_face_passed_through() {
    let path = shipped("glass-plate/glass-plate.toml");
    for method in ["adaptive", "adaptive+quasi"] {
        let top = trace_depth_on(&path, method, "glass_top");
        let side = trace_depth_on(&path, method, "glass_side");
        let substrate = trace_depth_on(&path, method, "substrate");
        eprintln!("{method}: top {top:.3}, side {side:.3}, substrate {substrate:.3}");
        assert!(top < 0.1, "{method}: top face {top}");
        assert!(side < 0.05, "{method}: side faces {side}");
        assert!(substrate < 0.01, "{method}: substrate {substrate}");
    }
}

/// A glossy floor (GGX alpha 0.6: kappa below the narrow threshold at these grazing views, so it
/// is a gather candidate; alpha 0.3 is passed through there)
/// in front of a diffuse wall and sphere: `adaptive` moves gathering to the more uniform
/// vertex behind it, depth 1, where the floor's reflections meet the wall and sphere, and also
/// where they leave the scene, which makes the next depth a candidate of kappa 1
/// (docs/architecture.md §7.5). Under the open sky alone the floor is at depth 1 by that rule
/// only (before it, the floor was every pilot's only candidate: a mean depth of 0).
#[test]
fn adaptive_gathers_behind_a_glossy_floor_and_where_its_reflections_escape() {
    let floor = "[materials.floor]\ntype = \"conductor\"\nfresnel = 0.9\nalpha = 0.6\n";
    let room = write_scene(&glossy_floor_scene(floor), &[]);
    let depth = trace_depth_on(&room.path, "adaptive", "floor");
    eprintln!("glossy floor in the room: {depth:.3}");
    assert!(depth > 0.9, "mean trace depth on the floor in the room {depth}");
    let sky = write_scene(
        &format!(
            "[camera]\nposition = [0, 1, 3]\ntarget = [0, 0, 0]\nfov_deg = 30\n{floor}\
             [[shape]]\ntype = \"quad\"\ncenter = [0, 0, 0]\nsize = [20, 20]\nnormal = [0, 1, 0]\nmaterial = \"floor\"\n\
             [[light]]\ntype = \"environment\"\nscale = 1.0\n"
        ),
        &[],
    );
    let depth = trace_depth_on(&sky.path, "adaptive", "floor");
    eprintln!("glossy floor under the sky: {depth:.3}");
    // a pilot whose BSDF sample fails (below the horizon, often for a rough lobe seen at
    // grazing angles) ends with depth 0 its only candidate: 0.94 here
    assert!(depth > 0.8, "mean trace depth on the floor under the sky {depth}");
}

/// `auto` renders the diffuse Cornell box with pt (the scene analysis: nothing narrow), and
/// chooses by its pilots (render/pilot.rs) where something is: quasi for the glass
/// plates, whose light reaches the plate's bottom and the floor under it through the narrow top,
/// pt for diffuse and moderately rough metal objects under a sky, which the path tracer's light
/// sampling reaches directly (BENCHMARKS.md, "The family": pt 1.4x ahead there).
#[test]
fn auto_picks_pt_for_diffuse_and_quasi_for_narrow_scenes() {
    for (scene, expected) in [
        ("cornell-box/cornell-box.toml", "pt"),
        ("glass-plate/glass-plate.toml", "quasi"),
        ("bench/plate-rough-bottom-0.3.toml", "quasi"),
        ("bench/sky-objects.toml", "pt"),
    ] {
        let ov = JobOverrides { width: Some(64), height: Some(64), spp: Some(32), ..Default::default() };
        let img = render_file(&shipped(scene), &ov).image;
        eprintln!("{scene}: {:?}", img.meta("auto_pilot"));
        assert_eq!(img.meta("method"), Some(expected), "{scene}: {:?}", img.meta("auto_pilot"));
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

/// `--radius` is in the scene file's units, as `[render] radius` is (issue 48: the command line
/// read metres): on a scene in millimetres, 20 from either place is a 2 cm radius.
#[test]
fn the_radius_is_in_scene_units_on_the_command_line_too() {
    let floor = "[materials.floor]\ntype = \"diffuse\"\nreflectance = 0.5";
    let mm = format!("units = \"mm\"\n{}", common::glossy_floor_scene(floor));
    let scene = write_scene(&mm, &[]);
    let ov = JobOverrides {
        spp: Some(1),
        method: Some("vismap".into()),
        width: Some(8),
        height: Some(6),
        ..Default::default()
    }
    .with_param("photons_per_iteration", 100u32);
    let cli = render_file(&scene.path, &ov.clone().with_param("radius", 20.0)).image;
    let file = write_scene(&mm.replace("[render]", "[render]\nradius = 20"), &[]);
    let in_file = render_file(&file.path, &ov).image;
    let metres = |img: &quasar::output::ExrImage| img.meta("radius").unwrap().parse::<f64>().unwrap();
    assert!((metres(&cli) - 0.02).abs() < 1e-6, "{}", metres(&cli));
    assert_eq!(metres(&cli), metres(&in_file));
}
