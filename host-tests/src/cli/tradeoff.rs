//! `tradeoff`: run time against error for every LOD method and precision,
//! every filter and whole frames (see `crate::tradeoff`); writes
//! `tradeoff.json` (one object per configuration), `tradeoff.md`, the
//! Pareto charts (`pareto-lod`, `pareto-texture`, `pareto-frame`) and the
//! stochastic convergence chart as PNG and SVG, and with `--publish` the
//! generated blocks of BENCHMARKS.md and docs/tradeoff.md and the charts in
//! `docs/tradeoff/`.

use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressStyle};

use crate::error::FileError;
use crate::output::machine::machine_line;
use crate::output::report::{write_between_markers, write_json, write_text};
use crate::tradeoff::budgets::Budgets;
use crate::tradeoff::report;
use crate::tradeoff::{
    Row, Settings, TradeoffError, convergence, filter_stage, frame_stage, lod_stage, pareto,
};

/// What `tradeoff` does.
#[derive(Clone, Debug)]
pub struct Args {
    /// Output folder.
    pub out: PathBuf,
    /// CI-sized run (a few seconds).
    pub quick: bool,
    /// Frame-stage scenes (empty: the defaults, see
    /// [`crate::tradeoff::default_scenes`]).
    pub scenes: Vec<String>,
    /// BART folder for the default scenes.
    pub bart: PathBuf,
    /// Frame size override.
    pub size: Option<(u32, u32)>,
    /// Project root whose BENCHMARKS.md, docs/tradeoff.md and docs/tradeoff/
    /// `--publish` writes (`None`: no publishing).
    pub publish: Option<PathBuf>,
}

fn bar(len: u64, show: bool) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::new(len);
    b.set_style(
        ProgressStyle::with_template(
            "{msg:24} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    b
}

/// Measures every stage.
fn measure(s: &Settings) -> Result<(Vec<Row>, Vec<convergence::Curve>), TradeoffError> {
    let per_scene = frame_stage::renders_per_scene(s);
    let total = 4 + 3 + per_scene * s.scenes.len() as u64 + convergence::renders(s);
    let b = bar(total, s.progress);
    let tick = || b.inc(1);
    b.set_message("LOD per hit");
    let mut rows = lod_stage::rows(s, &tick);
    b.set_message("filter per sample");
    rows.extend(filter_stage::rows(s, &tick));
    b.set_message("whole frames");
    rows.extend(frame_stage::rows(s, &tick)?);
    b.set_message("stochastic convergence");
    let curves = convergence::curves(s, &tick)?;
    b.finish_and_clear();
    Ok((rows, curves))
}

/// Copies the charts to `root/docs/tradeoff/` and writes the `tradeoff`
/// blocks of `root/BENCHMARKS.md` and `root/docs/tradeoff.md`.
fn publish(
    root: &Path,
    out: &Path,
    rows: &[Row],
    curves: &[convergence::Curve],
    m: &str,
    s: &Settings,
) -> Result<(), TradeoffError> {
    let docs = root.join("docs/tradeoff");
    std::fs::create_dir_all(&docs).map_err(|e| FileError::write(&docs, e))?;
    for stem in report::CHARTS {
        for ext in ["png", "svg"] {
            let name = format!("{stem}.{ext}");
            let to = docs.join(&name);
            std::fs::copy(out.join(&name), &to).map_err(|e| FileError::write(&to, e))?;
        }
    }
    let cmd = "bash scripts/tradeoff";
    let body = report::markdown(rows, curves, m, s.accumulate, "docs/tradeoff/", cmd);
    write_between_markers(&root.join("BENCHMARKS.md"), "tradeoff", &body)?;
    let readme = format!(
        "Machine: {}. Written by `{cmd}`; tables in [BENCHMARKS.md](../BENCHMARKS.md).\n\n{}\n![LOD per hit](tradeoff/pareto-lod.png)\n\n![Filter per sample](tradeoff/pareto-texture.png)\n\n![Whole frame](tradeoff/pareto-frame.png)\n\n![Stochastic convergence](tradeoff/stochastic-convergence.png)\n",
        m,
        report::headlines(rows, s.accumulate)
    );
    Ok(write_between_markers(
        &root.join("docs/tradeoff.md"),
        "tradeoff",
        &readme,
    )?)
}

/// `tradeoff`: measures, writes the files into `args.out`, publishes when
/// asked. Returns the rows.
///
/// # Errors
/// A scene that cannot be loaded, an unwritable output, missing markers.
pub fn cmd_tradeoff(args: &Args) -> Result<Vec<Row>, TradeoffError> {
    let out = &args.out;
    std::fs::create_dir_all(out).map_err(|e| FileError::write(out, e))?;
    let scenes = if args.scenes.is_empty() {
        if args.quick {
            vec!["builtin:hall".to_string()]
        } else {
            crate::tradeoff::default_scenes(&args.bart)
        }
    } else {
        args.scenes.clone()
    };
    let mut s = Settings::new(args.quick, scenes);
    if let Some(sz) = args.size {
        s.size = sz;
    }
    let (mut rows, curves) = measure(&s)?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    Budgets::load(&args.publish.clone().unwrap_or(root).join("BUDGETS.md")).apply(&mut rows);
    pareto::mark(&mut rows);
    let m = machine_line();
    write_json(&out.join("tradeoff.json"), &rows)?;
    write_json(&out.join("stochastic-convergence.json"), &curves)?;
    let cmd = format!(
        "raymip-host tradeoff{}",
        if args.quick { " --quick" } else { "" }
    );
    let md = format!(
        "# raymip trade-off: run time against error\n\n{}",
        report::markdown(&rows, &curves, &m, s.accumulate, "", &cmd)
    );
    write_text(&out.join("tradeoff.md"), &md)?;
    report::write_charts(out, &rows, &curves)?;
    if let Some(root) = &args.publish {
        publish(root, out, &rows, &curves, &m, &s)?;
    }
    println!("{}", report::pareto_list(&rows));
    Ok(rows)
}
