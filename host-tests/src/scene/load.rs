//! Loading a scene: `builtin:NAME`, an AFF file, or a BART scene folder.

use std::path::{Path, PathBuf};

use super::{Scene, aff, aff_adapter, builtin};

/// Loads `builtin:NAME` or an `.aff` file at animation time `time`.
pub fn load_scene(spec: &str, time: f64) -> Result<Scene, String> {
    if let Some(name) = spec.strip_prefix("builtin:") {
        return builtin::by_name(name);
    }
    load_aff(Path::new(spec), time)
}

/// Loads an AFF scene file.
pub fn load_aff(path: &Path, time: f64) -> Result<Scene, String> {
    aff::load(path, time)
        .map(aff_adapter)
        .map_err(|e| e.to_string())
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
pub fn load_scene_dir(dir: &Path, time: f64) -> Result<Scene, String> {
    let top = aff::find_top_level(dir).map_err(|e| e.to_string())?;
    load_aff(&top, time)
}
