//! The harness's shared error pieces: an I/O failure on a named file
//! ([`FileError`]), which the output, scene and measurement modules wrap
//! in their own error enums so that every message names the file.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// What the harness was doing with a file when the I/O error happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileOp {
    /// Opening or reading the file.
    Read,
    /// Creating or writing the file.
    Write,
}

/// An I/O error on a named file.
#[derive(Debug)]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// Reading or writing.
    pub op: FileOp,
    /// The operating system's error.
    pub source: io::Error,
}

impl FileError {
    /// A read error on `path`.
    pub fn read(path: &Path, source: io::Error) -> Self {
        Self {
            path: path.to_path_buf(),
            op: FileOp::Read,
            source,
        }
    }

    /// A write error on `path`.
    pub fn write(path: &Path, source: io::Error) -> Self {
        Self {
            path: path.to_path_buf(),
            op: FileOp::Write,
            source,
        }
    }
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.op {
            FileOp::Read => "cannot read",
            FileOp::Write => "cannot write",
        };
        write!(f, "{}: {what}: {}", self.path.display(), self.source)
    }
}

impl std::error::Error for FileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}
