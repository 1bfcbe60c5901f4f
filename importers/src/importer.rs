//! The interface of a scene importer ([`Importer`]) and the options every importer reads.

use std::path::Path;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::scene_desc::SceneDesc;

/// Options shared by all importers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportOptions {
    /// Extra factor applied to every length after the file's own units are converted to metres
    /// (`None` = 1). Must be finite and > 0.
    pub units_scale: Option<f32>,
    /// Let glTF files refer to external files by absolute paths or by relative paths that leave
    /// the glTF file's folder (refused by default; CLI `--allow-external-paths`).
    pub allow_external_paths: bool,
    /// The time code animated USD attributes and transforms are read at (`None`: the earliest
    /// time sample; CLI `--time-code`). Other formats have no animation that quasar reads.
    pub time_code: Option<f64>,
}

impl ImportOptions {
    /// The validated extra scale (1 when unset).
    pub fn scale(&self, file: &Path) -> Result<f32, ImportError> {
        match self.units_scale {
            None => Ok(1.0),
            Some(s) if s.is_finite() && s > 0.0 => Ok(s),
            Some(s) => Err(ImportError::new(
                ImportErrorKind::InvalidValue,
                ErrorPlace::file(file),
                format!("units scale must be finite and > 0, got {s}"),
            )),
        }
    }
}

/// A scene file format.
pub trait Importer: Sync {
    /// The lower-case file extensions (without the dot) this importer handles.
    fn extensions(&self) -> &[&str];

    /// Reads the file at `path` into a [`SceneDesc`] (lengths in metres, times
    /// `opts.units_scale`); a format that includes other scene files imports them with `formats`.
    fn import(&self, path: &Path, opts: &ImportOptions, formats: Formats<'_>) -> Result<SceneDesc, ImportError>;
}

/// The scene formats there are (the registry's table, [`crate::registry::IMPORTERS`]), handed to
/// every importer so that a format including other files (TOML scenes) can import any of them
/// without depending on the table that lists it.
#[derive(Clone, Copy)]
pub struct Formats<'a>(pub &'a [&'a dyn Importer]);

impl<'a> Formats<'a> {
    /// The importer for the extension of `path` (case-insensitive), if any.
    pub fn for_path(self, path: &Path) -> Option<&'a dyn Importer> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        self.0.iter().copied().find(|imp| imp.extensions().contains(&ext.as_str()))
    }

    /// All extensions some importer handles, in table order.
    pub fn extensions(self) -> Vec<&'a str> {
        self.0.iter().flat_map(|imp| imp.extensions().iter().copied()).collect()
    }

    /// Imports `path` with the importer for its extension (an error listing the supported
    /// extensions when there is none).
    pub fn import(self, path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
        match self.for_path(path) {
            Some(imp) => imp.import(path, opts, self),
            None => Err(ImportError::new(
                ImportErrorKind::Unsupported,
                ErrorPlace::file(path),
                format!(
                    "unsupported scene format (extension {:?}); supported extensions: {}",
                    path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default(),
                    self.extensions().iter().map(|e| format!(".{e}")).collect::<Vec<_>>().join(", ")
                ),
            )),
        }
    }
}
