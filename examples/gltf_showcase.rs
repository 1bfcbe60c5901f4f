//! Generates the shipped glTF showcase scene `scenes/gltf-showcase/` (glTF JSON + external binary
//! buffer + two PNG textures): perspective cameras, KHR_lights_punctual (point, spot,
//! directional), KHR_materials_transmission/ior/volume (glass), KHR_materials_emissive_strength,
//! KHR_texture_transform, base-colour and metallic-roughness textures, a multi-primitive mesh and
//! an instanced mesh.
//!
//! Run: `cargo run --release --example gltf_showcase [OUT_DIR [SEED_DIR]]` (default
//! `scenes/gltf-showcase`); with SEED_DIR it also writes small self-contained fuzzing seeds there
//! (`showcase.glb` with embedded textures and coarse spheres, `showcase-data-uri.gltf`).
//! Render: `cargo run --release -- render scenes/gltf-showcase/showcase.gltf -o showcase.exr`.

use std::f32::consts::PI;
use std::path::PathBuf;

use quasar_importers::gltf::writer::{BinStorage, GltfWriter, Prim};

/// A UV sphere of `radius` with `seg` segments around and `seg / 2` rings.
fn sphere(w: &mut GltfWriter, radius: f32, seg: u32, material: usize) -> Prim {
    let rings = seg / 2;
    let (mut p, mut n, mut uv, mut idx) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for r in 0..=rings {
        let th = PI * r as f32 / rings as f32;
        for s in 0..=seg {
            let ph = 2.0 * PI * s as f32 / seg as f32;
            let d = [th.sin() * ph.cos(), th.cos(), -th.sin() * ph.sin()];
            p.push(d.map(|c| c * radius));
            n.push(d);
            uv.push([s as f32 / seg as f32, r as f32 / rings as f32]);
        }
    }
    for r in 0..rings {
        for s in 0..seg {
            let a = r * (seg + 1) + s;
            let b = a + seg + 1;
            idx.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    let position = w.positions(&p);
    Prim {
        position,
        normal: Some(w.normals(&n)),
        uv: Some(w.uvs(&uv)),
        indices: Some(w.indices(&idx)),
        material: Some(material),
        mode: None,
    }
}

/// An axis-aligned box `lo..hi` (24 vertices, flat faces, per-face uvs).
fn cuboid(w: &mut GltfWriter, lo: [f32; 3], hi: [f32; 3], material: usize) -> Prim {
    let (mut p, mut n, mut uv, mut idx) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for axis in 0..3 {
        for side in [0usize, 1] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = p.len() as u32;
            for (a, b) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                let mut q = [0.0f32; 3];
                q[axis] = if side == 1 { hi[axis] } else { lo[axis] };
                q[u] = if a == 1 { hi[u] } else { lo[u] };
                q[v] = if b == 1 { hi[v] } else { lo[v] };
                p.push(q);
                let mut nn = [0.0f32; 3];
                nn[axis] = if side == 1 { 1.0 } else { -1.0 };
                n.push(nn);
                uv.push([a as f32, 1.0 - b as f32]);
            }
            // counter-clockwise seen from outside
            if side == 1 {
                idx.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
            } else {
                idx.extend_from_slice(&[base, base + 2, base + 1, base, base + 3, base + 2]);
            }
        }
    }
    let position = w.positions(&p);
    Prim {
        position,
        normal: Some(w.normals(&n)),
        uv: Some(w.uvs(&uv)),
        indices: Some(w.indices(&idx)),
        material: Some(material),
        mode: None,
    }
}

fn png(size: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(size, size, |x, y| image::Rgba(f(x, y)));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).expect("PNG encoding");
    out.into_inner()
}

fn main() -> std::io::Result<()> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "scenes/gltf-showcase".into()));
    std::fs::create_dir_all(&dir)?;
    let (checker, stripes) = textures();
    std::fs::write(dir.join("checker.png"), &checker)?;
    std::fs::write(dir.join("stripes.png"), &stripes)?;
    let w = build(None, 48);
    let (json, bin) = w.to_gltf(&BinStorage::External("showcase.bin".into()));
    std::fs::write(dir.join("showcase.gltf"), json)?;
    std::fs::write(dir.join("showcase.bin"), bin)?;
    println!("wrote {}", dir.join("showcase.gltf").display());
    if let Some(seeds) = std::env::args().nth(2).map(PathBuf::from) {
        std::fs::create_dir_all(&seeds)?;
        let w = build(Some((&checker, &stripes)), 6);
        std::fs::write(seeds.join("showcase.glb"), w.to_glb())?;
        std::fs::write(seeds.join("showcase-data-uri.gltf"), w.to_gltf(&BinStorage::DataUri).0)?;
        println!("wrote seeds to {}", seeds.display());
    }
    Ok(())
}

/// The two PNG textures: a checker (sRGB base colour) and a metallic-roughness stripe map.
fn textures() -> (Vec<u8>, Vec<u8>) {
    let checker = png(64, |x, y| if (x / 8 + y / 8) % 2 == 0 { [230, 226, 215, 255] } else { [40, 70, 120, 255] });
    let stripes = png(32, |x, _| if (x / 4) % 2 == 0 { [0, 40, 255, 255] } else { [0, 200, 0, 255] });
    (checker, stripes)
}

/// The showcase document; `embed` = the PNG bytes to store in the buffer (else external URIs),
/// `seg` = sphere segments.
fn build(embed: Option<(&[u8], &[u8])>, seg: u32) -> GltfWriter {
    let mut w = GltfWriter::new();
    for e in [
        "KHR_lights_punctual",
        "KHR_materials_transmission",
        "KHR_materials_ior",
        "KHR_materials_volume",
        "KHR_materials_emissive_strength",
        "KHR_texture_transform",
    ] {
        w.use_extension(e, false);
    }
    match embed {
        Some((checker, stripes)) => {
            w.image(checker, "image/png");
            w.image(stripes, "image/png");
        }
        None => {
            GltfWriter::push(&mut w.images, r#"{"uri":"checker.png","name":"checker"}"#);
            GltfWriter::push(&mut w.images, r#"{"uri":"stripes.png","name":"stripes"}"#);
        }
    }
    GltfWriter::push(&mut w.samplers, r#"{"magFilter":9728,"wrapS":10497,"wrapT":10497}"#);
    GltfWriter::push(&mut w.textures, r#"{"source":0,"sampler":0}"#);
    GltfWriter::push(&mut w.textures, r#"{"source":1}"#);

    let floor_mat = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"Floor","pbrMetallicRoughness":{"baseColorTexture":{"index":0,
        "extensions":{"KHR_texture_transform":{"scale":[6,6]}}},"metallicFactor":0,"roughnessFactor":1}}"#,
    );
    let glass = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"Glass","pbrMetallicRoughness":{"metallicFactor":0,"roughnessFactor":0},
        "extensions":{"KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_ior":{"ior":1.5},
        "KHR_materials_volume":{"thicknessFactor":0.3}}}"#,
    );
    let gold = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"Gold","pbrMetallicRoughness":{"baseColorFactor":[1.0,0.78,0.34,1],"metallicFactor":1,"roughnessFactor":0.35}}"#,
    );
    let striped = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"StripedMetal","pbrMetallicRoughness":{"baseColorFactor":[0.9,0.9,0.92,1],
        "metallicRoughnessTexture":{"index":1},"metallicFactor":1,"roughnessFactor":1}}"#,
    );
    let red = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"RedPaint","pbrMetallicRoughness":{"baseColorFactor":[0.7,0.08,0.05,1],"metallicFactor":0,"roughnessFactor":0.6}}"#,
    );
    let lamp = GltfWriter::push(
        &mut w.materials,
        r#"{"name":"Lamp","emissiveFactor":[1,0.85,0.6],"doubleSided":false,
        "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":2000}}}"#,
    );

    let floor = {
        let position = w.positions(&[[-3.0, 0.0, 3.0], [3.0, 0.0, 3.0], [3.0, 0.0, -3.0], [-3.0, 0.0, -3.0]]);
        let normal = Some(w.normals(&[[0.0, 1.0, 0.0]; 4]));
        let uv = Some(w.uvs(&[[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]));
        let indices = Some(w.indices(&[0, 1, 2, 0, 2, 3]));
        Prim { position, normal, uv, indices, material: Some(floor_mat), mode: None }
    };
    let floor_mesh = w.mesh("Floor", &[floor]);
    let glass_prim = sphere(&mut w, 0.45, seg, glass);
    let glass_mesh = w.mesh("GlassBall", &[glass_prim]);
    let gold_prim = sphere(&mut w, 0.2, (seg * 2 / 3).max(4), gold);
    let gold_mesh = w.mesh("GoldBall", &[gold_prim]);
    // one mesh, two primitives with two materials: a red block with a striped metal lid
    let body = cuboid(&mut w, [-0.35, 0.0, -0.35], [0.35, 0.5, 0.35], red);
    let lid = cuboid(&mut w, [-0.4, 0.5, -0.4], [0.4, 0.58, 0.4], striped);
    let block_mesh = w.mesh("Block", &[body, lid]);
    let panel = {
        let position = w.positions(&[[-0.5, 0.0, -0.25], [0.5, 0.0, -0.25], [0.5, 0.0, 0.25], [-0.5, 0.0, 0.25]]);
        // facing down (-y): counter-clockwise seen from below
        let indices = Some(w.indices(&[0, 1, 2, 0, 2, 3]));
        Prim { position, normal: None, uv: None, indices, material: Some(lamp), mode: None }
    };
    let panel_mesh = w.mesh("LampPanel", &[panel]);

    // cameras: "Main" (16:9) and "Top"
    GltfWriter::push(
        &mut w.cameras,
        r#"{"name":"Main","type":"perspective","perspective":{"yfov":0.6,"aspectRatio":1.7778,"znear":0.05}}"#,
    );
    GltfWriter::push(&mut w.cameras, r#"{"name":"Top","type":"perspective","perspective":{"yfov":0.9,"znear":0.05}}"#);
    // lights: intensities in candela (point, spot) and lux (directional)
    GltfWriter::push(&mut w.lights, r#"{"name":"Bulb","type":"point","color":[1,0.9,0.8],"intensity":60}"#);
    GltfWriter::push(
        &mut w.lights,
        r#"{"name":"Spot","type":"spot","color":[0.8,0.9,1],"intensity":400,"spot":{"innerConeAngle":0.25,"outerConeAngle":0.45}}"#,
    );
    GltfWriter::push(&mut w.lights, r#"{"name":"Sun","type":"directional","color":[1,0.97,0.9],"intensity":30}"#);

    let nodes = [
        format!(r#"{{"name":"Floor","mesh":{floor_mesh}}}"#),
        format!(r#"{{"name":"Glass","mesh":{glass_mesh},"translation":[-0.6,0.45,0.2]}}"#),
        format!(r#"{{"name":"GoldA","mesh":{gold_mesh},"translation":[0.55,0.2,0.6]}}"#),
        format!(r#"{{"name":"GoldB","mesh":{gold_mesh},"translation":[1.1,0.2,0.1]}}"#),
        format!(r#"{{"name":"Block","mesh":{block_mesh},"translation":[0.5,0,-0.6],"rotation":[0,0.2588,0,0.9659]}}"#),
        format!(r#"{{"name":"Lamp","mesh":{panel_mesh},"translation":[0,2.2,-0.3]}}"#),
        // camera looks down -z; placed in front, tilted down by ~17 degrees
        r#"{"name":"MainCam","camera":0,"translation":[0,1.3,4.0],"rotation":[-0.1478,0,0,0.989]}"#.into(),
        // straight down: rotate -90 degrees about x
        r#"{"name":"TopCam","camera":1,"translation":[0,5,0],"rotation":[-0.7071068,0,0,0.7071068]}"#.into(),
        r#"{"name":"BulbNode","translation":[-1.5,1.6,1.2],"extensions":{"KHR_lights_punctual":{"light":0}}}"#.into(),
        // spot above the glass ball, pointing down
        r#"{"name":"SpotNode","translation":[-0.6,2.5,0.2],"rotation":[-0.7071068,0,0,0.7071068],"extensions":{"KHR_lights_punctual":{"light":1}}}"#.into(),
        // sun from the upper right
        r#"{"name":"SunNode","rotation":[-0.3827,0.3827,0,0.8478],"extensions":{"KHR_lights_punctual":{"light":2}}}"#.into(),
    ];
    for n in &nodes {
        let i = GltfWriter::push(&mut w.nodes, n);
        w.roots.push(i);
    }
    w
}
