//! `[[light]] type = "luminaire"`: a luminaire from an IES (`.ies`) or EULUMDAT (`.ldt`) file,
//! at a point or with a luminous opening (docs/photometry.md).
//!
//! | key | meaning | default |
//! |---|---|---|
//! | `file` | the photometric file, relative to the scene | required |
//! | `position` | photometric centre (scene units) | required |
//! | `target` / `direction` | where the nadir (gamma 0) points | straight down |
//! | `roll_deg` | turn about the aim, counter-clockwise seen from behind | 0 |
//! | `spectrum` | spectral shape, scaled to luminance 1 | D65 white |
//! | `scale` | factor on the file's candela (e.g. a dimming level or lumen maintenance) | 1 |
//! | `opening` | the luminous opening for the near field: `{ size = [c0, c90] }` (a rectangle, sides along C0 and C90, scene units) or `{ diameter = d }` (a disk), in the C0/C90 plane through the photometric centre | a point |
//!
//! The candela come out in cd: radiant intensity = candela x `scale` x tilt factor x
//! spectrum / (683 lm/W x integral of ybar) per unit of the luminance-1 spectrum. An IES tilt
//! table is read at the angle between the aim and straight down.

use std::sync::Arc;

use glam::Vec3;
use quasar_materials::spectrum::Spectrum;

use crate::error::ImportError;
use crate::photometric::photometric_scale;
use crate::photometry::{aim_frame, read_photometric_file};
use crate::scene_desc::{LightDesc, LuminousOpening};
use crate::toml_reader::Tbl;

/// The keys of a luminaire besides `type`, `spectrum` and `scale`.
pub(super) const LUMINAIRE_KEYS: [&str; 6] = ["file", "position", "target", "direction", "roll_deg", "opening"];

/// Reads a luminaire `[[light]]` table whose `spectrum` (None: not given) and `scale` are read.
pub(super) fn luminaire(
    t: &Tbl<'_>,
    unit: f32,
    spectrum: Option<Spectrum>,
    scale: f32,
) -> Result<LightDesc, ImportError> {
    let doc = t.doc;
    let v = t.get("file").ok_or_else(|| t.missing("file"))?;
    let name = crate::toml_reader::string(doc, v, &t.key_path("file"))?;
    let (web, tilt) = read_photometric_file(&doc.resolve(name)).map_err(|e| e.included_from(doc.place(&v.span())))?;
    let position = t.opt_point("position", unit)?.ok_or_else(|| t.missing("position"))?;
    t.exclusive(&["target", "direction"])?;
    let aim = if let Some(target) = t.opt_point("target", unit)? {
        let d = target - position;
        if !d.is_finite() || d.length_squared() <= 0.0 {
            return Err(doc.invalid(&t.key_span("target"), format!("`{}`: target must differ from position", t.path)));
        }
        d
    } else {
        t.opt_dir("direction")?.unwrap_or(Vec3::NEG_Y)
    };
    let roll = t.opt_f32_where("roll_deg", "finite", f32::is_finite)?.unwrap_or(0.0);
    let spectrum = match spectrum {
        Some(s) => s,
        None => Spectrum::rgb_illuminant([1.0; 3]).expect("white is a valid light colour"),
    };
    let y = spectrum.luminance();
    if !(y.is_finite() && y > 0.0) {
        let at = t.key_span("spectrum");
        return Err(doc.invalid(&at, format!("`{}`: the spectrum has no luminance to scale candela by", t.path)));
    }
    let opening = match t.opt_table("opening")? {
        None => LuminousOpening::Point,
        Some(o) => opening(&o, unit)?,
    };
    let aim = aim.normalize();
    let tilt_deg = aim.dot(Vec3::NEG_Y).clamp(-1.0, 1.0).acos().to_degrees();
    let tilt_factor = tilt.as_ref().map_or(1.0, |t| t.factor(tilt_deg));
    Ok(LightDesc::Luminaire {
        position,
        frame: aim_frame(aim, roll),
        web: Arc::new(web),
        spectrum,
        scale: photometric_scale(1.0) * scale * tilt_factor / y,
        opening,
    })
}

/// Reads an `opening` table: exactly one of `size = [c0, c90]` and `diameter = d`, positive
/// lengths in scene units converted with `unit`.
fn opening(o: &Tbl<'_>, unit: f32) -> Result<LuminousOpening, ImportError> {
    let doc = o.doc;
    o.check_keys(&["size", "diameter"])?;
    o.exclusive(&["size", "diameter"])?;
    let positive = |v: f32| v.is_finite() && v > 0.0;
    if let Some(d) = o.opt_f32_where("diameter", "a positive length", positive)? {
        return Ok(LuminousOpening::Disk { diameter: d * unit });
    }
    let Some(v) = o.get("size") else {
        return Err(doc.invalid(&o.span, format!("`{}`: give `size = [c0, c90]` or `diameter = d`", o.path)));
    };
    let [a, b] = crate::toml_reader::floats::<2>(doc, v, &o.key_path("size"))?;
    if !(positive(a) && positive(b)) {
        return Err(doc.invalid(&o.key_span("size"), format!("`{}`: the sides must be positive lengths", o.path)));
    }
    Ok(LuminousOpening::Rect { c0: a * unit, c90: b * unit })
}
