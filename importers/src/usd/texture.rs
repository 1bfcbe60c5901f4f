//! `UsdUVTexture` shaders feeding UsdPreviewSurface inputs -> quasar textures (decoded by
//! [`crate::texture_decode`], evaluated by the renderer's texture code like glTF's):
//!
//! | UsdUVTexture input (default) | quasar |
//! |---|---|
//! | `file` (asset, resolved against the layer that authored it, also through a Material interface input) | the PNG/JPEG image, also an entry of the `.usdz` package the stage is in (`pkg.usdz[tex/a.png]`) |
//! | output `rgb` / `r` / `g` / `b` / `a` | the channel(s) the input reads |
//! | `wrapS` / `wrapT` (`useMetadata`) | `repeat` (also for `useMetadata`), `mirror`, `clamp`; `black` is clamped (warning) |
//! | `scale` (1, 1, 1, 1) | multiplies the texel: the factor of the quasar texture |
//! | `bias` (0, 0, 0, 0) | normal maps: the standard (2, -1) encoding expected; elsewhere ignored (warning) |
//! | `sourceColorSpace` (`auto`) | colour inputs are sRGB-decoded (`raw` on a colour: warning), scalar channels linear |
//! | `st` from `UsdPrimvarReader_float2`, optionally through `UsdTransform2d` (`scale`, `rotation`, `translation`) | the mesh's `primvars:st` with the 2-D transform (another `varname`: warning, `st` used) |

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use openusd::sdf;
use openusd::usd::{Prim, Stage};

use super::value;
use crate::asset::{file_name, read_asset};
use crate::error::{ErrorPlace, ImportError};
use crate::scene_desc::SourceLocation;
use crate::texture_decode::{MAX_TEXTURE_ALLOC, decode_image};
use crate::texture_desc::{TextureDesc, TextureRef, TextureWrap};

/// Connection hops followed from an input to its texture (through Material / NodeGraph
/// interface attributes).
const MAX_HOPS: usize = 8;

/// One `UsdUVTexture` feeding a surface input.
pub(super) struct UvTexture {
    /// The texture shader's prim path, for messages.
    pub at: String,
    /// The image file.
    pub file: PathBuf,
    /// The output the input reads: 0..=3 for `r`, `g`, `b`, `a`; None for `rgb`.
    pub channel: Option<usize>,
    /// Wrap along s and t.
    pub wrap: (TextureWrap, TextureWrap),
    /// `inputs:scale`.
    pub scale: [f32; 4],
    /// `inputs:bias`.
    pub bias: [f32; 4],
    /// The st transform in quasar's texture coordinates (v down).
    pub transform: [[f32; 3]; 2],
    /// `sourceColorSpace = "raw"`.
    pub raw: bool,
}

/// The prim and attribute an attribute's first connection points to.
fn source(stage: &Stage, prim: &Prim, attr: &str) -> Option<(Prim, String)> {
    let src = prim.attribute(attr).connections().ok()?.into_iter().next()?;
    let (p, prop) = src.split_property()?;
    Some((stage.prim(p), prop.to_string()))
}

fn shader_id(prim: &Prim) -> Option<String> {
    value::token(prim, "info:id").ok().flatten()
}

fn float4(prim: &Prim, name: &str, default: f32) -> [f32; 4] {
    match value::raw(prim, name).ok().flatten() {
        Some(sdf::Value::Vec4f(v)) => [v[0], v[1], v[2], v[3]],
        Some(sdf::Value::Vec4d(v)) => [v[0] as f32, v[1] as f32, v[2] as f32, v[3] as f32],
        _ => [default; 4],
    }
}

fn float2(prim: &Prim, name: &str, default: f32) -> [f32; 2] {
    match value::raw(prim, name).ok().flatten() {
        Some(sdf::Value::Vec2f(v)) => [v[0], v[1]],
        Some(sdf::Value::Vec2d(v)) => [v[0] as f32, v[1] as f32],
        _ => [default; 2],
    }
}

fn wrap(prim: &Prim, name: &str, notes: &mut Vec<String>, at: &str) -> TextureWrap {
    match value::token(prim, name).ok().flatten().as_deref() {
        Some("mirror") => TextureWrap::MirroredRepeat,
        Some("clamp") => TextureWrap::ClampToEdge,
        Some("black") => {
            notes.push(format!("{at}: {name} `black` is rendered as `clamp`"));
            TextureWrap::ClampToEdge
        }
        _ => TextureWrap::Repeat,
    }
}

/// The file of the texture shader `tex`: its `inputs:file` asset (or what it connects to),
/// resolved against the authoring layer; relative paths unresolved by the crate are taken
/// relative to the stage's file.
fn file(stage: &Stage, tex: &Prim, stage_file: &Path) -> Option<PathBuf> {
    let (mut prim, mut attr) = (tex.clone(), "inputs:file".to_string());
    for _ in 0..MAX_HOPS {
        if let Some((p, a)) = source(stage, &prim, &attr) {
            (prim, attr) = (p, a);
            continue;
        }
        return match value::raw(&prim, &attr).ok().flatten()? {
            sdf::Value::AssetPath(a) => Some(value::asset_file(&a, stage_file)),
            sdf::Value::String(s) => Some(stage_file.parent().unwrap_or(Path::new(".")).join(s)),
            _ => None,
        };
    }
    None
}

/// The 2-D transform of an `st` input in quasar's coordinates: USD's st' = T R S st (rotation in
/// degrees, counter-clockwise) conjugated by the v flip (u, v) -> (u, 1 - v).
fn st_transform(stage: &Stage, tex: &Prim, notes: &mut Vec<String>, at: &str) -> [[f32; 3]; 2] {
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let Some((mut reader, _)) = source(stage, tex, "inputs:st") else {
        return identity;
    };
    let mut m = identity;
    if shader_id(&reader).as_deref() == Some("UsdTransform2d") {
        let s = float2(&reader, "inputs:scale", 1.0);
        let t = float2(&reader, "inputs:translation", 0.0);
        let r = value::scalar(&reader, "inputs:rotation").ok().flatten().unwrap_or(0.0) as f32;
        let (sin, cos) = r.to_radians().sin_cos();
        let (a, b, c) = (cos * s[0], -sin * s[1], t[0]);
        let (d, e, f) = (sin * s[0], cos * s[1], t[1]);
        m = [[a, -b, b + c], [-d, e, 1.0 - e - f]];
        match source(stage, &reader, "inputs:in") {
            Some((r, _)) => reader = r,
            None => return m,
        }
    }
    if shader_id(&reader).as_deref().is_some_and(|id| id.starts_with("UsdPrimvarReader")) {
        let var = value::token(&reader, "inputs:varname").ok().flatten().unwrap_or_else(|| "st".into());
        if var != "st" {
            notes.push(format!("{at}: texture coordinates `{var}` are not read; primvars:st is used"));
        }
    }
    m
}

/// The `UsdUVTexture` feeding `shader`'s input `input` (through interface connections), with
/// notes for warnings; None when the input is not textured.
pub(super) fn find(
    stage: &Stage,
    shader: &Prim,
    input: &str,
    stage_file: &Path,
    notes: &mut Vec<String>,
) -> Option<UvTexture> {
    let (mut prim, mut attr) = (shader.clone(), format!("inputs:{input}"));
    for _ in 0..MAX_HOPS {
        let (p, a) = source(stage, &prim, &attr)?;
        if shader_id(&p).as_deref() == Some("UsdUVTexture") {
            let at = p.path().as_str().to_string();
            let channel = match a.strip_prefix("outputs:") {
                Some("r") => Some(0),
                Some("g") => Some(1),
                Some("b") => Some(2),
                Some("a") => Some(3),
                _ => None,
            };
            let Some(file) = file(stage, &p, stage_file) else {
                notes.push(format!("{at}: inputs:file is not set; the input's value is used"));
                return None;
            };
            let wrap = (wrap(&p, "inputs:wrapS", notes, &at), wrap(&p, "inputs:wrapT", notes, &at));
            let raw = value::token(&p, "inputs:sourceColorSpace").ok().flatten().as_deref() == Some("raw");
            let transform = st_transform(stage, &p, notes, &at);
            return Some(UvTexture {
                file,
                channel,
                wrap,
                scale: float4(&p, "inputs:scale", 1.0),
                bias: float4(&p, "inputs:bias", 0.0),
                transform,
                raw,
                at,
            });
        }
        (prim, attr) = (p, a);
    }
    None
}

/// The decoded images of one stage, each file and wrap mode decoded once.
#[derive(Default)]
pub(super) struct TextureSet {
    /// The textures, indexed by [`TextureRef::texture`].
    pub descs: Vec<TextureDesc>,
    by_key: HashMap<String, usize>,
}

impl TextureSet {
    fn decoded(&mut self, t: &UvTexture, stage_file: &Path) -> Result<usize, ImportError> {
        let key = format!("{}|{:?}", t.file.display(), t.wrap);
        if let Some(&i) = self.by_key.get(&key) {
            return Ok(i);
        }
        let place = format!("prim <{}>: inputs:file `{}`", t.at, t.file.display());
        let fail = |kind, msg: String| ImportError::new(kind, ErrorPlace::file(stage_file), format!("{place}: {msg}"));
        let bytes = read_asset(&t.file, MAX_TEXTURE_ALLOC).map_err(|(kind, msg)| fail(kind, msg))?;
        let (width, height, texels) = decode_image(&bytes, stage_file, &place)?;
        self.descs.push(TextureDesc {
            name: file_name(&t.file).unwrap_or_else(|| t.at.clone()),
            width,
            height,
            texels,
            wrap_u: t.wrap.0,
            wrap_v: t.wrap.1,
            nearest: false,
            source: SourceLocation { file: stage_file.to_owned(), line: None, item: Some(t.at.clone()) },
        });
        self.by_key.insert(key, self.descs.len() - 1);
        Ok(self.descs.len() - 1)
    }

    /// A reference to `t`'s image as it is (colour and normal maps).
    pub(super) fn image(&mut self, t: &UvTexture, stage_file: &Path) -> Result<TextureRef, ImportError> {
        Ok(TextureRef { texture: self.decoded(t, stage_file)?, transform: t.transform })
    }

    /// A texture in glTF's metallic-roughness packing (roughness in G, metallic in B) from the
    /// scalar textures `roughness` and `metallic` (either may be absent: its channel is 1 and the
    /// constant factor applies). One image already packed that way is used as it is; otherwise
    /// the channels are copied at the larger size (nearest texel).
    pub(super) fn metallic_roughness(
        &mut self,
        roughness: Option<&UvTexture>,
        metallic: Option<&UvTexture>,
        stage_file: &Path,
    ) -> Result<Option<TextureRef>, ImportError> {
        let channel = |t: &UvTexture| t.channel.unwrap_or(0);
        let sources: Vec<(&UvTexture, usize, usize)> = [(roughness, 1usize), (metallic, 2usize)]
            .into_iter()
            .filter_map(|(t, to)| t.map(|t| (t, to, channel(t))))
            .collect();
        let Some(&(first, _, _)) = sources.first() else { return Ok(None) };
        let same_image = sources.iter().all(|(t, _, _)| t.file == first.file && t.wrap == first.wrap);
        if same_image && sources.iter().all(|&(_, to, from)| to == from) {
            return self.image(first, stage_file).map(Some);
        }
        let decoded: Vec<(usize, usize, usize)> = sources
            .iter()
            .map(|&(t, to, from)| Ok((self.decoded(t, stage_file)?, to, from)))
            .collect::<Result<_, ImportError>>()?;
        let (w, h) = decoded
            .iter()
            .fold((1u32, 1u32), |(w, h), &(i, _, _)| (w.max(self.descs[i].width), h.max(self.descs[i].height)));
        let mut texels = vec![[0u8, 255, 255, 255]; (w * h) as usize];
        for &(i, to, from) in &decoded {
            let src = &self.descs[i];
            for y in 0..h {
                let sy = (u64::from(y) * u64::from(src.height) / u64::from(h)) as usize;
                for x in 0..w {
                    let sx = (u64::from(x) * u64::from(src.width) / u64::from(w)) as usize;
                    texels[(y * w + x) as usize][to] = src.texels[sy * src.width as usize + sx][from];
                }
            }
        }
        let name = sources.iter().map(|(t, _, _)| t.at.as_str()).collect::<Vec<_>>().join(" + ");
        self.descs.push(TextureDesc {
            name: format!("metallic-roughness of {name}"),
            width: w,
            height: h,
            texels,
            wrap_u: first.wrap.0,
            wrap_v: first.wrap.1,
            nearest: false,
            source: SourceLocation { file: stage_file.to_owned(), line: None, item: Some(first.at.clone()) },
        });
        Ok(Some(TextureRef { texture: self.descs.len() - 1, transform: first.transform }))
    }
}
