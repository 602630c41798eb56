//! The firmware's ray-differential lod against the f64 reference on random
//! camera chains ([`raymip_host::raydiff_chains`]), per case class: the
//! largest and the 99.9th-percentile error, how many chains exceed
//! `RAYDIFF_LOD_MAX_ERROR`, how many their first-order bound, and the
//! share of chains whose bound is within `RAYDIFF_LOD_MAX_ERROR`.
//!
//! ```sh
//! cargo run --release -p raymip-host --example raydiff_accuracy -- [CHAINS_PER_CLASS] [--write docs/lod-methods.md]
//! ```
//!
//! With `--write FILE`, the table goes between `<!-- raydiff-accuracy:begin -->`
//! and `<!-- raydiff-accuracy:end -->` in FILE.

use std::fmt::Write as _;

use indicatif::{ProgressBar, ProgressStyle};
use raymip::lod::raydiff::RAYDIFF_LOD_MAX_ERROR;
use raymip::rng::XorShift64;
use raymip_host::output::machine::machine_line;
use raymip_host::output::report::{publish, write_option};
use raymip_host::raydiff_chains::{CLASSES, Outcome, Raymip, run};
use rayon::prelude::*;

const BLOCK: &str = "raydiff-accuracy";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.iter().find_map(|a| a.parse().ok()).unwrap_or(100_000);
    let write = write_option(&args);
    let bar = ProgressBar::new(n * CLASSES.len() as u64).with_style(ProgressStyle::with_template(
        "{bar:40} {pos}/{len} chains {eta}",
    )?);
    let mut t = String::new();
    writeln!(
        t,
        "Written by `cargo run --release -p raymip-host --example raydiff_accuracy -- {n} --write docs/lod-methods.md` (do not edit): {n} chains per class (seeds 1, 3, 5, …), firmware lod against the f64 reference on the same quantised inputs, in levels; \"within bound\" counts the chains whose first-order bound (`ρ`, module docs of `raymip::lod::raydiff`) is within 2⁻⁷.\n"
    )?;
    writeln!(t, "Run on: {}.\n", machine_line())?;
    writeln!(
        t,
        "| class | max error | 99.9th percentile | over 2⁻⁷ | over its bound | bound within 2⁻⁷ | smallest cos on a path |"
    )?;
    writeln!(t, "|---|---|---|---|---|---|---|")?;
    for class in CLASSES {
        let mut out: Vec<Outcome> = (0..n)
            .into_par_iter()
            .map(|i| {
                bar.inc(1);
                run(&Raymip, class, &mut XorShift64(2 * i + 1))
            })
            .collect();
        out.sort_by(|a, b| a.err.total_cmp(&b.err));
        let p999 = out[((out.len() as f64) * 0.999) as usize].err;
        let max = out.last().map_or(0.0, |o| o.err);
        let over = out.iter().filter(|o| o.err > RAYDIFF_LOD_MAX_ERROR).count();
        let over_bound = out.iter().filter(|o| o.err > o.bound).count();
        let tight = out
            .iter()
            .filter(|o| o.bound <= RAYDIFF_LOD_MAX_ERROR)
            .count();
        let cos = out.iter().map(|o| o.cos_min).fold(1.0f64, f64::min);
        writeln!(
            t,
            "| {} | {max:.5} | {p999:.5} | {over} | {over_bound} | {:.1} % | {cos:.2e} |",
            class.name(),
            100.0 * tight as f64 / n as f64
        )?;
    }
    bar.finish_and_clear();
    Ok(publish(&t, write, BLOCK)?)
}
