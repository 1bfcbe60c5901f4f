//! The materials of a stage ([`Materials`]: each bound UsdShade material converted once, by
//! prim path) and the medium inside a material, which UsdPreviewSurface cannot express: quasar
//! reads it from documented attributes on the Material prim (docs/usd.md), in the units of the
//! TOML scene format's keys but with lengths always in metres (whatever `metersPerUnit`):
//!
//! | attribute | quasar |
//! |---|---|
//! | `float quasar:absorption` | sigma_a, 1/m (TOML `absorption`) |
//! | `color3f quasar:internalTransmittance`, `float quasar:thickness` | the internal transmittance (linear sRGB, uplifted) at a thickness in metres (TOML `internal_transmittance`, `thickness`) |
//! | `float quasar:scattering` | sigma_s, 1/m (TOML `scattering`) |
//! | `float quasar:phaseG` | Henyey-Greenstein g in [-1, 1] (TOML `phase_g`; 0 by default, only with `quasar:scattering`) |

use std::collections::HashMap;
use std::path::Path;

use openusd::sdf;
use openusd::usd::{Prim, Stage};
use quasar_materials::spectrum::Spectrum;
use quasar_materials::{Absorption, Scattering};

use super::value;
use super::{attr_err, err, material, texture};
use crate::error::{ImportError, ImportErrorKind};
use crate::scene_desc::{MaterialDesc, SourceLocation};

/// The stage's materials, by material prim path (named by the prim's name, made unique), and
/// the textures they read.
#[derive(Default)]
pub(super) struct Materials {
    by_path: HashMap<String, usize>,
    /// The materials, in the order first bound.
    pub descs: Vec<MaterialDesc>,
    /// The emission of each material's `emissiveColor`.
    pub emission: Vec<Option<crate::scene_desc::EmissionDesc>>,
    /// The images the materials read.
    pub textures: texture::TextureSet,
}

impl Materials {
    /// The index of the material at `path` (None: the fallback), converted on first use with
    /// its interior medium ([`interior`]).
    pub fn index(
        &mut self,
        stage: &Stage,
        file: &Path,
        path: Option<sdf::Path>,
        warnings: &mut Vec<String>,
    ) -> Result<usize, ImportError> {
        let key = path.as_ref().map_or_else(String::new, |p| p.as_str().to_string());
        if let Some(&i) = self.by_path.get(&key) {
            return Ok(i);
        }
        let c = match &path {
            Some(p) => material::convert(stage, p, file, &mut self.textures)?,
            None => material::Converted {
                material: material::fallback(),
                textures: Default::default(),
                emission: None,
                notes: Vec::new(),
            },
        };
        warnings.extend(c.notes.into_iter().map(|n| format!("{}: {n}", file.display())));
        let base = path.as_ref().and_then(|p| p.name().map(str::to_string)).unwrap_or_else(|| "usd-default".into());
        let name = crate::names::unique_name(&base, |n| self.descs.iter().any(|d| d.name == n));
        let (absorption, scattering) = match &path {
            Some(p) => interior(&stage.prim(p.clone()), file)?,
            None => (None, None),
        };
        self.descs.push(MaterialDesc {
            name,
            material: c.material,
            absorption,
            scattering,
            textures: c.textures,
            source: SourceLocation { file: file.to_owned(), line: None, item: Some(key.clone()) },
        });
        self.emission.push(c.emission);
        self.by_path.insert(key, self.descs.len() - 1);
        Ok(self.descs.len() - 1)
    }
}

impl Materials {
    /// The black two-sided diffuse material of the UsdLux area lights' meshes.
    pub fn light_material(&mut self, file: &Path) -> usize {
        self.descs.push(MaterialDesc {
            name: crate::names::unique_name("usd-light", |n| self.descs.iter().any(|d| d.name == n)),
            material: quasar_materials::Material::Diffuse {
                reflectance: quasar_materials::spectrum::Spectrum::Constant(0.0),
                two_sided: true,
            },
            absorption: None,
            scattering: None,
            textures: Default::default(),
            source: SourceLocation { file: file.to_owned(), line: None, item: None },
        });
        self.emission.push(None);
        self.descs.len() - 1
    }
}

/// The medium inside the material prim `prim` (module doc), checked like the TOML keys; an
/// invalid or contradictory value is an error naming the prim and the attribute.
fn interior(prim: &Prim, file: &Path) -> Result<(Option<Absorption>, Option<Scattering>), ImportError> {
    let at = prim.path().as_str().to_string();
    let number = |name: &str| value::scalar(prim, name).map_err(|e| attr_err(file, &at, e));
    let invalid = |msg: String| err(ImportErrorKind::InvalidValue, file, &at, msg);
    let coefficient = number("quasar:absorption")?;
    let transmittance = value::vec3(prim, "quasar:internalTransmittance").map_err(|e| attr_err(file, &at, e))?;
    let thickness = number("quasar:thickness")?;
    let absorption = match (coefficient, transmittance, thickness) {
        (None, None, None) => None,
        (Some(s), None, None) => Some(Absorption::Coefficient(Spectrum::Constant(s as f32))),
        (None, Some(t), Some(d)) => {
            let rgb = [t.x, t.y, t.z];
            let transmittance = Spectrum::rgb_reflectance(rgb).map_err(|e| {
                invalid(format!("attribute `quasar:internalTransmittance` = {rgb:?}: {e} (a colour in [0, 1])"))
            })?;
            Some(Absorption::Transmittance { transmittance, thickness: d as f32 })
        }
        (Some(_), _, _) => {
            return Err(invalid(
                "give `quasar:absorption` or `quasar:internalTransmittance` with `quasar:thickness`, not both".into(),
            ));
        }
        _ => {
            return Err(invalid("`quasar:internalTransmittance` and `quasar:thickness` go together".into()));
        }
    };
    if let Some(a) = &absorption {
        a.validate().map_err(invalid)?;
    }
    let g = number("quasar:phaseG")?;
    let scattering = match number("quasar:scattering")? {
        Some(s) => {
            let s = Scattering { coefficient: Spectrum::Constant(s as f32), g: g.unwrap_or(0.0) as f32 };
            s.validate().map_err(invalid)?;
            Some(s)
        }
        None if g.is_some() => return Err(invalid("`quasar:phaseG` goes with `quasar:scattering`".into())),
        None => None,
    };
    Ok((absorption, scattering))
}
