//! `raymip-host stress`: runs the stress cases ([`crate::stress`]), prints
//! their table and totals, writes the totals into docs/reliability.md on
//! request, and fails when any case panicked or misbehaved.

use std::fmt;
use std::path::Path;

use crate::output::OutputError;
use crate::output::report::write_between_markers;
use crate::stress::{Row, Totals, edges, markdown, run, totals_line};

/// Why `stress` failed.
#[derive(Debug)]
pub enum StressError {
    /// Cases panicked or misbehaved.
    Misbehaved {
        /// Cases whose outcome was not the documented one.
        misbehaved: usize,
        /// Cases that panicked.
        panicked: usize,
        /// Each such case: `edge / class: what came back`.
        cases: Vec<String>,
    },
    /// The docs/reliability.md block could not be written (names the file).
    Output(OutputError),
}

impl fmt::Display for StressError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Misbehaved {
                misbehaved,
                panicked,
                cases,
            } => write!(
                f,
                "stress: {misbehaved} misbehaved, {panicked} panicked:\n{}",
                cases.join("\n")
            ),
            Self::Output(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for StressError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Misbehaved { .. } => None,
            Self::Output(e) => Some(e),
        }
    }
}

impl From<OutputError> for StressError {
    fn from(e: OutputError) -> Self {
        Self::Output(e)
    }
}

/// `raymip-host stress`: prints the table and the totals; with `readme`,
/// also writes the totals between `<!-- stress:begin -->` and
/// `<!-- stress:end -->` of that file. Err (non-zero exit) when anything
/// panicked or misbehaved.
///
/// # Errors
/// A panicked or misbehaving case (named), or the docs/reliability.md block not written.
pub fn cmd_stress(readme: Option<&Path>) -> Result<(), StressError> {
    let rows = run();
    print!("{}", markdown(&rows));
    if let Some(path) = readme {
        write_readme(&rows, path)?;
    }
    verdict(&rows)
}

/// `stress --write-readme PATH` without the table on stdout (the test that
/// the docs/reliability.md block is current).
///
/// # Errors
/// As [`cmd_stress`].
pub fn cmd_stress_quiet(readme: &Path) -> Result<(), StressError> {
    let rows = run();
    write_readme(&rows, readme)?;
    verdict(&rows)
}

fn write_readme(rows: &[Row], path: &Path) -> Result<(), OutputError> {
    let text = format!(
        "Measured by `raymip-host stress --write-readme docs/reliability.md` ({} {}): {} API edges, **{}**.\n",
        std::env::consts::ARCH,
        std::env::consts::OS,
        edges(rows),
        totals_line(&Totals::of(rows))
    );
    write_between_markers(path, "stress", &text)
}

fn verdict(rows: &[Row]) -> Result<(), StressError> {
    let t = Totals::of(rows);
    if t.clean() {
        Ok(())
    } else {
        let bad: Vec<String> = rows
            .iter()
            .filter(|r| r.result.is_err())
            .map(|r| {
                format!(
                    "{} / {}: {}",
                    r.edge,
                    r.class,
                    r.result.as_ref().err().map_or("", |e| e.0.as_str())
                )
            })
            .collect();
        Err(StressError::Misbehaved {
            misbehaved: t.misbehaved,
            panicked: t.panicked,
            cases: bad,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stress::Kind;

    #[test]
    fn verdict_names_each_misbehaving_case() {
        let row = |class: &str, result| Row {
            class: class.into(),
            edge: "PbTable::update",
            result,
            panicked: false,
        };
        let rows = [
            row("NaN", Ok((Kind::Error, "NonFinite".into()))),
            row("huge", Err("entry 99 outside [-64, 64]".into())),
        ];
        let e = verdict(&rows).unwrap_err();
        assert!(
            matches!(
                &e,
                StressError::Misbehaved {
                    misbehaved: 1,
                    panicked: 0,
                    ..
                }
            ),
            "{e:?}"
        );
        let text = e.to_string();
        assert!(
            text.contains("PbTable::update / huge: entry 99 outside [-64, 64]"),
            "{text}"
        );
        assert!(verdict(&rows[..1]).is_ok());
    }
}
