//! The light a scene without any gets, as model viewers do (`quasar render --default-light`):
//! glTF files without `KHR_lights_punctual` and OBJ files without an emissive `Ke` would otherwise
//! render black. `auto` (the default) adds it only to a scene without light; `env` adds it to
//! every scene, beside the scene's own lights (a model whose only light is an emissive display or
//! lamp is otherwise dark around it); `none` never.
//!
//! The default is a uniform white environment of luminance 1 (radiance `Spectrum::rgb_illuminant
//! ([1, 1, 1])`, D65 white with Y = 1 from every direction): it lights every side of a model, so a
//! white Lambertian surface open to the whole sky renders at Y = 1, and a Cornell box is lit
//! through its opening. The render says so in a warning; the light is part of the scene from then
//! on (its `scene_fingerprint` differs from the dark scene's).

use quasar_importers::{LightDesc, SceneDesc};
use quasar_materials::spectrum::Spectrum;

/// What a scene is given beside its own lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DefaultLight {
    /// The white environment (module documentation) when the scene has no light, else nothing.
    #[default]
    Auto,
    /// The white environment, added to every scene, whatever lights it has.
    Environment,
    /// Nothing: a scene without light stays black (with a warning).
    None,
}

impl DefaultLight {
    /// Every choice with its command-line name.
    pub const ALL: [(&'static str, DefaultLight); 3] =
        [("auto", DefaultLight::Auto), ("env", DefaultLight::Environment), ("none", DefaultLight::None)];

    /// The choice named `name` (`auto`, `env` or `none`).
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

/// Gives `desc` the `choice` of light; returns the message to show, naming the scene file and
/// the flag that changes the choice (None when nothing was added: `auto` on a scene with a light,
/// or `none`, where the render itself warns of a black image).
pub fn add_default_light(desc: &mut SceneDesc, choice: DefaultLight) -> Option<String> {
    let lit = has_light(desc);
    let add = match choice {
        DefaultLight::Auto => !lit,
        DefaultLight::Environment => true,
        DefaultLight::None => false,
    };
    if !add {
        return None;
    }
    let spectrum = Spectrum::rgb_illuminant([1.0; 3]).expect("white is a valid light colour");
    desc.lights.push(LightDesc::Environment { spectrum, scale: 1.0, map: None });
    let scene = desc.source.display();
    Some(if lit {
        format!(
            "{scene}: --default-light env adds a uniform white environment of luminance 1 to the scene's own lights"
        )
    } else {
        format!(
            "{scene}: the scene has no light; it is lit by a uniform white environment of luminance 1 (--default-light none keeps it dark)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_scenes_without_light_get_one() {
        let mut desc = SceneDesc::default();
        let w = add_default_light(&mut desc, DefaultLight::Auto).unwrap();
        assert!(w.contains("--default-light none"), "{w}");
        assert!(matches!(&desc.lights[..], [LightDesc::Environment { scale: 1.0, map: None, .. }]));
        assert!(add_default_light(&mut desc, DefaultLight::Auto).is_none());
        assert_eq!(desc.lights.len(), 1);
        let mut dark = SceneDesc::default();
        assert!(add_default_light(&mut dark, DefaultLight::None).is_none());
        assert!(dark.lights.is_empty());
        assert_eq!(DefaultLight::from_name("env"), Ok(DefaultLight::Environment));
        assert_eq!(DefaultLight::default(), DefaultLight::Auto);
        assert!(DefaultLight::from_name("sun").unwrap_err().contains("auto, env, none"));
    }

    /// `env` adds the environment to a scene that has a light of its own, and says so (the landed
    /// main did nothing there, silently: issue 52).
    #[test]
    fn env_is_added_whenever_asked() {
        let mut desc = SceneDesc::default();
        let spectrum = Spectrum::rgb_illuminant([1.0; 3]).unwrap();
        desc.lights.push(LightDesc::Environment { spectrum, scale: 3.0, map: None });
        let w = add_default_light(&mut desc, DefaultLight::Environment).unwrap();
        assert!(w.contains("adds a uniform white environment") && w.contains("own lights"), "{w}");
        assert_eq!(desc.lights.len(), 2);
        assert!(matches!(desc.lights[1], LightDesc::Environment { scale: 1.0, map: None, .. }));
    }
}
