//! `[render]`, `[camera]` and `[[light]]`.

use quasar_materials::spectrum::Spectrum;

use super::reader::{Tbl, number};
use super::spectrum::{self, SpectrumUse};
use super::{LIGHT_TYPES, RENDER_METHODS};
use crate::error::ImportError;
use crate::scene_desc::{CameraDesc, FovAxis, LightDesc, RenderSettings};

/// Reads the `[render]` table (defaults when absent); lengths (`radius`) are converted with `unit`.
pub(super) fn render(t: Option<Tbl<'_>>, unit: f32) -> Result<RenderSettings, ImportError> {
    let mut r = RenderSettings::default();
    let Some(t) = t else { return Ok(r) };
    t.check_keys(&[
        "width",
        "height",
        "spp",
        "time",
        "seed",
        "max_depth",
        "method",
        "target_error",
        "iterations",
        "photons_per_iteration",
        "gather_depth",
        "max_gather_depth",
        "cone_deg",
        "radius",
        "alpha",
        "masking",
    ])?;
    let b = &mut r.bidirectional;
    b.iterations = t.opt_int("iterations", 1, u32::MAX as i128)?;
    b.photons_per_iteration = t.opt_int("photons_per_iteration", 1, 1i128 << 32)?;
    b.gather_depth = t.opt_int("gather_depth", 0, 64)?;
    b.max_gather_depth = t.opt_int("max_gather_depth", 0, 7)?;
    b.cone_deg = t.opt_f32_where("cone_deg", "in (0, 90) degrees", |c| c > 0.0 && c < 90.0)?;
    b.radius = t.opt_f32_where("radius", "> 0", |x| x > 0.0)?.map(|x| x * unit);
    if b.radius.is_some_and(|x| !(x.is_finite() && x > 0.0)) {
        return Err(t.doc.invalid(&t.key_span("radius"), "`render.radius` is out of range in metres"));
    }
    b.alpha = t.opt_f32_where("alpha", "in (0, 1)", |a| a > 0.0 && a < 1.0)?;
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
    r.max_depth = t.opt_int("max_depth", 0, 1_000_000)?;
    if let Some((m, _)) = t.choice("method", &RENDER_METHODS)? {
        r.method = m.to_owned();
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
        _ => &["file", "rotate_deg"],
    };
    t.check_keys(&[&["type", "spectrum", "scale"][..], own].concat())?;
    let spectrum = match t.get("spectrum") {
        Some(v) => spectrum::spectrum(doc, v, &t.key_path("spectrum"), SpectrumUse::Emission)?,
        None => Spectrum::Constant(1.0),
    };
    let scale = t.opt_f32_where("scale", "finite and >= 0", |s| s >= 0.0)?.unwrap_or(1.0);
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
                    let name = super::reader::string(doc, v, &what)?;
                    let path = doc.resolve(name);
                    let mut m =
                        crate::env_map::load_env_map(&path).map_err(|e| e.included_from(doc.place(&v.span())))?;
                    m.rotate_deg = t.opt_f32_where("rotate_deg", "finite", |r| r.is_finite())?.unwrap_or(0.0);
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
