//! Output of a trade-off run: `tradeoff.json`, `tradeoff.md`, the charts,
//! and the generated blocks of BENCHMARKS.md and docs/tradeoff.md.

use std::cmp::Ordering;
use std::fmt::Write as _;
use std::path::Path;

use super::chart::{self, Axes, Curves, Line, Panel, Point, Scatter};
use super::convergence::Curve;
use super::{Row, Stage, TradeoffError};

/// A number for the tables (`—` for none, `inf` for infinity).
fn num(x: Option<f64>, digits: usize) -> String {
    match x {
        None => "—".into(),
        Some(v) if v.is_infinite() => "inf".into(),
        Some(v) if v.is_nan() => "NaN".into(),
        Some(v) if v != 0.0 && v.abs() < 1e-3 => format!("{v:.2e}"),
        Some(v) => format!("{v:.digits$}"),
    }
}

fn yes(b: bool) -> &'static str {
    if b { "**yes**" } else { "" }
}

/// A Markdown table of `header` and `rows` (cells already formatted).
fn table(header: &[String], rows: impl Iterator<Item = Vec<String>>) -> String {
    let mut s = format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        "---|".repeat(header.len())
    );
    for r in rows {
        let _ = writeln!(s, "| {} |", r.join(" | "));
    }
    s
}

/// A stage's table: the `header` columns (`lead(row)` gives their cells),
/// then the columns every stage ends with: target instructions, errors
/// (`error`: against what and in which unit; `digits` decimals), Pareto.
fn stage_table<'a>(
    rows: impl Iterator<Item = &'a Row>,
    header: &[&str],
    error: &str,
    digits: usize,
    lead: impl Fn(&Row) -> Vec<String>,
) -> String {
    let mut h: Vec<String> = header.iter().map(|c| (*c).to_string()).collect();
    h.extend([
        "M4 instr".into(),
        "RV32 instr".into(),
        format!("max error {error}"),
        format!("RMS error {error}"),
        "Pareto".into(),
    ]);
    table(
        &h,
        rows.map(|r| {
            let mut c = lead(r);
            c.extend([
                num(r.instructions_m4, 1),
                num(r.instructions_rv32, 1),
                num(Some(r.error_max), digits),
                num(Some(r.error_rms), digits),
                yes(r.pareto).into(),
            ]);
            c
        }),
    )
}

/// The LOD table.
fn lod_table(rows: &[Row]) -> String {
    stage_table(
        rows.iter().filter(|r| r.stage == Stage::Lod),
        &["method", "precision", "host ns/call"],
        "(levels)",
        5,
        |r| vec![r.method.clone(), r.precision.clone(), num(r.time_ns, 2)],
    )
}

/// The filter table.
fn filter_table(rows: &[Row]) -> String {
    stage_table(
        rows.iter().filter(|r| r.stage == Stage::Filter),
        &[
            "filter",
            "precision",
            "frames",
            "host ns/sample",
            "max error vs own filter (LSB)",
            "RMS error vs own filter (LSB)",
        ],
        "vs target (LSB)",
        3,
        |r| {
            vec![
                r.filter.clone().unwrap_or_default(),
                r.precision.clone(),
                r.frames.to_string(),
                num(r.time_ns, 2),
                num(r.own_error_max, 3),
                num(r.own_error_rms, 3),
            ]
        },
    )
}

/// The frame table of one scene.
fn frame_table(rows: &[Row], scene: &str) -> String {
    stage_table(
        rows.iter()
            .filter(|r| r.stage == Stage::Frame && r.scene.as_deref() == Some(scene)),
        &[
            "method",
            "precision",
            "filter",
            "frames",
            "ms/frame",
            "M4 M instr/frame",
            "PicoRV32 M cycles/frame",
            "Pareto (M4 cost)",
            "PSNR vs truth (dB)",
            "PSNR vs f64 (dB)",
        ],
        "(LSB)",
        2,
        |r| {
            vec![
                r.method.clone(),
                r.precision.clone(),
                r.filter.clone().unwrap_or_default(),
                r.frames.to_string(),
                num(r.time_ms, 2),
                num(r.frame_m4.map(|n| n / 1e6), 2),
                num(r.frame_picorv32.map(|n| n / 1e6), 2),
                yes(r.pareto_cost).into(),
                num(r.psnr_truth_db, 2),
                num(r.psnr_float_db, 2),
            ]
        },
    )
}

/// Scenes of the frame rows, in order.
#[must_use]
pub fn scenes(rows: &[Row]) -> Vec<String> {
    let mut s: Vec<String> = Vec::new();
    for r in rows.iter().filter(|r| r.stage == Stage::Frame) {
        if let Some(n) = &r.scene
            && !s.contains(n)
        {
            s.push(n.clone());
        }
    }
    s
}

/// The Pareto-optimal configurations, one line per stage (and scene).
#[must_use]
pub fn pareto_list(rows: &[Row]) -> String {
    let mut s = String::new();
    let mut group = |title: String, f: &dyn Fn(&Row) -> bool| {
        let mut front: Vec<&Row> = rows.iter().filter(|r| r.pareto && f(r)).collect();
        front.sort_by(|a, b| a.time().total_cmp(&b.time()));
        let names: Vec<String> = front
            .iter()
            .map(|r| format!("{} ({})", r.label(), point(r)))
            .collect();
        let _ = writeln!(s, "- {title}: {}", names.join("; "));
    };
    for m in ["table", "cone", "cone+normal", "raydiff"] {
        group(format!("LOD per hit, {m}"), &|r| {
            r.stage == Stage::Lod && r.method == m
        });
    }
    group("filter per sample".into(), &|r| r.stage == Stage::Filter);
    for sc in scenes(rows) {
        group(format!("frame, {sc}, host time"), &|r| {
            r.stage == Stage::Frame && r.scene.as_deref() == Some(&sc)
        });
    }
    for sc in scenes(rows) {
        let mut front: Vec<&Row> = rows
            .iter()
            .filter(|r| r.pareto_cost && r.scene.as_deref() == Some(&sc))
            .collect();
        front.sort_by(|a, b| {
            a.frame_m4
                .partial_cmp(&b.frame_m4)
                .unwrap_or(Ordering::Equal)
        });
        let names: Vec<String> = front
            .iter()
            .map(|r| {
                format!(
                    "{} ({} M M4 instructions, {} dB)",
                    r.label(),
                    num(r.frame_m4.map(|n| n / 1e6), 2),
                    num(r.psnr_truth_db, 2)
                )
            })
            .collect();
        let _ = writeln!(s, "- frame, {sc}, firmware cost: {}", names.join("; "));
    }
    s
}

/// `time, error` of a row as the charts plot it.
fn point(r: &Row) -> String {
    match r.stage {
        Stage::Lod => format!(
            "{} ns, max {} levels",
            num(r.time_ns, 2),
            num(Some(r.error_max), 5)
        ),
        Stage::Filter => format!(
            "{} ns, RMS {} LSB",
            num(r.time_ns, 2),
            num(Some(r.error_rms), 3)
        ),
        Stage::Frame => format!("{} ms, {} dB", num(r.time_ms, 1), num(r.psnr_truth_db, 2)),
    }
}

/// The convergence table: RMS error at a few frame counts.
fn convergence_table(curves: &[Curve]) -> String {
    let Some(n) = curves.iter().map(|c| c.rms_lsb.len()).max() else {
        return String::new();
    };
    let at: Vec<usize> = [1, 4, 16, 64].into_iter().filter(|&k| k <= n).collect();
    let mut s = String::from("| mode | measured on |");
    for k in &at {
        let _ = write!(s, " RMS after {k} (LSB) |");
    }
    let _ = write!(
        s,
        " RMS(1)/RMS({}) | √{} |\n|---|---|",
        at[at.len() - 1],
        at[at.len() - 1]
    );
    s += &"---|".repeat(at.len() + 2);
    s.push('\n');
    for c in curves {
        let _ = write!(s, "| {} | {} |", c.mode, c.kind);
        for &k in &at {
            let _ = write!(s, " {} |", num(c.rms_lsb.get(k - 1).copied(), 3));
        }
        let last = at[at.len() - 1];
        let ratio = c
            .rms_lsb
            .first()
            .zip(c.rms_lsb.get(last - 1))
            .map(|(a, b)| a / b);
        let _ = writeln!(
            s,
            " {} | {} |",
            num(ratio, 2),
            num(Some((last as f64).sqrt()), 2)
        );
    }
    s
}

/// x axis of the frame chart's cost panels.
pub const FRAME_COST_AXIS: &str = "M4 instructions per frame, millions (log)";

/// The Pareto chart of a stage.
#[must_use]
pub fn stage_chart(rows: &[Row], stage: Stage) -> Scatter {
    // The points of the rows `f` keeps, at x = `cost(row)` (rows without
    // one left out), on the front when `front(row)`.
    let pts = |f: &dyn Fn(&Row) -> bool,
               cost: &dyn Fn(&Row) -> Option<f64>,
               front: &dyn Fn(&Row) -> bool|
     -> Vec<Point> {
        rows.iter()
            .filter(|r| r.stage == stage && f(r))
            .filter_map(|r| Some((r, cost(r)?)))
            .map(|(r, x)| Point {
                x,
                y: match stage {
                    Stage::Lod => r.error_max,
                    Stage::Filter => r.error_rms,
                    Stage::Frame => r.psnr_truth_db.unwrap_or(f64::NAN),
                },
                label: r.label(),
                series: match stage {
                    Stage::Lod | Stage::Frame => r.method.clone(),
                    Stage::Filter => r.precision.clone(),
                },
                front: front(r),
            })
            .collect()
    };
    let time = |r: &Row| Some(r.time());
    let pareto = |r: &Row| r.pareto;
    let (title, x, y, log_y) = match stage {
        Stage::Lod => (
            "LOD per hit: host time against max error vs f64",
            "host ns per call (log)",
            "max |lod − f64| (levels, log; 0 drawn at 1e-9)",
            true,
        ),
        Stage::Filter => (
            "Filter per sample: host time against RMS error vs the exact f64 target",
            "host ns per sample (log)",
            "RMS error vs exact trilinear (anisotropic rows: exact 16× anisotropic) (8-bit LSB, log)",
            true,
        ),
        Stage::Frame => (
            "Whole frame: firmware texture work (Cortex-M4) and host time against PSNR vs ground truth (higher is better)",
            "host ms per frame (log)",
            "PSNR vs truth (dB)",
            false,
        ),
    };
    let panels = if stage == Stage::Frame {
        // Top row: the M4 cost of each scene's texture work (the rows
        // BUDGETS.md can cost); bottom row: host time of every row.
        let scenes = scenes(rows);
        let cost = scenes.iter().map(|sc| Panel {
            title: format!("{sc}: firmware texture work"),
            x: Some(FRAME_COST_AXIS.into()),
            points: pts(
                &|r| r.scene.as_deref() == Some(sc),
                &|r| r.frame_m4.map(|n| n / 1e6),
                &|r| r.pareto_cost,
            ),
        });
        let host = scenes.iter().map(|sc| Panel {
            title: format!("{sc}: host time"),
            x: None,
            points: pts(&|r| r.scene.as_deref() == Some(sc), &time, &pareto),
        });
        cost.filter(|p| !p.points.is_empty()).chain(host).collect()
    } else {
        vec![Panel {
            title: String::new(),
            x: None,
            points: pts(&|_| true, &time, &pareto),
        }]
    };
    Scatter {
        title: title.into(),
        axes: Axes {
            x: x.into(),
            y: y.into(),
            log_y,
            y_floor: 1e-9,
        },
        panels,
        front_per_series: stage == Stage::Lod,
        legend_lower_right: stage == Stage::Frame,
    }
}

/// The convergence chart.
#[must_use]
pub fn convergence_chart(curves: &[Curve]) -> Curves {
    let panel = |kind: &str, title: &str| {
        let mut lines: Vec<Line> = curves
            .iter()
            .filter(|c| c.kind == kind)
            .map(|c| Line {
                name: c.mode.clone(),
                points: c
                    .rms_lsb
                    .iter()
                    .enumerate()
                    .map(|(i, &e)| ((i + 1) as f64, e))
                    .collect(),
                dashed: false,
            })
            .collect();
        if let Some(first) = lines.first().and_then(|l| l.points.first()).map(|p| p.1) {
            let n = lines[0].points.len();
            lines.push(Line {
                name: "1/√N from N = 1".into(),
                points: (1..=n)
                    .map(|k| (k as f64, first / (k as f64).sqrt()))
                    .collect(),
                dashed: true,
            });
        }
        (title.to_string(), lines)
    };
    Curves {
        title: "Stochastic filtering: mean of N frames against the deterministic filter".into(),
        axes: Axes {
            x: "frames accumulated N (log)".into(),
            y: "RMS error (8-bit LSB, log)".into(),
            log_y: true,
            y_floor: 1e-3,
        },
        panels: vec![
            panel("sample", "per sample (random texture)"),
            panel("frame", "per frame (first scene, table lod)"),
        ],
    }
}

/// The chart files (stems; each written as `.png` and `.svg`).
pub const CHARTS: [&str; 4] = [
    "pareto-lod",
    "pareto-texture",
    "pareto-frame",
    "stochastic-convergence",
];

/// Writes the four charts into `dir`.
///
/// # Errors
/// [`TradeoffError::Chart`] naming the chart's files.
pub fn write_charts(dir: &Path, rows: &[Row], curves: &[Curve]) -> Result<(), TradeoffError> {
    let write = |stem: &str, c: &dyn Fn(&Path) -> Result<(), chart::ChartError>| {
        let stem = dir.join(stem);
        c(&stem).map_err(|source| TradeoffError::Chart { stem, source })
    };
    let stage = |st| move |p: &Path| chart::write(p, &stage_chart(rows, st));
    write("pareto-lod", &stage(Stage::Lod))?;
    write("pareto-texture", &stage(Stage::Filter))?;
    write("pareto-frame", &stage(Stage::Frame))?;
    write("stochastic-convergence", &|p| {
        chart::write(p, &convergence_chart(curves))
    })
}

/// The row of a configuration (first scene for frames).
fn find<'a>(
    rows: &'a [Row],
    stage: Stage,
    method: &str,
    precision: &str,
    filter: Option<&str>,
    frames: u32,
) -> Option<&'a Row> {
    let first = scenes(rows).into_iter().next();
    rows.iter().find(|r| {
        r.stage == stage
            && r.method == method
            && r.precision == precision
            && r.filter.as_deref() == filter
            && r.frames == frames
            && (stage != Stage::Frame || r.scene == first)
    })
}

fn ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    a.zip(b).map(|(a, b)| a / b)
}

/// Headline lines of the anisotropic filter rows: cost and error of each
/// cap beside one trilinear probe (1×).
fn aniso_headlines(rows: &[Row]) -> String {
    let mut s = String::new();
    let iso = find(
        rows,
        Stage::Filter,
        "sample",
        "fixed accurate",
        Some("anisotropic 1×"),
        1,
    );
    for cap in [2, 4, 16] {
        let name = format!("anisotropic {cap}×");
        let fx = find(
            rows,
            Stage::Filter,
            "sample",
            "fixed accurate",
            Some(&name),
            1,
        );
        if let (Some(iso), Some(fx)) = (iso, fx) {
            let _ = writeln!(
                s,
                "- {name} per sample (footprints 16–32:1): host time ×{} of one trilinear probe (1×), {} / {} instructions on Cortex-M4 / RV32IMAC; RMS error vs the exact 16× filter {} LSB (1×: {} LSB), vs its own exact filter {} LSB.",
                num(ratio(fx.time_ns, iso.time_ns), 2),
                num(fx.instructions_m4, 0),
                num(fx.instructions_rv32, 0),
                num(Some(fx.error_rms), 2),
                num(Some(iso.error_rms), 2),
                num(fx.own_error_rms, 3),
            );
        }
    }
    s
}

/// Headline ratios, every number from `rows`.
#[must_use]
pub fn headlines(rows: &[Row], accumulate: u32) -> String {
    let mut s = String::new();
    let fx = find(rows, Stage::Lod, "table", "fixed accurate", None, 1);
    let fl = find(rows, Stage::Lod, "table", "f32 libm", None, 1);
    let mm = find(rows, Stage::Lod, "table", "f32 micromath", None, 1);
    if let (Some(fx), Some(fl)) = (fx, fl) {
        let _ = writeln!(
            s,
            "- Table lod, firmware fixed point against f32 `libm`: host time ×{} (f32/fixed), Cortex-M4 instructions ×{}, RV32IMAC instructions ×{}; max error {} levels (fixed) and {} levels (f32) vs f64.",
            num(ratio(fl.time_ns, fx.time_ns), 2),
            num(ratio(fl.instructions_m4, fx.instructions_m4), 2),
            num(ratio(fl.instructions_rv32, fx.instructions_rv32), 2),
            num(Some(fx.error_max), 5),
            num(Some(fl.error_max), 7),
        );
        if let Some(mm) = mm {
            let _ = writeln!(
                s,
                "- f32 `micromath` table lod: host time ×{} of fixed point, max error {} levels.",
                num(ratio(mm.time_ns, fx.time_ns), 2),
                num(Some(mm.error_max), 5)
            );
        }
    }
    for (det, sto) in [
        ("trilinear", "stochastic trilinear"),
        ("bilinear", "stochastic bilinear"),
        ("trilinear", "stochastic trilinear+bilinear"),
    ] {
        let d = find(
            rows,
            Stage::Filter,
            "sample",
            "fixed accurate",
            Some(det),
            1,
        );
        let one = find(
            rows,
            Stage::Filter,
            "sample",
            "fixed accurate",
            Some(sto),
            1,
        );
        let acc = find(
            rows,
            Stage::Filter,
            "sample",
            "fixed accurate",
            Some(sto),
            accumulate,
        );
        if let (Some(d), Some(one), Some(acc)) = (d, one, acc) {
            let _ = writeln!(
                s,
                "- {sto} per sample: host time ×{} of deterministic {det}; RMS error {} LSB in one frame, {} LSB after {accumulate} frames ({det}: {} LSB).",
                num(ratio(one.time_ns, d.time_ns), 2),
                num(Some(one.error_rms), 2),
                num(Some(acc.error_rms), 3),
                num(Some(d.error_rms), 3),
            );
        }
    }
    s += &aniso_headlines(rows);
    s += &frame_headline(rows);
    s
}

/// The headline of the first scene's frames: PSNR of table lod + trilinear
/// (fixed, f64, no mip mapping) and its firmware cost per frame.
fn frame_headline(rows: &[Row]) -> String {
    let mut s = String::new();
    if let Some(sc) = scenes(rows).first() {
        let t = find(
            rows,
            Stage::Frame,
            "table",
            "fixed accurate",
            Some("trilinear"),
            1,
        );
        let f = find(rows, Stage::Frame, "table", "f64", Some("trilinear"), 1);
        let m0 = find(
            rows,
            Stage::Frame,
            "mip0",
            "fixed accurate",
            Some("bilinear"),
            1,
        );
        if let (Some(t), Some(f), Some(m0)) = (t, f, m0) {
            let _ = write!(
                s,
                "- Frame ({sc}): table lod + trilinear, fixed point {} dB vs ground truth ({} dB from the f64 render of the same method), f64 {} dB, no mip mapping {} dB",
                num(t.psnr_truth_db, 2),
                num(t.psnr_float_db, 2),
                num(f.psnr_truth_db, 2),
                num(m0.psnr_truth_db, 2),
            );
            if let (Some(m4), Some(cycles)) = (t.frame_m4, t.frame_picorv32) {
                let _ = write!(
                    s,
                    "; its texture work {} M Cortex-M4 instructions, {} M PicoRV32 cycles per frame",
                    num(Some(m4 / 1e6), 2),
                    num(Some(cycles / 1e6), 2),
                );
            }
            s += ".\n";
        }
    }
    s
}

/// The report body: machine, headlines, Pareto fronts, charts (under
/// `charts`, a path prefix), tables and convergence.
#[must_use]
pub fn markdown(
    rows: &[Row],
    curves: &[Curve],
    machine: &str,
    accumulate: u32,
    charts: &str,
    command: &str,
) -> String {
    let mut s = format!("Machine: {machine}. Written by `{command}`.\n\n");
    s += &headlines(rows, accumulate);
    s += "\n**Pareto-optimal configurations** (no other configuration of the group is both faster and more accurate; groups: each LOD method, the filters, each scene's frames):\n\n";
    s += &pareto_list(rows);
    let _ = write!(
        s,
        "\n![LOD per hit]({charts}pareto-lod.png)\n\n![Filter per sample]({charts}pareto-texture.png)\n\n![Whole frame]({charts}pareto-frame.png)\n\n![Stochastic convergence]({charts}stochastic-convergence.png)\n\n"
    );
    s += "### LOD per hit\n\nError of the lod against the f64 formula of the same method over the same inputs (rounded to the fixed-point input formats first). Instructions: mean per call from BUDGETS.md where a probe counts the call.\n\n";
    s += &lod_table(rows);
    s += "\n### Filter per sample\n\nError per channel against the target, the exact f64 trilinear filter at the same (u, v, lod) (what every isotropic filter approximates; the chart's axis), and against the exact f64 version of the row's own filter (its expectation for a stochastic filter: the implementation error); a stochastic row with frames > 1 is the mean of that many frames' samples (the per-frame cost is unchanged). Anisotropic rows (at most N trilinear probes along the major axis) run on their own inputs, long footprints 16 to 32 times longer than wide with a minor axis of 0.5 to 4 texels; their target is the exact f64 anisotropic 16× filter of the same footprint, their own filter the exact f64 anisotropic filter with the row's cap (1× = one trilinear probe at the major axis's lod).\n\n";
    s += &filter_table(rows);
    for sc in scenes(rows) {
        let _ = write!(
            s,
            "\n### Whole frame: {sc}\n\nPSNR and errors against the supersampled ground truth; PSNR vs f64 against the f64 render of the same method (for a stochastic filter: of its deterministic expectation).\n\n"
        );
        s += &frame_table(rows, &sc);
    }
    s += "\n### Stochastic filtering over frames\n\nRMS error of the mean of the first N frames against the deterministic firmware filter it converges to; independent frames give RMS(1)/RMS(N) ≈ √N.\n\n";
    s += &convergence_table(curves);
    s
}
