//! Located loader errors: every error names a file and (where there is one)
//! a 1-based line, and the chain of includes that led there.

use std::fmt;
use std::path::PathBuf;

use crate::scene::ppm::PpmError;

/// What went wrong (the location is in [`AffError`]).
#[derive(Debug)]
#[non_exhaustive]
pub enum AffErrorKind {
    /// The file itself could not be read (the top-level file, or a folder
    /// scanned by [`find_top_level`](super::find_top_level)).
    Io(std::io::Error),
    /// `i LEVEL NAME` names a file that cannot be read.
    MissingInclude {
        /// The name as written.
        name: String,
        /// The resolved path.
        path: PathBuf,
        /// Why it could not be read.
        source: std::io::Error,
    },
    /// A texture named by `texturecoords … TEX` / `tt TEX` could not be
    /// read or is not a valid P6 file.
    Texture {
        /// The name as written.
        name: String,
        /// The PPM reader's error (names the PPM file and its header line).
        source: PpmError,
    },
    /// The file ended inside a record.
    UnexpectedEof {
        /// What the record still needed.
        expected: String,
    },
    /// A field that should be a number (or count/index) is not one.
    BadNumber {
        /// The token found (lossy UTF-8).
        token: String,
        /// What was expected there.
        expected: String,
    },
    /// A command character the format does not define.
    UnknownCommand(String),
    /// Any other malformed record (wrong keyword, index out of range,
    /// unbalanced braces, bad count, …).
    Syntax(String),
    /// No top-level `.aff` (or more than one) in a scene folder.
    TopLevel(String),
}

/// A loader error located at `file:line`.
///
/// `Display` is `file:line: message` (just `file: message` when `line` is 0,
/// i.e. when the problem is the file as a whole), followed by
/// `(included from a.aff:12, …)` when the file was reached through includes.
#[derive(Debug)]
pub struct AffError {
    /// The file the problem is in.
    pub file: PathBuf,
    /// 1-based line; 0 when the error concerns the whole file.
    pub line: usize,
    /// What went wrong (boxed to keep `Result<_, AffError>` small).
    pub kind: Box<AffErrorKind>,
    /// Include chain, innermost first: the `i` records that led to `file`.
    pub included_from: Vec<(PathBuf, usize)>,
}

impl AffError {
    pub(crate) fn new(file: impl Into<PathBuf>, line: usize, kind: AffErrorKind) -> Self {
        Self {
            file: file.into(),
            line,
            kind: Box::new(kind),
            included_from: Vec::new(),
        }
    }
}

impl fmt::Display for AffErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => write!(f, "cannot read: {e}"),
            Self::MissingInclude { name, path, source } => {
                write!(f, "cannot include {name:?} ({}): {source}", path.display())
            }
            Self::Texture { name, source } => write!(f, "texture {name:?}: {source}"),
            Self::UnexpectedEof { expected } => {
                write!(f, "unexpected end of file: expected {expected}")
            }
            Self::BadNumber { token, expected } => {
                write!(f, "expected {expected}, found {token:?}")
            }
            Self::UnknownCommand(c) => write!(f, "unknown command {c:?}"),
            Self::Syntax(m) | Self::TopLevel(m) => f.write_str(m),
        }
    }
}

impl fmt::Display for AffError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.file.display(), self.kind)?;
        } else {
            write!(f, "{}:{}: {}", self.file.display(), self.line, self.kind)?;
        }
        for (i, (file, line)) in self.included_from.iter().enumerate() {
            let sep = if i == 0 { " (included from " } else { ", " };
            write!(f, "{sep}{}:{line}", file.display())?;
        }
        if !self.included_from.is_empty() {
            f.write_str(")")?;
        }
        Ok(())
    }
}

impl std::error::Error for AffError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &*self.kind {
            AffErrorKind::Io(e) | AffErrorKind::MissingInclude { source: e, .. } => Some(e),
            AffErrorKind::Texture { source, .. } => Some(source),
            _ => None,
        }
    }
}
