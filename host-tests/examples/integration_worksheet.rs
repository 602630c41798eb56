//! Writes the worked example of docs/integration.md (issue 22): the memory
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
use std::mem::size_of;
use std::path::Path;

use raymip::path::raystack::{PATH_STATE_BYTES, stack_bound};
use raymip::texture::storage::mip::pyramid_len;
use raymip::{Log2Pb, Pyramid, TexelCache};
use raymip_host::cli::parse_size;
use raymip_host::output::report::{publish, write_option};
use raymip_host::render::skip::plan;
use raymip_host::render::texunit::Filter;
use raymip_host::render::{Arithmetic, Method, Options, Prepared, render};
use raymip_host::scene::{default_bart_dir, load_scene_dir};
use raymip_host::tradeoff::budgets::{Budgets, frame_calls};

const BOUNCES: u8 = 10;

fn kib(bytes: u64) -> String {
    format!("{:.1} KiB", bytes as f64 / 1024.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size = args
        .iter()
        .find_map(|a| parse_size(a).ok())
        .unwrap_or((640, 384));
    let write = write_option(&args);
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
    let p = plan(&prep, &opts);
    let c = render(&prep, &opts).counters;

    let triangles = prep.pb_fixed.len() as u64;
    let textured = prep
        .pb_fixed
        .iter()
        .filter(|&&e| e != Log2Pb::UNTEXTURED)
        .count();
    let table_bytes = triangles * size_of::<Log2Pb>() as u64;
    let largest = prep
        .textures
        .iter()
        .max_by_key(|t| u64::from(t.width) * u64::from(t.height))
        .ok_or("the kitchen has no texture")?;
    let largest_bytes = (pyramid_len(largest.width, largest.height, largest.levels) * 4) as u64;
    let stack_entries = stack_bound(BOUNCES, 2);
    let stack_bytes = (stack_entries * PATH_STATE_BYTES) as u64;
    let cache_bytes = size_of::<TexelCache<Pyramid<'static>, 64, 4>>() as u64;

    let mut t = String::new();
    writeln!(
        t,
        "BART kitchen, {}×{}, table method, firmware fixed point, {BOUNCES} bounces, trilinear \
         (`cargo run --release -p raymip-host --example integration_worksheet -- {}x{} --write docs/integration.md`).\n",
        size.0, size.1, size.0, size.1
    )?;
    writeln!(t, "| memory | count | bytes each | total |")?;
    writeln!(t, "|---|---|---|---|")?;
    writeln!(
        t,
        "| Pb table (`Log2Pb` per triangle; {textured} textured) | {triangles} triangles | {} | {} |",
        size_of::<Log2Pb>(),
        kib(table_bytes)
    )?;
    writeln!(
        t,
        "| pyramids, full (RGBA8, every level) | {} textures | largest {}×{}, {} levels: {} | {} |",
        prep.textures.len(),
        largest.width,
        largest.height,
        largest.levels,
        kib(largest_bytes),
        kib(p.full_bytes)
    )?;
    writeln!(
        t,
        "| pyramids, trimmed by the set-up analysis | {} textures skipped | — | {} ({:.1} % saved) |",
        p.textures_skipped,
        kib(p.stored_bytes),
        p.saved_percent()
    )?;
    writeln!(
        t,
        "| ray stack, `stack_bound({BOUNCES}, 2)` entries (`cone` + `raydiff`) | {stack_entries} entries | {PATH_STATE_BYTES} | {} |",
        kib(stack_bytes)
    )?;
    writeln!(
        t,
        "| texel cache `TexelCache<Pyramid, 64, 4>` ({} data, tags, LRU stamps; `size_of` on the host) | 1 | {cache_bytes} | {} |",
        kib(64 * 4 * 64),
        kib(cache_bytes)
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
    Ok(publish(&t, write, "integration")?)
}
