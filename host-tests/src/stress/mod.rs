//! The stress cases (run by `raymip-host stress` and the harness's tests):
//! every class of bad input at every API edge of the
//! firmware (and of its C ABI and the harness's scene loader), one row per
//! case with what came back, checked against what the API documents.
//!
//! Classes: NaN, ±inf, ±subnormal, ±0 and ±10³⁰ / ±10⁻³⁰ at the float
//! edges (camera, table triangles, sampler coordinates and lods, the f32
//! baselines); extreme fixed-point bit patterns at the fixed-point edges
//! (table and cone lod, sampler, path state); zero-area, collinear and
//! zero-UV triangles; `Pl` at the top of its range for 10+ bounces; grazing
//! `n·d`; ray-stack overflow; 1×1, 1×4096, 4096×1 and maximum-side
//! textures; pyramid storage one texel too small; bad pointers, sizes,
//! modes and stack lengths through the C ABI; non-finite numbers in a scene
//! file.
//!
//! Each case runs under [`std::panic::catch_unwind`]; its outcome is an
//! error value, a clamp (saturated, clamped or a documented marker) or a
//! plain value, and it *misbehaves* when that outcome is not the documented
//! one (an independent f64 or bit-level expectation) or when data that
//! must survive (table entries, level 0, a too-short buffer, stack
//! entries) changed. [`run`] returns the rows, [`markdown`] the table.

mod c_abi;
mod lod;
mod path;
mod scene;
mod setup;
mod texture;

use std::fmt::{self, Write as _};
use std::panic::{self, AssertUnwindSafe};

use raymip::ffi::RmStatus;

use c_abi::{c_abi, c_abi_lod, c_abi_sample, c_abi_stack};
use lod::{cone_lods, lods, lods_float};
use path::path;
use scene::{render_degenerate, scene_file};
use setup::{camera, table, table_geometry, table_limits};
use texture::{sampler, texture_limits, textures};

/// What a case returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An error value (Rust `Err`, C status, loader error).
    Error,
    /// A saturated, clamped or marker value (documented).
    Clamp,
    /// An ordinary value.
    Value,
}

/// One case of the table.
#[derive(Clone, Debug)]
pub struct Row {
    /// Input class (NaN, zero-area triangle, …).
    pub class: String,
    /// API edge.
    pub edge: &'static str,
    /// The result: `Ok((kind, what came back))`, or `Err(why)` when it was
    /// not the documented outcome or a panic (`panicked` set).
    pub result: Result<(Kind, String), Misbehaviour>,
    /// True when the case panicked.
    pub panicked: bool,
}

/// Totals of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Totals {
    /// Cases run.
    pub cases: usize,
    /// Cases answered with an error value.
    pub errors: usize,
    /// Cases answered with a clamp, saturation or marker.
    pub clamps: usize,
    /// Cases answered with an ordinary value.
    pub values: usize,
    /// Cases whose outcome was not the documented one (or lost data).
    pub misbehaved: usize,
    /// Cases that panicked.
    pub panicked: usize,
}

impl Totals {
    /// Adds up the rows.
    #[must_use]
    pub fn of(rows: &[Row]) -> Self {
        let mut t = Self {
            cases: rows.len(),
            ..Self::default()
        };
        for r in rows {
            match (&r.result, r.panicked) {
                (_, true) => t.panicked += 1,
                (Err(_), false) => t.misbehaved += 1,
                (Ok((Kind::Error, _)), _) => t.errors += 1,
                (Ok((Kind::Clamp, _)), _) => t.clamps += 1,
                (Ok((Kind::Value, _)), _) => t.values += 1,
            }
        }
        t
    }

    /// True when nothing panicked or misbehaved.
    #[must_use]
    pub fn clean(&self) -> bool {
        self.misbehaved == 0 && self.panicked == 0
    }
}

pub(super) type Outcome = Result<(Kind, String), Misbehaviour>;

/// A case whose outcome was not the documented one (or that panicked):
/// what came back instead.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Misbehaviour(pub String);

impl fmt::Display for Misbehaviour {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Misbehaviour {}

impl From<String> for Misbehaviour {
    fn from(s: String) -> Self {
        Self(s)
    }
}

impl From<&str> for Misbehaviour {
    fn from(s: &str) -> Self {
        Self(s.to_string())
    }
}

/// A case's failure: `what` came back instead of the documented outcome.
pub(super) fn bad<T>(what: impl Into<String>) -> Result<T, Misbehaviour> {
    Err(Misbehaviour(what.into()))
}

pub(super) fn err(s: impl Into<String>) -> Outcome {
    Ok((Kind::Error, s.into()))
}
pub(super) fn clamp(s: impl Into<String>) -> Outcome {
    Ok((Kind::Clamp, s.into()))
}
pub(super) fn value(s: impl Into<String>) -> Outcome {
    Ok((Kind::Value, s.into()))
}
/// `err(what)` when a C ABI call returned the documented refusal `want`
/// and `untouched` holds, else a failure naming the status.
pub(super) fn refused(s: RmStatus, want: RmStatus, untouched: bool, what: &str) -> Outcome {
    if s == want && untouched {
        err(what)
    } else {
        bad(format!("{s:?}"))
    }
}
/// `value(ok)` when `got` is within `tol` of the f64 reference `want`, else
/// a failure naming `what` and both numbers.
pub(super) fn near(what: &str, got: f64, want: f64, tol: f64, ok: String) -> Outcome {
    if (got - want).abs() <= tol {
        value(ok)
    } else {
        bad(format!("{what}{got} vs f64 {want}"))
    }
}

#[derive(Default)]
pub(super) struct Runner {
    rows: Vec<Row>,
}

impl Runner {
    pub(super) fn case(
        &mut self,
        class: impl Into<String>,
        edge: &'static str,
        f: impl FnOnce() -> Outcome,
    ) {
        let r = panic::catch_unwind(AssertUnwindSafe(f));
        let (result, panicked) = match r {
            Ok(o) => (o, false),
            Err(p) => {
                let msg = p
                    .downcast_ref::<&str>()
                    .map(|s| (*s).to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "panic".into());
                (bad(format!("panicked: {msg}")), true)
            }
        };
        self.rows.push(Row {
            class: class.into(),
            edge,
            result,
            panicked,
        });
    }
}

/// The float classes: name, f64 value, f32 value (the f32 subnormal is
/// its own: an f64 subnormal is 0 in f32).
pub const FLOAT_CLASSES: [(&str, f64, f32); 11] = [
    ("NaN", f64::NAN, f32::NAN),
    ("+inf", f64::INFINITY, f32::INFINITY),
    ("-inf", f64::NEG_INFINITY, f32::NEG_INFINITY),
    ("+subnormal", 1.0e-310, 1.0e-40),
    ("-subnormal", -1.0e-310, -1.0e-40),
    ("+0", 0.0, 0.0),
    ("-0", -0.0, -0.0),
    ("+1e30", 1.0e30, 1.0e30),
    ("-1e30", -1.0e30, -1.0e30),
    ("+1e-30", 1.0e-30, 1.0e-30),
    ("-1e-30", -1.0e-30, -1.0e-30),
];

/// Runs every case (quiet panic hook while running) and returns the rows.
#[must_use]
pub fn run() -> Vec<Row> {
    let hook = panic::take_hook();
    panic::set_hook(Box::new(|_| {}));
    let mut r = Runner::default();
    camera(&mut r);
    table(&mut r);
    table_geometry(&mut r);
    table_limits(&mut r);
    lods(&mut r);
    cone_lods(&mut r);
    lods_float(&mut r);
    sampler(&mut r);
    path(&mut r);
    textures(&mut r);
    texture_limits(&mut r);
    c_abi(&mut r);
    c_abi_lod(&mut r);
    c_abi_sample(&mut r);
    c_abi_stack(&mut r);
    scene_file(&mut r);
    render_degenerate(&mut r);
    panic::set_hook(hook);
    r.rows
}

/// The table as Markdown (one row per case) and the totals line.
#[must_use]
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::from("| # | class | edge | result | outcome |\n|---|---|---|---|---|\n");
    for (i, r) in rows.iter().enumerate() {
        let (res, out) = match (&r.result, r.panicked) {
            (Err(e), true) => (e.0.clone(), "PANICKED"),
            (Err(e), false) => (e.0.clone(), "MISBEHAVED"),
            (Ok((k, v)), _) => (
                v.clone(),
                match k {
                    Kind::Error => "error value",
                    Kind::Clamp => "clamp",
                    Kind::Value => "value",
                },
            ),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {out} |",
            i + 1,
            r.class,
            r.edge,
            res.replace('|', "\\|")
        );
    }
    s.push('\n');
    s.push_str(&totals_line(&Totals::of(rows)));
    s.push('\n');
    s
}

/// `N cases: … error values, … clamps, … values; … misbehaved, … panicked`.
#[must_use]
pub fn totals_line(t: &Totals) -> String {
    format!(
        "{} cases: {} error values, {} clamps, {} values; {} misbehaved, {} panicked",
        t.cases, t.errors, t.clamps, t.values, t.misbehaved, t.panicked
    )
}

/// Number of distinct API edges in the rows.
#[must_use]
pub fn edges(rows: &[Row]) -> usize {
    let mut e: Vec<&str> = rows.iter().map(|r| r.edge).collect();
    e.sort_unstable();
    e.dedup();
    e.len()
}
