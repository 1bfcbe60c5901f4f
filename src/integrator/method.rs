//! The method table: the one place where the integration methods are named, their parameters
//! declared and their renders built (pbrt-v4's `Integrator::Create`). The command line (`--method`
//! and one flag per parameter), the scene file's `[render]` keys, `auto`, `quasar bench
//! convergence` and the output header all read from it. Adding a method is one file (its
//! estimator or passes, its parameters, its [`MethodEntry`]) plus one row in [`METHODS`].

use super::analysis::SceneAnalysis;
pub use super::entry::{Build, Built, MethodEntry};
use super::params::{MethodParams, ParamError, ParamReader, ParamSpec};
use super::{bidir, direct_lighting, pt};
use crate::core::scene::Scene;

/// Every method, in the order of help texts.
pub static METHODS: [&MethodEntry; 6] = [
    &pt::PT,
    &direct_lighting::DIRECT,
    &bidir::methods::VISMAP,
    &bidir::methods::ADAPTIVE,
    &bidir::methods::QUASI,
    &bidir::methods::ADAPTIVE_QUASI,
];

/// A method as requested: by name, or `auto` (scene analysis, then for narrow or specular scenes a measured pilot, picks one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MethodChoice {
    /// [`SceneAnalysis::auto_method`] decides.
    Auto,
    /// This method.
    Named(&'static MethodEntry),
}

/// Every name `--method` accepts.
pub fn method_names() -> Vec<&'static str> {
    std::iter::once("auto").chain(METHODS.iter().map(|m| m.name)).collect()
}

/// The entry called `name`.
pub fn find(name: &str) -> Option<&'static MethodEntry> {
    METHODS.iter().copied().find(|m| m.name == name)
}

impl MethodChoice {
    /// Parses a method name.
    pub fn from_name(name: &str) -> Result<Self, String> {
        if name == "auto" {
            return Ok(Self::Auto);
        }
        find(name).map(Self::Named).ok_or_else(|| {
            format!(
                "unknown method '{name}' (expected one of: {}){}",
                method_names().join(", "),
                quasar_importers::did_you_mean(name, method_names())
            )
        })
    }

    /// The method actually run.
    pub fn resolve(self, scene: &Scene) -> &'static MethodEntry {
        match self {
            Self::Auto => SceneAnalysis::of(scene).auto_method(),
            Self::Named(m) => m,
        }
    }

    /// Name as requested.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Named(m) => m.name,
        }
    }
}

/// Every parameter of every method (each once, in table order).
pub fn all_params() -> Vec<&'static ParamSpec> {
    let mut out: Vec<&'static ParamSpec> = Vec::new();
    for m in METHODS {
        for &p in m.params {
            if !out.iter().any(|q| q.key == p.key) {
                out.push(p);
            }
        }
    }
    out
}

/// The methods that read parameter `key`.
pub fn users_of(key: &str) -> Vec<&'static str> {
    METHODS.iter().filter(|m| m.params.iter().any(|p| p.key == key)).map(|m| m.name).collect()
}

/// Builds `entry`'s method from `params` (values of the command line over the scene file's);
/// command-line values it does not read are errors.
pub fn instantiate<'s>(entry: &MethodEntry, params: &MethodParams, build: &Build<'s>) -> Result<Built<'s>, ParamError> {
    let reader = ParamReader::new(params);
    let built = (entry.build)(build, &reader)?;
    reader.report_unused(entry.name, |key| {
        let flag = all_params().iter().find(|p| p.key == key).map_or(key.replace('_', "-"), |p| p.flag.to_string());
        (flag, users_of(key))
    })?;
    Ok(built)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_parse() {
        let names = method_names();
        for (i, n) in names.iter().enumerate() {
            assert!(!names[..i].contains(n), "{n} twice");
            assert_eq!(MethodChoice::from_name(n).unwrap().name(), *n);
        }
        let e = MethodChoice::from_name("quasy").unwrap_err();
        assert!(e.contains("did you mean `quasi`"), "{e}");
        // a parameter key means one thing: the same spec wherever it is used
        for p in all_params() {
            for m in METHODS {
                if let Some(q) = m.params.iter().find(|q| q.key == p.key) {
                    assert_eq!(*q, p, "{} in {}", p.key, m.name);
                }
            }
        }
    }
}
