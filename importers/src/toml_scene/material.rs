//! `[materials.NAME]` tables: `type = "diffuse" | "conductor" | "dielectric" | "coated" | "sheen"`, or
//! `file = "x.toml"` for a tabulated BSDF (see `crate::bsdf_file`); a transmitting one (a
//! dielectric or a tabulated BSDF) may absorb inside (`absorption`, or `internal_transmittance`
//! at a `thickness`) and scatter (`scattering` with `phase_g`).

use quasar_materials::{Absorption, CoatAbsorption, Coating, ConductorFresnel, Ior, Material, Scattering};
use toml::de::DeValue;

use super::spectrum::{SpectrumUse, spectrum};
use crate::error::{ImportError, ImportErrorKind, did_you_mean};
use crate::toml_reader::{Doc, Tbl, Val, float, floats, string};

/// Material types of the TOML format.
pub const MATERIAL_TYPES: [&str; 5] = ["diffuse", "conductor", "dielectric", "coated", "sheen"];

/// Glass names that [`Ior::named`] knows (for suggestions in messages).
const GLASS_NAMES: [&str; 10] =
    ["BK7", "N-BK7", "fused-silica", "silica", "SiO2", "water", "acrylic", "PMMA", "polycarbonate", "PC"];
/// Material names that [`Absorption::named`] knows (for suggestions in messages).
const ABSORBER_NAMES: [&str; 6] = ["acrylic", "PMMA", "polycarbonate", "PC", "BK7", "N-BK7"];
/// Metal names that [`ConductorFresnel::named`] knows (for suggestions in messages).
const METAL_NAMES: [&str; 9] = ["Al", "aluminium", "aluminum", "Ag", "silver", "Au", "gold", "Cu", "copper"];

/// The catalogue entry (`lookup`) named by the string `v` at `what`; for a name it does not
/// know, an error at `v`: "`what`: {unknown} "name"; known: {names}{hint}" and a suggestion.
fn named<T>(
    doc: &Doc<'_>,
    v: &Val<'_>,
    what: &str,
    unknown: &str,
    (names, hint): (&[&str], &str),
    lookup: impl FnOnce(&str) -> Option<T>,
) -> Result<T, ImportError> {
    let name = string(doc, v, what)?;
    lookup(name).ok_or_else(|| {
        let (known, suggestion) = (names.join(", "), did_you_mean(name, names.iter().copied()));
        doc.invalid(&v.span(), format!("`{what}`: {unknown} \"{name}\"; known: {known}{hint}{suggestion}"))
    })
}

/// GGX alpha from `alpha` (used directly) or `roughness` (alpha = roughness^2); default 0 (smooth).
fn alpha(t: &Tbl<'_>) -> Result<f32, ImportError> {
    t.exclusive(&["alpha", "roughness"])?;
    if let Some(a) = t.opt_f32_where("alpha", ">= 0", |a| a >= 0.0)? {
        return Ok(a);
    }
    Ok(t.opt_f32_where("roughness", ">= 0", |r| r >= 0.0)?.map_or(0.0, |r| r * r))
}

/// Keys of a transmitting material's interior medium: its absorption and its scattering.
const ABSORPTION_KEYS: [&str; 5] = ["absorption", "internal_transmittance", "thickness", "scattering", "phase_g"];

/// The medium inside a transmitting material, as the scene file gives it.
#[derive(Default)]
pub(crate) struct Interior {
    /// `absorption` or `internal_transmittance` at `thickness`.
    pub absorption: Option<Absorption>,
    /// `scattering` (sigma_s, 1/m) with `phase_g`.
    pub scattering: Option<Scattering>,
}

/// The interior medium of a transmitting material: its absorption ([`absorption`]) and its
/// scattering, `scattering` (sigma_s in 1/m whatever the scene's units: a number or any
/// spectrum) with the Henyey-Greenstein asymmetry `phase_g` in [-1, 1] (0, isotropic, by
/// default; only with `scattering`).
fn interior(t: &Tbl<'_>, unit: f32) -> Result<Interior, ImportError> {
    let doc = t.doc;
    let absorption = absorption(t, unit)?;
    let g = t.opt_f32_where("phase_g", "in [-1, 1]", |g| (-1.0..=1.0).contains(&g))?;
    let scattering = match t.get("scattering") {
        Some(v) => {
            let s = Scattering {
                coefficient: spectrum(doc, v, &t.key_path("scattering"), SpectrumUse::Quantity)?,
                g: g.unwrap_or(0.0),
            };
            s.validate().map_err(|e| {
                doc.invalid(&t.span, format!("material `{}`: {e}", t.path.trim_start_matches("materials.")))
            })?;
            Some(s)
        }
        None if g.is_some() => {
            return Err(doc.invalid(
                &t.key_span("phase_g"),
                format!("`{}`: `phase_g` goes with `scattering` (the medium's sigma_s, 1/m)", t.path),
            ));
        }
        None => None,
    };
    Ok(Interior { absorption, scattering })
}

/// The interior absorption of a transmitting material: `absorption` (sigma_a in 1/m, whatever the
/// scene's units: a number, any spectrum, or a measured material's name, [`Absorption::named`]), or `internal_transmittance` (a spectrum in [0, 1])
/// at `thickness` (a length in the scene's units); None without either.
fn absorption(t: &Tbl<'_>, unit: f32) -> Result<Option<Absorption>, ImportError> {
    let doc = t.doc;
    t.exclusive(&["absorption", "internal_transmittance"])?;
    let a = if let Some(v) = t.get("absorption") {
        if t.has("thickness") {
            return Err(doc.invalid(
                &t.key_span("thickness"),
                format!("`{}`: `thickness` goes with `internal_transmittance`, not `absorption` (1/m)", t.path),
            ));
        }
        if let DeValue::String(_) = v.get_ref() {
            let hint = " (or give sigma_a in 1/m)";
            let what = t.key_path("absorption");
            named(doc, v, &what, "no measured absorption for", (&ABSORBER_NAMES, hint), Absorption::named)?
        } else {
            Absorption::Coefficient(spectrum(doc, v, &t.key_path("absorption"), SpectrumUse::Quantity)?)
        }
    } else if let Some(v) = t.get("internal_transmittance") {
        if !t.has("thickness") {
            return Err(doc.invalid(
                &v.span(),
                format!("`{}`: `internal_transmittance` needs the `thickness` it was measured at", t.path),
            ));
        }
        Absorption::Transmittance {
            transmittance: spectrum(doc, v, &t.key_path("internal_transmittance"), SpectrumUse::Reflectance)?,
            thickness: super::shape::positive_length(t, "thickness", unit)?,
        }
    } else {
        if t.has("thickness") {
            return Err(doc.invalid(
                &t.key_span("thickness"),
                format!("`{}`: `thickness` needs `internal_transmittance`", t.path),
            ));
        }
        return Ok(None);
    };
    a.validate()
        .map_err(|e| doc.invalid(&t.span, format!("material `{}`: {e}", t.path.trim_start_matches("materials."))))?;
    Ok(Some(a))
}

/// Reads the material table `v` named `name` with its interior medium (lengths in `unit`
/// metres); the material has passed [`Material::validate`].
pub(crate) fn material(t: &Tbl<'_>, unit: f32) -> Result<(Material, Interior), ImportError> {
    let doc = t.doc;
    if let Some(v) = t.get("file") {
        t.check_keys(&[&["file"][..], &ABSORPTION_KEYS].concat())?;
        let name = crate::toml_reader::string(doc, v, &t.key_path("file"))?;
        let path = doc.resolve(name);
        if !path.is_file() {
            return Err(doc.error(
                ImportErrorKind::MissingFile,
                &v.span(),
                format!("`{}`: tabulated BSDF file {} does not exist", t.key_path("file"), path.display()),
            ));
        }
        let table = crate::bsdf_file::load_tabulated_bsdf(&path).map_err(|e| e.included_from(doc.place(&v.span())))?;
        return Ok((Material::Tabulated(table), interior(t, unit)?));
    }
    let Some((ty, _)) = t.choice("type", &MATERIAL_TYPES)? else {
        return Err(
            doc.invalid(&t.span, format!("`{}`: missing key `type` (one of: {})", t.path, MATERIAL_TYPES.join(", ")))
        );
    };
    let m = match ty {
        "diffuse" => {
            t.check_keys(&["type", "reflectance", "two_sided"])?;
            let r = t.req("reflectance")?;
            Material::Diffuse {
                reflectance: spectrum(doc, r, &t.key_path("reflectance"), SpectrumUse::Reflectance)?,
                two_sided: t.opt_bool("two_sided")?.unwrap_or(true),
            }
        }
        "conductor" => {
            t.check_keys(&["type", "alpha", "roughness", "fresnel", "eta", "k", "metal", "two_sided"])?;
            t.exclusive(&["fresnel", "eta", "metal"])?;
            t.exclusive(&["fresnel", "k", "metal"])?;
            let fresnel = if let Some(v) = t.get("fresnel") {
                ConductorFresnel::Constant(spectrum(doc, v, &t.key_path("fresnel"), SpectrumUse::Reflectance)?)
            } else if let Some(v) = t.get("metal") {
                named(doc, v, &t.key_path("metal"), "unknown metal", (&METAL_NAMES, ""), ConductorFresnel::named)?
            } else if t.has("eta") || t.has("k") {
                let eta = t.req("eta")?;
                let k = t.req("k")?;
                ConductorFresnel::Complex {
                    eta: spectrum(doc, eta, &t.key_path("eta"), SpectrumUse::Quantity)?,
                    k: spectrum(doc, k, &t.key_path("k"), SpectrumUse::Quantity)?,
                }
            } else {
                return Err(doc.invalid(
                    &t.span,
                    format!("`{}`: a conductor needs `fresnel` (a reflectance), `eta` and `k`, or `metal`", t.path),
                ));
            };
            Material::Conductor { alpha: alpha(t)?, fresnel, two_sided: t.opt_bool("two_sided")?.unwrap_or(true) }
        }
        "coated" => coated(t, unit)?,
        "sheen" => {
            t.check_keys(&["type", "color", "alpha", "roughness", "base"])?;
            let color = spectrum(doc, t.req("color")?, &t.key_path("color"), SpectrumUse::Reflectance)?;
            Material::Sheen { color, alpha: alpha(t)?, base: Box::new(layer_base(t, unit, "sheen")?) }
        }
        _ => {
            t.check_keys(&[&["type", "ior", "alpha", "roughness", "transmittance"][..], &ABSORPTION_KEYS].concat())?;
            let v = t.req("ior")?;
            let transmittance = match t.get("transmittance") {
                Some(v) => Some(spectrum(doc, v, &t.key_path("transmittance"), SpectrumUse::Reflectance)?),
                None => None,
            };
            Material::Dielectric { ior: ior(t, v)?, alpha: alpha(t)?, transmittance }
        }
    };
    m.validate()
        .map_err(|e| doc.invalid(&t.span, format!("material `{}`: {e}", t.path.trim_start_matches("materials."))))?;
    let absorbs = if matches!(m, Material::Dielectric { .. }) { interior(t, unit)? } else { Interior::default() };
    Ok((m, absorbs))
}

/// `type = "coated"`: a coat of `ior` (a number, 1.5 by default), `alpha`/`roughness`, and
/// optionally `absorption` (1/m) over `thickness` (the coat's, in the scene's units) over the
/// `base` table (a diffuse or conductor material, or `file` = an opaque tabulated BSDF).
fn coated(t: &Tbl<'_>, unit: f32) -> Result<Material, ImportError> {
    let doc = t.doc;
    t.check_keys(&["type", "ior", "alpha", "roughness", "absorption", "thickness", "base", "two_sided"])?;
    let ior = t
        .opt_f32_where("ior", "a number in [1, 4]", |n| (1.0..=quasar_materials::coating::MAX_COAT_IOR).contains(&n))?
        .unwrap_or(1.5);
    let absorption = match t.get("absorption") {
        Some(v) => {
            let sigma_a = spectrum(doc, v, &t.key_path("absorption"), SpectrumUse::Quantity)?;
            if !t.has("thickness") {
                return Err(doc.invalid(&v.span(), format!("`{}`: `absorption` needs the coat's `thickness`", t.path)));
            }
            let thickness = super::shape::positive_length(t, "thickness", unit)?;
            Absorption::Coefficient(sigma_a.clone())
                .validate()
                .map_err(|e| doc.invalid(&v.span(), format!("`{}`: {e}", t.key_path("absorption"))))?;
            Some(CoatAbsorption::new(&sigma_a, thickness, ior))
        }
        None if t.has("thickness") => {
            return Err(
                doc.invalid(&t.key_span("thickness"), format!("`{}`: `thickness` goes with `absorption`", t.path))
            );
        }
        None => None,
    };
    Ok(Material::Coated {
        coating: Coating::new(ior, alpha(t)?, absorption),
        base: Box::new(layer_base(t, unit, "coat")?),
        two_sided: t.opt_bool("two_sided")?.unwrap_or(true),
    })
}

/// The `base` table of a layered material (a coat's or a sheen's, `what`): a diffuse or conductor
/// material, or an opaque tabulated BSDF (`file`).
fn layer_base(t: &Tbl<'_>, unit: f32, what: &str) -> Result<Material, ImportError> {
    let Some(b) = t.opt_table("base")? else {
        return Err(t.missing("base"));
    };
    if b.has("file") || b.opt_str("type")?.is_some_and(|ty| matches!(ty, "diffuse" | "conductor")) {
        return Ok(material(&b, unit)?.0);
    }
    Err(t.doc.invalid(
        &b.span,
        format!(
            "`{}`: a {what}'s base is a diffuse or conductor material, or an opaque tabulated BSDF (`file`)",
            b.path
        ),
    ))
}

/// `ior = 1.5 | "BK7" | { cauchy = [a, b] } | { sellmeier = { b = [...], c = [...] } }`.
fn ior(t: &Tbl<'_>, v: &Val<'_>) -> Result<Ior, ImportError> {
    let doc = t.doc;
    let what = t.key_path("ior");
    match v.get_ref() {
        DeValue::Integer(_) | DeValue::Float(_) => Ok(Ior::Constant(float(doc, v, &what)?)),
        DeValue::String(_) => named(doc, v, &what, "unknown optical material", (&GLASS_NAMES, ""), Ior::named),
        DeValue::Table(_) => {
            let it = Tbl::of(doc, v, what.clone())?;
            it.check_keys(&["cauchy", "sellmeier"])?;
            it.exclusive(&["cauchy", "sellmeier"])?;
            if let Some(c) = it.get("cauchy") {
                let [a, b] = floats::<2>(doc, c, &it.key_path("cauchy"))?;
                Ok(Ior::Cauchy { a, b })
            } else if let Some(s) = it.opt_table("sellmeier")? {
                s.check_keys(&["b", "c"])?;
                let b = floats::<3>(doc, s.req("b")?, &s.key_path("b"))?;
                let c = floats::<3>(doc, s.req("c")?, &s.key_path("c"))?;
                Ok(Ior::Sellmeier { b, c })
            } else {
                Err(doc.invalid(
                    &it.span,
                    format!("`{what}`: give `cauchy = [a, b]` or `sellmeier = {{ b = [...], c = [...] }}`"),
                ))
            }
        }
        other => Err(doc.invalid(
            &v.span(),
            format!(
                "`{what}` must be a number, a glass name or a dispersion table, got {}",
                crate::toml_reader::type_name(other)
            ),
        )),
    }
}
