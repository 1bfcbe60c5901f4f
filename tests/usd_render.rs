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
