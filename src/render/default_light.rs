//! The light a scene without any gets, as model viewers do (`quasar render --default-light`):
//! glTF files without `KHR_lights_punctual` and OBJ files without an emissive `Ke` would otherwise
//! render black.
//!
//! The default is a uniform white environment of luminance 1 (radiance `Spectrum::rgb_illuminant
//! ([1, 1, 1])`, D65 white with Y = 1 from every direction): it lights every side of a model, so a
//! white Lambertian surface open to the whole sky renders at Y = 1, and a Cornell box is lit
//! through its opening. The render says so in a warning; the light is part of the scene from then
//! on (its `scene_fingerprint` differs from the dark scene's).

use quasar_importers::{LightDesc, SceneDesc};
use quasar_materials::spectrum::Spectrum;

/// What a scene without a light is given.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DefaultLight {
    /// A uniform white environment of luminance 1 (module documentation).
    #[default]
    Environment,
    /// Nothing: the image stays black (with a warning).
    None,
}

impl DefaultLight {
    /// Every choice with its command-line name.
    pub const ALL: [(&'static str, DefaultLight); 2] =
        [("env", DefaultLight::Environment), ("none", DefaultLight::None)];

    /// The choice named `name` (`env` or `none`).
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|&(_, d)| d).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|(n, _)| *n).collect();
            format!("unknown default light `{name}` (expected one of: {})", names.join(", "))
        })
    }
}

/// Whether `desc` has anything that emits: a light or an emissive mesh with a positive scale.
pub fn has_light(desc: &SceneDesc) -> bool {
    !desc.lights.is_empty() || desc.meshes.iter().any(|m| m.emission.as_ref().is_some_and(|e| e.scale > 0.0))
}

/// Gives `desc` the `choice` of light when it has none; returns the warning to show, naming the
/// scene file and the flag that changes the choice (None when nothing was added: the scene has a
/// light, or `choice` is [`DefaultLight::None`] and the render warns of the black image).
pub fn add_default_light(desc: &mut SceneDesc, choice: DefaultLight) -> Option<String> {
    if has_light(desc) {
        return None;
    }
    let scene = desc.source.display();
    match choice {
        DefaultLight::Environment => {
            let spectrum = Spectrum::rgb_illuminant([1.0; 3]).expect("white is a valid light colour");
            desc.lights.push(LightDesc::Environment { spectrum, scale: 1.0, map: None });
            Some(format!(
                "{scene}: the scene has no light; it is lit by a uniform white environment of luminance 1 (--default-light none keeps it dark)"
            ))
        }
        DefaultLight::None => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_scenes_without_light_get_one() {
        let mut desc = SceneDesc::default();
        let w = add_default_light(&mut desc, DefaultLight::Environment).unwrap();
        assert!(w.contains("--default-light none"), "{w}");
        assert!(matches!(&desc.lights[..], [LightDesc::Environment { scale: 1.0, map: None, .. }]));
        assert!(add_default_light(&mut desc, DefaultLight::Environment).is_none());
        assert_eq!(desc.lights.len(), 1);
        let mut dark = SceneDesc::default();
        assert!(add_default_light(&mut dark, DefaultLight::None).is_none());
        assert!(dark.lights.is_empty());
        assert_eq!(DefaultLight::from_name("env"), Ok(DefaultLight::Environment));
        assert!(DefaultLight::from_name("sun").unwrap_err().contains("env, none"));
    }
}
