//! The auxiliary outputs (`--aov`, issue 48) against what the scene determines: a grey floor and
//! a red card above it, seen from above. Pixels whose four corners' rays all hit the card (or all
//! the floor outside it) lie wholly inside it, so there the normals are the plane's, the position
//! lies on it, the ids are its own and its Cryptomatte coverage is 1; every pixel's coverages sum
//! to 1 (the floor fills the view); the albedo is the materials' reflectance.

mod common;

use common::{render_file, write_scene};
use glam::{Vec2, Vec3};
use quasar::film::outputs::{OUTPUTS, Producer, aov_names};
use quasar::output::ExrImage;
use quasar::output::cryptomatte::id_bits;
use quasar::render::job::JobOverrides;

const SCENE: &str = r#"
[render]
width = 36
height = 28
[camera]
position = [0.2, 3, 0.6]
target = [0, 0, 0]
fov_deg = 40
[materials.grey]
type = "diffuse"
reflectance = 0.5
[materials.red]
type = "diffuse"
reflectance = { rgb = [0.8, 0.2, 0.1] }
[[shape]]
name = "floor"
type = "quad"
center = [0, 0, 0]
size = [6, 6]
normal = [0, 1, 0]
material = "grey"
[[shape]]
name = "card"
type = "quad"
center = [0, 0.5, 0]
size = [1, 1]
normal = [0, 1, 0]
material = "red"
[[light]]
type = "environment"
"#;

/// Where a pixel lies: wholly on the card, wholly on the floor outside it, or across an edge.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cover {
    Card,
    Floor,
    Edge,
}

/// Each pixel's [`Cover`], from the rays through its four corners (the pixel's footprint on a
/// plane is the convex hull of the corners' hits, and the card is convex).
fn covers(desc: &quasar_importers::SceneDesc, w: u32, h: u32) -> Vec<Cover> {
    let camera = quasar::core::camera::Camera::new(&desc.camera, w, h).unwrap();
    let on_card = |x: f32, y: f32| {
        let r = camera.ray(Vec2::new(x, y));
        let t = (0.5 - r.origin.y) / r.dir.y;
        let p: Vec3 = r.origin + r.dir * t;
        p.x.abs() < 0.5 && p.z.abs() < 0.5
    };
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            let corners = [on_card(x, y), on_card(x + 1.0, y), on_card(x, y + 1.0), on_card(x + 1.0, y + 1.0)];
            match corners.iter().filter(|&&c| c).count() {
                4 => Cover::Card,
                0 => Cover::Floor,
                _ => Cover::Edge,
            }
        })
        .collect()
}

fn all_aovs() -> JobOverrides {
    JobOverrides {
        spp: Some(2),
        method: Some("pt".into()),
        aovs: Some(aov_names().iter().map(|s| s.to_string()).collect()),
        aov_samples: Some(32),
        ..Default::default()
    }
}

fn channel<'a>(img: &'a ExrImage, name: &str) -> &'a [f32] {
    img.channel(name).unwrap_or_else(|| panic!("no channel {name}"))
}

#[test]
fn aovs_are_what_the_scene_determines() {
    let scene = write_scene(SCENE, &[]);
    let desc = quasar::render::job::load_scene(&scene.path).unwrap();
    let img = render_file(&scene.path, &all_aovs()).image;
    let cover = covers(&desc, 36, 28);
    let (n_card, n_floor) =
        (cover.iter().filter(|&&c| c == Cover::Card).count(), cover.iter().filter(|&&c| c == Cover::Floor).count());
    assert!(n_card > 20 && n_floor > 200, "{n_card} card and {n_floor} floor pixels");
    // every row of the AOV pass is written
    for row in OUTPUTS.iter().filter(|r| r.producer == Producer::AovPass) {
        assert!(img.channels.iter().any(|c| row.holds(&c.name)), "no channel of {}", row.pattern());
    }
    let v3 = |layer: &str, i: usize| {
        Vec3::new(
            channel(&img, &format!("{layer}.X"))[i],
            channel(&img, &format!("{layer}.Y"))[i],
            channel(&img, &format!("{layer}.Z"))[i],
        )
    };
    let ids: serde_json::Value = serde_json::from_str(img.meta("object_ids").unwrap()).unwrap();
    let id_of = |name: &str| {
        ids.as_object().unwrap().iter().find(|(_, v)| v.as_str() == Some(name)).map(|(k, _)| k.parse::<f32>().unwrap())
    };
    let materials: serde_json::Value = serde_json::from_str(img.meta("material_ids").unwrap()).unwrap();
    assert_eq!(materials.as_object().unwrap().len(), 2);
    let (mut albedo_floor, mut albedo_card) = ([0.0f64; 3], [0.0f64; 3]);
    for (i, &c) in cover.iter().enumerate() {
        // the floor fills the view: every pixel's coverages sum to 1
        let sum: f32 =
            (0..3).flat_map(|l| ["G", "A"].map(|k| channel(&img, &format!("CryptoObject{l:02}.{k}"))[i])).sum();
        assert!((sum - 1.0).abs() < 1e-5, "pixel {i}: coverages sum to {sum}");
        if c == Cover::Edge {
            continue;
        }
        let (name, height, material) = if c == Cover::Card { ("card", 0.5, "red") } else { ("floor", 0.0, "grey") };
        assert!((v3("normal", i) - Vec3::Y).length() < 1e-5, "pixel {i}: normal {}", v3("normal", i));
        assert!((v3("normal_geometric", i) - Vec3::Y).length() < 1e-5, "pixel {i}");
        assert!((v3("position", i).y - height).abs() < 1e-5, "pixel {i}: position {}", v3("position", i));
        assert_eq!(channel(&img, "object_id.Y")[i], id_of(name).unwrap(), "pixel {i}");
        for (layer, n) in [("CryptoObject", name), ("CryptoMaterial", material)] {
            assert_eq!(channel(&img, &format!("{layer}00.R"))[i].to_bits(), id_bits(n), "pixel {i}: {layer}");
            assert_eq!(channel(&img, &format!("{layer}00.G"))[i], 1.0, "pixel {i}: {layer}");
            assert_eq!(channel(&img, &format!("{layer}00.A"))[i], 0.0, "pixel {i}: {layer}");
        }
        let acc = if c == Cover::Card { &mut albedo_card } else { &mut albedo_floor };
        for (k, ch) in ["R", "G", "B"].iter().enumerate() {
            acc[k] += f64::from(channel(&img, &format!("albedo.{ch}"))[i]);
        }
    }
    // the albedo: the reflectance in linear sRGB (hero-wavelength noise of 32 rays per pixel)
    for (acc, n, want) in [(albedo_floor, n_floor, [0.5; 3]), (albedo_card, n_card, [0.8, 0.2, 0.1])] {
        let mean = acc.map(|a| a / n as f64);
        for k in 0..3 {
            assert!((mean[k] - want[k]).abs() < 0.02, "albedo {mean:?}, reflectance {want:?}");
        }
    }
    // the manifest names exactly the objects seen, with their ids
    let key = quasar::output::cryptomatte::header_key("CryptoObject", "manifest");
    let manifest: serde_json::Value = serde_json::from_str(img.meta(&key).unwrap()).unwrap();
    let m = manifest.as_object().unwrap();
    assert_eq!(m.len(), 2);
    assert_eq!(m["card"].as_str(), Some(format!("{:08x}", id_bits("card")).as_str()));
}

/// The auxiliary outputs do not depend on the shard: shards merge to the full render's, and an
/// unknown name is refused with the place it was given.
#[test]
fn aovs_merge_and_unknown_names_are_refused() {
    let scene = write_scene(SCENE, &[]);
    let full = render_file(&scene.path, &all_aovs()).image;
    let shards: Vec<ExrImage> =
        (0..2).map(|k| render_file(&scene.path, &JobOverrides { shard: Some((k, 2)), ..all_aovs() }).image).collect();
    let merged = quasar::tools::merge::merge(&shards).unwrap();
    for c in full.channels.iter().filter(|c| quasar::film::outputs::group_of(&c.name).is_some_and(|g| g.aov.is_some()))
    {
        assert_eq!(merged.channel(&c.name).unwrap(), c.values.as_slice(), "{}", c.name);
    }
    let bad = write_scene(&SCENE.replace("[render]", "[render]\naovs = [\"normal\", \"normals\"]"), &[]);
    let desc = quasar::render::job::load_scene(&bad.path).unwrap();
    let err = format!("{:#}", quasar::render::job::render_desc(&desc, &JobOverrides::default(), false).err().unwrap());
    assert!(
        err.contains("scene.toml:3") && err.contains("unknown output 'normals'") && err.contains("crypto_object"),
        "{err}"
    );
}
