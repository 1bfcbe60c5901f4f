//! Method parameters: each method declares the parameters it reads ([`ParamSpec`]: key, type,
//! range, default, documentation) in its row of the method table; the command line (as flags),
//! the scene file's `[render]` table (as keys) and the help text are all made from these
//! declarations, and every value is validated once, by the method that reads it.
//!
//! Values come from two places with different rules (pbrt-v4's `ParameterDictionary` and
//! `ReportUnused`): a command-line value the chosen method does not read is an error (it would
//! silently do nothing); a scene-file value it does not read is ignored (a scene written for
//! `quasi` renders with `pt` too), but a scene-file key no method reads is an error naming the
//! file and line.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::fmt;

pub use quasar_importers::ParamValue;
use quasar_importers::{ErrorPlace, RenderParam};

/// The type and range of a parameter's values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamKind {
    /// An integer in `min..=max`.
    Int {
        /// Smallest value.
        min: i128,
        /// Largest value.
        max: i128,
    },
    /// A real number in the open interval (`min`, `max`) (`f64::INFINITY` for no upper bound).
    Real {
        /// Lower bound (excluded).
        min: f64,
        /// Upper bound (excluded).
        max: f64,
    },
    /// A positive length in scene units (scene files: converted with their `units`).
    Length,
    /// true or false (a flag on the command line).
    Bool,
}

/// The default of a parameter: the value a method uses without one (typed, from the constant
/// the method itself reads), or what it computes instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamDefault {
    /// This integer.
    Int(i64),
    /// This number.
    Real(f64),
    /// This boolean.
    Bool(bool),
    /// Computed by the method from the scene or the render; the text says how.
    Computed(&'static str),
}

impl fmt::Display for ParamDefault {
    /// The value as a scene file writes it (`4`, `0.75`, `false`), or the text of a computed one.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Int(i) => write!(f, "{i}"),
            Self::Real(x) => write!(f, "{x}"),
            Self::Bool(b) => write!(f, "{b}"),
            Self::Computed(text) => f.write_str(text),
        }
    }
}

/// One method parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// Key in the scene file's `[render]` table and in [`MethodParams`].
    pub key: &'static str,
    /// Command-line flag (without `--`).
    pub flag: &'static str,
    /// Type and range.
    pub kind: ParamKind,
    /// The default: the method's own constant, or what it computes without a value (the
    /// documentation, the help and a checkpoint's resume key state it).
    pub default: ParamDefault,
    /// What it does.
    pub doc: &'static str,
}

impl ParamSpec {
    /// The range as text, for errors and the docs.
    pub fn range(&self) -> String {
        match self.kind {
            ParamKind::Int { min, max } => format!("an integer in {min}..={max}"),
            ParamKind::Real { min, max } if max.is_infinite() => format!("a number > {min}"),
            ParamKind::Real { min, max } => format!("a number in ({min}, {max})"),
            ParamKind::Length => "a positive length".into(),
            ParamKind::Bool => "true or false".into(),
        }
    }
}

/// Where a value came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// The command line (`--flag`) or a program's overrides.
    CommandLine,
    /// A scene file's `[render]` table, at this place; `unit` converts its lengths to metres.
    SceneFile {
        /// File, line and column.
        place: ErrorPlace,
        /// Metres per scene unit.
        unit: f32,
    },
}

/// An invalid parameter value or key, with its place.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct ParamError {
    /// Where (None: the command line).
    pub place: Option<ErrorPlace>,
    /// What is wrong.
    pub msg: String,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.place {
            Some(p) => write!(f, "{p}: {}", self.msg),
            None => write!(f, "{}", self.msg),
        }
    }
}

/// Parameter values by key, from the command line and the scene file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MethodParams {
    values: BTreeMap<String, (ParamValue, Origin)>,
    /// Metres per unit of the command line's lengths: the scene file's unit once
    /// [`over_scene`](Self::over_scene) has combined them (None: metres).
    command_line_unit: Option<f32>,
}

impl MethodParams {
    /// Sets `key` from the command line (replacing any value).
    pub fn set(&mut self, key: &str, value: impl Into<ParamValue>) {
        self.values.insert(key.to_string(), (value.into(), Origin::CommandLine));
    }

    /// These command-line values over the scene file's `file` (keys no method reads: an error
    /// at their place, with a suggestion); lengths on the command line are then in the scene
    /// file's units too (`unit` metres each), as in its `[render]` table.
    pub fn over_scene(&self, file: &[RenderParam], unit: f32, known: &[&str]) -> Result<Self, ParamError> {
        let mut out = Self { command_line_unit: Some(unit), ..Self::default() };
        for p in file {
            if !known.contains(&p.key.as_str()) {
                return Err(ParamError {
                    place: Some(p.place.clone()),
                    msg: format!(
                        "unknown key `{}` in `render`; the methods' keys are: {}{}",
                        p.key,
                        known.join(", "),
                        quasar_importers::did_you_mean(&p.key, known.iter().copied())
                    ),
                });
            }
            out.values.insert(p.key.clone(), (p.value.clone(), Origin::SceneFile { place: p.place.clone(), unit }));
        }
        for (k, v) in &self.values {
            out.values.insert(k.clone(), v.clone());
        }
        Ok(out)
    }

    /// The values (with their keys).
    pub fn values(&self) -> impl Iterator<Item = (&str, &ParamValue)> {
        self.values.iter().map(|(k, (v, _))| (k.as_str(), v))
    }

    /// The value of `key`.
    pub fn get(&self, key: &str) -> Option<&ParamValue> {
        self.values.get(key).map(|(v, _)| v)
    }

    /// True when `key` has a value.
    pub fn contains(&self, key: &str) -> bool {
        self.values.contains_key(key)
    }

    /// Removes `key`.
    pub fn remove(&mut self, key: &str) {
        self.values.remove(key);
    }

    /// True when no value is set.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The keys given on the command line.
    pub fn command_line_keys(&self) -> impl Iterator<Item = &str> {
        self.values.iter().filter(|(_, (_, o))| *o == Origin::CommandLine).map(|(k, _)| k.as_str())
    }

    /// Every value as (key, text), in key order (the settings of a checkpoint's resume key).
    pub fn entries(&self) -> Vec<(String, String)> {
        self.values.iter().map(|(k, (v, _))| (k.clone(), v.to_string())).collect()
    }
}

/// Typed access to [`MethodParams`] for one method, recording what it reads.
pub struct ParamReader<'a> {
    params: &'a MethodParams,
    read: RefCell<Vec<&'static str>>,
}

impl<'a> ParamReader<'a> {
    /// A reader of `params`.
    pub fn new(params: &'a MethodParams) -> Self {
        Self { params, read: RefCell::new(Vec::new()) }
    }

    fn get(&self, spec: &ParamSpec) -> Option<&'a (ParamValue, Origin)> {
        self.read.borrow_mut().push(spec.key);
        self.params.values.get(spec.key)
    }

    fn error(origin: &Origin, spec: &ParamSpec, msg: String) -> ParamError {
        match origin {
            Origin::CommandLine => ParamError { place: None, msg: format!("--{}: {msg}", spec.flag) },
            Origin::SceneFile { place, .. } => {
                ParamError { place: Some(place.clone()), msg: format!("`render.{}`: {msg}", spec.key) }
            }
        }
    }

    /// The integer value of `spec`, checked against its range.
    pub fn int(&self, spec: &ParamSpec) -> Result<Option<i128>, ParamError> {
        let Some((v, origin)) = self.get(spec) else { return Ok(None) };
        let ParamKind::Int { min, max } = spec.kind else { unreachable!("{} is not an integer parameter", spec.key) };
        match v {
            ParamValue::Int(i) if (min..=max).contains(i) => Ok(Some(*i)),
            other => Err(Self::error(origin, spec, format!("expected {}, got {other}", spec.range()))),
        }
    }

    /// The real value of `spec` (integers accepted), checked against its range; lengths are
    /// converted to metres when they come from a scene file.
    pub fn real(&self, spec: &ParamSpec) -> Result<Option<f64>, ParamError> {
        let Some((v, origin)) = self.get(spec) else { return Ok(None) };
        let x = match v {
            ParamValue::Int(i) => *i as f64,
            ParamValue::Float(f) => *f,
            other => return Err(Self::error(origin, spec, format!("expected {}, got {other}", spec.range()))),
        };
        let (ok, x) = match spec.kind {
            ParamKind::Real { min, max } => (x > min && x < max, x),
            ParamKind::Length => {
                let unit = match origin {
                    Origin::SceneFile { unit, .. } => *unit as f64,
                    Origin::CommandLine => self.params.command_line_unit.unwrap_or(1.0) as f64,
                };
                let m = x * unit;
                (x > 0.0 && m.is_finite() && m > 0.0 && m < f32::MAX as f64, m)
            }
            _ => unreachable!("{} is not a real parameter", spec.key),
        };
        if !ok || !x.is_finite() {
            return Err(Self::error(origin, spec, format!("expected {}, got {v}", spec.range())));
        }
        Ok(Some(x))
    }

    /// The boolean value of `spec`.
    pub fn bool(&self, spec: &ParamSpec) -> Result<Option<bool>, ParamError> {
        let Some((v, origin)) = self.get(spec) else { return Ok(None) };
        match v {
            ParamValue::Bool(b) => Ok(Some(*b)),
            other => Err(Self::error(origin, spec, format!("expected true or false, got {other}"))),
        }
    }

    /// Errors for command-line values `method` did not read (they would do nothing);
    /// `describe(key)` gives a key's flag and the methods that do read it.
    pub fn report_unused(
        &self,
        method: &str,
        describe: impl Fn(&str) -> (String, Vec<&'static str>),
    ) -> Result<(), ParamError> {
        let read = self.read.borrow();
        for k in self.params.command_line_keys() {
            if !read.contains(&k) {
                let (flag, users) = describe(k);
                return Err(ParamError {
                    place: None,
                    msg: if users.is_empty() {
                        format!("--{flag} is not a parameter of any method")
                    } else {
                        format!("--{flag} does not apply to {method} (it applies to {})", users.join(", "))
                    },
                });
            }
        }
        Ok(())
    }
}
