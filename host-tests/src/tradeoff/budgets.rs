//! Instruction counts per call on the targets, read from `BUDGETS.md`
//! (written by `scripts/budgets` from QEMU traces): the target axis of the
//! firmware rows. Fixed-point counts come from the "Instructions per call"
//! table (`min / mean / max` cells: the mean), f32 counts from the "Fixed
//! point beside f32" table (`M4 f32`, `RV32 f32` columns).

use std::collections::HashMap;

/// Mean instructions per call `(Cortex-M4, RV32IMAC)` of each call, fixed
/// point and f32.
#[derive(Clone, Debug, Default)]
pub struct Budgets {
    fixed: HashMap<String, (Option<f64>, Option<f64>)>,
    float: HashMap<String, (Option<f64>, Option<f64>)>,
}

/// The cells of a Markdown table row (`None` for other lines).
fn cells(line: &str) -> Option<Vec<String>> {
    let t = line.trim();
    (t.starts_with('|') && t.ends_with('|') && t.len() > 1).then(|| {
        t[1..t.len() - 1]
            .split('|')
            .map(|c| c.trim().to_string())
            .collect()
    })
}

/// The mean of a `min / mean / max` cell, or a plain number.
fn mean_cell(c: &str) -> Option<f64> {
    let parts: Vec<&str> = c.split('/').map(str::trim).collect();
    match parts.as_slice() {
        [_, mean, _] => mean.parse().ok(),
        [x] => x.parse().ok(),
        _ => None,
    }
}

impl Budgets {
    /// Parses the text of `BUDGETS.md` (unknown layout: no counts).
    #[must_use]
    pub fn parse(text: &str) -> Self {
        let mut b = Self::default();
        let mut header: Option<Vec<String>> = None;
        for line in text.lines() {
            let Some(row) = cells(line) else {
                header = None;
                continue;
            };
            if row
                .iter()
                .all(|c| c.chars().all(|ch| ch == '-' || ch == ':'))
            {
                continue;
            }
            let Some(h) = &header else {
                header = Some(row);
                continue;
            };
            let col = |name: &str| h.iter().position(|c| c == name).and_then(|i| row.get(i));
            let pair = |a: &str, r: &str| {
                (
                    col(a).and_then(|c| mean_cell(c)),
                    col(r).and_then(|c| mean_cell(c)),
                )
            };
            if h.first().is_some_and(|c| c == "call") {
                if h.iter().any(|c| c == "Cortex-M4") {
                    b.fixed
                        .entry(row[0].clone())
                        .or_insert(pair("Cortex-M4", "RV32IMAC"));
                } else if h.iter().any(|c| c == "M4 f32") {
                    b.float.insert(row[0].clone(), pair("M4 f32", "RV32 f32"));
                }
            }
        }
        b
    }

    /// Reads `path` (missing file: no counts).
    #[must_use]
    pub fn load(path: &std::path::Path) -> Self {
        std::fs::read_to_string(path).map_or_else(|_| Self::default(), |t| Self::parse(&t))
    }

    /// `(M4, RV32)` mean instructions of `call`, fixed point or f32.
    #[must_use]
    pub fn get(&self, call: &str, f32: bool) -> (Option<f64>, Option<f64>) {
        let m = if f32 { &self.float } else { &self.fixed };
        m.get(call).copied().unwrap_or((None, None))
    }

    /// Fills the instruction columns of every row that names a call.
    pub fn apply(&self, rows: &mut [super::Row]) {
        for r in rows {
            if let Some((call, f32)) = &r.budget_call {
                (r.instructions_m4, r.instructions_rv32) = self.get(call, *f32);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_both_tables() {
        let text = "\
| call | Cortex-M4 | RV32IMAC | goal |
|---|---|---|---|
| table lod | 25 / 27.8 / 28 | 45 / 46.9 / 47 | x |

| call | M4 fixed | M4 f32 | ratio | RV32 fixed | RV32 f32 | ratio |
|---|---|---|---|---|---|---|
| table lod | 27.8 | 59.0 | 2.12 | 46.9 | 1884.5 | 40.20 |
";
        let b = Budgets::parse(text);
        assert_eq!(b.get("table lod", false), (Some(27.8), Some(46.9)));
        assert_eq!(b.get("table lod", true), (Some(59.0), Some(1884.5)));
        assert_eq!(b.get("cone lod", false), (None, None));
    }
}
