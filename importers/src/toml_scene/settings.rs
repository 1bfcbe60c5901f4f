//! `[render]`, `[camera]` and `[[light]]`.

use quasar_materials::spectrum::Spectrum;

use super::LIGHT_TYPES;
use super::spectrum::{self, SpectrumUse};
use crate::error::ImportError;
use crate::scene_desc::{CameraDesc, FovAxis, LightDesc, ParamValue, RenderParam, RenderSettings};
use crate::toml_reader::{Tbl, number};

/// A key of the `[render]` table that the importer reads itself (the others are the methods'
/// parameters, documented by the renderer's method table).
#[derive(Clone, Copy, Debug)]
pub struct RenderKey {
    /// The key.
    pub key: &'static str,
    /// What it takes.
    pub value: &'static str,
    /// Its default.
    pub default: &'static str,
}

/// The `[render]` keys read here, in the documentation's order (docs/scene-format.md's table is
/// generated from it and the method table).
pub const RENDER_KEYS: [RenderKey; 11] = [
    RenderKey { key: "width", value: "image width in pixels, integer 1..=65536", default: "640" },
    RenderKey { key: "height", value: "image height in pixels, integer 1..=65536", default: "480" },
    RenderKey { key: "spp", value: "samples per pixel, integer >= 1", default: "64" },
    RenderKey { key: "time", value: "time budget in seconds (> 0); overrides `spp`", default: "unset" },
    RenderKey { key: "seed", value: "seed of the random streams, integer 0..=2^64-1", default: "0" },
    RenderKey {
        key: "method",
        value: "`\"auto\"` or a method of the method table (README: `--method`)",
        default: "`\"auto\"`",
    },
    RenderKey {
        key: "target_error",
        value: "stop when the image's estimated RMS relative error is at most this (> 0)",
        default: "unset",
    },
    RenderKey {
        key: "masking",
        value: "microfacet masking-shadowing of every GGX material: `\"height-correlated\"` or `\"separable\"`",
        default: "`\"height-correlated\"`",
    },
    RenderKey {
        key: "illuminance_samples",
        value: "samples per pixel of the `illuminance.Y` layer (lux at the first surface the pixel's camera rays hit, with its standard errors in `illuminance_stderr.Y`, [photometry.md](photometry.md)); 0: no layer",
        default: "0",
    },
    RenderKey {
        key: "aovs",
        value: "auxiliary outputs, an array of names of the README's channel table (`[\"normal\", \"albedo\", \"crypto_object\"]`; `--aov`)",
        default: "`[]`",
    },
    RenderKey { key: "aov_samples", value: "rays per pixel of the auxiliary outputs, 1..=65536", default: "16" },
];

/// Reads the `[render]` table (defaults when absent). The image, budget and seed keys are read
/// here; every other key is a method parameter, kept with its place for the renderer's method
/// table to validate (`unit` converts its lengths).
pub(super) fn render(t: Option<Tbl<'_>>, unit: f32) -> Result<RenderSettings, ImportError> {
    let mut r = RenderSettings { unit, ..RenderSettings::default() };
    let Some(t) = t else { return Ok(r) };
    for (k, v) in t.entries() {
        let key: &str = k.get_ref();
        if RENDER_KEYS.iter().any(|r| r.key == key) {
            continue;
        }
        let value = match v.get_ref() {
            toml::de::DeValue::Integer(i) => {
                let s = i.as_str();
                let n = i128::from_str_radix(s.trim_start_matches('+').replace('_', "").as_str(), i.radix())
                    .map_err(|_| t.doc.invalid(&v.span(), format!("`render.{key}`: {s} is not an integer")))?;
                ParamValue::Int(n)
            }
            toml::de::DeValue::Float(_) => ParamValue::Float(number(t.doc, v, &t.key_path(key))?),
            toml::de::DeValue::Boolean(b) => ParamValue::Bool(*b),
            toml::de::DeValue::String(s) => ParamValue::Str(s.to_string()),
            _ => {
                return Err(t.doc.invalid(&v.span(), format!("`render.{key}` must be a number, boolean or string")));
            }
        };
        r.params.push(RenderParam { key: key.to_string(), value, place: t.doc.place(&k.span()) });
    }
    r.target_error = t.opt_f32_where("target_error", "> 0", |e| e > 0.0)?.map(f64::from);
    if let Some(w) = t.opt_int("width", 1, 65536)? {
        r.width = w;
    }
    if let Some(h) = t.opt_int("height", 1, 65536)? {
        r.height = h;
    }
    if let Some(s) = t.opt_int("spp", 1, u32::MAX as i128)? {
        r.spp = s;
    }
    if let Some(v) = t.get("time") {
        let s = number(t.doc, v, &t.key_path("time"))?;
        if s <= 0.0 {
            return Err(t.doc.invalid(&v.span(), format!("`render.time` must be > 0 seconds, got {s}")));
        }
        r.time_s = Some(s);
    }
    if let Some(s) = t.opt_int("seed", 0, u64::MAX as i128)? {
        r.seed = s;
    }
    if let Some(v) = t.get("method") {
        r.method = crate::toml_reader::string(t.doc, v, &t.key_path("method"))?.to_owned();
        r.method_place = Some(t.doc.place(&v.span()));
    }
    if let Some(n) = t.opt_int("illuminance_samples", 0, 1 << 20)? {
        r.illuminance_samples = n;
    }
    if let Some(v) = t.get("aovs") {
        let what = t.key_path("aovs");
        let toml::de::DeValue::Array(a) = v.get_ref() else {
            return Err(t.doc.invalid(&v.span(), format!("`{what}` must be an array of output names")));
        };
        r.aovs = a
            .iter()
            .enumerate()
            .map(|(i, x)| crate::toml_reader::string(t.doc, x, &format!("{what}[{i}]")).map(str::to_owned))
            .collect::<Result<_, _>>()?;
        r.aovs_place = Some(t.doc.place(&v.span()));
    }
    if let Some(n) = t.opt_int("aov_samples", 1, 1 << 16)? {
        r.aov_samples = n;
    }
    if let Some((m, _)) = t.choice("masking", &quasar_materials::Masking::NAMES)? {
        r.masking = quasar_materials::Masking::from_name(m).unwrap_or_default();
    }
    Ok(r)
}

/// Reads a `[[light]]` table; positions are converted with `unit` (metres per scene unit).
pub(super) fn light(t: &Tbl<'_>, unit: f32) -> Result<LightDesc, ImportError> {
    let doc = t.doc;
    let Some((ty, _)) = t.choice("type", &LIGHT_TYPES)? else {
        return Err(
            doc.invalid(&t.span, format!("`{}`: missing key `type` (one of: {})", t.path, LIGHT_TYPES.join(", ")))
        );
    };
    let own: &[&str] = match ty {
        "point" => &["position"],
        "spot" => &["position", "target", "direction", "cone_deg", "falloff_start_deg"],
        "directional" => &["direction"],
        "luminaire" => &super::luminaire::LUMINAIRE_KEYS,
        _ => &["file", "rotate_deg"],
    };
    t.check_keys(&[&["type", "spectrum", "scale"][..], own].concat())?;
    let given = match t.get("spectrum") {
        Some(v) => Some(spectrum::spectrum(doc, v, &t.key_path("spectrum"), SpectrumUse::Emission)?),
        None => None,
    };
    let scale = t.opt_f32_where("scale", "finite and >= 0", |s| s >= 0.0)?.unwrap_or(1.0);
    if ty == "luminaire" {
        return super::luminaire::luminaire(t, unit, given, scale);
    }
    let spectrum = given.unwrap_or(Spectrum::Constant(1.0));
    let light = match ty {
        "point" => {
            let position = t.opt_point("position", unit)?.ok_or_else(|| t.missing("position"))?;
            LightDesc::Point { position, spectrum, scale }
        }
        "spot" => {
            let position = t.opt_point("position", unit)?.ok_or_else(|| t.missing("position"))?;
            t.exclusive(&["target", "direction"])?;
            let direction = if let Some(target) = t.opt_point("target", unit)? {
                let d = target - position;
                if !d.is_finite() || d.length_squared() <= 0.0 {
                    return Err(
                        doc.invalid(&t.key_span("target"), format!("`{}`: target must differ from position", t.path))
                    );
                }
                d
            } else {
                t.opt_dir("direction")?
                    .ok_or_else(|| doc.invalid(&t.span, format!("`{}`: give `target` or `direction`", t.path)))?
            };
            let cone = t.opt_f32_where("cone_deg", "in (0, 180]", |c| c > 0.0 && c <= 180.0)?;
            let cone = cone.ok_or_else(|| t.missing("cone_deg"))?;
            let start = t
                .opt_f32_where("falloff_start_deg", &format!("in [0, cone_deg = {cone}]"), |s| {
                    (0.0..=cone).contains(&s)
                })?
                .unwrap_or(cone);
            LightDesc::Spot { position, direction, cone_deg: cone, falloff_start_deg: start, spectrum, scale }
        }
        "directional" => {
            let direction = t.opt_dir("direction")?.ok_or_else(|| t.missing("direction"))?;
            LightDesc::Directional { direction, spectrum, scale }
        }
        _ => {
            let map = match t.get("file") {
                None => None,
                Some(v) => {
                    if t.get("spectrum").is_some() {
                        return Err(doc.invalid(
                            &t.key_span("spectrum"),
                            format!("`{}`: a map gives the colour: `spectrum` and `file` exclude each other", t.path),
                        ));
                    }
                    let what = t.key_path("file");
                    let name = crate::toml_reader::string(doc, v, &what)?;
                    let path = doc.resolve(name);
                    let mut m =
                        crate::env_map::load_env_map(&path).map_err(|e| e.included_from(doc.place(&v.span())))?;
                    let deg = t.opt_f32_where("rotate_deg", "finite", |r| r.is_finite())?.unwrap_or(0.0);
                    m.frame = glam::Mat3::from_rotation_y(deg.to_radians());
                    Some(std::sync::Arc::new(m))
                }
            };
            if map.is_none() && t.get("rotate_deg").is_some() {
                return Err(
                    doc.invalid(&t.key_span("rotate_deg"), format!("`{}`: `rotate_deg` needs a map `file`", t.path))
                );
            }
            LightDesc::Environment { spectrum, scale, map }
        }
    };
    Ok(light)
}

/// Reads the `[camera]` table (defaults when absent); lengths are converted with `unit`.
pub(super) fn camera(t: Option<Tbl<'_>>, unit: f32) -> Result<CameraDesc, ImportError> {
    let d = CameraDesc::default();
    let Some(t) = t else {
        return Ok(CameraDesc { position: d.position * unit, target: d.target * unit, ..d });
    };
    t.check_keys(&["position", "target", "up", "fov_deg", "fov_axis"])?;
    let position = t.opt_point("position", unit)?.unwrap_or(d.position * unit);
    let target = t.opt_point("target", unit)?.unwrap_or(d.target * unit);
    let up = t.opt_dir("up")?.unwrap_or(d.up);
    let fov_deg = t.opt_f32_where("fov_deg", "in (0, 180) degrees", |f| f > 0.0 && f < 180.0)?.unwrap_or(d.fov_deg);
    let fov_axis = match t.choice("fov_axis", &["x", "y"])? {
        Some(("x", _)) => FovAxis::X,
        Some(_) => FovAxis::Y,
        None => d.fov_axis,
    };
    let view = target - position;
    if !view.is_finite() || view.length_squared() <= 0.0 {
        let at = if t.has("target") { t.key_span("target") } else { t.span.clone() };
        return Err(t.doc.invalid(&at, "camera `target` must differ from `position` (and be at a finite distance)"));
    }
    if view.normalize().cross(up.normalize()).length() < 1e-4 {
        let at = if t.has("up") { t.key_span("up") } else { t.span.clone() };
        return Err(t
            .doc
            .invalid(&at, format!("camera `up` = {up} is parallel to the view direction {}", view.normalize())));
    }
    Ok(CameraDesc { position, target, up, fov_deg, fov_axis })
}
