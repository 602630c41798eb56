//! The LOD methods of the talk in fixed point (table, ray cones,
//! ray differentials ray-traced and from a G-buffer): their cost per
//! textured hit on the targets (read from BUDGETS.md, which
//! `scripts/budgets` and `scripts/softcore` write) and their PSNR against
//! supersampled ground truth on `builtin:hall`, `builtin:mirrors` and the
//! BART kitchen (left out, with a line saying so, when
//! `../shared/scenes/bart` is absent).
//!
//! ```sh
//! cargo run --release -p raymip-host --example lod_methods -- [WxH] [SPP] [--write docs/lod-methods.md | --check docs/lod-methods.md]
//! ```
//!
//! Prints the Markdown block and, with `--write FILE`, replaces the one
//! between `<!-- lod-methods:begin -->` and `<!-- lod-methods:end -->` in
//! FILE. The block holds no timing, so apart from its line naming the
//! machine it is the same on every machine: `--check FILE` fails when
//! FILE's block differs from a fresh run in any other line, and skips
//! (exit 0, with a message) when the BART scenes are missing.

use std::fmt::Write as _;
use std::path::Path;

use raymip_host::cli::MeasureArgs;
use raymip_host::output::machine::machine_line;
use raymip_host::output::metrics::psnr;
use raymip_host::output::report::{markdown_cells, publish};
use raymip_host::render::{Method, Options, Prepared, render_fixed_and_float, render_truth};
use raymip_host::scene::{Scene, builtin, default_bart_dir, load_scene_dir};

/// The block's name in the Markdown file.
const BLOCK: &str = "lod-methods";

/// A BUDGETS.md table row: its cells after the first, by the first cell.
fn budget_row(budgets: &str, section: &str, first: &str) -> Option<Vec<String>> {
    let text = &budgets[budgets.find(section)?..];
    text.lines().find_map(|l| {
        let cells = markdown_cells(l);
        (l.starts_with('|') && cells.first().is_some_and(|c| c == first))
            .then(|| cells[1..].to_vec())
    })
}

/// The mean of a `min / mean / max` cell.
fn mean(cell: &str) -> String {
    cell.split('/')
        .nth(1)
        .map_or_else(|| cell.to_string(), |m| m.trim().to_string())
}

/// The cost table: instructions per textured hit on the Cortex-M4 and
/// RV32IMAC (with the ratio to the cone lod) and PicoRV32 cycles.
fn cost_table(budgets: &str) -> String {
    let mut t = String::from(
        "| method per textured hit | Cortex-M4 instr. | ratio to cone | RV32IMAC instr. | ratio to cone | PicoRV32 cycles |\n|---|---|---|---|---|---|\n",
    );
    let per_hit = "## Ray differentials";
    let soft = "## Cycles on the PicoRV32";
    for (label, row, soft_row) in [
        ("table (`table_lod`)", "table lod", Some("table lod")),
        (
            "ray cones (`cone_lod`, with n·d)",
            "cone lod (with n·d)",
            Some("cone lod (with n·d)"),
        ),
        (
            "ray differentials, ray-traced (transfer + footprint + lod)",
            "ray differentials, ray-traced",
            Some("ray differentials, ray-traced"),
        ),
        (
            "ray differentials, G-buffer, first hit (set-up + footprint + lod)",
            "ray differentials, G-buffer",
            Some("ray differentials, G-buffer"),
        ),
    ] {
        let c = budget_row(budgets, per_hit, row).unwrap_or_default();
        let cell = |i: usize| c.get(i).cloned().unwrap_or_else(|| "—".into());
        let cycles = soft_row
            .and_then(|r| budget_row(budgets, soft, r))
            .and_then(|s| s.first().map(|x| mean(x)))
            .unwrap_or_else(|| "not measured".into());
        let _ = writeln!(
            t,
            "| {label} | {} | {} | {} | {} | {cycles} |",
            cell(0),
            cell(1),
            cell(2),
            cell(3)
        );
    }
    t
}

/// One PSNR row: per method, fixed point (f64 in parentheses).
fn psnr_row(
    label: &str,
    scene: Scene,
    size: (u32, u32),
    spp: u32,
) -> Result<String, Box<dyn std::error::Error>> {
    eprintln!("lod_methods: {label}");
    let prep = Prepared::new(scene, Some(size))?;
    let base = Options {
        size: Some(size),
        spp,
        ..Options::default()
    };
    let truth = render_truth(&prep, &base).to_rgb8();
    let mut row = format!("| {label} |");
    for method in [
        Method::Table,
        Method::Cone,
        Method::Raydiff,
        Method::Gbuffer,
        Method::Mip0,
    ] {
        let p = render_fixed_and_float(
            &prep,
            &Options {
                method,
                ..base.clone()
            },
        )
        .map(|img| psnr(&img.to_rgb8(), &truth));
        let _ = write!(row, " {:.2} ({:.2}) |", p[0], p[1]);
    }
    Ok(row)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cmd = MeasureArgs::from_env();
    let size = cmd.size.unwrap_or((320, 192));
    let spp = cmd.number.unwrap_or(64);
    let write = cmd.write.as_deref();
    let check = cmd
        .args
        .iter()
        .position(|a| a == "--check")
        .and_then(|i| cmd.args.get(i + 1))
        .map(Path::new);
    let kitchen = default_bart_dir().join("kitchen");
    if check.is_some() && !kitchen.is_dir() {
        println!(
            "lod_methods --check: SKIPPED: the BART kitchen ({}) is missing, the block cannot be reproduced here",
            kitchen.display()
        );
        return Ok(());
    }
    let budgets = std::fs::read_to_string("BUDGETS.md")?;
    let mut t = String::new();
    writeln!(
        t,
        "Written by `cargo run --release -p raymip-host --example lod_methods -- {}x{} {spp} --write docs/lod-methods.md` (do not edit; `--check docs/lod-methods.md` compares). Cost per textured hit: means from BUDGETS.md (QEMU instruction counts of `scripts/budgets`, PicoRV32 cycles of `scripts/softcore` where it measures the call).\n",
        size.0, size.1
    )?;
    // The machine line is the only one that depends on where it ran;
    // `--check` compares the rest.
    writeln!(t, "Rendered on: {}.\n", machine_line())?;
    t += &cost_table(&budgets);
    writeln!(
        t,
        "\nPSNR against ground truth ({spp} jittered samples per pixel, bilinear in level 0), {}×{}, trilinear at the method's lod, 10 bounces; fixed point = the firmware lod, ray stack and sampler, in parentheses the f64 render of the same method. The renders are deterministic (no timing in this block), so the figures do not depend on the machine. Ray-traced differentials (\"RayDiffs RT\") start at the camera and are transferred to every hit; G-buffer differentials (\"RayDiffs GB\", `--method gbuffer`) take the first hit's position and normal differentials from a G-buffer pass over the pixel centres (the neighbour with the smaller distance step per axis, `raydiff::gbuffer::first_hit`) and transfer them from there on, so after the first bounce they cost what the ray-traced ones cost.\n",
        size.0, size.1
    )?;
    writeln!(
        t,
        "| scene | table | ray cones | ray differentials (ray-traced) | ray differentials (G-buffer) | mip 0 (no LOD) |\n|---|---|---|---|---|---|"
    )?;
    for name in ["hall", "mirrors"] {
        writeln!(
            t,
            "{}",
            psnr_row(
                &format!("`builtin:{name}`"),
                builtin::by_name(name)?,
                size,
                spp
            )?
        )?;
    }
    if kitchen.is_dir() {
        writeln!(
            t,
            "{}",
            psnr_row("BART kitchen", load_scene_dir(&kitchen, 0.0)?, size, spp)?
        )?;
    } else {
        writeln!(
            t,
            "\nBART kitchen: not found (../shared/scenes/bart), left out."
        )?;
    }
    if let Some(path) = check {
        let text = std::fs::read_to_string(path)?;
        let (b, e) = (
            format!("<!-- {BLOCK}:begin -->\n"),
            format!("<!-- {BLOCK}:end -->"),
        );
        let old = text.find(&b).and_then(|i| {
            text[i + b.len()..]
                .find(&e)
                .map(|j| &text[i + b.len()..i + b.len() + j])
        });
        let stable = |b: &str| {
            b.lines()
                .filter(|l| !l.starts_with("Rendered on: "))
                .collect::<Vec<_>>()
                .join("\n")
                .trim()
                .to_string()
        };
        if old.map(stable) != Some(stable(&t)) {
            print!("{t}");
            return Err(format!(
                "lod_methods --check: FAIL: the {BLOCK} block of {} is stale (run with --write)",
                path.display()
            )
            .into());
        }
        println!(
            "lod_methods --check: the {BLOCK} block of {} is up to date",
            path.display()
        );
        return Ok(());
    }
    Ok(publish(&t, write, BLOCK)?)
}
