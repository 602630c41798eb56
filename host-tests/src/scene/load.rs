//! Loading a scene: `builtin:NAME`, an AFF file, or a BART scene folder.

use std::fmt;
use std::path::{Path, PathBuf};

use super::{Scene, aff, aff_adapter, builtin};
use aff::AffError;

/// Why a scene could not be loaded.
#[derive(Debug)]
pub enum SceneError {
    /// `builtin:NAME` names no built-in scene.
    UnknownBuiltin {
        /// The `NAME` given.
        name: String,
    },
    /// The AFF file (or BART folder) failed to read or parse; the error
    /// names the file and line.
    Aff(AffError),
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownBuiltin { name } => write!(
                f,
                "unknown built-in scene `{name}` (choose one of {})",
                builtin::NAMES.join(", ")
            ),
            Self::Aff(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::UnknownBuiltin { .. } => None,
            Self::Aff(e) => Some(e),
        }
    }
}

impl From<AffError> for SceneError {
    fn from(e: AffError) -> Self {
        Self::Aff(e)
    }
}

/// Short name of a scene spec for file names and tables: the builtin's
/// name, or the file stem of a path ("scene" without one).
#[must_use]
pub fn scene_label(spec: &str) -> String {
    spec.strip_prefix("builtin:").map_or_else(
        || {
            Path::new(spec)
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        },
        str::to_string,
    )
}

/// Loads `builtin:NAME` or an `.aff` file at animation time `time`.
pub fn load_scene(spec: &str, time: f64) -> Result<Scene, SceneError> {
    if let Some(name) = spec.strip_prefix("builtin:") {
        return builtin::by_name(name);
    }
    load_aff(Path::new(spec), time)
}

/// Loads an AFF scene file.
pub fn load_aff(path: &Path, time: f64) -> Result<Scene, SceneError> {
    Ok(aff_adapter(aff::load(path, time)?))
}

/// The default BART folder: `../shared/scenes/bart` relative to the current
/// directory, else relative to the repository root.
#[must_use]
pub fn default_bart_dir() -> PathBuf {
    let cwd = PathBuf::from("../shared/scenes/bart");
    if cwd.is_dir() {
        return cwd;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/bart")
}

/// Loads the scene in a BART folder (its top-level `.aff` file).
pub fn load_scene_dir(dir: &Path, time: f64) -> Result<Scene, SceneError> {
    let top = aff::find_top_level(dir)?;
    load_aff(&top, time)
}
