//! The CLI commands and their output: `render`, `compare`, `table1`,
//! `sample`, `stress`, `memory` and the demo's `gen-data`, as library functions (the binaries
//! in `src/bin/` only parse arguments and dispatch).

use std::path::{Path, PathBuf};

use crate::output::report::write_option;

pub mod compare;
pub mod demo_data;
mod error;
pub mod instances;
pub mod memory;
pub mod pcpi_vectors;
pub mod render;
pub mod sample;
pub mod stress;
pub mod table1;
pub mod tradeoff;

pub use compare::cmd_compare;
pub use error::CommandError;
pub use render::cmd_render;
pub use table1::cmd_table1;

/// A bad `--size` value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SizeError {
    /// No `x` between width and height.
    NotWxH {
        /// The value given.
        value: String,
    },
    /// The width or height is not a whole number in `1..=16384`.
    BadDimension {
        /// The whole value given.
        value: String,
        /// The part that is wrong.
        part: String,
    },
}

impl std::fmt::Display for SizeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotWxH { value } => write!(f, "--size `{value}`: expected WxH, e.g. 800x480"),
            Self::BadDimension { value, part } => write!(
                f,
                "--size `{value}`: `{part}` is not a number in 1..={MAX_SIZE}"
            ),
        }
    }
}

impl std::error::Error for SizeError {}

/// Largest width or height `--size` accepts, pixels.
pub const MAX_SIZE: u32 = 16384;

/// Parses `WxH` (each in `1..=`[`MAX_SIZE`]).
///
/// # Errors
/// [`SizeError`] naming the value and the part that is wrong.
pub fn parse_size(s: &str) -> Result<(u32, u32), SizeError> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| SizeError::NotWxH {
        value: s.to_string(),
    })?;
    let p = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|&n| n > 0 && n <= MAX_SIZE)
            .ok_or_else(|| SizeError::BadDimension {
                value: s.to_string(),
                part: t.to_string(),
            })
    };
    Ok((p(w)?, p(h)?))
}

/// The command line of a measurement example (`cargo run --release -p
/// raymip-host --example NAME -- [WxH] [N] [--write FILE]`): a `WxH`
/// size, a whole number (samples, where the example takes one) and the
/// page whose generated block `--write` rewrites, in any order.
#[derive(Clone, Debug, Default)]
pub struct MeasureArgs {
    /// Every argument, for options of the example's own.
    pub args: Vec<String>,
    /// The first argument that is a `WxH` size.
    pub size: Option<(u32, u32)>,
    /// The first argument that is a whole number.
    pub number: Option<u32>,
    /// The file after `--write`.
    pub write: Option<PathBuf>,
}

impl MeasureArgs {
    /// The arguments of this process.
    #[must_use]
    pub fn from_env() -> Self {
        Self::parse(std::env::args().skip(1).collect())
    }

    /// Reads `args`.
    #[must_use]
    pub fn parse(args: Vec<String>) -> Self {
        Self {
            size: args.iter().find_map(|a| parse_size(a).ok()),
            number: args.iter().find_map(|a| a.parse().ok()),
            write: write_option(&args).map(Path::to_path_buf),
            args,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneError, load_scene};

    #[test]
    fn sizes_and_scene_errors() {
        assert_eq!(parse_size("800x480"), Ok((800, 480)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        assert_eq!(
            parse_size("800"),
            Err(SizeError::NotWxH {
                value: "800".into()
            })
        );
        for (bad, part) in [
            ("0x10", "0"),
            ("ax4", "a"),
            ("10x", ""),
            ("99999x2", "99999"),
        ] {
            let e = parse_size(bad).unwrap_err();
            assert_eq!(
                e,
                SizeError::BadDimension {
                    value: bad.into(),
                    part: part.into()
                }
            );
            let msg = e.to_string();
            assert!(
                msg.contains("--size") && msg.contains(&format!("`{bad}`")),
                "{msg}"
            );
        }
        let e = load_scene("builtin:nope", 0.0).unwrap_err();
        assert!(
            matches!(&e, SceneError::UnknownBuiltin { name } if name == "nope"),
            "{e}"
        );
        let msg = e.to_string();
        assert!(msg.contains("nope") && msg.contains("hall"), "{msg}");
        let e = load_scene("/no/such/file.aff", 0.0).unwrap_err();
        assert!(
            matches!(&e, SceneError::Aff(a) if a.file == std::path::Path::new("/no/such/file.aff")),
            "{e}"
        );
        assert!(e.to_string().contains("/no/such/file.aff"), "{e}");
    }
}
