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
    let lv = common::mean(img.channel(quasar::film::LUMINANCE).unwrap()) * f64::from(LUMINANCE_PER_Y);
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

/// A UsdUVTexture seen straight on renders the right way up and round: the 2 x 2 image (red,
/// green / blue, white) on a quad whose st runs (0, 0) at the lower left to (1, 1), lit by a
/// white dome, gives those colours in the image's quadrants.
#[test]
fn uv_textures_render_the_right_way_up() {
    let dir = tempfile::tempdir().unwrap();
    let img = image::RgbaImage::from_fn(2, 2, |x, y| match (x, y) {
        (0, 0) => image::Rgba([255, 0, 0, 255]),
        (1, 0) => image::Rgba([0, 255, 0, 255]),
        (0, 1) => image::Rgba([0, 0, 255, 255]),
        _ => image::Rgba([255, 255, 255, 255]),
    });
    img.save(dir.path().join("quads.png")).unwrap();
    let stage = r#"#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "World"
{
    def Mesh "Quad" (prepend apiSchemas = ["MaterialBindingAPI"])
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
        texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] (interpolation = "vertex")
        uniform token subdivisionScheme = "none"
        rel material:binding = </World/Look>
    }
    def Material "Look"
    {
        token outputs:surface.connect = </World/Look/Surface.outputs:surface>
        def Shader "Surface"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor.connect = </World/Look/Tex.outputs:rgb>
            float inputs:roughness = 1
            token outputs:surface
        }
        def Shader "Tex"
        {
            uniform token info:id = "UsdUVTexture"
            asset inputs:file = @./quads.png@
            token inputs:wrapS = "clamp"
            token inputs:wrapT = "clamp"
            float3 outputs:rgb
        }
    }
    def Camera "Cam"
    {
        float focalLength = 20
        float horizontalAperture = 10
        float verticalAperture = 10
        double3 xformOp:translate = (0.5, 0.5, 1.5)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def DomeLight "Sky"
    {
        float inputs:intensity = 1
    }
}
"#;
    let p = dir.path().join("tex.usda");
    std::fs::write(&p, stage).unwrap();
    let out = common::render_file(&p, &common::pt_ov(16, 16, 16, 1));
    let ch = |name: &str| out.image.channel(name).unwrap().to_vec();
    let (r, g, b) = (ch("R"), ch("G"), ch("B"));
    let quadrant = |qx: usize, qy: usize| {
        let (mut s, mut n) = ([0.0f64; 3], 0.0);
        // the inner 4 x 4 pixels of each 8 x 8 quadrant (the quad fills the view)
        for y in qy * 8 + 2..qy * 8 + 6 {
            for x in qx * 8 + 2..qx * 8 + 6 {
                let i = y * 16 + x;
                s[0] += f64::from(r[i]);
                s[1] += f64::from(g[i]);
                s[2] += f64::from(b[i]);
                n += 1.0;
            }
        }
        s.map(|v| v / n)
    };
    let dominant = |c: [f64; 3]| (0..3).max_by(|&a, &b| c[a].total_cmp(&c[b])).unwrap();
    assert_eq!(dominant(quadrant(0, 0)), 0, "top left is red: {:?}", quadrant(0, 0));
    assert_eq!(dominant(quadrant(1, 0)), 1, "top right is green: {:?}", quadrant(1, 0));
    assert_eq!(dominant(quadrant(0, 1)), 2, "bottom left is blue: {:?}", quadrant(0, 1));
    let white = quadrant(1, 1);
    assert!(white.iter().all(|&c| c > 0.5 * white[0].max(white[1]).max(white[2])), "bottom right is white: {white:?}");
}

/// A textured DomeLight follows UsdLux's OpenEXR lat-long orientation: the left half of the image
/// (longitude 0..pi) lights the dome's +X half, so a camera looking along +X sees it bright and
/// one looking along -X dark; a dome turned 90 degrees about +Y moves the bright half to -Z, and
/// one turned 90 degrees about +Z (its pole tilted onto -X) moves it up (+Y).
#[test]
fn dome_light_textures_follow_the_openexr_orientation() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (16usize, 8usize);
    exr::prelude::write_rgb_file(dir.path().join("sky.exr"), w, h, |x, _| {
        if x < w / 2 { (1.0f32, 1.0f32, 1.0f32) } else { (0.01, 0.01, 0.01) }
    })
    .unwrap();
    let stage = |dome: &str, cam: &str| {
        format!(
            r#"#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "World"
{{
    def Camera "Cam"
    {{
        float focalLength = 50
        float xformOp:{cam}
        uniform token[] xformOpOrder = ["xformOp:{cam_op}"]
    }}
    def DomeLight "Sky"
    {{
        float inputs:intensity = 1
        asset inputs:texture:file = @./sky.exr@
        token inputs:texture:format = "latlong"
        float xformOp:{dome}
        uniform token[] xformOpOrder = ["xformOp:{dome_op}"]
    }}
}}
"#,
            cam_op = cam.split(' ').next().unwrap(),
            dome_op = dome.split(' ').next().unwrap(),
        )
    };
    // camera yaw -90 looks along +X, 90 along -X, 0 along -Z, 180 along +Z; pitch 90 up, -90 down
    for (dome, bright_cam, dark_cam) in [
        ("rotateY = 0", "rotateY = -90", "rotateY = 90"),
        ("rotateY = 90", "rotateY = 0", "rotateY = 180"),
        ("rotateZ = 90", "rotateX = 90", "rotateX = -90"),
    ] {
        let mean = |cam: &str| {
            let p = dir.path().join("dome.usda");
            std::fs::write(&p, stage(dome, cam)).unwrap();
            let desc = quasar_importers::import_scene(&p, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
            let img = render_desc(&desc, &common::pt_ov(8, 8, 4, 1), false).unwrap().image;
            common::mean(img.channel(quasar::film::LUMINANCE).unwrap())
        };
        let (bright, dark) = (mean(bright_cam), mean(dark_cam));
        assert!(bright > 20.0 * dark, "dome {dome}: bright side {bright}, dark side {dark}");
    }
}
