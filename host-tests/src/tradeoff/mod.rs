//! Run time against error (`raymip-host tradeoff`): every LOD method and
//! precision, every texture filter and whole frames, each configuration
//! timed on the host (and, for the firmware stages, counted on the targets
//! from `BUDGETS.md`) and measured against its f64 reference or the
//! supersampled ground truth; Pareto fronts and charts.
//!
//! One file per concept: [`timing`] (ns per call), [`log2fx`] (the
//! fixed-point variants), [`lod_stage`], [`filter_stage`], [`frame_stage`]
//! (the three stages), [`convergence`] (stochastic filtering over
//! frames), [`budgets`] (instruction counts), [`pareto`] (fronts),
//! [`chart`] (plotters), [`report`] (JSON, Markdown, generated blocks).

use std::path::PathBuf;

use serde::Serialize;

pub mod budgets;
pub mod chart;
pub mod convergence;
mod error;
pub mod filter_stage;
pub mod frame_stage;
pub mod lod_stage;
pub mod log2fx;
pub mod pareto;
pub mod report;
pub mod timing;

pub use error::TradeoffError;

/// The stage a configuration belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    /// Level of detail per hit (error in levels vs f64).
    Lod,
    /// Texture filter per sample (error in LSB vs the exact f64 filter).
    Filter,
    /// Whole frame (error in LSB and PSNR vs ground truth).
    Frame,
}

impl Stage {
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Lod => "lod",
            Self::Filter => "filter",
            Self::Frame => "frame",
        }
    }
}

/// One measured configuration (one element of `tradeoff.json`).
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Stage.
    pub stage: Stage,
    /// Scene (frame rows).
    pub scene: Option<String>,
    /// LOD method (`sample` for filter rows).
    pub method: String,
    /// Arithmetic (`fixed accurate`, `f32 libm`, …).
    pub precision: String,
    /// Texture filter (filter and frame rows).
    pub filter: Option<String>,
    /// Frames averaged (1, or the accumulation of stochastic rows).
    pub frames: u32,
    /// Host ns per call (LOD, filter rows).
    pub time_ns: Option<f64>,
    /// Host ms per frame (frame rows).
    pub time_ms: Option<f64>,
    /// Mean instructions per call on Cortex-M4 (BUDGETS.md), where counted.
    pub instructions_m4: Option<f64>,
    /// Mean instructions per call on RV32IMAC (BUDGETS.md), where counted.
    pub instructions_rv32: Option<f64>,
    /// Largest absolute error (unit: `error_unit`).
    pub error_max: f64,
    /// RMS error (unit: `error_unit`).
    pub error_rms: f64,
    /// Filter rows: largest error against the exact f64 filter of the
    /// row's own filter (its expectation for a stochastic one), LSB; the
    /// implementation error, where `error_max` is the distance to the
    /// trilinear target.
    pub own_error_max: Option<f64>,
    /// Filter rows: RMS error against the exact f64 filter of the row's
    /// own filter, LSB.
    pub own_error_rms: Option<f64>,
    /// `levels` (LOD) or `LSB` (8-bit channel values).
    pub error_unit: &'static str,
    /// Frame PSNR vs the supersampled ground truth (dB).
    pub psnr_truth_db: Option<f64>,
    /// Frame PSNR vs the f64 render of the same method (dB; for
    /// stochastic filters: its deterministic expectation).
    pub psnr_float_db: Option<f64>,
    /// On the Pareto front of its stage (and scene): no other
    /// configuration is both faster and more accurate.
    pub pareto: bool,
    /// Frame rows: Cortex-M4 instructions of the frame's texture work
    /// (`frame_calls` × BUDGETS.md per call; f64 rows at their f32 twins'
    /// counts), where BUDGETS.md counts every call.
    pub frame_m4: Option<f64>,
    /// Frame rows: PicoRV32 cycles of the same calls (fixed point only).
    pub frame_picorv32: Option<f64>,
    /// Frame rows: on the Pareto front of M4 cost per frame against PSNR
    /// among the rows of its scene that have a cost.
    pub pareto_cost: bool,
    /// The BUDGETS.md call and whether its f32 column applies.
    #[serde(skip)]
    pub budget_call: Option<(String, bool)>,
    /// Frame rows: the firmware calls the render counted, and whether the
    /// f32 counts apply (f64 rows).
    #[serde(skip)]
    pub frame_calls: Option<(Vec<budgets::Call>, bool)>,
}

impl Row {
    /// A row with the given identity and errors; the rest empty.
    #[must_use]
    pub fn new(
        stage: Stage,
        method: &str,
        precision: &str,
        max: f64,
        rms: f64,
        unit: &'static str,
    ) -> Self {
        Self {
            stage,
            scene: None,
            method: method.to_string(),
            precision: precision.to_string(),
            filter: None,
            frames: 1,
            time_ns: None,
            time_ms: None,
            instructions_m4: None,
            instructions_rv32: None,
            error_max: max,
            error_rms: rms,
            own_error_max: None,
            own_error_rms: None,
            error_unit: unit,
            psnr_truth_db: None,
            psnr_float_db: None,
            pareto: false,
            frame_m4: None,
            frame_picorv32: None,
            pareto_cost: false,
            budget_call: None,
            frame_calls: None,
        }
    }

    /// Short label of the configuration in the charts.
    #[must_use]
    pub fn label(&self) -> String {
        let mut s = match self.stage {
            Stage::Lod => format!("{} {}", self.method, self.precision),
            Stage::Filter => format!(
                "{} {}",
                self.filter.as_deref().unwrap_or(""),
                short(&self.precision)
            ),
            Stage::Frame => format!(
                "{} {} {}",
                self.method,
                short(&self.precision),
                self.filter.as_deref().unwrap_or("")
            ),
        };
        if self.frames > 1 {
            s += &format!(" ×{}", self.frames);
        }
        s
    }

    /// Host time in the stage's unit (ns per call or ms per frame).
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time_ns.or(self.time_ms).unwrap_or(f64::NAN)
    }
}

fn short(precision: &str) -> &str {
    match precision {
        "fixed accurate" => "fixed",
        "f32 libm" => "f32",
        p => p,
    }
}

/// `(max |e|, RMS e)` of a series of errors (NaN counts as infinite).
pub fn error_stats(errors: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut max, mut sq, mut n) = (0.0f64, 0.0, 0usize);
    for e in errors {
        let a = if e.is_nan() { f64::INFINITY } else { e.abs() };
        max = max.max(a);
        sq += a * a;
        n += 1;
    }
    (max, if n == 0 { 0.0 } else { (sq / n as f64).sqrt() })
}

/// What to measure and how long.
#[derive(Clone, Debug)]
pub struct Settings {
    /// LOD inputs per configuration.
    pub lod_inputs: usize,
    /// Filter inputs per configuration.
    pub filter_inputs: usize,
    /// Level-0 edge of the filter test texture.
    pub texture_size: u32,
    /// Timed passes (the median is kept).
    pub repeats: usize,
    /// Frames averaged for the accumulated stochastic rows.
    pub accumulate: u32,
    /// Frames averaged for the accumulated stochastic frame rows.
    pub frame_accumulate: u32,
    /// Frames of the convergence curves (1..=this).
    pub convergence_frames: u32,
    /// Frame-stage scenes (`builtin:…`, an `.aff` file or a BART folder).
    pub scenes: Vec<String>,
    /// Frame size.
    pub size: (u32, u32),
    /// Ground-truth samples per pixel.
    pub spp: u32,
    /// Reflection/refraction bounces.
    pub bounces: u8,
    /// Renders per frame configuration (the median time is kept).
    pub frame_repeats: usize,
    /// Show progress bars.
    pub progress: bool,
}

impl Settings {
    /// The full run (`quick = false`) or the CI-sized one, over `scenes`.
    #[must_use]
    pub fn new(quick: bool, scenes: Vec<String>) -> Self {
        if quick {
            Self {
                lod_inputs: 512,
                filter_inputs: 512,
                texture_size: 16,
                repeats: 5,
                accumulate: 16,
                frame_accumulate: 4,
                convergence_frames: 16,
                scenes,
                size: (40, 24),
                spp: 4,
                bounces: 2,
                frame_repeats: 1,
                progress: false,
            }
        } else {
            Self {
                lod_inputs: 4096,
                filter_inputs: 4096,
                texture_size: 64,
                repeats: 41,
                accumulate: 64,
                frame_accumulate: 16,
                convergence_frames: 64,
                scenes,
                size: (320, 192),
                spp: 64,
                bounces: 4,
                frame_repeats: 3,
                progress: true,
            }
        }
    }
}

/// The default frame-stage scenes: the built-in hall and mirrors, and the
/// BART kitchen and robots under `bart` when they are there.
#[must_use]
pub fn default_scenes(bart: &std::path::Path) -> Vec<String> {
    let mut s = vec!["builtin:hall".to_string(), "builtin:mirrors".to_string()];
    for name in ["kitchen", "robots"] {
        let p: PathBuf = bart.join(name);
        if p.is_dir() {
            s.push(p.to_string_lossy().into_owned());
        }
    }
    s
}
