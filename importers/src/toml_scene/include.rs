//! `[[include]]` and `[[override]]`: other scene files (TOML, OBJ or any registered format)
//! placed into the scene with their units and a transform, their materials and textures merged
//! under unique names, and material overrides by glob.

use glam::{Affine3A, Vec3};

use super::{Builder, MAX_INCLUDE_DEPTH, import_at_depth, units};
use crate::error::{ImportError, ImportErrorKind};
use crate::glob::glob_match;
use crate::importer::ImportOptions;
use crate::names::unique_name;
use crate::obj::{ObjMaterials, import_obj};
use crate::scene_desc::{LightDesc, MaterialDesc, MeshDesc};
use crate::toml_reader::{Tbl, Val, string};
use crate::transform::{transform_camera, transform_light, transform_mesh};

impl<'a> Builder<'a> {
    /// Imports the file named by `t.file` (OBJ, TOML or any registered format) and places it:
    /// file units, then `xf`. Returns the meshes (with their source material names) and lights.
    #[allow(clippy::type_complexity)]
    pub(super) fn import_file(
        &mut self,
        t: &Tbl<'_>,
        material: Option<usize>,
        xf: Affine3A,
    ) -> Result<(Vec<(MeshDesc, String)>, Vec<LightDesc>), ImportError> {
        let doc = self.doc;
        let fv: &Val<'_> = t.req("file")?;
        let name = string(doc, fv, &t.key_path("file"))?;
        let path = doc.resolve(name);
        let here = doc.place(&fv.span());
        if !path.is_file() {
            return Err(doc.error(
                ImportErrorKind::MissingFile,
                &fv.span(),
                format!("`{}`: cannot find `{name}` (looked for {})", t.key_path("file"), path.display()),
            ));
        }
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let plain = ImportOptions { time_code: self.time_code, ..ImportOptions::default() };
        let sub = if ext == "toml" {
            if t.has("units") {
                return Err(doc.invalid(
                    &t.key_span("units"),
                    format!("`{}`: an included TOML scene declares its own `units`", t.path),
                ));
            }
            if self.depth >= MAX_INCLUDE_DEPTH {
                return Err(doc.error(
                    ImportErrorKind::TooLarge,
                    &fv.span(),
                    format!("TOML scenes nested more than {MAX_INCLUDE_DEPTH} deep (an include cycle?)"),
                ));
            }
            import_at_depth(&path, &plain, self.formats, self.depth + 1)
        } else if ext == "obj" {
            let mode = if material.is_some() { ObjMaterials::NamesOnly } else { ObjMaterials::FromMtl };
            import_obj(&path, &plain, mode)
        } else if let Some(imp) = self.formats.for_path(&path) {
            imp.import(&path, &plain, self.formats)
        } else {
            let exts: Vec<String> = self.formats.extensions().iter().map(|e| format!(".{e}")).collect();
            return Err(doc.error(
                ImportErrorKind::Unsupported,
                &fv.span(),
                format!("`{name}`: unsupported file type; supported: {}", exts.join(", ")),
            ));
        }
        .map_err(|e| e.included_from(here))?;
        // OBJ has no units: it uses the scene's unless `units` says otherwise.
        // Other formats (TOML, later glTF) are already in metres.
        let file_unit = match units(t, "units")? {
            Some(u) => u,
            None if ext == "obj" => self.scene_unit,
            None => 1.0,
        };
        let m = xf * Affine3A::from_scale(Vec3::splat(file_unit * self.extra));
        let file_name = path.file_name().map_or_else(|| name.to_owned(), |n| n.to_string_lossy().into_owned());
        let orig_names: Vec<String> = sub.materials.iter().map(|m| m.name.clone()).collect();
        let mut remap = Vec::with_capacity(sub.materials.len());
        let tex_base = self.textures.len();
        if material.is_none() {
            self.textures.extend(sub.textures);
        }
        for mut md in sub.materials {
            if material.is_some() {
                remap.push(usize::MAX);
                continue;
            }
            for r in md.textures.references_mut() {
                r.texture += tex_base;
            }
            let nm = unique_name(&format!("{file_name}:{}", md.name), |n| self.by_name.contains_key(n));
            remap.push(self.add_material(MaterialDesc { name: nm, ..md }));
        }
        for mut c in sub.cameras {
            transform_camera(&mut c.camera, &m);
            self.cameras.push(c);
        }
        self.warnings.extend(sub.warnings);
        let mut meshes = Vec::with_capacity(sub.meshes.len());
        for mut mesh in sub.meshes {
            let Some(orig) = orig_names.get(mesh.material).cloned() else {
                return Err(
                    doc.invalid(&fv.span(), format!("`{name}`: mesh `{}` refers to a missing material", mesh.name))
                );
            };
            mesh.material = material.unwrap_or(remap[mesh.material]);
            if let Some(e) = &mut mesh.emission {
                match (&mut e.texture, material) {
                    (Some(t), None) => t.texture.texture += tex_base,
                    // the file's textures were not added: its mean colour remains
                    (Some(_), Some(_)) => e.texture = None,
                    (None, _) => {}
                }
            }
            transform_mesh(&mut mesh, &m);
            meshes.push((mesh, orig));
        }
        let mut lights = sub.lights;
        for l in &mut lights {
            transform_light(l, &m);
        }
        Ok((meshes, lights))
    }

    pub(super) fn include(&mut self, t: &Tbl<'a>) -> Result<(), ImportError> {
        t.check_keys(&["file", "transform", "units", "material"])?;
        let xf = self.transform(t)?;
        let material = self.material_ref(t, "material")?;
        let (meshes, lights) = self.import_file(t, material, xf)?;
        self.reserve_triangles(t, meshes.iter().map(|(m, _)| m.indices.len() as u64).sum())?;
        for (m, orig) in meshes {
            self.push_mesh(t, m, orig)?;
        }
        self.lights.extend(lights);
        Ok(())
    }

    /// `[[override]]`: gives every mesh whose name, source material name or material name
    /// matches the glob `match` the material `material` and/or the area emission `emission`
    /// (a measured lamp spectrum on an imported model's emitter).
    pub(super) fn override_(&mut self, t: &Tbl<'_>) -> Result<(), ImportError> {
        t.check_keys(&["match", "material", "emission"])?;
        let pattern = t.opt_str("match")?.ok_or_else(|| t.missing("match"))?;
        let material = self.material_ref(t, "material")?;
        let emission = match t.opt_table("emission")? {
            Some(e) => Some(super::shape::emission(&e)?),
            None => None,
        };
        if material.is_none() && emission.is_none() {
            return Err(t.missing("material"));
        }
        let mut hits = 0usize;
        for (m, orig) in self.meshes.iter_mut().zip(&self.orig_material) {
            let current = &self.materials[m.material].name;
            if glob_match(pattern, &m.name) || glob_match(pattern, orig) || glob_match(pattern, current) {
                if let Some(material) = material {
                    m.material = material;
                }
                if let Some(e) = &emission {
                    m.emission = Some(e.clone());
                }
                hits += 1;
            }
        }
        if hits == 0 {
            let mut names: Vec<&str> = self.meshes.iter().map(|m| m.name.as_str()).take(8).collect();
            if self.meshes.len() > 8 {
                names.push("...");
            }
            return Err(self.doc.error(
                ImportErrorKind::UnresolvedReference,
                &t.key_span("match"),
                format!("override `{pattern}` matches no mesh or material name (meshes: {})", names.join(", ")),
            ));
        }
        Ok(())
    }
}
