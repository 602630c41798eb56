//! JSON and text reports, and the generated blocks of README-style pages
//! (`<!-- NAME:begin -->` … `<!-- NAME:end -->`).

use std::fs;
use std::path::Path;

use super::OutputError;
use crate::error::FileError;

/// Writes `value` (a `serde_json::Value` or any serialisable type) as
/// pretty JSON.
///
/// # Errors
/// When the value cannot be serialised or the file written.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<(), OutputError> {
    let s = serde_json::to_string_pretty(value).map_err(|source| OutputError::Json {
        path: path.to_path_buf(),
        source,
    })?;
    fs::write(path, s + "\n").map_err(|e| FileError::write(path, e).into())
}

/// Writes text.
///
/// # Errors
/// When the file cannot be written.
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    fs::write(path, text).map_err(|e| FileError::write(path, e).into())
}

/// The trimmed cells of one Markdown table row (`| a | b |` → `["a", "b"]`).
#[must_use]
pub fn markdown_cells(line: &str) -> Vec<String> {
    line.trim()
        .trim_matches('|')
        .split('|')
        .map(|c| c.trim().to_string())
        .collect()
}

/// Replaces the text between the lines `<!-- NAME:begin -->` and
/// `<!-- NAME:end -->` of the file `path` (a README) with `text`: how the
/// measurement commands write their tables.
///
/// # Errors
/// When the file cannot be read or written or lacks the markers.
pub fn write_between_markers(path: &Path, name: &str, text: &str) -> Result<(), OutputError> {
    let begin = format!("<!-- {name}:begin -->");
    let end = format!("<!-- {name}:end -->");
    let old = std::fs::read_to_string(path).map_err(|e| FileError::read(path, e))?;
    let (Some(b), Some(e)) = (old.find(&begin), old.find(&end)) else {
        return Err(OutputError::MissingMarkers {
            path: path.to_path_buf(),
            name: name.to_string(),
        });
    };
    if e < b {
        return Err(OutputError::MarkersOutOfOrder {
            path: path.to_path_buf(),
            name: name.to_string(),
        });
    }
    let new = format!("{}{begin}\n{text}{}", &old[..b], &old[e..]);
    std::fs::write(path, new).map_err(|e| FileError::write(path, e).into())
}

/// The file named after `--write` in a measurement command's arguments.
#[must_use]
pub fn write_option(args: &[String]) -> Option<&Path> {
    args.iter()
        .position(|a| a == "--write")
        .and_then(|i| args.get(i + 1))
        .map(Path::new)
}

/// Prints the Markdown `table` of a measurement and, when `write` names a
/// file (`--write FILE`), replaces its `NAME` block with it
/// ([`write_between_markers`]).
///
/// # Errors
/// As [`write_between_markers`].
pub fn publish(table: &str, write: Option<&Path>, name: &str) -> Result<(), OutputError> {
    print!("{table}");
    if let Some(path) = write {
        write_between_markers(path, name, table)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markers_missing_or_out_of_order() {
        let dir = std::env::temp_dir().join(format!("raymip-markers-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let readme = dir.join("README.md");
        std::fs::write(&readme, "no markers\n").unwrap();
        let e = write_between_markers(&readme, "stress", "x").unwrap_err();
        assert!(
            matches!(&e, OutputError::MissingMarkers { name, .. } if name == "stress"),
            "{e}"
        );
        assert!(
            e.to_string()
                .contains("README.md: markers <!-- stress:begin -->"),
            "{e}"
        );
        std::fs::write(&readme, "<!-- stress:end -->\n<!-- stress:begin -->\n").unwrap();
        let e = write_between_markers(&readme, "stress", "x").unwrap_err();
        assert!(matches!(&e, OutputError::MarkersOutOfOrder { .. }), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
