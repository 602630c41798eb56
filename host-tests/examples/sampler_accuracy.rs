//! Writes the docs/texture-sampling.md table of the sampler's error per format, filter and
//! precision tier, measured against the f64 reference (`raymip_reference::sampler`, through `raymip_host::accuracy`).
//!
//! ```sh
//! cargo run --release -p raymip-host --example sampler_accuracy -- [SAMPLES] [--write docs/texture-sampling.md]
//! ```
//!
//! Prints the Markdown table; with `--write FILE` it replaces the text
//! between `<!-- sampler-accuracy:begin -->` and
//! `<!-- sampler-accuracy:end -->` in FILE.

use std::fmt::Write as _;

use raymip::units::Precision;
use raymip_host::accuracy::{FILTERS, measure};
use raymip_host::cli::MeasureArgs;
use raymip_host::output::report::publish;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cmd = MeasureArgs::from_env();
    let samples = cmd.number.map_or(20_000, |n| n as usize);
    let write = cmd.write.as_deref();
    let mut rows = measure(samples, 0x5EED_2026, Precision::Accurate);
    rows.extend(measure(samples, 0x5EED_2027, Precision::Fast));
    let mut table = String::new();
    writeln!(
        table,
        "Max error per channel in 8-bit LSB against the f64 reference (measured / documented bound), {samples} random samples per cell (`cargo run --release -p raymip-host --example sampler_accuracy -- {samples} --write docs/texture-sampling.md`):\n"
    )?;
    write!(table, "| format | tier |")?;
    for f in FILTERS {
        write!(table, " {f} |")?;
    }
    writeln!(table)?;
    writeln!(table, "|---|---|{}", "---|".repeat(FILTERS.len()))?;
    for chunk in rows.chunks(FILTERS.len()) {
        let tier = match chunk[0].precision {
            Precision::Accurate => "ACCURATE",
            Precision::Fast => "FAST",
        };
        write!(table, "| {} | {tier} |", chunk[0].format)?;
        for r in chunk {
            if r.max_error > r.bound {
                return Err(format!(
                    "{} {}: {} above bound {}",
                    r.format, r.filter, r.max_error, r.bound
                )
                .into());
            }
            write!(table, " {:.3} / {:.3} |", r.max_error, r.bound)?;
        }
        writeln!(table)?;
    }
    let ties: usize = rows.iter().map(|r| r.ties).sum();
    writeln!(
        table,
        "\n({ties} anisotropic samples whose probe count is a tie within 2⁻¹² in log2 were left out.)"
    )?;
    Ok(publish(&table, write, "sampler-accuracy")?)
}
