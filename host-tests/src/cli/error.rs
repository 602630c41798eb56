//! Why a `render`, `compare`, `table1` or geometric-LOD command failed:
//! the typed errors of the modules it calls (scene, render set-up, output
//! files), plus the command's own verdicts.

use std::fmt;
use std::path::PathBuf;

use crate::error::FileError;
use crate::output::OutputError;
use crate::render::RenderError;
use crate::scene::SceneError;

/// Why a command failed.
#[derive(Debug)]
pub enum CommandError {
    /// The scene could not be loaded (names the scene or file and line).
    Scene(SceneError),
    /// The render could not be set up (names the option or item).
    Render(RenderError),
    /// An output file could not be written (names the file).
    Output(OutputError),
    /// A file or folder could not be read or created.
    File(FileError),
    /// `table1`: the BART folder does not exist and `--builtin` was not given.
    ScenesNotFound {
        /// The folder looked for.
        dir: PathBuf,
    },
    /// `table1`: a scene failed to load without `--skip-unloadable`.
    Unloadable {
        /// The scene's name.
        name: String,
        /// Why.
        source: SceneError,
    },
    /// `table1`: no scene was measured.
    NothingMeasured,
    /// `render`: the render with trimmed pyramids differs from the full one.
    TrimmedDiffers,
    /// A two-level render's paths differ from the flat reference's.
    PathMismatches {
        /// The render (view and configuration).
        render: String,
        /// Paths that differ.
        count: u64,
    },
}

impl fmt::Display for CommandError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Scene(e) => e.fmt(f),
            Self::Render(e) => e.fmt(f),
            Self::Output(e) => e.fmt(f),
            Self::File(e) => e.fmt(f),
            Self::ScenesNotFound { dir } => write!(
                f,
                "{}: scene folder not found (pass --scenes DIR, or --builtin for the built-in scenes)",
                dir.display()
            ),
            Self::Unloadable { name, source } => write!(
                f,
                "{name}: cannot be loaded, so it cannot be measured: {source} (pass --skip-unloadable to measure the other scenes)"
            ),
            Self::NothingMeasured => f.write_str("no scene could be measured"),
            Self::TrimmedDiffers => {
                f.write_str("the render with trimmed pyramids differs from the full one")
            }
            Self::PathMismatches { render, count } => {
                write!(f, "{render}: {count} path mismatches")
            }
        }
    }
}

impl std::error::Error for CommandError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Scene(e) | Self::Unloadable { source: e, .. } => Some(e),
            Self::Render(e) => Some(e),
            Self::Output(e) => Some(e),
            Self::File(e) => Some(e),
            Self::ScenesNotFound { .. }
            | Self::NothingMeasured
            | Self::TrimmedDiffers
            | Self::PathMismatches { .. } => None,
        }
    }
}

macro_rules! from {
    ($($v:ident($t:ty)),*) => {
        $(impl From<$t> for CommandError {
            fn from(e: $t) -> Self {
                Self::$v(e)
            }
        })*
    };
}
from!(
    Scene(SceneError),
    Render(RenderError),
    Output(OutputError),
    File(FileError)
);

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn display_names_the_folder_scene_and_render() {
        let e = CommandError::ScenesNotFound {
            dir: PathBuf::from("/no/bart"),
        };
        assert!(
            e.to_string()
                .starts_with("/no/bart: scene folder not found"),
            "{e}"
        );
        let e = CommandError::Unloadable {
            name: "kitchen".into(),
            source: SceneError::UnknownBuiltin { name: "x".into() },
        };
        assert!(
            e.to_string().starts_with("kitchen: cannot be loaded"),
            "{e}"
        );
        assert!(e.source().is_some());
        let e = CommandError::PathMismatches {
            render: "near stochastic".into(),
            count: 3,
        };
        assert_eq!(e.to_string(), "near stochastic: 3 path mismatches");
        let e = CommandError::from(RenderError::Transition { value: -1.0 });
        assert!(e.to_string().contains("--transition -1"), "{e}");
        assert!(e.source().is_some());
    }
}
