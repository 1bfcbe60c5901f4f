//! A USD stage rendered end to end in photometric units, the check glTF has: a `SphereLight`
//! with `treatAsPoint` of 1 cd (intensity 1 nit on a sphere of radius 1/sqrt(pi) m: I = L pi r^2)
//! 1 m above a white Lambertian floor gives 1 lx there, i.e. a luminance of 1/pi cd/m^2.

mod common;

use quasar::render::job::{JobOverrides, render_desc};
use quasar_importers::photometric::LUMINANCE_PER_Y;
use quasar_importers::{ImportOptions, import_scene};

const STAGE: &str = r#"#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "World"
{
    def Mesh "Floor" (prepend apiSchemas = ["MaterialBindingAPI"])
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-10, 0, 10), (10, 0, 10), (10, 0, -10), (-10, 0, -10)]
        uniform token subdivisionScheme = "none"
        rel material:binding = </World/White>
    }
    def Material "White"
    {
        token outputs:surface.connect = </World/White/Surface.outputs:surface>
        def Shader "Surface"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (1, 1, 1)
            float inputs:roughness = 1
            float inputs:metallic = 0
            token outputs:surface
        }
    }
    def Camera "Cam"
    {
        float focalLength = 6
        float horizontalAperture = 1
        float verticalAperture = 1
        double3 xformOp:translate = (0, 0.5, 0)
        float xformOp:rotateX = -90
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
    }
    def SphereLight "Bulb"
    {
        float inputs:intensity = 1
        float inputs:radius = 0.5641896
        bool treatAsPoint = 1
        double3 xformOp:translate = (0, 1, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
}
"#;

#[test]
fn one_candela_usd_point_light_gives_the_photometric_luminance() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cd.usda");
    std::fs::write(&p, STAGE).unwrap();
    let desc = import_scene(&p, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let ov = JobOverrides {
        width: Some(8),
        height: Some(8),
        spp: Some(4),
        method: Some("pt".into()),
        threads: Some(2),
        ..Default::default()
    };
    let img = render_desc(&desc, &ov, false).unwrap_or_else(|e| panic!("{e:#}")).image;
    let lv = common::mean(img.channel("XYZ.Y").unwrap()) * f64::from(LUMINANCE_PER_Y);
    let want = 1.0 / std::f64::consts::PI;
    assert!((lv / want - 1.0).abs() < 0.02, "luminance {lv} cd/m^2, expected {want}");
}

/// The shipped Cornell box as a USD stage (`scenes/usd/cornell-box.toml`: geometry and camera
/// from `cornell-box.usda`, the measured spectra by `[[override]]`) renders the image of the
/// TOML scene: block z-test of independent renders (different seeds), beauty and every layer.
#[test]
fn cornell_box_stage_renders_the_toml_image() {
    let toml = common::render_file(&common::shipped("cornell-box/cornell-box.toml"), &common::pt_ov(48, 48, 64, 1));
    let usd = common::render_file(&common::shipped("usd/cornell-box.toml"), &common::pt_ov(48, 48, 64, 2));
    common::assert_converges("cornell box, USD vs TOML", &usd, &toml, &common::ALL_QUANTITIES);
}

/// `cornell-box.usda` and `cornell-box.usdc` hold the same stage (written by
/// `scenes/usd/make_usd.py` from one in-memory stage): with one seed, every channel of every
/// pixel is the same bit for bit.
#[test]
fn usda_and_usdc_of_one_stage_render_bit_for_bit() {
    let ov = common::pt_ov(24, 24, 4, 7);
    let a = common::render_file(&common::shipped("usd/cornell-box.usda"), &ov);
    let c = common::render_file(&common::shipped("usd/cornell-box.usdc"), &ov);
    assert_eq!(a.image.channels.len(), c.image.channels.len());
    for (x, y) in a.image.channels.iter().zip(&c.image.channels) {
        assert_eq!(x.name, y.name);
        let same = x.values.iter().zip(&y.values).all(|(p, q)| p.to_bits() == q.to_bits());
        assert!(same, "channel {} differs between usda and usdc", x.name);
    }
}

/// The glass plate as a composed Z-up stage (`scenes/usd/glass-plate.usda`: the plate asset by
/// reference, its narrow top finish by variant, a RectLight with a colour temperature and a
/// DomeLight in nits) renders the image of `scenes/glass-plate/glass-plate.toml`.
#[test]
fn composed_glass_plate_stage_renders_the_toml_image() {
    let toml = common::render_file(&common::shipped("glass-plate/glass-plate.toml"), &common::pt_ov(64, 48, 256, 3));
    let usd = common::render_file(&common::shipped("usd/glass-plate.usda"), &common::pt_ov(64, 48, 256, 4));
    common::assert_converges("glass plate, USD vs TOML", &usd, &toml, &common::ALL_QUANTITIES);
}
