//! Writes the worked example of docs/integration.md: the memory
//! a controller needs for the BART kitchen and what one frame's texture work
//! costs it, every figure measured or computed here, none typed.
//!
//! ```sh
//! cargo run --release -p raymip-host --example integration_worksheet -- [WxH] [--write docs/integration.md]
//! ```
//!
//! Memory: the Pb table (`size_of::<Log2Pb>()` per triangle), the pyramids
//! full and as trimmed by the set-up analysis (`render::skip::plan`), the ray
//! stack (`stack_bound(10, 2)` entries of `PATH_STATE_BYTES`, the harness's
//! build: `cone` + `raydiff`), a texel cache (`size_of` of the type). Per
//! frame: the counted calls of a table-method render (fixed point, 10
//! bounces, trilinear) times the Cortex-M4 mean instructions per call read
//! from BUDGETS.md ("Instructions per call"), by `tradeoff::budgets`
//! (`frame_calls`, `Budgets::frame_cost`: the same cost as the trade-off's
//! frame chart). Replaces the text between
//! `<!-- integration:begin -->` and `<!-- integration:end -->` with `--write`.

use std::fmt::Write as _;
use std::path::Path;

use clap::Parser;
use raymip_host::cli::MeasureArgs;
use raymip_host::cli::memory::{MemoryArgs, memory_table};
use raymip_host::output::report::publish;
use raymip_host::render::texunit::Filter;
use raymip_host::render::{Arithmetic, Method, Options, Prepared, render};
use raymip_host::scene::{default_bart_dir, load_scene_dir};
use raymip_host::tradeoff::budgets::{Budgets, frame_calls};

const BOUNCES: u8 = 10;

/// `raymip-host memory`'s arguments.
#[derive(Parser)]
struct MemoryCli {
    #[command(flatten)]
    args: MemoryArgs,
}

/// The memory blocks of docs/integration.md: the kitchen, and a made-up
/// scene described by numbers (block name, `raymip-host memory` arguments).
const MEMORY: [(&str, &str); 2] = [
    (
        "memory-kitchen",
        "--scene ../shared/scenes/bart/kitchen --size 640x384 --cache 64x4 --cached-textures 1",
    ),
    (
        "memory-example",
        "--triangles 50000 --texture 1024x1024*20 --bounces 10 --cache 64x4 --path-range 50..2000 --texel-size 0.002..0.01",
    ),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cmd = MeasureArgs::from_env();
    let size = cmd.size.unwrap_or((640, 384));
    let write = cmd.write.as_deref();
    let dir = default_bart_dir().join("kitchen");
    if !dir.is_dir() {
        println!(
            "SKIP: BART kitchen not found ({}): nothing written",
            dir.display()
        );
        return Ok(());
    }
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let budgets = Budgets::load(Path::new(&format!("{root}/BUDGETS.md")));
    let m4 = |call: &str| {
        budgets
            .get(call, false)
            .0
            .ok_or_else(|| format!("BUDGETS.md: no Cortex-M4 count for \"{call}\""))
    };

    let prep = Prepared::new(load_scene_dir(&dir, 0.0)?, Some(size))?;
    let opts = Options {
        method: Method::Table,
        arithmetic: Arithmetic::Fixed,
        size: Some(size),
        bounces: BOUNCES,
        spp: 1,
        record_blocks: false,
        progress: false,
        aniso: None,
    };
    let c = render(&prep, &opts).counters;

    let mut t = String::new();
    writeln!(
        t,
        "BART kitchen, {}×{}, table method, firmware fixed point, {BOUNCES} bounces, trilinear \
         (`cargo run --release -p raymip-host --example integration_worksheet -- {}x{} --write docs/integration.md`).",
        size.0, size.1, size.0, size.1
    )?;
    let calls = frame_calls(Method::Table, Filter::Trilinear, &c).ok_or("no counted calls")?;
    let frame_m4 = budgets
        .frame_cost(&calls, false)
        .m4
        .ok_or("BUDGETS.md: a call of the frame has no Cortex-M4 count")?;
    writeln!(
        t,
        "\n| per frame | count | Cortex-M4 instructions per call (BUDGETS.md, mean) | Cortex-M4 instructions |"
    )?;
    writeln!(t, "|---|---|---|---|")?;
    writeln!(
        t,
        "| rays traced (by the accelerator) | {} | — | — |",
        c.rays
    )?;
    writeln!(
        t,
        "| untextured hits (no firmware work) | {} | — | — |",
        c.untextured_skipped
    )?;
    for call in &calls {
        let what = match call.name {
            "table lod" => "table lods (one per textured hit)".to_string(),
            "trilinear sample" => format!(
                "trilinear samples (one per textured hit; {} texels fetched, {} second-level fetches skipped)",
                c.fetched, c.fetch_skipped
            ),
            other => other.to_string(),
        };
        let per = m4(call.name)?;
        writeln!(
            t,
            "| {what} | {} | {per:.1} | {:.2} M |",
            call.count,
            call.count as f64 * per / 1e6
        )?;
    }
    writeln!(
        t,
        "| **texture work of one frame** | | | **{:.2} M** |",
        frame_m4 / 1e6
    )?;
    publish(&t, write, "integration")?;

    let bart = default_bart_dir();
    for (block, line) in MEMORY {
        let run = line.replace("../shared/scenes/bart", &bart.to_string_lossy());
        let cli =
            MemoryCli::try_parse_from(std::iter::once("memory").chain(run.split_whitespace()))?;
        let table = format!(
            "`cargo run --release -p raymip-host -- memory {line}`\n\n{}",
            memory_table(&cli.args)?
        );
        publish(&table, write, block)?;
    }
    Ok(())
}
