//! Writes a scene description as a Mitsuba 3 scene (XML and OBJ meshes) for the independent
//! cross-check of `tests/crosscheck/` (docs/validation.md), with quasar's conventions made
//! explicit so that both renderers compute the same image:
//!
//! | quasar | Mitsuba 3 |
//! |---|---|
//! | spectra (any form) | `wavelength:value` spectra: tables as their knots (zero outside in both), every other curve tabulated at each nm of 360..830 |
//! | diffuse, `two_sided` | `diffuse` (in `twosided` when two-sided) |
//! | conductor, constant Fresnel F | `conductor`/`roughconductor` with `material = "none"` (F = 1) and `specular_reflectance` = F |
//! | conductor, eta + i k | `eta`, `k` spectra |
//! | dielectric, constant IOR | `dielectric`/`roughdielectric`, `int_ior`, `ext_ior` = 1 |
//! | coated over a Lambertian or conductor base | the physical layer: the base's BSDF under a `dielectric`/`roughdielectric` copy of the mesh 2 mm (1 + max coordinate) above it ([`super::mitsuba_obj::coat_shape`]) |
//! | GGX alpha (used directly), visible-normal sampling | `distribution = "ggx"`, `alpha`, `sample_visible` |
//! | emissive mesh (front face) | `area` emitter with `radiance` |
//! | point, directional, environment | `point` (`intensity`), `directional` (`irradiance`), `constant` (`radiance`) |
//! | spot with a hard edge (falloff start = cone) | `spot` with `beam_width` = `cutoff_angle` |
//! | pinhole camera, box pixel filter | `perspective` (`fov`, `fov_axis`), `hdrfilm` XYZ, `box` filter |
//! | `pt`, unbounded depth | `path`, `max_depth` = -1 |
//!
//! What Mitsuba cannot express the same way is an error naming it: dispersive IORs (Mitsuba's
//! dielectrics have one IOR), tabulated BSDFs, coats over tabulated bases or absorbing coats, textures, two-sided emission, spot lights with a
//! soft edge (quasar's falloff is a smoothstep in cos theta, Mitsuba's linear in theta).
//! One difference remains and is documented rather than removed: quasar's GGX uses Smith's
//! height-correlated masking-shadowing, Mitsuba's the separable product G1 G1; they differ only
//! where both directions are near grazing (below 1% of the reflectance for alpha <= 0.3 at
//! incidence within 60 degrees).

use std::fmt::Write as _;
use std::path::Path;

use quasar_importers::{FovAxis, LightDesc, SceneDesc};
use quasar_materials::bsdf::microfacet::SMOOTH_ALPHA;
use quasar_materials::spectrum::{LAMBDA_MAX, LAMBDA_MIN, Spectrum};
use quasar_materials::{ConductorFresnel, Ior, Material};

/// A Mitsuba scene: the XML and the OBJ files it refers to (relative names).
#[derive(Clone, Debug)]
pub struct MitsubaScene {
    /// The scene XML.
    pub xml: String,
    /// (file name relative to the XML, OBJ text) of every mesh.
    pub meshes: Vec<(String, String)>,
}

/// `scale` x `s` as a Mitsuba spectrum value string: the knots of a table (Mitsuba's
/// irregular spectra are zero outside their range, like quasar's tables), otherwise the curve
/// at every nm of the simulated range.
fn spectrum_value(s: &Spectrum, scale: f32) -> String {
    if let Spectrum::Dense(d) = s {
        return spectrum_value(d.curve(), scale);
    }
    let mut out = String::new();
    match s {
        Spectrum::Constant(v) => {
            let _ = write!(out, "{}", v * scale);
        }
        Spectrum::PiecewiseLinear { lambda, values } => {
            for (l, v) in lambda.iter().zip(values) {
                let _ = write!(out, "{}{l}:{}", if out.is_empty() { "" } else { ", " }, v * scale);
            }
        }
        _ => {
            let mut l = LAMBDA_MIN;
            while l <= LAMBDA_MAX {
                let _ = write!(out, "{}{l}:{}", if out.is_empty() { "" } else { ", " }, s.value(l) * scale);
                l += 1.0;
            }
        }
    }
    out
}

fn spectrum_tag(name: &str, s: &Spectrum, scale: f32) -> String {
    format!("<spectrum name=\"{name}\" value=\"{}\"/>", spectrum_value(s, scale))
}

fn vec3(v: glam::Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

/// Mitsuba's GGX parameters for alpha (visible-normal sampling, as quasar).
fn ggx(alpha: f32) -> String {
    format!(
        "<string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"{alpha}\"/><boolean name=\"sample_visible\" value=\"true\"/>"
    )
}

/// The BSDF of `material` (named `name`, for messages), or why Mitsuba cannot express it.
fn bsdf(name: &str, material: &Material) -> Result<String, String> {
    let rough = |alpha: f32| alpha >= SMOOTH_ALPHA;
    let two_sided = |inner: String, yes: bool| {
        if yes { format!("<bsdf type=\"twosided\">{inner}</bsdf>") } else { inner }
    };
    Ok(match material {
        Material::Diffuse { reflectance, two_sided: t } => {
            two_sided(format!("<bsdf type=\"diffuse\">{}</bsdf>", spectrum_tag("reflectance", reflectance, 1.0)), *t)
        }
        Material::Conductor { alpha, fresnel, two_sided: t } => {
            let kind = if rough(*alpha) { "roughconductor" } else { "conductor" };
            let dist = if rough(*alpha) { ggx(*alpha) } else { String::new() };
            let f = match fresnel {
                ConductorFresnel::Constant(s) => {
                    format!(
                        "<string name=\"material\" value=\"none\"/>{}",
                        spectrum_tag("specular_reflectance", s, 1.0)
                    )
                }
                ConductorFresnel::Complex { eta, k } => {
                    format!("{}{}", spectrum_tag("eta", eta, 1.0), spectrum_tag("k", k, 1.0))
                }
            };
            two_sided(format!("<bsdf type=\"{kind}\">{dist}{f}</bsdf>"), *t)
        }
        Material::Dielectric { ior, alpha, transmittance } => {
            let Ior::Constant(n) = ior else {
                return Err(format!("material '{name}': a dispersive IOR (Mitsuba's dielectrics have one IOR)"));
            };
            let kind = if rough(*alpha) { "roughdielectric" } else { "dielectric" };
            let dist = if rough(*alpha) { ggx(*alpha) } else { String::new() };
            let tint = transmittance.as_ref().map_or(String::new(), |t| spectrum_tag("specular_transmittance", t, 1.0));
            format!(
                "<bsdf type=\"{kind}\">{dist}<float name=\"int_ior\" value=\"{n}\"/><float name=\"ext_ior\" value=\"1\"/>{tint}</bsdf>"
            )
        }
        Material::Tabulated(_) => return Err(format!("material '{name}': a tabulated BSDF")),
        Material::Sheen { .. } => return Err(format!("material '{name}': a sheen (Mitsuba 3 has no sheen BSDF)")),
        // the coat as what it models: the base under a dielectric layer (see `coat_shape`)
        Material::Coated { coating, base, .. } => {
            if !matches!(base.as_ref(), Material::Diffuse { .. } | Material::Conductor { .. }) {
                return Err(format!("material '{name}': a coat over a tabulated base"));
            }
            if coating.absorption.is_some() {
                return Err(format!("material '{name}': an absorbing coat"));
            }
            return bsdf(name, base);
        }
    })
}

/// The interior medium of a material that absorbs or scatters: Mitsuba's `homogeneous` medium
/// of sigma_t = sigma_a + sigma_s and albedo sigma_s / sigma_t (1/m, on the 1 nm grid; the scene
/// is in metres), sigma_t at least 1e-7 / m (Mitsuba 3.9's `volpath` returns NaN where sigma_t is
/// 0; 1e-7 / m changes a metre's transmittance by 1e-7), with an `hg` phase function of the
/// same g.
fn interior_medium(a: Option<&quasar_materials::Absorption>, s: Option<&quasar_materials::Scattering>) -> String {
    let lambda: Vec<f32> = (LAMBDA_MIN as u32..=LAMBDA_MAX as u32).map(|l| l as f32).collect();
    let at = |l: f32| quasar_materials::spectrum::SampledWavelengths::from_parts([l; 4], [1.0; 4]);
    let (mut sigma_t, mut albedo) = (Vec::new(), Vec::new());
    for &l in &lambda {
        let sa = a.map_or(0.0, |a| a.sigma_a(&at(l)).0[0]);
        let ss = s.map_or(0.0, |s| s.sigma_s(&at(l)).0[0]);
        let st = (sa + ss).max(1e-7);
        sigma_t.push(st);
        albedo.push((ss / st).clamp(0.0, 1.0));
    }
    let sigma_t = Spectrum::PiecewiseLinear { lambda: lambda.clone(), values: sigma_t };
    // a constant albedo as a number: Mitsuba 3.9 cannot build its sampling distribution from a
    // spectrum that is 0 everywhere (an absorbing medium's)
    let albedo = if albedo.iter().all(|&a| a == albedo[0]) {
        format!("<float name=\"albedo\" value=\"{}\"/>", albedo[0])
    } else {
        spectrum_tag("albedo", &Spectrum::PiecewiseLinear { lambda, values: albedo }, 1.0)
    };
    let phase = s.map_or(String::new(), |s| {
        format!("<phase type=\"hg\"><float name=\"g\" value=\"{}\"/></phase>", s.phase().g())
    });
    format!(
        "<medium name=\"interior\" type=\"homogeneous\">{albedo}{}{phase}</medium>",
        spectrum_tag("sigma_t", &sigma_t, 1.0)
    )
}

/// The Mitsuba scene of `desc` rendered at `width` x `height` with `spp` samples per pixel.
/// With media it renders with `volpath`, which traces them (`path` ignores media).
pub fn export(desc: &SceneDesc, width: u32, height: u32, spp: u32) -> Result<MitsubaScene, String> {
    let mut xml = String::from("<scene version=\"3.0.0\">\n");
    let integrator = if desc.materials.iter().any(|m| m.absorption.is_some() || m.scattering.is_some()) {
        "volpath"
    } else {
        "path"
    };
    let _ = writeln!(xml, "<integrator type=\"{integrator}\"><integer name=\"max_depth\" value=\"-1\"/></integrator>");
    let c = &desc.camera;
    let near = (1e-4 * (c.target - c.position).length()).min(1e-2);
    let axis = match c.fov_axis {
        FovAxis::X => "x",
        FovAxis::Y => "y",
    };
    let _ = writeln!(
        xml,
        "<sensor type=\"perspective\"><float name=\"fov\" value=\"{}\"/><string name=\"fov_axis\" value=\"{axis}\"/>\
         <float name=\"near_clip\" value=\"{near}\"/><float name=\"far_clip\" value=\"1e9\"/>\
         <transform name=\"to_world\"><lookat origin=\"{}\" target=\"{}\" up=\"{}\"/></transform>\
         <sampler type=\"independent\"><integer name=\"sample_count\" value=\"{spp}\"/></sampler>\
         <film type=\"hdrfilm\"><integer name=\"width\" value=\"{width}\"/><integer name=\"height\" value=\"{height}\"/>\
         <string name=\"pixel_format\" value=\"xyz\"/><rfilter type=\"box\"/></film></sensor>",
        c.fov_deg,
        vec3(c.position),
        vec3(c.target),
        vec3(c.up)
    );
    for (i, m) in desc.materials.iter().enumerate() {
        if !m.textures.is_empty() {
            return Err(format!("material '{}': textures", m.name));
        }
        let b = bsdf(&m.name, &m.material)?;
        // the id goes on the outermost element
        let b = b.replacen("<bsdf ", &format!("<bsdf id=\"mat{i}\" "), 1);
        let _ = writeln!(xml, "{b}");
        if let Material::Coated { coating, .. } = &m.material {
            let alpha = quasar_materials::bsdf::coat_albedo::coat_alpha(coating.alpha);
            let (kind, dist) =
                if alpha > SMOOTH_ALPHA { ("roughdielectric", ggx(alpha)) } else { ("dielectric", String::new()) };
            let _ = writeln!(
                xml,
                "<bsdf id=\"coat{i}\" type=\"{kind}\">{dist}<float name=\"int_ior\" value=\"{}\"/><float name=\"ext_ior\" value=\"1\"/></bsdf>",
                coating.ior
            );
        }
    }
    let mut meshes = Vec::new();
    for (i, m) in desc.meshes.iter().enumerate() {
        let file = format!("mesh{i}.obj");
        let obj = super::mitsuba_obj::obj_text(&m.positions, m.normals.as_deref(), &m.indices);
        let emitter = match &m.emission {
            Some(e) if e.two_sided => return Err(format!("mesh '{}': two-sided emission", m.name)),
            Some(e) => format!("<emitter type=\"area\">{}</emitter>", spectrum_tag("radiance", &e.spectrum, e.scale)),
            None => String::new(),
        };
        let medium = desc.materials.get(m.material).map_or(String::new(), |d| {
            if d.absorption.is_some() || d.scattering.is_some() {
                interior_medium(d.absorption.as_ref(), d.scattering.as_ref())
            } else {
                String::new()
            }
        });
        // an OBJ shape of `file` with the BSDF `bsdf` and further elements `extra`
        let shape = |file: &str, bsdf: &str, extra: &str| {
            format!(
                "<shape type=\"obj\"><string name=\"filename\" value=\"{file}\"/><boolean name=\"face_normals\" value=\"{}\"/>\
                 <ref id=\"{bsdf}\"/>{extra}</shape>",
                m.normals.is_none()
            )
        };
        let _ = writeln!(xml, "{}", shape(&file, &format!("mat{}", m.material), &format!("{emitter}{medium}")));
        meshes.push((file, obj));
        if matches!(desc.materials.get(m.material).map(|d| &d.material), Some(Material::Coated { .. })) {
            let file = format!("coat{i}.obj");
            let _ = writeln!(xml, "{}", shape(&file, &format!("coat{}", m.material), ""));
            meshes.push((file, super::mitsuba_obj::coat_shape(m)));
        }
    }
    for l in &desc.lights {
        let e = match l {
            LightDesc::Point { position, spectrum, scale } => format!(
                "<emitter type=\"point\"><point name=\"position\" value=\"{}\"/>{}</emitter>",
                vec3(*position),
                spectrum_tag("intensity", spectrum, *scale)
            ),
            LightDesc::Spot { position, direction, cone_deg, falloff_start_deg, spectrum, scale } => {
                if falloff_start_deg < cone_deg {
                    return Err("a spot light with a soft edge (falloff_start_deg < cone_deg)".into());
                }
                let d = direction.normalize();
                let up = if d.y.abs() < 0.9 { glam::Vec3::Y } else { glam::Vec3::X };
                format!(
                    "<emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"{}\" target=\"{}\" up=\"{}\"/></transform>\
                     <float name=\"cutoff_angle\" value=\"{cone_deg}\"/><float name=\"beam_width\" value=\"{cone_deg}\"/>{}</emitter>",
                    vec3(*position),
                    vec3(*position + d),
                    vec3(up),
                    spectrum_tag("intensity", spectrum, *scale)
                )
            }
            LightDesc::Directional { direction, spectrum, scale } => format!(
                "<emitter type=\"directional\"><vector name=\"direction\" value=\"{}\"/>{}</emitter>",
                vec3(*direction),
                spectrum_tag("irradiance", spectrum, *scale)
            ),
            LightDesc::Luminaire { .. } => {
                return Err("a luminaire (Mitsuba 3 has no measured-distribution emitter)".into());
            }
            LightDesc::Environment { map: Some(map), scale, .. } => env_map(map, *scale)?,
            LightDesc::Environment { spectrum, scale, map: None } => {
                format!("<emitter type=\"constant\">{}</emitter>", spectrum_tag("radiance", spectrum, *scale))
            }
        };
        let _ = writeln!(xml, "{e}");
    }
    xml += "</scene>\n";
    Ok(MitsubaScene { xml, meshes })
}

/// Luminance of Mitsuba 3.9's `d65` spectrum (see [`env_map`]).
const MITSUBA_D65_LUMINANCE: f32 = 0.998_893_8;

/// A grey lat-long map as Mitsuba's `envmap`: the same file, turned so that Mitsuba's u = atan2(x, -z) / 2 pi meets
/// quasar's u = 0.5 + atan2(x, -z) / 2 pi (a half turn about the map's pole). A grey texel's
/// spectrum is D65 times its value in both renderers; coloured texels are refused, since Mitsuba
/// uplifts RGB with its own tables. One difference remains: Mitsuba interpolates between texel
/// centres where quasar holds a texel's radiance constant. A smooth map renders the same image in
/// both; a sharp feature a few texels wide does not (a sun disc nine texels wide lit the
/// family's sky-objects scene 0.2% differently, z -20 at 8192 spp): give the sun as a
/// directional light, as the family does.
///
/// Mitsuba multiplies a grey texel by its own `d65` spectrum, whose luminance under its own CIE
/// 1931 ybar is 0.9988938 (sum of d65(λ) ȳ(λ) / sum of ȳ(λ) over 360..830 nm in 0.5 nm steps,
/// with `mi.load_dict({'type': 'd65'})` and `mi.cie1931_y` of the `scalar_spectral` variant), where
/// quasar's D65 white has luminance 1: the map's scale is divided by it
/// ([`MITSUBA_D65_LUMINANCE`]). Measured without it: a flat map of 1 rendered 0.10% darker in
/// Mitsuba than its constant emitter of quasar's D65 (64x64, 16384 spp), the same in quasar.
fn env_map(map: &quasar_importers::EnvMapDesc, scale: f32) -> Result<String, String> {
    if let Some(i) = map.texels.iter().position(|t| t[0] != t[1] || t[1] != t[2]) {
        return Err(format!(
            "an environment map with coloured texels ({}: texel {} of row {} is not grey; Mitsuba uplifts RGB its own way)",
            map.file.display(),
            i % map.width.max(1),
            i / map.width.max(1)
        ));
    }
    let path = map.file.canonicalize().map_err(|e| format!("{}: {e}", map.file.display()))?;
    let scale = scale / MITSUBA_D65_LUMINANCE;
    let half_turn = glam::Mat3::from_rotation_y(std::f32::consts::PI);
    let m = map.frame * half_turn;
    let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
    Ok(format!(
        "<emitter type=\"envmap\"><string name=\"filename\" value=\"{}\"/><float name=\"scale\" value=\"{scale}\"/>\
         <transform name=\"to_world\"><matrix value=\"{} {} {} 0 {} {} {} 0 {} {} {} 0 0 0 0 1\"/></transform></emitter>",
        path.display(),
        x.x,
        y.x,
        z.x,
        x.y,
        y.y,
        z.y,
        x.z,
        y.z,
        z.z
    ))
}

/// Writes [`export`]'s scene into `dir` (created if needed) as `scene.xml` and its meshes.
pub fn write(desc: &SceneDesc, dir: &Path, width: u32, height: u32, spp: u32) -> Result<(), String> {
    let scene = export(desc, width, height, spp)?;
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let put = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))
    };
    for (name, text) in &scene.meshes {
        put(name, text)?;
    }
    put("scene.xml", &scene.xml)
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_importers::ImportOptions;
    use quasar_importers::parse_toml_scene;

    fn desc(extra: &str) -> SceneDesc {
        let text = format!(
            r#"
[render]
masking = "separable"
[materials.white]
type = "diffuse"
reflectance = {{ wavelengths = [400, 700], values = [0.2, 0.8] }}
[materials.metal]
type = "conductor"
fresnel = 0.9
alpha = 0.2
two_sided = false
[[shape]]
type = "quad"
size = [1, 1]
material = "metal"
[[shape]]
type = "quad"
size = [0.1, 0.1]
center = [0, 0, 1]
normal = [0, 0, -1]
material = "white"
emission = {{ spectrum = {{ blackbody = 3000 }}, scale = 2 }}
{extra}
"#
        );
        parse_toml_scene(&text, Path::new("t.toml"), &ImportOptions::default()).unwrap()
    }

    #[test]
    fn conventions_are_written_explicitly() {
        let d = desc("[[light]]\ntype = \"spot\"\nposition = [0, 0, 2]\ndirection = [0, 0, -1]\ncone_deg = 30");
        assert_eq!(d.render.masking, quasar_materials::Masking::Separable);
        let s = export(&d, 8, 6, 16).unwrap();
        assert!(s.xml.contains("value=\"400:0.2, 700:0.8\""), "tables are written as their knots");
        assert!(
            s.xml.contains("<bsdf id=\"mat1\" type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/>")
        );
        assert!(s.xml.contains(
            "<string name=\"material\" value=\"none\"/><spectrum name=\"specular_reflectance\" value=\"0.9\"/>"
        ));
        assert!(s.xml.contains("<bsdf id=\"mat0\" type=\"twosided\"><bsdf type=\"diffuse\">"));
        assert!(s.xml.contains("<emitter type=\"area\"><spectrum name=\"radiance\" value=\"360:"));
        assert!(s.xml.contains("<float name=\"beam_width\" value=\"30\"/>"));
        assert_eq!(s.meshes.len(), 2);
        assert!(s.meshes[0].1.contains("f 1 2 3"));
    }

    /// An absorbing medium is written with an albedo of the number 0 (Mitsuba 3.9 refuses a
    /// spectrum that is 0 everywhere), a scattering one with its albedo spectrum and `hg` phase.
    #[test]
    fn media_are_homogeneous_with_albedo_and_phase() {
        let medium = |keys: &str| {
            let extra = format!(
                "[materials.g]\ntype = \"dielectric\"\nior = 1.5\n{keys}\n[[shape]]\ntype = \"sphere\"\nradius = 0.1\nmaterial = \"g\""
            );
            export(&desc(&extra), 8, 6, 1).unwrap().xml
        };
        let absorbing = medium("absorption = 2");
        assert!(
            absorbing.contains("<medium name=\"interior\" type=\"homogeneous\"><float name=\"albedo\" value=\"0\"/>")
        );
        assert!(absorbing.contains("<integrator type=\"volpath\">") && !absorbing.contains("<phase"));
        let scattering =
            medium("absorption = { wavelengths = [400, 700], values = [4, 1] }\nscattering = 10\nphase_g = 0.5");
        assert!(scattering.contains("<spectrum name=\"albedo\" value=\"360:"), "a spectral albedo");
        assert!(scattering.contains("<phase type=\"hg\"><float name=\"g\" value=\"0.5\"/></phase>"));
    }

    #[test]
    fn what_mitsuba_cannot_express_is_refused_by_name() {
        let soft = "[[light]]\ntype = \"spot\"\nposition = [0, 0, 2]\ndirection = [0, 0, -1]\ncone_deg = 30\nfalloff_start_deg = 20";
        assert!(export(&desc(soft), 8, 6, 1).unwrap_err().contains("soft edge"));
        let glass = "[materials.bk7]\ntype = \"dielectric\"\nior = \"BK7\"\n[[shape]]\ntype = \"sphere\"\nradius = 0.1\nmaterial = \"bk7\"";
        assert!(export(&desc(glass), 8, 6, 1).unwrap_err().contains("'bk7': a dispersive IOR"));
    }
}
