//! `SceneDesc`: the renderer-independent, plain-data description of a scene that every importer
//! produces and the renderer compiles (docs/architecture.md §2). Nothing here refers to render-time
//! structures. Lengths are in metres (importers apply `units`), directions need not be normalised.

use std::path::PathBuf;

use glam::{Vec2, Vec3};
use quasar_materials::{Material, spectrum::Spectrum};

use crate::error::ErrorPlace;
pub use crate::source::SourceLocation;
pub use crate::texture_desc::{MaterialTextures, TextureDesc, TextureRef, TextureWrap};

/// Largest number of triangles in one scene (every importer counts its shapes, includes and
/// instances against it before generating them).
pub const MAX_SCENE_TRIANGLES: u64 = 1 << 28;

/// A named material.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialDesc {
    /// Name (unique within the scene).
    pub name: String,
    /// The model and its parameters.
    pub material: Material,
    /// The absorption of the medium inside a transmitting material (the side its surfaces'
    /// geometric normals point away from), None for a clear one.
    pub absorption: Option<quasar_materials::Absorption>,
    /// The scattering of that medium (sigma_s and the phase function), None for a medium that
    /// only absorbs.
    pub scattering: Option<quasar_materials::Scattering>,
    /// Textures that modulate the material's parameters (glTF); empty for untextured materials.
    pub textures: MaterialTextures,
    /// Where it was defined.
    pub source: SourceLocation,
}

/// Light emitted by a surface: spectral radiance L_e(lambda) = `scale * spectrum(lambda)`,
/// in W/(sr m^2 nm) when the scene uses absolute units.
#[derive(Clone, Debug, PartialEq)]
pub struct EmissionDesc {
    /// Spectral shape.
    pub spectrum: Spectrum,
    /// Multiplier (>= 0, finite).
    pub scale: f32,
    /// Emit from both faces; otherwise only towards the side the geometric normal points to
    /// (normal = (v1 - v0) x (v2 - v0), counter-clockwise winding).
    pub two_sided: bool,
    /// A texture the emission varies with over the surface (glTF `emissiveTexture`); `spectrum`
    /// is then its mean colour, for what needs one colour (`quasar info`, exports).
    pub texture: Option<EmissiveTexture>,
}

/// Emission that varies over a surface: L_e = scale x the light colour of `factor` times the
/// texel (sRGB-decoded) at the point's texture coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissiveTexture {
    /// The texture and its coordinate transform.
    pub texture: crate::texture_desc::TextureRef,
    /// Linear RGB factor on the texel (glTF `emissiveFactor` x `emissive_strength`).
    pub factor: [f32; 3],
}

/// A triangle mesh in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshDesc {
    /// Name (file/object/group), for messages and overrides.
    pub name: String,
    /// Vertex positions (world space, metres).
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (same length as `positions`), or `None` for flat shading.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates (same length as `positions`; glTF convention: origin at the
    /// image's top-left, v down), or `None`.
    pub uvs: Option<Vec<Vec2>>,
    /// Per-vertex linear RGB colours (same length as `positions`; glTF `COLOR_0`), which
    /// multiply a glTF material's base colour, or `None`.
    pub colors: Option<Vec<[f32; 3]>>,
    /// Triangles as indices into `positions`.
    pub indices: Vec<[u32; 3]>,
    /// Index into [`SceneDesc::materials`].
    pub material: usize,
    /// Area emission, if the mesh is a light.
    pub emission: Option<EmissionDesc>,
    /// Where it was defined.
    pub source: SourceLocation,
}

impl MeshDesc {
    /// Sum of the triangle areas, 1/2 |(v1 - v0) x (v2 - v0)| each (indices out of range count 0).
    pub fn area(&self) -> f64 {
        self.indices
            .iter()
            .map(|t| match t.map(|i| self.positions.get(i as usize)) {
                [Some(a), Some(b), Some(c)] => 0.5 * f64::from((*b - *a).cross(*c - *a).length()),
                _ => 0.0,
            })
            .sum()
    }
}

/// A light that is not a surface (area lights are emissive meshes).
#[derive(Clone, Debug, PartialEq)]
pub enum LightDesc {
    /// Isotropic point light: intensity I(lambda) = scale * spectrum, W/(sr nm).
    Point {
        /// Position.
        position: Vec3,
        /// Spectral shape.
        spectrum: Spectrum,
        /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
        /// spectra make it a luminance-equivalent value).
        scale: f32,
    },
    /// Spot light: point light restricted to a cone, smooth falloff between the two angles.
    Spot {
        /// Position.
        position: Vec3,
        /// Axis direction.
        direction: Vec3,
        /// Half-angle (degrees) where intensity reaches 0.
        cone_deg: f32,
        /// Half-angle (degrees) inside which intensity is full (<= cone_deg).
        falloff_start_deg: f32,
        /// Spectral shape.
        spectrum: Spectrum,
        /// Multiplier (on-axis intensity).
        scale: f32,
    },
    /// Distant light: irradiance E(lambda) = scale * spectrum (W/(m^2 nm)) on a surface facing it.
    Directional {
        /// Direction the light travels in.
        direction: Vec3,
        /// Spectral shape.
        spectrum: Spectrum,
        /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
        /// spectra make it a luminance-equivalent value).
        scale: f32,
    },
    /// Point luminaire with a measured distribution (IES / EULUMDAT, docs/photometry.md): radiant
    /// intensity I(w, lambda) = scale * spectrum(lambda) * candela(frame^-1 w).
    Luminaire {
        /// Photometric centre.
        position: Vec3,
        /// Luminaire frame -> world: orthonormal columns C0, C90 and up (the nadir is -column 2).
        frame: glam::Mat3,
        /// The candela distribution.
        web: std::sync::Arc<crate::photometry::PhotometricWeb>,
        /// Spectral shape, luminance 1.
        spectrum: Spectrum,
        /// W/(sr nm) per candela of the unit spectrum: [`crate::photometric::photometric_scale`]
        /// of 1 cd times the user's and the tilt's factors.
        scale: f32,
        /// Where the light leaves: a point (far field) or a luminous opening (near field).
        opening: LuminousOpening,
    },
    /// Environment at infinity: radiance L(lambda) = scale * spectrum from every direction, or
    /// with a lat-long `map`, scale times the light colour of the map's texel in each direction.
    Environment {
        /// Spectral shape (constant environments).
        spectrum: Spectrum,
        /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
        /// spectra make it a luminance-equivalent value).
        scale: f32,
        /// A lat-long radiance map (`file = "sky.exr"`).
        map: Option<std::sync::Arc<EnvMapDesc>>,
    },
}

/// Where a luminaire's light leaves it (docs/photometry.md, "Near field"): the photometric centre
/// (the far-field model of the file), or a flat luminous opening in the luminaire's C0/C90 plane
/// centred on it, from every point of which the file's distribution leaves scaled by 1/area:
/// radiance L(x, w) = I(w) / (A |cos theta|), theta from the up axis, so that the opening's
/// intensity integral_A L |cos theta| dA is the file's I(w) in every direction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LuminousOpening {
    /// All light from the photometric centre.
    #[default]
    Point,
    /// A rectangle of side `c0` along C0 and `c90` along C90 (metres).
    Rect {
        /// Side along C0.
        c0: f32,
        /// Side along C90.
        c90: f32,
    },
    /// A disk of diameter `diameter` (metres).
    Disk {
        /// Diameter.
        diameter: f32,
    },
}

/// A lat-long (equirectangular) environment map: linear RGB radiance texels; in the map's own
/// frame row 0 is the zenith (+Y) and u = 0.5 + atan2(d.x, -d.z) / (2 pi) (the image centre
/// looks along -Z); `frame` turns that frame into the world (TOML `rotate_deg`: about +Y,
/// counter-clockwise seen from above; USD: the dome's transform). Each texel's RGB is a light
/// colour: (1, 1, 1) is D65 white of luminance 1.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvMapDesc {
    /// The file it came from (for messages).
    pub file: PathBuf,
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Row-major RGB texels.
    pub texels: Vec<[f32; 3]>,
    /// Map frame -> world: the world directions of the map's +X, +Y (the pole, row 0) and +Z
    /// (orthonormal, right-handed); the identity for an unturned map, a rotation about +Y for
    /// `rotate_deg`.
    pub frame: glam::Mat3,
}

/// Which image axis `fov_deg` spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FovAxis {
    /// Horizontal field of view.
    X,
    /// Vertical field of view.
    #[default]
    Y,
}

/// A pinhole perspective camera.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up hint (image up); must not be parallel to target - position.
    pub up: Vec3,
    /// Full field of view in degrees along `fov_axis` (0 < fov < 180).
    pub fov_deg: f32,
    /// Axis of `fov_deg`.
    pub fov_axis: FovAxis,
}

impl Default for CameraDesc {
    fn default() -> Self {
        Self {
            position: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_deg: 40.0,
            fov_axis: FovAxis::Y,
        }
    }
}

/// A camera defined in a scene file (e.g. a glTF camera), selectable by name or index.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedCamera {
    /// Name in the file (glTF `name`, or `camera<N>` when it has none).
    pub name: String,
    /// The camera, in world space.
    pub camera: CameraDesc,
    /// Width / height the file asks for (glTF `aspectRatio`), if any.
    pub aspect: Option<f32>,
}

/// Render settings a scene may carry (the CLI overrides them).
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Time budget in seconds (overrides spp when set).
    pub time_s: Option<f64>,
    /// Seed of the random streams.
    pub seed: u64,
    /// Integration method name ("pt", "auto", ...), validated by the renderer's method table.
    pub method: String,
    /// Where `method` was given (for errors).
    pub method_place: Option<ErrorPlace>,
    /// Stop at this estimated RMS relative error of the image.
    pub target_error: Option<f64>,
    /// The methods' parameters (every other `[render]` key), validated by the method that reads
    /// them.
    pub params: Vec<RenderParam>,
    /// Metres per unit of the file the `[render]` table came from (its lengths' unit).
    pub unit: f32,
    /// Microfacet masking-shadowing form of every GGX material (`masking`).
    pub masking: quasar_materials::Masking,
    /// Samples per pixel of the `illuminance.Y` layer (`illuminance_samples`; 0: no layer).
    pub illuminance_samples: u32,
    /// The auxiliary outputs asked for (`aovs`), validated by the renderer's output table.
    pub aovs: Vec<String>,
    /// Where `aovs` was given (for errors).
    pub aovs_place: Option<ErrorPlace>,
    /// Rays per pixel of the auxiliary outputs (`aov_samples`).
    pub aov_samples: u32,
}

/// A value of a method parameter as written in a scene file or on the command line.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    /// An integer.
    Int(i128),
    /// A real number.
    Float(f64),
    /// A boolean.
    Bool(bool),
    /// A string.
    Str(String),
}

impl std::fmt::Display for ParamValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Int(i) => write!(f, "{i}"),
            Self::Float(x) => write!(f, "{x}"),
            Self::Bool(b) => write!(f, "{b}"),
            Self::Str(s) => write!(f, "{s:?}"),
        }
    }
}

impl From<i128> for ParamValue {
    fn from(v: i128) -> Self {
        Self::Int(v)
    }
}
impl From<u32> for ParamValue {
    fn from(v: u32) -> Self {
        Self::Int(v.into())
    }
}
impl From<u64> for ParamValue {
    fn from(v: u64) -> Self {
        Self::Int(v.into())
    }
}
impl From<f64> for ParamValue {
    fn from(v: f64) -> Self {
        Self::Float(v)
    }
}
impl From<f32> for ParamValue {
    fn from(v: f32) -> Self {
        Self::Float(v.into())
    }
}
impl From<bool> for ParamValue {
    fn from(v: bool) -> Self {
        Self::Bool(v)
    }
}

/// One method parameter of a scene file's `[render]` table, with its place.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderParam {
    /// The key.
    pub key: String,
    /// The value.
    pub value: ParamValue,
    /// File, line and column of the key.
    pub place: ErrorPlace,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            spp: 64,
            time_s: None,
            seed: 0,
            method: "auto".into(),
            method_place: None,
            target_error: None,
            params: Vec::new(),
            unit: 1.0,
            masking: quasar_materials::Masking::HeightCorrelated,
            illuminance_samples: 0,
            aovs: Vec::new(),
            aovs_place: None,
            aov_samples: 16,
        }
    }
}

/// A whole scene as plain data.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneDesc {
    /// Materials; meshes refer to them by index.
    pub materials: Vec<MaterialDesc>,
    /// Triangle meshes (world space).
    pub meshes: Vec<MeshDesc>,
    /// Non-surface lights.
    pub lights: Vec<LightDesc>,
    /// The camera.
    pub camera: CameraDesc,
    /// Cameras defined in the file (and in included files), in file order; `camera` is one of
    /// them or was given explicitly.
    pub cameras: Vec<NamedCamera>,
    /// Textures; materials refer to them by index.
    pub textures: Vec<TextureDesc>,
    /// Problems that did not stop the import (unsupported extensions, approximations), for the
    /// user: the CLI prints them as `warning: ...`.
    pub warnings: Vec<String>,
    /// Render settings from the scene file.
    pub render: RenderSettings,
    /// The file the scene was loaded from.
    pub source: PathBuf,
    /// Virtual illuminance sensors (`[[sensor]]`), measured in the same run as the image.
    pub sensors: Vec<crate::sensor_desc::SensorDesc>,
    /// What the import did, for `quasar info` (USD: the prims drawn and skipped with the
    /// reasons, the time code read); empty for formats with nothing to say.
    pub import_summary: Vec<String>,
}

impl SceneDesc {
    /// Makes the file's camera named `name` the scene camera (`quasar render --camera NAME`, as
    /// TOML's `[camera] name` does for included files); its aspect ratio, when the file gives
    /// one, sets `render.width` for `render.height`. An unknown name is an error naming the
    /// scene file and listing the cameras it has.
    pub fn use_camera(&mut self, name: &str) -> Result<(), String> {
        let Some(c) = self.cameras.iter().find(|c| c.name == name) else {
            let names: Vec<&str> = self.cameras.iter().map(|c| c.name.as_str()).collect();
            let has = if names.is_empty() { "none".to_string() } else { names.join(", ") };
            return Err(format!("{}: no camera named `{name}` (the scene's cameras: {has})", self.source.display()));
        };
        self.camera = c.camera.clone();
        if let Some(a) = c.aspect {
            self.render.width = (self.render.height as f32 * a).round().clamp(1.0, 65536.0) as u32;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_camera_is_chosen_by_name() {
        let mut desc = SceneDesc { source: "s.gltf".into(), ..Default::default() };
        let front = CameraDesc { position: Vec3::new(0.0, 0.0, 9.0), ..Default::default() };
        desc.cameras.push(NamedCamera { name: "Top".into(), camera: CameraDesc::default(), aspect: None });
        desc.cameras.push(NamedCamera { name: "Front".into(), camera: front.clone(), aspect: Some(2.0) });
        desc.render.height = 100;
        desc.use_camera("Front").unwrap();
        assert_eq!((desc.camera.clone(), desc.render.width), (front, 200));
        let e = desc.use_camera("Side").unwrap_err();
        assert!(e.contains("s.gltf") && e.contains("`Side`") && e.contains("Top, Front"), "{e}");
    }
}
