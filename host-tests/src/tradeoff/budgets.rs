//! Instruction counts per call on the targets, read from `BUDGETS.md`
//! (written by `scripts/budgets` from QEMU traces): the target axis of the
//! firmware rows. Fixed-point counts come from the "Instructions per call"
//! table (`min / mean / max` cells: the mean), f32 counts from the "Fixed
//! point beside f32" table (`M4 f32`, `RV32 f32` columns), PicoRV32
//! cycles from the soft-core table (`cycles` column).
//!
//! The cost of a frame's texture work is here too ([`frame_calls`],
//! [`Budgets::frame_cost`]): the counted firmware calls of a render times
//! these per-call counts (the trade-off's frame chart and the worksheet of
//! docs/integration.md).

use std::collections::HashMap;

use raymip::texture::Mode;

use crate::render::texunit::Filter;
use crate::render::{Counters, Method};

/// Mean instructions per call `(Cortex-M4, RV32IMAC)` of each call, fixed
/// point and f32, and mean PicoRV32 cycles per call (fixed point).
#[derive(Clone, Debug, Default)]
pub struct Budgets {
    fixed: HashMap<String, (Option<f64>, Option<f64>)>,
    float: HashMap<String, (Option<f64>, Option<f64>)>,
    cycles: HashMap<String, f64>,
}

/// One firmware call of a frame: its BUDGETS.md row and how many times the
/// frame makes it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Call {
    /// The call's name in BUDGETS.md (`table lod`, `trilinear sample`, …).
    pub name: &'static str,
    /// Calls in the frame (from the renderer's counters).
    pub count: u64,
}

/// What a frame's texture work costs a controller.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameCost {
    /// Cortex-M4 instructions (`None` when a call has no count).
    pub m4: Option<f64>,
    /// PicoRV32 cycles (`None` when a call has no soft-core row, and for
    /// f32 counts, which the soft core does not have).
    pub picorv32: Option<f64>,
}

/// The firmware calls of one frame's texture work for `method` and
/// `filter`, counted by the renderer (`c`):
///
/// - the lod per textured hit: `table lod`, `cone lod (with n·d)`; none
///   for `mip0` (lod 0);
/// - ray differentials (`raydiff`): the primary set-up per path, the
///   transfer per hit, a reflection or refraction per continuation, and
///   the footprint and its lod per textured hit;
/// - G-buffer ray differentials (`gbuffer`): the same, but the first hit
///   of each path takes the G-buffer set-up instead of a transfer;
/// - the sample per isotropic sample (`bilinear sample`, `trilinear
///   sample`: the filter stage's call of the mode).
///
/// Tracing, shading and the path-state update per segment (the same for
/// every method) are not texture work and not counted. `None` for a filter
/// whose sample BUDGETS.md does not count (nearest, the stochastic modes)
/// and for the supersampled ground truth.
#[must_use]
pub fn frame_calls(method: Method, filter: Filter, c: &Counters) -> Option<Vec<Call>> {
    let mode = match filter {
        Filter::Trilinear => Mode::Trilinear,
        Filter::Bilinear | Filter::BilinearLevel0 => Mode::BilinearNearestLevel,
        Filter::Nearest | Filter::Stochastic(_) => return None,
    };
    let sample = super::filter_stage::budget_call(mode, false)?;
    let call = |name, count| Call { name, count };
    let mut calls = match method {
        Method::Table => vec![call("table lod", c.textured_hits)],
        Method::Cone => vec![call("cone lod (with n·d)", c.textured_hits)],
        Method::Raydiff => vec![
            call("primary set-up from the camera", c.paths),
            call("transfer to a hit", c.hits),
            call("reflection (shading-normal differentials)", c.reflections),
            call("refraction (shading-normal differentials)", c.refractions),
            call("footprint (two texel-space axes)", c.textured_hits),
            call("lod from the footprint (larger axis)", c.textured_hits),
        ],
        Method::Gbuffer => {
            let first = c.depth_hist.first().copied().unwrap_or(0);
            vec![
                call("primary set-up from the camera", c.paths),
                call("G-buffer first-hit set-up (four neighbours)", first),
                call("transfer to a hit", c.hits.saturating_sub(first)),
                call("reflection (shading-normal differentials)", c.reflections),
                call("refraction (shading-normal differentials)", c.refractions),
                call("footprint (two texel-space axes)", c.textured_hits),
                call("lod from the footprint (larger axis)", c.textured_hits),
            ]
        }
        Method::Mip0 => Vec::new(),
        Method::Truth => return None,
    };
    calls.push(call(sample, c.samples));
    Some(calls)
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
                } else if let Some(c) = col("cycles").and_then(|c| mean_cell(c)) {
                    b.cycles.entry(row[0].clone()).or_insert(c);
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

    /// Mean PicoRV32 cycles of `call` (fixed point).
    #[must_use]
    pub fn cycles(&self, call: &str) -> Option<f64> {
        self.cycles.get(call).copied()
    }

    /// `Σ count × per-call count` of `calls` on the Cortex-M4 and the
    /// PicoRV32; with `f32`, the f32 twins' M4 counts (and no PicoRV32
    /// cycles).
    #[must_use]
    pub fn frame_cost(&self, calls: &[Call], f32: bool) -> FrameCost {
        let total = |per: &dyn Fn(&str) -> Option<f64>| {
            calls
                .iter()
                .map(|c| per(c.name).map(|n| c.count as f64 * n))
                .sum::<Option<f64>>()
        };
        FrameCost {
            m4: total(&|n| self.get(n, f32).0),
            picorv32: if f32 {
                None
            } else {
                total(&|n| self.cycles(n))
            },
        }
    }

    /// Fills the instruction columns of every row that names a call, and
    /// the frame cost of every frame row with counted calls.
    pub fn apply(&self, rows: &mut [super::Row]) {
        for r in rows {
            if let Some((call, f32)) = &r.budget_call {
                (r.instructions_m4, r.instructions_rv32) = self.get(call, *f32);
            }
            if let Some((calls, f32)) = &r.frame_calls {
                let c = self.frame_cost(calls, *f32);
                (r.frame_m4, r.frame_picorv32) = (c.m4, c.picorv32);
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

    #[test]
    fn frame_cost_is_counted_calls_times_budgets() {
        let text = "\
| call | Cortex-M4 | RV32IMAC |
|---|---|---|
| table lod | 27 / 28.0 / 29 | 46 / 46.0 / 46 |
| trilinear sample | 240 / 240.0 / 240 | 322 / 322.0 / 322 |

| call | M4 fixed | M4 f32 | ratio | RV32 fixed | RV32 f32 | ratio |
|---|---|---|---|---|---|---|
| table lod | 28.0 | 59.0 | 2.11 | 46.0 | 1884.5 | 40.97 |
| trilinear sample | 240.0 | 693.6 | 2.89 | 322.0 | 9494.1 | 29.48 |

| call | cycles | instructions | CPI |
|---|---|---|---|
| table lod | 218 / 218.5 / 222 | 48 / 48.0 / 48 | 4.55 |
| trilinear sample | 1690 / 1690.0 / 1690 | 330 / 330.0 / 330 | 5.12 |

| call | cycles without | cycles with co-processor |
|---|---|---|
| table lod | 218.2 | 38 / 38.0 / 38 |
";
        let b = Budgets::parse(text);
        assert_eq!(b.cycles("table lod"), Some(218.5));
        let c = Counters {
            textured_hits: 1000,
            samples: 1000,
            hits: 1500,
            ..Counters::default()
        };
        let calls = frame_calls(Method::Table, Filter::Trilinear, &c).unwrap();
        assert_eq!(
            calls,
            [
                Call {
                    name: "table lod",
                    count: 1000
                },
                Call {
                    name: "trilinear sample",
                    count: 1000
                }
            ]
        );
        // 1000 · (28 + 240) instructions, 1000 · (218.5 + 1690) cycles.
        let fixed = b.frame_cost(&calls, false);
        assert_eq!(fixed.m4, Some(268_000.0));
        assert_eq!(fixed.picorv32, Some(1_908_500.0));
        // f64 rows cost what the f32 twins cost: 1000 · (59 + 693.6).
        let f32 = b.frame_cost(&calls, true);
        assert!((f32.m4.unwrap() - 752_600.0).abs() < 1e-6);
        assert_eq!(f32.picorv32, None);
        // mip0 has no lod call; nearest and stochastic samples are not counted.
        assert_eq!(
            frame_calls(Method::Mip0, Filter::Bilinear, &c).map(|v| v.len()),
            Some(1)
        );
        assert_eq!(frame_calls(Method::Table, Filter::Nearest, &c), None);
        // A call without a row: no cost.
        let cone = frame_calls(Method::Cone, Filter::Trilinear, &c).unwrap();
        assert_eq!(b.frame_cost(&cone, false), FrameCost::default());
    }
}
