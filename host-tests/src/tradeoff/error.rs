//! Why the `tradeoff` command failed: a scene or render it measures, a
//! chart, or an output file.

use std::fmt;
use std::path::PathBuf;

use super::chart::ChartError;
use crate::error::FileError;
use crate::output::OutputError;
use crate::render::RenderError;
use crate::scene::SceneError;

/// Why `tradeoff` failed.
#[derive(Debug)]
pub enum TradeoffError {
    /// A scene could not be loaded.
    Scene {
        /// The scene as given (`builtin:NAME`, a file or BART folder).
        spec: String,
        /// Why (names the file and line).
        source: SceneError,
    },
    /// A scene's render could not be set up.
    Render {
        /// The scene as given.
        spec: String,
        /// Why.
        source: RenderError,
    },
    /// A chart could not be drawn or written.
    Chart {
        /// The chart's files without extension (`.svg`, `.png`).
        stem: PathBuf,
        /// Why.
        source: ChartError,
    },
    /// An output file could not be written (names the file).
    Output(OutputError),
}

impl fmt::Display for TradeoffError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Scene { spec, source } => write!(f, "scene {spec}: {source}"),
            Self::Render { spec, source } => write!(f, "scene {spec}: {source}"),
            Self::Chart { stem, source } => write!(f, "chart {}: {source}", stem.display()),
            Self::Output(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for TradeoffError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Scene { source, .. } => Some(source),
            Self::Render { source, .. } => Some(source),
            Self::Chart { source, .. } => Some(source),
            Self::Output(e) => Some(e),
        }
    }
}

impl From<OutputError> for TradeoffError {
    fn from(e: OutputError) -> Self {
        Self::Output(e)
    }
}

impl From<FileError> for TradeoffError {
    fn from(e: FileError) -> Self {
        Self::Output(e.into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn display_names_the_scene_and_the_chart() {
        let e = TradeoffError::Scene {
            spec: "builtin:nope".into(),
            source: SceneError::UnknownBuiltin {
                name: "nope".into(),
            },
        };
        assert!(
            e.to_string()
                .starts_with("scene builtin:nope: unknown built-in scene"),
            "{e}"
        );
        assert!(e.source().is_some());
        let e = TradeoffError::Chart {
            stem: PathBuf::from("out/pareto-frame"),
            source: ChartError::LabelsOverlap {
                panel: "hall".into(),
                a: 1,
                b: 2,
            },
        };
        assert_eq!(
            e.to_string(),
            "chart out/pareto-frame: panel \"hall\": labels 1 and 2 overlap"
        );
        let e = TradeoffError::from(FileError::write(
            std::path::Path::new("/ro/x.json"),
            std::io::Error::other("denied"),
        ));
        assert!(e.to_string().starts_with("/ro/x.json: cannot write"), "{e}");
    }
}
